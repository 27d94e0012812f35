#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/closed_border.h"
#include "core/pipeline.h"

using namespace snert;

namespace {

// A signed distance (positive inside) of a sphere larger than the grid: it leaves the volume
// through all six faces, so without closing the surfaces are six open cuts; the corners stay
// outside, so the closed surface is one sphere-like piece (Euler characteristic 2).
Volume big_sphere(glm::ivec3 dims, float radius) {
    Volume v = make_volume(dims);
    v.spacing = {0.8f, 1.0f, 2.5f};
    v.origin = {-10.0f, 4.0f, 7.0f};
    const glm::vec3 centre = glm::vec3(dims - 1) * 0.5f;
    for (int z = 0; z < dims.z; ++z)
        for (int y = 0; y < dims.y; ++y)
            for (int x = 0; x < dims.x; ++x)
                v.samples[v.index(x, y, z)] = radius - glm::length(glm::vec3(x, y, z) - centre);
    return v;
}

PipelineOptions options_at(float iso) {
    PipelineOptions o;
    o.iso = iso;
    o.relax.iso = iso;
    o.relax.max_iterations = 30;
    return o;
}

void expect_closed_sphere(const MethodResult& r, const char* what) {
    SCOPED_TRACE(what);
    const MethodMetrics& m = r.metrics;
    EXPECT_GT(m.triangles, 500u);
    EXPECT_TRUE(m.topology.watertight);
    EXPECT_TRUE(m.topology.manifold);
    EXPECT_TRUE(m.topology.oriented);
    EXPECT_EQ(m.topology.boundary_edges, 0u);
    EXPECT_EQ(m.boundary_edges_off_border, 0u);
    EXPECT_EQ(m.topology.euler, 2);
    EXPECT_EQ(m.self_intersections, 0u);
    EXPECT_TRUE(m.fe_ready);
    EXPECT_GT(m.volume, 0.0); // oriented outwards
}

} // namespace

TEST(ClosedBorder, PadValueIsOutsideMirroredAboutIso) {
    EXPECT_EQ(outside_pad_value(130.0f, 100.0f, InsideIs::Above), 70.0f);
    EXPECT_EQ(outside_pad_value(40.0f, 100.0f, InsideIs::Above), 40.0f); // outside: repeated
    EXPECT_EQ(outside_pad_value(70.0f, 100.0f, InsideIs::Below), 130.0f);
    EXPECT_EQ(outside_pad_value(140.0f, 100.0f, InsideIs::Below), 140.0f);
    // A sample at iso counts as inside; its pad must not.
    EXPECT_LT(outside_pad_value(100.0f, 100.0f, InsideIs::Above), 100.0f);
    EXPECT_GT(outside_pad_value(100.0f, 100.0f, InsideIs::Below), 100.0f);
    // Mirroring a huge value would overflow: it stays finite and outside.
    const float big = std::numeric_limits<float>::max();
    const float low = outside_pad_value(big, -big * 0.75f, InsideIs::Above);
    EXPECT_TRUE(std::isfinite(low));
    EXPECT_LT(low, -big * 0.75f);
}

TEST(ClosedBorder, PaddedVolumeKeepsWorldCoordinates) {
    Volume v = big_sphere({5, 4, 3}, 3.0f);
    v.direction = glm::mat3(glm::vec3(0, 1, 0), glm::vec3(-1, 0, 0), glm::vec3(0, 0, 1));
    const float iso = 1.0f;
    const Volume p = pad_outside(v, iso, InsideIs::Above);
    ASSERT_EQ(p.dims, glm::ivec3(7, 6, 5));
    EXPECT_EQ(p.spacing, v.spacing);
    for (const glm::vec3 q : {glm::vec3(0.0f), glm::vec3(4.0f, 3.0f, 2.0f), glm::vec3(1.5f)}) {
        const glm::vec3 a = index_to_world(v, q), b = index_to_world(p, q + 1.0f);
        EXPECT_NEAR(glm::length(a - b), 0.0f, 1e-5f);
    }
    for (int z = 0; z < p.dims.z; ++z)
        for (int y = 0; y < p.dims.y; ++y)
            for (int x = 0; x < p.dims.x; ++x) {
                const bool pad = x == 0 || y == 0 || z == 0 || x == p.dims.x - 1 ||
                                 y == p.dims.y - 1 || z == p.dims.z - 1;
                const float nearest =
                    v.at(std::clamp(x - 1, 0, v.dims.x - 1), std::clamp(y - 1, 0, v.dims.y - 1),
                         std::clamp(z - 1, 0, v.dims.z - 1));
                if (!pad) {
                    EXPECT_EQ(p.at(x, y, z), nearest);
                } else {
                    EXPECT_FALSE(is_inside(p.at(x, y, z), iso, InsideIs::Above));
                    EXPECT_EQ(p.at(x, y, z), outside_pad_value(nearest, iso, InsideIs::Above));
                }
            }
    Segmentation s = segment_threshold(v, iso);
    const Segmentation ps = pad_outside(s);
    ASSERT_EQ(ps.dims, p.dims);
    EXPECT_EQ(ps.count_inside(), s.count_inside());
    EXPECT_EQ(ps.inside, segment_threshold(p, iso).inside);
}

TEST(ClosedBorder, SphereCutByTheBorderIsClosedByBothMethods) {
    const Volume v = big_sphere({20, 18, 16}, 11.0f);
    const PipelineOptions o = options_at(0.0f);
    // Without closing, both surfaces are open where the sphere leaves the grid.
    const MethodResult open_mc = run_method(Method::MarchingCubes, v, nullptr, o, {});
    const MethodResult open_net = run_method(Method::Snert, v, nullptr, o, {});
    EXPECT_FALSE(open_mc.metrics.topology.watertight);
    EXPECT_FALSE(open_net.metrics.topology.watertight);
    EXPECT_GT(open_mc.metrics.topology.boundary_edges, 0u);

    const Volume closed = pad_outside(v, o.iso, o.inside);
    const MethodResult mc = run_method(Method::MarchingCubes, closed, nullptr, o, {});
    const MethodResult net = run_method(Method::Snert, closed, nullptr, o, {});
    const MethodResult sna = run_method(Method::Sna, closed, nullptr, o, {});
    expect_closed_sphere(mc, "Marching Cubes");
    expect_closed_sphere(net, "SNERT");
    expect_closed_sphere(sna, "SNA");
    EXPECT_EQ(mc.metrics.topology.euler, net.metrics.topology.euler);

    // The caps lie where the voxels end: half a voxel beyond the border samples, in world
    // units as before closing (index -0.5 and dims - 0.5 of the original grid).
    glm::vec3 lo(1e9f), hi(-1e9f);
    for (const glm::vec3 w : mc.mesh.positions) {
        const glm::vec3 q = world_to_index(v, w);
        lo = glm::min(lo, q);
        hi = glm::max(hi, q);
    }
    EXPECT_NEAR(glm::length(lo - glm::vec3(-0.5f)), 0.0f, 1e-4f);
    EXPECT_NEAR(glm::length(hi - (glm::vec3(v.dims) - 0.5f)), 0.0f, 1e-4f);
    // The relaxed net's caps are pulled to the same place by the gradient term and kept in
    // their cells: within the outer half voxel.
    for (const glm::vec3 w : net.mesh.positions) {
        const glm::vec3 q = world_to_index(v, w);
        EXPECT_TRUE(glm::all(glm::greaterThanEqual(q, glm::vec3(-1.0f))));
        EXPECT_TRUE(glm::all(glm::lessThanEqual(q, glm::vec3(v.dims))));
    }
    // Enclosed volumes agree to a few percent (world units).
    EXPECT_NEAR(net.metrics.volume / mc.metrics.volume, 1.0, 0.02);
}

TEST(ClosedBorder, DarkObjectAndLabelMaskAreClosedToo) {
    // The same sphere as a dark object (inside below the iso).
    Volume dark = big_sphere({16, 16, 16}, 9.5f);
    for (float& s : dark.samples) s = 100.0f - 10.0f * s;
    PipelineOptions o = options_at(100.0f);
    o.inside = InsideIs::Below;
    const Volume closed = pad_outside(dark, o.iso, o.inside);
    expect_closed_sphere(run_method(Method::MarchingCubes, closed, nullptr, o, {}), "MC, dark");
    expect_closed_sphere(run_method(Method::Snert, closed, nullptr, o, {}), "SNERT, dark");

    // A label's mask padded with outside voxels, the grey values padded for the gradient term.
    const Segmentation mask = segment_threshold(dark, 100.0f, InsideIs::Below);
    const Segmentation closed_mask = pad_outside(mask);
    expect_closed_sphere(run_method(Method::MarchingCubes, closed, &closed_mask, o, {}),
                         "MC, label mask");
    expect_closed_sphere(run_method(Method::Snert, closed, &closed_mask, o, {}),
                         "SNERT, label mask");
}
