// Facts of a volume's samples that the CLI and the app suggest defaults from: the value
// histogram, Otsu's iso, the labels of a label map and the grey iso at a mask's boundary.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "segmentation.h"
#include "volume.h"

namespace snert {

// ---- Histogram and iso suggestion -------------------------------------------------------------

// Equal-width bins over [lo, hi], the range of the finite samples. Bin i holds values in
// [lo + i*w, lo + (i+1)*w), the last bin also holds hi. Non-finite samples are not counted
// (finite ones off a given range would fall into the end bins).
struct Histogram {
    float lo = 0.0f, hi = 0.0f;
    std::vector<std::uint64_t> counts;

    double bin_width() const; // double: hi - lo can exceed the float range
    double bin_centre(std::size_t bin) const;
    std::uint64_t total() const;
};
Histogram make_histogram(const Volume& volume, int bins = 256);
// The same where the volume's value_range() is known already (a loader has it): one pass over
// the samples instead of two.
Histogram make_histogram(const Volume& volume, int bins, ValueRange range);
// Every `factor` neighbouring bins added into one: exactly make_histogram(volume, bins / factor)
// (a bin index scaled by a power of two, floored, then halved is the coarser index), for a
// factor that is a power of two dividing the bin count. Throws std::invalid_argument when the
// factor does not divide it.
Histogram merge_bins(const Histogram& histogram, int factor);

// Otsu's threshold (Otsu 1979): the bin boundary that maximises the between-class variance
// of the histogram. Returns the value between the last bin of the dark class and the first of
// the bright one; lo for an empty or single-valued histogram.
float otsu_threshold(const Histogram& histogram);

// The iso the CLI and the app suggest when none is given: Otsu on a 256-bin histogram.
inline constexpr int kIsoSuggestionBins = 256;
float suggest_iso(const Volume& volume);
float suggest_iso(const Volume& volume, ValueRange range); // range: value_range(volume)

// ---- Label maps ------------------------------------------------------------------------------

// The distinct integer labels present in a label map, ascending (rounded to nearest).
std::vector<int> labels_present(const Volume& labels);

// The default iso of the grey image for a supervised segmentation: over every pair of
// 6-neighbour samples whose mask labels differ, the mean of the two grey values, i.e. the
// midpoint (inside_mean + outside_mean) / 2 of the grey levels on the two sides of the mask's
// boundary. Throws std::invalid_argument when the mask has no boundary (empty or full), or the
// grids differ.
struct BoundaryIso {
    float iso = 0.0f;
    double inside_mean = 0.0, outside_mean = 0.0;
    std::size_t pairs = 0;             // boundary neighbour pairs averaged
    InsideIs inside = InsideIs::Above; // Above when the object is brighter than its outside
};
BoundaryIso boundary_iso(const Volume& grey, const Segmentation& mask);

} // namespace snert
