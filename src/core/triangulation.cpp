// Splitting the net's quads into triangles (de Bruin et al., section 2.5).
#include "triangulation.h"

#include <algorithm>
#include <cmath>

namespace snert {

namespace {

float angle_at(glm::vec3 apex, glm::vec3 a, glm::vec3 b) {
    const glm::vec3 u = a - apex, v = b - apex;
    const float lu = glm::length(u), lv = glm::length(v);
    if (!(lu > 0.0f) || !(lv > 0.0f)) return 0.0f;
    return std::acos(std::clamp(glm::dot(u, v) / (lu * lv), -1.0f, 1.0f));
}

} // namespace

bool quad_splits_along_ac(glm::vec3 a, glm::vec3 b, glm::vec3 c, glm::vec3 d,
                          TriangulationRule rule, glm::vec3 spacing) {
    a *= spacing, b *= spacing, c *= spacing, d *= spacing;
    if (rule == TriangulationRule::ShorterDiagonal)
        return glm::dot(a - c, a - c) <= glm::dot(b - d, b - d);
    // Delaunay: a-c is the locally Delaunay edge when the angles opposite it sum to at most pi.
    return angle_at(b, a, c) + angle_at(d, c, a) <= 3.14159265358979f;
}

Mesh triangulate(const SurfaceNet& net, std::span<const glm::vec3> positions,
                 TriangulationRule rule, glm::vec3 spacing) {
    Mesh mesh;
    mesh.positions.assign(positions.begin(), positions.end());
    mesh.indices.resize(net.quads.size() * 6 + net.triangles.size() * 3);
    std::uint32_t* out = mesh.indices.data();
    for (const auto& q : net.quads) {
        const bool along_ac = quad_splits_along_ac(positions[q[0]], positions[q[1]],
                                                   positions[q[2]], positions[q[3]], rule, spacing);
        for (const auto& t : quad_triangles(q, along_ac)) out = std::copy(t.begin(), t.end(), out);
    }
    for (const auto& t : net.triangles) out = std::copy(t.begin(), t.end(), out);
    return mesh;
}

} // namespace snert
