// Picking a triangle with a ray, and a triangle's angles.
#include <gtest/gtest.h>

#include <cmath>

#include "core/marching_cubes.h"
#include "core/phantom.h"
#include "core/triangle_pick.h"

using namespace snert;

namespace {

// Two unit squares of two triangles each, one at z = 0 and one at z = 2.
Mesh two_layers() {
    Mesh m;
    for (float z : {0.0f, 2.0f}) {
        const auto base = std::uint32_t(m.positions.size());
        m.positions.insert(m.positions.end(), {{0, 0, z}, {1, 0, z}, {1, 1, z}, {0, 1, z}});
        m.indices.insert(m.indices.end(), {base, base + 1, base + 2, base, base + 2, base + 3});
    }
    return m;
}

} // namespace

TEST(TrianglePick, NearestTriangleAlongTheRay) {
    const Mesh m = two_layers();
    // From above: the z = 2 layer first; (0.8, 0.2) lies in the first triangle of a square.
    auto hit = first_hit(m, {0.8f, 0.2f, 5.0f}, {0, 0, -1});
    ASSERT_TRUE(hit);
    EXPECT_EQ(hit->triangle, 2u);
    EXPECT_FLOAT_EQ(hit->distance, 3.0f);
    EXPECT_NEAR(glm::distance(hit->point, glm::vec3(0.8f, 0.2f, 2.0f)), 0.0f, 1e-6f);
    // From below: the z = 0 layer, the second triangle for (0.2, 0.8); back faces count.
    hit = first_hit(m, {0.2f, 0.8f, -1.0f}, {0, 0, 2});
    ASSERT_TRUE(hit);
    EXPECT_EQ(hit->triangle, 1u);
    EXPECT_FLOAT_EQ(hit->distance, 0.5f);
    // Between the layers, looking up: only z = 2 is ahead.
    hit = first_hit(m, {0.8f, 0.2f, 1.0f}, {0, 0, 1});
    ASSERT_TRUE(hit);
    EXPECT_EQ(hit->triangle, 2u);
    // Beside the squares, parallel to them, or no direction: nothing.
    EXPECT_FALSE(first_hit(m, {1.5f, 0.5f, 5.0f}, {0, 0, -1}));
    EXPECT_FALSE(first_hit(m, {0.5f, 0.5f, 1.0f}, {1, 0, 0}));
    EXPECT_FALSE(first_hit(m, {0.5f, 0.5f, 5.0f}, {0, 0, 0}));
}

TEST(TrianglePick, AnglesOfKnownTriangles) {
    const auto right = triangle_angles({0, 0, 0}, {1, 0, 0}, {0, 1, 0});
    EXPECT_NEAR(right[0], 90.0f, 1e-4f);
    EXPECT_NEAR(right[1], 45.0f, 1e-4f);
    EXPECT_NEAR(right[2], 45.0f, 1e-4f);
    const auto thirty = triangle_angles({0, 0, 0}, {std::sqrt(3.0f), 0, 0}, {0, 1, 0});
    EXPECT_NEAR(thirty[1], 30.0f, 1e-4f);
    EXPECT_NEAR(thirty[2], 60.0f, 1e-4f);
    EXPECT_NEAR(thirty[0] + thirty[1] + thirty[2], 180.0f, 1e-4f);
    const auto flat = triangle_angles({0, 0, 0}, {1, 0, 0}, {2, 0, 0});
    EXPECT_EQ(flat[0] + flat[1] + flat[2], 0.0f);
}

TEST(TrianglePick, FirstHitOnTheSmallSphereAndItsNearestCorner) {
    const Phantom p = make_phantom("small-sphere");
    const Mesh mc = marching_cubes(p.volume, {p.iso, InsideIs::Above});
    // From outside along -x through the centre (5.6, 5.45, 5.3): the near side at x = 9.6.
    const auto hit = first_hit(mc, {20.0f, 5.45f, 5.3f}, {-1.0f, 0.0f, 0.0f});
    ASSERT_TRUE(hit.has_value());
    EXPECT_NEAR(hit->point.x, 9.6f, 0.1f);
    EXPECT_NEAR(hit->distance, 20.0f - hit->point.x, 1e-4f);
    EXPECT_LT(glm::length(mc.positions[hit->nearest_vertex] - hit->point), 1.0f);
    // Pointing away, or passing beside it: nothing.
    EXPECT_FALSE(first_hit(mc, {20.0f, 5.45f, 5.3f}, {1.0f, 0.0f, 0.0f}).has_value());
    EXPECT_FALSE(first_hit(mc, {20.0f, 30.0f, 5.3f}, {-1.0f, 0.0f, 0.0f}).has_value());
}
