// Building a SurfaceNet from a binary segmentation.
//
// This work is based on:
//   S. F. F. Gibson, "Constrained elastic SurfaceNets", MICCAI 1998 (nodes, links, relaxation);
//   P. W. de Bruin et al., "Improving triangle mesh quality with SurfaceNets", MICCAI 2000
//   (quads found per grid edge, section 2.5);
//   G. M. Nielson, "Dual marching cubes", IEEE Visualization 2004 (one node per piece of the
//   Marching Cubes case, which makes the net the dual of the MC surface).
//
// Passes over slabs of cells, as in VTK's flying edges, each over fixed chunks of slabs in
// parallel: the inside bits (bit_planes.h, shared with Marching Cubes), counts of nodes per row
// and of link nodes, links and quads per slab, their prefix sums into node ids and offsets, then
// one pass that fills nodes, links and quads in place, each slab from its offsets. Node ids
// follow the cells' x-fastest order (pieces of one cell in loop order), and the rare fixed
// triangles are joined in chunk order, so the output does not depend on scheduling. A chunk
// looks nodes up in dense planes of cells around its current slab (three planes, not a
// volume-sized index), so memory stays proportional to the surface.
#include "surface_net.h"

#include <algorithm>
#include <memory>
#include <optional>
#include <span>
#include <stdexcept>

#include "bit_planes.h"
#include "huge_pages.h"
#include "input_error.h"
#include "marching_cubes.h"
#include "parallel.h"
#include "scratch_pool.h"
#include "step_progress.h"

namespace snert {

namespace {

// For each case, the piece (loop) holding each crossed cube edge, -1 where not crossed: 256
// cases x 12 edges, derived once from the Marching Cubes table.
using PieceTable = std::array<std::array<std::int8_t, 12>, 256>;
const PieceTable& surface_piece_table() {
    static const PieceTable table = [] {
        PieceTable pieces{};
        for (unsigned mask = 0; mask < 256; ++mask) {
            pieces[mask].fill(-1);
            const detail::MarchingCubesCase& c = detail::marching_cubes_case(mask);
            int first = 0;
            for (int loop = 0; loop < c.loop_count; ++loop) {
                for (int i = first; i < first + c.loop_size[loop]; ++i)
                    pieces[mask][c.loop_edges[i]] = std::int8_t(loop);
                first += c.loop_size[loop];
            }
        }
        return pieces;
    }();
    return table;
}

} // namespace

namespace detail {

int surface_piece_of_edge(unsigned inside_mask, int edge) {
    return surface_piece_table()[inside_mask & 255u][std::size_t(edge)];
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

// The segments of the Marching Cubes case on the cell's +axis face, each as its two crossed
// edges. Two crossings make one segment; four (an ambiguous face) make two, each cutting off
// one inside corner, the rule Marching Cubes uses.
struct FaceSegments {
    int count = 0;
    std::array<std::array<int, 2>, 2> edges{};
};

FaceSegments make_face_segments(unsigned mask, int axis) {
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

// make_face_segments of every case and axis, derived once.
const FaceSegments& face_segments(unsigned mask, int axis) {
    static const auto table = [] {
        std::array<std::array<FaceSegments, 3>, 256> faces{};
        for (unsigned m = 0; m < 256; ++m)
            for (int a = 0; a < 3; ++a) faces[m][std::size_t(a)] = make_face_segments(m, a);
        return faces;
    }();
    return table[mask][std::size_t(axis)];
}

// Edge on the cell's +axis face, seen from the neighbouring cell (where it is on the -axis face).
int edge_across_face(int edge, int axis) {
    const glm::ivec2 o = other_axes(edge / 4);
    return edge - (o.x == axis ? 1 : 2);
}

// A grid edge as a number: its lower voxel's index * 3 + its axis.
std::uint64_t edge_key(glm::ivec3 dims, glm::ivec3 cell, int edge) {
    const int axis = edge / 4;
    const glm::ivec2 o = other_axes(axis);
    glm::ivec3 p = cell;
    p[o.x] += edge & 1;
    p[o.y] += (edge >> 1) & 1;
    return std::uint64_t(grid_index(dims, p.x, p.y, p.z)) * 3 + std::uint64_t(axis);
}

// Where the inside bits come from: a segmentation's bytes, or the samples of a grey volume
// against an iso (segment_threshold()'s rule, without its byte a voxel).
struct InsideSource {
    const Segmentation* segmentation = nullptr;
    const Volume* volume = nullptr;
    float iso = 0.0f;
    InsideIs rule = InsideIs::Above;
    glm::ivec3 dims() const { return segmentation ? segmentation->dims : volume->dims; }
};

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

// Writes the link nodes into the net's node arrays (sized for them) at their ids.
void add_link_nodes(SurfaceNet& net, const std::vector<LinkNode>& link_nodes) {
    for (const LinkNode& l : link_nodes) {
        net.cells[l.node] = l.cell;
        net.pieces[l.node] = kLinkNodePiece;
        // On the face, in the quarter the segment cuts off; it starts at the segment's middle.
        const glm::vec3 m =
            0.5f * (edge_midpoint(l.cube_edges[0]) + edge_midpoint(l.cube_edges[1]));
        std::uint8_t region = 0;
        for (int axis = 0; axis < 3; ++axis) {
            const unsigned code = axis == l.axis ? 3u : m[axis] < 0.5f ? 1u : 2u;
            region = std::uint8_t(region | code << (2 * axis));
        }
        net.regions[l.node] = region;
        net.positions[l.node] = glm::vec3(l.cell) + m;
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

// A link as its two nodes. The build writes all links into one array, each slab at the offset
// its count gave, in the order of the cells (see NetBuilder::slab_links).
using Link = std::array<std::uint32_t, 2>;

// The polygons of a range of slabs, in output order: its quads written straight into the net's
// array from the first of the slots its count gave (a quad split into triangles leaves its slot
// unused, at the range's end), its fixed triangles apart.
struct Polygons {
    std::array<std::uint32_t, 4>* quads = nullptr; // the range's slots
    std::size_t slots = 0, quad_count = 0;
    std::vector<std::array<std::uint32_t, 3>> triangles;
};

// Adds the polygon of one crossed grid edge: its quad, where no link node splits a side; else
// the quad with the link nodes inserted into their sides (up to one per side), fanned into
// triangles from the first link node, same winding. The fan's triangles are fixed (no choice of
// diagonal later), which is acceptable for the rare cells that need them.
void add_quad(Polygons& out, const std::array<std::uint32_t, 4>& quad,
              const std::vector<LinkNode>& link_nodes,
              const std::vector<std::pair<std::uint64_t, std::uint32_t>>& split_edges,
              std::uint64_t key) {
    auto it = std::lower_bound(split_edges.begin(), split_edges.end(),
                               std::make_pair(key, std::uint32_t(0)));
    if (it == split_edges.end() || it->first != key) {
        if (out.quad_count == out.slots)
            throw std::logic_error("surface net: fill pass makes more quads than counted");
        out.quads[out.quad_count++] = quad;
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
        out.triangles.push_back({polygon[std::size_t(fan)], polygon[std::size_t((fan + k) % size)],
                                 polygon[std::size_t((fan + k + 1) % size)]});
}

// Sets the CSR arrays (offsets, values) of `rows` rows from for_each_entry(visit), which calls
// visit(row, value) for every entry, in the same order each time it runs: a row's values keep
// that order. The offsets serve as the rows' fill cursors, each then one row ahead, and are
// shifted back afterwards: no cursor array, which on a large net is one more fresh buffer.
template <class ForEachEntry>
void fill_csr(std::size_t rows, std::vector<std::uint32_t>& offsets,
              std::vector<std::uint32_t>& values, const ForEachEntry& for_each_entry) {
    detail::assign_on_huge_pages(offsets, rows + 1, 0u);
    for_each_entry([&](std::uint32_t row, std::uint32_t) { ++offsets[row + 1]; });
    for (std::size_t i = 0; i < rows; ++i) offsets[i + 1] += offsets[i];
    detail::assign_on_huge_pages(values, offsets.back(), 0u);
    for_each_entry([&](std::uint32_t row, std::uint32_t value) { values[offsets[row]++] = value; });
    // offsets[i] is now where row i ends, that is where row i + 1 starts.
    std::copy_backward(offsets.begin(), offsets.end() - 1, offsets.end());
    offsets[0] = 0;
}

void add_stars(SurfaceNet& net) {
    const std::size_t quads = net.quads.size();
    fill_csr(net.node_count(), net.star_offsets, net.star, [&](auto&& visit) {
        for (std::size_t q = 0; q < quads; ++q)
            for (std::uint32_t n : net.quads[q]) visit(n, std::uint32_t(q));
        for (std::size_t t = 0; t < net.triangles.size(); ++t)
            for (std::uint32_t n : net.triangles[t]) visit(n, std::uint32_t(quads + t));
    });
}

// The stars of a net whose only change since add_stars is fixed triangles appended from
// `first` on, as add_stars would now make them: a new triangle's id is larger than any polygon's
// before it, so it ends its corners' stars. One copy of the old entries with the few new ones in
// between, where building the stars again took two passes over every polygon (the border's
// mending adds a bridge or two to a clinical net: 20 ms each time on the CT at -500).
void append_triangles_to_stars(SurfaceNet& net, std::size_t first) {
    const std::size_t quads = net.quads.size();
    std::vector<std::pair<std::uint32_t, std::uint32_t>> added; // (node, polygon), sorted
    for (std::size_t t = first; t < net.triangles.size(); ++t)
        for (std::uint32_t n : net.triangles[t]) added.push_back({n, std::uint32_t(quads + t)});
    std::sort(added.begin(), added.end());
    std::vector<std::uint32_t>& offsets = net.star_offsets;
    const std::vector<std::uint32_t>& old = net.star;
    std::vector<std::uint32_t> star; // fresh memory on huge pages, as fill_csr's
    detail::resize_on_huge_pages(star, old.size() + added.size());
    auto out = star.begin();
    std::size_t copied = 0; // old entries copied so far
    for (std::size_t k = 0; k < added.size();) {
        // The old entries up to the end of this node's row, then its new ones.
        const std::uint32_t node = added[k].first;
        const std::size_t row_end = offsets[std::size_t(node) + 1];
        out = std::copy(old.begin() + std::ptrdiff_t(copied), old.begin() + std::ptrdiff_t(row_end),
                        out);
        copied = row_end;
        for (; k < added.size() && added[k].first == node; ++k) *out++ = added[k].second;
    }
    std::copy(old.begin() + std::ptrdiff_t(copied), old.end(), out);
    net.star = std::move(star);
    // Row i now starts after the entries added to rows before it.
    std::size_t k = 0;
    for (std::size_t node = 0; node + 1 < offsets.size(); ++node) {
        while (k < added.size() && added[k].first < node) ++k;
        offsets[node] += std::uint32_t(k);
    }
    offsets.back() = std::uint32_t(net.star.size());
}

// The fans of polygons around one node: polygons joined where they share an edge at the node.
// For polygon k of the star, in_of[k] -> node -> out_of[k] are its two edges at the node.
struct NodeFans {
    std::vector<std::uint32_t> polygons, in_of, out_of, fan; // fan: a root per polygon
    std::vector<std::uint32_t> roots;                        // one per fan
};

// Sets f to the fans of `node` (f's storage is reused: this runs for every border node).
void node_fans(const SurfaceNet& net, std::uint32_t node, std::span<const std::uint32_t> star,
               NodeFans& f) {
    f.roots.clear();
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
void split_fans(SurfaceNet& net, std::uint32_t node, const NodeFans& f, std::span<Link> links) {
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
            for (Link& l : links)
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
// this pass waits for the next pass, with stars built anew. Leaves the stars of the mended net
// in net.star_offsets and net.star.
void mend_pinched_border_nodes(SurfaceNet& net, std::span<Link> links) {
    constexpr int kPasses = 16;
    add_stars(net);
    for (int pass = 0; pass < kPasses; ++pass) {
        const std::size_t nodes = net.node_count();
        // The stars as this pass starts. A pass changes polygons' corners and adds polygons and
        // nodes, never the stars themselves: they stay those of the pass's start.
        const std::vector<std::uint32_t>& offsets = net.star_offsets;
        const std::vector<std::uint32_t>& star = net.star;
        std::array<std::uint32_t, 4> c{};
        bool changed = false, split = false; // any change; a node split (not only bridges)
        const std::size_t first_new_triangle = net.triangles.size();
        NodeFans f;

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
            node_fans(net, node, around, f);
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
                changed = true;
            } else if (pass + 1 < kPasses || !waiting) {
                split_fans(net, node, f, links);
                changed = split = true;
            }
        }
        if (split)
            add_stars(net);
        else if (changed)
            append_triangles_to_stars(net, first_new_triangle);
        if (!waiting) return;
    }
}

// Slabs of cells per chunk of the parallel passes (parallel.h): fixed, so the output does not
// depend on the thread count; small enough for two or more threads to balance.
constexpr std::size_t kSlabsPerChunk = 8;

// The node id of the first piece and the case of every surface cell of one plane of cells,
// dense over the plane. Entries of other cells are stale and never read: a face or edge that a
// lookup goes through is crossed, so the cell on its other side is a surface cell.
class CellPlane {
  public:
    CellPlane(std::size_t width, std::uint32_t* first, std::uint8_t* mask)
        : width_(width), first_(first), mask_(mask) {}
    void set(int x, int y, std::uint32_t first, unsigned mask) {
        first_[at(x, y)] = first;
        mask_[at(x, y)] = std::uint8_t(mask);
    }
    std::uint32_t first(int x, int y) const { return first_[at(x, y)]; }
    unsigned mask(int x, int y) const { return mask_[at(x, y)]; }

  private:
    std::size_t at(int x, int y) const { return std::size_t(y) * width_ + std::size_t(x); }
    std::size_t width_;
    std::uint32_t* first_;
    std::uint8_t* mask_;
};

// The three cell planes a chunk works with, plane z in slot z % 3. One array per field for all
// three: 4 MB on a 512^2 slice, enough for huge pages where one plane's 1 MB is not.
class CellPlanes {
  public:
    explicit CellPlanes(glm::ivec3 cell_dims)
        : size_(std::size_t(cell_dims.x) * std::size_t(cell_dims.y)), first_(3 * size_),
          mask_(3 * size_), planes_{plane(cell_dims.x, 0), plane(cell_dims.x, 1),
                                    plane(cell_dims.x, 2)} {}
    CellPlane& operator[](int z) { return planes_[std::size_t(z % 3)]; }

  private:
    CellPlane plane(int width, std::size_t slot) const {
        return {std::size_t(width), first_.get() + slot * size_, mask_.get() + slot * size_};
    }
    std::size_t size_;
    detail::ScratchArray<std::uint32_t> first_;
    detail::ScratchArray<std::uint8_t> mask_;
    std::array<CellPlane, 3> planes_;
};

// Where both segments of the ambiguous +axis face of a cell (case `mask`) join the same two
// pieces, with the neighbour's case `neighbour_mask`: the second segment needs a link node.
bool doubled_link(const PieceTable& pieces, unsigned mask, unsigned neighbour_mask, int axis,
                  const FaceSegments& face) {
    if (face.count != 2) return false;
    const int e0 = face.edges[0][0], e1 = face.edges[1][0];
    return pieces[mask][std::size_t(e0)] == pieces[mask][std::size_t(e1)] &&
           pieces[neighbour_mask][std::size_t(edge_across_face(e0, axis))] ==
               pieces[neighbour_mask][std::size_t(edge_across_face(e1, axis))];
}

// The 4 cells around the grid edge from a voxel p along `axis`, counter-clockwise seen from
// +axis: with u = axis + 1 and v = axis + 2 (cyclic), at (u, v) offsets (-1,-1), (0,-1), (0,0),
// (-1,0); each as its offset from p and the cube edge the grid edge is in that cell.
struct RingCell {
    int dx, dy, dz, edge;
};
const std::array<std::array<RingCell, 4>, 3>& quad_rings() {
    static const auto rings = [] {
        std::array<std::array<RingCell, 4>, 3> r{};
        const glm::ivec2 ring[4] = {{-1, -1}, {0, -1}, {0, 0}, {-1, 0}};
        for (int axis = 0; axis < 3; ++axis)
            for (int k = 0; k < 4; ++k) {
                glm::ivec3 offset(0);
                offset[(axis + 1) % 3] = ring[k].x;
                offset[(axis + 2) % 3] = ring[k].y;
                r[std::size_t(axis)][std::size_t(k)] = {offset.x, offset.y, offset.z,
                                                        cube_edge(axis, -offset)};
            }
        return r;
    }();
    return rings;
}

// Builds the net in passes over slabs of cells (see the top of this file): the inside bits;
// counts of nodes per row of cells and of link nodes per slab; their prefix sums, so that every
// node's id is known; then one pass that fills nodes, links and polygons, slab by slab.
class NetBuilder {
  public:
    NetBuilder(const InsideSource& source, const Progress& progress)
        : source_(source), progress_(progress), dims_(source.dims()), cd_(dims_ - 1), bits_(dims_),
          cases_(&detail::marching_cubes_case(0)), pieces_(surface_piece_table()),
          // Steps: planes classified, slabs counted, slabs filled.
          steps_(progress, std::size_t(dims_.z) + 2 * std::size_t(cd_.z)) {}

    SurfaceNet run() {
        const std::size_t planes = std::size_t(dims_.z), slabs = std::size_t(cd_.z);
        for_each_chunk(planes, kSlabsPerChunk,
                       [&](std::size_t, std::size_t first, std::size_t end) {
                           for (std::size_t z = first; z < end; ++z) classify_plane(int(z));
                       });

        const std::size_t rows = std::size_t(cd_.y) * slabs;
        row_offsets_.assign(rows + 1, 0);
        link_node_offsets_.assign(slabs + 1, 0);
        slab_link_offsets_.assign(slabs + 1, 0);
        slab_quad_offsets_.assign(slabs + 1, 0);
        for_each_chunk(slabs, kSlabsPerChunk, [&](std::size_t, std::size_t first, std::size_t end) {
            for (std::size_t z = first; z < end; ++z) count_nodes(int(z));
        });
        // Prefix sums: the output can now be allocated exactly.
        for (std::size_t r = 0; r < rows; ++r) {
            if (row_offsets_[r + 1] > UINT32_MAX - row_offsets_[r])
                throw InputError("surface net: the net would have more than 2^32 nodes, more "
                                 "than 32-bit indices can address");
            row_offsets_[r + 1] += row_offsets_[r];
        }
        link_node_offsets_[0] = row_offsets_[rows]; // link nodes follow the cells' nodes
        for (std::size_t z = 0; z < slabs; ++z) {
            if (link_node_offsets_[z + 1] > UINT32_MAX - link_node_offsets_[z])
                throw InputError("surface net: the net would have more than 2^32 nodes, more "
                                 "than 32-bit indices can address");
            link_node_offsets_[z + 1] += link_node_offsets_[z];
            slab_link_offsets_[z + 1] += slab_link_offsets_[z];
            slab_quad_offsets_[z + 1] += slab_quad_offsets_[z];
        }

        SurfaceNet net;
        net.cell_dims = cd_;
        const std::size_t nodes = link_node_offsets_[slabs];
        // The node arrays and the quads' slots are zeroed in parallel: a serial part of the run
        // otherwise.
        for_each_chunk(5, 1, [&](std::size_t array, std::size_t, std::size_t) {
            if (array == 0) detail::resize_on_huge_pages(net.cells, nodes);
            if (array == 1) detail::resize_on_huge_pages(net.pieces, nodes);
            if (array == 2) detail::resize_on_huge_pages(net.regions, nodes);
            if (array == 3) detail::resize_on_huge_pages(net.positions, nodes);
            if (array == 4) detail::resize_on_huge_pages(net.quads, slab_quad_offsets_[slabs]);
        });
        links_ = detail::ScratchArray<Link>(slab_link_offsets_[slabs]);
        const std::span<Link> links(links_.get(), slab_link_offsets_[slabs]);
        std::vector<Polygons> polygon_parts(chunk_count(slabs, kSlabsPerChunk));
        for_each_chunk(slabs, kSlabsPerChunk,
                       [&](std::size_t chunk, std::size_t first, std::size_t end) {
                           fill_slabs(int(first), int(end), net, polygon_parts[chunk]);
                       });
        // The classification is done with: its bit a voxel (13 MB on a 512 x 512 x 400 CT) is let
        // go before the polygons, stars and links are gathered, the build's peak of memory.
        bits_ = detail::BitVolume();

        gather_polygons(polygon_parts, net);
        mend_pinched_border_nodes(net, links); // also builds the stars
        set_links(net, links);
        progress_.update(1.0f);
        return net;
    }

  private:
    void classify_plane(int z) {
        steps_.step();
        for (int y = 0; y < dims_.y; ++y) {
            const std::size_t first = grid_index(dims_, 0, y, z);
            if (source_.segmentation) {
                const std::uint8_t* v = &source_.segmentation->inside[first];
                bits_.set_row(y, z, [&](int x) { return v[x] != 0; });
                continue;
            }
            detail::set_threshold_row(bits_, y, z, &source_.volume->samples[first], source_.iso,
                                      source_.rule == InsideIs::Above);
        }
    }

    bool inside(int x, int y, int z) const {
        return ((bits_.row(y, z)[x / detail::kWordBits] >> (x % detail::kWordBits)) & 1u) != 0;
    }

    std::size_t row_index(int y, int z) const {
        return std::size_t(z) * std::size_t(cd_.y) + std::size_t(y);
    }
    // Whether row (y, z) of cells holds a node, once the counts are summed: the fill passes skip
    // the rows the surface misses without looking at their bits.
    bool row_has_cells(int y, int z) const {
        const std::size_t r = row_index(y, z);
        return row_offsets_[r + 1] != row_offsets_[r];
    }

    // Nodes of each row of cells of slab z (one per piece), and the link nodes, links and quad
    // slots of the slab (slab_links and slab_quads make the same ones).
    void count_nodes(int z) {
        steps_.step();
        std::size_t link_nodes = 0, links = 0, quads = 0;
        for (int y = 0; y < cd_.y; ++y) {
            std::uint32_t count = 0;
            bits_.for_each_surface_cell(y, z, [&](int x, unsigned mask) {
                count += cases_[mask].loop_count;
                quads += quad_slots(x, y, z, mask);
                for (int axis = 0; axis < 3; ++axis) {
                    glm::ivec3 n(x, y, z);
                    if (++n[axis] >= cd_[axis]) continue;
                    const FaceSegments& face = face_segments(mask, axis);
                    links += std::size_t(face.count);
                    if (face.count != 2) continue;
                    const unsigned neighbour_mask = bits_.cell_rows(n.y, n.z).mask(n.x);
                    if (doubled_link(pieces_, mask, neighbour_mask, axis, face))
                        ++link_nodes, ++links; // a-m-b instead of a-b
                }
            });
            row_offsets_[row_index(y, z) + 1] = count;
        }
        link_node_offsets_[std::size_t(z) + 1] = link_nodes;
        slab_link_offsets_[std::size_t(z) + 1] = links;
        slab_quad_offsets_[std::size_t(z) + 1] = quads;
    }

    // Whether the grid edge from cell p's lowest corner along `axis` (case `mask`) makes a
    // polygon: when its two voxels differ (corners 0 and 1 << axis), and it is not on the grid's
    // border, where it has fewer than 4 cells around it.
    static bool makes_polygon(const int p[3], unsigned mask, int axis) {
        return ((mask >> (1 << axis)) & 1u) != (mask & 1u) && p[(axis + 1) % 3] >= 1 &&
               p[(axis + 2) % 3] >= 1;
    }
    // The polygons surface cell (x, y, z) makes in slab_quads.
    static std::size_t quad_slots(int x, int y, int z, unsigned mask) {
        const int p[3] = {x, y, z};
        return std::size_t(makes_polygon(p, mask, 0)) + std::size_t(makes_polygon(p, mask, 1)) +
               std::size_t(makes_polygon(p, mask, 2));
    }

    void fill_plane(int z, CellPlane& plane) const {
        for (int y = 0; y < cd_.y; ++y) {
            if (!row_has_cells(y, z)) continue;
            std::uint32_t id = row_offsets_[row_index(y, z)];
            bits_.for_each_surface_cell(y, z, [&](int x, unsigned mask) {
                plane.set(x, y, id, mask);
                id += cases_[mask].loop_count;
            });
        }
    }

    // Nodes, links and polygons of slabs [first, last). The cell planes z - 1, z and z + 1 are
    // at hand for slab z; the link nodes of slab first - 1, which the polygons of slab first
    // can need, are found again (without their links).
    void fill_slabs(int first, int last, SurfaceNet& net, Polygons& polygons) const {
        polygons.quads = net.quads.data() + slab_quad_offsets_[std::size_t(first)];
        polygons.slots =
            slab_quad_offsets_[std::size_t(last)] - slab_quad_offsets_[std::size_t(first)];
        const auto planes = plane_pool_.take([&] { return CellPlanes(cd_); });
        const auto plane = [&](int z) -> CellPlane& { return (*planes)[z]; };
        std::vector<LinkNode> before, here; // link nodes of slabs z - 1 and z
        std::vector<std::pair<std::uint64_t, std::uint32_t>> split_edges;
        fill_plane(first, plane(first));
        if (first > 0) {
            fill_plane(first - 1, plane(first - 1));
            slab_links(first - 1, plane(first - 1), plane(first), nullptr, before);
        }
        for (int z = first; z < last; ++z) {
            steps_.step();
            if (z + 1 < cd_.z) fill_plane(z + 1, plane(z + 1));
            fill_nodes(z, net);
            here.clear();
            slab_links(z, plane(z), plane(z + 1), links_.get() + slab_link_offsets_[std::size_t(z)],
                       here);
            add_link_nodes(net, here);
            std::vector<LinkNode> near(before);
            near.insert(near.end(), here.begin(), here.end());
            split_edges = sorted_split_edges(near);
            slab_quads(z, z > 0 ? &plane(z - 1) : nullptr, plane(z), near, split_edges, polygons);
            std::swap(before, here);
        }
    }

    // One node per piece, at the cell centre when alone, else at the centroid of its crossed
    // edges' midpoints.
    void fill_nodes(int z, SurfaceNet& net) const {
        for (int y = 0; y < cd_.y; ++y) {
            if (!row_has_cells(y, z)) continue;
            std::uint32_t id = row_offsets_[row_index(y, z)];
            bits_.for_each_surface_cell(y, z, [&](int x, unsigned mask) {
                const detail::MarchingCubesCase& c = cases_[mask];
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
    }

    // Links of slab z: the pieces of a cell and of its +axis neighbour that meet on the face
    // between them (share a crossed edge of it), cell by cell in node order. Where both
    // segments of an ambiguous face join the same two pieces, the second gets a node of its own
    // (LinkNode), numbered after the cells' nodes in slab order.
    // The links go to `links`, the slab's part of the links' array (none when null: the slab
    // before a chunk, where only the link nodes are wanted).
    void slab_links(int z, const CellPlane& plane, const CellPlane& above, Link* links,
                    std::vector<LinkNode>& link_nodes) const {
        std::uint32_t next_link_node = std::uint32_t(link_node_offsets_[std::size_t(z)]);
        const std::size_t count =
            slab_link_offsets_[std::size_t(z) + 1] - slab_link_offsets_[std::size_t(z)];
        std::size_t made = 0;
        const auto add_link = [&](std::uint32_t a, std::uint32_t b) {
            if (links == nullptr) return;
            if (made == count)
                throw std::logic_error("surface net: fill pass makes more links than counted");
            links[made++] = {a, b};
        };
        for (int y = 0; y < cd_.y; ++y) {
            if (!row_has_cells(y, z)) continue;
            std::uint32_t i = row_offsets_[row_index(y, z)];
            bits_.for_each_surface_cell(y, z, [&](int x, unsigned mask) {
                const glm::ivec3 c(x, y, z);
                for (int axis = 0; axis < 3; ++axis) {
                    if (c[axis] + 1 >= cd_[axis]) continue;
                    const FaceSegments& face = face_segments(mask, axis);
                    if (face.count == 0) continue;
                    glm::ivec3 n = c;
                    n[axis] += 1;
                    const CellPlane& np = axis == 2 ? above : plane;
                    const unsigned neighbour_mask = np.mask(n.x, n.y);
                    for (int k = 0; k < face.count; ++k) {
                        const int edge = face.edges[std::size_t(k)][0];
                        const std::uint32_t a = i + std::uint32_t(pieces_[mask][std::size_t(edge)]);
                        const std::uint32_t b = node_of_edge(np.first(n.x, n.y), neighbour_mask,
                                                             edge_across_face(edge, axis));
                        if (k == 1 && doubled_link(pieces_, mask, neighbour_mask, axis, face)) {
                            const std::uint32_t m = next_link_node++;
                            link_nodes.push_back({m,
                                                  c,
                                                  a,
                                                  b,
                                                  {edge_key(dims_, c, face.edges[1][0]),
                                                   edge_key(dims_, c, face.edges[1][1])},
                                                  face.edges[1],
                                                  axis});
                            add_link(a, m);
                            add_link(m, b);
                            continue;
                        }
                        add_link(a, b);
                    }
                }
                i += cases_[mask].loop_count;
            });
        }
        if (next_link_node != link_node_offsets_[std::size_t(z) + 1] ||
            (links != nullptr && made != count))
            throw std::logic_error("surface net: fill pass disagrees with count pass");
    }

    // The node of the piece holding cube edge `edge` (crossed) of a cell whose first node is
    // `first`.
    std::uint32_t node_of_edge(std::uint32_t first, unsigned mask, int edge) const {
        const int piece = pieces_[mask][std::size_t(edge)];
        if (piece < 0) throw std::logic_error("surface net: a quad edge is not crossed");
        return first + std::uint32_t(piece);
    }

    // Quads of slab z: one per grid edge whose two voxel labels differ, made of the pieces
    // holding that edge in the 4 cells around it. Around an edge from voxel p along `axis`,
    // with u = axis + 1 and v = axis + 2 (cyclic), the cells at (u, v) offsets (-1,-1), (0,-1),
    // (0,0), (-1,0) run counter-clockwise seen from +axis, so the quad faces +axis when p is
    // inside; otherwise it is reversed. The cell at offset (0,0) is cell p itself, a surface
    // cell: visiting the cells' lowest-corner edges finds every quad once, in time proportional
    // to the surface.
    void slab_quads(int z, const CellPlane* below, const CellPlane& plane,
                    const std::vector<LinkNode>& link_nodes,
                    const std::vector<std::pair<std::uint64_t, std::uint32_t>>& split_edges,
                    Polygons& out) const {
        const std::array<std::array<RingCell, 4>, 3>& rings = quad_rings();
        for (int y = 0; y < cd_.y; ++y) {
            if (!row_has_cells(y, z)) continue;
            bits_.for_each_surface_cell(y, z, [&](int x, unsigned mask) {
                const int p[3] = {x, y, z};
                const bool here = (mask & 1u) != 0;
                for (int axis = 0; axis < 3; ++axis) {
                    if (!makes_polygon(p, mask, axis)) continue;
                    std::array<std::uint32_t, 4> quad;
                    for (int k = 0; k < 4; ++k) {
                        const RingCell& r = rings[std::size_t(axis)][std::size_t(k)];
                        const CellPlane& cp = r.dz == 0 ? plane : *below;
                        const int cx = x + r.dx, cy = y + r.dy;
                        quad[std::size_t(k)] =
                            node_of_edge(cp.first(cx, cy), cp.mask(cx, cy), r.edge);
                    }
                    if (!here) std::swap(quad[1], quad[3]);
                    add_quad(out, quad, link_nodes, split_edges,
                             std::uint64_t(grid_index(dims_, x, y, z)) * 3 + std::uint64_t(axis));
                }
            });
        }
    }

    // The polygons of all ranges, in range order: each range's quads moved down over the slots
    // that split quads left unused before it (none on most volumes), the triangles joined.
    static void gather_polygons(const std::vector<Polygons>& parts, SurfaceNet& net) {
        std::size_t quads = 0, triangles = 0;
        for (const Polygons& part : parts) {
            if (part.quads != net.quads.data() + quads) // moving down: std::copy may overlap
                std::copy(part.quads, part.quads + part.quad_count, net.quads.begin() + quads);
            quads += part.quad_count;
            triangles += part.triangles.size();
        }
        net.quads.resize(quads);
        net.triangles.reserve(triangles);
        for (const Polygons& part : parts)
            net.triangles.insert(net.triangles.end(), part.triangles.begin(), part.triangles.end());
    }

    // The links as CSR: each node's neighbours in the order of the links.
    static void set_links(SurfaceNet& net, std::span<const Link> links) {
        fill_csr(net.node_count(), net.link_offsets, net.links, [&](auto&& visit) {
            for (const Link& l : links) {
                visit(l[0], l[1]);
                visit(l[1], l[0]);
            }
        });
    }

    const InsideSource source_;
    const Progress& progress_;
    const glm::ivec3 dims_, cd_;
    detail::BitVolume bits_;
    const detail::MarchingCubesCase* cases_;
    const PieceTable& pieces_;
    std::vector<std::uint32_t> row_offsets_;     // first node of each row of cells, plus the total
    std::vector<std::size_t> link_node_offsets_; // first link node of each slab, plus the total
    std::vector<std::size_t> slab_link_offsets_; // first link of each slab, plus the total
    std::vector<std::size_t> slab_quad_offsets_; // first quad slot of each slab, plus the total
    detail::ScratchArray<Link> links_;           // all links, slab after slab
    mutable detail::StepProgress steps_;
    mutable detail::ScratchPool<CellPlanes> plane_pool_;
};

} // namespace

SurfaceNet build_surface_net(const Segmentation& segmentation, const Progress& progress) {
    const glm::ivec3 dims = segmentation.dims;
    if (dims.x < 2 || dims.y < 2 || dims.z < 2) return {};
    progress.update(0.0f);
    return NetBuilder(InsideSource{&segmentation}, progress).run();
}

SurfaceNet build_surface_net(const Volume& volume, float iso, InsideIs rule,
                             const Progress& progress) {
    const glm::ivec3 dims = volume.dims;
    if (dims.x < 2 || dims.y < 2 || dims.z < 2) return {};
    if (volume.samples.size() != volume.voxel_count())
        throw std::invalid_argument("surface net: the volume's samples do not fill its grid");
    progress.update(0.0f);
    return NetBuilder(InsideSource{nullptr, &volume, iso, rule}, progress).run();
}

} // namespace snert
