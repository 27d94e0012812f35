// Mesh: an indexed triangle mesh, the output of every method and the input of every metric.
//
// Triangles are wound counter-clockwise seen from outside: the normal
// cross(p1 - p0, p2 - p0) points from the inside of the segmented object to the outside.
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include <glm/glm.hpp>

namespace snert {

struct Mesh {
    std::vector<glm::vec3> positions;
    std::vector<std::uint32_t> indices; // 3 per triangle

    std::size_t triangle_count() const { return indices.size() / 3; }
    std::size_t vertex_count() const { return positions.size(); }
};

// The first index of `mesh` that names no vertex, or none: every reader of a mesh from outside
// checks this before it indexes the positions.
std::optional<std::uint32_t> first_index_out_of_range(const Mesh& mesh);

// The same triangles and the same vertices, bit for bit (a -0 differs from a 0, a NaN equals
// itself): what "the same result" means for a mesh.
bool same_mesh(const Mesh& a, const Mesh& b);

struct Volume;

// Applies the volume's index->world mapping to every vertex (index space -> millimetres).
// Keeps the winding outward even when the mapping mirrors (negative determinant).
Mesh mesh_to_world(const Mesh& mesh, const Volume& volume);

// mesh_to_world in place, bit for bit: for a mesh not needed in index space afterwards, so that
// a clinical mesh is not held twice.
void place_in_world(Mesh& mesh, const Volume& volume);

// place_in_world with the mesh's points already mapped (points_to_world of its positions), which
// replace them. Throws std::invalid_argument unless there is one point a vertex.
void place_in_world(Mesh& mesh, const Volume& volume, std::vector<glm::vec3> world_positions);

// The world points of index-space points, as mesh_to_world maps a mesh's vertices.
std::vector<glm::vec3> points_to_world(std::span<const glm::vec3> points, const Volume& volume);

// The index-space points of world points, as world_to_index_map maps each one.
std::vector<glm::vec3> points_to_index(std::span<const glm::vec3> points, const Volume& volume);

// The map mesh_to_world applies to each point, to get bit for bit the same world points.
struct IndexToWorld {
    glm::mat3 linear{1.0f};
    glm::vec3 origin{0.0f};
    glm::vec3 operator()(glm::vec3 p) const { return origin + linear * p; }
};
IndexToWorld index_to_world_map(const Volume& volume);

// Its inverse, world points to index space, as world_to_index() maps each point.
struct WorldToIndex {
    glm::mat3 inverse_linear{1.0f};
    glm::vec3 origin{0.0f};
    glm::vec3 operator()(glm::vec3 p) const { return inverse_linear * (p - origin); }
};
WorldToIndex world_to_index_map(const Volume& volume);

struct Bounds {
    glm::vec3 min{0.0f};
    glm::vec3 max{0.0f};
};
Bounds mesh_bounds(const Mesh& mesh);

} // namespace snert
