// Decimation on real scans: MC's and SNERT's meshes reduced towards a tenth of their triangles
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
    // Largest share of the triangles left when a tenth is asked: measured 0.100 on the carotid
    // (both methods: the target), 0.100 (MC: the target) and 0.164 (SNERT) on the 4 mm head,
    // whose thin parts pinch under meshoptimizer's collapses (it has no link condition). Before
    // patches and specks (decimation.h), a quarter asked stopped at 0.25 and 0.306 there.
    double reached;
};

class DecimationOnRealVolume : public ::testing::TestWithParam<DecimationCase> {};

TEST_P(DecimationOnRealVolume, StaysFeReady) {
    SNERT_REQUIRE_DATA();
    const DecimationCase& c = GetParam();
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
        d_options.target_triangles = full.mesh.triangle_count() / 10;
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
                         ::testing::Values(DecimationCase{"carotid.vtk", 190.0f, 0.101},
                                           DecimationCase{"HeadMRVolume.mhd", 40.0f, 0.17}),
                         [](const auto& param_info) {
                             return std::string(param_info.param.file).substr(0, 7);
                         });

} // namespace
