// Binary segmentation by threshold or by label.
#include "segmentation.h"

#include <algorithm>
#include <cmath>
#include <numeric>

#include "huge_pages.h"
#include "parallel.h"

namespace snert {

namespace {

// Samples per chunk of the parallel loops: large enough to amortise handing out a chunk.
constexpr std::size_t kSamplesPerChunk = std::size_t(1) << 20;

// out[i] = inside(samples[i]), over fixed chunks in parallel. `inside` is a plain comparison so
// that the loop vectorises.
template <class Inside>
void classify_samples(const std::vector<float>& samples, std::vector<std::uint8_t>& out,
                      const Inside& inside) {
    for_each_chunk(samples.size(), kSamplesPerChunk,
                   [&, inside](std::size_t, std::size_t first, std::size_t end) {
                       // Local pointers: a byte store may alias anything, so through the
                       // captures they would be reloaded on every sample.
                       const float* in = samples.data() + first;
                       std::uint8_t* o = out.data() + first;
                       for (std::size_t i = 0; i < end - first; ++i) o[i] = inside(in[i]) ? 1 : 0;
                   });
}

} // namespace

std::size_t Segmentation::count_inside() const {
    return std::size_t(std::count(inside.begin(), inside.end(), std::uint8_t(1)));
}

Segmentation segment_threshold(const Volume& volume, float iso, InsideIs rule) {
    Segmentation s{volume.dims, {}};
    detail::resize_on_huge_pages(s.inside, volume.samples.size());
    // NaN compares false both ways, so it is outside for either rule.
    if (rule == InsideIs::Above)
        classify_samples(volume.samples, s.inside, [iso](float v) { return v >= iso; });
    else
        classify_samples(volume.samples, s.inside, [iso](float v) { return v <= iso; });
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
    detail::resize_on_huge_pages(v.samples, segmentation.inside.size());
    for (std::size_t i = 0; i < v.samples.size(); ++i)
        v.samples[i] = segmentation.inside[i] ? 1.0f : 0.0f;
    return v;
}

} // namespace snert
