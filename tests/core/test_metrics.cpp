// Metrics against hand-computed values: triangle shapes, smoothness of known solids, topology
// counts, area and volume, accuracy, and the grid-accelerated mesh distance against brute force.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <map>
#include <random>
#include <stdexcept>
#include <string>
#include <thread>
#include <tuple>
#include <utility>

#include "core/metrics.h"
#include "support/test_meshes.h"

namespace snert {
namespace {

using namespace snert::test;

constexpr double kPi = 3.14159265358979323846;

// --- Triangle shape -------------------------------------------------------------------------

TEST(TriangleShape, Equilateral) {
    const TriangleShape s = triangle_shape({0, 0, 0}, {2, 0, 0}, {1, std::sqrt(3.0f), 0});
    EXPECT_NEAR(s.quality, 1.0, 1e-6);
    EXPECT_NEAR(s.quality60, 1.0, 1e-6);
    EXPECT_NEAR(s.radius_ratio, 1.0, 1e-6);
    EXPECT_NEAR(s.min_angle, 60.0, 1e-4);
    EXPECT_NEAR(s.area, std::sqrt(3.0), 1e-6);
    EXPECT_FALSE(s.degenerate);
}

TEST(TriangleShape, RightIsosceles) {
    const TriangleShape s = triangle_shape({0, 0, 0}, {1, 0, 0}, {0, 1, 0});
    EXPECT_NEAR(s.quality, 0.5, 1e-6);    // 45 / 90
    EXPECT_NEAR(s.quality60, 0.75, 1e-6); // 45 / 60
    EXPECT_NEAR(s.radius_ratio, 2.0 * (std::sqrt(2.0) - 1.0), 1e-6);
    EXPECT_NEAR(s.min_angle, 45.0, 1e-4);
    EXPECT_NEAR(s.area, 0.5, 1e-7);
}

TEST(TriangleShape, ThirtySixtyNinety) {
    // Sides 1, sqrt 3, 2; angles 30, 60, 90; 2r/R = 8 A^2 / (s abc) = sqrt 3 - 1.
    const TriangleShape s = triangle_shape({0, 0, 0}, {std::sqrt(3.0f), 0, 0}, {0, 1, 0});
    EXPECT_NEAR(s.quality, 1.0 / 3.0, 1e-6);
    EXPECT_NEAR(s.quality60, 0.5, 1e-6);
    EXPECT_NEAR(s.radius_ratio, std::sqrt(3.0) - 1.0, 1e-6);
    EXPECT_NEAR(s.min_angle, 30.0, 1e-4);
    EXPECT_NEAR(s.area, std::sqrt(3.0) / 2.0, 1e-6);
}

TEST(TriangleShape, IndependentOfOrderScaleAndPosition) {
    const glm::vec3 a{0.3f, -1.2f, 2.0f}, b{1.7f, 0.4f, -0.5f}, c{-0.8f, 2.1f, 0.9f};
    const TriangleShape s = triangle_shape(a, b, c);
    for (const TriangleShape& t :
         {triangle_shape(b, c, a), triangle_shape(c, b, a),
          triangle_shape(a * 1000.0f + 50.0f, b * 1000.0f + 50.0f, c * 1000.0f + 50.0f)}) {
        EXPECT_NEAR(t.quality, s.quality, 1e-5);
        EXPECT_NEAR(t.quality60, s.quality60, 1e-5);
        EXPECT_NEAR(t.radius_ratio, s.radius_ratio, 1e-5);
        EXPECT_NEAR(t.min_angle, s.min_angle, 1e-3);
    }
    EXPECT_GT(s.quality, 0.0f);
    EXPECT_LT(s.quality, 1.0f);
}

TEST(TriangleShape, DegenerateGivesZeroNotNaN) {
    for (const auto& [a, b, c] :
         {std::tuple{glm::vec3(0), glm::vec3(1, 0, 0), glm::vec3(2, 0, 0)},
          std::tuple{glm::vec3(1), glm::vec3(1), glm::vec3(1)},
          std::tuple{glm::vec3(0), glm::vec3(0), glm::vec3(0, 1, 0)},
          std::tuple{glm::vec3(0), glm::vec3(1, 0, 0), glm::vec3(0.5f, NAN, 0)}}) {
        const TriangleShape s = triangle_shape(a, b, c);
        EXPECT_TRUE(s.degenerate);
        EXPECT_EQ(s.quality, 0.0f);
        EXPECT_EQ(s.quality60, 0.0f);
        EXPECT_EQ(s.radius_ratio, 0.0f);
        EXPECT_EQ(s.min_angle, 0.0f);
        EXPECT_EQ(s.area, 0.0f);
    }
}

TEST(TriangleShape, DegenerateThresholdIsRelative) {
    // Height / longest edge of 1e-7 is below kDegenerateHeightRatio, 1e-4 is a real sliver.
    const TriangleShape flat = triangle_shape({0, 0, 0}, {1000, 0, 0}, {500, 1e-4f, 0});
    EXPECT_TRUE(flat.degenerate);
    EXPECT_GT(flat.area, 0.0f);
    const TriangleShape sliver = triangle_shape({0, 0, 0}, {1, 0, 0}, {0.5f, 1e-4f, 0});
    EXPECT_FALSE(sliver.degenerate);
    EXPECT_GT(sliver.quality, 0.0f);
    // Smallest angle atan(2e-4) in degrees, the largest about 180.
    EXPECT_NEAR(sliver.min_angle, std::atan(2e-4) * 180.0 / kPi, 1e-5);
}

// --- Quality statistics ---------------------------------------------------------------------

TEST(QualityStats, MixOfKnownTriangles) {
    Mesh m;
    m.positions = {{0, 0, 0}, {2, 0, 0}, {1, std::sqrt(3.0f), 0}, // equilateral
                   {0, 0, 5}, {1, 0, 5}, {0, 1, 5},               // right isosceles
                   {0, 0, 9}, {1, 0, 9}, {2, 0, 9}};              // degenerate
    m.indices = {0, 1, 2, 3, 4, 5, 6, 7, 8};
    const QualityStats s = quality_stats(m);
    EXPECT_NEAR(s.mean, 1.5 / 3.0, 1e-6);
    EXPECT_EQ(s.min, 0.0);
    EXPECT_NEAR(s.quality60_mean, 1.75 / 3.0, 1e-6);
    EXPECT_NEAR(s.radius_ratio_mean, (1.0 + 2.0 * (std::sqrt(2.0) - 1.0)) / 3.0, 1e-6);
    EXPECT_EQ(s.min_angle_min, 0.0);
    EXPECT_EQ(s.degenerate, 1u);
    EXPECT_EQ(s.slivers, 1u); // the degenerate one
    std::array<std::size_t, kQualityBins> expected{};
    expected[0] = 1;                // q = 0
    expected[kQualityBins / 2] = 1; // q = 0.5 opens the upper half
    expected[kQualityBins - 1] = 1; // q = 1 is in the last, closed bin
    EXPECT_EQ(s.histogram, expected);

    const std::vector<float> q = triangle_quality(m);
    ASSERT_EQ(q.size(), 3u);
    EXPECT_NEAR(q[0], 1.0f, 1e-6);
    EXPECT_NEAR(q[1], 0.5f, 1e-6);
    EXPECT_EQ(q[2], 0.0f);
}

// Each measure per triangle, and its summary: the same means and bins as quality_stats.
TEST(TriangleMeasures, PerTriangleAndSummarised) {
    Mesh m;
    m.positions = {{0, 0, 0}, {2, 0, 0}, {1, std::sqrt(3.0f), 0}, // equilateral
                   {0, 0, 5}, {1, 0, 5}, {0, 1, 5},               // right isosceles
                   {0, 0, 9}, {1, 0, 9}, {2, 0, 9}};              // degenerate
    m.indices = {0, 1, 2, 3, 4, 5, 6, 7, 8};
    const TriangleMeasures t = triangle_measures(m);
    EXPECT_EQ(t.quality, triangle_quality(m));
    ASSERT_EQ(t.quality60.size(), 3u);
    EXPECT_NEAR(t.quality60[1], 0.75f, 1e-6);
    EXPECT_NEAR(t.radius_ratio[1], 2.0 * (std::sqrt(2.0) - 1.0), 1e-6);
    EXPECT_EQ(t.radius_ratio[2], 0.0f);
    EXPECT_EQ(t.of(ShapeMeasure::Quality60).data(), t.quality60.data());

    const QualityStats s = quality_stats(m);
    EXPECT_NEAR(summarize_measure(t.of(ShapeMeasure::Quality)).mean, s.mean, 1e-6);
    EXPECT_EQ(summarize_measure(t.of(ShapeMeasure::Quality)).histogram, s.histogram);
    const MeasureSummary q60 = summarize_measure(t.of(ShapeMeasure::Quality60));
    EXPECT_NEAR(q60.mean, s.quality60_mean, 1e-6);
    EXPECT_EQ(q60.histogram[0], 1u);
    EXPECT_EQ(q60.histogram[15], 1u); // 0.75
    EXPECT_EQ(q60.histogram[kQualityBins - 1], 1u);
    EXPECT_NEAR(summarize_measure(t.of(ShapeMeasure::RadiusRatio)).mean, s.radius_ratio_mean, 1e-6);
    EXPECT_EQ(summarize_measure({}).mean, 0.0);
}

TEST(QualityStats, SliversBelowOneTenth) {
    // Isosceles needles with apex angle 2 atan(w): q = apex / base angle, about 4 w / pi for
    // small w. w = 0.07 gives q = 0.09 (a sliver), w = 0.09 gives q = 0.116 (not one).
    Mesh m;
    for (float w : {0.07f, 0.09f}) {
        const std::uint32_t base = std::uint32_t(m.positions.size());
        m.positions.insert(m.positions.end(), {{0, -w, 0}, {1, 0, 0}, {0, w, 0}});
        m.indices.insert(m.indices.end(), {base, base + 1, base + 2});
    }
    const QualityStats s = quality_stats(m);
    EXPECT_EQ(s.slivers, 1u);
    EXPECT_EQ(s.degenerate, 0u);
    EXPECT_NEAR(s.min_angle_min, 2.0 * std::atan(0.07) * 180.0 / kPi, 1e-4);
}

TEST(QualityStats, EmptyMeshIsAllZero) {
    const QualityStats s = quality_stats(Mesh{});
    EXPECT_EQ(s.mean, 0.0);
    EXPECT_EQ(s.min, 0.0);
    EXPECT_EQ(s.degenerate, 0u);
    EXPECT_TRUE(triangle_quality(Mesh{}).empty());
}

TEST(QualityStats, LargeGridOverManyChunks) {
    // 2 * 130^2 = 33800 right isosceles triangles: more than one parallel chunk.
    const Mesh grid = flat_grid(130);
    const QualityStats s = quality_stats(grid);
    EXPECT_NEAR(s.mean, 0.5, 1e-9);
    EXPECT_NEAR(s.min, 0.5, 1e-6);
    EXPECT_NEAR(s.min_angle_min, 45.0, 1e-4);
    EXPECT_EQ(s.degenerate, 0u);
    EXPECT_EQ(s.histogram[kQualityBins / 2], grid.triangle_count());
}

TEST(QualityStats, RejectsBadIndices) {
    Mesh m;
    m.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
    m.indices = {0, 1, 3};
    EXPECT_THROW(quality_stats(m), std::invalid_argument);
    m.indices = {0, 1};
    EXPECT_THROW(topology(m), std::invalid_argument);
}

// The first bad index wherever it lies in its block of the scan (the first, the last, one past
// a block's end, the mesh's last), none when all name vertices; the largest in the message.
TEST(MeshIndices, FirstOutOfRangeWhereverItLies) {
    Mesh m = test::icosphere(3); // 1280 triangles: indices over several blocks
    ASSERT_GT(m.indices.size(), 3000u);
    EXPECT_FALSE(first_index_out_of_range(m).has_value());
    const auto vertices = std::uint32_t(m.positions.size());
    for (const std::size_t at : {std::size_t(0), std::size_t(1023), std::size_t(1024),
                                 std::size_t(2049), m.indices.size() - 1}) {
        Mesh bad = m;
        bad.indices[at] = vertices + 7;
        bad.indices[m.indices.size() - 1 - at / 2] = vertices; // a second, later or the same
        const std::uint32_t first = at <= m.indices.size() - 1 - at / 2
                                        ? bad.indices[at]
                                        : bad.indices[m.indices.size() - 1 - at / 2];
        EXPECT_EQ(first_index_out_of_range(bad), first) << at;
        try {
            (void)topology(bad);
            ADD_FAILURE() << "no error for index " << at;
        } catch (const std::invalid_argument& e) {
            EXPECT_NE(std::string(e.what()).find(std::to_string(vertices + 7)), std::string::npos)
                << e.what();
        }
    }
    EXPECT_FALSE(first_index_out_of_range(Mesh{}).has_value());
}

// --- Smoothness -----------------------------------------------------------------------------

TEST(Smoothness, FlatGridIsZero) {
    EXPECT_NEAR(smoothness(flat_grid(6)), 0.0, 1e-12);
}

TEST(Smoothness, CubeCornersArePiOverTwo) {
    // Three right angles meet at each corner however the faces are split: 2 pi - 3 pi / 2.
    EXPECT_NEAR(smoothness(unit_cube()), kPi / 2.0, 1e-12);
    EXPECT_NEAR(smoothness(flipped(unit_cube())), kPi / 2.0, 1e-12);
}

TEST(Smoothness, RegularOctahedron) {
    // Four 60 degree angles at each vertex: 2 pi - 4 pi / 3.
    EXPECT_NEAR(smoothness(octahedron()), 2.0 * kPi / 3.0, 1e-6);
}

TEST(Smoothness, BoundaryVerticesAreLeftOut) {
    // A square pyramid without base: only the apex is interior.
    Mesh m;
    m.positions = {{0, 0, 1}, {1, 1, 0}, {-1, 1, 0}, {-1, -1, 0}, {1, -1, 0}};
    m.indices = {0, 1, 2, 0, 2, 3, 0, 3, 4, 0, 4, 1};
    const double apex_angle = std::acos(1.0 / 3.0); // between (1, 1, -1) and (-1, 1, -1)
    EXPECT_NEAR(smoothness(m), std::abs(2.0 * kPi - 4.0 * apex_angle), 1e-6);
    Mesh single;
    single.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
    single.indices = {0, 1, 2};
    EXPECT_EQ(smoothness(single), 0.0);
}

TEST(Smoothness, PinchedVertexIsLeftOut) {
    // Two cubes sharing one corner: that vertex has two fans (angle sum 3 pi) and is excluded,
    // so the mean stays pi / 2 (it would not if the pinch vertex counted).
    Mesh m = unit_cube();
    Mesh second = translated(unit_cube(), {1, 1, 1});
    for (std::uint32_t& i : second.indices) i = i == 0 ? 7 : i + 8;
    m.positions.insert(m.positions.end(), second.positions.begin(), second.positions.end());
    m.indices.insert(m.indices.end(), second.indices.begin(), second.indices.end());
    EXPECT_NEAR(smoothness(m), kPi / 2.0, 1e-12);
    const Topology t = topology(m);
    EXPECT_TRUE(t.watertight); // closed,
    EXPECT_FALSE(t.manifold);  // but not manifold at the shared corner
    EXPECT_EQ(t.nonmanifold_vertices, 1u);
    EXPECT_EQ(t.nonmanifold_edges, 0u);
    EXPECT_EQ(t.euler, 15 - 36 + 24);
}

TEST(Smoothness, ConvexSphereFollowsGaussBonnet) {
    // The angle defects of a closed genus-0 mesh sum to 4 pi; on a convex one they are all
    // positive, so the mean |defect| is exactly 4 pi / V.
    for (int level : {1, 3}) {
        const Mesh sphere = icosphere(level);
        EXPECT_NEAR(smoothness(sphere), 4.0 * kPi / double(sphere.vertex_count()), 1e-9);
    }
}

// --- Topology -------------------------------------------------------------------------------

TEST(Topology, ClosedCube) {
    const Topology t = topology(unit_cube());
    EXPECT_TRUE(t.watertight);
    EXPECT_TRUE(t.manifold);
    EXPECT_TRUE(t.oriented);
    EXPECT_EQ(t.euler, 2);
    EXPECT_EQ(t.boundary_edges, 0u);
    EXPECT_EQ(t.nonmanifold_edges, 0u);
    EXPECT_EQ(t.nonmanifold_vertices, 0u);
    EXPECT_EQ(t.collapsed_triangles, 0u);
    EXPECT_TRUE(topology(flipped(unit_cube())).oriented);
}

TEST(Topology, OneFlippedTriangleIsNotOriented) {
    Mesh m = unit_cube();
    std::swap(m.indices[1], m.indices[2]);
    const Topology t = topology(m);
    EXPECT_TRUE(t.watertight);
    EXPECT_TRUE(t.manifold);
    EXPECT_FALSE(t.oriented);
}

TEST(Topology, GridHasBoundary) {
    const int n = 7;
    const Topology t = topology(flat_grid(n));
    EXPECT_FALSE(t.watertight); // open,
    EXPECT_TRUE(t.manifold);    // but a manifold with boundary
    EXPECT_EQ(t.nonmanifold_vertices, 0u);
    EXPECT_TRUE(t.oriented);
    EXPECT_EQ(t.boundary_edges, std::size_t(4 * n));
    EXPECT_EQ(t.nonmanifold_edges, 0u);
    EXPECT_EQ(t.euler, 1); // a disc
}

TEST(Topology, LargeGridOverManyChunks) {
    // 201^2 vertices: several vertex chunks; 2 * 200^2 triangles.
    const Topology t = topology(flat_grid(200));
    EXPECT_EQ(t.boundary_edges, 800u);
    EXPECT_EQ(t.euler, 1);
    EXPECT_TRUE(t.oriented);
}

TEST(Topology, FinEdgeIsNonManifold) {
    Mesh m;
    m.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}};
    m.indices = {0, 1, 2, 1, 0, 3, 0, 1, 4};
    const Topology t = topology(m);
    EXPECT_EQ(t.nonmanifold_edges, 1u);
    EXPECT_EQ(t.nonmanifold_vertices, 2u); // both ends of the fin edge
    EXPECT_EQ(t.boundary_edges, 6u);
    EXPECT_FALSE(t.watertight);
    EXPECT_FALSE(t.manifold);
    EXPECT_FALSE(t.oriented); // edge 0-1 is used twice as 0 -> 1
    EXPECT_EQ(t.euler, 5 - 7 + 3);
}

TEST(Topology, CollapsedTriangle) {
    Mesh m = unit_cube();
    m.indices.insert(m.indices.end(), {0, 0, 1});
    const Topology t = topology(m);
    EXPECT_EQ(t.collapsed_triangles, 1u);
    EXPECT_FALSE(t.watertight);
    EXPECT_FALSE(t.manifold);
}

TEST(Topology, TwoDiscsTouchingAtAVertex) {
    // Two open fans sharing their centre: each edge is fine, the vertex is not.
    Mesh m;
    m.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {-1, 0, 1}, {0, -1, 1}};
    m.indices = {0, 1, 2, 0, 3, 4};
    const Topology t = topology(m);
    EXPECT_EQ(t.nonmanifold_edges, 0u);
    EXPECT_EQ(t.nonmanifold_vertices, 1u);
    EXPECT_FALSE(t.manifold);
}

TEST(Topology, BoundaryEdgesOffTheBorder) {
    // A 9 x 9 grid of squares in a 10^3 volume: its border lies on the volume's faces x, y = 0
    // and 9. Moved inwards by two voxels its border is a hole inside the volume.
    Mesh m = flat_grid(9);
    for (glm::vec3& p : m.positions) p.z = 5;
    EXPECT_EQ(boundary_edges_off_border(m, glm::ivec3(10), 1.0f), 0u);
    Mesh small = flat_grid(4);
    for (glm::vec3& p : small.positions) p += glm::vec3(2, 2, 5);
    EXPECT_EQ(boundary_edges_off_border(small, glm::ivec3(10), 1.0f), 16u);
    EXPECT_EQ(boundary_edges_off_border(unit_cube(), glm::ivec3(10), 1.0f), 0u); // closed
    // One triangle: its three edges, whether one or both ends are inside; none when all three
    // corners lie within the margin of a face.
    Mesh one{{{0.5f, 4, 4}, {5, 4, 4}, {5, 6, 4}}, {0, 1, 2}};
    EXPECT_EQ(boundary_edges_off_border(one, glm::ivec3(10), 1.0f), 3u);
    one.positions = {{0.5f, 4, 4}, {1, 5, 4}, {0, 6, 5}};
    EXPECT_EQ(boundary_edges_off_border(one, glm::ivec3(10), 1.0f), 0u);
    // A collapsed triangle on edge 0-1 uses it twice more (no self-loop 1-1): it is no longer a
    // boundary edge, the other two still are.
    one.positions = {{2, 4, 4}, {5, 4, 4}, {5, 6, 4}};
    one.indices = {0, 1, 2, 0, 1, 1};
    EXPECT_EQ(boundary_edges_off_border(one, glm::ivec3(10), 1.0f), 2u);
}

TEST(Topology, SphereAndOctahedron) {
    for (const Mesh& m : {octahedron(), icosphere(2)}) {
        const Topology t = topology(m);
        EXPECT_TRUE(t.watertight);
        EXPECT_TRUE(t.manifold);
        EXPECT_TRUE(t.oriented);
        EXPECT_EQ(t.euler, 2);
    }
}

TEST(Topology, UnreferencedVerticesDoNotCount) {
    Mesh m = unit_cube();
    m.positions.push_back({5, 5, 5});
    EXPECT_EQ(topology(m).euler, 2);
}

TEST(Topology, EmptyMesh) {
    const Topology t = topology(Mesh{});
    EXPECT_FALSE(t.watertight);
    EXPECT_FALSE(t.manifold);
    EXPECT_FALSE(t.oriented);
    EXPECT_EQ(t.euler, 0);
}

TEST(FanMeasures, AreTheSeparateMeasuresFromOneAnalysis) {
    // A sphere with holes inside the volume, a collapsed triangle and its world points under a
    // mirroring, shearing map: the topology, the border count and the world mesh's smoothness,
    // bit for bit, wound either way in the world (a mirror turns the winding inside out).
    Mesh mesh = test::phantom_mc("sphere", 20);
    std::mt19937 rng(5);
    std::uniform_real_distribution<float> jitter(-0.1f, 0.1f);
    for (glm::vec3& p : mesh.positions) p += glm::vec3(jitter(rng), jitter(rng), jitter(rng));
    Mesh holed;
    holed.positions = mesh.positions;
    for (std::size_t t = 0; t < mesh.triangle_count(); ++t)
        if (t % 37 != 0)
            holed.indices.insert(holed.indices.end(), mesh.indices.begin() + std::ptrdiff_t(3 * t),
                                 mesh.indices.begin() + std::ptrdiff_t(3 * t + 3));
    holed.indices.insert(holed.indices.end(),
                         {holed.indices[0], holed.indices[1], holed.indices[1]});
    const glm::mat3 map(glm::vec3(-0.7f, 0, 0), glm::vec3(0.2f, 1.1f, 0), glm::vec3(0, 0.1f, 2.3f));
    std::vector<glm::vec3> world;
    for (const glm::vec3& p : holed.positions) world.push_back(map * p + glm::vec3(5, -3, 1));
    const glm::ivec3 dims(20);

    const FanMeasures fans = fan_measures(holed, dims, world);
    const Topology t = topology(holed);
    EXPECT_EQ(fans.topology.boundary_edges, t.boundary_edges);
    EXPECT_GT(t.boundary_edges, 100u);
    EXPECT_EQ(fans.topology.nonmanifold_edges, t.nonmanifold_edges);
    EXPECT_EQ(fans.topology.nonmanifold_vertices, t.nonmanifold_vertices);
    EXPECT_EQ(fans.topology.collapsed_triangles, 1u);
    EXPECT_EQ(fans.topology.euler, t.euler);
    EXPECT_EQ(fans.topology.manifold, t.manifold);
    EXPECT_EQ(fans.topology.oriented, t.oriented);
    EXPECT_EQ(fans.topology.watertight, t.watertight);
    EXPECT_EQ(fans.boundary_edges_off_border, boundary_edges_off_border(holed, dims));
    EXPECT_GT(fans.boundary_edges_off_border, 100u);
    Mesh in_world{world, holed.indices};
    EXPECT_EQ(fans.smoothness, smoothness(in_world));
    for (std::size_t c = 0; c + 2 < in_world.indices.size(); c += 3)
        std::swap(in_world.indices[c + 1], in_world.indices[c + 2]);
    EXPECT_EQ(fans.smoothness, smoothness(in_world));
    EXPECT_GT(fans.smoothness, 0.0);
    world.pop_back();
    EXPECT_THROW(fan_measures(holed, dims, world), std::invalid_argument);
}

// --- Area and volume ------------------------------------------------------------------------

TEST(AreaVolume, UnitCube) {
    EXPECT_NEAR(surface_area(unit_cube()), 6.0, 1e-12);
    EXPECT_NEAR(enclosed_volume(unit_cube()), 1.0, 1e-12);
    EXPECT_NEAR(enclosed_volume(flipped(unit_cube())), -1.0, 1e-12);
    EXPECT_NEAR(enclosed_volume(translated(unit_cube(), {1000, -2000, 3000})), 1.0, 1e-9);
}

TEST(AreaVolume, Tetrahedron) {
    const Mesh m = tetrahedron();
    EXPECT_NEAR(enclosed_volume(m), 1.0 / 6.0, 1e-12);
    EXPECT_NEAR(surface_area(m), 1.5 + std::sqrt(3.0) / 2.0, 1e-7);
    EXPECT_TRUE(topology(m).oriented);
}

TEST(AreaVolume, Octahedron) {
    EXPECT_NEAR(enclosed_volume(octahedron()), 4.0 / 3.0, 1e-7);
    EXPECT_NEAR(surface_area(octahedron()), 8.0 * std::sqrt(3.0) / 4.0 * 2.0, 1e-6);
}

// --- Accuracy -------------------------------------------------------------------------------

TEST(Accuracy, OctahedronAgainstUnitSphere) {
    const DistanceFunction sphere = [](glm::vec3 p) { return glm::length(p) - 1.0f; };
    const Accuracy a = accuracy(octahedron(), sphere);
    EXPECT_NEAR(a.vertices_mean, 0.0, 1e-7);
    EXPECT_NEAR(a.vertices_max, 0.0, 1e-7);
    // Face centres (1, 1, 1) / 3 lie 1 - 1 / sqrt 3 inside; the signed value counts as distance.
    EXPECT_NEAR(a.faces_mean, 1.0 - 1.0 / std::sqrt(3.0), 1e-6);
    EXPECT_NEAR(a.faces_max, 1.0 - 1.0 / std::sqrt(3.0), 1e-6);
}

TEST(Accuracy, LargeGridAgainstShiftedPlane) {
    const Mesh grid = flat_grid(100);
    const Accuracy a = accuracy(grid, [](glm::vec3 p) { return p.z - 0.25f + 0.001f * p.x; });
    // |0.001 x - 0.25| falls from 0.25 at x = 0 to 0.15 at x = 100; the mean x of the vertices
    // and of the face centres is 50, so both means are 0.2.
    EXPECT_NEAR(a.vertices_mean, 0.2, 1e-5);
    EXPECT_NEAR(a.vertices_max, 0.25, 1e-6);
    EXPECT_NEAR(a.faces_mean, 0.2, 1e-5);
    EXPECT_EQ(accuracy(Mesh{}, [](glm::vec3) { return 1.0f; }).vertices_mean, 0.0);
    // A linear distance is integrated exactly by the centroid rule: 0.2 over the surface too.
    EXPECT_NEAR(a.surface_mean, 0.2, 1e-5);
    EXPECT_NEAR(a.surface_max, 0.25, 1e-3);
}

// The figures at the points alone (the app's plot over the iterations): accuracy()'s own, to the
// bit, and no surface samples asked for.
TEST(Accuracy, AtPointsAloneAsAccuracyGivesThem) {
    const Mesh grid = flat_grid(40);
    std::atomic<std::size_t> calls{0};
    const DistanceFunction tilted = [&](glm::vec3 p) {
        ++calls;
        return p.z - 0.25f + 0.001f * p.x * p.y;
    };
    const Accuracy whole = accuracy(grid, tilted);
    calls = 0;
    const Accuracy points = point_accuracy(grid, tilted);
    EXPECT_EQ(calls, grid.positions.size() + grid.triangle_count());
    EXPECT_EQ(points.vertices_mean, whole.vertices_mean);
    EXPECT_EQ(points.vertices_max, whole.vertices_max);
    EXPECT_EQ(points.faces_mean, whole.faces_mean);
    EXPECT_EQ(points.faces_max, whole.faces_max);
    EXPECT_GT(whole.surface_mean, 0.0);
    EXPECT_EQ(points.surface_mean, 0.0);
    EXPECT_EQ(points.surface_max, 0.0);
}

TEST(Accuracy, SurfaceIsAreaWeighted) {
    // Triangle 0 (area 0.5) at z = 1, triangle 1 (area 2) at z = 3; distance |z|.
    Mesh m;
    m.positions = {{0, 0, 1}, {1, 0, 1}, {0, 1, 1}, {0, 0, 3}, {2, 0, 3}, {0, 2, 3}};
    m.indices = {0, 1, 2, 3, 4, 5};
    const DistanceFunction z = [](glm::vec3 p) { return p.z; };
    const Accuracy a = accuracy(m, z);
    EXPECT_NEAR(a.vertices_mean, 2.0, 1e-12);
    EXPECT_NEAR(a.faces_mean, 2.0, 1e-12);
    EXPECT_NEAR(a.surface_mean, (0.5 * 1 + 2 * 3) / 2.5, 1e-12);
    EXPECT_NEAR(a.surface_max, 3.0, 1e-12);
    // Areas from another copy (here the first triangle stretched 4 times): weights 2 and 2.
    Mesh stretched = m;
    for (int v = 0; v < 3; ++v) stretched.positions[std::size_t(v)].x *= 4;
    EXPECT_NEAR(accuracy(m, z, stretched.positions).surface_mean, 2.0, 1e-12);
    // One point per vertex, or no answer.
    std::vector<glm::vec3> too_few = m.positions;
    too_few.pop_back();
    EXPECT_THROW(accuracy(m, z, too_few), std::invalid_argument);
}

TEST(Accuracy, SurfaceSeesWhatVerticesMiss) {
    // The octahedron's vertices lie on the unit sphere (vertex figure 0); its faces do not.
    const DistanceFunction sphere = [](glm::vec3 p) { return glm::length(p) - 1.0f; };
    const Accuracy a = accuracy(octahedron(), sphere);
    EXPECT_GT(a.surface_mean, 0.2);
    EXPECT_LT(a.surface_mean, a.faces_mean); // the centres are the farthest points
    EXPECT_LT(a.surface_max, a.faces_max);   // no sample sits at the centroid (a sub-corner)
}

TEST(SurfaceDistance, SplitSetsTheSamples) {
    // With accuracy()'s split, accuracy()'s surface figures; with split 1, the area-weighted
    // mean at the centroids and the largest centroid distance (the octahedron's faces_max).
    const DistanceFunction sphere = [](glm::vec3 p) { return glm::length(p) - 1.0f; };
    const Mesh m = octahedron();
    const Accuracy a = accuracy(m, sphere);
    const SurfaceDistance fine = surface_distance(m, sphere, {}, kSurfaceSampleSplit);
    EXPECT_EQ(fine.mean, a.surface_mean);
    EXPECT_EQ(fine.max, a.surface_max);
    const SurfaceDistance centroids = surface_distance(m, sphere, {}, 1);
    EXPECT_NEAR(centroids.mean, a.faces_mean, 1e-12); // equal areas: the plain centroid mean
    EXPECT_NEAR(centroids.max, a.faces_max, 1e-12);
    EXPECT_GT(centroids.max, fine.max);
    EXPECT_THROW(surface_distance(m, sphere, {}, 0), std::invalid_argument);
}

// --- Mesh distance --------------------------------------------------------------------------

// Independent brute-force reference: the plane distance when the projection falls inside the
// triangle, otherwise the nearest of the three edges.
double segment_distance(glm::dvec3 p, glm::dvec3 a, glm::dvec3 b) {
    const glm::dvec3 ab = b - a;
    const double len2 = glm::dot(ab, ab);
    const double t = len2 > 0 ? std::clamp(glm::dot(p - a, ab) / len2, 0.0, 1.0) : 0.0;
    return glm::length(p - (a + t * ab));
}

double reference_triangle_distance(glm::dvec3 p, glm::dvec3 a, glm::dvec3 b, glm::dvec3 c) {
    const glm::dvec3 n = glm::cross(b - a, c - a);
    if (glm::length(n) > 1e-12) {
        const glm::dvec3 u = glm::normalize(n);
        const double height = glm::dot(p - a, u);
        const glm::dvec3 q = p - height * u;
        const bool inside = glm::dot(glm::cross(b - a, q - a), n) >= 0 &&
                            glm::dot(glm::cross(c - b, q - b), n) >= 0 &&
                            glm::dot(glm::cross(a - c, q - c), n) >= 0;
        if (inside) return std::abs(height);
    }
    return std::min(
        {segment_distance(p, a, b), segment_distance(p, b, c), segment_distance(p, c, a)});
}

double brute_force_distance(const Mesh& m, glm::vec3 p) {
    double best = INFINITY;
    for (std::size_t t = 0; t < m.indices.size(); t += 3)
        best = std::min(best, reference_triangle_distance(p, m.positions[m.indices[t]],
                                                          m.positions[m.indices[t + 1]],
                                                          m.positions[m.indices[t + 2]]));
    return best;
}

TEST(MeshDistance, SingleTriangleByHand) {
    Mesh m;
    m.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
    m.indices = {0, 1, 2};
    const MeshDistance d(m);
    EXPECT_NEAR(d({0.25f, 0.25f, 2.0f}), 2.0f, 1e-6);          // above the face
    EXPECT_NEAR(d({0.25f, 0.25f, -0.5f}), 0.5f, 1e-6);         // below
    EXPECT_NEAR(d({3.0f, 0.0f, 0.0f}), 2.0f, 1e-6);            // beyond corner (1, 0, 0)
    EXPECT_NEAR(d({0.5f, -1.0f, 0.0f}), 1.0f, 1e-6);           // beside edge y = 0
    EXPECT_NEAR(d({1.0f, 1.0f, 0.0f}), std::sqrt(0.5f), 1e-6); // beside the hypotenuse
    EXPECT_NEAR(d({-3.0f, -4.0f, 0.0f}), 5.0f, 1e-5);          // beyond corner (0, 0, 0)
    EXPECT_EQ(d({0.2f, 0.3f, 0.0f}), 0.0f);                    // on the face
    EXPECT_TRUE(std::isnan(d({NAN, 0, 0})));
}

TEST(MeshDistance, CubeByHand) {
    const MeshDistance d(unit_cube());
    EXPECT_NEAR(d({0.5f, 0.5f, 0.5f}), 0.5f, 1e-6);
    EXPECT_NEAR(d({0.5f, 0.5f, 0.2f}), 0.2f, 1e-6);
    EXPECT_NEAR(d({2.5f, 0.5f, 0.5f}), 1.5f, 1e-6);
    EXPECT_NEAR(d({2.0f, 2.0f, 2.0f}), std::sqrt(3.0f), 1e-6);
    EXPECT_NEAR(d({-100.0f, 0.5f, 0.5f}), 100.0f, 1e-4);
}

TEST(MeshDistance, MatchesBruteForceOnBumpySphere) {
    Mesh m = icosphere(3); // 1280 triangles
    for (glm::vec3& p : m.positions)
        p *= 1.0f + 0.15f * std::sin(5.0f * p.x) * std::cos(3.0f * p.y + p.z);
    // A few degenerate triangles must not upset it: a collapsed and a collinear one.
    const std::uint32_t first = std::uint32_t(m.positions.size());
    m.positions.insert(m.positions.end(), {{2.0f, 0.0f, 0.0f}, {3.0f, 0.0f, 0.0f}, {4.0f, 0, 0}});
    m.indices.insert(m.indices.end(), {0, 0, 1, first, first + 1, first + 2});
    const MeshDistance d(m);
    std::mt19937 random(7);
    std::uniform_real_distribution<float> near(-1.6f, 1.6f), far(-40.0f, 40.0f);
    std::vector<glm::vec3> points;
    for (int i = 0; i < 300; ++i) points.push_back({near(random), near(random), near(random)});
    for (int i = 0; i < 30; ++i) points.push_back({far(random), far(random), far(random)});
    for (int i = 0; i < 30; ++i) points.push_back(m.positions[std::size_t(i) * 17] * 1.001f);
    for (const glm::vec3& p : points) {
        const double expected = brute_force_distance(m, p);
        EXPECT_NEAR(d(p), expected, 1e-5 * std::max(1.0, expected))
            << p.x << ' ' << p.y << ' ' << p.z;
    }
}

// A query starts from the triangle nearest to the thread's previous point; the answer must not
// depend on it, bit for bit (the metrics would otherwise depend on the thread count). Points at
// ties are the hard ones: on the surface, at edge midpoints (two triangles equally near) and at
// vertices, where rounding could let either triangle win.
TEST(MeshDistance, AnswerDoesNotDependOnThePointBefore) {
    Mesh m = icosphere(3);
    for (glm::vec3& p : m.positions)
        p = 40.0f * p * (1.0f + 0.15f * std::sin(5.0f * p.x) * std::cos(3.0f * p.y + p.z)) +
            glm::vec3(100.0f, -50.0f, 300.0f); // world-like coordinates: rounding at their size
    std::vector<glm::vec3> points;
    for (std::size_t t = 0; t < m.indices.size(); t += 3 * 7) {
        const glm::vec3 a = m.positions[m.indices[t]], b = m.positions[m.indices[t + 1]],
                        c = m.positions[m.indices[t + 2]];
        points.insert(points.end(), {a, 0.5f * (a + b), (a + b + c) / 3.0f,
                                     (a + b + c) / 3.0f + 0.3f * glm::cross(b - a, c - a)});
    }
    std::mt19937 random(11);
    std::uniform_real_distribution<float> box(-60.0f, 60.0f);
    for (int i = 0; i < 100; ++i)
        points.push_back(glm::vec3(100.0f, -50.0f, 300.0f) +
                         glm::vec3(box(random), box(random), box(random)));
    std::vector<float> first;
    {
        const MeshDistance fresh(m);
        for (const glm::vec3& p : points) first.push_back(fresh(p));
    }
    const MeshDistance d(m);
    const glm::vec3 centre(100.0f, -50.0f, 300.0f);
    int compared = 0;
    for (std::size_t i = 0; i < points.size(); ++i) {
        const glm::vec3 p = points[i];
        for (const glm::vec3 before : {2.0f * centre - p, centre, centre + glm::vec3(500.0f),
                                       points[(i * 31 + 5) % points.size()], p}) {
            (void)d(before);
            ASSERT_EQ(d(p), first[i]) << "point " << i;
            ++compared;
        }
        EXPECT_NEAR(first[i], brute_force_distance(m, p), 1e-4 * std::max(1.0f, first[i]));
    }
    EXPECT_EQ(compared, 5 * int(points.size()));
}

// Each thread keeps the triangles it measured last. A grid made after another is gone (perhaps
// at its address, with the same triangle numbers) and two grids asked in turn must each measure
// their own triangles.
TEST(MeshDistance, KeptTrianglesAreNeverAnotherGrids) {
    const auto scaled = [](float scale) {
        Mesh m = icosphere(2);
        for (glm::vec3& p : m.positions) p *= scale;
        return m;
    };
    const glm::vec3 p(0.3f, 0.2f, 1.9f), q(0.31f, 0.2f, 1.9f);
    for (const float scale : {1.0f, 1.5f, 0.5f}) {
        const Mesh m = scaled(scale);
        const MeshDistance d(m);
        for (const glm::vec3 x : {p, q, p})
            EXPECT_NEAR(d(x), brute_force_distance(m, x), 1e-5) << "scale " << scale;
    }
    const Mesh small = scaled(0.5f), large = scaled(1.5f);
    const MeshDistance to_small(small), to_large(large);
    for (int k = 0; k < 3; ++k) {
        EXPECT_NEAR(to_small(p), brute_force_distance(small, p), 1e-5);
        EXPECT_NEAR(to_large(p), brute_force_distance(large, p), 1e-5);
    }
}

TEST(MeshDistance, ConcurrentQueriesAgree) {
    const MeshDistance d(icosphere(2));
    std::vector<glm::vec3> points;
    for (int i = 0; i < 200; ++i)
        points.push_back({std::sin(i * 1.3f) * 2, std::cos(i * 0.7f), i * 0.01f});
    std::vector<float> serial;
    for (const glm::vec3& p : points) serial.push_back(d(p));
    std::vector<std::vector<float>> results(4);
    {
        std::vector<std::jthread> threads;
        for (auto& r : results)
            threads.emplace_back([&, copy = d] {
                for (const glm::vec3& p : points) r.push_back(copy(p));
            });
    }
    for (const auto& r : results) EXPECT_EQ(r, serial);
    // Used as an accuracy reference, the sphere is at distance 0 from its own vertices.
    EXPECT_NEAR(accuracy(icosphere(2), d).vertices_max, 0.0, 1e-6);
}

TEST(MeshDistance, FlatAndTinyMeshes) {
    const MeshDistance plane(flat_grid(20)); // one cell thick
    EXPECT_NEAR(plane({3.3f, 7.7f, 2.0f}), 2.0f, 1e-6);
    EXPECT_NEAR(plane({-1.0f, 5.0f, 0.0f}), 1.0f, 1e-6);
    Mesh point; // all three corners at one spot
    point.positions = {{1, 2, 3}};
    point.indices = {0, 0, 0};
    EXPECT_NEAR(MeshDistance(point)({1, 2, 7}), 4.0f, 1e-6);
}

TEST(MeshDistance, RejectsEmptyReference) {
    EXPECT_THROW(MeshDistance(Mesh{}), std::invalid_argument);
}

// Borrowed through a map (world to index space, as the distance to Marching Cubes measures it),
// the mesh gives bit for bit what a mapped copy gives, and is left as it was.
TEST(MeshDistance, BorrowedThroughAMapMatchesAMappedCopy) {
    Mesh world = icosphere(3);
    for (glm::vec3& p : world.positions) p = p * 40.0f + glm::vec3(-120.0f, 35.0f, 8.0f);
    WorldToIndex map;
    map.inverse_linear = glm::mat3(-1.4f, 0.1f, 0.0f, 0.0f, 1.7f, 0.2f, 0.0f, 0.0f, 4.6f);
    map.origin = {-150.0f, 10.0f, -20.0f};
    Mesh copy = world;
    for (glm::vec3& p : copy.positions) p = map(p);
    const Mesh before = world;
    const MeshDistance borrowed(world, map), owned(copy);
    std::mt19937 random(11);
    std::uniform_real_distribution<float> x(-60.0f, 60.0f), y(0.0f, 200.0f), z(-10.0f, 400.0f);
    for (int i = 0; i < 400; ++i) {
        const glm::vec3 p(x(random), y(random), z(random));
        EXPECT_EQ(borrowed(p), owned(p)) << p.x << ' ' << p.y << ' ' << p.z;
    }
    EXPECT_EQ(world.positions, before.positions);
    EXPECT_EQ(world.indices, before.indices);
}

// Slivers, right, obtuse and acute triangles side by side, as Marching Cubes makes them: a wavy
// height field over a grid whose points are pushed far along x and y. Each triangle is asked near
// its corners, sides and centre, just off its surface, where a neighbour is nearly as near: a
// triangle's bounding sphere that missed a part of it would lose that part to the neighbour.
TEST(MeshDistance, SliversAndObtuseTrianglesMatchBruteForce) {
    constexpr int kSide = 16;
    std::mt19937 random(5);
    std::uniform_real_distribution<float> jitter(-0.45f, 0.45f);
    Mesh m;
    for (int y = 0; y < kSide; ++y)
        for (int x = 0; x < kSide; ++x) {
            const float px = float(x) + jitter(random), py = float(y) + jitter(random);
            m.positions.push_back({px, py, 2.0f * std::sin(0.4f * px) * std::cos(0.3f * py)});
        }
    for (std::uint32_t y = 0; y + 1 < kSide; ++y)
        for (std::uint32_t x = 0; x + 1 < kSide; ++x) {
            const std::uint32_t a = y * kSide + x, b = a + 1, c = a + kSide, d = c + 1;
            if ((x + y) % 2 == 0)
                m.indices.insert(m.indices.end(), {a, b, d, a, d, c});
            else
                m.indices.insert(m.indices.end(), {a, b, c, b, d, c});
        }
    int obtuse = 0;
    std::vector<glm::vec3> points;
    for (std::size_t t = 0; t < m.indices.size(); t += 3) {
        const glm::vec3 a = m.positions[m.indices[t]], b = m.positions[m.indices[t + 1]],
                        c = m.positions[m.indices[t + 2]];
        if (glm::dot(b - a, c - a) < 0 || glm::dot(a - b, c - b) < 0 || glm::dot(a - c, b - c) < 0)
            ++obtuse;
        const glm::vec3 n = 1e-3f * glm::normalize(glm::cross(b - a, c - a));
        for (const glm::vec3 w : {glm::vec3(0.96f, 0.02f, 0.02f), glm::vec3(0.02f, 0.96f, 0.02f),
                                  glm::vec3(0.02f, 0.02f, 0.96f), glm::vec3(0.49f, 0.49f, 0.02f),
                                  glm::vec3(0.02f, 0.49f, 0.49f), glm::vec3(0.49f, 0.02f, 0.49f),
                                  glm::vec3(1.0f / 3.0f)}) {
            const glm::vec3 p = w.x * a + w.y * b + w.z * c;
            points.insert(points.end(), {p + n, p - n});
        }
    }
    EXPECT_GT(obtuse, int(m.triangle_count()) / 4); // the case the sphere's centre is chosen for
    const MeshDistance d(m);
    std::shuffle(points.begin(), points.end(), random);
    for (const glm::vec3& p : points) {
        const double expected = brute_force_distance(m, p);
        ASSERT_NEAR(d(p), expected, 1e-6) << p.x << ' ' << p.y << ' ' << p.z;
    }
}

// Degenerate (collinear) triangles, measured as their sides, listed in the same cells: their
// spheres carry the flatness in the radius's sign, which the grid's sphere test must ignore (it
// reads a cell's spheres four at a time). Bundles of parallel needles 0.08 apart above a sheet;
// each query lies just off the end of one needle and follows a query at the needle beside it, so
// it starts from a triangle 0.08 away while its own needle's sphere centre is 0.27 away.
TEST(MeshDistance, FlatTrianglesAmongOthersMatchBruteForce) {
    constexpr int kSide = 8;
    Mesh m;
    for (int y = 0; y < kSide; ++y)
        for (int x = 0; x < kSide; ++x)
            m.positions.push_back({float(x), float(y), 0.1f * float((x * 7 + y * 3) % 5)});
    for (std::uint32_t y = 0; y + 1 < kSide; ++y)
        for (std::uint32_t x = 0; x + 1 < kSide; ++x) {
            const std::uint32_t a = y * kSide + x, b = a + 1, c = a + kSide, d = c + 1;
            m.indices.insert(m.indices.end(), {a, b, d, a, d, c});
        }
    std::mt19937 random(11);
    std::uniform_real_distribution<float> across(0.5f, float(kSide) - 1.5f), turn(0.0f, 6.28f);
    std::vector<glm::vec3> points;
    for (int bundle = 0; bundle < 20; ++bundle) {
        const glm::vec3 start(across(random), across(random), 0.6f);
        const float angle = turn(random);
        const glm::vec3 step(0.3f * std::cos(angle), 0.3f * std::sin(angle), 0.0f);
        const glm::vec3 apart(-0.08f * std::sin(angle), 0.08f * std::cos(angle), 0.0f);
        for (int k = 0; k < 6; ++k) {
            // The middle corner on the line between the other two.
            const glm::vec3 a = start + float(k) * apart;
            const std::uint32_t first = std::uint32_t(m.positions.size());
            m.positions.insert(m.positions.end(), {a, a + step, a + 2.0f * step});
            m.indices.insert(m.indices.end(), {first, first + 2, first + 1});
            points.push_back(a + 1.9f * step + glm::vec3(0.0f, 0.0f, 0.02f));
        }
    }
    const MeshDistance d(m);
    for (const glm::vec3& p : points) {
        const double expected = brute_force_distance(m, p);
        ASSERT_NEAR(d(p), expected, 1e-6) << p.x << ' ' << p.y << ' ' << p.z;
    }
}

// Two small triangles 2000 edges apart: a query half-way lies more than 255 cells from either,
// where the distance transform saturates. The answer is still exact.
TEST(MeshDistance, FarBeyondTheShellCountItSkips) {
    Mesh m;
    m.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {2000, 0, 0}, {2001, 0, 0}, {2000, 1, 0}};
    m.indices = {0, 1, 2, 3, 4, 5};
    const MeshDistance d(m);
    for (const glm::vec3 p :
         {glm::vec3(1000, 0.2f, 3), glm::vec3(400, 0.5f, 0), glm::vec3(1700, 0.3f, 0)})
        EXPECT_NEAR(d(p), brute_force_distance(m, p), 1e-6 * brute_force_distance(m, p));
}

// Small triangles scattered through a large box: far more cells than the grid's cap, and the map
// of empty space kept over blocks of cells (a byte a block, not a cell). Queries in the empty
// space between them skip whole blocks and must still find the nearest triangle.
TEST(MeshDistance, EmptySpaceSkippedBlockByBlockStaysExact) {
    std::mt19937 random(3);
    std::uniform_real_distribution<float> box(0.0f, 300.0f), small(-0.5f, 0.5f);
    Mesh m;
    for (std::uint32_t t = 0; t < 60; ++t) {
        const glm::vec3 a(box(random), box(random), box(random));
        m.positions.insert(m.positions.end(), {a, a + glm::vec3(small(random), small(random), 0.6f),
                                               a + glm::vec3(0.6f, small(random), small(random))});
        m.indices.insert(m.indices.end(), {3 * t, 3 * t + 1, 3 * t + 2});
    }
    const MeshDistance d(m);
    for (int i = 0; i < 400; ++i) {
        const glm::vec3 p(box(random), box(random), box(random));
        const double expected = brute_force_distance(m, p);
        ASSERT_NEAR(d(p), expected, 1e-5 * expected) << p.x << ' ' << p.y << ' ' << p.z;
    }
}

} // namespace
} // namespace snert
