// Building a SurfaceNet from a binary segmentation.
//
// This work is based on:
//   S. F. F. Gibson, "Constrained elastic SurfaceNets", MICCAI 1998 (nodes, links, relaxation);
//   P. W. de Bruin et al., "Improving triangle mesh quality with SurfaceNets", MICCAI 2000
//   (quads found per grid edge, section 2.5);
//   G. M. Nielson, "Dual marching cubes", IEEE Visualization 2004 (one node per piece of the
//   Marching Cubes case, which makes the net the dual of the MC surface).
//
// Passes over rows of cells, as in VTK's flying edges: classify and count nodes, prefix-sum the
// counts into node ids, then fill nodes, links and quads. Node ids follow the cells' x-fastest
// order (pieces of one cell in loop order), so the output does not depend on scheduling. Nodes
// are looked up per row (binary search over x) instead of through a full cell-sized index, which
// keeps memory proportional to the surface, not the volume.
#include "surface_net.h"

#include <algorithm>
#include <optional>
#include <span>
#include <stdexcept>

#include "input_error.h"
#include "marching_cubes.h"

namespace snert {

namespace detail {

int surface_piece_of_edge(unsigned inside_mask, int edge) {
    // 256 cases x 12 edges, derived once from the Marching Cubes table.
    static const auto table = [] {
        std::array<std::array<std::int8_t, 12>, 256> pieces{};
        for (unsigned mask = 0; mask < 256; ++mask) {
            pieces[mask].fill(-1);
            const MarchingCubesCase& c = marching_cubes_case(mask);
            int first = 0;
            for (int loop = 0; loop < c.loop_count; ++loop) {
                for (int i = first; i < first + c.loop_size[loop]; ++i)
                    pieces[mask][c.loop_edges[i]] = std::int8_t(loop);
                first += c.loop_size[loop];
            }
        }
        return pieces;
    }();
    return table[inside_mask & 255u][std::size_t(edge)];
}

} // namespace detail

namespace {

// The two axes other than `axis`, lower first: the order of an edge's offset bits.
glm::ivec2 other_axes(int axis) {
    return axis == 0 ? glm::ivec2(1, 2) : axis == 1 ? glm::ivec2(0, 2) : glm::ivec2(0, 1);
}

// Cube edge along `axis` whose lower end sits at `offset` (0 or 1 on the other axes).
int cube_edge(int axis, glm::ivec3 offset) {
    const glm::ivec2 o = other_axes(axis);
    return axis * 4 + offset[o.x] + 2 * offset[o.y];
}

glm::vec3 edge_midpoint(int edge) {
    const int axis = edge / 4;
    const glm::ivec2 o = other_axes(axis);
    glm::vec3 m(0.0f);
    m[axis] = 0.5f;
    m[o.x] = float(edge & 1);
    m[o.y] = float((edge >> 1) & 1);
    return m;
}

// Inside mask of cell c: bit k set when corner k (offset (k & 1, k >> 1 & 1, k >> 2 & 1)) is in.
unsigned cell_mask(const Segmentation& s, glm::ivec3 c) {
    unsigned mask = 0;
    for (int k = 0; k < 8; ++k)
        if (s.at(c.x + (k & 1), c.y + ((k >> 1) & 1), c.z + ((k >> 2) & 1))) mask |= 1u << k;
    return mask;
}

int piece_count(unsigned mask) {
    return detail::marching_cubes_case(mask).loop_count;
}

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

// Visits the surface cells of cell row (y, z) in increasing x: visit(x, inside mask).
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
    const std::uint8_t* a = &s.inside[r00 * nx]; // corners (., 0, 0)
    const std::uint8_t* b = &s.inside[r10 * nx]; // corners (., 1, 0)
    const std::uint8_t* c = &s.inside[r01 * nx]; // corners (., 0, 1)
    const std::uint8_t* d = &s.inside[r11 * nx]; // corners (., 1, 1)
    // Four bits per column (one per row); a cell's mask is its two columns side by side.
    const auto column = [&](int x) {
        return unsigned(a[x] != 0) | unsigned(b[x] != 0) << 1 | unsigned(c[x] != 0) << 2 |
               unsigned(d[x] != 0) << 3;
    };
    unsigned left = column(0);
    for (int x = 0; x + 1 < s.dims.x; ++x) {
        const unsigned right = column(x + 1);
        if (!(left == right && (left == 0 || left == 15))) {
            // Corner k = dx | dy << 1 | dz << 2; column bit j = dy | dz << 1.
            unsigned mask = 0;
            for (unsigned j = 0; j < 4; ++j) {
                mask |= ((left >> j) & 1u) << (2 * j);
                mask |= ((right >> j) & 1u) << (2 * j + 1);
            }
            visit(x, mask);
        }
        left = right;
    }
}

class NodeIndex {
  public:
    NodeIndex(const SurfaceNet& net, std::vector<std::uint32_t> row_offsets)
        : net_(net), row_offsets_(std::move(row_offsets)) {}

    // First node id of cell c, which must be a surface cell.
    std::uint32_t first_of(glm::ivec3 c) const {
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

// The node of cell c (inside mask `mask`) whose piece holds cube edge `edge` (crossed).
std::uint32_t node_of_edge(const NodeIndex& index, glm::ivec3 c, unsigned mask, int edge) {
    const int piece = detail::surface_piece_of_edge(mask, edge);
    if (piece < 0) throw std::logic_error("surface net: a quad edge is not crossed");
    return index.first_of(c) + std::uint32_t(piece);
}

// The segments of the Marching Cubes case on the cell's +axis face, each as its two crossed
// edges. Two crossings make one segment; four (an ambiguous face) make two, each cutting off
// one inside corner, the rule Marching Cubes uses.
struct FaceSegments {
    int count = 0;
    std::array<std::array<int, 2>, 2> edges{};
};

FaceSegments face_segments(unsigned mask, int axis) {
    const glm::ivec2 in_face = other_axes(axis);
    FaceSegments face;
    std::array<int, 4> crossed{};
    int crossings = 0;
    for (int edge = 0; edge < 12; ++edge) {
        if (edge / 4 == axis) continue;
        const glm::ivec2 o = other_axes(edge / 4);
        const int on_face = o.x == axis ? (edge & 1) : ((edge >> 1) & 1);
        if (on_face == 1 && detail::surface_piece_of_edge(mask, edge) >= 0)
            crossed[std::size_t(crossings++)] = edge;
    }
    if (crossings == 2) {
        face.count = 1;
        face.edges[0] = {crossed[0], crossed[1]};
    } else if (crossings == 4) {
        for (int k = 0; k < 8; ++k) {
            const glm::ivec3 corner(k & 1, (k >> 1) & 1, (k >> 2) & 1);
            if (corner[axis] != 1 || ((mask >> k) & 1u) == 0) continue;
            std::array<int, 2> segment{};
            for (int w = 0; w < 2; ++w) {
                glm::ivec3 lower = corner;
                lower[in_face[w]] = 0;
                segment[std::size_t(w)] = cube_edge(in_face[w], lower);
            }
            face.edges[std::size_t(face.count++)] = segment;
        }
    }
    return face;
}

// Edge on the cell's +axis face, seen from the neighbouring cell (where it is on the -axis face).
int edge_across_face(int edge, int axis) {
    const glm::ivec2 o = other_axes(edge / 4);
    return edge - (o.x == axis ? 1 : 2);
}

// A grid edge as a number: its lower voxel's index * 3 + its axis.
std::uint64_t edge_key(const Segmentation& s, glm::ivec3 cell, int edge) {
    const int axis = edge / 4;
    const glm::ivec2 o = other_axes(axis);
    glm::ivec3 p = cell;
    p[o.x] += edge & 1;
    p[o.y] += (edge >> 1) & 1;
    return std::uint64_t(s.index(p.x, p.y, p.z)) * 3 + std::uint64_t(axis);
}

// Where both segments of an ambiguous face join the same two pieces a and b, the net would
// link a and b twice and the four quads of the face's crossed edges would all hold the side
// a-b (a non-manifold edge; the cell complex is fine, its triangulation is not). The second
// segment gets a node m of its own, on the face: links a-m-b, and m is inserted into the side
// a-b of the two quads of that segment's crossed edges (add_quad).
struct LinkNode {
    std::uint32_t node = 0; // m
    glm::ivec3 cell{0};     // the cell below the face: m's cell constraint
    std::uint32_t a = 0, b = 0;
    std::array<std::uint64_t, 2> edges{}; // the segment's grid edges (edge_key)
    std::array<int, 2> cube_edges{};      // ... as edges of `cell`
    int axis = 0;                         // the face is at cell[axis] + 1
};

void add_link_nodes(SurfaceNet& net, const std::vector<LinkNode>& link_nodes) {
    for (const LinkNode& l : link_nodes) {
        net.cells.push_back(l.cell);
        net.pieces.push_back(kLinkNodePiece);
        // On the face, in the quarter the segment cuts off; it starts at the segment's middle.
        const glm::vec3 m =
            0.5f * (edge_midpoint(l.cube_edges[0]) + edge_midpoint(l.cube_edges[1]));
        std::uint8_t region = 0;
        for (int axis = 0; axis < 3; ++axis) {
            const unsigned code = axis == l.axis ? 3u : m[axis] < 0.5f ? 1u : 2u;
            region = std::uint8_t(region | code << (2 * axis));
        }
        net.regions.push_back(region);
        net.positions.push_back(glm::vec3(l.cell) + m);
    }
}

std::vector<std::pair<std::uint64_t, std::uint32_t>>
sorted_split_edges(const std::vector<LinkNode>& link_nodes) {
    std::vector<std::pair<std::uint64_t, std::uint32_t>> edges;
    for (std::uint32_t k = 0; k < link_nodes.size(); ++k)
        for (std::uint64_t e : link_nodes[k].edges) edges.push_back({e, k});
    std::sort(edges.begin(), edges.end());
    return edges;
}

// Adds the polygon of one crossed grid edge: its quad, where no link node splits a side; else
// the quad with the link nodes inserted into their sides (up to one per side), fanned into
// triangles from the first link node, same winding. The fan's triangles are fixed (no choice of
// diagonal later), which is acceptable for the rare cells that need them.
void add_quad(SurfaceNet& net, const std::array<std::uint32_t, 4>& quad,
              const std::vector<LinkNode>& link_nodes,
              const std::vector<std::pair<std::uint64_t, std::uint32_t>>& split_edges,
              std::uint64_t key) {
    auto it = std::lower_bound(split_edges.begin(), split_edges.end(),
                               std::make_pair(key, std::uint32_t(0)));
    if (it == split_edges.end() || it->first != key) {
        net.quads.push_back(quad);
        return;
    }
    std::array<std::uint32_t, 8> polygon{};
    int size = 0, fan = -1;
    for (int k = 0; k < 4; ++k) {
        const std::uint32_t from = quad[std::size_t(k)], to = quad[std::size_t((k + 1) % 4)];
        polygon[std::size_t(size++)] = from;
        for (auto s = it; s != split_edges.end() && s->first == key; ++s) {
            const LinkNode& l = link_nodes[s->second];
            if ((from == l.a && to == l.b) || (from == l.b && to == l.a)) {
                if (fan < 0) fan = size;
                polygon[std::size_t(size++)] = l.node;
            }
        }
    }
    if (fan < 0) throw std::logic_error("surface net: a split link is not a side of its quad");
    for (int k = 1; k + 1 < size; ++k)
        net.triangles.push_back({polygon[std::size_t(fan)], polygon[std::size_t((fan + k) % size)],
                                 polygon[std::size_t((fan + k + 1) % size)]});
}

void add_stars(SurfaceNet& net) {
    const std::size_t quads = net.quads.size();
    auto for_each_corner = [&](auto&& visit) {
        for (std::size_t q = 0; q < quads; ++q)
            for (std::uint32_t n : net.quads[q]) visit(n, std::uint32_t(q));
        for (std::size_t t = 0; t < net.triangles.size(); ++t)
            for (std::uint32_t n : net.triangles[t]) visit(n, std::uint32_t(quads + t));
    };
    net.star_offsets.assign(net.node_count() + 1, 0);
    for_each_corner([&](std::uint32_t n, std::uint32_t) { ++net.star_offsets[n + 1]; });
    for (std::size_t i = 0; i < net.node_count(); ++i)
        net.star_offsets[i + 1] += net.star_offsets[i];
    net.star.resize(net.star_offsets.back());
    std::vector<std::uint32_t> cursor(net.star_offsets.begin(), net.star_offsets.end() - 1);
    for_each_corner(
        [&](std::uint32_t n, std::uint32_t polygon) { net.star[cursor[n]++] = polygon; });
}

// The fans of polygons around one node: polygons joined where they share an edge at the node.
// For polygon k of the star, in_of[k] -> node -> out_of[k] are its two edges at the node.
struct NodeFans {
    std::vector<std::uint32_t> polygons, in_of, out_of, fan; // fan: a root per polygon
    std::vector<std::uint32_t> roots;                        // one per fan
};

NodeFans node_fans(const SurfaceNet& net, std::uint32_t node, std::span<const std::uint32_t> star) {
    NodeFans f;
    f.polygons.assign(star.begin(), star.end());
    const std::size_t count = star.size();
    f.in_of.resize(count);
    f.out_of.resize(count);
    f.fan.resize(count);
    std::array<std::uint32_t, 4> c{};
    for (std::size_t k = 0; k < count; ++k) {
        const int n = polygon_corners(net, star[k], c);
        for (int j = 0; j < n; ++j)
            if (c[std::size_t(j)] == node) {
                f.in_of[k] = c[std::size_t((j + n - 1) % n)];
                f.out_of[k] = c[std::size_t((j + 1) % n)];
            }
        f.fan[k] = std::uint32_t(k);
    }
    const auto root = [&](std::uint32_t k) {
        while (f.fan[k] != k) k = f.fan[k] = f.fan[f.fan[k]];
        return k;
    };
    for (std::uint32_t a = 0; a < count; ++a)
        for (std::uint32_t b = a + 1; b < count; ++b)
            if (f.in_of[a] == f.in_of[b] || f.in_of[a] == f.out_of[b] ||
                f.out_of[a] == f.in_of[b] || f.out_of[a] == f.out_of[b])
                f.fan[root(a)] = root(b);
    for (std::uint32_t k = 0; k < count; ++k) {
        f.fan[k] = root(k);
        if (std::find(f.roots.begin(), f.roots.end(), f.fan[k]) == f.roots.end())
            f.roots.push_back(f.fan[k]);
    }
    return f;
}

// Two fans of a pinched border node joined by one triangle across one of the gaps between them
// (where the piece met the border), as Marching Cubes' polygon there joins them: the vertex is
// then manifold and the Euler characteristic stays MC's. A fan runs from a start neighbour (an
// edge into the node that no polygon of the fan leaves by) to an end one; the triangle
// (node, start of fan 1, end of fan 0) continues both windings. Empty where a fan has no single
// start and end, or where the triangle's third edge exists already.
std::optional<std::array<std::uint32_t, 3>>
bridge_of_two_fans(const SurfaceNet& net, std::uint32_t node, const NodeFans& f,
                   std::span<const std::uint32_t> offsets, std::span<const std::uint32_t> star) {
    std::array<std::uint32_t, 2> start{}, end{};
    for (std::size_t r = 0; r < 2; ++r) {
        int starts = 0, ends = 0;
        for (std::size_t k = 0; k < f.polygons.size(); ++k) {
            if (f.fan[k] != f.roots[r]) continue;
            bool entered = false, left = false;
            for (std::size_t m = 0; m < f.polygons.size(); ++m) {
                if (f.fan[m] != f.roots[r]) continue;
                entered = entered || f.out_of[m] == f.in_of[k];
                left = left || f.in_of[m] == f.out_of[k];
            }
            if (!entered) start[r] = f.in_of[k], ++starts;
            if (!left) end[r] = f.out_of[k], ++ends;
        }
        if (starts != 1 || ends != 1) return std::nullopt;
    }
    if (start[1] == end[0]) return std::nullopt;
    std::array<std::uint32_t, 4> c{};
    for (std::uint32_t k = offsets[end[0]]; k < offsets[end[0] + 1]; ++k) {
        const int n = polygon_corners(net, star[k], c);
        if (std::find(c.begin(), c.begin() + n, start[1]) != c.begin() + n) return std::nullopt;
    }
    return std::array<std::uint32_t, 3>{node, start[1], end[0]};
}

// Gives fan r > 0 of `node` a copy of the node (same cell and region) that takes its polygons
// and links; each starts a little towards its own fan so the two are apart.
void split_fans(SurfaceNet& net, std::uint32_t node, const NodeFans& f,
                std::vector<std::array<std::uint32_t, 2>>& links) {
    for (std::size_t r = 0; r < f.roots.size(); ++r) {
        const std::uint32_t owner = r == 0 ? node : std::uint32_t(net.node_count());
        glm::vec3 centre(0.0f);
        int around = 0;
        for (std::size_t k = 0; k < f.polygons.size(); ++k) {
            if (f.fan[k] != f.roots[r]) continue;
            centre += net.positions[f.in_of[k]] + net.positions[f.out_of[k]];
            around += 2;
            if (r == 0) continue;
            const std::uint32_t id = f.polygons[k];
            std::uint32_t* p = id < net.quads.size() ? net.quads[id].data()
                                                     : net.triangles[id - net.quads.size()].data();
            for (int j = 0; j < (id < net.quads.size() ? 4 : 3); ++j)
                if (p[j] == node) p[j] = owner;
            for (auto& l : links)
                for (int e = 0; e < 2; ++e)
                    if (l[std::size_t(e)] == node && (l[std::size_t(1 - e)] == f.in_of[k] ||
                                                      l[std::size_t(1 - e)] == f.out_of[k]))
                        l[std::size_t(e)] = owner;
        }
        const NodeBox box = node_box(net, node);
        glm::vec3 start =
            net.positions[node] + 0.25f * (centre / float(around) - net.positions[node]);
        for (int a = 0; a < 3; ++a) {
            const float inset = 0.01f * (box.hi[a] - box.lo[a]);
            start[a] = std::clamp(start[a], box.lo[a] + inset, box.hi[a] - inset);
        }
        if (r == 0) {
            net.positions[node] = start;
            continue;
        }
        net.cells.push_back(net.cells[node]);
        net.pieces.push_back(kBorderCopyPiece);
        net.regions.push_back(net.regions[node]);
        net.positions.push_back(start);
    }
}

// At the volume border the quads of border grid edges are missing, and a node whose piece
// leaves the volume twice keeps two separate fans of polygons: a pinched (non-manifold) vertex.
// Two fans are joined by a bridge triangle (bridge_of_two_fans). Where that cannot be done
// (three fans, no single start, the edge exists) the node is split into one node per fan
// instead: manifold too, but the Euler characteristic rises by one per copy (no test volume
// needs it). A change touches the stars of the nodes around it, so a node next to one changed in
// this pass waits for the next pass, with stars built anew.
void mend_pinched_border_nodes(SurfaceNet& net, std::vector<std::array<std::uint32_t, 2>>& links) {
    constexpr int kPasses = 16;
    for (int pass = 0; pass < kPasses; ++pass) {
        const std::size_t nodes = net.node_count();
        // The stars as this pass starts (copies of them: the pass adds polygons and nodes).
        add_stars(net);
        const std::vector<std::uint32_t> offsets = net.star_offsets, star = net.star;
        std::array<std::uint32_t, 4> c{};

        std::vector<std::uint8_t> touched(nodes, 0);
        bool waiting = false;
        const auto touch_around = [&](std::uint32_t node) {
            touched[node] = 1;
            for (std::uint32_t k = offsets[node]; k < offsets[node + 1]; ++k)
                for (int j = 0, n = polygon_corners(net, star[k], c); j < n; ++j)
                    touched[c[std::size_t(j)]] = 1;
        };
        for (std::uint32_t node = 0; node < nodes; ++node) {
            const std::span<const std::uint32_t> around(star.data() + offsets[node],
                                                        offsets[node + 1] - offsets[node]);
            // Away from the border the net is MC's dual, manifold: only border cells can pinch.
            const glm::ivec3 cell = net.cells[node];
            const bool border = glm::any(glm::equal(cell, glm::ivec3(0))) ||
                                glm::any(glm::equal(cell, net.cell_dims - 1));
            if (around.size() < 2 || !border) continue;
            const NodeFans f = node_fans(net, node, around);
            if (f.roots.size() < 2) continue;
            if (touched[node]) {
                waiting = true;
                continue;
            }
            const auto bridge = f.roots.size() == 2
                                    ? bridge_of_two_fans(net, node, f, offsets, star)
                                    : std::nullopt;
            if (bridge && (touched[(*bridge)[1]] || touched[(*bridge)[2]])) {
                waiting = true;
                continue;
            }
            touch_around(node);
            if (bridge) {
                for (std::uint32_t n : *bridge) touch_around(n);
                net.triangles.push_back(*bridge);
            } else if (pass + 1 < kPasses || !waiting) {
                split_fans(net, node, f, links);
            }
        }
        if (!waiting) return;
    }
}

} // namespace

SurfaceNet build_surface_net(const Segmentation& segmentation, const Progress& progress) {
    SurfaceNet net;
    const glm::ivec3 dims = segmentation.dims;
    if (dims.x < 2 || dims.y < 2 || dims.z < 2) return net;
    const glm::ivec3 cd = dims - 1;
    net.cell_dims = cd;

    // Pass 1: count nodes (pieces of surface cells) per row of cells.
    const std::size_t rows = std::size_t(cd.y) * std::size_t(cd.z);
    const std::vector<std::uint8_t> voxel_rows = classify_rows(segmentation);
    std::vector<std::uint32_t> row_offsets(rows + 1, 0);
    for (int z = 0; z < cd.z; ++z) {
        progress.update(0.4f * float(z) / float(cd.z));
        for (int y = 0; y < cd.y; ++y) {
            std::uint32_t count = 0;
            for_each_surface_cell_in_row(segmentation, voxel_rows, y, z,
                                         [&](int, unsigned mask) { count += piece_count(mask); });
            row_offsets[std::size_t(z) * cd.y + y + 1] = count;
        }
    }
    // Pass 2: prefix sum; output can now be allocated exactly.
    for (std::size_t r = 0; r < rows; ++r) {
        if (row_offsets[r + 1] > UINT32_MAX - row_offsets[r])
            throw InputError("surface net: the net would have more than 2^32 nodes, more than "
                             "32-bit indices can address");
        row_offsets[r + 1] += row_offsets[r];
    }
    const std::size_t nodes = row_offsets[rows];
    net.cells.resize(nodes);
    net.pieces.resize(nodes);
    net.regions.resize(nodes);
    net.positions.resize(nodes);

    // Pass 3: fill the nodes, one per piece.
    for (int z = 0; z < cd.z; ++z)
        for (int y = 0; y < cd.y; ++y) {
            std::uint32_t id = row_offsets[std::size_t(z) * cd.y + y];
            for_each_surface_cell_in_row(segmentation, voxel_rows, y, z, [&](int x, unsigned mask) {
                const detail::MarchingCubesCase& c = detail::marching_cubes_case(mask);
                const glm::vec3 corner = glm::vec3(float(x), float(y), float(z));
                int first = 0;
                for (int loop = 0; loop < c.loop_count; ++loop) {
                    glm::vec3 centre(0.5f);
                    if (c.loop_count > 1) {
                        centre = glm::vec3(0.0f);
                        for (int i = first; i < first + c.loop_size[loop]; ++i)
                            centre += edge_midpoint(c.loop_edges[i]);
                        centre /= float(c.loop_size[loop]);
                    }
                    first += c.loop_size[loop];
                    net.cells[id] = {x, y, z};
                    net.pieces[id] = std::uint8_t(loop);
                    net.regions[id] = 0; // the whole cell
                    net.positions[id] = corner + centre;
                    ++id;
                }
            });
        }
    progress.update(0.6f);
    const NodeIndex index(net, std::move(row_offsets));

    // Links: the pieces of a cell and of its +axis neighbour that meet on the face between
    // them (share a crossed edge of it). Where both segments of an ambiguous face join the same
    // two pieces, the second gets a node of its own: see add_link_node.
    std::vector<std::array<std::uint32_t, 2>> links;
    std::vector<LinkNode> link_nodes;
    for (std::uint32_t i = 0; i < nodes; ++i) {
        if (net.pieces[i] != 0) continue; // once per cell
        const glm::ivec3 c = net.cells[i];
        const unsigned mask = cell_mask(segmentation, c);
        for (int axis = 0; axis < 3; ++axis) {
            if (c[axis] + 1 >= cd[axis]) continue;
            glm::ivec3 n = c;
            n[axis] += 1;
            const unsigned neighbour_mask = cell_mask(segmentation, n);
            const FaceSegments face = face_segments(mask, axis);
            std::array<std::uint32_t, 2> previous{};
            for (int k = 0; k < face.count; ++k) {
                const int edge = face.edges[k][0];
                const std::uint32_t a =
                    i + std::uint32_t(detail::surface_piece_of_edge(mask, edge));
                const std::uint32_t b =
                    node_of_edge(index, n, neighbour_mask, edge_across_face(edge, axis));
                if (k == 1 && previous == std::array<std::uint32_t, 2>{a, b}) {
                    const std::uint32_t m = std::uint32_t(nodes + link_nodes.size());
                    link_nodes.push_back({m,
                                          c,
                                          a,
                                          b,
                                          {edge_key(segmentation, c, face.edges[k][0]),
                                           edge_key(segmentation, c, face.edges[k][1])},
                                          face.edges[k],
                                          axis});
                    links.push_back({a, m});
                    links.push_back({m, b});
                    continue;
                }
                previous = {a, b};
                links.push_back({a, b});
            }
        }
    }
    add_link_nodes(net, link_nodes);
    const std::vector<std::pair<std::uint64_t, std::uint32_t>> split_edges =
        sorted_split_edges(link_nodes);
    progress.update(0.8f);

    // Quads: one per grid edge whose two voxel labels differ, made of the pieces holding that
    // edge in the 4 cells around it. Around an edge from voxel p along `axis`, with u = axis + 1
    // and v = axis + 2 (cyclic), the cells at (u, v) offsets (-1,-1), (0,-1), (0,0), (-1,0) run
    // counter-clockwise seen from +axis, so the quad faces +axis when p is inside; otherwise it
    // is reversed. The cell at offset (0,0) is cell p itself, a surface cell: visiting the cells'
    // lowest-corner edges finds every quad once, in time proportional to the surface.
    const glm::ivec2 ring[4] = {{-1, -1}, {0, -1}, {0, 0}, {-1, 0}};
    net.quads.reserve(nodes);
    for (std::uint32_t i = 0; i < nodes; ++i) {
        if (net.pieces[i] != 0) continue; // once per cell
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
                const glm::ivec3 offset = p - c; // where the edge sits in cell c
                quad[std::size_t(k)] =
                    node_of_edge(index, c, cell_mask(segmentation, c), cube_edge(axis, offset));
            }
            if (!here) std::swap(quad[1], quad[3]);
            add_quad(net, quad, link_nodes, split_edges,
                     segmentation.index(p.x, p.y, p.z) * 3 + std::uint64_t(axis));
        }
    }
    mend_pinched_border_nodes(net, links);
    net.link_offsets.assign(net.node_count() + 1, 0);
    for (const auto& l : links) ++net.link_offsets[l[0] + 1], ++net.link_offsets[l[1] + 1];
    for (std::size_t k = 0; k < net.node_count(); ++k)
        net.link_offsets[k + 1] += net.link_offsets[k];
    net.links.resize(net.link_offsets.back());
    std::vector<std::uint32_t> cursor(net.link_offsets.begin(), net.link_offsets.end() - 1);
    for (const auto& l : links) {
        net.links[cursor[l[0]]++] = l[1];
        net.links[cursor[l[1]]++] = l[0];
    }
    add_stars(net);
    progress.update(1.0f);
    return net;
}

} // namespace snert
