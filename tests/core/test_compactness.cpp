// Compactness: the equal-count comparison and the compactness curve on the sphere phantom.
#include <gtest/gtest.h>

#include <numeric>

#include "core/compactness.h"
#include "core/parallel.h"
#include "core/phantom.h"

namespace snert {
namespace {

std::vector<MethodResult> mc_and_snert(const Phantom& sphere) {
    PipelineOptions options;
    options.iso = sphere.iso;
    options.relax.max_iterations = 20;
    std::vector<MethodResult> results;
    for (const Method method : {Method::MarchingCubes, Method::Snert})
        results.push_back(
            run_method(method, sphere.volume, nullptr, options, sphere.reference_distance));
    return results;
}

TEST(Compactness, EqualCountReducesAndMeasuresAgain) {
    const Phantom sphere = make_phantom("sphere", 48);
    std::vector<MethodResult> results = mc_and_snert(sphere);
    measure_against_marching_cubes(results, sphere.volume);
    const std::size_t smallest =
        std::min(results[0].mesh.triangle_count(), results[1].mesh.triangle_count());
    EXPECT_EQ(equal_count_target(results, std::nullopt), smallest);
    EXPECT_EQ(equal_count_target(results, std::size_t(123)), 123u);

    const std::size_t target = smallest / 4;
    const double snert_to_mc_full = results[1].metrics.to_marching_cubes->surface_mean;
    const std::vector<DecimationReport> reports =
        reduce_to_equal_count(results, target, sphere.volume, sphere.reference_distance, {});
    ASSERT_EQ(reports.size(), 2u);
    for (std::size_t i = 0; i < 2; ++i) {
        const MethodMetrics& m = results[i].metrics;
        EXPECT_EQ(reports[i].achieved, results[i].mesh.triangle_count());
        EXPECT_LE(m.triangles, target);
        EXPECT_GE(double(m.triangles), 0.99 * double(target));
        // Measured again: the counts and the histogram are the reduced mesh's.
        EXPECT_EQ(m.triangles, results[i].mesh.triangle_count());
        EXPECT_EQ(
            std::accumulate(m.quality.histogram.begin(), m.quality.histogram.end(), std::size_t(0)),
            m.triangles);
        EXPECT_TRUE(m.topology.watertight && m.topology.manifold && m.fe_ready);
        ASSERT_TRUE(m.accuracy);
        // Chords of a quarter of the triangles: further from the sphere than the full meshes
        // (0.009 voxel over the surface), measured 0.037 (MC) and 0.039 (SNERT).
        EXPECT_GT(m.accuracy->surface_mean, 0.015);
        EXPECT_LT(m.accuracy->surface_mean, 0.05);
    }
    EXPECT_EQ(results[1].metrics.iterations, 20) << "the relaxation's numbers are kept";
    // SNERT's distance is to the unreduced MC mesh: it grew by the chords' depth.
    ASSERT_TRUE(results[1].metrics.to_marching_cubes);
    EXPECT_GT(results[1].metrics.to_marching_cubes->surface_mean, snert_to_mc_full);
}

TEST(Compactness, CurveLosesAccuracyAsTrianglesGo) {
    const Phantom sphere = make_phantom("sphere", 48);
    const std::vector<MethodResult> results = mc_and_snert(sphere);
    for (const MethodResult& r : results) {
        const std::vector<CompactnessPoint> curve = compactness_curve(r.mesh, sphere.volume);
        ASSERT_EQ(curve.size(), kCompactnessFractions.size());
        const double full = double(r.mesh.triangle_count());
        EXPECT_EQ(curve[0].triangles, r.mesh.triangle_count());
        EXPECT_EQ(curve[0].accuracy_mean, 0.0);
        EXPECT_NEAR(curve[0].quality_mean, r.metrics.quality.mean, 1e-9);
        for (std::size_t i = 1; i < curve.size(); ++i) {
            SCOPED_TRACE(curve[i].fraction);
            EXPECT_LE(double(curve[i].triangles), curve[i].fraction * full + 1);
            EXPECT_GE(double(curve[i].triangles), 0.98 * curve[i].fraction * full);
            EXPECT_GT(curve[i].accuracy_mean, curve[i - 1].accuracy_mean);
            EXPECT_GE(curve[i].accuracy_max, curve[i].accuracy_mean);
            // Even at 5 % the surface stays within half a voxel of the full one.
            EXPECT_LT(curve[i].accuracy_max, 0.5);
        }
    }
}

TEST(Compactness, CurveDoesNotDependOnTheThreadCount) {
    // The intersection checks and the distances run in parallel chunks; the curve (counts,
    // refusals, distances) must be the same on one thread, bit for bit.
    const Phantom phantom = make_phantom("sphere", 32);
    Mesh mesh = mc_and_snert(phantom).front().mesh;
    std::vector<CompactnessPoint> one, all;
    {
        const ThreadLimit limit(1);
        one = compactness_curve(mesh, phantom.volume);
    }
    all = compactness_curve(mesh, phantom.volume);
    ASSERT_EQ(one.size(), all.size());
    for (std::size_t i = 0; i < one.size(); ++i) {
        EXPECT_EQ(one[i].triangles, all[i].triangles);
        EXPECT_EQ(one[i].refusals, all[i].refusals);
        EXPECT_EQ(one[i].accuracy_mean, all[i].accuracy_mean);
        EXPECT_EQ(one[i].accuracy_max, all[i].accuracy_max);
        EXPECT_EQ(one[i].quality_mean, all[i].quality_mean);
    }
}

TEST(Compactness, EmptyMeshHasNoCurve) {
    const Phantom sphere = make_phantom("sphere", 16);
    EXPECT_TRUE(compactness_curve(Mesh{}, sphere.volume).empty());
}

} // namespace
} // namespace snert
