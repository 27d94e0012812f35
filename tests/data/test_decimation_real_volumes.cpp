// Decimation on real scans: MC's and SNERT's meshes reduced towards 5 % of their triangles
// stay FE-ready (manifold, open only at the volume border, no self-intersection, no zero-area
// triangle), and the reduction gets at least as far as measured. Skipped without the data.
#include <gtest/gtest.h>

#include <cstdio>

#include "core/decimation.h"
#include "core/pipeline.h"
#include "io/load_volume.h"
#include "support/real_data.h"

using namespace snert;

namespace {

struct DecimationCase {
    const char* file;
    float iso;
    // Largest share of the triangles left when a twentieth is asked: measured 0.050 on the
    // carotid (both methods: the target) and 0.062 (both) on the 4 mm head, whose thin parts
    // pinch under meshoptimizer's collapses (it has no link condition), so patches of them stay
    // as they were. Asked a tenth, the head had stopped at 0.164 when refused regions were frozen
    // instead of halved, and at 0.306 of a quarter before patches and specks (decimation.h).
    double reached;
    // Skipped under the sanitizers (SNERT_LARGE_VOLUMES=0), where the head's 1 700 refused tries
    // take 100 s; `make test` runs it in the optimized build (18 s).
    bool slow = false;
};

class DecimationOnRealVolume : public ::testing::TestWithParam<DecimationCase> {};

TEST_P(DecimationOnRealVolume, StaysFeReady) {
    SNERT_REQUIRE_DATA();
    const DecimationCase& c = GetParam();
    if (c.slow && SNERT_LARGE_VOLUMES == 0)
        GTEST_SKIP() << c.file
                     << " is too slow under the sanitizers; `make test` runs it in an "
                        "optimized build";
    const Volume volume = load_volume(test::data_file(c.file));
    PipelineOptions options;
    options.iso = c.iso;
    options.relax.max_iterations = 20;
    const DistanceFunction reference =
        first_order_distance(std::make_shared<const Volume>(volume), c.iso);
    for (const Method method : {Method::MarchingCubes, Method::Snert}) {
        SCOPED_TRACE(std::string(name_of(method)));
        const MethodResult full = run_method(method, volume, nullptr, options, reference);
        ASSERT_TRUE(full.metrics.fe_ready);
        DecimationOptions d_options;
        d_options.target_triangles = full.mesh.triangle_count() / 20;
        const Decimated d = decimate(full.mesh, d_options);
        EXPECT_EQ(d.report.achieved, d.mesh.triangle_count());
        std::printf("%s: %zu -> %zu triangles (%.3f), %zu specks removed\n",
                    std::string(name_of(method)).c_str(), full.mesh.triangle_count(),
                    d.report.achieved,
                    double(d.report.achieved) / double(full.mesh.triangle_count()),
                    d.report.vanished_components);
        EXPECT_LE(double(d.report.achieved), c.reached * double(full.mesh.triangle_count()));
        EXPECT_EQ(d.report.stalled, d.report.achieved > d_options.target_triangles);
        Mesh index = d.mesh;
        for (glm::vec3& p : index.positions) p = world_to_index(volume, p);
        const MethodMetrics m = measure(index, volume, reference);
        EXPECT_TRUE(m.topology.manifold);
        EXPECT_EQ(m.boundary_edges_off_border, 0u) << "a hole opened inside the volume";
        EXPECT_EQ(m.self_intersections, 0u);
        EXPECT_EQ(m.quality.degenerate, 0u);
        EXPECT_TRUE(m.fe_ready);
    }
}

INSTANTIATE_TEST_SUITE_P(SharedData, DecimationOnRealVolume,
                         ::testing::Values(DecimationCase{"carotid.vtk", 190.0f, 0.051},
                                           DecimationCase{"HeadMRVolume.mhd", 40.0f, 0.065, true}),
                         [](const auto& param_info) {
                             return std::string(param_info.param.file).substr(0, 7);
                         });

} // namespace
