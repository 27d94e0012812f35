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
// the inside classification and the placement of crossings; (3) the passes.
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

#include "input_error.h"

namespace snert {

// ---------------------------------------------------------------------------------------------
// (1) The case table.
//
// For each of the 256 corner configurations: on each cube face, connect the crossed edges into
// segments (on an ambiguous face, cut each inside corner off on its own); orient each segment
// so that, seen from outside the cube, the inside corners lie on its right; the segments then
// chain into closed loops, wound counter-clockwise seen from the outside of the surface; each
// loop is triangulated once, here, with a fixed triangulation.

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
    // cell decides the same.
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

// A corner of a loop's polygon: a crossed edge.
struct PolygonVertex {
    int edge = 0;          // the crossed edge
    glm::dvec3 point{0.0}; // expected position: the edge midpoint
    unsigned faces = 0;    // cube faces it lies on, bit 2 * axis + side
};

PolygonVertex edge_vertex(int edge) {
    PolygonVertex v{edge, edge_midpoint(edge), 0};
    for (int axis = 0; axis < 3; ++axis)
        for (int side = 0; side < 2; ++side)
            if (edge_on_face(edge, axis, side)) v.faces |= 1u << (2 * axis + side);
    return v;
}

// A diagonal between two crossings on a common face could be used by the neighbouring cell
// too (then four triangles would share it), so it is never allowed; the case table proves it
// is never needed. Every diagonal then runs through the cell's interior and belongs to this
// cell alone: this is what makes Marching Cubes edge-manifold.
bool chord_allowed(const PolygonVertex& a, const PolygonVertex& b) {
    return (a.faces & b.faces) == 0;
}

// Triangulation of one polygon, chosen once per case (dynamic programming over sub-polygons)
// among those whose diagonals are allowed: on the expected vertex positions, the largest
// smallest angle, then the shortest total diagonal length. A fan would put slivers into the
// hexagons and larger loops, and choosing per cell from the actual positions would cost time
// in the hot loop for a small gain. Triangles (i, k, j) with i < k < j keep the winding.
std::vector<std::array<int, 3>> triangulate_polygon(const std::vector<PolygonVertex>& polygon) {
    const int n = int(polygon.size());
    struct Choice {
        double min_angle = std::numeric_limits<double>::infinity();
        double diagonals = 0;
        int split = -1;
    };
    constexpr double kTie = 1e-9;
    const auto better = [](const Choice& a, const Choice& b) {
        if (a.min_angle > b.min_angle + kTie) return true;
        if (a.min_angle < b.min_angle - kTie) return false;
        return a.diagonals < b.diagonals - kTie;
    };
    const auto is_side = [&](int i, int j) { return j - i == 1 || (i == 0 && j == n - 1); };
    const auto allowed = [&](int i, int j) {
        return is_side(i, j) || chord_allowed(polygon[i], polygon[j]);
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
                if (!allowed(i, k) || !allowed(k, j)) continue;
                if ((k - i > 1 && left.split < 0) || (j - k > 1 && right.split < 0)) continue;
                Choice candidate;
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
    if (n >= 3 && best[std::size_t(n - 1)].split < 0)
        throw std::logic_error("marching cubes table: a loop needs a diagonal on a face");
    std::vector<std::array<int, 3>> triangles;
    std::vector<std::array<int, 2>> pending{{0, n - 1}};
    while (!pending.empty()) {
        const auto [i, j] = pending.back();
        pending.pop_back();
        if (j - i < 2) continue;
        const int k = best[std::size_t(i) * n + j].split;
        triangles.push_back({polygon[i].edge, polygon[k].edge, polygon[j].edge});
        pending.push_back({i, k});
        pending.push_back({k, j});
    }
    return triangles;
}

void add_triangles(MarchingCubesCase& out, const std::vector<std::array<int, 3>>& triangles) {
    for (const auto& t : triangles) {
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
        add_triangles(result, triangulate_polygon(polygon));
    }
    return result;
}

const std::array<MarchingCubesCase, 256>& tables() {
    static const std::array<MarchingCubesCase, 256> built = [] {
        std::array<MarchingCubesCase, 256> cases;
        for (unsigned mask = 0; mask < 256; ++mask) cases[mask] = build_case(mask);
        return cases;
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
    return tables()[inside_mask & 255u];
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

// Where a crossing lies on its edge: linear interpolation between samples a (t = 0) and b
// (t = 1), with t kept in [margin, 1 - margin]. A sample exactly at iso counts as inside, as if
// it were inside by an infinitesimal amount (a symbolic perturbation of the iso value): each of
// its crossings stays a vertex of its own, `margin` off the sample towards the outside one. So
// the mesh is exactly the case table's surface of the segmentation, and no two vertices ever
// coincide (two grid edges meet only at samples). t is computed in double so that it never
// overflows; infinite samples give the end point nearer to the crossing; a NaN sample (outside)
// gives the end point at it.
inline float crossing_coordinate(int lower, float a, float b, float iso, double margin) {
    double t = (double(iso) - double(a)) / (double(b) - double(a));
    if (std::isnan(t)) t = std::isinf(a) ? (std::isinf(b) ? 0.5 : 1.0) : 0.0;
    return float(double(lower) + std::clamp(t, margin, 1.0 - margin));
}

// The margin of crossings from samples, in voxels: 2^-10, or two float steps of the largest
// coordinate where that is more (coordinates of 8192 and beyond). A power of two no finer than
// the float grid, so lower + margin and lower + 1 - margin are exact floats, distinct from the
// samples. Large enough that no triangle is degenerate by the measure of metrics.h: a triangle
// of the case table with every crossing parameter in [m, 1 - m] has twice its area at least
// 0.7 m times its longest edge squared (a search over all 256 cases), 7e-4 for m = 2^-10,
// against 1e-6 for `degenerate`; the smallest, three crossings around one corner at iso, are
// equilateral. Small enough to stay far below Marching Cubes' own error (about 1e-2 voxel).
inline double crossing_margin(glm::ivec3 dims) {
    int exponent = 0; // the largest coordinate is in [2^(exponent - 1), 2^exponent)
    std::frexp(double(std::max({dims.x, dims.y, dims.z, 1}) - 1), &exponent);
    return std::ldexp(1.0, std::max(-10, exponent - 23));
}

// ---------------------------------------------------------------------------------------------
// (3) The passes.
//
// Vertex ownership: plane z owns the crossings on its x and y edges and the crossings on the z
// edges up to plane z + 1. Its ids form one block: x/y crossings row by row, then z crossings
// row by row. Slab z (the cells between planes z and z + 1) owns a block of triangles. Both
// blocks are sized in the count pass, so the fill pass writes disjoint ranges and could run
// slabs in parallel.

class Extractor {
  public:
    Extractor(const Volume& volume, const MarchingCubesOptions& options, const Progress& progress)
        : volume_(volume), iso_(options.iso), above_(options.inside == InsideIs::Above),
          progress_(progress), dims_(volume.dims),
          words_((volume.dims.x + kWordBits - 1) / kWordBits), margin_(crossing_margin(dims_)) {}

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
        std::size_t xy = 0, z = 0;
    };
    struct PlaneIds {
        std::vector<std::uint32_t> x, y; // per sample of the plane, valid where crossed
    };
    // The crossed edges at sample row (y, z), one word at a time.
    struct RowEdges {
        Word x = 0, y = 0, z = 0;
    };

    void report(float begin, float end, int step, int steps) const {
        progress_.update(begin + (end - begin) * float(step) / float(std::max(steps, 1)));
    }

    // Pass 0: the inside bit of every sample.
    void classify() {
        inside_ = SampleBits(dims_, words_);
        for (int z = 0; z < dims_.z; ++z) {
            report(0.0f, 0.35f, z, dims_.z);
            for (int y = 0; y < dims_.y; ++y) {
                const float* samples = volume_.samples.data() + volume_.index(0, y, z);
                if (above_)
                    classify_row<true>(samples, inside_.row(y, z));
                else
                    classify_row<false>(samples, inside_.row(y, z));
            }
        }
    }

    template <bool kAbove> void classify_row(const float* samples, Word* inside) const {
        // Comparisons into bytes first (this loop vectorises), then bytes into bits. NaN
        // compares false: outside.
        alignas(64) std::uint8_t in[kWordBits];
        for (int w = 0; w < words_; ++w) {
            const int first = w * kWordBits, n = std::min(kWordBits, dims_.x - first);
            const float* v = samples + first;
            if (n == kWordBits) {
                for (int i = 0; i < kWordBits; ++i) in[i] = kAbove ? v[i] >= iso_ : v[i] <= iso_;
            } else {
                for (int i = 0; i < kWordBits; ++i)
                    in[i] = i < n && (kAbove ? v[i] >= iso_ : v[i] <= iso_);
            }
            inside[w] = pack_bytes(in);
        }
    }

    RowEdges row_edges(int y, int z, int w) const {
        RowEdges e;
        const Word* in = inside_.row(y, z);
        e.x = (in[w] ^ bits_above(in, w, words_)) & bits_before(dims_.x - 1, w);
        if (y + 1 < dims_.y) e.y = in[w] ^ inside_.row(y + 1, z)[w];
        if (z + 1 < dims_.z) e.z = in[w] ^ inside_.row(y, z + 1)[w];
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

    // Pass 1: triangles per slab, then vertices per plane, then prefix sums.
    void count() {
        const detail::MarchingCubesCase* cases = &detail::marching_cubes_case(0);
        const int slabs = dims_.z - 1;
        std::vector<std::size_t> slab_triangles(std::size_t(slabs), 0);
        for (int z = 0; z < slabs; ++z) {
            report(0.35f, 0.39f, z, slabs);
            std::size_t triangles = 0;
            for (int y = 0; y + 1 < dims_.y; ++y) {
                const CellRows rows = inside_rows(y, z);
                for (int w = 0; w < words_; ++w)
                    for_each_bit(active_cells(rows, w), w,
                                 [&](int x) { triangles += cases[rows.mask(x)].triangle_count; });
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
                    c.xy += std::size_t(std::popcount(e.x) + std::popcount(e.y));
                    c.z += std::size_t(std::popcount(e.z));
                }
        }

        vertex_offset_.assign(std::size_t(dims_.z) + 1, 0);
        for (int z = 0; z < dims_.z; ++z) {
            const PlaneCount& c = plane_count_[std::size_t(z)];
            vertex_offset_[std::size_t(z) + 1] = vertex_offset_[std::size_t(z)] + c.xy + c.z;
        }
        if (vertex_offset_.back() > std::numeric_limits<std::uint32_t>::max())
            throw InputError("marching cubes: the mesh would have " +
                             std::to_string(vertex_offset_.back()) +
                             " vertices, more than 32-bit indices can address");
        triangle_offset_.assign(std::size_t(slabs) + 1, 0);
        for (int z = 0; z < slabs; ++z)
            triangle_offset_[std::size_t(z) + 1] =
                triangle_offset_[std::size_t(z)] + slab_triangles[std::size_t(z)];
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
        }
        std::vector<std::uint32_t> z_ids(plane_size, 0);
        assign_plane_ids(first, lower, &mesh);
        for (int z = first; z < last; ++z) {
            report(0.4f, 1.0f, z - first, last - first);
            const bool owns_next = z + 1 < last || z + 1 == dims_.z - 1;
            assign_plane_ids(z + 1, upper, owns_next ? &mesh : nullptr);
            assign_z_ids(z, z_ids, mesh);
            emit_triangles(z, lower, upper, z_ids, mesh);
            std::swap(lower, upper);
        }
    }

    // Ids of the x/y crossings of plane z; positions are written when `mesh` is given (the
    // plane is owned by the caller's slab range).
    void assign_plane_ids(int z, PlaneIds& ids, Mesh* mesh) const {
        std::uint32_t next = std::uint32_t(vertex_offset_[std::size_t(z)]);
        const auto place = [&](glm::vec3 p) {
            if (mesh != nullptr) mesh->positions[next] = p;
            return next++;
        };
        const std::size_t nx = std::size_t(dims_.x);
        for (int y = 0; y < dims_.y; ++y) {
            const std::size_t row = std::size_t(y) * nx;
            const float* s = volume_.samples.data() + volume_.index(0, y, z);
            const float* s_next = y + 1 < dims_.y ? s + nx : nullptr;
            for (int w = 0; w < words_; ++w) {
                const RowEdges e = row_edges(y, z, w);
                for_each_bit(e.x, w, [&](int x) {
                    const float px = crossing_coordinate(x, s[x], s[x + 1], iso_, margin_);
                    ids.x[row + std::size_t(x)] = place(glm::vec3(px, float(y), float(z)));
                });
                for_each_bit(e.y, w, [&](int x) {
                    const float py = crossing_coordinate(y, s[x], s_next[x], iso_, margin_);
                    ids.y[row + std::size_t(x)] = place(glm::vec3(float(x), py, float(z)));
                });
            }
        }
    }

    // Ids and positions of the z crossings between planes z and z + 1 (owned by plane z).
    void assign_z_ids(int z, std::vector<std::uint32_t>& ids, Mesh& mesh) const {
        std::uint32_t next =
            std::uint32_t(vertex_offset_[std::size_t(z)] + plane_count_[std::size_t(z)].xy);
        const std::size_t nx = std::size_t(dims_.x);
        for (int y = 0; y < dims_.y; ++y) {
            const std::size_t row = std::size_t(y) * nx;
            const float* s = volume_.samples.data() + volume_.index(0, y, z);
            const float* s_next = volume_.samples.data() + volume_.index(0, y, z + 1);
            for (int w = 0; w < words_; ++w)
                for_each_bit(row_edges(y, z, w).z, w, [&](int x) {
                    const float pz = crossing_coordinate(z, s[x], s_next[x], iso_, margin_);
                    mesh.positions[next] = glm::vec3(float(x), float(y), pz);
                    ids[row + std::size_t(x)] = next++;
                });
        }
    }

    void emit_triangles(int z, const PlaneIds& lower, const PlaneIds& upper,
                        const std::vector<std::uint32_t>& z_ids, Mesh& mesh) const {
        const detail::MarchingCubesCase* cases = &detail::marching_cubes_case(0);
        std::uint32_t* out = mesh.indices.data() + 3 * triangle_offset_[std::size_t(z)];
        const std::size_t nx = std::size_t(dims_.x);
        for (int y = 0; y + 1 < dims_.y; ++y) {
            const CellRows rows = inside_rows(y, z);
            for (int w = 0; w < words_; ++w) {
                for_each_bit(active_cells(rows, w), w, [&](int x) {
                    const detail::MarchingCubesCase& entry = cases[rows.mask(x)];
                    // Edge e of the cell -> vertex id, in the numbering of the table.
                    const std::size_t r0 = std::size_t(y) * nx + std::size_t(x), r1 = r0 + nx;
                    const std::uint32_t id[12] = {lower.x[r0],   lower.x[r1],     upper.x[r0],
                                                  upper.x[r1],   lower.y[r0],     lower.y[r0 + 1],
                                                  upper.y[r0],   upper.y[r0 + 1], z_ids[r0],
                                                  z_ids[r0 + 1], z_ids[r1],       z_ids[r1 + 1]};
                    for (int t = 0; t < entry.triangle_count; ++t) {
                        out[0] = id[entry.triangles[t][0]];
                        out[1] = id[entry.triangles[t][1]];
                        out[2] = id[entry.triangles[t][2]];
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
    const double margin_; // see crossing_margin
    SampleBits inside_;
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
