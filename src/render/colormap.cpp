#include "colormap.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>
#include <string>

namespace snert::render {

namespace {
// viridis (van der Walt & Smith, matplotlib 1.5, CC0) at t = 0, 1/8, ..., 1.
constexpr std::array<glm::vec3, 9> kViridisStops = {
    glm::vec3{0x44, 0x01, 0x54} / 255.0f, glm::vec3{0x47, 0x2c, 0x7a} / 255.0f,
    glm::vec3{0x3b, 0x51, 0x8b} / 255.0f, glm::vec3{0x2c, 0x71, 0x8e} / 255.0f,
    glm::vec3{0x21, 0x90, 0x8d} / 255.0f, glm::vec3{0x27, 0xad, 0x81} / 255.0f,
    glm::vec3{0x5c, 0xc8, 0x63} / 255.0f, glm::vec3{0xaa, 0xdc, 0x32} / 255.0f,
    glm::vec3{0xfd, 0xe7, 0x25} / 255.0f};
// Moreland's cool-warm diverging map at t = 0, 1/8, ..., 1.
constexpr std::array<glm::vec3, 9> kCoolWarmStops = {
    glm::vec3{59, 76, 192} / 255.0f,   glm::vec3{98, 130, 234} / 255.0f,
    glm::vec3{141, 176, 254} / 255.0f, glm::vec3{184, 208, 249} / 255.0f,
    glm::vec3{221, 221, 221} / 255.0f, glm::vec3{245, 196, 173} / 255.0f,
    glm::vec3{244, 154, 123} / 255.0f, glm::vec3{222, 96, 77} / 255.0f,
    glm::vec3{180, 4, 38} / 255.0f};

glm::vec3 interpolate(const std::array<glm::vec3, 9>& stops, float t) {
    t = std::clamp(t, 0.0f, 1.0f);
    const float position = t * float(stops.size() - 1);
    const std::size_t below = std::min(std::size_t(position), stops.size() - 2);
    return glm::mix(stops[below], stops[below + 1], position - float(below));
}

std::vector<std::uint8_t> sampled_rgba8(int n, glm::vec3 (*map)(float), const char* name) {
    if (n < 2) throw std::invalid_argument(std::string(name) + ": need at least 2 samples");
    std::vector<std::uint8_t> rgba(std::size_t(n) * 4);
    for (int i = 0; i < n; ++i) {
        const glm::vec3 c = map(float(i) / float(n - 1));
        for (int k = 0; k < 3; ++k)
            rgba[std::size_t(i) * 4 + k] = std::uint8_t(std::lround(c[k] * 255.0f));
        rgba[std::size_t(i) * 4 + 3] = 255;
    }
    return rgba;
}
} // namespace

glm::vec3 cool_warm(float t) {
    return interpolate(kCoolWarmStops, std::isnan(t) ? 0.5f : t);
}

std::vector<std::uint8_t> cool_warm_rgba8(int n) {
    return sampled_rgba8(n, cool_warm, "cool_warm_rgba8");
}

glm::vec3 viridis(float t) {
    if (std::isnan(t)) t = 0.0f;
    t = std::clamp(t, 0.0f, 1.0f);
    const float position = t * float(kViridisStops.size() - 1);
    const std::size_t below = std::min(std::size_t(position), kViridisStops.size() - 2);
    const float fraction = position - float(below);
    return glm::mix(kViridisStops[below], kViridisStops[below + 1], fraction);
}

std::vector<std::uint8_t> viridis_rgba8(int n) {
    return sampled_rgba8(n, viridis, "viridis_rgba8");
}

glm::vec3 measure_color(ShapeMeasure measure, float value, float threshold,
                        const MeasureScale& scale) {
    if (!is_distance(measure) && value < threshold) return kPoorQualityColor;
    const float t = (value - scale.low) / (scale.high - scale.low);
    return scale.diverging ? cool_warm(t) : viridis(t);
}

glm::vec3 method_color(Method method) {
    if (method == Method::MarchingCubes) return {0.90f, 0.62f, 0.00f}; // orange
    if (method == Method::Gradient) return {0.00f, 0.62f, 0.45f};      // bluish green
    return {0.00f, 0.45f, 0.70f};                                      // blue: sna, snert
}

} // namespace snert::render
