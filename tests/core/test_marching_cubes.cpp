#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <map>
#include <random>
#include <set>
#include <stop_token>
#include <string>
#include <tuple>
#include <vector>

#include "io/load_volume.h"
#include "io/raw_volume.h"
#include "core/marching_cubes.h"
#include "core/metrics.h"
#include "core/phantom.h"
#include "support/real_data.h"

using namespace snert;
using detail::cube_edge_corner;
using detail::marching_cubes_case;
using detail::MarchingCubesCase;

namespace {

bool corner_inside(unsigned mask, int corner) {
    return ((mask >> corner) & 1u) != 0;
}
bool edge_crossed(unsigned mask, int e) {
    return corner_inside(mask, cube_edge_corner(e, 0)) !=
           corner_inside(mask, cube_edge_corner(e, 1));
}
glm::dvec3 corner_point(int c) {
    return {c & 1, (c >> 1) & 1, (c >> 2) & 1};
}
glm::dvec3 edge_midpoint(int e) {
    return 0.5 * (corner_point(cube_edge_corner(e, 0)) + corner_point(cube_edge_corner(e, 1)));
}

// The loops of a case as separate edge lists.
std::vector<std::vector<int>> loops_of(const MarchingCubesCase& c) {
    std::vector<std::vector<int>> loops;
    int used = 0;
    for (int l = 0; l < c.loop_count; ++l) {
        loops.emplace_back(c.loop_edges + used, c.loop_edges + used + c.loop_size[l]);
        used += c.loop_size[l];
    }
    return loops;
}

Mesh mc(const Volume& v, float iso, InsideIs inside = InsideIs::Above) {
    return marching_cubes(v, MarchingCubesOptions{iso, inside});
}

double triangle_area(const Mesh& m, std::size_t t) {
    const glm::dvec3 a = m.positions[m.indices[3 * t]], b = m.positions[m.indices[3 * t + 1]],
                     c = m.positions[m.indices[3 * t + 2]];
    return 0.5 * glm::length(glm::cross(b - a, c - a));
}

glm::dvec3 triangle_normal(const Mesh& m, std::size_t t) {
    const glm::dvec3 a = m.positions[m.indices[3 * t]], b = m.positions[m.indices[3 * t + 1]],
                     c = m.positions[m.indices[3 * t + 2]];
    return glm::cross(b - a, c - a);
}

bool every_vertex_referenced(const Mesh& m) {
    std::vector<char> used(m.positions.size(), 0);
    for (std::uint32_t i : m.indices) used[i] = 1;
    return std::all_of(used.begin(), used.end(), [](char u) { return u != 0; });
}

using Point = std::tuple<float, float, float>;
std::map<Point, int> position_counts(const Mesh& m) {
    std::map<Point, int> counts;
    for (const glm::vec3& p : m.positions) ++counts[{p.x, p.y, p.z}];
    return counts;
}

// Crossed grid edges of a volume, counted by brute force: one MC vertex each.
std::size_t crossed_edges(const Volume& v, float iso, InsideIs rule = InsideIs::Above) {
    const auto in = [&](int x, int y, int z) { return is_inside(v.at(x, y, z), iso, rule); };
    std::size_t n = 0;
    for (int z = 0; z < v.dims.z; ++z)
        for (int y = 0; y < v.dims.y; ++y)
            for (int x = 0; x < v.dims.x; ++x) {
                if (x + 1 < v.dims.x && in(x, y, z) != in(x + 1, y, z)) ++n;
                if (y + 1 < v.dims.y && in(x, y, z) != in(x, y + 1, z)) ++n;
                if (z + 1 < v.dims.z && in(x, y, z) != in(x, y, z + 1)) ++n;
            }
    return n;
}

// The binary segmentation of v (1 inside, 0 outside): its mesh at iso 0.5 is plain Marching
// Cubes of the same case table without any sample at iso.
Volume segmentation_volume(const Volume& v, float iso, InsideIs rule) {
    Volume b = v;
    for (float& s : b.samples) s = is_inside(s, iso, rule) ? 1.0f : 0.0f;
    return b;
}

// Vertices whose incident triangles form more than one fan (linked through shared edges at the
// vertex): pinched, not vertex-manifold. Counted independently of metrics.h.
std::size_t pinched_vertices(const Mesh& m) {
    std::vector<std::vector<std::uint32_t>> around(m.positions.size());
    for (std::size_t t = 0; t < m.triangle_count(); ++t)
        for (int k = 0; k < 3; ++k) around[m.indices[3 * t + k]].push_back(std::uint32_t(t));
    std::size_t pinched = 0;
    for (std::uint32_t v = 0; v < around.size(); ++v) {
        const auto& tris = around[v];
        std::vector<std::size_t> parent(tris.size());
        for (std::size_t i = 0; i < parent.size(); ++i) parent[i] = i;
        const auto root = [&](std::size_t i) {
            while (parent[i] != i) i = parent[i] = parent[parent[i]];
            return i;
        };
        std::map<std::uint32_t, std::size_t> first_with; // other end of an edge -> triangle
        for (std::size_t i = 0; i < tris.size(); ++i)
            for (int k = 0; k < 3; ++k) {
                const std::uint32_t other = m.indices[3 * tris[i] + k];
                if (other == v) continue;
                const auto [it, added] = first_with.emplace(other, i);
                if (!added) parent[root(i)] = root(it->second);
            }
        std::size_t fans = 0;
        for (std::size_t i = 0; i < tris.size(); ++i) fans += root(i) == i ? 1 : 0;
        if (fans > 1) ++pinched;
    }
    return pinched;
}

// Edges used by one triangle that do not lie in a border plane of the volume: holes.
std::size_t open_edges_off_border(const Mesh& m, glm::ivec3 dims) {
    std::map<std::pair<std::uint32_t, std::uint32_t>, int> uses;
    for (std::size_t t = 0; t < m.triangle_count(); ++t)
        for (int k = 0; k < 3; ++k) {
            const std::uint32_t a = m.indices[3 * t + k], b = m.indices[3 * t + (k + 1) % 3];
            ++uses[{std::min(a, b), std::max(a, b)}];
        }
    const auto on_border = [&](std::uint32_t a, std::uint32_t b) {
        for (int axis = 0; axis < 3; ++axis)
            for (float side : {0.0f, float(dims[axis] - 1)})
                if (m.positions[a][axis] == side && m.positions[b][axis] == side) return true;
        return false;
    };
    std::size_t open = 0;
    for (const auto& [edge, count] : uses)
        if (count == 1 && !on_border(edge.first, edge.second)) ++open;
    return open;
}

// Smallest 2 * area / longest edge^2 over the triangles (the measure of `degenerate`).
double flattest_triangle(const Mesh& m) {
    double flattest = std::numeric_limits<double>::infinity();
    for (std::size_t t = 0; t < m.triangle_count(); ++t) {
        const glm::dvec3 a = m.positions[m.indices[3 * t]], b = m.positions[m.indices[3 * t + 1]],
                         c = m.positions[m.indices[3 * t + 2]];
        const double longest =
            std::max({glm::length(b - a), glm::length(c - b), glm::length(a - c)});
        flattest = std::min(flattest, glm::length(glm::cross(b - a, c - a)) / (longest * longest));
    }
    return flattest;
}

// What Marching Cubes promises for any input: closed and oriented away from the border,
// edge- and vertex-manifold, no degenerate triangle, one distinct vertex per crossed edge, and
// the connectivity of the binary segmentation's plain case table. Returns a description of the
// first failure, empty when sound.
std::string surface_fault(const Volume& v, float iso, InsideIs rule = InsideIs::Above) {
    const Mesh m = mc(v, iso, rule);
    const Topology topo = topology(m);
    if (topo.nonmanifold_edges != 0 || topo.collapsed_triangles != 0) return "edge not manifold";
    if (!m.indices.empty() && !topo.oriented) return "not oriented";
    if (open_edges_off_border(m, v.dims) != 0) return "open edge away from the border";
    if (const std::size_t n = pinched_vertices(m); n != 0)
        return std::to_string(n) + " pinched vertices";
    if (const std::size_t n = quality_stats(m).degenerate; n != 0)
        return std::to_string(n) + " degenerate triangles";
    if (m.vertex_count() != crossed_edges(v, iso, rule)) return "not one vertex per crossed edge";
    if (position_counts(m).size() != m.vertex_count()) return "coincident vertices";
    if (m.indices != mc(segmentation_volume(v, iso, rule), 0.5f).indices)
        return "connectivity differs from the segmentation's";
    return {};
}

void expect_closed_oriented(const Mesh& m, const std::string& what) {
    const Topology topo = topology(m);
    EXPECT_TRUE(topo.watertight) << what << ": boundary " << topo.boundary_edges << ", nonmanifold "
                                 << topo.nonmanifold_edges << ", collapsed "
                                 << topo.collapsed_triangles;
    EXPECT_TRUE(topo.oriented) << what;
}

Volume padded_cell(unsigned mask, const std::array<float, 8>& inside_values) {
    Volume v = make_volume({4, 4, 4}, 0.0f);
    for (int c = 0; c < 8; ++c)
        v.samples[v.index(1 + (c & 1), 1 + ((c >> 1) & 1), 1 + ((c >> 2) & 1))] =
            corner_inside(mask, c) ? inside_values[std::size_t(c)] : 0.0f;
    return v;
}

// Random volume, by default with a one-sample outside border (value `outside`), so the surface
// is closed; unpadded, every sample is drawn and the surface reaches the border.
template <class Draw>
Volume random_volume(std::mt19937& rng, float outside, Draw draw, bool padded = true) {
    std::uniform_int_distribution<int> size(5, 7);
    Volume v = make_volume({size(rng), size(rng), size(rng)}, outside);
    const int pad = padded ? 1 : 0;
    for (int z = pad; z + pad < v.dims.z; ++z)
        for (int y = pad; y + pad < v.dims.y; ++y)
            for (int x = pad; x + pad < v.dims.x; ++x) v.samples[v.index(x, y, z)] = draw(rng);
    return v;
}

} // namespace

// ---------------------------------------------------------------------------------------------
// The generated case table.

TEST(MarchingCubesTable, LoopsCoverEveryCrossedEdgeExactlyOnce) {
    for (unsigned mask = 0; mask < 256; ++mask) {
        const MarchingCubesCase& c = marching_cubes_case(mask);
        std::multiset<int> in_loops;
        int expected_triangles = 0;
        for (const auto& loop : loops_of(c)) {
            EXPECT_GE(loop.size(), 3u) << mask;
            expected_triangles += int(loop.size()) - 2;
            in_loops.insert(loop.begin(), loop.end());
        }
        std::multiset<int> crossed;
        for (int e = 0; e < 12; ++e)
            if (edge_crossed(mask, e)) crossed.insert(e);
        EXPECT_EQ(in_loops, crossed) << mask;
        EXPECT_EQ(c.triangle_count, expected_triangles) << mask;
    }
    EXPECT_EQ(marching_cubes_case(0).triangle_count, 0);
    EXPECT_EQ(marching_cubes_case(255).triangle_count, 0);
    // Checkerboard: every face ambiguous, inside corners separated: four corner triangles.
    const unsigned checkerboard = 1u << 0 | 1u << 3 | 1u << 5 | 1u << 6;
    EXPECT_EQ(marching_cubes_case(checkerboard).loop_count, 4);
    EXPECT_EQ(marching_cubes_case(checkerboard).triangle_count, 4);
    // Two diagonal inside corners of the cube: two separate corner triangles.
    EXPECT_EQ(marching_cubes_case(1u << 0 | 1u << 7).loop_count, 2);
}

TEST(MarchingCubesTable, CrossingsAtAnInsideCornerAreConsecutiveInOneLoop) {
    // A loop cuts off its group of inside corners whole: the crossings of one inside corner
    // form one run of one loop.
    for (unsigned mask = 0; mask < 256; ++mask) {
        const auto loops = loops_of(marching_cubes_case(mask));
        for (int corner = 0; corner < 8; ++corner) {
            if (!corner_inside(mask, corner)) continue;
            std::set<int> at_corner;
            for (int e = 0; e < 12; ++e)
                if (edge_crossed(mask, e) &&
                    (cube_edge_corner(e, 0) == corner || cube_edge_corner(e, 1) == corner))
                    at_corner.insert(e);
            if (at_corner.empty()) continue;
            int loops_touched = 0;
            for (const auto& loop : loops) {
                const int n = int(loop.size());
                int members = 0, run_starts = 0;
                for (int i = 0; i < n; ++i) {
                    const bool here = at_corner.count(loop[i]) != 0;
                    const bool before = at_corner.count(loop[(i + n - 1) % n]) != 0;
                    members += here ? 1 : 0;
                    run_starts += here && !before ? 1 : 0;
                }
                if (members == 0) continue;
                ++loops_touched;
                EXPECT_EQ(members, int(at_corner.size())) << mask << " corner " << corner;
                // One run, or the whole loop (the corner triangle of three crossings).
                EXPECT_TRUE(run_starts == 1 || members == n) << mask << " corner " << corner;
            }
            EXPECT_EQ(loops_touched, 1) << mask << " corner " << corner;
        }
    }
}

TEST(MarchingCubesTable, TrianglesTriangulateEachLoopWithItsWinding) {
    for (unsigned mask = 0; mask < 256; ++mask) {
        const MarchingCubesCase& c = marching_cubes_case(mask);
        std::map<std::pair<int, int>, int> directed;
        for (int t = 0; t < c.triangle_count; ++t)
            for (int k = 0; k < 3; ++k)
                ++directed[{c.triangles[t][k], c.triangles[t][(k + 1) % 3]}];
        const auto uses = [&](int from, int to) {
            const auto it = directed.find({from, to});
            return it == directed.end() ? 0 : it->second;
        };
        std::size_t sides = 0;
        for (const auto& loop : loops_of(c)) {
            const int n = int(loop.size());
            sides += std::size_t(n);
            // Each polygon side is used exactly once, in the loop's direction.
            for (int i = 0; i < n; ++i) {
                EXPECT_EQ(uses(loop[i], loop[(i + 1) % n]), 1) << mask;
                EXPECT_EQ(uses(loop[(i + 1) % n], loop[i]), 0) << mask;
            }
        }
        // Nothing is used twice in one direction, and every diagonal once in each direction.
        std::size_t diagonal_uses = 0;
        for (const auto& [edge, count] : directed) {
            EXPECT_EQ(count, 1) << mask;
            if (uses(edge.second, edge.first) == 1) ++diagonal_uses;
        }
        EXPECT_EQ(sides + diagonal_uses, 3u * c.triangle_count) << mask;
    }
}

TEST(MarchingCubesTable, CornerTrianglesFaceAwayFromTheInside) {
    for (int corner = 0; corner < 8; ++corner) {
        for (bool inverted : {false, true}) {
            const unsigned mask = inverted ? 255u & ~(1u << corner) : 1u << corner;
            const MarchingCubesCase& c = marching_cubes_case(mask);
            ASSERT_EQ(c.triangle_count, 1);
            const glm::dvec3 a = edge_midpoint(c.triangles[0][0]);
            const glm::dvec3 n = glm::cross(edge_midpoint(c.triangles[0][1]) - a,
                                            edge_midpoint(c.triangles[0][2]) - a);
            const glm::dvec3 away = a - corner_point(corner); // from the corner outwards
            EXPECT_GT(glm::dot(n, inverted ? -away : away), 0.0) << corner << " " << inverted;
        }
    }
}

TEST(MarchingCubesTable, NoTriangleIsFlatWhileCrossingsKeepTheirMargin) {
    // Crossings are kept a margin m = 2^-10 off the samples. Over every triangle of the table
    // and crossing parameters in [m, 1 - m] (taken independently, which covers more than
    // samples can produce), 2 * area / longest^2 stays above 0.7 m, far above the 1e-6 that
    // metrics.h calls degenerate. Zero only at parameters 0 or 1: a triangle of crossings on
    // three different edges of a cube is flat only with a corner on a sample.
    const double m = std::ldexp(1.0, -10);
    const double params[] = {m, 2 * m, 0.01, 0.1, 0.3, 0.5, 0.7, 0.9, 0.99, 1 - 2 * m, 1 - m};
    double flattest = 1;
    for (unsigned mask = 0; mask < 256; ++mask) {
        const MarchingCubesCase& c = marching_cubes_case(mask);
        for (int t = 0; t < c.triangle_count; ++t) {
            const auto point = [&](int k, double along) {
                const int e = c.triangles[t][k];
                const glm::dvec3 lo = corner_point(cube_edge_corner(e, 0));
                return lo + along * (corner_point(cube_edge_corner(e, 1)) - lo);
            };
            for (double ta : params)
                for (double tb : params)
                    for (double tc : params) {
                        const glm::dvec3 a = point(0, ta), b = point(1, tb), d = point(2, tc);
                        const double longest =
                            std::max({glm::length(b - a), glm::length(d - b), glm::length(a - d)});
                        flattest = std::min(flattest, glm::length(glm::cross(b - a, d - a)) /
                                                          (longest * longest));
                    }
        }
    }
    EXPECT_GT(flattest, 0.7 * m);
    EXPECT_GT(flattest, 100 * kDegenerateHeightRatio);
}

// ---------------------------------------------------------------------------------------------
// Single cells, exhaustively.

TEST(MarchingCubes, EveryCaseAloneIsClosedOrientedAndOutward) {
    for (unsigned mask = 1; mask < 256; ++mask) {
        const Volume v = padded_cell(mask, {1, 1, 1, 1, 1, 1, 1, 1});
        const Mesh m = mc(v, 0.5f);
        const std::string what = "case " + std::to_string(mask);
        const Topology topo = topology(m);
        EXPECT_TRUE(topo.manifold) << what;
        EXPECT_TRUE(topo.oriented) << what;
        EXPECT_GT(enclosed_volume(m), 0.0) << what;
        EXPECT_EQ(m.vertex_count(), crossed_edges(v, 0.5f)) << what;
        EXPECT_TRUE(every_vertex_referenced(m)) << what;
        for (std::size_t t = 0; t < m.triangle_count(); ++t) EXPECT_GT(triangle_area(m, t), 0.0);
    }
}

TEST(MarchingCubes, EveryCellWithSamplesAtIsoIsSoundAtAnyCoordinate) {
    // All 3^8 corner states (outside 0, exactly at iso 1, inside 2) of one cell in a padded
    // grid, near the origin and near x = 511 (where floats are 2^-15 apart): a sample at iso is
    // infinitesimally inside, so the mesh is the binary segmentation's, closed and manifold,
    // with its crossings 2^-10 off the sample and no degenerate triangle.
    const double margin = std::ldexp(1.0, -10);
    for (int x0 : {1, 510}) {
        double flattest = 1;
        for (int code = 0; code < 6561; ++code) {
            Volume v = make_volume({x0 + 3, 4, 4}, 0.0f);
            for (int c = 0, rest = code; c < 8; ++c, rest /= 3)
                v.samples[v.index(x0 + (c & 1), 1 + ((c >> 1) & 1), 1 + ((c >> 2) & 1))] =
                    float(rest % 3);
            const std::string what = "code " + std::to_string(code) + " at x " + std::to_string(x0);
            ASSERT_EQ(surface_fault(v, 1.0f), "") << what;
            const Mesh m = mc(v, 1.0f);
            if (m.indices.empty()) continue;
            ASSERT_TRUE(topology(m).manifold) << what;
            ASSERT_TRUE(every_vertex_referenced(m)) << what;
            flattest = std::min(flattest, flattest_triangle(m));
        }
        EXPECT_GT(flattest, 0.5 * margin) << x0;
    }
}

// ---------------------------------------------------------------------------------------------
// Random noise: closed, edge-manifold, consistently oriented, whatever the input.

TEST(MarchingCubes, RandomFloatNoiseIsClosedManifoldAndOriented) {
    std::mt19937 rng(12345);
    std::uniform_real_distribution<float> value(-1.0f, 1.0f);
    for (int i = 0; i < 2000; ++i) {
        const Volume v = random_volume(rng, -1.0f, value);
        const Mesh m = mc(v, 0.0f);
        const std::string what = "volume " + std::to_string(i);
        if (m.indices.empty()) continue;
        const Topology topo = topology(m);
        ASSERT_TRUE(topo.manifold) << what;
        ASSERT_TRUE(topo.oriented) << what;
        ASSERT_EQ(topo.euler % 2, 0) << what;
        ASSERT_EQ(m.vertex_count(), crossed_edges(v, 0.0f)) << what;
        ASSERT_TRUE(every_vertex_referenced(m)) << what;
        ASSERT_EQ(position_counts(m).size(), m.vertex_count()) << what << ": duplicate vertex";
    }
}

TEST(MarchingCubes, RowsWiderThanOneWordAreHandledAcrossWordBoundaries) {
    // The classification works on 64-sample words; cells straddle words at x = 63, 127, ...
    std::mt19937 rng(4242);
    std::uniform_real_distribution<float> value(-1.0f, 1.0f);
    for (int width : {64, 65, 127, 129, 200}) {
        Volume v = make_volume({width, 6, 5}, -1.0f);
        for (int z = 1; z + 1 < v.dims.z; ++z)
            for (int y = 1; y + 1 < v.dims.y; ++y)
                for (int x = 1; x + 1 < v.dims.x; ++x) v.samples[v.index(x, y, z)] = value(rng);
        const Mesh m = mc(v, 0.0f);
        const Topology topo = topology(m);
        EXPECT_TRUE(topo.manifold) << width;
        EXPECT_TRUE(topo.oriented) << width;
        EXPECT_EQ(m.vertex_count(), crossed_edges(v, 0.0f)) << width;
        EXPECT_TRUE(every_vertex_referenced(m)) << width;
    }
    // A box from x = 60 to 130 (71 samples) by 2 by 2: exact counts as in
    // FilledBoxHasAnalyticCounts.
    Volume box = make_volume({150, 6, 6}, 0.0f);
    for (int z = 2; z < 4; ++z)
        for (int y = 2; y < 4; ++y)
            for (int x = 60; x <= 130; ++x) box.samples[box.index(x, y, z)] = 1.0f;
    const Mesh m = mc(box, 0.5f);
    EXPECT_EQ(m.vertex_count(), 2u * (71 * 2 + 2 * 2 + 2 * 71));
    EXPECT_EQ(m.triangle_count(), 4u * (70 + 1 + 70) + 8u * (70 + 1 + 1) + 8u);
    EXPECT_TRUE(topology(m).manifold);
}

TEST(MarchingCubes, IntegerNoiseWithSamplesAtIsoIsSound) {
    // Integer values at an integer iso, as in CT/MR volumes: values 0, 1, 2 at iso 1 (a third
    // or 60% of the samples exactly at iso) and 0..9 at iso 2..7. Padded volumes must be closed;
    // unpadded ones reach the border and may be open only there. Both inside rules.
    std::mt19937 rng(777);
    std::size_t at_iso = 0, samples = 0, triangles = 0;
    for (int i = 0; i < 3000; ++i) {
        const bool narrow = i % 3 != 2;
        const double p = i % 2 == 0 ? 1.0 / 3.0 : 0.6;
        std::discrete_distribution<int> narrow_value({(1 - p) / 2, p, (1 - p) / 2});
        std::uniform_int_distribution<int> wide_value(0, 9);
        const float iso = narrow ? 1.0f : float(2 + i % 6);
        const InsideIs rule = i % 5 == 4 ? InsideIs::Below : InsideIs::Above;
        const float outside = rule == InsideIs::Above ? -1.0f : 10.0f;
        const bool padded = i % 4 != 3;
        const Volume v = random_volume(
            rng, outside,
            [&](std::mt19937& r) { return float(narrow ? narrow_value(r) : wide_value(r)); },
            padded);
        const std::string what = "volume " + std::to_string(i);
        ASSERT_EQ(surface_fault(v, iso, rule), "") << what;
        if (padded && crossed_edges(v, iso, rule) > 0) {
            ASSERT_TRUE(topology(mc(v, iso, rule)).manifold) << what;
        }
        at_iso += std::size_t(std::count(v.samples.begin(), v.samples.end(), iso));
        samples += v.samples.size();
        triangles += mc(v, iso, rule).triangle_count();
    }
    std::printf("[          ] integer noise: %zu triangles, %zu of %zu samples at iso\n", triangles,
                at_iso, samples);
    EXPECT_GT(at_iso * 10, samples); // the case this test is about: over 10% at iso
}

TEST(MarchingCubes, InsideBelowOnNegatedValuesGivesTheSameMesh) {
    std::mt19937 rng(99);
    std::discrete_distribution<int> state({1, 1, 1});
    for (int i = 0; i < 200; ++i) {
        const Volume v = random_volume(rng, 0.0f, [&](std::mt19937& r) { return float(state(r)); });
        Volume negated = v;
        for (float& s : negated.samples) s = -s;
        const Mesh above = mc(v, 1.0f, InsideIs::Above);
        const Mesh below = mc(negated, -1.0f, InsideIs::Below);
        ASSERT_EQ(above.indices, below.indices) << i;
        ASSERT_EQ(above.positions, below.positions) << i;
    }
}

// ---------------------------------------------------------------------------------------------
// Samples exactly at iso: infinitesimally inside, crossings kept off them.

TEST(MarchingCubes, PlaneThroughSamplesHasNoZeroAreaTriangles) {
    const Phantom plane = make_plane_phantom(64, {1, 2, 3}, glm::vec3(31.5f));
    const std::size_t at_iso =
        std::size_t(std::count(plane.volume.samples.begin(), plane.volume.samples.end(), 0.0f));
    ASSERT_GT(at_iso, 300u); // the case this test is about
    const Mesh m = mc(plane.volume, 0.0f);
    ASSERT_GT(m.triangle_count(), 1000u);

    const glm::dvec3 normal(1, 2, 3);
    for (std::size_t t = 0; t < m.triangle_count(); ++t) {
        ASSERT_GT(triangle_area(m, t), 0.0) << t;
        ASSERT_GT(glm::dot(triangle_normal(m, t), normal), 0.0) << t; // outward: along +n
    }
    EXPECT_EQ(quality_stats(m).degenerate, 0u);
    EXPECT_EQ(pinched_vertices(m), 0u);
    // Off the plane by at most the margin (crossings of samples on the plane).
    for (const glm::vec3& p : m.positions)
        ASSERT_LE(plane.reference_distance(p), 1.0f / 1024 + 1e-5f);
    EXPECT_TRUE(every_vertex_referenced(m));
    EXPECT_EQ(position_counts(m).size(), m.vertex_count()) << "duplicate vertices";

    // Every edge away from the volume border is shared by two triangles, once in each direction.
    std::map<std::pair<std::uint32_t, std::uint32_t>, int> directed;
    for (std::size_t t = 0; t < m.triangle_count(); ++t)
        for (int k = 0; k < 3; ++k)
            ++directed[{m.indices[3 * t + k], m.indices[3 * t + (k + 1) % 3]}];
    const auto on_border = [&](std::uint32_t a, std::uint32_t b) {
        for (int axis = 0; axis < 3; ++axis)
            for (float side : {0.0f, 63.0f})
                if (m.positions[a][axis] == side && m.positions[b][axis] == side) return true;
        return false;
    };
    std::size_t interior = 0;
    for (const auto& [edge, count] : directed) {
        ASSERT_EQ(count, 1);
        if (on_border(edge.first, edge.second)) continue;
        ++interior;
        ASSERT_EQ(directed.count({edge.second, edge.first}), 1u) << "open interior edge";
    }
    EXPECT_GT(interior, 1000u);
}

TEST(MarchingCubes, BoxOfSamplesAtIsoHugsTheSampleBox) {
    // Every inside sample exactly at iso: the surface is the binary block's (counts as in
    // FilledBoxHasAnalyticCounts for a 4 x 4 x 4 block), 2^-10 outside the box through the
    // samples.
    Volume v = make_volume({8, 8, 8}, 0.0f);
    for (int z = 2; z <= 5; ++z)
        for (int y = 2; y <= 5; ++y)
            for (int x = 2; x <= 5; ++x) v.samples[v.index(x, y, z)] = 1.0f;
    const Mesh m = mc(v, 1.0f);
    EXPECT_EQ(m.vertex_count(), 96u);
    EXPECT_EQ(m.triangle_count(), 188u);
    const Topology topo = topology(m);
    EXPECT_TRUE(topo.manifold);
    EXPECT_TRUE(topo.oriented);
    EXPECT_EQ(topo.euler, 2);
    EXPECT_EQ(quality_stats(m).degenerate, 0u);
    const float margin = 1.0f / 1024;
    for (const glm::vec3& p : m.positions) {
        const glm::vec3 outside = glm::max(glm::vec3(2.0f) - p, p - glm::vec3(5.0f));
        EXPECT_EQ(std::max({outside.x, outside.y, outside.z}), margin); // exactly, in float
    }
    EXPECT_GT(enclosed_volume(m), 27.0);
    EXPECT_LT(enclosed_volume(m), 27.0 + 60.0 * margin); // 54 face cells, thin chamfers
}

TEST(MarchingCubes, IsolatedSampleAtIsoIsATinyOctahedron) {
    // Like the segmentation's single inside voxel, not nothing: a closed component that the
    // SurfaceNet of the same segmentation has too.
    Volume v = make_volume({3, 3, 3}, 0.0f);
    v.samples[v.index(1, 1, 1)] = 1.0f;
    const Mesh m = mc(v, 1.0f);
    ASSERT_EQ(m.vertex_count(), 6u);
    ASSERT_EQ(m.triangle_count(), 8u);
    for (const glm::vec3& p : m.positions) EXPECT_EQ(glm::length(p - glm::vec3(1.0f)), 1.0f / 1024);
    const Topology topo = topology(m);
    EXPECT_TRUE(topo.manifold);
    EXPECT_EQ(topo.euler, 2);
    EXPECT_GT(enclosed_volume(m), 0.0);
    const QualityStats q = quality_stats(m);
    EXPECT_EQ(q.degenerate, 0u);
    EXPECT_GT(q.min, 0.99); // three crossings around one corner at iso: equilateral
}

TEST(MarchingCubes, PlateOneSampleThickAtIsoIsAThinClosedSlab) {
    // A plate of samples at iso, outside on both sides: one closed slab 2^-10 thick on each side
    // of the samples, not two surfaces through the same points.
    Volume v = make_volume({7, 7, 5}, 0.0f);
    for (int y = 1; y <= 5; ++y)
        for (int x = 1; x <= 5; ++x) v.samples[v.index(x, y, 2)] = 1.0f;
    const Mesh m = mc(v, 1.0f);
    const Topology topo = topology(m);
    EXPECT_TRUE(topo.manifold);
    EXPECT_TRUE(topo.oriented);
    EXPECT_EQ(topo.euler, 2);
    EXPECT_EQ(quality_stats(m).degenerate, 0u);
    EXPECT_EQ(pinched_vertices(m), 0u);
    for (const glm::vec3& p : m.positions) EXPECT_LE(std::abs(p.z - 2.0f), 1.0f / 1024);
    EXPECT_GT(enclosed_volume(m), 0.0);
    EXPECT_LT(enclosed_volume(m), 25.0 * 2.0 / 1024);
}

TEST(MarchingCubes, CrossingsKeepTheirMarginAtLargeCoordinates) {
    // Isolated samples at iso along a long row: tiny octahedra of equilateral triangles whose
    // vertices sit exactly `margin` off the sample, 2^-10 while coordinates stay below 8192
    // and two float steps of the largest coordinate beyond.
    struct Row {
        int length;
        std::vector<int> at_iso;
        float margin;
    };
    const Row rows[] = {{600, {1, 254, 256, 510, 512, 597}, 1.0f / 1024},
                        {17000, {8190, 8192, 16382, 16384, 16997}, 1.0f / 256}};
    for (const Row& row : rows) {
        for (int axis = 0; axis < 3; ++axis) {
            glm::ivec3 dims(3);
            dims[axis] = row.length;
            Volume v = make_volume(dims, 0.0f);
            for (int at : row.at_iso) {
                glm::ivec3 p(1);
                p[axis] = at;
                v.samples[v.index(p.x, p.y, p.z)] = 1.0f;
            }
            const std::string what = std::to_string(row.length) + " along " + std::to_string(axis);
            ASSERT_EQ(surface_fault(v, 1.0f), "") << what;
            const Mesh m = mc(v, 1.0f);
            ASSERT_EQ(m.triangle_count(), 8 * row.at_iso.size()) << what;
            EXPECT_GT(quality_stats(m).min, 0.99) << what;
            for (const glm::vec3& p : m.positions) {
                const glm::vec3 sample = glm::round(p);
                EXPECT_EQ(glm::length(p - sample), row.margin) << what;
                EXPECT_EQ(v.at(int(sample.x), int(sample.y), int(sample.z)), 1.0f) << what;
            }
        }
    }
}

// ---------------------------------------------------------------------------------------------
// Exact counts.

TEST(MarchingCubes, EmptyAndFullVolumesGiveNothing) {
    for (float value : {0.0f, 2.0f}) {
        const Mesh m = mc(make_volume({6, 5, 4}, value), 1.0f);
        EXPECT_EQ(m.triangle_count(), 0u);
        EXPECT_EQ(m.vertex_count(), 0u);
    }
    EXPECT_EQ(mc(make_volume({1, 5, 5}, 2.0f), 1.0f).triangle_count(), 0u); // no cells
    EXPECT_EQ(mc(Volume{}, 1.0f).triangle_count(), 0u);
}

TEST(MarchingCubes, SingleInsideVoxelGivesAnOctahedron) {
    Volume v = make_volume({3, 3, 3}, 0.0f);
    v.samples[v.index(1, 1, 1)] = 1.0f;
    const Mesh m = mc(v, 0.5f);
    ASSERT_EQ(m.vertex_count(), 6u);
    ASSERT_EQ(m.triangle_count(), 8u);
    for (const glm::vec3& p : m.positions) {
        const glm::vec3 d = glm::abs(p - glm::vec3(1.0f));
        EXPECT_FLOAT_EQ(d.x + d.y + d.z, 0.5f); // one axis off the centre by 0.5
        EXPECT_FLOAT_EQ(std::max({d.x, d.y, d.z}), 0.5f);
    }
    const Topology topo = topology(m);
    EXPECT_TRUE(topo.manifold);
    EXPECT_TRUE(topo.oriented);
    EXPECT_EQ(topo.euler, 2);
    EXPECT_NEAR(enclosed_volume(m), 4.0 / 3.0 * 0.125, 1e-6); // octahedron of half-diagonal 0.5
}

TEST(MarchingCubes, FilledBoxHasAnalyticCounts) {
    // Inside samples: an a x b x c block. Vertices: one per outward edge of each boundary
    // sample, 2 (ab + bc + ca). Triangles: 2 per cell across a face ((a-1)(b-1) per face pair
    // side), 2 per cell along a box edge (a-1 per edge, 4 edges per axis), 1 per corner cell.
    const int a = 3, b = 4, c = 5;
    Volume v = make_volume({a + 4, b + 4, c + 4}, 0.0f);
    for (int z = 2; z < 2 + c; ++z)
        for (int y = 2; y < 2 + b; ++y)
            for (int x = 2; x < 2 + a; ++x) v.samples[v.index(x, y, z)] = 1.0f;
    const Mesh m = mc(v, 0.5f);
    const std::size_t faces = 2 * ((a - 1) * (b - 1) + (b - 1) * (c - 1) + (c - 1) * (a - 1));
    const std::size_t edges = 4 * ((a - 1) + (b - 1) + (c - 1));
    EXPECT_EQ(m.vertex_count(), std::size_t(2 * (a * b + b * c + c * a))); // 94
    EXPECT_EQ(m.triangle_count(), 2 * faces + 2 * edges + 8);              // 184
    const Topology topo = topology(m);
    EXPECT_TRUE(topo.manifold);
    EXPECT_TRUE(topo.oriented);
    EXPECT_EQ(topo.euler, 2);
    // Volume: the block grown by 0.5, less the chamfers along its edges and at its corners.
    const double core = (a - 1) * (b - 1) * (c - 1);
    const double slabs = 0.5 * double(faces);
    const double edge_prisms = 0.125 * double(edges); // cross-section: right triangle, legs 0.5
    const double corners = 8.0 / 48.0;                // tetrahedra with legs 0.5
    EXPECT_NEAR(enclosed_volume(m), core + slabs + edge_prisms + corners, 1e-6);
}

// ---------------------------------------------------------------------------------------------
// Phantoms.

TEST(MarchingCubes, SphereIsAccurateClosedAndOutward) {
    const Phantom sphere = make_phantom("sphere", 64);
    const Mesh m = mc(sphere.volume, sphere.iso);
    float worst = 0;
    for (const glm::vec3& p : m.positions) worst = std::max(worst, sphere.reference_distance(p));
    EXPECT_LT(worst, 0.01f);
    const Topology topo = topology(m);
    EXPECT_TRUE(topo.manifold);
    EXPECT_TRUE(topo.oriented);
    EXPECT_EQ(topo.euler, 2);
    const double volume = enclosed_volume(m);
    EXPECT_GT(volume, 0.0);
    EXPECT_NEAR(volume / sphere.reference_volume, 1.0, 0.005);
    EXPECT_EQ(quality_stats(m).degenerate, 0u);
}

TEST(MarchingCubes, InsideBelowOnNegatedSphereIsTheSameOutwardSurface) {
    const Phantom sphere = make_phantom("sphere", 32);
    Volume negated = sphere.volume;
    for (float& s : negated.samples) s = -s;
    const Mesh above = mc(sphere.volume, 0.0f, InsideIs::Above);
    const Mesh below = mc(negated, 0.0f, InsideIs::Below);
    EXPECT_EQ(above.positions, below.positions);
    EXPECT_EQ(above.indices, below.indices);
    EXPECT_GT(enclosed_volume(below), 0.0);
}

TEST(MarchingCubes, TwoSpheresHaveNoNearZeroAreaTriangles) {
    // The crease where the spheres meet passes close to samples: crossings there are kept off
    // the samples, so no triangle is flat.
    const Phantom spheres = make_phantom("two-spheres", 64);
    EXPECT_EQ(surface_fault(spheres.volume, spheres.iso), "");
    const Mesh m = mc(spheres.volume, spheres.iso);
    EXPECT_TRUE(topology(m).manifold);
    EXPECT_EQ(topology(m).euler, 2);
    EXPECT_GT(flattest_triangle(m), 100 * kDegenerateHeightRatio);
}

TEST(MarchingCubes, TorusHasGenusOne) {
    const Phantom torus = make_phantom("torus", 64);
    const Mesh m = mc(torus.volume, torus.iso);
    const Topology topo = topology(m);
    EXPECT_TRUE(topo.manifold);
    EXPECT_TRUE(topo.oriented);
    EXPECT_EQ(topo.euler, 0);
    EXPECT_NEAR(enclosed_volume(m) / torus.reference_volume, 1.0, 0.01);
}

// ---------------------------------------------------------------------------------------------
// Contract details.

TEST(MarchingCubes, ReportsProgressAndCancels) {
    const Phantom sphere = make_phantom("sphere", 16);
    std::vector<float> reported;
    Progress progress;
    progress.report = [&](float f) { reported.push_back(f); };
    const Mesh m = marching_cubes(sphere.volume, {}, progress);
    ASSERT_GE(reported.size(), 16u); // about once per slice and pass
    EXPECT_TRUE(std::is_sorted(reported.begin(), reported.end()));
    EXPECT_EQ(reported.front(), 0.0f);
    EXPECT_EQ(reported.back(), 1.0f);

    std::stop_source stop;
    stop.request_stop();
    Progress cancelled;
    cancelled.stop = stop.get_token();
    EXPECT_THROW(marching_cubes(sphere.volume, {}, cancelled), Cancelled);
}

TEST(MarchingCubes, RejectsBadInput) {
    Volume v = make_volume({4, 4, 4}, 0.0f);
    v.samples.pop_back();
    EXPECT_THROW(mc(v, 0.0f), std::invalid_argument);
    EXPECT_THROW(mc(make_volume({4, 4, 4}, 0.0f), std::nanf("")), std::invalid_argument);
}

TEST(MarchingCubes, NaNSamplesAreOutsideAndNonFiniteValuesGiveFinitePositions) {
    Volume v = make_volume({5, 5, 5}, 0.0f);
    v.samples[v.index(2, 2, 2)] = std::numeric_limits<float>::infinity();
    v.samples[v.index(2, 2, 1)] = std::nanf("");
    v.samples[v.index(2, 3, 2)] = 1.0f;
    const Mesh m = mc(v, 0.5f);
    expect_closed_oriented(m, "non-finite");
    for (const glm::vec3& p : m.positions) EXPECT_TRUE(std::isfinite(p.x + p.y + p.z));
}

// ---------------------------------------------------------------------------------------------
// Real CT/MRI volumes at their suggested integer iso values (SOURCES.md of the data), where
// many samples lie exactly at iso. Skipped when the volumes are absent.

namespace {

using test::data_file;

void expect_sound(const Volume& v, float iso, const std::string& what) {
    EXPECT_EQ(surface_fault(v, iso), "") << what;
    const Mesh m = mc(v, iso);
    EXPECT_GT(m.triangle_count(), 10000u) << what;
    const std::size_t at_iso = std::size_t(std::count(v.samples.begin(), v.samples.end(), iso));
    std::printf("[          ] %s at %g: %zu triangles, %zu samples at iso\n", what.c_str(), iso,
                m.triangle_count(), at_iso);
}

} // namespace

TEST(MarchingCubesRealVolumes, NoDegenerateTriangleOrPinchedVertexAtIntegerIsoValues) {
    SNERT_REQUIRE_DATA();
    expect_sound(load_volume(data_file("FLAIR.nrrd")), 40.0f, "FLAIR.nrrd");
    expect_sound(load_volume(data_file("HeadMRVolume.mhd")), 40.0f, "HeadMRVolume.mhd");
    expect_sound(load_volume(data_file("carotid.vtk")), 190.0f, "carotid.vtk");
    RawOptions raw;
    raw.dims = {64, 64, 93};
    raw.type = ScalarType::UInt16;
    const Volume headsq = load_raw(data_file("headsq/quarter.1"), raw);
    expect_sound(headsq, 1150.0f, "headsq");
    expect_sound(headsq, 500.0f, "headsq");
}
