// The teaching phantoms: small fixed grids, each surface where its reference says, and the one
// property each is there to show (a plate one sample thick, a crease, a plane off the samples).
#include <gtest/gtest.h>

#include <algorithm>
#include <string>

#include "core/marching_cubes.h"
#include "core/metrics.h"
#include "core/phantom.h"
#include "core/segmentation.h"
#include "core/surface_net.h"

using namespace snert;

namespace {

Mesh mc_of(const Phantom& p) {
    return marching_cubes(p.volume, {p.iso, InsideIs::Above});
}

} // namespace

TEST(TeachingPhantoms, SmallGridsWhoseNetFitsOnOneScreen) {
    ASSERT_EQ(teaching_phantom_names().size(), 4u);
    for (const std::string& name : teaching_phantom_names()) {
        SCOPED_TRACE(name);
        EXPECT_TRUE(is_teaching_phantom(name));
        EXPECT_NE(std::find(phantom_names().begin(), phantom_names().end(), name),
                  phantom_names().end());
        // The size argument does not change a teaching phantom's grid.
        const Phantom p = make_phantom(name, 64);
        EXPECT_EQ(p.volume.dims, make_phantom(name, 16).volume.dims);
        EXPECT_LE(std::max({p.volume.dims.x, p.volume.dims.y, p.volume.dims.z}), 15);
        const SurfaceNet net = build_surface_net(segment_threshold(p.volume, p.iso));
        EXPECT_GT(net.node_count(), 40u);
        EXPECT_LT(net.node_count(), 700u);
        // The reference surface is where Marching Cubes finds the iso-surface: MC's vertices lie
        // on grid edges, within a small linear-interpolation error of the exact surface.
        const Mesh mc = mc_of(p);
        ASSERT_GT(mc.triangle_count(), 0u);
        float worst = 0.0f;
        for (const glm::vec3& v : mc.positions) worst = std::max(worst, p.reference_distance(v));
        EXPECT_LT(worst, 0.25f); // measured: 0.22 at the crease, 0.2 at the plate's rim
    }
    EXPECT_FALSE(is_teaching_phantom("sphere"));
}

TEST(TeachingPhantoms, SmallSphereHasRadiusFourAndIsClosed) {
    const Phantom p = make_phantom("small-sphere");
    EXPECT_EQ(p.volume.dims, glm::ivec3(12));
    // The distance map: 4 minus the distance to the centre, so the samples reach nearly 4.
    float top = -1e9f;
    for (float v : p.volume.samples) top = std::max(top, v);
    EXPECT_GT(top, 3.3f); // the nearest sample is 0.67 from the centre
    EXPECT_LE(top, 4.0f);
    const Topology t = topology(mc_of(p));
    EXPECT_TRUE(t.watertight);
    EXPECT_EQ(t.euler, 2);
}

TEST(TeachingPhantoms, ThinPlateIsOneSampleThick) {
    const Phantom p = make_phantom("thin-plate");
    const Segmentation s = segment_threshold(p.volume, p.iso);
    std::size_t inside = 0;
    for (int z = 0; z < p.volume.dims.z; ++z)
        for (int y = 0; y < p.volume.dims.y; ++y)
            for (int x = 0; x < p.volume.dims.x; ++x)
                if (s.inside[p.volume.index(x, y, z)]) {
                    ++inside;
                    EXPECT_EQ(z, 3);
                }
    EXPECT_EQ(inside, 64u); // 8 x 8 samples
    // Both sides of the plate get their own nodes: cells above and below the plate's samples.
    const SurfaceNet net = build_surface_net(s);
    std::size_t below = 0, above = 0;
    for (const glm::ivec3& c : net.cells) {
        below += c.z == 2;
        above += c.z == 3;
    }
    EXPECT_GT(below, 40u);
    EXPECT_GT(above, 40u);
    const Topology t = topology(mc_of(p));
    EXPECT_TRUE(t.watertight);
    EXPECT_EQ(t.euler, 2);
}

TEST(TeachingPhantoms, CreaseJoinsTwoSpheres) {
    const Phantom p = make_phantom("crease");
    // One closed surface (the spheres overlap), with a crease ring of zero reference distance
    // half way between the centres (x = 7.3), radius sqrt(3.5^2 - 2.3^2) around the axis.
    const Topology t = topology(mc_of(p));
    EXPECT_TRUE(t.watertight);
    EXPECT_EQ(t.euler, 2);
    const float ring = std::sqrt(3.5f * 3.5f - 2.3f * 2.3f);
    EXPECT_NEAR(p.reference_distance({7.3f, 5.2f + ring, 5.1f}), 0.0f, 1e-4f);
    EXPECT_NEAR(p.reference_distance({7.3f, 5.2f, 5.1f}), ring, 1e-4f);
    // The crease is a dent: the surface there is nearer the axis than either sphere's equator.
    EXPECT_LT(ring, 3.5f - 0.5f);
    EXPECT_GT(p.volume.at(7, 5, 5), 0.0f); // the waist between the spheres is inside
}

TEST(TeachingPhantoms, TiltedPlanePassesBetweenTheSamples) {
    const Phantom p = make_phantom("tilted-plane");
    EXPECT_EQ(p.volume.dims, glm::ivec3(10));
    for (std::size_t i = 0; i < p.volume.samples.size(); ++i) {
        EXPECT_NE(p.volume.samples[i], 0.0f);
        // The grey value is the signed distance: its size is the reference distance.
        const int x = int(i % 10), y = int(i / 10 % 10), z = int(i / 100);
        EXPECT_NEAR(std::abs(p.volume.samples[i]),
                    p.reference_distance(glm::vec3(float(x), float(y), float(z))), 1e-4f);
    }
}
