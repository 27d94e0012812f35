// Volume: a regular 3D grid of float32 samples, the input of every mesher.
//
// Samples are stored x fastest, then y, then z. Geometry has two frames:
//  - index space: voxel (i, j, k) sits at the point (i, j, k); the meshers, the surface net and
//    the relaxation all work here, so a "cell" is the unit cube between 8 voxel centres;
//  - world space (millimetres): origin + direction * (spacing * index), the frame of exported
//    meshes and of every metric that has a physical unit.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

namespace snert {

// A sample's index in a grid of `dims` samples, x fastest (the order of Volume::samples).
inline std::size_t grid_index(glm::ivec3 dims, int x, int y, int z) {
    return (std::size_t(z) * std::size_t(dims.y) + std::size_t(y)) * std::size_t(dims.x) +
           std::size_t(x);
}

struct Volume {
    glm::ivec3 dims{0};         // samples along x, y, z
    glm::vec3 spacing{1.0f};    // world distance between neighbouring samples, per axis
    glm::vec3 origin{0.0f};     // world position of sample (0, 0, 0)
    glm::mat3 direction{1.0f};  // columns: world direction of the x, y, z index axes
    std::vector<float> samples; // dims.x * dims.y * dims.z values, x fastest

    std::size_t voxel_count() const {
        return std::size_t(dims.x) * std::size_t(dims.y) * std::size_t(dims.z);
    }
    std::size_t index(int x, int y, int z) const { return grid_index(dims, x, y, z); }
    float at(int x, int y, int z) const { return samples[index(x, y, z)]; }
    bool empty() const { return samples.empty(); }
};

// Allocates a volume of the given size filled with `value`. Throws std::invalid_argument when a
// dimension is below 1 or the sample count overflows.
Volume make_volume(glm::ivec3 dims, float value = 0.0f);

// Index space -> world space (millimetres) and back.
glm::vec3 index_to_world(const Volume& volume, glm::vec3 index_point);
glm::vec3 world_to_index(const Volume& volume, glm::vec3 world_point);
// Linear part of index_to_world (direction * diag(spacing)): maps index-space vectors to world.
glm::mat3 index_to_world_linear(const Volume& volume);

// Trilinear interpolation at an index-space point. Points outside the grid are clamped to it,
// so the value at the border continues outwards (no artificial edge).
float sample_trilinear(const Volume& volume, glm::vec3 p);

// Gradient of the grey values (per index unit) at an index-space point: central differences at
// the 8 surrounding samples (one-sided at the border), trilinearly interpolated.
glm::vec3 gradient_central(const Volume& volume, glm::vec3 p);

// sample_trilinear and gradient_central at once, equal to them bit for bit: the 8 corner samples
// and their neighbours are addressed once, which is what a relaxation step needs per node.
struct ValueGradient {
    float value = 0.0f;
    glm::vec3 gradient{0.0f};
};
ValueGradient sample_value_gradient(const Volume& volume, glm::vec3 p);

// What sample_value_gradient interpolates in one cell: its 8 corner samples and their central
// differences. Points in the same cell (the sample points of one small triangle, consecutive
// vertices of a mesh) share them, and the corners take 32 sample reads and 24 differences,
// the interpolation only a few mixes.
struct CellCorners {
    glm::ivec3 base{-1}; // the cell's lower corner, as sampling clamps it; -1: none held yet
    // Corner x + 2 y + 4 z: its sample, then its differences along x, y and z. Four values a
    // corner, so that one mix interpolates all four. Filled with base, so left uninitialised.
    alignas(16) float corner[8][4];
};
// sample_value_gradient, bit for bit, taking the corners from `kept` when p lies in the cell it
// holds, else filling it with p's cell. `kept` must only ever be used with this one volume.
ValueGradient sample_value_gradient(const Volume& volume, glm::vec3 p, CellCorners& kept);

// The corners of up to 8 cells, one for each parity of a cell's coordinates: cells that share a
// face, edge or corner never take each other's place, so the sample points of a small triangle
// (spread over two to four cells, visited back and forth) fill each cell once.
struct CellCornerCache {
    CellCorners by_parity[8];
};
// sample_value_gradient, bit for bit, with the corners of p's cell from `kept` (filled there when
// missing). `kept` must only ever be used with this one volume.
ValueGradient sample_value_gradient(const Volume& volume, glm::vec3 p, CellCornerCache& kept);

// sample_trilinear (bit for bit) and the exact gradient of that trilinear field (per index
// unit), both from the 8 samples of p's cell: a quarter of the memory reads of
// sample_value_gradient, but a gradient that jumps across cell faces (within a cell each
// component varies along the other two axes only).
ValueGradient sample_trilinear_with_gradient(const Volume& volume, glm::vec3 p);

// Asks the caches for the 8 samples of p's cell (the four rows of two samples it spans), for a
// loop that will sample there a few items later: a hint only, no effect on any result. On a
// clinical CT the cells of successive nodes lie far apart in memory, and a relaxation step
// waited on each node's samples in turn.
void prefetch_cell(const Volume& volume, glm::vec3 p);

// Gradient field of Gaussian-derivative filters with standard deviation `sigma` (in voxels),
// one vec3 per sample, same layout as Volume::samples. Separable, truncated at 3 sigma, the
// border extended by clamping. sigma <= 0 falls back to central differences per sample.
struct GradientField {
    glm::ivec3 dims{0};
    std::vector<glm::vec3> values;
};
GradientField gradient_field_gaussian(const Volume& volume, float sigma);
GradientField gradient_field_central(const Volume& volume);

// Trilinear interpolation of a precomputed gradient field at an index-space point.
glm::vec3 sample_trilinear(const GradientField& field, glm::vec3 p);

// Smallest and largest finite sample; {0, 0} for an empty volume.
struct ValueRange {
    float min = 0.0f;
    float max = 0.0f;
};
ValueRange value_range(const Volume& volume);

} // namespace snert
