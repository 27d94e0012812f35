// Exact triangle-triangle intersection of the triangles of one mesh, and a mesh-level count of
// self-intersecting triangle pairs (what TetGen's `tetgen -d` reports as intersecting facets).
//
// Two triangles of a mesh INTERSECT when their closed point sets meet anywhere other than at
// the corners and edges they share:
//   - no shared corner: any common point counts, touching included (a corner of one on the
//     other, an edge on an edge), as TetGen counts it;
//   - one shared corner p: they intersect when they meet anywhere but p (one pierces the other
//     near p, an edge of one lies along an edge of the other, they overlap in their plane);
//   - a shared edge pq: they intersect only when they overlap beyond pq, i.e. they are coplanar
//     and folded onto each other (both free corners on the same side of pq); any dihedral angle
//     other than zero is fine, even a sharp one;
//   - three shared corners: a duplicate triangle, which always intersects its twin.
// Corners are shared when their positions are bitwise equal (+0 and -0 are equal), so two
// triangles sharing vertex indices share corners, and so do coincident but unwelded vertices
// (TetGen merges those too).
//
// The predicates are exact for every finite float input: orient3d and orient2d are evaluated in
// double with Shewchuk's forward error bound (Adaptive Precision Floating-Point Arithmetic and
// Fast Robust Geometric Predicates, 1997), and where the filter cannot decide the sign, exactly
// with error-free transformations (TwoSum, and TwoProduct by fma). Float coordinates make this
// exact without overflow or underflow: every intermediate term is a multiple of 2^-447 and below
// 2^400. Non-finite corners make a triangle intersect nothing.
//
// A flat triangle (three distinct collinear corners) is treated as the union of its edges, of
// which only those not ending in a shared corner are tested; but when it shares two corners
// with the other, it lies along the shared edge, folded onto the other: intersecting. A
// triangle with two coincident corners is no facet at all and intersects nothing. TetGen
// reports such pairs the same way. All of these are counted as `degenerate` by the quality
// metrics anyway, and make a mesh not FE-ready on their own.
#pragma once

#include <cstddef>
#include <cstdint>
#include <utility>
#include <vector>

#include <glm/glm.hpp>

#include "mesh.h"

namespace snert {

// Sign of det[a - d, b - d, c - d] (Shewchuk's orient3d): +1 when d lies below the plane of
// a, b, c, on the side opposite to the normal (b - a) x (c - a); -1 above; 0 coplanar. Exact.
int orient3d(glm::vec3 a, glm::vec3 b, glm::vec3 c, glm::vec3 d);

// Sign of det[a - c, b - c] of 2D points: +1 when a, b, c turn counter-clockwise. Exact.
int orient2d(glm::vec2 a, glm::vec2 b, glm::vec2 c);

// Whether triangles a and b intersect other than at shared corners and edges (rules above).
bool triangles_intersect(const glm::vec3 a[3], const glm::vec3 b[3]);

namespace detail {
// The same answer by the general way alone: the edges of each against the other, without the
// shortcut for pairs in general position. The tests hold triangles_intersect to it.
bool triangles_intersect_by_edges(const glm::vec3 a[3], const glm::vec3 b[3]);
} // namespace detail

// Self-intersecting triangle pairs of a mesh.
struct SelfIntersections {
    std::size_t count = 0; // intersecting pairs (best 0)
    // The first pairs (t, u), t < u, in increasing order of t then u, at most the cap given.
    std::vector<std::pair<std::uint32_t, std::uint32_t>> pairs;
};

// Finds every intersecting pair of triangles. Broad phase: a uniform grid over the triangles'
// bounding boxes (cells of about the mean box size, at most a few million cells); a pair is
// examined in the one cell that holds the lowest corner of its boxes' overlap, so never twice
// and never all pairs. Parallel over chunks of triangles; the result does not depend on the
// thread count. Throws std::invalid_argument for a bad index. `max_pairs` caps the list, not
// the count.
SelfIntersections self_intersections(const Mesh& mesh, std::size_t max_pairs = 64);

// The intersecting pairs with at least one triangle marked in `subject` (one entry per
// triangle), found through the same grid but examined only from the marked triangles: what a
// local change (a decimation step) may have broken, at the cost of the marked triangles alone.
// Same order and cap as above.
SelfIntersections intersections_involving(const Mesh& mesh,
                                          const std::vector<std::uint8_t>& subject,
                                          std::size_t max_pairs = 64);

// The count alone.
std::size_t count_self_intersections(const Mesh& mesh);

} // namespace snert
