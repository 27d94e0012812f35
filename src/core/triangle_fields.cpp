#include "triangle_fields.h"

#include <cmath>
#include <stdexcept>
#include <string>

#include "parallel.h"

namespace snert {

namespace {

constexpr std::size_t kChunk = 1 << 13;

void check_indices(const Mesh& mesh) {
    if (mesh.indices.size() % 3 != 0)
        throw std::invalid_argument("triangle fields: index count is not a multiple of 3");
    if (const auto i = first_index_out_of_range(mesh))
        throw std::invalid_argument("triangle fields: index " + std::to_string(*i) +
                                    " out of range");
}

} // namespace

std::vector<float> centroid_distances(const Mesh& world_mesh, const Volume& volume,
                                      const DistanceFunction& reference) {
    check_indices(world_mesh);
    if (!reference) return {};
    std::vector<float> distance(world_mesh.triangle_count());
    // The corners are mapped, then averaged, as accuracy() averages index-space corners.
    for_each_chunk(distance.size(), kChunk, [&](std::size_t, std::size_t begin, std::size_t end) {
        for (std::size_t t = begin; t < end; ++t) {
            const std::uint32_t* i = &world_mesh.indices[3 * t];
            const glm::vec3 a = world_to_index(volume, world_mesh.positions[i[0]]);
            const glm::vec3 b = world_to_index(volume, world_mesh.positions[i[1]]);
            const glm::vec3 c = world_to_index(volume, world_mesh.positions[i[2]]);
            distance[t] = std::abs(reference((a + b + c) / 3.0f));
        }
    });
    return distance;
}

} // namespace snert
