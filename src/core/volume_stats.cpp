// Histogram, Otsu's iso suggestion and the label-map helpers.
//
// This work is based on:
//  - N. Otsu, "A threshold selection method from gray-level histograms", IEEE Trans. SMC 9(1),
//    1979: the threshold maximises the between-class variance w0 w1 (m0 - m1)^2.
#include <algorithm>
#include <cmath>
#include <limits>
#include <set>
#include <stdexcept>

#include "parallel.h"
#include "volume_stats.h"

namespace snert {

// ---- Histogram ----------------------------------------------------------------------------------

double Histogram::bin_width() const {
    return counts.empty() ? 0.0 : (double(hi) - double(lo)) / double(counts.size());
}

double Histogram::bin_centre(std::size_t bin) const {
    return double(lo) + (double(bin) + 0.5) * bin_width();
}

std::uint64_t Histogram::total() const {
    std::uint64_t sum = 0;
    for (auto c : counts) sum += c;
    return sum;
}

Histogram make_histogram(const Volume& volume, int bins) {
    return make_histogram(volume, bins, value_range(volume));
}

Histogram make_histogram(const Volume& volume, int bins, ValueRange range) {
    bins = std::clamp(bins, 1, 1 << 20);
    Histogram h;
    h.counts.assign(std::size_t(bins), 0);
    h.lo = range.min;
    h.hi = range.max;
    // Counted in parallel pieces, each with counts of its own, then summed: whole numbers, the
    // same sums in any order. A clinical CT's 100 M samples took 150 ms on one thread. Fine
    // histograms (more than 4096 bins) are counted in one piece, so the pieces' counts stay small.
    const std::size_t samples = volume.samples.size();
    const std::size_t piece = bins > 4096 ? std::max<std::size_t>(samples, 1)
                                          : std::max<std::size_t>(samples / 16 + 1, 1 << 20);
    std::vector<std::vector<std::uint64_t>> pieces(chunk_count(samples, piece));
    for_each_chunk(samples, piece, [&](std::size_t p, std::size_t begin, std::size_t end) {
        // Locals, not the caller's by reference: the counts' stores would make the compiler
        // load those again for every sample.
        const float* values = volume.samples.data();
        const double lo = h.lo, span = double(h.hi) - double(h.lo), count = double(bins);
        const double last = double(bins - 1);
        const auto skipped = std::uint32_t(bins); // a non-finite sample's slot, not counted
        // A block's bins first, in a loop without branches that the compiler vectorises (the
        // division was most of a sample's time); a value off the range (non-finite included)
        // is clamped into it before the conversion, then the non-finite are sent to the
        // skipped slot. Then counted into four sets of counts in turn: a CT's long runs of one
        // bin (air) made each increment wait for the one before.
        constexpr std::size_t kBlock = 256, kSets = 4;
        const std::size_t stride = std::size_t(bins) + 1;
        const std::size_t set_count = bins > 4096 ? 1 : kSets; // a fine histogram's are large
        std::vector<std::uint64_t> sets(set_count * stride, 0);
        std::uint32_t bin[kBlock];
        for (std::size_t first = begin; first < end; first += kBlock) {
            const std::size_t n = std::min(kBlock, end - first);
            for (std::size_t k = 0; k < n; ++k) {
                const float v = values[first + k];
                const double x = span > 0.0 ? (double(v) - lo) / span * count : 0.0;
                const auto b = std::uint32_t(int(std::max(0.0, std::min(last, x))));
                bin[k] = v - v == 0.0f ? b : skipped; // v - v is 0 exactly for finite v
            }
            std::size_t k = 0;
            if (set_count == kSets)
                for (; k + kSets <= n; k += kSets)
                    for (std::size_t s = 0; s < kSets; ++s) ++sets[s * stride + bin[k + s]];
            for (; k < n; ++k) ++sets[bin[k]];
        }
        pieces[p].assign(std::size_t(bins), 0);
        for (std::size_t s = 0; s < set_count; ++s)
            for (std::size_t b = 0; b < std::size_t(bins); ++b)
                pieces[p][b] += sets[s * stride + b];
    });
    for (const std::vector<std::uint64_t>& counts : pieces)
        for (std::size_t b = 0; b < counts.size(); ++b) h.counts[b] += counts[b];
    return h;
}

Histogram merge_bins(const Histogram& histogram, int factor) {
    if (factor < 1 || histogram.counts.size() % std::size_t(factor) != 0)
        throw std::invalid_argument("merge_bins: the factor must divide the bin count");
    Histogram merged;
    merged.lo = histogram.lo;
    merged.hi = histogram.hi;
    merged.counts.assign(histogram.counts.size() / std::size_t(factor), 0);
    for (std::size_t b = 0; b < histogram.counts.size(); ++b)
        merged.counts[b / std::size_t(factor)] += histogram.counts[b];
    return merged;
}

float otsu_threshold(const Histogram& histogram) {
    const auto& c = histogram.counts;
    const double total = double(histogram.total());
    if (c.size() < 2 || total == 0.0 || !(histogram.hi > histogram.lo)) return histogram.lo;
    double weighted_total = 0.0;
    for (std::size_t i = 0; i < c.size(); ++i) weighted_total += double(i) * double(c[i]);
    // Class 0 = bins 0..k. A run of equally good k (empty bins between two peaks) is resolved
    // to its middle, so a two-valued image is split half-way between its values.
    double w0 = 0.0, sum0 = 0.0, best = -1.0;
    std::size_t best_first = 0, best_last = 0;
    for (std::size_t k = 0; k + 1 < c.size(); ++k) {
        w0 += double(c[k]);
        sum0 += double(k) * double(c[k]);
        const double w1 = total - w0;
        if (w0 == 0.0) continue;
        if (w1 == 0.0) break;
        const double m0 = sum0 / w0, m1 = (weighted_total - sum0) / w1;
        const double between = w0 * w1 * (m0 - m1) * (m0 - m1);
        const double tolerance = 1e-12 * std::max(best, 1.0);
        if (between > best + tolerance) {
            best = between;
            best_first = best_last = k;
        } else if (std::abs(between - best) <= tolerance && best_last + 1 == k) {
            best_last = k;
        }
    }
    if (best < 0.0) return histogram.lo;
    const double boundary = 0.5 * double(best_first + best_last) + 1.0;
    const double value = double(histogram.lo) + boundary * histogram.bin_width();
    return float(std::clamp(value, double(histogram.lo), double(histogram.hi)));
}

float suggest_iso(const Volume& volume) {
    return suggest_iso(volume, value_range(volume));
}

float suggest_iso(const Volume& volume, ValueRange range) {
    return otsu_threshold(make_histogram(volume, kIsoSuggestionBins, range));
}

// ---- Label maps ---------------------------------------------------------------------------------

namespace {

std::string text(glm::ivec3 v) {
    return std::to_string(v.x) + "x" + std::to_string(v.y) + "x" + std::to_string(v.z);
}

} // namespace

std::vector<int> labels_present(const Volume& labels) {
    std::set<int> found;
    for (float v : labels.samples) {
        if (!std::isfinite(v) || std::abs(v) > 2.0e9f) continue;
        found.insert(int(std::nearbyint(v)));
    }
    return {found.begin(), found.end()};
}

BoundaryIso boundary_iso(const Volume& grey, const Segmentation& mask) {
    if (grey.dims != mask.dims || grey.samples.size() != mask.inside.size())
        throw std::invalid_argument("boundary_iso: the mask's grid " + text(mask.dims) +
                                    " differs from the grey image's " + text(grey.dims));
    double inside_sum = 0.0, outside_sum = 0.0;
    std::size_t pairs = 0;
    const glm::ivec3 d = grey.dims;
    const auto visit = [&](std::size_t a, std::size_t b) {
        if (mask.inside[a] == mask.inside[b]) return;
        const std::size_t in = mask.inside[a] ? a : b, out = mask.inside[a] ? b : a;
        inside_sum += double(grey.samples[in]);
        outside_sum += double(grey.samples[out]);
        ++pairs;
    };
    for (int z = 0; z < d.z; ++z)
        for (int y = 0; y < d.y; ++y)
            for (int x = 0; x < d.x; ++x) {
                const std::size_t i = grey.index(x, y, z);
                if (x + 1 < d.x) visit(i, grey.index(x + 1, y, z));
                if (y + 1 < d.y) visit(i, grey.index(x, y + 1, z));
                if (z + 1 < d.z) visit(i, grey.index(x, y, z + 1));
            }
    if (pairs == 0)
        throw std::invalid_argument("the label's mask has no boundary (it is empty or fills the "
                                    "whole volume)");
    BoundaryIso result;
    result.pairs = pairs;
    result.inside_mean = inside_sum / double(pairs);
    result.outside_mean = outside_sum / double(pairs);
    result.iso = float(0.5 * (result.inside_mean + result.outside_mean));
    result.inside = result.inside_mean >= result.outside_mean ? InsideIs::Above : InsideIs::Below;
    return result;
}

} // namespace snert
