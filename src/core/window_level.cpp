// Window/level and the slice's pixels (see window_level.h).
#include "window_level.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace snert {

namespace {
constexpr Named<WindowPreset> kWindowPresets[] = {
    {WindowPreset::Auto, "auto", "automatic"},
    {WindowPreset::Full, "full", "full range"},
    {WindowPreset::CtBone, "ct-bone", "CT bone (W 2000, L 400)"},
    {WindowPreset::CtSoftTissue, "ct-soft-tissue", "CT soft tissue (W 400, L 40)"},
    {WindowPreset::Mr, "mr", "MR (1-99 % of the signal)"},
};
} // namespace

std::span<const Named<WindowPreset>> name_table(WindowPreset) {
    return kWindowPresets;
}

WindowLevel window_preset(WindowPreset preset, const Volume& volume) {
    if (preset == WindowPreset::Auto) {
        const ValueRange range = value_range(volume);
        preset = range.min <= -900.0f && range.max >= 200.0f ? WindowPreset::CtSoftTissue
                 : range.min >= 0.0f                         ? WindowPreset::Mr
                                                             : WindowPreset::Full;
    }
    switch (preset) {
    case WindowPreset::CtBone:
        return {2000.0f, 400.0f};
    case WindowPreset::CtSoftTissue:
        return {400.0f, 40.0f};
    case WindowPreset::Auto:
    case WindowPreset::Full:
    case WindowPreset::Mr:
        break;
    }
    const ValueRange range = value_range(volume);
    float lo = range.min, hi = range.max;
    if (preset == WindowPreset::Mr) {
        std::vector<float> signal;
        signal.reserve(volume.samples.size());
        for (float v : volume.samples)
            if (std::isfinite(v) && v != 0.0f) signal.push_back(v);
        if (!signal.empty()) {
            const auto at = [&](double q) {
                const auto k = std::ptrdiff_t(q * double(signal.size() - 1));
                std::nth_element(signal.begin(), signal.begin() + k, signal.end());
                return signal[std::size_t(k)];
            };
            lo = at(0.01);
            hi = at(0.99);
        }
    }
    const float window = hi > lo ? hi - lo : 1.0f;
    return {window, 0.5f * (lo + hi)};
}

std::uint8_t window_grey(float value, const WindowLevel& wl) {
    if (!std::isfinite(value)) return 0;
    const float w = wl.window > 0.0f ? wl.window : 1.0f;
    const float t = (value - (wl.level - 0.5f * w)) / w;
    return std::uint8_t(std::lround(255.0f * std::clamp(t, 0.0f, 1.0f)));
}

std::vector<std::uint8_t> slice_pixels(const Slice& slice, const WindowLevel& wl,
                                       std::span<const std::uint8_t> mask, glm::vec3 overlay,
                                       float opacity) {
    if (!mask.empty() && mask.size() != slice.values.size())
        throw std::invalid_argument("slice_pixels: the mask does not match the slice");
    std::vector<std::uint8_t> rgba(slice.values.size() * 4);
    for (std::size_t i = 0; i < slice.values.size(); ++i) {
        const float grey = float(window_grey(slice.values[i], wl));
        glm::vec3 c(grey);
        if (!mask.empty() && mask[i] != 0) c = (1.0f - opacity) * c + opacity * 255.0f * overlay;
        for (int k = 0; k < 3; ++k) rgba[4 * i + std::size_t(k)] = std::uint8_t(std::lround(c[k]));
        rgba[4 * i + 3] = 255;
    }
    return rgba;
}

} // namespace snert
