// Vertex clustering on a uniform grid sized from the surface area.
#include "preview_mesh.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <unordered_map>
#include <unordered_set>

namespace snert::app {

PreviewMesh make_preview(const Mesh& mesh, std::size_t target_triangles) {
    PreviewMesh preview;
    const std::size_t triangles = mesh.triangle_count();
    if (target_triangles == 0 || triangles <= 2 * target_triangles) return preview;
    double area = 0;
    for (std::size_t t = 0; t < triangles; ++t) {
        const glm::vec3 a = mesh.positions[mesh.indices[3 * t]];
        const glm::vec3 b = mesh.positions[mesh.indices[3 * t + 1]];
        const glm::vec3 c = mesh.positions[mesh.indices[3 * t + 2]];
        area += 0.5 * double(glm::length(glm::cross(b - a, c - a)));
    }
    // A closed surface has about twice as many triangles as vertices: one cluster per
    // area / (target / 2).
    const double cell = std::sqrt(area / (0.5 * double(target_triangles)));
    if (!(cell > 0) || !std::isfinite(cell)) return preview;
    const Bounds bounds = mesh_bounds(mesh);
    std::unordered_map<std::uint64_t, std::uint32_t> representative;
    representative.reserve(target_triangles);
    std::vector<std::uint32_t> cluster(mesh.positions.size());
    for (std::size_t v = 0; v < mesh.positions.size(); ++v) {
        const glm::dvec3 g = glm::floor(glm::dvec3(mesh.positions[v] - bounds.min) / cell);
        const std::uint64_t key =
            (std::uint64_t(g.x) << 42) ^ (std::uint64_t(g.y) << 21) ^ std::uint64_t(g.z);
        cluster[v] = representative.try_emplace(key, std::uint32_t(v)).first->second;
    }
    // Many triangles collapse onto the same three clusters: keep the first of each.
    struct TripleHash {
        std::size_t operator()(const std::array<std::uint32_t, 3>& k) const {
            return std::hash<std::uint64_t>()((std::uint64_t(k[0]) << 32 | k[1]) ^
                                              (std::uint64_t(k[2]) * 0x9E3779B97F4A7C15ull));
        }
    };
    std::unordered_set<std::array<std::uint32_t, 3>, TripleHash> kept;
    kept.reserve(2 * target_triangles);
    for (std::size_t t = 0; t < triangles; ++t) {
        const std::uint32_t a = cluster[mesh.indices[3 * t]], b = cluster[mesh.indices[3 * t + 1]],
                            c = cluster[mesh.indices[3 * t + 2]];
        if (a == b || b == c || a == c) continue;
        std::array<std::uint32_t, 3> key{a, b, c};
        std::sort(key.begin(), key.end());
        if (!kept.insert(key).second) continue;
        preview.indices.insert(preview.indices.end(), {a, b, c});
        preview.source.push_back(std::uint32_t(t));
    }
    return preview;
}

} // namespace snert::app
