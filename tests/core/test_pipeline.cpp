// The comparison pipeline: one method at a time, and the nets' distance to Marching Cubes.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#include "core/parallel.h"
#include "core/phantom.h"
#include "core/pipeline.h"

namespace snert {
namespace {

std::vector<MethodResult> sphere_comparison(const Phantom& sphere) {
    PipelineOptions options;
    options.iso = sphere.iso;
    options.relax.max_iterations = 20;
    std::vector<MethodResult> results;
    for (const Method method : {Method::MarchingCubes, Method::Sna, Method::Snert})
        results.push_back(
            run_method(method, sphere.volume, nullptr, options, sphere.reference_distance));
    return results;
}

// same_mesh compares bits: a vertex moved by one unit in the last place, a -0 for a 0, another
// corner order or a vertex more is another mesh; a NaN vertex is the same as itself.
TEST(Mesh, SameMeshComparesBits) {
    Mesh a;
    a.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
    a.indices = {0, 1, 2};
    EXPECT_TRUE(same_mesh(a, a));
    EXPECT_TRUE(same_mesh(Mesh{}, Mesh{}));
    Mesh b = a;
    b.positions[1].x = std::nextafter(1.0f, 2.0f);
    EXPECT_FALSE(same_mesh(a, b));
    b = a;
    b.positions[0].x = -0.0f;
    EXPECT_FALSE(same_mesh(a, b));
    b = a;
    b.indices = {0, 2, 1};
    EXPECT_FALSE(same_mesh(a, b));
    b = a;
    b.positions.push_back({0, 0, 1});
    EXPECT_FALSE(same_mesh(a, b));
    b = a;
    b.positions[2].y = std::numeric_limits<float>::quiet_NaN();
    EXPECT_TRUE(same_mesh(b, b));
}

TEST(Pipeline, NetsAreMeasuredAgainstMarchingCubes) {
    const Phantom sphere = make_phantom("sphere", 48);
    std::vector<MethodResult> results = sphere_comparison(sphere);
    measure_against_marching_cubes(results, sphere.volume);
    EXPECT_FALSE(results[0].metrics.to_marching_cubes) << "MC is not measured against itself";
    const auto& sna = results[1].metrics.to_marching_cubes;
    const auto& snert = results[2].metrics.to_marching_cubes;
    ASSERT_TRUE(sna && snert);
    // MC's vertices lie on the iso-surface: averaging shrinks the sphere away from it (measured
    // 0.26 voxel), SNERT's gradient term keeps it there (0.008).
    EXPECT_GT(sna->surface_mean, 0.2);
    EXPECT_LT(snert->surface_mean, 0.012);
    EXPECT_LT(snert->surface_mean, 0.05 * sna->surface_mean);
    EXPECT_GT(snert->surface_max, snert->surface_mean);
}

TEST(Pipeline, ACopyOfMarchingCubesIsAtDistanceZero) {
    const Phantom sphere = make_phantom("sphere", 32);
    std::vector<MethodResult> results = sphere_comparison(sphere);
    results[1] = results[0];
    results[1].method = Method::Snert;
    measure_against_marching_cubes(results, sphere.volume);
    ASSERT_TRUE(results[1].metrics.to_marching_cubes);
    EXPECT_LT(results[1].metrics.to_marching_cubes->surface_max, 1e-4);
}

TEST(Pipeline, MeasuringIntoTheWorldKeepsEveryFigureUnderAMirror) {
    // The same grid twice: plainly, and mirrored, sheared and anisotropic (as a NIfTI's RAS to
    // LPS can be). Accuracy weights by world areas, which a mirror keeps; the world mesh must be
    // mesh_to_world's, wound outward. (An earlier measure() refused the mirrored one: its area
    // weights came from a world copy whose flipped triangles were no longer the index mesh's.)
    const Phantom sphere = make_phantom("sphere", 24);
    Volume mirrored = sphere.volume;
    mirrored.spacing = {0.5f, 1.0f, 2.0f};
    mirrored.direction = glm::mat3(glm::vec3(-1, 0, 0), glm::vec3(0.2f, 1, 0), glm::vec3(0, 0, 1));
    mirrored.origin = {100.0f, -20.0f, 3.0f};
    const Mesh index_mesh = marching_cubes(sphere.volume, {sphere.iso, InsideIs::Above});
    MeasureOptions what;
    what.reference_volume = sphere.reference_volume;

    Mesh plain = index_mesh;
    const MethodMetrics p =
        measure_into_world(plain, sphere.volume, sphere.reference_distance, what);
    Mesh world = index_mesh;
    const MethodMetrics m = measure_into_world(world, mirrored, sphere.reference_distance, what);

    const Mesh expected = mesh_to_world(index_mesh, mirrored);
    EXPECT_EQ(world.positions, expected.positions);
    EXPECT_EQ(world.indices, expected.indices);
    EXPECT_GT(m.volume, 0.0) << "wound outward in the world";
    EXPECT_NEAR(m.volume, enclosed_volume(expected), 1e-9 * m.volume);
    EXPECT_NEAR(m.area, surface_area(expected), 1e-9 * m.area);
    ASSERT_TRUE(p.accuracy && m.accuracy);
    // In index space the two are one mesh; only the surface weights see the world's areas.
    EXPECT_EQ(m.accuracy->vertices_mean, p.accuracy->vertices_mean);
    EXPECT_EQ(m.accuracy->faces_max, p.accuracy->faces_max);
    EXPECT_EQ(m.accuracy->surface_max, p.accuracy->surface_max);
    EXPECT_NE(m.accuracy->surface_mean, p.accuracy->surface_mean); // anisotropic areas
    EXPECT_EQ(m.volume_error, p.volume_error);
    EXPECT_EQ(m.topology.euler, p.topology.euler);
    EXPECT_TRUE(m.topology.watertight && m.topology.oriented);
    // The smoothness of each world mesh as measured alone, bit for bit.
    EXPECT_EQ(m.smoothness, smoothness(expected));
    EXPECT_EQ(p.smoothness, smoothness(mesh_to_world(index_mesh, sphere.volume)));
    EXPECT_EQ(m.self_intersections, 0u);
    EXPECT_TRUE(m.fe_ready);
    // measure() of the index mesh is the same measurement.
    const MethodMetrics again = measure(index_mesh, mirrored, sphere.reference_distance, what);
    EXPECT_EQ(again.accuracy->surface_mean, m.accuracy->surface_mean);
    EXPECT_EQ(again.area, m.area);
}

TEST(Pipeline, NetsKeepTheirMeshesWhenMeasuredAgainstMarchingCubes) {
    // The distance to MC borrows each net's triangles for its index-space copy: they come back.
    const Phantom sphere = make_phantom("sphere", 32);
    std::vector<MethodResult> results = sphere_comparison(sphere);
    std::vector<Mesh> before;
    for (const MethodResult& r : results) before.push_back(r.mesh);
    measure_against_marching_cubes(results, sphere.volume);
    for (std::size_t i = 0; i < results.size(); ++i) {
        EXPECT_EQ(results[i].mesh.positions, before[i].positions);
        EXPECT_EQ(results[i].mesh.indices, before[i].indices);
    }
    // And each net's figure is distance_to_mesh()'s.
    const std::optional<Accuracy> direct =
        distance_to_mesh(results[2].mesh, results[0].mesh, sphere.volume);
    ASSERT_TRUE(direct && results[2].metrics.to_marching_cubes);
    EXPECT_EQ(direct->surface_mean, results[2].metrics.to_marching_cubes->surface_mean);
    EXPECT_EQ(direct->vertices_max, results[2].metrics.to_marching_cubes->vertices_max);
}

TEST(Pipeline, NothingToMeasureWithoutMarchingCubes) {
    const Phantom sphere = make_phantom("sphere", 32);
    std::vector<MethodResult> results = sphere_comparison(sphere);
    results.erase(results.begin());
    measure_against_marching_cubes(results, sphere.volume);
    for (const MethodResult& r : results) EXPECT_FALSE(r.metrics.to_marching_cubes);
}

} // namespace
} // namespace snert

namespace snert {
namespace {

// A whole comparison on a real-looking volume (the noisy sphere: slivers, refused moves) gives
// the same meshes and numbers with one thread as with one per core.
TEST(Pipeline, ResultsDoNotDependOnTheThreadCount) {
    const Phantom noisy = make_phantom("noisy-sphere", 40);
    auto run = [&](unsigned threads) {
        const ThreadLimit limit(threads);
        std::vector<MethodResult> results = sphere_comparison(noisy);
        measure_against_marching_cubes(results, noisy.volume);
        return results;
    };
    const std::vector<MethodResult> one = run(1), all = run(0);
    ASSERT_EQ(one.size(), all.size());
    for (std::size_t m = 0; m < one.size(); ++m) {
        SCOPED_TRACE(std::string(name_of(one[m].method)));
        EXPECT_EQ(one[m].mesh.positions, all[m].mesh.positions);
        EXPECT_EQ(one[m].mesh.indices, all[m].mesh.indices);
        EXPECT_EQ(one[m].metrics.quality.mean, all[m].metrics.quality.mean);
        EXPECT_EQ(one[m].metrics.smoothness, all[m].metrics.smoothness);
        EXPECT_EQ(one[m].metrics.shortened_moves, all[m].metrics.shortened_moves);
        if (one[m].metrics.to_marching_cubes) {
            EXPECT_EQ(one[m].metrics.to_marching_cubes->surface_mean,
                      all[m].metrics.to_marching_cubes->surface_mean);
        }
    }
}

// The first-order distance keeps the last cell's corners per thread: a second function, for a
// volume made after the first one is gone (and so perhaps at its address), must not read them.
TEST(Pipeline, FirstOrderDistanceNeverReadsAnotherVolumesCell) {
    const glm::vec3 p(3.25f, 2.5f, 4.75f);
    const auto distance_with = [&](float slope, float shift) {
        Volume v = make_volume({8, 8, 8});
        for (int z = 0; z < 8; ++z)
            for (int y = 0; y < 8; ++y)
                for (int x = 0; x < 8; ++x)
                    v.samples[v.index(x, y, z)] = slope * (float(x) - shift);
        return first_order_distance(std::make_shared<const Volume>(std::move(v)), 0.0f)(p);
    };
    // |I - iso| / |grad I| of I = slope (x - shift) is |x - shift|; the sample point is in the
    // same cell both times.
    EXPECT_FLOAT_EQ(distance_with(1.0f, 0.0f), 3.25f);
    EXPECT_FLOAT_EQ(distance_with(2.0f, 1.0f), 2.25f);
    // Two volumes alive at once, asked in turn from one thread.
    Volume a = make_volume({8, 8, 8}, 1.0f), b = make_volume({8, 8, 8});
    for (std::size_t i = 0; i < b.samples.size(); ++i) b.samples[i] = float(i % 8);
    const DistanceFunction to_a = first_order_distance(std::make_shared<const Volume>(a), 0.0f);
    const DistanceFunction to_b = first_order_distance(std::make_shared<const Volume>(b), 0.0f);
    for (int k = 0; k < 3; ++k) {
        EXPECT_EQ(to_a(p), 0.0f) << "a flat volume has no gradient";
        EXPECT_FLOAT_EQ(to_b(p), 3.25f);
    }
}

TEST(Parallel, ThreadLimitsNestAndComeBack) {
    const unsigned cores = thread_budget();
    {
        const ThreadLimit one(1);
        EXPECT_EQ(thread_budget(), 1u);
        {
            const ThreadLimit none(0);
            EXPECT_EQ(thread_budget(), cores);
        }
        EXPECT_EQ(thread_budget(), 1u);
        // Another thread has its own limit: one per core.
        unsigned other = 0;
        std::thread([&] { other = thread_budget(); }).join();
        EXPECT_EQ(other, cores);
    }
    EXPECT_EQ(thread_budget(), cores);
}

} // namespace
} // namespace snert
