// The SurfaceNet and its relaxation on every real volume of the shared data folder: the mesh a
// finite-element mesher gets must be manifold, free of self-intersections and of slivers, and
// the relaxation must settle. Skipped, saying why, when the folder is absent.
#include <gtest/gtest.h>

#include <functional>
#include <string>

#include "core/volume_stats.h"
#include "io/load_volume.h"
#include "io/raw_volume.h"
#include "core/marching_cubes.h"
#include "core/metrics.h"
#include "core/pipeline.h"
#include "support/real_data.h"

using namespace snert;

namespace {

using test::data_file;

struct RealVolume {
    std::string name;
    Volume grey;
    Segmentation segmentation;
    float iso = 0.0f;
    InsideIs inside = InsideIs::Above;
};

struct RealCase {
    std::string name;
    std::function<RealVolume()> load;
    double max_sliver_share; // slivers (q < 0.1) of the relaxed SNERT mesh
    bool large = false;      // skipped under the sanitizers (see tests/CMakeLists.txt)
};

RealVolume grey_case(const std::string& name, Volume grey, float iso) {
    RealVolume v{name, std::move(grey), {}, iso};
    v.segmentation = segment_threshold(v.grey, iso);
    return v;
}

std::vector<RealCase> real_cases() {
    const auto file = [](const std::string& relative, float iso) {
        return [=] { return grey_case(relative, load_volume(data_file(relative)), iso); };
    };
    // The DICOM head's 4.8 mm slices make the net's quads 1 x 4.8 mm, and where pieces share a
    // cell their first triangles are slivers already (1.4 %); the relaxation lifts them.
    return {
        {"FLAIR.nrrd", file("FLAIR.nrrd", 40.0f), 0.001, true},
        {"HeadMRVolume.mhd", file("HeadMRVolume.mhd", 40.0f), 0.001},
        {"carotid.vtk", file("carotid.vtk", 190.0f), 0.001},
        {"dicom_mr_head_t1_sag", file("dicom_mr_head_t1_sag", 200.0f), 0.001, true},
        {"example_ct_sm.nii.gz", file("totalseg_ct_abdomen/example_ct_sm.nii.gz", 200.0f), 0.001},
        {"headsq",
         [] {
             RawOptions raw;
             raw.dims = {64, 64, 93};
             raw.type = ScalarType::UInt16;
             raw.spacing = {3.2f, 3.2f, 1.5f};
             return grey_case("headsq", load_raw(data_file("headsq/quarter.1"), raw), 1150.0f);
         },
         0.001},
        {"liver label",
         [] {
             RealVolume v;
             v.name = "liver label";
             v.grey = load_volume(data_file("totalseg_ct_abdomen/example_ct_sm.nii.gz"));
             v.segmentation =
                 segment_label(load_volume(data_file("totalseg_ct_abdomen/example_seg.nii.gz")), 5);
             const BoundaryIso boundary = boundary_iso(v.grey, v.segmentation);
             v.iso = boundary.iso;
             v.inside = boundary.inside;
             return v;
         },
         0.001},
    };
}

class NetOnRealVolume : public ::testing::TestWithParam<RealCase> {
  protected:
    void SetUp() override {
        SNERT_REQUIRE_DATA();
        if (GetParam().large && SNERT_LARGE_VOLUMES == 0)
            GTEST_SKIP() << GetParam().name
                         << " is too slow under the sanitizers; `make test` runs it in an "
                            "optimized build";
    }
};

std::string case_name(const ::testing::TestParamInfo<RealCase>& info) {
    std::string name;
    for (char c : info.param.name) name += std::isalnum(static_cast<unsigned char>(c)) ? c : '_';
    return name;
}

} // namespace

TEST_P(NetOnRealVolume, InitialNetIsTheDualOfMarchingCubes) {
    const RealVolume v = GetParam().load();
    const SurfaceNet net = build_surface_net(v.segmentation);
    const Topology t = topology(triangulate(net, net.positions));
    EXPECT_EQ(t.nonmanifold_edges, 0u);
    EXPECT_EQ(t.nonmanifold_vertices, 0u);
    EXPECT_TRUE(t.oriented);
    EXPECT_TRUE(t.manifold);
    // Marching Cubes of the same segmentation (on its mask, so samples at iso do not matter).
    const Volume mask = mask_volume(v.segmentation, v.grey);
    const Topology mc = topology(marching_cubes(mask, {0.5f, InsideIs::Above}));
    EXPECT_EQ(t.watertight, mc.watertight);
    // Also where the surface leaves the volume (open there): the border bridges keep it.
    EXPECT_EQ(t.euler, mc.euler);
}

namespace {

void expect_fe_ready(const MethodMetrics& m) {
    EXPECT_EQ(m.self_intersections, 0u);
    EXPECT_EQ(m.topology.nonmanifold_edges, 0u);
    EXPECT_EQ(m.topology.nonmanifold_vertices, 0u);
    EXPECT_EQ(m.quality.degenerate, 0u);
    EXPECT_TRUE(m.fe_ready);
}

PipelineOptions options_for(const RealVolume& v, RelaxMode mode) {
    PipelineOptions options;
    options.iso = v.iso;
    options.inside = v.inside;
    options.relax.iso = v.iso;
    options.relax.mode = mode;
    return options;
}

} // namespace

// SNERT run to rest (the app's "run to convergence", with the 0.01 voxel): it settles
// within 200 iterations, and the mesh it ends with is FE-ready with (almost) no slivers.
TEST_P(NetOnRealVolume, SnertSettlesWithin200IterationsIntoAnFeReadyMesh) {
    const RealVolume v = GetParam().load();
    PipelineOptions options = options_for(v, RelaxMode::Snert);
    options.relax.max_iterations = 200;
    options.relax.epsilon = 0.01f;
    const MethodResult r = run_surface_net(v.grey, v.segmentation, options, {});
    EXPECT_TRUE(r.metrics.converged) << r.metrics.final_max_move;
    EXPECT_LE(r.metrics.iterations, 200);
    expect_fe_ready(r.metrics);
    EXPECT_LE(double(r.metrics.quality.slivers) / double(r.metrics.triangles),
              GetParam().max_sliver_share);
}

// The other two modes, a few iterations each: the same guarantees.
TEST_P(NetOnRealVolume, SnaAndGradientMeshesAreFeReady) {
    const RealVolume v = GetParam().load();
    for (RelaxMode mode : {RelaxMode::Averaging, RelaxMode::Gradient}) {
        PipelineOptions options = options_for(v, mode);
        options.relax.max_iterations = 8;
        const MethodResult r = run_surface_net(v.grey, v.segmentation, options, {});
        SCOPED_TRACE(std::string(name_of(r.method)));
        expect_fe_ready(r.metrics);
    }
}

INSTANTIATE_TEST_SUITE_P(SharedData, NetOnRealVolume, ::testing::ValuesIn(real_cases()), case_name);
