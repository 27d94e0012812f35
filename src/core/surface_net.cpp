// Building a SurfaceNet from a binary segmentation.
//
// This work is based on:
//   S. F. F. Gibson, "Constrained elastic SurfaceNets", MICCAI 1998 (nodes, links, relaxation);
//   P. W. de Bruin et al., "Improving triangle mesh quality with SurfaceNets", MICCAI 2000
//   (quads found per grid edge, section 2.5).
//
// Passes over z-slabs of cells, as in VTK's flying edges: classify and count surface cells,
// prefix-sum the counts into node ids, then fill nodes, links and quads. Node ids follow the
// cells' x-fastest order, so the output does not depend on how slabs are scheduled. Nodes are
// looked up per row (binary search over x) instead of through a full cell-sized index, which
// keeps memory proportional to the surface, not the volume.
#include "surface_net.h"

#include <algorithm>
#include <stdexcept>

namespace snert {

namespace {

// Per row of voxels: 0 when all outside, 1 when all inside, 2 when mixed. A row of cells whose
// four voxel rows are uniform and equal holds no surface cell and is skipped (the trimming idea
// of flying edges, at row granularity).
std::vector<std::uint8_t> classify_rows(const Segmentation& s) {
    std::vector<std::uint8_t> rows(std::size_t(s.dims.y) * std::size_t(s.dims.z));
    for (std::size_t r = 0; r < rows.size(); ++r) {
        const std::uint8_t* v = &s.inside[r * std::size_t(s.dims.x)];
        bool any_in = false, any_out = false;
        for (int x = 0; x < s.dims.x; ++x) (v[x] ? any_in : any_out) = true;
        rows[r] = any_in && any_out ? 2 : any_in ? 1 : 0;
    }
    return rows;
}

// Visits the surface cells of cell row (y, z) in increasing x: visit(x).
template <class Visit>
void for_each_surface_cell_in_row(const Segmentation& s, const std::vector<std::uint8_t>& rows,
                                  int y, int z, Visit&& visit) {
    const std::size_t dy = std::size_t(s.dims.y);
    const std::size_t r00 = std::size_t(z) * dy + std::size_t(y), r10 = r00 + 1, r01 = r00 + dy,
                      r11 = r01 + 1;
    if (rows[r00] != 2 && rows[r00] == rows[r10] && rows[r00] == rows[r01] &&
        rows[r00] == rows[r11])
        return;
    const std::size_t nx = std::size_t(s.dims.x);
    const std::uint8_t* a = &s.inside[r00 * nx];
    const std::uint8_t* b = &s.inside[r10 * nx];
    const std::uint8_t* c = &s.inside[r01 * nx];
    const std::uint8_t* d = &s.inside[r11 * nx];
    // Column sums 0..4 of the four rows: a cell is mixed unless both its columns are 0 or both 4.
    int left = a[0] + b[0] + c[0] + d[0];
    for (int x = 0; x + 1 < s.dims.x; ++x) {
        const int right = a[x + 1] + b[x + 1] + c[x + 1] + d[x + 1];
        if (!(left == right && (left == 0 || left == 4))) visit(x);
        left = right;
    }
}

// The face between cell c and its neighbour along +axis: the 4 voxels at c[axis] + 1.
bool face_is_mixed(const Segmentation& s, glm::ivec3 c, int axis) {
    const int u = (axis + 1) % 3, v = (axis + 2) % 3;
    glm::ivec3 p = c;
    p[axis] += 1;
    bool any_in = false, any_out = false;
    for (int du = 0; du < 2; ++du)
        for (int dv = 0; dv < 2; ++dv) {
            glm::ivec3 q = p;
            q[u] += du;
            q[v] += dv;
            (s.at(q.x, q.y, q.z) ? any_in : any_out) = true;
        }
    return any_in && any_out;
}

class NodeIndex {
  public:
    NodeIndex(const SurfaceNet& net, std::vector<std::uint32_t> row_offsets)
        : net_(net), row_offsets_(std::move(row_offsets)) {}

    // Node id of cell c, which must be a surface cell.
    std::uint32_t operator()(glm::ivec3 c) const {
        const std::size_t row = std::size_t(c.z) * std::size_t(net_.cell_dims.y) + std::size_t(c.y);
        auto first = net_.cells.begin() + row_offsets_[row];
        auto last = net_.cells.begin() + row_offsets_[row + 1];
        auto it = std::lower_bound(first, last, c.x,
                                   [](const glm::ivec3& cell, int x) { return cell.x < x; });
        return std::uint32_t(it - net_.cells.begin());
    }

  private:
    const SurfaceNet& net_;
    std::vector<std::uint32_t> row_offsets_;
};

} // namespace

SurfaceNet build_surface_net(const Segmentation& segmentation, const Progress& progress) {
    SurfaceNet net;
    const glm::ivec3 dims = segmentation.dims;
    if (dims.x < 2 || dims.y < 2 || dims.z < 2) return net;
    const glm::ivec3 cd = dims - 1;
    net.cell_dims = cd;

    // Pass 1: count surface cells per row of cells.
    const std::size_t rows = std::size_t(cd.y) * std::size_t(cd.z);
    const std::vector<std::uint8_t> voxel_rows = classify_rows(segmentation);
    std::vector<std::uint32_t> row_offsets(rows + 1, 0);
    for (int z = 0; z < cd.z; ++z) {
        progress.update(0.4f * float(z) / float(cd.z));
        for (int y = 0; y < cd.y; ++y) {
            std::uint32_t count = 0;
            for_each_surface_cell_in_row(segmentation, voxel_rows, y, z, [&](int) { ++count; });
            row_offsets[std::size_t(z) * cd.y + y + 1] = count;
        }
    }
    // Pass 2: prefix sum; output can now be allocated exactly.
    for (std::size_t r = 0; r < rows; ++r) {
        if (row_offsets[r + 1] > UINT32_MAX - row_offsets[r])
            throw std::length_error("surface net has more than 2^32 nodes");
        row_offsets[r + 1] += row_offsets[r];
    }
    const std::size_t nodes = row_offsets[rows];
    net.cells.resize(nodes);
    net.positions.resize(nodes);

    // Pass 3: fill nodes at cell centres.
    for (int z = 0; z < cd.z; ++z)
        for (int y = 0; y < cd.y; ++y) {
            std::uint32_t id = row_offsets[std::size_t(z) * cd.y + y];
            for_each_surface_cell_in_row(segmentation, voxel_rows, y, z, [&](int x) {
                net.cells[id] = {x, y, z};
                net.positions[id] = glm::vec3(x, y, z) + 0.5f;
                ++id;
            });
        }
    progress.update(0.6f);
    const NodeIndex node_of(net, std::move(row_offsets));

    // Links: a surface cell and its +axis neighbour are linked when the face between them has
    // mixed labels. Count degrees first, then fill (CSR).
    std::vector<std::uint32_t> degree(nodes + 1, 0);
    auto for_each_link = [&](auto&& visit) {
        for (std::uint32_t i = 0; i < nodes; ++i) {
            const glm::ivec3 c = net.cells[i];
            for (int axis = 0; axis < 3; ++axis) {
                if (c[axis] + 1 >= cd[axis] || !face_is_mixed(segmentation, c, axis)) continue;
                glm::ivec3 n = c;
                n[axis] += 1;
                visit(i, node_of(n));
            }
        }
    };
    for_each_link([&](std::uint32_t a, std::uint32_t b) { ++degree[a], ++degree[b]; });
    net.link_offsets.assign(nodes + 1, 0);
    for (std::size_t i = 0; i < nodes; ++i)
        net.link_offsets[i + 1] = net.link_offsets[i] + degree[i];
    net.links.resize(net.link_offsets[nodes]);
    std::vector<std::uint32_t> cursor(net.link_offsets.begin(), net.link_offsets.end() - 1);
    for_each_link([&](std::uint32_t a, std::uint32_t b) {
        net.links[cursor[a]++] = b;
        net.links[cursor[b]++] = a;
    });
    progress.update(0.8f);

    // Quads: one per grid edge whose two voxel labels differ, made of the 4 cells around it.
    // Around an edge from voxel p along `axis`, with u = axis + 1 and v = axis + 2 (cyclic), the
    // cells at (u, v) offsets (-1,-1), (0,-1), (0,0), (-1,0) run counter-clockwise seen from
    // +axis, so the quad faces +axis when p is inside; otherwise it is reversed. The cell at
    // offset (0,0) is cell p itself, a surface cell: visiting the nodes' lowest-corner edges
    // finds every quad once, in time proportional to the surface.
    const glm::ivec2 ring[4] = {{-1, -1}, {0, -1}, {0, 0}, {-1, 0}};
    net.quads.reserve(nodes);
    for (std::uint32_t i = 0; i < nodes; ++i) {
        const glm::ivec3 p = net.cells[i];
        const bool here = segmentation.at(p.x, p.y, p.z);
        for (int axis = 0; axis < 3; ++axis) {
            const int u = (axis + 1) % 3, v = (axis + 2) % 3;
            if (p[u] < 1 || p[v] < 1) continue; // a border edge: fewer than 4 cells around it
            glm::ivec3 q = p;
            q[axis] += 1;
            if (segmentation.at(q.x, q.y, q.z) == here) continue;
            std::array<std::uint32_t, 4> quad;
            for (int k = 0; k < 4; ++k) {
                glm::ivec3 c = p;
                c[u] += ring[k].x;
                c[v] += ring[k].y;
                quad[std::size_t(k)] = node_of(c);
            }
            if (!here) std::swap(quad[1], quad[3]);
            net.quads.push_back(quad);
        }
    }
    progress.update(1.0f);
    return net;
}

} // namespace snert
