#include "ray_pick.h"

#include <cmath>

namespace snert {

std::optional<RayHit> first_hit(const Mesh& mesh, glm::vec3 origin, glm::vec3 direction) {
    std::optional<RayHit> best;
    const glm::dvec3 o(origin), d(direction);
    for (std::size_t t = 0; t + 2 < mesh.indices.size(); t += 3) {
        const glm::dvec3 a(mesh.positions[mesh.indices[t]]);
        const glm::dvec3 e1 = glm::dvec3(mesh.positions[mesh.indices[t + 1]]) - a;
        const glm::dvec3 e2 = glm::dvec3(mesh.positions[mesh.indices[t + 2]]) - a;
        const glm::dvec3 p = glm::cross(d, e2);
        const double det = glm::dot(e1, p);
        if (std::abs(det) < 1e-18) continue; // parallel to the triangle's plane
        const glm::dvec3 s = o - a;
        const double u = glm::dot(s, p) / det;
        if (u < 0.0 || u > 1.0) continue;
        const glm::dvec3 q = glm::cross(s, e1);
        const double v = glm::dot(d, q) / det;
        if (v < 0.0 || u + v > 1.0) continue;
        const double along = glm::dot(e2, q) / det;
        if (!(along > 0.0) || (best && along >= double(best->t))) continue;
        RayHit hit;
        hit.triangle = std::uint32_t(t / 3);
        hit.t = float(along);
        hit.point = glm::vec3(o + along * d);
        // The corner with the largest barycentric weight is the nearest in the triangle.
        const double w[3] = {1.0 - u - v, u, v};
        int corner = 0;
        for (int k = 1; k < 3; ++k)
            if (w[k] > w[corner]) corner = k;
        hit.nearest_vertex = mesh.indices[t + std::size_t(corner)];
        best = hit;
    }
    return best;
}

} // namespace snert
