// The slice view's geometry (no GL): fitting a window with the samples' aspect, the way back
// from the screen, and picking a node.
#include <gtest/gtest.h>

#include "core/phantom.h"
#include "core/segmentation.h"
#include "render/slice_view.h"

using namespace snert;
using namespace snert::render;

TEST(SliceView, MappingFitsTheWindowWithTheSamplesAspect) {
    SliceScene scene;
    scene.plane = {SliceAxis::Coronal, 3};
    scene.size = {10, 20};
    scene.spacing = {1.0f, 2.0f}; // v samples twice as far apart
    const SliceWindow window = whole_slice(scene.size);
    const SliceMapping m = map_slice(ImVec2(0, 0), ImVec2(400, 400), scene, window);
    // 10 x 40 world units in 400 x 400 pixels: 10 pixels per unit, v upwards on coronal.
    EXPECT_FLOAT_EQ(m.scale.x, 10.0f);
    EXPECT_FLOAT_EQ(m.scale.y, -20.0f);
    const ImVec2 centre = m.to_screen(window.min + 0.5f * window.size);
    EXPECT_FLOAT_EQ(centre.x, 200.0f);
    EXPECT_FLOAT_EQ(centre.y, 200.0f);
    const glm::vec2 back = m.to_slice(m.to_screen({3.25f, 7.5f}));
    EXPECT_NEAR(back.x, 3.25f, 1e-5f);
    EXPECT_NEAR(back.y, 7.5f, 1e-5f);
    EXPECT_FLOAT_EQ(m.pixels_per_sample(), 10.0f);
    // Axial slices run v downwards (image rows).
    scene.plane.axis = SliceAxis::Axial;
    EXPECT_GT(map_slice(ImVec2(0, 0), ImVec2(400, 400), scene, window).scale.y, 0.0f);
    // A window of 2 x 2 cells zooms far enough for the cell picture.
    EXPECT_GE(map_slice(ImVec2(0, 0), ImVec2(400, 400), scene, window_around({5, 5}, 2.0f))
                  .pixels_per_sample(),
              kCellDetailPixels);
}

TEST(SliceView, PicksTheNearestNodeOfTheLayer) {
    const Phantom p = make_phantom("small-sphere");
    const SurfaceNet net = build_surface_net(segment_threshold(p.volume, p.iso));
    SliceScene scene;
    scene.plane = {SliceAxis::Axial, 5};
    scene.size = {12, 12};
    scene.net = {Method::Snert, &net, net.positions, net_in_slice(net, scene.plane)};
    const SliceMapping m =
        map_slice(ImVec2(0, 0), ImVec2(600, 600), scene, whole_slice(scene.size));
    const std::uint32_t node = scene.net.layer.nodes[3];
    const ImVec2 at = m.to_screen(index_to_slice(SliceAxis::Axial, net.positions[node]));
    EXPECT_EQ(pick_slice_node(scene, m, ImVec2(at.x + 2, at.y - 1), 8.0f), node);
    EXPECT_FALSE(pick_slice_node(scene, m, ImVec2(300, 300), 8.0f).has_value()); // the middle
}
