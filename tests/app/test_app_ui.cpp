// The app drawn headless (OSMesa) with scripted input: buttons, slider, plots, shortcuts,
// parameters, camera, files. Checked by the app's state; tests/app/ui_snapshot.cpp adds the
// golden-image check.
#include <gtest/gtest.h>

#include <filesystem>

#include "app/headless.h"
#include "io/mesh_io.h"
#include "support/real_data.h"
#include "support/temp_folder.h"

using namespace snert;
using namespace snert::app;

namespace {

namespace fs = std::filesystem;

// A fresh app on a small phantom, with no settings file, that relaxes `iterations` times.
std::unique_ptr<HeadlessApp> make_app(int iterations, const std::string& input = "phantom:sphere",
                                      int size = 32) {
    HeadlessOptions options;
    options.width = 1200;
    options.height = 760;
    options.gl_backend = "osmesa";
    options.app.input = input;
    options.app.phantom_size = size;
    auto h = std::make_unique<HeadlessApp>(options);
    Parameters& p = h->app().settings().parameters;
    p.relax.max_iterations = iterations;
    p.relax.epsilon = 0.0f; // every iteration runs
    return h;
}

// Everything has arrived and the right view shows the iteration the slider shows.
bool settled(const App& app) {
    const JobResults& r = app.results();
    return r.finished && r.mc && r.frame && r.mc_current && r.frame_current &&
           r.frame->iteration == app.shown_iteration();
}

void click_widget(HeadlessApp& h, const std::string& id) {
    const auto rect = h.app().widget_rect(id);
    ASSERT_TRUE(rect) << "no widget " << id;
    h.click(rect->centre_x(), rect->centre_y());
}

} // namespace

TEST(AppUi, StepButtonsAndSliderPickTheIteration) {
    auto h = make_app(12);
    ASSERT_TRUE(h->run_until(settled));
    App& app = h->app();
    EXPECT_TRUE(app.following());
    EXPECT_EQ(app.shown_iteration(), 12);
    EXPECT_EQ(app.results().iteration_count(), 13);

    click_widget(*h, "step_back");
    EXPECT_FALSE(app.following());
    EXPECT_EQ(app.shown_iteration(), 11);
    ASSERT_TRUE(h->run_until(settled));
    EXPECT_EQ(app.results().frame->iteration, 11);
    // Every number follows the iteration: the table's metrics are those of iteration 11.
    EXPECT_EQ(app.results().frame->metrics.quality.mean, app.results().iterations[11].quality_mean);

    click_widget(*h, "step_back");
    click_widget(*h, "step_forward");
    click_widget(*h, "step_forward");
    EXPECT_EQ(app.shown_iteration(), 12);
    click_widget(*h, "first");
    EXPECT_EQ(app.shown_iteration(), 0);
    ASSERT_TRUE(h->run_until(settled));
    EXPECT_EQ(app.results().frame->iteration, 0);

    // Drag the slider's grab from the left end to the right end, then back to the middle.
    const UiRect slider = *app.widget_rect("iteration_slider");
    h->drag(slider.x0 + 4, slider.centre_y(), slider.x1 + 20, slider.centre_y());
    EXPECT_EQ(app.shown_iteration(), 12);
    h->drag(slider.x1 - 4, slider.centre_y(), slider.centre_x(), slider.centre_y());
    EXPECT_GE(app.shown_iteration(), 5);
    EXPECT_LE(app.shown_iteration(), 7);
    ASSERT_TRUE(h->run_until(settled));
    const int k = app.shown_iteration();
    EXPECT_EQ(app.results().frame->iteration, k);
    EXPECT_EQ(app.results().frame->metrics.smoothness,
              app.results().iterations[std::size_t(k)].smoothness);

    click_widget(*h, "last");
    EXPECT_TRUE(app.following());
    EXPECT_EQ(app.shown_iteration(), 12);
}

TEST(AppUi, ConvergencePlotPicksAnIteration) {
    auto h = make_app(10);
    ASSERT_TRUE(h->run_until(settled));
    click_widget(*h, "tab_convergence");
    h->frame();
    const auto plot = h->app().widget_rect("plot_1"); // mean quality
    ASSERT_TRUE(plot);
    h->click(plot->x0 + 0.02f * plot->width(), plot->centre_y()); // left edge of the box: early
    EXPECT_FALSE(h->app().following());
    EXPECT_LE(h->app().shown_iteration(), 2);
}

TEST(AppUi, PlayRunsThroughTheIterations) {
    auto h = make_app(8);
    ASSERT_TRUE(h->run_until(settled));
    App& app = h->app();
    click_widget(*h, "play"); // at the end: plays from the start
    EXPECT_TRUE(app.playing());
    EXPECT_EQ(app.shown_iteration(), 0);
    int last_seen = 0;
    bool increasing = true;
    ASSERT_TRUE(h->run_until([&](const App& a) {
        if (a.shown_iteration() < last_seen) increasing = false;
        last_seen = a.shown_iteration();
        return !a.playing();
    }));
    EXPECT_TRUE(increasing);
    EXPECT_EQ(app.shown_iteration(), 8);
    ASSERT_TRUE(h->run_until(settled));
}

TEST(AppUi, ShortcutsDriveTheApp) {
    auto h = make_app(6);
    ASSERT_TRUE(h->run_until(settled));
    App& app = h->app();
    h->tap(key::Left);
    EXPECT_EQ(app.shown_iteration(), 5);
    h->tap(key::Home);
    EXPECT_EQ(app.shown_iteration(), 0);
    h->tap(key::Right);
    EXPECT_EQ(app.shown_iteration(), 1);
    h->tap(key::End);
    EXPECT_TRUE(app.following());
    h->tap(key::F);
    EXPECT_EQ(app.settings().view.shading, "flat");
    h->tap(key::W);
    EXPECT_TRUE(app.settings().view.wireframe);
    h->tap(key::Q);
    EXPECT_EQ(app.settings().view.shading, "quality");
    EXPECT_FALSE(app.quit_requested());
    h->tap(key::B, true);
    EXPECT_FALSE(app.settings().layout.show_bottom_panel);
    h->tap(key::F1);
    EXPECT_TRUE(app.help_open());
    h->tap(key::Q, true);
    EXPECT_TRUE(app.quit_requested());
    // Every action has a shortcut the Help window lists.
    for (const Shortcut& s : shortcuts()) EXPECT_EQ(shortcut_for(s.action).action, s.action);
}

TEST(AppUi, ChangingAParameterRestartsTheComputation) {
    auto h = make_app(5);
    ASSERT_TRUE(h->run_until(settled));
    App& app = h->app();
    const auto generation = app.results().generation;
    const auto mc = app.results().mc;
    app.settings().parameters.relax.mode = RelaxMode::Averaging;
    h->frame();
    EXPECT_EQ(app.results().generation, generation + 1);
    ASSERT_TRUE(h->run_until(settled));
    EXPECT_EQ(app.results().frame->method, Method::Sna);
    EXPECT_EQ(app.results().mc, mc); // Marching Cubes did not depend on the mode

    // Dragging the iso slider: many changes, one per frame; the last one wins.
    const UiRect iso = *app.widget_rect("iso_slider");
    h->drag(iso.centre_x(), iso.centre_y(), iso.centre_x() + 0.3f * iso.width(), iso.centre_y(), 6);
    EXPECT_FALSE(app.settings().parameters.auto_iso);
    const float chosen = app.settings().parameters.iso;
    EXPECT_GT(chosen, 0.0f);
    ASSERT_TRUE(h->run_until(settled));
    EXPECT_EQ(app.results().iso, chosen);
    EXPECT_FALSE(app.results().analytic_reference);
}

TEST(AppUi, ViewsAreRedrawnOnlyWhenSomethingChanges) {
    auto h = make_app(4);
    ASSERT_TRUE(h->run_until(settled));
    h->frame();
    const int before = h->app().view_render_count();
    for (int i = 0; i < 5; ++i) h->frame();
    EXPECT_EQ(h->app().view_render_count(), before);
    EXPECT_FALSE(h->app().animating());
    h->tap(key::S); // smooth shading: one redraw
    EXPECT_EQ(h->app().view_render_count(), before + 1);
}

TEST(AppUi, CameraFollowsTheMouse) {
    auto h = make_app(3);
    ASSERT_TRUE(h->run_until(settled));
    App& app = h->app();
    const render::OrbitCamera start = app.camera();
    const UiRect view = *app.widget_rect("view_net");
    h->drag(view.centre_x(), view.centre_y(), view.centre_x() + 80, view.centre_y());
    EXPECT_NE(app.camera().yaw, start.yaw);
    EXPECT_EQ(app.camera().distance, start.distance);
    h->move_mouse(view.centre_x(), view.centre_y());
    h->wheel(2);
    h->frame();
    EXPECT_LT(app.camera().distance, start.distance);
    h->tap(key::R);
    EXPECT_EQ(app.camera().yaw, start.yaw);
    EXPECT_EQ(app.camera().distance, start.distance);
    h->tap(key::Digit3); // top view
    EXPECT_EQ(app.settings().view.preset, "top");
}

TEST(AppUi, RunToConvergenceRelaxesFurther) {
    auto h = make_app(2);
    h->app().settings().parameters.relax.epsilon = 1e-3f;
    ASSERT_TRUE(h->run_until(settled));
    App& app = h->app();
    ASSERT_FALSE(app.results().finished->converged);
    click_widget(*h, "run_to_convergence");
    ASSERT_TRUE(
        h->run_until([](const App& a) { return settled(a) && a.results().iteration_count() > 3; }));
    EXPECT_GT(app.results().finished->iterations, 2);
    EXPECT_TRUE(app.following());
}

TEST(AppUi, ScreenshotAndExportWriteFiles) {
    auto h = make_app(3);
    ASSERT_TRUE(h->run_until(settled));
    App& app = h->app();
    const test::TempFolder temp("snert-app-files");
    const std::string folder = temp.path().string();
    const std::string png = folder + "/views.png";
    app.request_screenshot(png);
    h->frame();
    const render::Image shot = render::read_png(png);
    const UiRect views = *app.widget_rect("views");
    EXPECT_EQ(shot.width, int(std::lround(views.x1)) - int(std::lround(views.x0)));
    EXPECT_EQ(shot.height, int(std::lround(views.y1)) - int(std::lround(views.y0)));
    app.request_screenshot(folder + "/no/such/folder/x.png");
    h->frame();
    EXPECT_NE(app.notices().back().find("no/such/folder/x.png"), std::string::npos);

    const auto written = app.export_meshes(folder + "/sphere", "ply");
    ASSERT_EQ(written.size(), 2u);
    EXPECT_EQ(read_mesh(written[0]).triangle_count(), app.results().mc->mesh.triangle_count());
    EXPECT_EQ(read_mesh(written[1]).triangle_count(), app.results().frame->mesh.triangle_count());
    EXPECT_EQ(written[1], folder + "/sphere-snert-3.ply");
}

TEST(AppUi, DroppedFilesOpen) {
    auto h = make_app(2);
    ASSERT_TRUE(h->run_until(settled));
    App& app = h->app();
    app.on_drop({"/no/such/volume.nrrd"});
    h->frame();
    EXPECT_NE(app.notices().back().find("/no/such/volume.nrrd"), std::string::npos);
    EXPECT_EQ(app.settings().parameters.volume.input, "phantom:sphere");

    const std::string file = test::data_file("HeadMRVolume.mhd");
    if (!fs::exists(file) || !can_load_files()) GTEST_SKIP() << "no " << file << " or no ITK";
    app.on_drop({file});
    h->frame();
    ASSERT_TRUE(h->run_until(settled, 300));
    EXPECT_TRUE(app.results().error.empty()) << app.results().error;
    EXPECT_EQ(app.results().source->volume->dims, glm::ivec3(48, 62, 42));
    EXPECT_EQ(app.settings().recent_files.front(), file);
    EXPECT_FALSE(app.results().analytic_reference);
}

TEST(AppUi, OpenFieldCompletesWithTabAndOpensWithEnter) {
    const std::string folder = test::data_dir();
    if (!fs::exists(folder + "/HeadMRVolume.mhd") || !can_load_files())
        GTEST_SKIP() << "no " << folder << "/HeadMRVolume.mhd or no ITK";
    auto h = make_app(2);
    ASSERT_TRUE(h->run_until(settled));
    App& app = h->app();
    click_widget(*h, "open_field");
    h->type(folder + "/HeadMRV");
    h->tap(key::Tab);
    // HeadMRVolume.mhd and HeadMRVolume.raw: completed up to what they share.
    EXPECT_EQ(app.open_field_text(), folder + "/HeadMRVolume.");
    h->type("mhd");
    h->tap(key::Enter);
    EXPECT_EQ(app.settings().parameters.volume.input, folder + "/HeadMRVolume.mhd");
    ASSERT_TRUE(h->run_until(settled, 300));
    EXPECT_EQ(app.results().source->volume->dims, glm::ivec3(48, 62, 42));
}

TEST(AppUi, SettingsSurviveARestart) {
    const test::TempFolder temp("snert-app-settings");
    const std::string folder = temp.path().string();
    const std::string path = folder + "/snert/settings.ini";
    {
        HeadlessOptions options;
        options.gl_backend = "osmesa";
        options.app.settings_path = path;
        HeadlessApp h(options);
        EXPECT_EQ(h.app().settings().parameters.volume.input, "phantom:two-spheres"); // default
        Settings& s = h.app().settings();
        s.parameters.volume = {"phantom:torus", 40};
        s.parameters.relax.mode = RelaxMode::Gradient;
        s.parameters.relax.max_iterations = 7;
        s.view.shading = "flat";
        s.layout.side_panel_width = 280;
        s.layout.show_bottom_panel = false;
        s.add_recent("/data/a.nrrd");
        h.frame();
        h.app().save_settings();
    }
    HeadlessOptions options;
    options.gl_backend = "osmesa";
    options.app.settings_path = path;
    HeadlessApp h(options);
    const Settings& s = h.app().settings();
    EXPECT_EQ(s.parameters.volume.input, "phantom:torus");
    EXPECT_EQ(s.parameters.volume.phantom_size, 40);
    EXPECT_EQ(s.parameters.relax.mode, RelaxMode::Gradient);
    EXPECT_EQ(s.parameters.relax.max_iterations, 7);
    EXPECT_EQ(s.view.shading, "flat");
    EXPECT_EQ(s.layout.side_panel_width, 280.0f);
    EXPECT_FALSE(s.layout.show_bottom_panel);
    ASSERT_EQ(s.recent_files.size(), 1u);
    EXPECT_EQ(s.recent_files[0], "/data/a.nrrd");
}
