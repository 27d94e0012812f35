// SurfaceNet (Gibson 1998; de Bruin et al., "Improving triangle mesh quality with SurfaceNets",
// section 2.1): nodes in surface cells, links between them, and quads for triangulation.
//
// A cell is the unit cube between 8 neighbouring voxel centres, named by its lowest corner
// (x, y, z) with 0 <= x < dims.x - 1 and so on. A cell is a surface cell when its 8 labels are
// not all equal; its node starts at the cell centre (x + 0.5, y + 0.5, z + 0.5) in index space.
// Two face-adjacent surface cells are linked when the face between them has mixed labels: that
// keeps the two sides of a one-voxel plate apart. Every grid edge whose two voxel labels differ
// gives one quad made of the 4 cells around it, wound so its normal points from the inside
// label to the outside one. Edges on the grid border have fewer than 4 cells and give no quad.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "progress.h"
#include "segmentation.h"

namespace snert {

struct SurfaceNet {
    glm::ivec3 cell_dims{0};                         // cells per axis: segmentation dims - 1
    std::vector<glm::ivec3> cells;                   // cell (lowest corner) of each node
    std::vector<glm::vec3> positions;                // initial node positions: cell centres
    std::vector<std::uint32_t> link_offsets;         // CSR: links of node i are
    std::vector<std::uint32_t> links;                //   links[link_offsets[i] .. [i + 1])
    std::vector<std::array<std::uint32_t, 4>> quads; // node ids, counter-clockwise from outside

    std::size_t node_count() const { return cells.size(); }
    std::size_t link_count() const { return links.size() / 2; }
};

SurfaceNet build_surface_net(const Segmentation& segmentation, const Progress& progress = {});

} // namespace snert
