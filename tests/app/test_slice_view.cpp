// The app's slice view, driven as a user would: V shows it, PageUp / PageDown pick the slice,
// a click on a node takes its move apart, and the values follow the iteration slider. The
// values shown are checked against the core's relaxation and inspector run here.
#include <gtest/gtest.h>

#include <cstdlib>

#include "app/headless.h"
#include "app/slice_panel.h"
#include "app/shortcuts.h"
#include "core/node_inspection.h"
#include "render/image.h"

using namespace snert;
using namespace snert::app;

namespace {

bool settled(const App& app) {
    const JobResults& r = app.results();
    return r.finished && r.mc && r.frame && r.mc_current && r.frame_current &&
           r.frame->iteration == app.shown_iteration() && r.frame->metrics_complete && r.net &&
           r.net->context;
}

// The core's own numbers for node `node`'s move in iteration k.
NodeInspection core_inspection(const RelaxContext& c, std::uint32_t node, int k) {
    RelaxOptions o = c.options;
    o.max_iterations = k - 1;
    o.epsilon = 0.0f;
    const RelaxResult before = relax(*c.net, c.grey.get(), o);
    std::vector<glm::vec3> after(before.positions.size());
    relax_step(*c.net, c.grey.get(), c.options, k, before.positions, after);
    return inspect_node(*c.net, c.grey.get(), c.options, k, before.positions, after, node);
}

} // namespace

TEST(AppSliceView, PicksASliceAndANodeWhoseMoveFollowsTheIteration) {
    HeadlessOptions options;
    options.width = 1280;
    options.height = 800;
    options.gl_backend = "osmesa";
    options.app.source = SourceSpec{"phantom:small-sphere"};
    HeadlessApp h(options);
    Parameters& p = h.app().settings().parameters;
    p.relax.max_iterations = 3;
    p.relax.epsilon = 0.0f;
    ASSERT_TRUE(h.run_until(settled));
    App& app = h.app();
    EXPECT_FALSE(app.slice_view_shown());
    h.tap(key::V);
    h.frame();
    ASSERT_TRUE(app.slice_view_shown());
    ASSERT_TRUE(app.widget_rect("slice_view"));
    const SlicePanel& slice = app.slice_panel();
    EXPECT_EQ(slice.plane().axis, SliceAxis::Axial);
    EXPECT_EQ(slice.plane().index, 6); // the middle of 12
    h.tap(key::PageUp);
    h.frame();
    EXPECT_EQ(slice.plane().index, 7);
    h.tap(key::PageDown);
    h.tap(key::PageDown);
    h.frame();
    EXPECT_EQ(slice.plane().index, 5);
    // The whole 12 x 12 slice is large enough on screen for the cells and nodes (Fig. 1).
    EXPECT_GE(slice.mapping().pixels_per_sample(), render::kCellDetailPixels);
    ASSERT_GT(slice.scene().net.layer.nodes.size(), 10u);
    ASSERT_EQ(slice.scene().contours.size(), 2u);
    EXPECT_GT(slice.scene().contours[0].segments.size(), 10u);

    // Click the fourth node of the layer.
    const std::uint32_t node = slice.scene().net.layer.nodes[3];
    const ImVec2 at = slice.mapping().to_screen(
        index_to_slice(SliceAxis::Axial, slice.scene().net.positions[node]));
    h.click(at.x, at.y);
    ASSERT_EQ(slice.picked_node(), node);
    ASSERT_TRUE(h.run_until([](const App& a) {
        return a.slice_panel().inspection() && a.slice_panel().inspection()->iteration == 3;
    }));
    if (const char* out = std::getenv("SNERT_SLICE_VIEW_PNG")) { // a look at it, on request
        h.frame();
        render::write_png(out, h.capture());
    }
    const RelaxContext& context = *app.results().net->context;
    const NodeInspection expected = core_inspection(context, node, 3);
    const NodeInspection& shown = *slice.inspection();
    EXPECT_EQ(shown.node, node);
    ASSERT_EQ(shown.sub_steps.size(), expected.sub_steps.size());
    EXPECT_EQ(shown.sub_steps[0].terms.a, expected.sub_steps[0].terms.a);
    EXPECT_EQ(shown.sub_steps[0].terms.dg, expected.sub_steps[0].terms.dg);
    EXPECT_EQ(shown.sub_steps[0].ray_box, expected.sub_steps[0].ray_box);
    EXPECT_EQ(shown.after, expected.after);
    // The node's path for the 3D view: iterations 0 to 3, ending where the move ended.
    ASSERT_EQ(slice.node_path().size(), 4u);
    EXPECT_EQ(slice.node_path()[0], context.net->positions[node]);
    EXPECT_EQ(slice.node_path()[3], expected.after);
    // Where the app's own frame has the node (its vertices are the nodes): the same point.
    const glm::vec3 world = app.results().frame->mesh.positions[node];
    EXPECT_LT(glm::length(world_to_index(*app.results().source->volume, world) - shown.after),
              1e-4f);

    // One iteration back: the inspection follows the slider.
    h.tap(key::Left);
    ASSERT_TRUE(h.run_until([](const App& a) {
        return a.slice_panel().inspection() && a.slice_panel().inspection()->iteration == 2;
    }));
    EXPECT_EQ(slice.inspection()->after, core_inspection(context, node, 2).after);
    // A click away from every node moves the crosshair there and drops the node.
    const UiRect r = *app.widget_rect("slice_view");
    h.click(r.x0 + 0.3f * (r.x1 - r.x0) * 0.5f, r.y0 + 0.5f * (r.y1 - r.y0));
    EXPECT_FALSE(slice.picked_node().has_value());
    EXPECT_TRUE(slice.crosshair().has_value());
    // A point picked elsewhere (a 3D view): its slice and the crosshair on it.
    app.show_in_slice({3.25f, 8.5f, 8.4f});
    h.frame();
    EXPECT_EQ(slice.plane().index, 8);
    EXPECT_EQ(*slice.crosshair(), glm::vec3(3.25f, 8.5f, 8.0f));
    // A click on the net's 3D view picks the node under the pointer and shows its layer.
    const UiRect net_view = *app.widget_rect("view_net");
    h.click(net_view.centre_x(), net_view.centre_y());
    h.frame();
    ASSERT_TRUE(slice.picked_node().has_value());
    EXPECT_EQ(slice.plane().index, context.net->cells[*slice.picked_node()].z);
    // It is the node nearest to the view's centre among the sphere's front nodes: on the near
    // half of the sphere as the camera sees it.
    const glm::vec3 centre(5.6f, 5.45f, 5.3f);
    const glm::vec3 eye = world_to_index(*app.results().source->volume, app.camera().eye());
    EXPECT_GT(glm::dot(context.net->positions[*slice.picked_node()] - centre, eye - centre), 0.0f);
}
