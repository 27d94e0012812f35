// Mesh helpers shared by the meshers, the metrics and the exporters.
#include "mesh.h"

#include <algorithm>
#include <utility>

#include "volume.h"

namespace snert {

IndexToWorld index_to_world_map(const Volume& volume) {
    return {index_to_world_linear(volume), volume.origin};
}

Mesh mesh_to_world(const Mesh& mesh, const Volume& volume) {
    Mesh out;
    out.positions.reserve(mesh.positions.size());
    const IndexToWorld to_world = index_to_world_map(volume);
    const glm::mat3 linear = to_world.linear;
    for (const glm::vec3& p : mesh.positions) out.positions.push_back(to_world(p));
    out.indices = mesh.indices;
    // A mirroring mapping (as NIfTI's RAS to LPS can be) turns the winding inside out.
    if (glm::determinant(linear) < 0.0f)
        for (std::size_t t = 0; t + 2 < out.indices.size(); t += 3)
            std::swap(out.indices[t + 1], out.indices[t + 2]);
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
