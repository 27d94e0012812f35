// Binary segmentation by threshold or by label.
#include "segmentation.h"

#include <algorithm>
#include <cmath>
#include <numeric>

namespace snert {

std::size_t Segmentation::count_inside() const {
    return std::size_t(std::count(inside.begin(), inside.end(), std::uint8_t(1)));
}

Segmentation segment_threshold(const Volume& volume, float iso, InsideIs rule) {
    Segmentation s{volume.dims, std::vector<std::uint8_t>(volume.samples.size())};
    // NaN compares false both ways, so it is outside for either rule.
    for (std::size_t i = 0; i < volume.samples.size(); ++i)
        s.inside[i] = is_inside(volume.samples[i], iso, rule) ? 1 : 0;
    return s;
}

Segmentation segment_label(const Volume& labels, int label) {
    Segmentation s{labels.dims, std::vector<std::uint8_t>(labels.samples.size())};
    const float wanted = float(label);
    for (std::size_t i = 0; i < labels.samples.size(); ++i)
        s.inside[i] = std::nearbyint(labels.samples[i]) == wanted ? 1 : 0;
    return s;
}

Volume mask_volume(const Segmentation& segmentation, const Volume& like) {
    Volume v;
    v.dims = segmentation.dims;
    v.spacing = like.spacing;
    v.origin = like.origin;
    v.direction = like.direction;
    v.samples.resize(segmentation.inside.size());
    for (std::size_t i = 0; i < v.samples.size(); ++i)
        v.samples[i] = segmentation.inside[i] ? 1.0f : 0.0f;
    return v;
}

} // namespace snert
