// Mesh helpers shared by the meshers, the metrics and the exporters.
#include "mesh.h"

#include <algorithm>
#include <cstring>
#include <utility>

#include "volume.h"

namespace snert {

IndexToWorld index_to_world_map(const Volume& volume) {
    return {index_to_world_linear(volume), volume.origin};
}

WorldToIndex world_to_index_map(const Volume& volume) {
    return {glm::inverse(index_to_world_linear(volume)), volume.origin};
}

bool same_mesh(const Mesh& a, const Mesh& b) {
    return a.indices == b.indices && a.positions.size() == b.positions.size() &&
           (a.positions.empty() || std::memcmp(a.positions.data(), b.positions.data(),
                                               a.positions.size() * sizeof(glm::vec3)) == 0);
}

Mesh mesh_to_world(const Mesh& mesh, const Volume& volume) {
    Mesh out = mesh;
    place_in_world(out, volume);
    return out;
}

void place_in_world(Mesh& mesh, const Volume& volume) {
    const IndexToWorld to_world = index_to_world_map(volume);
    for (glm::vec3& p : mesh.positions) p = to_world(p);
    // A mirroring mapping (as NIfTI's RAS to LPS can be) turns the winding inside out.
    if (glm::determinant(to_world.linear) < 0.0f)
        for (std::size_t t = 0; t + 2 < mesh.indices.size(); t += 3)
            std::swap(mesh.indices[t + 1], mesh.indices[t + 2]);
}

std::vector<glm::vec3> points_to_world(std::span<const glm::vec3> points, const Volume& volume) {
    const IndexToWorld to_world = index_to_world_map(volume);
    std::vector<glm::vec3> out(points.size());
    std::transform(points.begin(), points.end(), out.begin(), to_world);
    return out;
}

Bounds mesh_bounds(const Mesh& mesh) {
    if (mesh.positions.empty()) return {};
    Bounds b{mesh.positions.front(), mesh.positions.front()};
    for (const glm::vec3& p : mesh.positions) {
        b.min = glm::min(b.min, p);
        b.max = glm::max(b.max, p);
    }
    return b;
}

} // namespace snert
