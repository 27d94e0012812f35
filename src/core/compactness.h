// Compactness, the paper's third requirement of an FE mesh: how few triangles a surface needs.
// Two uses of decimation (decimation.h), shared by `snert compare`, `snert render` and the app:
//
//   - the equal-count comparison: the paper compares MC and SNERT "with the same number of
//     triangles" (Fig. 6); MC makes about as many triangles as the net on a phantom but not on
//     every scan, so every mesh is reduced to one count and measured again;
//   - the compactness curve: each mesh reduced to 100, 50, 25, 10 and 5 % of its triangles, with
//     its distance to the unreduced mesh and its triangle quality at each level, showing which
//     method keeps its accuracy and quality as triangles are removed.
#pragma once

#include <array>
#include <cstddef>
#include <optional>
#include <span>
#include <vector>

#include "decimation.h"
#include "pipeline.h"

namespace snert {

// The count every result is reduced to: `requested` when given, else the smallest triangle
// count among them. 0 for no results.
std::size_t equal_count_target(std::span<const MethodResult> results,
                               std::optional<std::size_t> requested);

// Reduces every result's (world) mesh to `target` triangles and measures it again with
// measure() (`reference` and `what` as the pipeline measured it, the mesh taken back to index
// space). Keeps ms and the relaxation's numbers. Each net's to_marching_cubes is its distance to
// the UNREDUCED Marching Cubes mesh among the results, the best stand-in for the iso-surface.
// Meshes already at or under `target` are left as they are. Where one mesh stops short of
// `target` (decimation.h: its checks refused further steps), the others are reduced to the count
// it reached instead, so the counts stay equal. Returns one report per result (requested: the
// count asked of that mesh in the end).
std::vector<DecimationReport> reduce_to_equal_count(std::span<MethodResult> results,
                                                    std::size_t target, const Volume& volume,
                                                    const DistanceFunction& reference,
                                                    const MeasureOptions& what);

// The shares of the triangles the compactness curve keeps.
inline constexpr std::array<double, 5> kCompactnessFractions = {1.0, 0.5, 0.25, 0.1, 0.05};

struct CompactnessPoint {
    double fraction = 1.0;     // share of the unreduced triangles asked for
    std::size_t triangles = 0; // triangles reached
    // Distance between the reduced and the unreduced surface (voxels, index space), both ways:
    // mean = the average of the two area-weighted mean distances (reduced to unreduced and back),
    // max = the larger of the two largest sampled distances (a sampled Hausdorff distance).
    double accuracy_mean = 0, accuracy_max = 0; // best 0
    double quality_mean = 0;                    // smallest / largest angle, world units (best 1)
    int refusals = 0; // decimation tries refused on the way here (decimation.h)
};

// The curve of one (world) mesh on `volume`'s grid: one point per kCompactnessFractions, each
// level reduced from the one before. Empty for a mesh without triangles. Deterministic.
std::vector<CompactnessPoint> compactness_curve(const Mesh& mesh, const Volume& volume);

} // namespace snert
