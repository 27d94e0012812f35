// Decimation: fewer triangles for the same surface, with meshoptimizer's simplifier (edge
// collapses ordered by quadric error: Garland and Heckbert, Surface Simplification Using Quadric
// Error Metrics, 1997), and checks that keep the result fit for a finite-element mesher.
//
// meshoptimizer (0.18) only collapses edges onto existing vertices: every vertex of the result is
// a vertex of the input, at the same float position. It stops at a triangle count or at an error
// relative to the mesh's extent (its largest bounding-box side); decimate() takes an absolute
// error in the mesh's own units and converts it. It knows nothing of self-intersections, and a
// collapse can pinch the surface (a non-manifold edge or vertex) or change its genus. So
// decimate() works in steps (each at most halving the count) and checks every step's result
// against the mesh it started from:
//   - topology: no edge of three or more triangles, no vertex of two fans, no edge used twice in
//     one direction, where the input had none; no new boundary edge between vertices that were
//     not on the input's boundary (a closed surface stays closed, an open one is open only
//     where it was); no connected component vanishes, except specks (below). A tunnel narrower
//     than the deviation may close (the genus falls, reported as euler_change; the surface stays
//     closed and manifold), which a check of the whole surface's Euler characteristic would
//     refuse with no place to point at (none closed on the carotid and the 4 mm head, measured);
//   - no new self-intersecting triangle pair (exact predicates, triangle_intersection.h);
//   - no flipped triangle: a new triangle's normal must agree with the input's vertex normals at
//     its corners (positive dot product with their sum);
//   - no new degenerate triangle (metrics.h's kDegenerateHeightRatio).
// Each step simplifies patches of the mesh (the triangles in one cell of a grid, about a thousand
// each, the grid shifted by half a cell between steps) on their own, rims locked, in parallel.
// The rest passed before, so only what a step changed is examined: its new triangles (flips,
// shape, and intersections against the triangles near them, through a grid), and the edges and
// fans of the vertices of triangles that came or went; a retry examines only the triangles that
// its refused predecessor did not pass (vertices never move, so the verdicts on the others stand).
// Where a try breaks a rule, the patches around what broke it are halved and each half is
// simplified again on its own, down to patches of 16 triangles, which keep their triangles as
// they are; the rest of the step keeps its collapses. So what cannot be reduced (on a noisy scan,
// a few hundred thin places that pinch whenever they are collapsed) stays fine-grained in small
// patches, and the step is accepted once every patch passes; a step that keeps nothing is tried
// again half as large. What was refused is reported: a result never breaks a rule to reach the
// target.
//
// Specks, components too small to keep a closed shape at the target's share of their
// triangles, are removed whole before the first step (counted in the report), unless
// DecimationOptions::keep_every_component: a speck left to the collapses folds into a flat
// pillow that every step refuses, and keeping it spends the count on noise.
//
// Deterministic: the patches are independent, and neither they nor the checks depend on the
// thread count. Winding is kept: triangles keep the orientation of the input (see mesh.h).
#pragma once

#include <cstddef>
#include <limits>

#include "mesh.h"

namespace snert {

struct DecimationOptions {
    // Stop at or under this many triangles; 0 for no count goal (an error goal alone).
    std::size_t target_triangles = 0;
    // The largest deviation meshoptimizer's quadric estimate may reach, in the mesh's units
    // (absolute, summed over the steps); infinity for a count goal alone.
    float max_error = std::numeric_limits<float>::infinity();
    // Each step asks for at most this share of the triangles removed (0 < share <= 1).
    double step_share = 0.5;
    // Halvings of a step that collapsed nothing that passed, tried before decimate() stops.
    int max_shrinks = 4;
    // Specks, components of the input too small to keep a closed shape at the target's share
    // of their triangles (fewer than 4 left: a tetrahedron), may vanish; true keeps every one.
    // Noisy scans have hundreds (the 4 mm head: 178 of one voxel, 8 triangles each), and
    // shrinking each to a tetrahedron would spend a 5 % count on noise.
    bool keep_every_component = false;
};

// What decimate() did; counts are triangles unless said otherwise.
struct DecimationReport {
    std::size_t original = 0;  // triangles of the input
    std::size_t requested = 0; // DecimationOptions::target_triangles (0: none)
    std::size_t achieved = 0;  // triangles of the result
    float error = 0;           // meshoptimizer's deviation estimate summed over the steps (units)
    int steps = 0;             // steps accepted
    int refusals = 0;          // tries refused by the checks (each retried with the patches halved)
    // What the refused tries broke (summed over them): triangles flagged by each rule.
    std::size_t refused_topology = 0, refused_intersections = 0, refused_flips = 0,
                refused_degenerate = 0;
    // Specks that vanished (DecimationOptions::keep_every_component), and their input triangles.
    std::size_t vanished_components = 0, vanished_triangles = 0;
    bool stalled = false; // stopped short of the goal: no collapse was possible or allowed
    // Euler characteristic of the result minus the input's: +2 for each tunnel (handle) narrower
    // than the deviation that closed (0 on a sphere; noisy scans have many small tunnels).
    long euler_change = 0;
};

struct Decimated {
    Mesh mesh; // referenced vertices only, in the input's order
    DecimationReport report;
};

// Reduces `mesh` towards options.target_triangles (and/or options.max_error); see above. A mesh
// already at or under the target comes back unchanged. Throws std::invalid_argument for a bad
// index (index count not a multiple of 3, index out of range).
Decimated decimate(const Mesh& mesh, const DecimationOptions& options);

} // namespace snert
