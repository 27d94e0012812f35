// One layer of outside around a volume or a segmentation (closed_border.h).
#include "closed_border.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "huge_pages.h"
#include "parallel.h"

namespace snert {

namespace {

glm::ivec3 padded_dims(glm::ivec3 dims) {
    if (glm::any(glm::lessThan(dims, glm::ivec3(1))))
        throw std::invalid_argument("padding: an empty grid");
    constexpr int kMax = std::numeric_limits<int>::max() - 2;
    if (glm::any(glm::greaterThan(dims, glm::ivec3(kMax))))
        throw std::invalid_argument("padding: a dimension too large");
    return dims + 2;
}

// Fills every sample of a (dims + 2) grid from the sample at the clamped index of the (dims)
// grid, through `pad` where the padded sample lies outside that grid. Slices in parallel; each
// sample is written once, so the result does not depend on the thread count.
template <class T, class Pad>
void fill_padded(const T* in, glm::ivec3 dims, T* out, const Pad& pad) {
    const glm::ivec3 pd = dims + 2;
    const std::size_t row = std::size_t(pd.x);
    for_each_chunk(std::size_t(pd.z), 1, [&](std::size_t, std::size_t first, std::size_t end) {
        for (std::size_t pz = first; pz < end; ++pz) {
            const int z = std::clamp(int(pz) - 1, 0, dims.z - 1);
            const bool z_pad = pz == 0 || int(pz) == pd.z - 1;
            for (int py = 0; py < pd.y; ++py) {
                const int y = std::clamp(py - 1, 0, dims.y - 1);
                const bool row_pad = z_pad || py == 0 || py == pd.y - 1;
                const T* src = in + (std::size_t(z) * std::size_t(dims.y) + std::size_t(y)) *
                                        std::size_t(dims.x);
                T* dst = out + (pz * std::size_t(pd.y) + std::size_t(py)) * row;
                dst[0] = pad(src[0]);
                dst[row - 1] = pad(src[dims.x - 1]);
                if (row_pad)
                    for (int x = 0; x < dims.x; ++x) dst[x + 1] = pad(src[x]);
                else
                    std::copy(src, src + dims.x, dst + 1);
            }
        }
    });
}

std::size_t checked_count(glm::ivec3 d) {
    const std::size_t max = std::numeric_limits<std::size_t>::max();
    const std::size_t xy = std::size_t(d.x) * std::size_t(d.y);
    if (xy / std::size_t(d.x) != std::size_t(d.y) || (d.z > 0 && xy > max / std::size_t(d.z)))
        throw std::invalid_argument("padding: the sample count overflows");
    return xy * std::size_t(d.z);
}

} // namespace

float outside_pad_value(float value, float iso, InsideIs rule) {
    if (!is_inside(value, iso, rule)) return value;
    // Mirror about iso; the result must be strictly outside (a sample at iso counts as inside)
    // and finite (2 iso - value can overflow).
    const float lowest = std::numeric_limits<float>::lowest();
    const float highest = std::numeric_limits<float>::max();
    if (rule == InsideIs::Above) {
        const float mirrored = std::max(lowest, float(2.0 * double(iso) - double(value)));
        return mirrored < iso ? mirrored : std::nextafter(iso, lowest);
    }
    const float mirrored = std::min(highest, float(2.0 * double(iso) - double(value)));
    return mirrored > iso ? mirrored : std::nextafter(iso, highest);
}

Volume pad_outside(const Volume& volume, float iso, InsideIs rule) {
    Volume padded;
    padded.dims = padded_dims(volume.dims);
    padded.spacing = volume.spacing;
    padded.direction = volume.direction;
    padded.origin = index_to_world(volume, glm::vec3(-1.0f));
    detail::resize_on_huge_pages(padded.samples, checked_count(padded.dims));
    fill_padded(volume.samples.data(), volume.dims, padded.samples.data(),
                [iso, rule](float v) { return outside_pad_value(v, iso, rule); });
    return padded;
}

Segmentation pad_outside(const Segmentation& segmentation) {
    Segmentation padded;
    padded.dims = padded_dims(segmentation.dims);
    padded.inside.resize(checked_count(padded.dims));
    fill_padded(segmentation.inside.data(), segmentation.dims, padded.inside.data(),
                [](std::uint8_t) { return std::uint8_t(0); });
    return padded;
}

} // namespace snert
