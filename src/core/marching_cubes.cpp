// Marching Cubes with a generated, topologically consistent case table (contract: the header).
//
// This work is based on:
//  - W. E. Lorensen, H. E. Cline, "Marching Cubes: A High Resolution 3D Surface Construction
//    Algorithm", SIGGRAPH 1987: one table lookup per cell, vertices on crossed edges placed by
//    linear interpolation.
//  - The ambiguous-face problem (M. J. Duerst, "Additional reference to Marching Cubes",
//    Computer Graphics 22(2), 1988) and its consistent resolution by deciding every face from
//    its own four samples with one fixed preference (C. Montani, R. Scateni, R. Scopigno, "A
//    modified look-up table for implicit disambiguation of Marching Cubes", The Visual Computer
//    10(6), 1994): both cells of a face then agree and the surface is crack-free.
//  - W. Schroeder, R. Maynard, B. Geveci, "Flying Edges: A High-Performance Scalable
//    Isocontouring Algorithm", IEEE LDAV 2015: passes over slabs that count, prefix-sum,
//    allocate exactly and fill, with vertices owned by edges.
//
// Layout of this file: (1) the case table, generated once from the face rule; (2) bit planes of
// the inside/weld classification; (3) the passes.
#include "marching_cubes.h"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstddef>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

namespace snert {

// ---------------------------------------------------------------------------------------------
// (1) The case table.
//
// For each of the 256 corner configurations: on each cube face, connect the crossed edges into
// segments (on an ambiguous face, cut each inside corner off on its own); orient each segment
// so that, seen from outside the cube, the inside corners lie on its right; the segments then
// chain into closed loops, wound counter-clockwise seen from the outside of the surface; each
// loop is triangulated once, here, with a fixed triangulation. A second table holds every
// case again for every subset of its inside corners being welded (3^8 corner states).

namespace detail {

namespace {

glm::ivec3 corner_offset(int corner) {
    return {corner & 1, (corner >> 1) & 1, (corner >> 2) & 1};
}
int corner_at(glm::ivec3 offset) {
    return offset.x | offset.y << 1 | offset.z << 2;
}
bool corner_inside(unsigned mask, int corner) {
    return ((mask >> corner) & 1u) != 0;
}

bool edge_crossed(unsigned mask, int edge) {
    return corner_inside(mask, cube_edge_corner(edge, 0)) !=
           corner_inside(mask, cube_edge_corner(edge, 1));
}

bool edge_on_face(int edge, int axis, int side) {
    return edge / 4 != axis && corner_offset(cube_edge_corner(edge, 0))[axis] == side;
}

glm::dvec3 edge_midpoint(int edge) {
    return 0.5 * (glm::dvec3(corner_offset(cube_edge_corner(edge, 0))) +
                  glm::dvec3(corner_offset(cube_edge_corner(edge, 1))));
}

struct Segment {
    int from, to; // crossed edges
};

// Orients the segment between crossed edges a and b of the face with outward normal
// `face_normal` so that `inside_corner` lies on its right seen from outside the cube. Chained
// over the six faces this winds each loop counter-clockwise around the outward normal.
Segment oriented_segment(int a, int b, int inside_corner, glm::dvec3 face_normal) {
    const glm::dvec3 pa = edge_midpoint(a), pb = edge_midpoint(b);
    const glm::dvec3 corner = glm::dvec3(corner_offset(inside_corner));
    const double left = glm::dot(glm::cross(pb - pa, corner - pa), face_normal);
    return left < 0 ? Segment{a, b} : Segment{b, a};
}

void add_face_segments(int axis, int side, unsigned inside, std::vector<Segment>& segments) {
    glm::dvec3 normal(0.0);
    normal[axis] = side != 0 ? 1.0 : -1.0;
    std::vector<int> crossed;
    for (int e = 0; e < 12; ++e)
        if (edge_on_face(e, axis, side) && edge_crossed(inside, e)) crossed.push_back(e);
    if (crossed.empty()) return;
    std::vector<int> inside_corners;
    for (int c = 0; c < 8; ++c)
        if (corner_offset(c)[axis] == side && corner_inside(inside, c)) inside_corners.push_back(c);
    if (crossed.size() == 2) {
        segments.push_back(oriented_segment(crossed[0], crossed[1], inside_corners[0], normal));
        return;
    }
    // Four crossings: two diagonal inside corners. Cutting each one off on its own is the rule
    // that keeps inside corners separated. It depends only on the face, so the neighbouring
    // cell decides the same; and all crossings at one inside corner stay consecutive in one
    // loop, which welding relies on.
    for (int c : inside_corners) {
        std::array<int, 2> ends{};
        int found = 0;
        for (int e : crossed)
            if (cube_edge_corner(e, 0) == c || cube_edge_corner(e, 1) == c) ends[found++] = e;
        segments.push_back(oriented_segment(ends[0], ends[1], c, normal));
    }
}

double smallest_angle(glm::dvec3 a, glm::dvec3 b, glm::dvec3 c) {
    const auto angle = [](glm::dvec3 at, glm::dvec3 p, glm::dvec3 q) {
        const glm::dvec3 u = p - at, v = q - at;
        return std::atan2(glm::length(glm::cross(u, v)), glm::dot(u, v));
    };
    return std::min({angle(a, b, c), angle(b, c, a), angle(c, a, b)});
}

// A corner of a loop's polygon: a crossed edge, or (after welding) a cell corner standing in
// for the run of crossed edges at it.
struct PolygonVertex {
    int edge = 0;          // a crossed edge whose vertex this is
    glm::dvec3 point{0.0}; // expected position: the edge midpoint, or the corner
    unsigned faces = 0;    // cube faces it lies on, bit 2 * axis + side
    int corner = -1;       // the welded corner, -1 for a crossing
};

PolygonVertex edge_vertex(int edge) {
    PolygonVertex v{edge, edge_midpoint(edge), 0};
    for (int axis = 0; axis < 3; ++axis)
        for (int side = 0; side < 2; ++side)
            if (edge_on_face(edge, axis, side)) v.faces |= 1u << (2 * axis + side);
    return v;
}

PolygonVertex corner_vertex(int corner, int edge) {
    PolygonVertex v{edge, glm::dvec3(corner_offset(corner)), 0, corner};
    for (int axis = 0; axis < 3; ++axis) v.faces |= 1u << (2 * axis + corner_offset(corner)[axis]);
    return v;
}

struct Triangulation {
    std::vector<std::array<int, 3>> triangles; // edges of the polygon vertices
    int boundary_cost = 0;                     // see chord_cost
};

// How much a diagonal between polygon vertices a and b risks being used by a neighbouring cell
// too (then four triangles would share it), -1 where it is not allowed. Inside the cell: 0.
// Between two crossings on a common face: never needed (the case table proves it), so never
// allowed; this is what makes plain Marching Cubes edge-manifold. From a welded corner along a
// face: the two cells of a face split such chords between them, the cell below the face takes
// those touching the face's main diagonal (corners with equal offsets along the face's two
// axes), the cell above the others, so they cannot both use one (1 if this cell's kind, 3 if
// not). Along a cell edge (two adjacent welded corners, shared by four cells): 5.
int chord_cost(const PolygonVertex& a, const PolygonVertex& b) {
    const unsigned shared = a.faces & b.faces;
    if (shared == 0) return 0;
    if (a.corner < 0 && b.corner < 0) return -1;
    if (std::popcount(shared) > 1) return 5;
    const int face = std::countr_zero(shared), axis = face / 2, side = face % 2;
    const glm::ivec3 corner = corner_offset(a.corner >= 0 ? a.corner : b.corner);
    const bool main_diagonal = corner[(axis + 1) % 3] == corner[(axis + 2) % 3];
    return main_diagonal == (side == 0) ? 1 : 3;
}

// Triangulation of one polygon, chosen once per case (dynamic programming over sub-polygons):
// first the smallest total chord_cost (none at all without welding: every diagonal then runs
// through the cell's interior and belongs to this cell alone; with welding the result is
// verified anyway, see resolve_welds). Then, on the expected vertex positions, the largest
// smallest angle, then the shortest total diagonal length: a fan would put slivers into the
// hexagons and larger loops, and choosing per cell from the actual positions would cost time
// in the hot loop for a small gain. Triangles (i, k, j) with i < k < j keep the winding.
Triangulation triangulate_polygon(const std::vector<PolygonVertex>& polygon) {
    const int n = int(polygon.size());
    struct Choice {
        int cost = 0;
        double min_angle = std::numeric_limits<double>::infinity();
        double diagonals = 0;
        int split = -1;
    };
    constexpr double kTie = 1e-9;
    const auto better = [](const Choice& a, const Choice& b) {
        if (a.cost != b.cost) return a.cost < b.cost;
        if (a.min_angle > b.min_angle + kTie) return true;
        if (a.min_angle < b.min_angle - kTie) return false;
        return a.diagonals < b.diagonals - kTie;
    };
    const auto is_side = [&](int i, int j) { return j - i == 1 || (i == 0 && j == n - 1); };
    const auto cost = [&](int i, int j) {
        return is_side(i, j) ? 0 : chord_cost(polygon[i], polygon[j]);
    };
    const auto length = [&](int i, int j) {
        return is_side(i, j) ? 0.0 : glm::length(polygon[j].point - polygon[i].point);
    };
    // best[i * n + j]: the sub-polygon i, i+1, ..., j closed by the chord (j, i).
    std::vector<Choice> best(std::size_t(n) * std::size_t(n));
    for (int span = 2; span < n; ++span) {
        for (int i = 0; i + span < n; ++i) {
            const int j = i + span;
            Choice& chosen = best[std::size_t(i) * n + j];
            for (int k = i + 1; k < j; ++k) {
                const Choice& left = best[std::size_t(i) * n + k];
                const Choice& right = best[std::size_t(k) * n + j];
                const int left_cost = cost(i, k), right_cost = cost(k, j);
                if (left_cost < 0 || right_cost < 0) continue;
                if ((k - i > 1 && left.split < 0) || (j - k > 1 && right.split < 0)) continue;
                Choice candidate;
                candidate.cost = left.cost + right.cost + left_cost + right_cost;
                candidate.min_angle = std::min(
                    {left.min_angle, right.min_angle,
                     smallest_angle(polygon[i].point, polygon[k].point, polygon[j].point)});
                candidate.diagonals =
                    left.diagonals + right.diagonals + length(i, k) + length(k, j);
                candidate.split = k;
                if (chosen.split < 0 || better(candidate, chosen)) chosen = candidate;
            }
        }
    }
    // Always feasible: the triangulation of the unwelded loop, with the triangles that collapse
    // under welding left out, is one.
    if (best[std::size_t(n - 1)].split < 0)
        throw std::logic_error("marching cubes table: a polygon has no valid triangulation");
    Triangulation result;
    result.boundary_cost = best[std::size_t(n - 1)].cost;
    std::vector<std::array<int, 2>> pending{{0, n - 1}};
    while (!pending.empty()) {
        const auto [i, j] = pending.back();
        pending.pop_back();
        if (j - i < 2) continue;
        const int k = best[std::size_t(i) * n + j].split;
        result.triangles.push_back({polygon[i].edge, polygon[k].edge, polygon[j].edge});
        pending.push_back({i, k});
        pending.push_back({k, j});
    }
    return result;
}

template <class Case> void add_triangles(Case& out, const Triangulation& triangulation) {
    for (const auto& t : triangulation.triangles) {
        if (out.triangle_count == MarchingCubesCase::kMaxTriangles)
            throw std::logic_error("marching cubes table: too many triangles");
        auto& slot = out.triangles[out.triangle_count++];
        for (int c = 0; c < 3; ++c) slot[c] = std::uint8_t(t[c]);
    }
}

MarchingCubesCase build_case(unsigned inside) {
    std::vector<Segment> segments;
    for (int axis = 0; axis < 3; ++axis)
        for (int side = 0; side < 2; ++side) add_face_segments(axis, side, inside, segments);

    // Each crossed edge lies on two faces; the orientation makes it the end of the segment on
    // one and the start on the other, so following `next` walks closed loops.
    std::array<int, 12> next;
    next.fill(-1);
    std::array<int, 12> arrivals{};
    for (const Segment& s : segments) {
        if (next[s.from] != -1) throw std::logic_error("marching cubes table: edge starts twice");
        next[s.from] = s.to;
        ++arrivals[s.to];
    }
    for (int e = 0; e < 12; ++e)
        if (edge_crossed(inside, e) != (next[e] != -1 && arrivals[e] == 1))
            throw std::logic_error("marching cubes table: segments do not chain into loops");

    MarchingCubesCase result;
    std::array<bool, 12> visited{};
    int used_edges = 0;
    for (int start = 0; start < 12; ++start) {
        if (next[start] == -1 || visited[start]) continue;
        std::vector<PolygonVertex> polygon;
        for (int e = start; !visited[e]; e = next[e]) {
            visited[e] = true;
            polygon.push_back(edge_vertex(e));
        }
        if (result.loop_count == MarchingCubesCase::kMaxLoops)
            throw std::logic_error("marching cubes table: too many loops");
        result.loop_size[result.loop_count++] = std::uint8_t(polygon.size());
        for (const PolygonVertex& v : polygon)
            result.loop_edges[used_edges++] = std::uint8_t(v.edge);
        const Triangulation triangulation = triangulate_polygon(polygon);
        if (triangulation.boundary_cost != 0)
            throw std::logic_error("marching cubes table: a loop needs a diagonal on a face");
        add_triangles(result, triangulation);
    }
    return result;
}

// The case with welded corners: each loop with the crossings of a welded corner merged into
// one vertex (they are consecutive, see add_face_segments), re-triangulated; loops left with
// fewer than 3 vertices vanish.
WeldedCase build_welded_case(const MarchingCubesCase& base, unsigned inside, unsigned welded) {
    WeldedCase result;
    int first = 0;
    for (int l = 0; l < base.loop_count; ++l) {
        std::vector<int> keys; // welded corner, or 8 + edge
        std::vector<PolygonVertex> polygon;
        for (int i = first; i < first + base.loop_size[l]; ++i) {
            const int e = base.loop_edges[i];
            const int lo = cube_edge_corner(e, 0), hi = cube_edge_corner(e, 1);
            const int in = corner_inside(inside, lo) ? lo : hi;
            const bool weld = corner_inside(welded, in);
            const int key = weld ? in : 8 + e;
            if (!keys.empty() && keys.back() == key) continue;
            keys.push_back(key);
            polygon.push_back(weld ? corner_vertex(in, e) : edge_vertex(e));
        }
        first += base.loop_size[l];
        if (keys.size() > 1 && keys.front() == keys.back()) {
            keys.pop_back();
            polygon.pop_back();
        }
        std::vector<int> sorted = keys;
        std::sort(sorted.begin(), sorted.end());
        if (std::adjacent_find(sorted.begin(), sorted.end()) != sorted.end())
            throw std::logic_error("marching cubes table: welded crossings not consecutive");
        if (keys.size() < 3) continue;
        for (int key : keys)
            if (key < 8) result.used_corners = std::uint8_t(result.used_corners | 1u << key);
        add_triangles(result, triangulate_polygon(polygon));
    }
    return result;
}

// Corner states as a base-3 number (0 outside, 1 inside, 2 welded): the index of the welded
// table. ternary[mask] is the mask's corners read as base-3 digits 1.
const std::array<std::uint16_t, 256>& ternary_digits() {
    static const std::array<std::uint16_t, 256> digits = [] {
        std::array<std::uint16_t, 256> d{};
        for (unsigned mask = 0; mask < 256; ++mask) {
            unsigned value = 0, power = 1;
            for (int c = 0; c < 8; ++c, power *= 3)
                if (corner_inside(mask, c)) value += power;
            d[mask] = std::uint16_t(value);
        }
        return d;
    }();
    return digits;
}

constexpr int kStates = 6561; // 3^8

struct Tables {
    std::array<MarchingCubesCase, 256> cases;
    std::vector<WeldedCase> welded; // by ternary index
};

const Tables& tables() {
    static const Tables built = [] {
        Tables t;
        for (unsigned mask = 0; mask < 256; ++mask) t.cases[mask] = build_case(mask);
        t.welded.resize(kStates);
        const auto& ternary = ternary_digits();
        for (unsigned inside = 0; inside < 256; ++inside)
            for (unsigned welded = inside;; welded = (welded - 1) & inside) { // subsets
                t.welded[ternary[inside] + ternary[welded]] =
                    build_welded_case(t.cases[inside], inside, welded);
                if (welded == 0) break;
            }
        return t;
    }();
    return built;
}

} // namespace

int cube_edge_corner(int edge, int end) {
    const int axis = edge / 4, bits = edge % 4;
    const int first_other = axis == 0 ? 1 : 0, second_other = axis == 2 ? 1 : 2;
    glm::ivec3 offset(0);
    offset[first_other] = bits & 1;
    offset[second_other] = bits >> 1;
    offset[axis] = end;
    return corner_at(offset);
}

const MarchingCubesCase& marching_cubes_case(unsigned inside_mask) {
    return tables().cases[inside_mask & 255u];
}

const WeldedCase& welded_case(unsigned inside_mask, unsigned welded_mask) {
    const auto& ternary = ternary_digits();
    inside_mask &= 255u;
    return tables().welded[ternary[inside_mask] + ternary[welded_mask & inside_mask]];
}

} // namespace detail

namespace {

// ---------------------------------------------------------------------------------------------
// (2) Bit planes. One bit per sample, rows of whole 64-bit words (padding bits are 0): a whole
// row of 64 cells is classified with a few word operations, so the empty bulk of a volume costs
// almost nothing and only cells the surface passes through are visited one by one.

using Word = std::uint64_t;
constexpr int kWordBits = 64;

class SampleBits {
  public:
    SampleBits() = default;
    SampleBits(glm::ivec3 dims, int words_per_row)
        : words_per_row_(words_per_row), rows_per_plane_(dims.y),
          words_(std::size_t(words_per_row) * std::size_t(dims.y) * std::size_t(dims.z), 0) {}
    bool empty() const { return words_.empty(); }
    Word* row(int y, int z) { return words_.data() + offset(y, z); }
    const Word* row(int y, int z) const { return words_.data() + offset(y, z); }

  private:
    std::size_t offset(int y, int z) const {
        return (std::size_t(z) * std::size_t(rows_per_plane_) + std::size_t(y)) *
               std::size_t(words_per_row_);
    }
    int words_per_row_ = 0;
    int rows_per_plane_ = 0;
    std::vector<Word> words_;
};

// Bit x of the result is bit x + 1 of the row.
inline Word bits_above(const Word* row, int w, int words) {
    return (row[w] >> 1) | (w + 1 < words ? row[w + 1] << (kWordBits - 1) : Word(0));
}
// Bit x of the result is bit x - 1 of the row; `fill` is shifted in at x = 0.
inline Word bits_below(const Word* row, int w, Word fill) {
    return (row[w] << 1) | (w > 0 ? row[w - 1] >> (kWordBits - 1) : fill);
}
// Bits x < count within word w.
inline Word bits_before(int count, int w) {
    const int first = w * kWordBits;
    if (count >= first + kWordBits) return ~Word(0);
    if (count <= first) return 0;
    return (Word(1) << (count - first)) - 1;
}
// 64 bytes of 0 or 1 -> one bit each. Eight at a time: the multiplication moves the low bit of
// byte k to bit 56 + k without carries into the top byte.
inline Word pack_bytes(const std::uint8_t* bytes) {
    Word bits = 0;
    for (int k = 0; k < 8; ++k) {
        Word eight = 0; // byte j at bits 8j; compilers turn this into one load
        for (int j = 0; j < 8; ++j) eight |= Word(bytes[8 * k + j]) << (8 * j);
        bits |= ((eight * 0x0102040810204080ull) >> 56) << (8 * k);
    }
    return bits;
}

// Bits x and x + 1 of a row as a 2-bit number (x + 1 must be a sample).
inline unsigned bit_pair(const Word* row, int x) {
    const int w = x / kWordBits, b = x % kWordBits;
    Word v = row[w] >> b;
    if (b == kWordBits - 1) v |= row[w + 1] << 1;
    return unsigned(v & 3u);
}
inline bool bit_at(const Word* row, int x) {
    return ((row[x / kWordBits] >> (x % kWordBits)) & 1u) != 0;
}
template <class F> inline void for_each_bit(Word bits, int w, F&& f) {
    while (bits != 0) {
        f(w * kWordBits + std::countr_zero(bits));
        bits &= bits - 1;
    }
}

// The 8-bit corner mask of cell x from the four sample rows around its row of cells:
// (y, z), (y + 1, z), (y, z + 1), (y + 1, z + 1) give corners 0-1, 2-3, 4-5, 6-7.
struct CellRows {
    const Word* r[4];
    unsigned mask(int x) const {
        return bit_pair(r[0], x) | bit_pair(r[1], x) << 2 | bit_pair(r[2], x) << 4 |
               bit_pair(r[3], x) << 6;
    }
};

// Linear interpolation parameter of the crossing between samples a (t = 0) and b (t = 1), in
// double so that it is exactly 0 only when a == iso (then the crossing is welded) and never
// overflows; infinite samples give the end point nearer to the crossing.
inline double crossing_parameter(float a, float b, float iso) {
    const double t = (double(iso) - double(a)) / (double(b) - double(a));
    if (std::isnan(t)) return std::isinf(a) ? (std::isinf(b) ? 0.5 : 1.0) : 0.0;
    return std::clamp(t, 0.0, 1.0);
}

// ---------------------------------------------------------------------------------------------
// (3) The passes.
//
// Vertex ownership: plane z owns the crossings on its x and y edges, the welded samples of the
// plane and the crossings on the z edges up to plane z + 1. Its ids form one block: welded
// samples, then x/y crossings row by row, then z crossings row by row. Slab z (the cells
// between planes z and z + 1) owns a block of triangles. Both blocks are sized in the count
// pass, so the fill pass writes disjoint ranges and could run slabs in parallel.

class Extractor {
  public:
    Extractor(const Volume& volume, const MarchingCubesOptions& options, const Progress& progress)
        : volume_(volume), iso_(options.iso), above_(options.inside == InsideIs::Above),
          progress_(progress), dims_(volume.dims),
          words_((volume.dims.x + kWordBits - 1) / kWordBits), zero_row_(std::size_t(words_), 0),
          ones_row_(std::size_t(words_), ~Word(0)) {}

    Mesh run() {
        classify(); // progress 0 .. 0.35
        count();    // 0.35 .. 0.4
        Mesh mesh;
        mesh.positions.resize(vertex_offset_.back());
        mesh.indices.resize(3 * triangle_offset_.back());
        fill_slabs(0, dims_.z - 1, mesh); // 0.4 .. 1
        progress_.update(1.0f);
        return mesh;
    }

  private:
    struct PlaneCount {
        std::size_t welds = 0, xy = 0, z = 0;
    };
    struct PlaneIds {
        std::vector<std::uint32_t> x, y, weld; // per sample of the plane, valid where crossed
    };
    // The crossed edges at sample row (y, z), one word at a time, split into edges with a
    // vertex of their own and edges welded to their inside sample.
    struct RowEdges {
        Word x_own = 0, x_welded = 0, y_own = 0, y_welded = 0, z_own = 0, z_welded = 0;
    };

    bool has_welds() const { return !weld_.empty(); }
    const Word* weld_row(int y, int z) const {
        return has_welds() ? weld_.row(y, z) : zero_row_.data();
    }
    // Welded samples that some surviving triangle uses: exactly those get a vertex.
    Word used_welds(int y, int z, int w) const {
        return weld_.row(y, z)[w] & (used_from_below_.row(y, z)[w] | used_from_above_.row(y, z)[w]);
    }
    void report(float begin, float end, int step, int steps) const {
        progress_.update(begin + (end - begin) * float(step) / float(std::max(steps, 1)));
    }

    // Pass 0: inside and at-iso bits of every sample, then the weld bits.
    void classify() {
        inside_ = SampleBits(dims_, words_);
        SampleBits at_iso(dims_, words_);
        std::vector<char> plane_at_iso(std::size_t(dims_.z), 0);
        for (int z = 0; z < dims_.z; ++z) {
            report(0.0f, 0.25f, z, dims_.z);
            bool any = false;
            for (int y = 0; y < dims_.y; ++y) {
                const float* samples = volume_.samples.data() + volume_.index(0, y, z);
                any |= above_ ? classify_row<true>(samples, inside_.row(y, z), at_iso.row(y, z))
                              : classify_row<false>(samples, inside_.row(y, z), at_iso.row(y, z));
            }
            plane_at_iso[std::size_t(z)] = any;
        }
        bool any_weld = false;
        for (int z = 0; z < dims_.z; ++z) {
            report(0.25f, 0.3f, z, dims_.z);
            if (plane_at_iso[std::size_t(z)])
                for (int y = 0; y < dims_.y; ++y) any_weld |= keep_surface_samples(at_iso, y, z);
        }
        if (any_weld) {
            weld_ = std::move(at_iso);
            resolve_welds();
            used_from_below_ = SampleBits(dims_, words_);
            used_from_above_ = SampleBits(dims_, words_);
        }
    }

    // Welding all crossings of a sample at iso into one vertex is local to that sample, but two
    // welded samples can meet badly. Two neighbours exactly at iso put the whole grid edge
    // between them on the surface, and cells on opposite sides of it may both triangulate
    // across it; a plate one sample thick at iso has both of its sides welded onto the same
    // samples. Both make edges with four triangles. So every weld is checked exactly: each edge
    // from the welded vertex must be used once in each direction by the triangles of its 8
    // cells (once on the volume border). A sample that fails is unwelded, and its welded
    // neighbours are checked again. Welds are only ever removed, so this ends; without welds the
    // surface is plain Marching Cubes, which is edge-manifold, and every weld that is left has
    // passed its check after the last change around it. Order: scan order, then each
    // unweld's consequences at once, so the result is deterministic. Serial, but it visits only
    // samples exactly at iso that have an outside neighbour.
    void resolve_welds() {
        std::vector<glm::ivec3> recheck;
        const auto unweld = [&](glm::ivec3 p) {
            weld_.row(p.y, p.z)[p.x / kWordBits] &= ~(Word(1) << (p.x % kWordBits));
            for (int dz = -1; dz <= 1; ++dz)
                for (int dy = -1; dy <= 1; ++dy)
                    for (int dx = -1; dx <= 1; ++dx) {
                        const glm::ivec3 q = p + glm::ivec3(dx, dy, dz);
                        if (glm::all(glm::greaterThanEqual(q, glm::ivec3(0))) &&
                            glm::all(glm::lessThan(q, dims_)) && bit_at(weld_.row(q.y, q.z), q.x))
                            recheck.push_back(q);
                    }
        };
        const auto settle = [&](glm::ivec3 p) {
            if (weld_keeps_manifold(p)) return;
            unweld(p);
            while (!recheck.empty()) {
                const glm::ivec3 q = recheck.back();
                recheck.pop_back();
                if (bit_at(weld_.row(q.y, q.z), q.x) && !weld_keeps_manifold(q)) unweld(q);
            }
        };
        for (int z = 0; z < dims_.z; ++z) {
            report(0.3f, 0.35f, z, dims_.z);
            for (int y = 0; y < dims_.y; ++y)
                for (int w = 0; w < words_; ++w)
                    for_each_bit(weld_.row(y, z)[w], w, [&](int x) {
                        if (bit_at(weld_.row(y, z), x)) settle({x, y, z});
                    });
        }
    }

    // Identity of the vertex of crossed edge e of the cell at `origin`: its welded inside
    // sample, or the edge itself.
    std::uint64_t vertex_key(glm::ivec3 origin, int e, unsigned inside, unsigned welded) const {
        const int lo = detail::cube_edge_corner(e, 0), hi = detail::cube_edge_corner(e, 1);
        const int in = ((inside >> lo) & 1u) != 0 ? lo : hi;
        const auto sample_id = [&](int corner) {
            const glm::ivec3 q =
                origin + glm::ivec3(corner & 1, (corner >> 1) & 1, (corner >> 2) & 1);
            return std::uint64_t(volume_.index(q.x, q.y, q.z));
        };
        if (((welded >> in) & 1u) != 0) return sample_id(in) * 4 + 3;
        return sample_id(lo) * 4 + std::uint64_t(e / 4);
    }

    // Whether every edge at the welded vertex of sample p is used once in each direction.
    bool weld_keeps_manifold(glm::ivec3 p) const {
        const std::uint64_t self = std::uint64_t(volume_.index(p.x, p.y, p.z)) * 4 + 3;
        // (neighbour key, +1 for an edge leaving p, +2 for one arriving), at most 8 cells x 12
        // triangles.
        std::array<std::pair<std::uint64_t, int>, 8 * 2 * detail::MarchingCubesCase::kMaxTriangles>
            uses;
        std::size_t count = 0;
        for (int c = 0; c < 8; ++c) {
            const glm::ivec3 origin = p - glm::ivec3(c & 1, (c >> 1) & 1, (c >> 2) & 1);
            if (glm::any(glm::lessThan(origin, glm::ivec3(0))) ||
                glm::any(glm::greaterThanEqual(origin, dims_ - 1)))
                continue;
            const unsigned inside = inside_rows(origin.y, origin.z).mask(origin.x);
            const unsigned welded = weld_rows(origin.y, origin.z).mask(origin.x);
            const detail::WeldedCase& entry = detail::welded_case(inside, welded);
            for (int t = 0; t < entry.triangle_count; ++t) {
                std::uint64_t key[3];
                for (int k = 0; k < 3; ++k)
                    key[k] = vertex_key(origin, entry.triangles[t][k], inside, welded);
                for (int k = 0; k < 3; ++k) {
                    if (key[k] != self) continue;
                    uses[count++] = {key[(k + 1) % 3], 1};
                    uses[count++] = {key[(k + 2) % 3], 2};
                }
            }
        }
        std::sort(uses.begin(), uses.begin() + std::ptrdiff_t(count));
        // Sorted, each neighbour must appear exactly as (n, 1), (n, 2); on the volume border
        // the surface is open and one of the two may be missing.
        for (std::size_t i = 0; i < count;) {
            std::size_t end = i;
            while (end < count && uses[end].first == uses[i].first) ++end;
            const bool pair = end - i == 2 && uses[i].second == 1 && uses[i + 1].second == 2;
            if (!pair && !(end - i == 1 && on_common_border(p, uses[i].first))) return false;
            i = end;
        }
        return true;
    }

    // Whether sample p and the vertex `key` lie in one border plane of the volume.
    bool on_common_border(glm::ivec3 p, std::uint64_t key) const {
        const std::uint64_t index = key / 4;
        const int along = int(key % 4); // axis of the vertex's edge, 3 for a welded sample
        const std::uint64_t nx = std::uint64_t(dims_.x), ny = std::uint64_t(dims_.y);
        const glm::ivec3 q(int(index % nx), int(index / nx % ny), int(index / (nx * ny)));
        for (int axis = 0; axis < 3; ++axis) {
            if (axis == along || q[axis] != p[axis]) continue;
            if (p[axis] == 0 || p[axis] == dims_[axis] - 1) return true;
        }
        return false;
    }

    template <bool kAbove>
    bool classify_row(const float* samples, Word* inside, Word* at_iso) const {
        // Comparisons into bytes first (this loop vectorises), then bytes into bits.
        alignas(64) std::uint8_t in[kWordBits], eq[kWordBits];
        Word any_at_iso = 0;
        for (int w = 0; w < words_; ++w) {
            const int first = w * kWordBits, n = std::min(kWordBits, dims_.x - first);
            const float* v = samples + first;
            std::uint8_t any_eq = 0;
            if (n == kWordBits) {
                for (int i = 0; i < kWordBits; ++i) {
                    in[i] = kAbove ? v[i] >= iso_ : v[i] <= iso_;
                    eq[i] = v[i] == iso_;
                    any_eq |= eq[i];
                }
            } else {
                for (int i = 0; i < kWordBits; ++i) {
                    in[i] = i < n && (kAbove ? v[i] >= iso_ : v[i] <= iso_);
                    eq[i] = i < n && v[i] == iso_;
                    any_eq |= eq[i];
                }
            }
            inside[w] = pack_bytes(in);
            at_iso[w] = any_eq != 0 ? pack_bytes(eq) : 0;
            any_at_iso |= at_iso[w];
        }
        return any_at_iso != 0;
    }

    // Keeps the at-iso bits of samples with an outside neighbour (only those have crossings,
    // so only those are candidates for a welded vertex). Returns whether any bit is left.
    bool keep_surface_samples(SampleBits& at_iso, int y, int z) const {
        const Word* row = inside_.row(y, z);
        const Word* y_lo = y > 0 ? inside_.row(y - 1, z) : ones_row_.data();
        const Word* y_hi = y + 1 < dims_.y ? inside_.row(y + 1, z) : ones_row_.data();
        const Word* z_lo = z > 0 ? inside_.row(y, z - 1) : ones_row_.data();
        const Word* z_hi = z + 1 < dims_.z ? inside_.row(y, z + 1) : ones_row_.data();
        Word* candidates = at_iso.row(y, z);
        Word any = 0;
        for (int w = 0; w < words_; ++w) {
            if (candidates[w] == 0) continue;
            const Word x_lo = bits_below(row, w, Word(1)); // a missing neighbour is no crossing
            const Word x_hi = bits_above(row, w, words_) | ~bits_before(dims_.x - 1, w);
            candidates[w] &= ~(x_lo & x_hi & y_lo[w] & y_hi[w] & z_lo[w] & z_hi[w]);
            any |= candidates[w];
        }
        return any != 0;
    }

    RowEdges row_edges(int y, int z, int w) const {
        RowEdges e;
        const Word* in = inside_.row(y, z);
        const Word* weld = weld_row(y, z);
        const Word x_crossed = (in[w] ^ bits_above(in, w, words_)) & bits_before(dims_.x - 1, w);
        const Word x_weld = weld[w] | bits_above(weld, w, words_);
        e.x_own = x_crossed & ~x_weld;
        e.x_welded = x_crossed & x_weld;
        if (y + 1 < dims_.y) {
            const Word y_crossed = in[w] ^ inside_.row(y + 1, z)[w];
            const Word y_weld = weld[w] | weld_row(y + 1, z)[w];
            e.y_own = y_crossed & ~y_weld;
            e.y_welded = y_crossed & y_weld;
        }
        if (z + 1 < dims_.z) {
            const Word z_crossed = in[w] ^ inside_.row(y, z + 1)[w];
            const Word z_weld = weld[w] | weld_row(y, z + 1)[w];
            e.z_own = z_crossed & ~z_weld;
            e.z_welded = z_crossed & z_weld;
        }
        return e;
    }

    // Cells of row (y, slab z) that the surface passes through (corners not all equal).
    Word active_cells(const CellRows& rows, int w) const {
        const auto any = [&](int i) {
            return rows.r[0][i] | rows.r[1][i] | rows.r[2][i] | rows.r[3][i];
        };
        const auto all = [&](int i) {
            return rows.r[0][i] & rows.r[1][i] & rows.r[2][i] & rows.r[3][i];
        };
        const bool more = w + 1 < words_;
        const Word any_w = any(w), all_w = all(w);
        const Word any_pair = any_w | (any_w >> 1) | (more ? any(w + 1) << (kWordBits - 1) : 0);
        const Word all_pair = all_w & ((all_w >> 1) | (more ? all(w + 1) << (kWordBits - 1) : 0));
        return any_pair & ~all_pair & bits_before(dims_.x - 1, w);
    }

    CellRows inside_rows(int y, int z) const {
        return {{inside_.row(y, z), inside_.row(y + 1, z), inside_.row(y, z + 1),
                 inside_.row(y + 1, z + 1)}};
    }
    CellRows weld_rows(int y, int z) const {
        return {{weld_row(y, z), weld_row(y + 1, z), weld_row(y, z + 1), weld_row(y + 1, z + 1)}};
    }

    // Pass 1: triangles per slab (marking which welded samples keep a triangle), then vertices
    // per plane, then prefix sums.
    void count() {
        const detail::MarchingCubesCase* cases = &detail::marching_cubes_case(0);
        const int slabs = dims_.z - 1;
        std::vector<std::size_t> slab_triangles(std::size_t(slabs), 0);
        for (int z = 0; z < slabs; ++z) {
            report(0.35f, 0.39f, z, slabs);
            std::size_t triangles = 0;
            for (int y = 0; y + 1 < dims_.y; ++y) {
                const CellRows rows = inside_rows(y, z);
                const CellRows welds = weld_rows(y, z);
                for (int w = 0; w < words_; ++w) {
                    for_each_bit(active_cells(rows, w), w, [&](int x) {
                        const unsigned inside = rows.mask(x);
                        const unsigned welded = has_welds() ? welds.mask(x) : 0u;
                        if (welded == 0) {
                            triangles += cases[inside].triangle_count;
                            return;
                        }
                        const detail::WeldedCase& entry = detail::welded_case(inside, welded);
                        triangles += entry.triangle_count;
                        mark_used(x, y, z, entry.used_corners);
                    });
                }
            }
            slab_triangles[std::size_t(z)] = triangles;
        }

        plane_count_.assign(std::size_t(dims_.z), PlaneCount{});
        for (int z = 0; z < dims_.z; ++z) {
            report(0.39f, 0.4f, z, dims_.z);
            PlaneCount& c = plane_count_[std::size_t(z)];
            for (int y = 0; y < dims_.y; ++y)
                for (int w = 0; w < words_; ++w) {
                    const RowEdges e = row_edges(y, z, w);
                    c.xy += std::size_t(std::popcount(e.x_own) + std::popcount(e.y_own));
                    c.z += std::size_t(std::popcount(e.z_own));
                    if (has_welds()) c.welds += std::size_t(std::popcount(used_welds(y, z, w)));
                }
        }

        vertex_offset_.assign(std::size_t(dims_.z) + 1, 0);
        for (int z = 0; z < dims_.z; ++z) {
            const PlaneCount& c = plane_count_[std::size_t(z)];
            vertex_offset_[std::size_t(z) + 1] =
                vertex_offset_[std::size_t(z)] + c.welds + c.xy + c.z;
        }
        if (vertex_offset_.back() > std::numeric_limits<std::uint32_t>::max())
            throw std::runtime_error("marching cubes: the mesh would have " +
                                     std::to_string(vertex_offset_.back()) +
                                     " vertices, more than 32-bit indices can address");
        triangle_offset_.assign(std::size_t(slabs) + 1, 0);
        for (int z = 0; z < slabs; ++z)
            triangle_offset_[std::size_t(z) + 1] =
                triangle_offset_[std::size_t(z)] + slab_triangles[std::size_t(z)];
    }

    // Slab z marks plane z in used_from_above_ and plane z + 1 in used_from_below_, so two
    // slabs never write the same word.
    void mark_used(int x, int y, int z, unsigned corners) {
        for (int c = 0; c < 8; ++c) {
            if (((corners >> c) & 1u) == 0) continue;
            const int cx = x + (c & 1), cy = y + ((c >> 1) & 1);
            SampleBits& bits = (c & 4) != 0 ? used_from_below_ : used_from_above_;
            bits.row(cy, z + ((c >> 2) & 1))[cx / kWordBits] |= Word(1) << (cx % kWordBits);
        }
    }

    // Pass 2 for slabs [first, last): vertex ids (and positions of the planes this range owns:
    // its own planes, plus the last plane of the volume), then triangles.
    void fill_slabs(int first, int last, Mesh& mesh) const {
        if (first >= last) return;
        const std::size_t plane_size = std::size_t(dims_.x) * std::size_t(dims_.y);
        PlaneIds lower, upper;
        for (PlaneIds* p : {&lower, &upper}) {
            p->x.assign(plane_size, 0);
            p->y.assign(plane_size, 0);
            p->weld.assign(plane_size, 0);
        }
        std::vector<std::uint32_t> z_ids(plane_size, 0);
        assign_plane_ids(first, lower, &mesh);
        for (int z = first; z < last; ++z) {
            report(0.4f, 1.0f, z - first, last - first);
            const bool owns_next = z + 1 < last || z + 1 == dims_.z - 1;
            assign_plane_ids(z + 1, upper, owns_next ? &mesh : nullptr);
            assign_z_ids(z, lower, upper, z_ids, mesh);
            emit_triangles(z, lower, upper, z_ids, mesh);
            std::swap(lower, upper);
        }
    }

    // Ids of the welded samples and of the x/y crossings of plane z; positions are written
    // when `mesh` is given (the plane is owned by the caller's slab range).
    void assign_plane_ids(int z, PlaneIds& ids, Mesh* mesh) const {
        std::uint32_t next = std::uint32_t(vertex_offset_[std::size_t(z)]);
        const auto place = [&](glm::vec3 p) {
            if (mesh != nullptr) mesh->positions[next] = p;
            return next++;
        };
        const std::size_t nx = std::size_t(dims_.x);
        if (has_welds())
            for (int y = 0; y < dims_.y; ++y)
                for (int w = 0; w < words_; ++w)
                    for_each_bit(used_welds(y, z, w), w, [&](int x) {
                        ids.weld[std::size_t(y) * nx + std::size_t(x)] =
                            place(glm::vec3(float(x), float(y), float(z)));
                    });
        for (int y = 0; y < dims_.y; ++y) {
            const std::size_t row = std::size_t(y) * nx;
            const float* s = volume_.samples.data() + volume_.index(0, y, z);
            const float* s_next = y + 1 < dims_.y ? s + nx : nullptr;
            const Word* weld = weld_row(y, z);
            for (int w = 0; w < words_; ++w) {
                const RowEdges e = row_edges(y, z, w);
                for_each_bit(e.x_own, w, [&](int x) {
                    const double t = crossing_parameter(s[x], s[x + 1], iso_);
                    ids.x[row + std::size_t(x)] =
                        place(glm::vec3(float(double(x) + t), float(y), float(z)));
                });
                for_each_bit(e.x_welded, w, [&](int x) {
                    ids.x[row + std::size_t(x)] =
                        ids.weld[row + std::size_t(bit_at(weld, x) ? x : x + 1)];
                });
                for_each_bit(e.y_own, w, [&](int x) {
                    const double t = crossing_parameter(s[x], s_next[x], iso_);
                    ids.y[row + std::size_t(x)] =
                        place(glm::vec3(float(x), float(double(y) + t), float(z)));
                });
                for_each_bit(e.y_welded, w, [&](int x) {
                    ids.y[row + std::size_t(x)] =
                        ids.weld[(bit_at(weld, x) ? row : row + nx) + std::size_t(x)];
                });
            }
        }
    }

    // Ids and positions of the z crossings between planes z and z + 1 (owned by plane z).
    void assign_z_ids(int z, const PlaneIds& lower, const PlaneIds& upper,
                      std::vector<std::uint32_t>& ids, Mesh& mesh) const {
        const PlaneCount& c = plane_count_[std::size_t(z)];
        std::uint32_t next = std::uint32_t(vertex_offset_[std::size_t(z)] + c.welds + c.xy);
        const std::size_t nx = std::size_t(dims_.x);
        for (int y = 0; y < dims_.y; ++y) {
            const std::size_t row = std::size_t(y) * nx;
            const float* s = volume_.samples.data() + volume_.index(0, y, z);
            const float* s_next = volume_.samples.data() + volume_.index(0, y, z + 1);
            const Word* weld = weld_row(y, z);
            for (int w = 0; w < words_; ++w) {
                const RowEdges e = row_edges(y, z, w);
                for_each_bit(e.z_own, w, [&](int x) {
                    const double t = crossing_parameter(s[x], s_next[x], iso_);
                    mesh.positions[next] = glm::vec3(float(x), float(y), float(double(z) + t));
                    ids[row + std::size_t(x)] = next++;
                });
                for_each_bit(e.z_welded, w, [&](int x) {
                    ids[row + std::size_t(x)] =
                        (bit_at(weld, x) ? lower.weld : upper.weld)[row + std::size_t(x)];
                });
            }
        }
    }

    void emit_triangles(int z, const PlaneIds& lower, const PlaneIds& upper,
                        const std::vector<std::uint32_t>& z_ids, Mesh& mesh) const {
        const detail::MarchingCubesCase* cases = &detail::marching_cubes_case(0);
        std::uint32_t* out = mesh.indices.data() + 3 * triangle_offset_[std::size_t(z)];
        const std::size_t nx = std::size_t(dims_.x);
        for (int y = 0; y + 1 < dims_.y; ++y) {
            const CellRows rows = inside_rows(y, z);
            const CellRows welds = weld_rows(y, z);
            for (int w = 0; w < words_; ++w) {
                for_each_bit(active_cells(rows, w), w, [&](int x) {
                    const unsigned inside = rows.mask(x);
                    const detail::MarchingCubesCase& entry = cases[inside];
                    // Edge e of the cell -> vertex id, in the numbering of the table.
                    const std::size_t r0 = std::size_t(y) * nx + std::size_t(x), r1 = r0 + nx;
                    const std::uint32_t id[12] = {lower.x[r0],   lower.x[r1],     upper.x[r0],
                                                  upper.x[r1],   lower.y[r0],     lower.y[r0 + 1],
                                                  upper.y[r0],   upper.y[r0 + 1], z_ids[r0],
                                                  z_ids[r0 + 1], z_ids[r1],       z_ids[r1 + 1]};
                    const unsigned welded = has_welds() ? welds.mask(x) : 0u;
                    if (welded == 0) {
                        for (int t = 0; t < entry.triangle_count; ++t) {
                            out[0] = id[entry.triangles[t][0]];
                            out[1] = id[entry.triangles[t][1]];
                            out[2] = id[entry.triangles[t][2]];
                            out += 3;
                        }
                        return;
                    }
                    const detail::WeldedCase& merged = detail::welded_case(inside, welded);
                    for (int t = 0; t < merged.triangle_count; ++t) {
                        for (int c = 0; c < 3; ++c) out[c] = id[merged.triangles[t][c]];
                        out += 3;
                    }
                });
            }
        }
        if (out != mesh.indices.data() + 3 * triangle_offset_[std::size_t(z) + 1])
            throw std::logic_error("marching cubes: fill pass disagrees with count pass");
    }

    const Volume& volume_;
    const float iso_;
    const bool above_;
    const Progress& progress_;
    const glm::ivec3 dims_;
    const int words_;
    const std::vector<Word> zero_row_, ones_row_;
    SampleBits inside_;
    SampleBits weld_;            // inside samples exactly at iso that are welded (empty: none)
    SampleBits used_from_below_; // welded samples kept by a triangle of the slab below
    SampleBits used_from_above_; // ... of the slab above
    std::vector<PlaneCount> plane_count_;
    std::vector<std::size_t> vertex_offset_;   // per plane, plus the total
    std::vector<std::size_t> triangle_offset_; // per slab, plus the total
};

} // namespace

Mesh marching_cubes(const Volume& volume, const MarchingCubesOptions& options,
                    const Progress& progress) {
    if (std::isnan(options.iso)) throw std::invalid_argument("marching cubes: iso value is NaN");
    if (volume.dims.x < 0 || volume.dims.y < 0 || volume.dims.z < 0 ||
        volume.samples.size() != volume.voxel_count())
        throw std::invalid_argument("marching cubes: volume of " + std::to_string(volume.dims.x) +
                                    " x " + std::to_string(volume.dims.y) + " x " +
                                    std::to_string(volume.dims.z) + " has " +
                                    std::to_string(volume.samples.size()) + " samples");
    progress.update(0.0f);
    if (volume.dims.x < 2 || volume.dims.y < 2 || volume.dims.z < 2) {
        progress.update(1.0f);
        return {};
    }
    return Extractor(volume, options, progress).run();
}

} // namespace snert
