// One slice of a volume and what lies in it: the grey values of a sample plane (axial, coronal
// or sagittal), the cross-section of a mesh with that plane as line segments, and the part of
// a SurfaceNet the slice view draws (the paper's Fig. 1): the nodes of the layer of cells
// between sample plane `index` and `index + 1`, their links, and which of those cells are
// surface cells.
//
// Slice coordinates (u, v) are index-space coordinates along the plane's two axes:
//   axial     normal z, u = x, v = y
//   coronal   normal y, u = x, v = z
//   sagittal  normal x, u = y, v = z
#pragma once

#include <array>
#include <cstdint>
#include <span>
#include <string_view>
#include <vector>

#include <glm/glm.hpp>

#include "mesh.h"
#include "names.h"
#include "surface_net.h"
#include "volume.h"

namespace snert {

enum class SliceAxis { Axial, Coronal, Sagittal };
// "axial", "coronal", "sagittal" (names.h: parse_name, name_of, name_choices).
std::span<const Named<SliceAxis>> name_table(SliceAxis);

struct SlicePlane {
    SliceAxis axis = SliceAxis::Axial;
    int index = 0; // the sample plane along the normal axis
    bool operator==(const SlicePlane&) const = default;
};

int normal_axis(SliceAxis axis);       // 2, 1, 0
glm::ivec2 plane_axes(SliceAxis axis); // the index axes of u and v
// Sample planes along the normal: volume dims along it.
int slice_count(const Volume& volume, SliceAxis axis);
// The width x height of the slice: dims along u and v.
glm::ivec2 slice_size(glm::ivec3 dims, SliceAxis axis);
// Index-space point of slice coordinates (u, v) on the plane, and the slice coordinates of an
// index-space point (its projection on the plane).
glm::vec3 slice_to_index(const SlicePlane& plane, glm::vec2 uv);
glm::vec2 index_to_slice(SliceAxis axis, glm::vec3 p);

struct Slice {
    SlicePlane plane;
    glm::ivec2 size{0};        // samples along u and v
    std::vector<float> values; // u fastest
    float at(int u, int v) const { return values[std::size_t(v) * std::size_t(size.x) + u]; }
};
// Throws std::invalid_argument when the index is outside [0, slice_count).
Slice extract_slice(const Volume& volume, const SlicePlane& plane);
// The same for a per-sample mask (a Segmentation's inside flags), 0/1 per slice sample.
std::vector<std::uint8_t> extract_slice_mask(std::span<const std::uint8_t> mask, glm::ivec3 dims,
                                             const SlicePlane& plane);
// The inside flags (0/1) of a slice's samples: the mask's there, or without a mask the slice's own
// grey values by segment_threshold's rule (NaN is outside), the flags extract_slice_mask takes
// from the thresholded volume without a byte for every sample of it (100 MiB on a clinical CT).
std::vector<std::uint8_t> slice_inside(const Slice& slice, const Segmentation* mask, float iso,
                                       InsideIs rule);

struct Segment2 {
    glm::vec2 a{0.0f}, b{0.0f}; // slice coordinates
};
// The cross-section of an index-space mesh with the plane: one segment per triangle that
// crosses it. A vertex on the plane counts as above it, so an edge lying in the plane is drawn
// once (by the triangle below it) and a triangle touching the plane at a vertex gives none.
std::vector<Segment2> mesh_cross_section(const Mesh& index_mesh, const SlicePlane& plane);
// The same for a mesh in world units on `volume`'s grid (the pipeline's meshes), without
// copying it to index space: only the crossing edges' ends are mapped back.
std::vector<Segment2> mesh_cross_section(const Mesh& world_mesh, const Volume& volume,
                                         const SlicePlane& plane);

// The part of a net in the slice's layer of cells (see the top of the file).
struct SliceNet {
    int layer = 0;                                   // cells with this index along the normal
    std::vector<std::uint32_t> nodes;                // node ids in the layer
    std::vector<std::array<std::uint32_t, 2>> links; // pairs of those nodes, each once
    std::vector<glm::ivec2> surface_cells;           // (u, v) of the layer's cells holding a node
};
// The layer is min(index, cell count - 1) along the normal; empty when the net has no cells.
SliceNet net_in_slice(const SurfaceNet& net, const SlicePlane& plane);

} // namespace snert
