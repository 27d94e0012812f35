// Mesh helpers shared by the meshers, the metrics and the exporters.
#include "mesh.h"

#include <algorithm>
#include <cstring>
#include <stdexcept>
#include <string>
#include <utility>

#include "huge_pages.h"
#include "volume.h"

namespace snert {

IndexToWorld index_to_world_map(const Volume& volume) {
    return {index_to_world_linear(volume), volume.origin};
}

WorldToIndex world_to_index_map(const Volume& volume) {
    return {glm::inverse(index_to_world_linear(volume)), volume.origin};
}

std::optional<std::uint32_t> first_index_out_of_range(const Mesh& mesh) {
    if (mesh.positions.size() > UINT32_MAX) return std::nullopt; // every 32-bit index names one
    const auto vertices = std::uint32_t(mesh.positions.size());
    const std::uint32_t* index = mesh.indices.data();
    const std::size_t count = mesh.indices.size();
    // A block at a time, by a loop without a branch that the compiler vectorises (the metrics
    // check their mesh a dozen times, 2.5 M indices each on a clinical mesh); the block that
    // holds one is searched again for it.
    constexpr std::size_t kBlock = 1024;
    for (std::size_t first = 0; first < count; first += kBlock) {
        const std::size_t n = std::min(kBlock, count - first);
        std::uint32_t out = 0;
        for (std::size_t k = 0; k < n; ++k) out |= index[first + k] >= vertices ? 1u : 0u;
        if (out != 0)
            for (std::size_t k = 0; k < n; ++k)
                if (index[first + k] >= vertices) return index[first + k];
    }
    return std::nullopt;
}

bool same_mesh(const Mesh& a, const Mesh& b) {
    return a.indices == b.indices && a.positions.size() == b.positions.size() &&
           (a.positions.empty() || std::memcmp(a.positions.data(), b.positions.data(),
                                               a.positions.size() * sizeof(glm::vec3)) == 0);
}

namespace {

// Points a chunk: enough work to outweigh handing the chunk to a thread.
constexpr std::size_t kPointChunk = std::size_t(1) << 14;

// `to` = map(`from`) point by point, on every thread (`to` may be `from`): on one thread these
// copies of a clinical mesh's points were serial stretches of every comparison (about 10 ms each
// at 420 000 points).
template <class Map>
void map_points(std::span<const glm::vec3> from, std::span<glm::vec3> to, const Map& map) {
    for_each_chunk(from.size(), kPointChunk, [&](std::size_t, std::size_t first, std::size_t end) {
        for (std::size_t i = first; i < end; ++i) to[i] = map(from[i]);
    });
}

// map_points into fresh storage on huge pages (4 KiB pages fault one by one).
template <class Map>
std::vector<glm::vec3> mapped_points(std::span<const glm::vec3> points, const Map& map) {
    std::vector<glm::vec3> out;
    detail::resize_on_huge_pages(out, points.size());
    map_points(points, out, map);
    return out;
}

// A mirroring mapping (as NIfTI's RAS to LPS can be) turns the winding inside out.
void keep_winding_outward(Mesh& mesh, const IndexToWorld& to_world) {
    if (glm::determinant(to_world.linear) < 0.0f)
        for (std::size_t t = 0; t + 2 < mesh.indices.size(); t += 3)
            std::swap(mesh.indices[t + 1], mesh.indices[t + 2]);
}

} // namespace

Mesh mesh_to_world(const Mesh& mesh, const Volume& volume) {
    // In fresh storage on huge pages: a clinical mesh's 15 MB, faulted 4 KiB at a time, cost the
    // app tens of milliseconds before it could show Marching Cubes.
    const IndexToWorld to_world = index_to_world_map(volume);
    Mesh out{mapped_points(mesh.positions, to_world), detail::copy_on_huge_pages(mesh.indices)};
    keep_winding_outward(out, to_world);
    return out;
}

void place_in_world(Mesh& mesh, const Volume& volume) {
    const IndexToWorld to_world = index_to_world_map(volume);
    map_points(mesh.positions, mesh.positions, to_world);
    keep_winding_outward(mesh, to_world);
}

void place_in_world(Mesh& mesh, const Volume& volume, std::vector<glm::vec3> world_positions) {
    if (world_positions.size() != mesh.positions.size())
        throw std::invalid_argument("place_in_world: " + std::to_string(world_positions.size()) +
                                    " world points for " + std::to_string(mesh.positions.size()) +
                                    " vertices");
    mesh.positions = std::move(world_positions);
    keep_winding_outward(mesh, index_to_world_map(volume));
}

std::vector<glm::vec3> points_to_world(std::span<const glm::vec3> points, const Volume& volume) {
    return mapped_points(points, index_to_world_map(volume));
}

std::vector<glm::vec3> points_to_index(std::span<const glm::vec3> points, const Volume& volume) {
    return mapped_points(points, world_to_index_map(volume));
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
