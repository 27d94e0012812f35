// Triangulation of the SurfaceNet's quads (de Bruin et al., section 2.5). Each quad splits
// into two triangles along its shorter diagonal, or by the Delaunay criterion (the diagonal
// whose two opposite angles sum to less than pi). Recomputed after every iteration, because
// the node positions change. The mesh's vertices are the net's nodes, in node order.
#pragma once

#include <array>
#include <cstdint>
#include <span>

#include <glm/glm.hpp>

#include "mesh.h"
#include "surface_net.h"

namespace snert {

enum class TriangulationRule { ShorterDiagonal, Delaunay };

// Lengths and angles are measured in world millimetres (index offsets times `spacing`), so thick
// slices do not skew the choice.
Mesh triangulate(const SurfaceNet& net, std::span<const glm::vec3> positions,
                 TriangulationRule rule = TriangulationRule::ShorterDiagonal,
                 glm::vec3 spacing = glm::vec3(1.0f));

// Which corners of a quad make its two triangles (winding kept), [along_ac][triangle][corner]:
// along its first diagonal q0-q2, or along q1-q3.
inline constexpr std::uint8_t kQuadSplitCorners[2][2][3] = {{{0, 1, 3}, {1, 2, 3}},
                                                            {{0, 1, 2}, {0, 2, 3}}};

// The two triangles of quad q (kQuadSplitCorners).
inline std::array<std::array<std::uint32_t, 3>, 2>
quad_triangles(const std::array<std::uint32_t, 4>& q, bool along_ac) {
    const auto& c = kQuadSplitCorners[along_ac ? 1 : 0];
    return {{{q[c[0][0]], q[c[0][1]], q[c[0][2]]}, {q[c[1][0]], q[c[1][1]], q[c[1][2]]}}};
}

namespace detail {
bool delaunay_splits_along_ac(glm::vec3 a, glm::vec3 b, glm::vec3 c, glm::vec3 d);
} // namespace detail

// True when the quad a b c d (index space) splits along a-c under `rule`. Inline: the guard asks
// it for every quad of every step, and the shorter diagonal is a few products (the call
// and its twelve floats' passing took longer).
inline bool quad_splits_along_ac(glm::vec3 a, glm::vec3 b, glm::vec3 c, glm::vec3 d,
                                 TriangulationRule rule, glm::vec3 spacing) {
    a *= spacing, b *= spacing, c *= spacing, d *= spacing;
    if (rule == TriangulationRule::ShorterDiagonal)
        return glm::dot(a - c, a - c) <= glm::dot(b - d, b - d);
    return detail::delaunay_splits_along_ac(a, b, c, d);
}

} // namespace snert
