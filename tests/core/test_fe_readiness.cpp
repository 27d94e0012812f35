// The FE-readiness summary and the per-triangle fields of an export: exact shares on triangles
// with known angles, ratio ranges against the closed forms of the angles, the pipeline's wiring.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <numeric>
#include <vector>

#include "core/fe_readiness.h"
#include "core/parallel.h"
#include "core/phantom.h"
#include "core/pipeline.h"
#include "core/triangle_fields.h"
#include "support/test_meshes.h"

namespace snert {
namespace {

constexpr double kDegree = 3.14159265358979323846 / 180.0;

// 2 r / R = 8 sin(A/2) sin(B/2) sin(C/2), and Verdict's aspect ratio from the law of sines:
// sin(largest) * (sin A + sin B + sin C) / (2 sqrt(3) sin A sin B sin C).
double radius_ratio_of(double a, double b, double c) {
    return 8.0 * std::sin(a * kDegree / 2) * std::sin(b * kDegree / 2) * std::sin(c * kDegree / 2);
}
double aspect_ratio_of(double a, double b, double c) {
    const double sa = std::sin(a * kDegree), sb = std::sin(b * kDegree), sc = std::sin(c * kDegree);
    return std::sin(std::max({a, b, c}) * kDegree) * (sa + sb + sc) /
           (2 * std::sqrt(3.0) * sa * sb * sc);
}

// Four separate triangles in z = 0 with angles (60, 60, 60), (10, 80, 90), (20, 20, 140) and
// (40, 40, 100): one smallest angle under 15, two under 30, one largest over 120.
Mesh four_triangles() {
    Mesh m;
    auto add = [&](glm::vec3 a, glm::vec3 b, glm::vec3 c) {
        const auto first = std::uint32_t(m.positions.size());
        m.positions.insert(m.positions.end(), {a, b, c});
        m.indices.insert(m.indices.end(), {first, first + 1, first + 2});
    };
    const float h = float(std::sqrt(3.0) / 2);
    add({0, 0, 0}, {1, 0, 0}, {0.5f, h, 0});
    add({0, 0, 0}, {1, 0, 0}, {0, float(std::tan(10 * kDegree)), 0}); // 10 degrees at (1, 0)
    add({-1, 0, 0}, {1, 0, 0}, {0, float(std::tan(20 * kDegree)), 0});
    add({-1, 0, 0}, {1, 0, 0}, {0, float(std::tan(40 * kDegree)), 0});
    return m;
}

TEST(FeReadiness, ExactSharesOfKnownAngles) {
    const Mesh m = four_triangles();
    const FeReadiness fe = fe_readiness(m, topology(m), 0);
    EXPECT_EQ(fe.triangles, 4u);
    EXPECT_EQ(fe.min_angle_below_15, 0.25);
    EXPECT_EQ(fe.min_angle_below_30, 0.5);
    EXPECT_EQ(fe.max_angle_above_120, 0.25);
    // Best: the equilateral triangle. Worst: the obtuse 20-20-140 one by the radius ratio, the
    // needle 10-80-90 by the aspect ratio (the two measures disagree here).
    EXPECT_NEAR(fe.radius_ratio_min, radius_ratio_of(20, 20, 140), 1e-5);
    EXPECT_NEAR(fe.radius_ratio_max, 1.0, 1e-6);
    EXPECT_NEAR(fe.aspect_ratio_min, 1.0, 1e-6);
    EXPECT_NEAR(fe.aspect_ratio_max, aspect_ratio_of(10, 80, 90), 1e-5);
    EXPECT_LT(radius_ratio_of(20, 20, 140), radius_ratio_of(10, 80, 90)); // the order assumed
    EXPECT_GT(aspect_ratio_of(10, 80, 90), aspect_ratio_of(20, 20, 140));
    EXPECT_FALSE(fe.closed);  // four open triangles
    EXPECT_TRUE(fe.manifold); // with a boundary
    EXPECT_EQ(fe.self_intersections, 0u);
}

TEST(FeReadiness, ClosedMeshesOfGoodTriangles) {
    // The octahedron: equilateral, nothing to report.
    const Mesh octahedron = test::octahedron();
    const FeReadiness o = fe_readiness(octahedron, topology(octahedron), 0);
    EXPECT_TRUE(o.closed && o.manifold);
    EXPECT_EQ(o.min_angle_below_30, 0.0);
    EXPECT_EQ(o.max_angle_above_120, 0.0);
    EXPECT_NEAR(o.radius_ratio_min, 1.0, 1e-6);
    EXPECT_NEAR(o.aspect_ratio_max, 1.0, 1e-6);
    // The cube: twelve right isosceles triangles, 2r/R = 2 sqrt 2 - 2, aspect (1 + sqrt 2) /
    // sqrt 3.
    const Mesh cube = test::unit_cube();
    const FeReadiness c = fe_readiness(cube, topology(cube), 3);
    EXPECT_TRUE(c.closed && c.manifold);
    EXPECT_EQ(c.self_intersections, 3u); // passed on as measured
    EXPECT_EQ(c.min_angle_below_30, 0.0);
    EXPECT_EQ(c.max_angle_above_120, 0.0);
    EXPECT_NEAR(c.radius_ratio_min, 2 * std::sqrt(2.0) - 2, 1e-6);
    EXPECT_NEAR(c.radius_ratio_max, 2 * std::sqrt(2.0) - 2, 1e-6);
    EXPECT_NEAR(c.aspect_ratio_min, (1 + std::sqrt(2.0)) / std::sqrt(3.0), 1e-6);
    EXPECT_NEAR(c.aspect_ratio_max, c.aspect_ratio_min, 1e-6);
}

TEST(FeReadiness, DegenerateTriangleIsTheWorstOfAll) {
    Mesh m = test::square();
    m.positions.push_back({0, 0, 0});
    m.positions.push_back({2, 0, 0});
    m.positions.push_back({4, 0, 0}); // collinear: zero area
    m.indices.insert(m.indices.end(), {4, 5, 6});
    const FeReadiness fe = fe_readiness(m, topology(m), 0);
    EXPECT_NEAR(fe.min_angle_below_15, 1.0 / 3.0, 1e-12);
    EXPECT_NEAR(fe.max_angle_above_120, 1.0 / 3.0, 1e-12);
    EXPECT_EQ(fe.radius_ratio_min, 0.0);
    EXPECT_EQ(fe.aspect_ratio_max, std::numeric_limits<double>::infinity());
    EXPECT_NEAR(fe.aspect_ratio_min, (1 + std::sqrt(2.0)) / std::sqrt(3.0), 1e-6);
}

TEST(FeReadiness, EmptyMeshAndBadIndex) {
    const FeReadiness fe = fe_readiness(Mesh{}, Topology{}, 0);
    EXPECT_EQ(fe.triangles, 0u);
    EXPECT_EQ(fe.min_angle_below_15, 0.0);
    EXPECT_EQ(fe.aspect_ratio_max, 0.0);
    Mesh bad = test::tetrahedron();
    bad.indices.back() = 9;
    EXPECT_THROW(fe_readiness(bad, Topology{}, 0), std::invalid_argument);
}

TEST(FeReadiness, SameWithOneThreadAsWithAll) {
    const Mesh mesh = test::phantom_mc("noisy-sphere", 80);
    const Topology t = topology(mesh);
    FeReadiness one, all;
    {
        const ThreadLimit limit(1);
        one = fe_readiness(mesh, t, 0);
    }
    all = fe_readiness(mesh, t, 0);
    EXPECT_GT(mesh.triangle_count(), 20000u); // several chunks
    EXPECT_EQ(one.min_angle_below_15, all.min_angle_below_15);
    EXPECT_EQ(one.min_angle_below_30, all.min_angle_below_30);
    EXPECT_EQ(one.max_angle_above_120, all.max_angle_above_120);
    EXPECT_EQ(one.radius_ratio_min, all.radius_ratio_min);
    EXPECT_EQ(one.aspect_ratio_max, all.aspect_ratio_max);
    EXPECT_GT(all.min_angle_below_15, 0.0); // MC of a noisy volume has needles
}

// measure() fills the summary from the world mesh and its own checks.
TEST(FeReadiness, MeasuredByThePipeline) {
    const Phantom sphere = make_phantom("sphere", 32);
    PipelineOptions options;
    options.iso = sphere.iso;
    const MethodResult mc = run_marching_cubes(sphere.volume, options, sphere.reference_distance);
    const MethodMetrics& m = mc.metrics;
    EXPECT_EQ(m.fe.triangles, m.triangles);
    EXPECT_EQ(m.fe.closed, m.topology.watertight);
    EXPECT_TRUE(m.fe.closed);
    EXPECT_TRUE(m.fe.manifold);
    EXPECT_EQ(m.fe.self_intersections, m.self_intersections);
    const FeReadiness again = fe_readiness(mc.mesh, m.topology, m.self_intersections);
    EXPECT_EQ(m.fe.min_angle_below_30, again.min_angle_below_30);
    EXPECT_EQ(m.fe.radius_ratio_min, again.radius_ratio_min);
    // Marching Cubes on a sphere: many thin triangles (the paper's point), none degenerate here.
    EXPECT_GT(m.fe.min_angle_below_30, 0.1);
    EXPECT_TRUE(std::isfinite(m.fe.aspect_ratio_max));
}

TEST(TriangleMeasures, AnglesOfKnownTriangles) {
    const TriangleMeasures f = triangle_measures(four_triangles());
    const double smallest[] = {60, 10, 20, 40}, largest[] = {60, 90, 140, 100};
    ASSERT_EQ(f.quality.size(), 4u);
    for (std::size_t t = 0; t < 4; ++t) {
        EXPECT_NEAR(f.min_angle[t], smallest[t], 1e-4) << t;
        EXPECT_NEAR(f.max_angle[t], largest[t], 1e-4) << t;
        EXPECT_NEAR(f.quality[t], smallest[t] / largest[t], 1e-6) << t;
    }
}

// The per-triangle distance is the face-centre accuracy, triangle by triangle.
TEST(TriangleFields, CentroidDistancesAverageToFaceAccuracy) {
    Phantom sphere = make_phantom("sphere", 32);
    sphere.volume.spacing = glm::vec3(0.5f, 0.7f, 1.5f); // world differs from index space
    PipelineOptions options;
    options.iso = sphere.iso;
    const MethodResult mc = run_marching_cubes(sphere.volume, options, sphere.reference_distance);
    const std::vector<float> d =
        centroid_distances(mc.mesh, sphere.volume, sphere.reference_distance);
    ASSERT_EQ(d.size(), mc.mesh.triangle_count());
    const double mean = std::accumulate(d.begin(), d.end(), 0.0) / double(d.size());
    ASSERT_TRUE(mc.metrics.accuracy);
    EXPECT_NEAR(mean, mc.metrics.accuracy->faces_mean, 1e-5);
    EXPECT_NEAR(*std::max_element(d.begin(), d.end()), mc.metrics.accuracy->faces_max, 1e-4);
    EXPECT_TRUE(centroid_distances(mc.mesh, sphere.volume, {}).empty());
}

} // namespace
} // namespace snert
