#include <gtest/gtest.h>

#include "core/marching_cubes.h"
#include "core/phantom.h"
#include "core/ray_pick.h"

using namespace snert;

TEST(RayPick, FirstHitOnTheSmallSphere) {
    const Phantom p = make_phantom("small-sphere");
    const Mesh mc = marching_cubes(p.volume, {p.iso, InsideIs::Above});
    // From outside along -x through the centre (5.6, 5.45, 5.3): the near side at x = 9.6.
    const auto hit = first_hit(mc, {20.0f, 5.45f, 5.3f}, {-1.0f, 0.0f, 0.0f});
    ASSERT_TRUE(hit.has_value());
    EXPECT_NEAR(hit->point.x, 9.6f, 0.1f);
    EXPECT_NEAR(hit->t, 20.0f - hit->point.x, 1e-4f);
    EXPECT_LT(glm::length(mc.positions[hit->nearest_vertex] - hit->point), 1.0f);
    // Pointing away, or passing beside it: nothing.
    EXPECT_FALSE(first_hit(mc, {20.0f, 5.45f, 5.3f}, {1.0f, 0.0f, 0.0f}).has_value());
    EXPECT_FALSE(first_hit(mc, {20.0f, 30.0f, 5.3f}, {-1.0f, 0.0f, 0.0f}).has_value());
}
