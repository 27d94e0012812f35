#include "triangle_pick.h"

#include <cmath>
#include <limits>

#include <glm/gtc/constants.hpp>

#include "vector_angle.h"

namespace snert {

std::optional<TriangleHit> first_hit(const Mesh& mesh, glm::vec3 origin, glm::vec3 direction) {
    // Möller and Trumbore's test, in double so that grazing rays decide the same on every
    // machine.
    const glm::dvec3 o(origin), d(direction);
    if (glm::dot(d, d) == 0.0) return std::nullopt;
    std::optional<TriangleHit> best;
    double best_t = std::numeric_limits<double>::infinity();
    const std::size_t n = mesh.triangle_count();
    for (std::size_t t = 0; t < n; ++t) {
        const std::uint32_t* i = &mesh.indices[3 * t];
        if (i[0] >= mesh.positions.size() || i[1] >= mesh.positions.size() ||
            i[2] >= mesh.positions.size())
            continue;
        const glm::dvec3 a(mesh.positions[i[0]]), b(mesh.positions[i[1]]), c(mesh.positions[i[2]]);
        const glm::dvec3 e1 = b - a, e2 = c - a;
        const glm::dvec3 p = glm::cross(d, e2);
        const double det = glm::dot(e1, p);
        // Parallel to the plane, or a triangle without area.
        if (std::abs(det) <= 1e-12 * glm::length(e1) * glm::length(e2) * glm::length(d)) continue;
        const glm::dvec3 s = o - a;
        const double u = glm::dot(s, p) / det;
        if (u < 0.0 || u > 1.0) continue;
        const glm::dvec3 q = glm::cross(s, e1);
        const double v = glm::dot(d, q) / det;
        if (v < 0.0 || u + v > 1.0) continue;
        const double hit_t = glm::dot(e2, q) / det;
        if (!(hit_t > 0.0) || hit_t >= best_t) continue;
        best_t = hit_t;
        best = TriangleHit{t, float(hit_t), glm::vec3(o + hit_t * d)};
    }
    if (best) {
        const std::uint32_t* i = &mesh.indices[3 * best->triangle];
        float nearest = std::numeric_limits<float>::infinity();
        for (int k = 0; k < 3; ++k) {
            const glm::vec3 offset = mesh.positions[i[k]] - best->point;
            const float d2 = glm::dot(offset, offset);
            if (d2 < nearest) {
                nearest = d2;
                best->nearest_vertex = i[k];
            }
        }
    }
    return best;
}

std::array<float, 3> triangle_angles(glm::vec3 a, glm::vec3 b, glm::vec3 c) {
    if (triangle_shape(a, b, c).degenerate) return {0.0f, 0.0f, 0.0f};
    const glm::dvec3 p[3] = {glm::dvec3(a), glm::dvec3(b), glm::dvec3(c)};
    std::array<float, 3> angles{};
    for (int k = 0; k < 3; ++k) {
        const glm::dvec3 u = p[(k + 1) % 3] - p[k], w = p[(k + 2) % 3] - p[k];
        // As triangle_shape measures them (vector_angle.h).
        angles[std::size_t(k)] =
            float(detail::vector_angle(glm::length(glm::cross(u, w)), glm::dot(u, w)) * 180.0 /
                  glm::pi<double>());
    }
    return angles;
}

} // namespace snert
