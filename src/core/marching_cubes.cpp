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
#include <cmath>
#include <cstddef>
#include <limits>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "bit_planes.h"
#include "huge_pages.h"
#include "input_error.h"
#include "parallel.h"
#include "prefetch.h"
#include "scratch_pool.h"
#include "step_progress.h"
#include "vector_angle.h"

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
        return detail::vector_angle(glm::length(glm::cross(u, v)), glm::dot(u, v));
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

using detail::BitVolume;
using detail::for_each_bit;
using detail::kWordBits;
using detail::Word;

// ---------------------------------------------------------------------------------------------
// (2) The placement of crossings (the bit planes of the classification: bit_planes.h).

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
// blocks are sized in the count pass, so the fill pass writes disjoint ranges: every pass runs
// over fixed chunks of planes or slabs (parallel.h), and the output does not depend on how many
// threads run them.

// Planes or slabs per chunk: enough work per chunk to amortise the start of a chunk of the fill
// pass (one plane's ids recomputed), small enough for two or more threads to balance.
constexpr std::size_t kSlabsPerChunk = 8;

// Rows ahead that prefetch_crossings works: about a memory latency of work.
constexpr int kPrefetchRows = 4;

class Extractor {
  public:
    Extractor(const Volume& volume, const MarchingCubesOptions& options, const Progress& progress)
        : volume_(volume), iso_(options.iso), above_(options.inside == InsideIs::Above),
          progress_(progress), dims_(volume.dims),
          words_((volume.dims.x + kWordBits - 1) / kWordBits), margin_(crossing_margin(dims_)),
          // Steps: planes classified, planes counted, slabs filled.
          steps_(progress, 3 * std::size_t(dims_.z) - 1) {}

    Mesh run() {
        const std::size_t planes = std::size_t(dims_.z), slabs = planes - 1;
        inside_ = BitVolume(dims_);
        for_each_chunk(planes, kSlabsPerChunk,
                       [&](std::size_t, std::size_t first, std::size_t end) {
                           for (std::size_t z = first; z < end; ++z) classify_plane(int(z));
                       });
        plane_count_.assign(planes, PlaneCount{});
        std::vector<std::size_t> slab_triangles(slabs, 0);
        for_each_chunk(planes, kSlabsPerChunk,
                       [&](std::size_t, std::size_t first, std::size_t end) {
                           for (std::size_t z = first; z < end; ++z) {
                               steps_.step();
                               plane_count_[z] = count_plane_vertices(int(z));
                               if (z < slabs) slab_triangles[z] = count_slab_triangles(int(z));
                           }
                       });
        set_offsets(slab_triangles);
        Mesh mesh;
        // Sizing the two arrays (up to 60 MB) is a serial part of the run: with fresh memory the
        // kernel's mapping of their pages is most of it, so that is asked for in pieces on every
        // thread first (the indices are twice the positions), then each is zeroed.
        const std::size_t vertices = vertex_offset_.back(), indices = 3 * triangle_offset_.back();
        detail::reserve_on_huge_pages(mesh.positions, vertices);
        detail::reserve_on_huge_pages(mesh.indices, indices);
        constexpr std::size_t kPieces = 8;
        for_each_chunk(2 * kPieces, 1, [&](std::size_t k, std::size_t, std::size_t) {
            const auto map_piece = [](auto& v, std::size_t n, std::size_t piece) {
                const std::size_t first = n * piece / kPieces, end = n * (piece + 1) / kPieces;
                detail::map_pages_for_writing(static_cast<void*>(v.data() + first),
                                              (end - first) * sizeof(v[0]));
            };
            if (k < kPieces)
                map_piece(mesh.positions, vertices, k);
            else
                map_piece(mesh.indices, indices, k - kPieces);
        });
        for_each_chunk(2, 1, [&](std::size_t array, std::size_t, std::size_t) {
            if (array == 0)
                mesh.positions.resize(vertices);
            else
                mesh.indices.resize(indices);
        });
        for_each_chunk(slabs, kSlabsPerChunk, [&](std::size_t, std::size_t first, std::size_t end) {
            fill_slabs(int(first), int(end), mesh);
        });
        progress_.update(1.0f);
        return mesh;
    }

  private:
    struct PlaneCount {
        std::size_t xy = 0, z = 0;
    };
    // Vertex ids per sample of a plane, valid only where the edge is crossed (never read
    // elsewhere, so left uninitialised): the x and y edges' parts of a FillIds.
    struct PlaneIds {
        std::uint32_t* x;
        std::uint32_t* y;
    };
    // The ids a range of slabs works with: planes z and z + 1, and the z edges between them. One
    // array for the five: 5 MB on a 512^2 slice, on huge pages, where 1 MB arrays are not.
    struct FillIds {
        explicit FillIds(std::size_t plane_size)
            : ids(5 * plane_size), lower{part(0, plane_size), part(1, plane_size)},
              upper{part(2, plane_size), part(3, plane_size)}, z(part(4, plane_size)) {}
        std::uint32_t* part(std::size_t k, std::size_t plane_size) const {
            return ids.get() + k * plane_size;
        }
        detail::ScratchArray<std::uint32_t> ids;
        PlaneIds lower, upper;
        std::uint32_t* z;
    };
    // The crossed edges at sample row (y, z), one word at a time.
    struct RowEdges {
        Word x = 0, y = 0, z = 0;
    };

    // Pass 0: the inside bit of every sample of plane z. NaN compares false: outside.
    void classify_plane(int z) {
        steps_.step();
        for (int y = 0; y < dims_.y; ++y) {
            detail::set_threshold_row(
                inside_, y, z, volume_.samples.data() + volume_.index(0, y, z), iso_, above_);
        }
    }

    RowEdges row_edges(int y, int z, int w) const {
        RowEdges e;
        const Word* in = inside_.row(y, z);
        e.x = (in[w] ^ detail::bits_above(in, w, words_)) & detail::bits_before(dims_.x - 1, w);
        if (y + 1 < dims_.y) e.y = in[w] ^ inside_.row(y + 1, z)[w];
        if (z + 1 < dims_.z) e.z = in[w] ^ inside_.row(y, z + 1)[w];
        return e;
    }

    // Pass 1: triangles of slab z, crossings owned by plane z; then prefix sums.
    std::size_t count_slab_triangles(int z) const {
        const detail::MarchingCubesCase* cases = &detail::marching_cubes_case(0);
        std::size_t triangles = 0;
        for (int y = 0; y + 1 < dims_.y; ++y)
            inside_.for_each_surface_cell(
                y, z, [&](int, unsigned mask) { triangles += cases[mask].triangle_count; });
        return triangles;
    }

    PlaneCount count_plane_vertices(int z) const {
        PlaneCount c;
        for (int y = 0; y < dims_.y; ++y)
            for (int w = 0; w < words_; ++w) {
                const RowEdges e = row_edges(y, z, w);
                if ((e.x | e.y | e.z) == 0) continue; // most words: nothing to count
                c.xy += detail::set_bits(e.x) + detail::set_bits(e.y);
                c.z += detail::set_bits(e.z);
            }
        return c;
    }

    void set_offsets(const std::vector<std::size_t>& slab_triangles) {
        vertex_offset_.assign(plane_count_.size() + 1, 0);
        for (std::size_t z = 0; z < plane_count_.size(); ++z)
            vertex_offset_[z + 1] = vertex_offset_[z] + plane_count_[z].xy + plane_count_[z].z;
        if (vertex_offset_.back() > std::numeric_limits<std::uint32_t>::max())
            throw InputError("marching cubes: the mesh would have " +
                             std::to_string(vertex_offset_.back()) +
                             " vertices, more than 32-bit indices can address");
        triangle_offset_.assign(slab_triangles.size() + 1, 0);
        for (std::size_t z = 0; z < slab_triangles.size(); ++z)
            triangle_offset_[z + 1] = triangle_offset_[z] + slab_triangles[z];
    }

    // Pass 2 for slabs [first, last): vertex ids (and positions of the planes this range owns:
    // its own planes, plus the last plane of the volume), then triangles. The ids of plane
    // `first` are recomputed here (without positions) when an earlier chunk owns it.
    void fill_slabs(int first, int last, Mesh& mesh) const {
        const auto ids =
            ids_pool_.take([&] { return FillIds(std::size_t(dims_.x) * std::size_t(dims_.y)); });
        PlaneIds* lower = &ids->lower;
        PlaneIds* upper = &ids->upper;
        assign_plane_ids(first, *lower, &mesh);
        for (int z = first; z < last; ++z) {
            steps_.step();
            const bool owns_next = z + 1 < last || z + 1 == dims_.z - 1;
            assign_plane_ids(z + 1, *upper, owns_next ? &mesh : nullptr);
            assign_z_ids(z, ids->z, mesh);
            emit_triangles(z, *lower, *upper, ids->z, mesh);
            std::swap(lower, upper);
        }
    }

    // Ids of the x/y crossings of plane z; positions are written when `mesh` is given (the
    // plane is owned by the caller's slab range).
    void assign_plane_ids(int z, PlaneIds& ids, Mesh* mesh) const {
        std::uint32_t next = std::uint32_t(vertex_offset_[std::size_t(z)]);
        const std::size_t nx = std::size_t(dims_.x);
        for (int y = 0; y < dims_.y; ++y) {
            if (mesh != nullptr) prefetch_crossings(y + kPrefetchRows, z, false);
            std::uint32_t* x_ids = ids.x + std::size_t(y) * nx;
            std::uint32_t* y_ids = ids.y + std::size_t(y) * nx;
            const float* s = volume_.samples.data() + volume_.index(0, y, z);
            const float* s_next = y + 1 < dims_.y ? s + nx : nullptr;
            for (int w = 0; w < words_; ++w) {
                const RowEdges e = row_edges(y, z, w);
                if (mesh == nullptr) {
                    for_each_bit(e.x, w, [&](int x) { x_ids[x] = next++; });
                    for_each_bit(e.y, w, [&](int x) { y_ids[x] = next++; });
                    continue;
                }
                for_each_bit(e.x, w, [&](int x) {
                    const float px = crossing_coordinate(x, s[x], s[x + 1], iso_, margin_);
                    mesh->positions[next] = glm::vec3(px, float(y), float(z));
                    x_ids[x] = next++;
                });
                for_each_bit(e.y, w, [&](int x) {
                    const float py = crossing_coordinate(y, s[x], s_next[x], iso_, margin_);
                    mesh->positions[next] = glm::vec3(float(x), py, float(z));
                    y_ids[x] = next++;
                });
            }
        }
    }

    // Starts loading the samples at the crossed x and y edges of row (y, z), or at its z edges,
    // and at the edges' other ends. Crossings are sparse, so hardware prefetchers miss them,
    // and the volume was last read long ago (classify): without this, placing vertices waits
    // on memory for most of its time.
    void prefetch_crossings(int y, int z, bool z_edges) const {
        if (y >= dims_.y) return;
        const float* s = volume_.samples.data() + volume_.index(0, y, z);
        const std::size_t other = z_edges ? volume_.index(0, 0, 1) : std::size_t(dims_.x);
        for (int w = 0; w < words_; ++w) {
            const RowEdges e = row_edges(y, z, w);
            for_each_bit(z_edges ? e.z : e.x | e.y, w, [&](int x) {
                detail::prefetch(s + x);
                detail::prefetch(s + x + other);
            });
        }
    }

    // Ids and positions of the z crossings between planes z and z + 1 (owned by plane z).
    void assign_z_ids(int z, std::uint32_t* ids, Mesh& mesh) const {
        std::uint32_t next =
            std::uint32_t(vertex_offset_[std::size_t(z)] + plane_count_[std::size_t(z)].xy);
        const std::size_t nx = std::size_t(dims_.x);
        for (int y = 0; y < dims_.y; ++y) {
            prefetch_crossings(y + kPrefetchRows, z, true);
            std::uint32_t* row_ids = ids + std::size_t(y) * nx;
            const float* s = volume_.samples.data() + volume_.index(0, y, z);
            const float* s_next = volume_.samples.data() + volume_.index(0, y, z + 1);
            for (int w = 0; w < words_; ++w)
                for_each_bit(row_edges(y, z, w).z, w, [&](int x) {
                    const float pz = crossing_coordinate(z, s[x], s_next[x], iso_, margin_);
                    mesh.positions[next] = glm::vec3(float(x), float(y), pz);
                    row_ids[x] = next++;
                });
        }
    }

    void emit_triangles(int z, const PlaneIds& lower, const PlaneIds& upper,
                        const std::uint32_t* z_ids, Mesh& mesh) const {
        const detail::MarchingCubesCase* cases = &detail::marching_cubes_case(0);
        std::uint32_t* out = mesh.indices.data() + 3 * triangle_offset_[std::size_t(z)];
        const std::size_t nx = std::size_t(dims_.x);
        for (int y = 0; y + 1 < dims_.y; ++y) {
            // Edge e of cell x has its id at edge_ids[e][x], in the numbering of the table;
            // only crossed edges are read.
            const std::size_t r0 = std::size_t(y) * nx, r1 = r0 + nx;
            const std::uint32_t* edge_ids[12] = {lower.x + r0,   lower.x + r1,     upper.x + r0,
                                                 upper.x + r1,   lower.y + r0,     lower.y + r0 + 1,
                                                 upper.y + r0,   upper.y + r0 + 1, z_ids + r0,
                                                 z_ids + r0 + 1, z_ids + r1,       z_ids + r1 + 1};
            inside_.for_each_surface_cell(y, z, [&](int x, unsigned mask) {
                const detail::MarchingCubesCase& entry = cases[mask];
                for (int t = 0; t < entry.triangle_count; ++t) {
                    out[0] = edge_ids[entry.triangles[t][0]][x];
                    out[1] = edge_ids[entry.triangles[t][1]][x];
                    out[2] = edge_ids[entry.triangles[t][2]][x];
                    out += 3;
                }
            });
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
    BitVolume inside_;
    std::vector<PlaneCount> plane_count_;
    std::vector<std::size_t> vertex_offset_;   // per plane, plus the total
    std::vector<std::size_t> triangle_offset_; // per slab, plus the total
    mutable detail::StepProgress steps_;
    mutable detail::ScratchPool<FillIds> ids_pool_; // one FillIds per thread, not per chunk
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
