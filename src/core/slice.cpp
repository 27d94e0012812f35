// Slices of a volume, and the meshes' and the net's parts in them (see slice.h).
#include "slice.h"

#include <algorithm>
#include <set>
#include <stdexcept>
#include <string>

namespace snert {

namespace {
constexpr Named<SliceAxis> kSliceAxes[] = {
    {SliceAxis::Axial, "axial", "axial (z)"},
    {SliceAxis::Coronal, "coronal", "coronal (y)"},
    {SliceAxis::Sagittal, "sagittal", "sagittal (x)"},
};
} // namespace

std::span<const Named<SliceAxis>> name_table(SliceAxis) {
    return kSliceAxes;
}

int normal_axis(SliceAxis axis) {
    switch (axis) {
    case SliceAxis::Axial:
        return 2;
    case SliceAxis::Coronal:
        return 1;
    case SliceAxis::Sagittal:
        return 0;
    }
    return 2;
}

glm::ivec2 plane_axes(SliceAxis axis) {
    switch (axis) {
    case SliceAxis::Axial:
        return {0, 1};
    case SliceAxis::Coronal:
        return {0, 2};
    case SliceAxis::Sagittal:
        return {1, 2};
    }
    return {0, 1};
}

int slice_count(const Volume& volume, SliceAxis axis) {
    return volume.dims[normal_axis(axis)];
}

glm::ivec2 slice_size(glm::ivec3 dims, SliceAxis axis) {
    const glm::ivec2 a = plane_axes(axis);
    return {dims[a.x], dims[a.y]};
}

glm::vec3 slice_to_index(const SlicePlane& plane, glm::vec2 uv) {
    const glm::ivec2 a = plane_axes(plane.axis);
    glm::vec3 p(0.0f);
    p[a.x] = uv.x;
    p[a.y] = uv.y;
    p[normal_axis(plane.axis)] = float(plane.index);
    return p;
}

glm::vec2 index_to_slice(SliceAxis axis, glm::vec3 p) {
    const glm::ivec2 a = plane_axes(axis);
    return {p[a.x], p[a.y]};
}

namespace {

void check_index(glm::ivec3 dims, const SlicePlane& plane) {
    const int count = dims[normal_axis(plane.axis)];
    if (plane.index < 0 || plane.index >= count)
        throw std::invalid_argument(std::string(name_of(plane.axis)) + " slice " +
                                    std::to_string(plane.index) + " is outside 0.." +
                                    std::to_string(count - 1));
}

// Calls f(u, v, sample index) for every sample of the plane.
template <class F> void for_each_sample(glm::ivec3 dims, const SlicePlane& plane, F f) {
    const glm::ivec2 a = plane_axes(plane.axis);
    const glm::ivec2 size = slice_size(dims, plane.axis);
    glm::ivec3 p(0);
    p[normal_axis(plane.axis)] = plane.index;
    for (int v = 0; v < size.y; ++v)
        for (int u = 0; u < size.x; ++u) {
            p[a.x] = u;
            p[a.y] = v;
            f(u, v,
              (std::size_t(p.z) * std::size_t(dims.y) + std::size_t(p.y)) * std::size_t(dims.x) +
                  std::size_t(p.x));
        }
}

} // namespace

Slice extract_slice(const Volume& volume, const SlicePlane& plane) {
    check_index(volume.dims, plane);
    Slice s;
    s.plane = plane;
    s.size = slice_size(volume.dims, plane.axis);
    s.values.resize(std::size_t(s.size.x) * std::size_t(s.size.y));
    for_each_sample(volume.dims, plane, [&](int u, int v, std::size_t i) {
        s.values[std::size_t(v) * std::size_t(s.size.x) + std::size_t(u)] = volume.samples[i];
    });
    return s;
}

std::vector<std::uint8_t> extract_slice_mask(std::span<const std::uint8_t> mask, glm::ivec3 dims,
                                             const SlicePlane& plane) {
    check_index(dims, plane);
    if (mask.size() != std::size_t(dims.x) * std::size_t(dims.y) * std::size_t(dims.z))
        throw std::invalid_argument("extract_slice_mask: the mask does not match the grid");
    const glm::ivec2 size = slice_size(dims, plane.axis);
    std::vector<std::uint8_t> out(std::size_t(size.x) * std::size_t(size.y));
    for_each_sample(dims, plane, [&](int u, int v, std::size_t i) {
        out[std::size_t(v) * std::size_t(size.x) + std::size_t(u)] = mask[i] != 0 ? 1 : 0;
    });
    return out;
}

std::vector<std::uint8_t> slice_inside(const Slice& slice, const Segmentation* mask, float iso,
                                       InsideIs rule) {
    if (mask) return extract_slice_mask(mask->inside, mask->dims, slice.plane);
    std::vector<std::uint8_t> out(slice.values.size());
    std::transform(slice.values.begin(), slice.values.end(), out.begin(),
                   [&](float value) { return is_inside(value, iso, rule) ? 1 : 0; });
    return out;
}

namespace {

// The cross-section of a mesh whose vertex v lies at index-space point to_index(v): the
// signed distance to the plane per vertex once, the ends of crossing edges mapped back.
template <class ToIndex>
std::vector<Segment2> cross_section(const Mesh& mesh, const SlicePlane& plane, ToIndex to_index) {
    const int n = normal_axis(plane.axis);
    std::vector<double> h(mesh.positions.size());
    for (std::size_t i = 0; i < h.size(); ++i) h[i] = to_index(i)[n] - double(plane.index);
    std::vector<Segment2> out;
    for (std::size_t t = 0; t + 2 < mesh.indices.size(); t += 3) {
        const std::uint32_t v[3] = {mesh.indices[t], mesh.indices[t + 1], mesh.indices[t + 2]};
        // The points where the triangle's edges change side (on the plane counts as above).
        glm::vec2 ends[2];
        int count = 0;
        for (int k = 0; k < 3 && count < 2; ++k) {
            const std::uint32_t a = v[k], b = v[(k + 1) % 3];
            if ((h[a] >= 0.0) == (h[b] >= 0.0)) continue;
            const double s = h[a] / (h[a] - h[b]);
            const glm::dvec3 pa = to_index(a), pb = to_index(b);
            ends[count++] = index_to_slice(plane.axis, glm::vec3(pa + s * (pb - pa)));
        }
        // A triangle touching the plane at one vertex only gives a point: no segment.
        if (count == 2 && ends[0] != ends[1]) out.push_back({ends[0], ends[1]});
    }
    return out;
}

} // namespace

std::vector<Segment2> mesh_cross_section(const Mesh& index_mesh, const SlicePlane& plane) {
    return cross_section(index_mesh, plane,
                         [&](std::size_t i) { return glm::dvec3(index_mesh.positions[i]); });
}

std::vector<Segment2> mesh_cross_section(const Mesh& world_mesh, const Volume& volume,
                                         const SlicePlane& plane) {
    const glm::dmat3 inverse = glm::inverse(glm::dmat3(index_to_world_linear(volume)));
    const glm::dvec3 origin(volume.origin);
    return cross_section(world_mesh, plane, [&](std::size_t i) {
        return inverse * (glm::dvec3(world_mesh.positions[i]) - origin);
    });
}

SliceNet net_in_slice(const SurfaceNet& net, const SlicePlane& plane) {
    SliceNet s;
    const int n = normal_axis(plane.axis);
    const int cells = net.cell_dims[n];
    if (cells < 1) return s;
    s.layer = std::clamp(plane.index, 0, cells - 1);
    std::vector<std::uint8_t> in_layer(net.node_count(), 0);
    std::set<std::pair<int, int>> surface;
    const glm::ivec2 a = plane_axes(plane.axis);
    for (std::size_t i = 0; i < net.node_count(); ++i) {
        if (net.cells[i][n] != s.layer) continue;
        in_layer[i] = 1;
        s.nodes.push_back(std::uint32_t(i));
        surface.insert({net.cells[i][a.y], net.cells[i][a.x]});
    }
    for (const std::uint32_t i : s.nodes)
        for (std::uint32_t k = net.link_offsets[i]; k < net.link_offsets[i + 1]; ++k) {
            const std::uint32_t j = net.links[k];
            if (j > i && in_layer[j]) s.links.push_back({i, j});
        }
    for (const auto& [v, u] : surface) s.surface_cells.push_back({u, v});
    return s;
}

} // namespace snert
