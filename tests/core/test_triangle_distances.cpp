// The per-triangle distances the views colour by (core/triangle_distances.h), against geometry
// whose distances are known: a sphere (the exact signed distance) and a plane moved by a known
// offset.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "core/marching_cubes.h"
#include "core/mesh.h"
#include "core/phantom.h"
#include "core/triangle_distances.h"

namespace snert {
namespace {

// A sphere of radius 8 around a centre off the grid, values r - |q - c| (inside above 0), on an
// anisotropic grid so that the world -> index map matters.
constexpr float kRadius = 8.0f;
const glm::vec3 kCentre(11.3f, 11.6f, 11.45f);

Volume sphere_volume(float sign = 1.0f) {
    Volume v = make_volume(glm::ivec3(24));
    v.spacing = glm::vec3(1.5f, 1.0f, 2.0f);
    v.origin = glm::vec3(-3.0f, 4.0f, 1.0f);
    for (int z = 0; z < 24; ++z)
        for (int y = 0; y < 24; ++y)
            for (int x = 0; x < 24; ++x)
                v.samples[v.index(x, y, z)] =
                    sign * (kRadius - glm::length(glm::vec3(x, y, z) - kCentre));
    return v;
}

glm::vec3 index_centroid(const Mesh& world, const Volume& v, std::size_t t) {
    const std::uint32_t* i = &world.indices[3 * t];
    return (world_to_index(v, world.positions[i[0]]) + world_to_index(v, world.positions[i[1]]) +
            world_to_index(v, world.positions[i[2]])) /
           3.0f;
}

TEST(TriangleDistances, SignedIsoDistanceOfTheSphereMatchesTheExactSignedDistance) {
    const Volume v = sphere_volume();
    const Mesh world = mesh_to_world(marching_cubes(v, {0.0f, InsideIs::Above}), v);
    ASSERT_GT(world.triangle_count(), 1000u);
    const std::vector<float> d = signed_iso_distances(world, v, 0.0f, InsideIs::Above);
    ASSERT_EQ(d.size(), world.triangle_count());
    double sum = 0, exact_sum = 0, worst = 0;
    std::size_t inside = 0;
    for (std::size_t t = 0; t < d.size(); ++t) {
        // The exact signed distance of the centroid: negative inside the sphere.
        const float exact = glm::length(index_centroid(world, v, t) - kCentre) - kRadius;
        worst = std::max(worst, double(std::abs(d[t] - exact)));
        sum += d[t];
        exact_sum += exact;
        if (exact < 0.0f) ++inside;
        // Small, and of the exact distance's sign where that is not within rounding of 0.
        EXPECT_LT(std::abs(d[t]), 0.2f) << t;
        if (std::abs(exact) > 0.02f) {
            EXPECT_EQ(d[t] < 0.0f, exact < 0.0f) << t;
        }
    }
    // First order on a trilinear field: off the exact distance by the curvature's share only
    // (measured: 0.031 at worst).
    EXPECT_LT(worst, 0.04);
    // Marching Cubes' chords cut inside a convex surface: every centroid lies inside, and the
    // mean is negative. Measured: -0.0047 voxel, the exact -0.028 (the trilinear iso-surface,
    // which the first order measures to, lies itself about 0.02 inside the sphere).
    EXPECT_EQ(inside, d.size());
    const double mean = sum / double(d.size());
    EXPECT_LT(mean, -0.003);
    EXPECT_GT(mean, -0.02);
    EXPECT_NEAR(mean, exact_sum / double(d.size()), 0.03);
}

TEST(TriangleDistances, SignFollowsWhichSideIsInside) {
    // The same sphere as a dark object (inside below): the same distances, outside still +.
    const Volume bright = sphere_volume(1.0f), dark = sphere_volume(-1.0f);
    const Mesh world = mesh_to_world(marching_cubes(bright, {0.0f, InsideIs::Above}), bright);
    const std::vector<float> a = signed_iso_distances(world, bright, 0.0f, InsideIs::Above);
    const std::vector<float> b = signed_iso_distances(world, dark, 0.0f, InsideIs::Below);
    ASSERT_EQ(a.size(), b.size());
    for (std::size_t t = 0; t < a.size(); ++t) EXPECT_FLOAT_EQ(a[t], b[t]) << t;
}

TEST(TriangleDistances, DistanceToAPlaneMovedByHalfAVoxel) {
    Phantom plane = make_plane_phantom(16, glm::vec3(0, 0, 1), glm::vec3(7.5f, 7.5f, 6.3f));
    plane.volume.spacing = glm::vec3(1.0f, 1.0f, 2.0f);
    const Mesh world =
        mesh_to_world(marching_cubes(plane.volume, {plane.iso, InsideIs::Above}), plane.volume);
    ASSERT_GT(world.triangle_count(), 100u);
    Mesh moved = world;
    for (glm::vec3& p : moved.positions) p.z += 1.0f; // half a voxel along z (spacing 2)
    const std::vector<float> d = distances_to_other_mesh(world, moved, plane.volume);
    ASSERT_EQ(d.size(), world.triangle_count());
    for (const float x : d) EXPECT_NEAR(x, 0.5f, 1e-4f);
    // Against itself: 0 everywhere; against nothing: not measured.
    for (const float x : distances_to_other_mesh(world, world, plane.volume))
        EXPECT_NEAR(x, 0.0f, 1e-5f);
    for (const float x : distances_to_other_mesh(world, Mesh{}, plane.volume))
        EXPECT_TRUE(std::isnan(x));
}

TEST(TriangleDistances, PairDistancesMeasureEachMeshAgainstTheOther) {
    Phantom plane = make_plane_phantom(16, glm::vec3(0, 0, 1), glm::vec3(7.5f, 7.5f, 6.3f));
    const Mesh world =
        mesh_to_world(marching_cubes(plane.volume, {plane.iso, InsideIs::Above}), plane.volume);
    Mesh moved = world;
    for (glm::vec3& p : moved.positions) p.z += 0.3f;
    const PairDistances other = pair_distances(ShapeMeasure::DistanceOther, world, moved,
                                               plane.volume, plane.iso, InsideIs::Above);
    ASSERT_EQ(other.first.size(), world.triangle_count());
    ASSERT_EQ(other.second.size(), moved.triangle_count());
    EXPECT_NEAR(other.first_summary.mean, 0.3, 1e-4);
    EXPECT_NEAR(other.second_summary.mean, 0.3, 1e-4);
    // 0.3 on the range [0, 0.5]: every triangle in bin 12 of 20.
    EXPECT_FLOAT_EQ(other.scale.low, 0.0f);
    EXPECT_FLOAT_EQ(other.scale.high, 0.5f);
    EXPECT_FALSE(other.scale.diverging);
    EXPECT_EQ(other.first_summary.histogram[11], world.triangle_count());

    // To the iso-surface: the plane's own mesh lies on it (0), the moved one 0.3 outside
    // (above the plane, where the phantom is outside).
    const PairDistances iso = pair_distances(ShapeMeasure::DistanceIso, world, moved, plane.volume,
                                             plane.iso, InsideIs::Above);
    EXPECT_NEAR(iso.first_summary.mean, 0.0, 1e-4);
    EXPECT_NEAR(std::abs(iso.second_summary.mean), 0.3, 1e-3);
    EXPECT_TRUE(iso.scale.diverging);
    EXPECT_FLOAT_EQ(iso.scale.low, -iso.scale.high);
    // A shape measure is not a distance: nothing measured.
    EXPECT_TRUE(pair_distances(ShapeMeasure::Quality, world, moved, plane.volume, plane.iso,
                               InsideIs::Above)
                    .first.empty());
}

TEST(TriangleDistances, ScaleRoundsTheFarthestUpToOneTwoOrFive) {
    const auto high = [](std::vector<float> values) {
        return distance_scale(ShapeMeasure::DistanceOther, values, {}).high;
    };
    EXPECT_FLOAT_EQ(high({0.013f}), 0.02f);
    EXPECT_FLOAT_EQ(high({0.25f}), 0.5f);
    EXPECT_FLOAT_EQ(high({0.7f}), 1.0f);
    EXPECT_FLOAT_EQ(high({3.0f}), 5.0f);
    EXPECT_FLOAT_EQ(high({0.0f}), 0.001f);
    EXPECT_FLOAT_EQ(high({}), 0.001f);
    // The 98th percentile: one far triangle in a hundred does not set the range.
    std::vector<float> many(99, 0.04f);
    many.push_back(9.0f);
    EXPECT_FLOAT_EQ(high(many), 0.05f);
    // Signed: the magnitude, both ways; NaN left out.
    const MeasureScale s = distance_scale(ShapeMeasure::DistanceIso, std::vector<float>{-0.3f},
                                          std::vector<float>{std::nanf("")});
    EXPECT_FLOAT_EQ(s.low, -0.5f);
    EXPECT_FLOAT_EQ(s.high, 0.5f);
    EXPECT_TRUE(s.diverging);
    EXPECT_EQ(s.unit, "voxels");
}

TEST(TriangleDistances, SummaryBinsOverTheScale) {
    const MeasureScale scale{-0.5f, 0.5f, true, "voxels"};
    const std::vector<float> values = {-2.0f, -0.49f, 0.0f, 0.26f, 0.5f, 7.0f, std::nanf("")};
    const MeasureSummary s = summarize_measure(values, scale);
    EXPECT_EQ(s.histogram[0], 2u);  // below the range, and its first bin
    EXPECT_EQ(s.histogram[10], 1u); // 0 starts the 11th bin
    EXPECT_EQ(s.histogram[15], 1u); // 0.26
    EXPECT_EQ(s.histogram[19], 2u); // the top and beyond
    EXPECT_NEAR(s.mean, (-2.0 - 0.49 + 0.0 + 0.26 + 0.5 + 7.0) / 6.0, 1e-6); // NaN left out
}

} // namespace
} // namespace snert
