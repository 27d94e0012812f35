// SurfaceNet (Gibson 1998; de Bruin et al., "Improving triangle mesh quality with SurfaceNets",
// section 2.1): nodes in surface cells, links between them, and quads for triangulation.
//
// A cell is the unit cube between 8 neighbouring voxel centres, named by its lowest corner
// (x, y, z) with 0 <= x < dims.x - 1 and so on. A cell is a surface cell when its 8 labels are
// not all equal. The paper puts one node in each surface cell; on real scans that makes
// non-manifold meshes, because a cell can hold several separate pieces of surface (two tips of
// a thin structure, a saddle). Here a surface cell holds one node per piece: per loop of its
// Marching Cubes case, with ambiguous faces decided by the same rule as Marching Cubes (inside
// corners separated). The net is then the dual of the Marching Cubes surface of the same
// segmentation: a node per MC polygon, a quad per crossed grid edge, hence closed and manifold
// wherever MC's surface is, with the same Euler characteristic.
//
// A node starts at the cell centre (x + 0.5, y + 0.5, z + 0.5) in index space when it is its
// cell's only piece, as in the paper; pieces that share a cell start at the centroid of their
// crossed edges' midpoints, so they start apart. Two nodes of face-adjacent cells are linked
// when their pieces meet on the face (share a crossed edge of it): that keeps the two sides of
// a one-voxel plate apart. Every grid edge whose two voxel labels differ gives one quad made of
// the nodes of the pieces holding that edge in the 4 cells around it, wound so its normal
// points from the inside label to the outside one. Edges on the grid border have fewer than 4
// cells and give no quad.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "progress.h"
#include "segmentation.h"

namespace snert {

// `pieces` value of a node that splits a doubled link (see surface_net.cpp): it sits on the face
// between two cells and is constrained to the lower one.
inline constexpr std::uint8_t kLinkNodePiece = 255;
// `pieces` value of a copy of a node that met the volume border with two separate fans of
// polygons (see surface_net.cpp): same cell and region as the node.
inline constexpr std::uint8_t kBorderCopyPiece = 254;

struct SurfaceNet {
    glm::ivec3 cell_dims{0};                             // cells per axis: segmentation dims - 1
    std::vector<glm::ivec3> cells;                       // cell (lowest corner) of each node
    std::vector<std::uint8_t> pieces;                    // which piece of its cell (0 when alone)
    std::vector<std::uint8_t> regions;                   // where in its cell a node may move
    std::vector<glm::vec3> positions;                    // initial node positions (index space)
    std::vector<std::uint32_t> link_offsets;             // CSR: links of node i are
    std::vector<std::uint32_t> links;                    //   links[link_offsets[i] .. [i + 1])
    std::vector<std::array<std::uint32_t, 4>> quads;     // node ids, counter-clockwise from outside
    std::vector<std::array<std::uint32_t, 3>> triangles; // beside split links, same winding
    // CSR: the polygons around node i, star[star_offsets[i] .. [i + 1]): quad q as q, fixed
    // triangle t as quads.size() + t.
    std::vector<std::uint32_t> star_offsets;
    std::vector<std::uint32_t> star;

    std::size_t node_count() const { return cells.size(); }
    std::size_t link_count() const { return links.size() / 2; }
};

// A node's region, where in its cell it may move: the whole cell (the paper's constraint), but
// for a link node the quarter of the face its segment cuts off. Pieces that share a cell are
// kept from passing through each other by the relaxation's mesh check (mesh_guard.h), not by
// their regions. Two bits per axis (x lowest): 0 the whole [0, 1], 1 [0, 0.5], 2 [0.5, 1],
// 3 the face at 1.
struct NodeBox {
    glm::vec3 lo, hi; // index space
};
inline NodeBox node_box(const SurfaceNet& net, std::size_t node) {
    const glm::vec3 cell(net.cells[node]);
    NodeBox box{cell, cell + 1.0f};
    const unsigned region = net.regions[node];
    for (int axis = 0; axis < 3; ++axis) {
        const unsigned code = (region >> (2 * axis)) & 3u;
        if (code == 1) box.hi[axis] -= 0.5f;
        if (code == 2) box.lo[axis] += 0.5f;
        if (code == 3) box.lo[axis] += 1.0f;
    }
    return box;
}

// Builds the net in passes over fixed chunks of slabs of cells on up to one thread per core
// (parallel.h; a ThreadLimit caps it). Node, link and polygon order are the cells' x-fastest
// order, the same for any thread count. Progress is reported about once per slice and pass, one
// call at a time and increasing; cancellation (Cancelled) is checked at the same points.
SurfaceNet build_surface_net(const Segmentation& segmentation, const Progress& progress = {});
// The net of segment_threshold(volume, iso, rule), node for node, without the segmentation's
// byte a voxel: the samples are classified as the net is built. Throws std::invalid_argument
// when the samples do not fill the grid.
SurfaceNet build_surface_net(const Volume& volume, float iso, InsideIs rule,
                             const Progress& progress = {});

// The corners of polygon `id` of the net (quad q as q, fixed triangle t as quads.size() + t, the
// numbering of `star`): 4 or 3 of them, in winding order.
inline int polygon_corners(const SurfaceNet& net, std::uint32_t id,
                           std::array<std::uint32_t, 4>& out) {
    if (id < net.quads.size()) {
        out = net.quads[id];
        return 4;
    }
    const auto& t = net.triangles[id - net.quads.size()];
    out = {t[0], t[1], t[2], 0};
    return 3;
}

namespace detail {
// The piece (loop of the Marching Cubes case `inside_mask`) that holds cube edge `edge`, or -1
// when the edge is not crossed. Corner and edge numbering as in marching_cubes.h.
int surface_piece_of_edge(unsigned inside_mask, int edge);
} // namespace detail

} // namespace snert
