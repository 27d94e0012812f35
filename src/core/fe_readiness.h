// The FE-readiness summary of a mesh: what a finite-element mesher or solver will ask of its
// triangles and of its topology, in one struct. The shares say how much of the surface has the
// small angles that stiffen a solver's matrices (under 15 and 30 degrees) and the obtuse angles
// that spoil its interpolation (over 120 degrees); the ranges give the best and worst
// triangle by two standard measures; the flags repeat the checks measure() made.
#pragma once

#include <cstddef>

#include "mesh.h"
#include "metrics.h"

namespace snert {

struct FeReadiness {
    std::size_t triangles = 0;
    // Shares of all triangles in [0, 1]; a degenerate triangle counts as smallest angle 0 and
    // largest angle 180 degrees.
    double min_angle_below_15 = 0;  // smallest angle < kFeSmallAngle
    double min_angle_below_30 = 0;  // smallest angle < kFeNarrowAngle
    double max_angle_above_120 = 0; // largest angle > kFeObtuseAngle
    // Ranges over all triangles (0 for a mesh without triangles).
    double radius_ratio_min = 0, radius_ratio_max = 0; // 2 r / R (best 1, 0 when degenerate)
    double aspect_ratio_min = 0, aspect_ratio_max = 0; // Verdict's (best 1, infinite when
                                                       // degenerate)
    bool closed = false;                               // Topology::watertight
    bool manifold = false;                             // Topology::manifold
    std::size_t self_intersections = 0;
};

// The triangle measures of `world_mesh` (world units, as everything FE-facing), with the
// topology and the self-intersections as measure() found them for the same mesh. Deterministic
// whatever the thread count. Throws std::invalid_argument for a bad index.
FeReadiness fe_readiness(const Mesh& world_mesh, const Topology& topology,
                         std::size_t self_intersections);
// The same from the quality_stats() of the world mesh, whose pass over the triangles gathers what
// the summary reads of their shapes: measure() takes both from one pass.
FeReadiness fe_readiness(const QualityStats& world_quality, const Topology& topology,
                         std::size_t self_intersections);

} // namespace snert
