// The app drawn headless (OSMesa) with scripted input: buttons, slider, plots, shortcuts,
// parameters, camera, files; every kind of input the CLI opens (phantom, NRRD, raw, label map,
// DICOM series) and what a failed open leaves. Checked by the app's state;
// tests/app/ui_snapshot.cpp adds the golden-image check.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <numeric>
#include <string>
#include <thread>
#include <vector>

#include "app/headless.h"
#include "app/view_renderer.h"
#include "core/marching_cubes.h"
#include "core/phantom.h"
#include "render/camera.h"
#include "render/gl.h"
#include "render/normals.h"
#include "core/triangle_distances.h"
#include "core/triangle_pick.h"
#include "support/read_mesh.h"
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
    options.app.source = SourceSpec{input};
    if (options.app.source->is_phantom()) options.app.source->phantom_size = size;
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
           r.frame->iteration == app.shown_iteration() && r.frame->metrics_complete;
}

void click_widget(HeadlessApp& h, const std::string& id) {
    const auto rect = h.app().widget_rect(id);
    ASSERT_TRUE(rect) << "no widget " << id;
    h.click(rect->centre_x(), rect->centre_y());
}

// Settled on `spec`: it loaded, and everything of its job has arrived.
bool settled_on(const App& app, const SourceSpec& spec) {
    return settled(app) && app.loaded_source() && *app.loaded_source() == spec &&
           app.results().source && app.results().source->spec == spec;
}

// A ball of bright voxels (200) in a dark box (10), as uint8 samples, x fastest.
std::vector<std::uint8_t> ball(glm::ivec3 dims) {
    std::vector<std::uint8_t> v;
    const glm::vec3 centre = 0.5f * glm::vec3(dims - 1);
    const float radius = 0.3f * float(std::min({dims.x, dims.y, dims.z}));
    for (int z = 0; z < dims.z; ++z)
        for (int y = 0; y < dims.y; ++y)
            for (int x = 0; x < dims.x; ++x)
                v.push_back(glm::length(glm::vec3(x, y, z) - centre) < radius ? 200 : 10);
    return v;
}

// A NRRD file of the ball; `keep` < 1 cuts its data short (a truncated file).
std::string write_nrrd(const test::TempFolder& folder, const std::string& name, glm::ivec3 dims,
                       double keep = 1.0) {
    std::vector<std::uint8_t> bytes;
    const std::string header =
        "NRRD0004\ntype: uint8\ndimension: 3\nsizes: " + std::to_string(dims.x) + " " +
        std::to_string(dims.y) + " " + std::to_string(dims.z) +
        "\nspacings: 1 1 1.5\nencoding: raw\n\n";
    bytes.assign(header.begin(), header.end());
    const std::vector<std::uint8_t> samples = ball(dims);
    bytes.insert(bytes.end(), samples.begin(),
                 samples.begin() + std::ptrdiff_t(double(samples.size()) * keep));
    const std::string path = folder.file(name);
    test::write_bytes(path, bytes);
    return path;
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
    EXPECT_EQ(app.frame_interval(), App::kAnimatingFrame); // not the progress bar's few frames
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

    // Dragging along the value histogram: many changes, one per frame; the last one wins.
    const UiRect iso = *app.widget_rect("value_histogram");
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
    EXPECT_EQ(h->app().frame_interval(), App::kIdleFrame);
    h->tap(key::S); // smooth shading: one redraw
    EXPECT_EQ(h->app().view_render_count(), before + 1);
}

// The Compactness tab: its curves, and the switch that shows both meshes at one triangle count
// (the worker's reduced pair), redrawing both views; switched off, the full meshes return.
TEST(AppUi, EqualCountSwitchShowsTheReducedMeshes) {
    auto h = make_app(4);
    ASSERT_TRUE(h->run_until(settled));
    EXPECT_FALSE(h->app().results().compactness) << "made only when asked for";
    click_widget(*h, "tab_compactness");
    ASSERT_TRUE(h->run_until([](const App& app) { return app.results().compactness.has_value(); }));
    const auto& c = h->app().results().compactness;
    ASSERT_TRUE(c->mc_equal && c->net_equal);
    h->frame();
    EXPECT_TRUE(h->app().widget_rect("compactness_plot_0"));
    EXPECT_TRUE(h->app().widget_rect("compactness_plot_2"));
    const int mc_draws = h->app().view_renderer().view_draws(0);
    const int net_draws = h->app().view_renderer().view_draws(1);
    click_widget(*h, "equal_count");
    h->frame();
    EXPECT_TRUE(h->app().equal_count());
    EXPECT_GT(h->app().view_renderer().view_draws(0), mc_draws);
    EXPECT_GT(h->app().view_renderer().view_draws(1), net_draws);
    click_widget(*h, "equal_count");
    h->frame();
    EXPECT_FALSE(h->app().equal_count());
}

// A step to the next iteration sends the positions, normals and quality of the net, and only
// the indices of the quads whose diagonal flipped; the Marching Cubes view is not redrawn.
TEST(AppUi, StepUploadsPositionsOnlyAndRedrawsOneView) {
    auto h = make_app(8);
    ASSERT_TRUE(h->run_until(settled));
    h->frame();
    const ViewRenderer& views = h->app().view_renderer();
    const int mc_draws = views.view_draws(0), net_draws = views.view_draws(1);
    const render::UploadCounters before = views.uploads(1);
    h->app().step(-1);
    ASSERT_TRUE(h->run_until(settled));
    const render::UploadCounters after = views.uploads(1);
    EXPECT_EQ(after.uploads, before.uploads); // no new buffers
    EXPECT_GE(after.updates, before.updates + 1);
    const std::size_t index_bytes = h->app().results().frame->mesh.indices.size() * 4;
    EXPECT_LT(after.index_bytes - before.index_bytes, index_bytes / 2);
    EXPECT_EQ(views.view_draws(0), mc_draws);
    EXPECT_GT(views.view_draws(1), net_draws);
    // The measured version of the same frame changes no picture.
    const int draws = views.view_draws(1);
    for (int i = 0; i < 3; ++i) h->frame();
    EXPECT_EQ(views.view_draws(1), draws);
}

TEST(AppUi, KeyPressedAndReleasedBetweenTwoFramesIsNotLost) {
    auto h = make_app(6);
    ASSERT_TRUE(h->run_until(settled));
    h->app().key_pressed(key::Left, false); // down and up before the next frame
    h->frame();
    EXPECT_EQ(h->app().shown_iteration(), 5);
    h->app().key_pressed(key::Left, false);
    h->app().key_pressed(key::Left, false, true); // a repeat steps too
    h->app().key_pressed(key::W, false, true);    // other keys do not repeat
    const bool wireframe = h->app().settings().view.wireframe;
    h->frame();
    EXPECT_EQ(h->app().shown_iteration(), 3);
    EXPECT_EQ(h->app().settings().view.wireframe, wireframe);
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
    EXPECT_NE(app.notices().back().text.find("no/such/folder/x.png"), std::string::npos);
    EXPECT_TRUE(app.notices().back().error);

    const auto written = app.export_meshes(folder + "/sphere", "ply");
    ASSERT_EQ(written.size(), 2u);
    EXPECT_EQ(read_mesh(written[0]).triangle_count(), app.results().mc->mesh.triangle_count());
    EXPECT_EQ(read_mesh(written[1]).triangle_count(), app.results().frame->mesh.triangle_count());
    EXPECT_EQ(written[1], folder + "/sphere-snert-3.ply");

    // The FE formats through the same function as `snert export`: the VTK's distances are the
    // face accuracy the app measured, an .inp has the element type chosen.
    const auto vtk = app.export_meshes(folder + "/sphere", "vtk");
    ASSERT_EQ(vtk.size(), 2u);
    const VtkCellData cells = read_vtk_cell_data(vtk[0]);
    ASSERT_EQ(cells.count("distance"), 1u);
    const std::vector<float>& d = cells.at("distance");
    ASSERT_EQ(d.size(), app.results().mc->mesh.triangle_count());
    ASSERT_TRUE(app.results().mc->metrics.accuracy);
    EXPECT_NEAR(std::accumulate(d.begin(), d.end(), 0.0) / double(d.size()),
                app.results().mc->metrics.accuracy->faces_mean, 1e-5);
    const auto inp = app.export_meshes(folder + "/sphere", "inp", AbaqusElement::Sfm3d3);
    std::ifstream in(inp[1]);
    const std::string text{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
    EXPECT_NE(text.find("*ELEMENT, TYPE=SFM3D3, ELSET=snert\n"), std::string::npos);
}

TEST(AppUi, DroppedFilesOpen) {
    auto h = make_app(2);
    ASSERT_TRUE(h->run_until(settled));
    App& app = h->app();
    app.on_drop({"/no/such/volume.nrrd"});
    h->frame();
    EXPECT_NE(app.notices().back().text.find("/no/such/volume.nrrd"), std::string::npos);
    EXPECT_TRUE(app.notices().back().error);
    EXPECT_EQ(app.settings().parameters.volume.input, "phantom:sphere");

    const std::string file = test::data_file("HeadMRVolume.mhd");
    if (!fs::exists(file)) GTEST_SKIP() << "no " << file;
    app.on_drop({file});
    h->frame();
    ASSERT_TRUE(h->run_until(settled, 300));
    EXPECT_TRUE(app.results().error.empty()) << app.results().error;
    EXPECT_EQ(app.results().source->volume->dims, glm::ivec3(48, 62, 42));
    EXPECT_EQ(app.settings().recent_files.front(), SourceSpec{file});
    EXPECT_FALSE(app.results().analytic_reference);
}

TEST(AppUi, OpenFieldCompletesWithTabAndOpensWithEnter) {
    const std::string folder = test::data_dir();
    if (!fs::exists(folder + "/HeadMRVolume.mhd"))
        GTEST_SKIP() << "no " << folder << "/HeadMRVolume.mhd";
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
    const SourceSpec torus{"phantom:torus", 24};
    {
        HeadlessOptions options;
        options.gl_backend = "osmesa";
        options.app.settings_path = path;
        HeadlessApp h(options);
        EXPECT_EQ(h.app().settings().parameters.volume.input, "phantom:two-spheres"); // default
        Settings& s = h.app().settings();
        s.parameters.relax.mode = RelaxMode::Gradient;
        s.parameters.relax.max_iterations = 7;
        s.view.shading = "flat";
        s.layout.side_panel_width = 280;
        s.layout.show_bottom_panel = false;
        s.add_recent(SourceSpec{"/data/a.nrrd"});
        h.app().open(torus);
        ASSERT_TRUE(h.run_until([&](const App& a) { return settled_on(a, torus); }));
        h.app().save_settings();
    }
    HeadlessOptions options;
    options.gl_backend = "osmesa";
    options.app.settings_path = path;
    HeadlessApp h(options);
    const Settings& s = h.app().settings();
    EXPECT_EQ(s.parameters.volume, torus);
    EXPECT_EQ(s.parameters.relax.mode, RelaxMode::Gradient);
    EXPECT_EQ(s.parameters.relax.max_iterations, 7);
    EXPECT_EQ(s.view.shading, "flat");
    EXPECT_EQ(s.layout.side_panel_width, 280.0f);
    EXPECT_FALSE(s.layout.show_bottom_panel);
    ASSERT_EQ(s.recent_files.size(), 1u);
    EXPECT_EQ(s.recent_files[0].input, "/data/a.nrrd");
}

TEST(AppUi, CommandLineOverridesTheSavedSettings) {
    const test::TempFolder temp("snert-app-cli");
    const std::string path = temp.file("settings.ini");
    Settings saved;
    saved.parameters.volume = {"phantom:torus", 24};
    saved.parameters.relax.mode = RelaxMode::Gradient;
    save_settings(saved, path);
    HeadlessOptions options;
    options.gl_backend = "osmesa";
    options.app.settings_path = path;
    options.app.source = SourceSpec{"phantom:sphere", 20};
    options.app.iso = 1.5f;
    options.app.inside = InsideIs::Below;
    PipelineOptions pipeline;
    pipeline.relax.mode = RelaxMode::Averaging;
    pipeline.relax.max_iterations = 3;
    pipeline.relax.triangulation = TriangulationRule::Delaunay;
    options.app.pipeline = pipeline;
    HeadlessApp h(options);
    const Parameters& p = h.app().settings().parameters;
    EXPECT_EQ(p.volume, (SourceSpec{"phantom:sphere", 20}));
    EXPECT_FALSE(p.auto_iso);
    EXPECT_EQ(p.iso, 1.5f);
    EXPECT_EQ(p.inside, InsideIs::Below);
    EXPECT_EQ(p.relax.mode, RelaxMode::Averaging);
    EXPECT_EQ(p.relax.max_iterations, 3);
    EXPECT_EQ(p.triangulation, TriangulationRule::Delaunay);
    ASSERT_TRUE(h.run_until(settled));
    EXPECT_EQ(h.app().results().iso, 1.5f);
    EXPECT_EQ(h.app().results().frame->method, Method::Sna);
}

// --- Every kind of input the CLI opens ------------------------------------------------------

TEST(AppInput, OpensAPhantomFromItsMenu) {
    auto h = make_app(2);
    ASSERT_TRUE(h->run_until(settled));
    App& app = h->app();
    const SourceSpec torus{"phantom:torus", 32};
    app.open(torus);
    ASSERT_TRUE(h->run_until([&](const App& a) { return settled_on(a, torus); }));
    EXPECT_NE(app.results().source->title.find("torus"), std::string::npos);
    EXPECT_TRUE(app.results().analytic_reference);
    EXPECT_TRUE(app.load_error().empty());
    EXPECT_TRUE(app.form().path.empty());             // a phantom has no path
    EXPECT_TRUE(app.settings().recent_files.empty()); // phantoms have their own menu
}

TEST(AppInput, OpensANrrdFileTypedIntoTheField) {
    const test::TempFolder temp("snert-app-nrrd");
    const std::string file = write_nrrd(temp, "ball.nrrd", {20, 18, 16});
    auto h = make_app(3);
    ASSERT_TRUE(h->run_until(settled));
    App& app = h->app();
    click_widget(*h, "open_field");
    h->type(file);
    click_widget(*h, "open_button");
    const SourceSpec spec{file};
    EXPECT_EQ(app.settings().parameters.volume, spec);
    ASSERT_TRUE(h->run_until([&](const App& a) { return settled_on(a, spec); }));
    EXPECT_EQ(app.results().source->volume->dims, glm::ivec3(20, 18, 16));
    EXPECT_GT(app.results().mc->mesh.triangle_count(), 100u);
    EXPECT_EQ(app.settings().recent_files.front(), spec);
    EXPECT_EQ(app.form().path, file);
}

TEST(AppInput, OpensHeaderlessRawDataWithItsOptions) {
    const test::TempFolder temp("snert-app-raw");
    const glm::ivec3 dims(22, 20, 18);
    // uint16, big-endian: the ball's values times 100, high byte first.
    std::vector<std::uint8_t> bytes;
    for (const std::uint8_t v : ball(dims)) {
        const auto value = std::uint16_t(v * 100);
        bytes.push_back(std::uint8_t(value >> 8));
        bytes.push_back(std::uint8_t(value & 0xff));
    }
    const std::string file = temp.file("ball.raw");
    test::write_bytes(file, bytes);

    auto h = make_app(3);
    ASSERT_TRUE(h->run_until(settled));
    App& app = h->app();
    EXPECT_FALSE(app.widget_rect("raw_checkbox")); // nothing typed: no raw options
    click_widget(*h, "open_field");
    h->type(file);
    click_widget(*h, "raw_checkbox");
    ASSERT_TRUE(app.form().raw);
    h->frame();
    EXPECT_TRUE(app.widget_rect("raw_dims")); // the raw options are shown
    const RawOptions raw{dims, ScalarType::UInt16, glm::vec3(0.8f, 0.8f, 2.0f), Endian::Big};
    app.form().raw_options = raw;
    click_widget(*h, "open_button");
    SourceSpec spec{file};
    spec.raw = raw;
    EXPECT_EQ(app.settings().parameters.volume, spec);
    ASSERT_TRUE(h->run_until([&](const App& a) { return settled_on(a, spec); }));
    const Volume& v = *app.results().source->volume;
    EXPECT_EQ(v.dims, dims);
    EXPECT_EQ(v.spacing, raw.spacing);
    EXPECT_EQ(value_range(v).max, 20000.0f); // big-endian read as such
    EXPECT_GT(app.results().mc->mesh.triangle_count(), 100u);
    EXPECT_EQ(app.settings().recent_files.front(), spec);
    // The wrong grid: the file's size does not match, nothing else changes.
    app.form().raw_options.dims = glm::ivec3(30, 20, 18);
    app.open_form();
    ASSERT_TRUE(h->run_until([](const App& a) { return !a.load_error().empty() && settled(a); }));
    EXPECT_NE(app.load_error().find("ball.raw"), std::string::npos) << app.load_error();
    EXPECT_EQ(app.settings().parameters.volume, spec);
    EXPECT_EQ(app.form().raw_options, raw); // the fields show the input shown again
}

TEST(AppInput, LabelMapBesideTheGreyImage) {
    SNERT_REQUIRE_DATA();
    const std::string ct = test::data_file("totalseg_ct_abdomen/example_ct_sm.nii.gz");
    const std::string seg = test::data_file("totalseg_ct_abdomen/example_seg.nii.gz");
    if (!fs::exists(ct) || !fs::exists(seg))
        GTEST_SKIP() << "no TotalSegmentator example in " << test::data_dir();
    auto h = make_app(3);
    ASSERT_TRUE(h->run_until(settled));
    App& app = h->app();
    app.open_path(ct);
    ASSERT_TRUE(h->run_until([&](const App& a) { return settled_on(a, SourceSpec{ct}); }, 300));

    // The label map: Open lists its labels, with the names its header carries.
    click_widget(*h, "labels_field");
    h->type(seg);
    h->tap(key::Enter);
    SourceSpec listed{ct};
    listed.labels = seg;
    EXPECT_EQ(app.settings().parameters.volume, listed);
    ASSERT_TRUE(h->run_until([&](const App& a) { return settled_on(a, listed); }, 300));
    const std::vector<LabelEntry>& labels = app.results().source->labels_present;
    const auto liver = std::find_if(labels.begin(), labels.end(),
                                    [](const LabelEntry& e) { return e.value == 5; });
    ASSERT_NE(liver, labels.end());
    EXPECT_EQ(liver->name, "liver");
    EXPECT_EQ(liver->voxels, 38634u);
    h->frame();
    ASSERT_TRUE(app.widget_rect("label_combo"));

    // Label 5: its mask, the iso of its boundary, a Marching Cubes mesh.
    app.choose_label(5);
    SourceSpec liver_spec = listed;
    liver_spec.label = 5;
    ASSERT_TRUE(h->run_until([&](const App& a) { return settled_on(a, liver_spec); }, 300));
    EXPECT_TRUE(app.results().source->mask);
    EXPECT_EQ(app.results().iso, app.results().source->suggested_iso);
    EXPECT_GT(app.results().mc->mesh.triangle_count(), 1000u);
    EXPECT_GT(app.results().frame->mesh.triangle_count(), 1000u);
    EXPECT_NE(app.status_text().find("label 5"), std::string::npos) << app.status_text();
    EXPECT_EQ(app.settings().recent_files.front(), liver_spec);
    EXPECT_EQ(app.settings_to_save().parameters.volume, liver_spec);
}

TEST(AppInput, DicomFolderListsItsSeriesAndOpensOne) {
    SNERT_REQUIRE_DATA();
    if (SNERT_LARGE_VOLUMES == 0)
        GTEST_SKIP() << "the DICOM head (770 k triangles, meshed twice) takes minutes under the "
                        "sanitizers; this test runs in optimized builds";
    const std::string folder = test::data_file("dicom_mr_head_t1_sag");
    if (!fs::is_directory(folder)) GTEST_SKIP() << "no " << folder;
    auto h = make_app(0); // the input is the point: MC and the initial net
    ASSERT_TRUE(h->run_until(settled));
    App& app = h->app();
    app.open_path(folder);
    const SourceSpec largest{folder};
    ASSERT_TRUE(h->run_until(
        [&](const App& a) { return settled_on(a, largest) && !a.series_list().scanning; }, 300));
    const SeriesList& list = app.series_list();
    EXPECT_EQ(list.folder, folder);
    EXPECT_TRUE(list.error.empty()) << list.error;
    ASSERT_EQ(list.series.size(), 1u);
    EXPECT_EQ(list.series[0].files, 35u);
    h->frame();
    EXPECT_TRUE(app.widget_rect("series_combo"));

    const std::string uid = list.series[0].uid;
    app.choose_series(uid);
    SourceSpec chosen{folder};
    chosen.series_uid = uid;
    ASSERT_TRUE(h->run_until([&](const App& a) { return settled_on(a, chosen); }, 300));
    EXPECT_EQ(app.results().source->volume->dims, glm::ivec3(256, 256, 35));
    EXPECT_EQ(app.results().source->info->series_uid, uid);
    EXPECT_EQ(app.settings().recent_files.front(), chosen);
}

// --- A failed open never breaks the session -------------------------------------------------

// The Volume panel's Cubic voxels: ticked, the file shown is resampled at once; an edge typed
// applies on Enter; a grid too large is refused in red and the last volume stays; unticked,
// the stored grid comes back.
TEST(AppInput, CubicVoxelsResampleTheFileShown) {
    const test::TempFolder temp("snert-app-cubic");
    const std::string file = write_nrrd(temp, "ball.nrrd", {20, 18, 16}); // 1 x 1 x 1.5 mm
    auto h = make_app(2, file);
    const SourceSpec stored{file};
    ASSERT_TRUE(h->run_until([&](const App& a) { return settled_on(a, stored); }));
    App& app = h->app();
    click_widget(*h, "cubic_checkbox");
    SourceSpec cubic = stored;
    cubic.isotropic = 0.0f; // the smallest spacing: 1 mm
    EXPECT_EQ(app.settings().parameters.volume, cubic);
    ASSERT_TRUE(h->run_until([&](const App& a) { return settled_on(a, cubic); }));
    EXPECT_EQ(app.results().source->volume->dims, glm::ivec3(20, 18, 23)); // 22.5 mm: 23 samples
    EXPECT_NE(app.results().source->description.find("resampled to 20x18x23"), std::string::npos)
        << app.results().source->description;

    click_widget(*h, "cubic_edge");
    h->type("0.5");
    h->tap(key::Enter);
    cubic.isotropic = 0.5f;
    EXPECT_EQ(app.settings().parameters.volume, cubic);
    ASSERT_TRUE(h->run_until([&](const App& a) { return settled_on(a, cubic); }));
    EXPECT_EQ(app.results().source->volume->dims, glm::ivec3(39, 35, 46));

    // An edge that makes an absurd grid: the error names the file, the last volume stays.
    app.form().cubic_edge = 1e-6f;
    app.open_form();
    ASSERT_TRUE(h->run_until([](const App& a) { return !a.load_error().empty() && settled(a); }));
    EXPECT_NE(app.load_error().find("ball.nrrd: resampling to cubic voxels of 1e-06 mm"),
              std::string::npos)
        << app.load_error();
    EXPECT_EQ(app.settings().parameters.volume, cubic);
    EXPECT_EQ(app.form().cubic_edge, 0.5f); // the fields show the input shown again

    click_widget(*h, "cubic_checkbox");
    EXPECT_EQ(app.settings().parameters.volume, stored);
    ASSERT_TRUE(h->run_until([&](const App& a) { return settled_on(a, stored); }));
    EXPECT_EQ(app.results().source->volume->dims, glm::ivec3(20, 18, 16));
}

TEST(AppInput, TruncatedFileKeepsTheOldInputAndMeshes) {
    const test::TempFolder temp("snert-app-bad");
    const std::string good = write_nrrd(temp, "good.nrrd", {20, 20, 20});
    const std::string bad = write_nrrd(temp, "cut.nrrd", {32, 32, 32}, 0.4);
    auto h = make_app(4, good);
    ASSERT_TRUE(h->run_until([&](const App& a) { return settled_on(a, SourceSpec{good}); }));
    App& app = h->app();
    app.settings().parameters.auto_iso = false;
    app.settings().parameters.iso = 120.0f;
    ASSERT_TRUE(h->run_until([](const App& a) { return settled(a) && a.results().iso == 120.0f; }));
    const auto mc = app.results().mc;
    const std::size_t triangles = mc->mesh.triangle_count();

    app.open_path(bad);
    EXPECT_TRUE(app.settings().parameters.auto_iso); // a new input starts on its suggestion
    ASSERT_TRUE(h->run_until([](const App& a) { return !a.load_error().empty(); }));
    // The error, in red, naming the file; the old input back, with its iso choice.
    EXPECT_NE(app.load_error().find("cut.nrrd"), std::string::npos) << app.load_error();
    EXPECT_TRUE(app.notices().back().error);
    EXPECT_EQ(app.settings().parameters.volume, SourceSpec{good});
    EXPECT_FALSE(app.settings().parameters.auto_iso);
    EXPECT_EQ(app.settings().parameters.iso, 120.0f);
    EXPECT_EQ(app.form().path, good); // the field shows what is shown
    EXPECT_EQ(app.results().mc, mc);  // the old meshes stay meanwhile
    EXPECT_EQ(*app.loaded_source(), SourceSpec{good});
    h->frame();
    EXPECT_TRUE(app.widget_rect("load_error"));

    // Everything still works on the old volume: a parameter change re-runs on it.
    app.settings().parameters.relax.mode = RelaxMode::Averaging;
    ASSERT_TRUE(h->run_until([&](const App& a) {
        return settled_on(a, SourceSpec{good}) && a.results().frame->method == Method::Sna;
    }));
    EXPECT_TRUE(app.results().error.empty()) << app.results().error;
    EXPECT_EQ(app.results().iteration_count(), 5);
    EXPECT_EQ(app.results().mc->mesh.triangle_count(), triangles);
    EXPECT_FALSE(app.settings().parameters.auto_iso);
    EXPECT_NE(app.status_text().find("good.nrrd"), std::string::npos) << app.status_text();

    // Only inputs that loaded are remembered.
    const std::string settings_path = temp.file("settings.ini");
    for (const SourceSpec& spec : app.settings().recent_files) EXPECT_NE(spec.input, bad);
    EXPECT_EQ(app.settings_to_save().parameters.volume, SourceSpec{good});
    save_settings(app.settings_to_save(), settings_path);
    EXPECT_EQ(test::read_text(settings_path).find("cut.nrrd"), std::string::npos);

    // Not a volume at all: the same.
    const std::string text = temp.file("notes.nrrd");
    test::write_text(text, "these are notes, not a volume\n");
    app.open_path(text);
    ASSERT_TRUE(h->run_until([&](const App& a) {
        return a.load_error().find("notes.nrrd") != std::string::npos && settled(a);
    }));
    EXPECT_EQ(app.settings().parameters.volume, SourceSpec{good});
    EXPECT_EQ(app.results().source->spec, SourceSpec{good});
}

TEST(AppInput, ABadSavedInputStartsOnTheDefaultPhantom) {
    const test::TempFolder temp("snert-app-bad-start");
    const std::string bad = write_nrrd(temp, "cut.nrrd", {32, 32, 32}, 0.5);
    const std::string path = temp.file("settings.ini");
    test::write_text(path, "volume = " + bad + "\niterations = 2\n"); // an older snert's file
    HeadlessOptions options;
    options.gl_backend = "osmesa";
    options.app.settings_path = path;
    HeadlessApp h(options);
    const SourceSpec fallback = Parameters().volume;
    ASSERT_TRUE(h.run_until([&](const App& a) { return settled_on(a, fallback); }));
    EXPECT_NE(h.app().load_error().find("cut.nrrd"), std::string::npos);
    h.app().save_settings();
    EXPECT_EQ(load_settings(path).parameters.volume, fallback);
}

TEST(AppUi, AboutShowsTheVersionAndThePaper) {
    auto h = make_app(1);
    h->app().show_about();
    h->frame();
    h->frame();
    EXPECT_TRUE(h->app().about_open());
    h->tap(key::Escape);
    EXPECT_FALSE(h->app().about_open());
}

// While the camera moves, a mesh with a preview is drawn as its preview; once the camera stayed
// still for a moment, as the whole mesh.
TEST(AppViews, PreviewWhileTheCameraMovesThenTheWholeMesh) {
    auto h = make_app(1); // for its GL context and a mesh
    ASSERT_TRUE(h->run_until(settled));
    auto mesh = std::make_shared<DisplayMesh>(*h->app().results().mc);
    mesh->preview = std::make_shared<const PreviewMesh>(
        make_preview(mesh->mesh, mesh->mesh.triangle_count() / 4));
    ASSERT_FALSE(mesh->preview->indices.empty());
    ViewRenderer views;
    views.set_mesh(0, mesh);
    render::OrbitCamera camera = h->app().camera();
    const render::DrawStyle style;
    views.render(160, 120, camera, style); // a new camera: it moved
    EXPECT_EQ(views.preview_draws(0), 1);
    EXPECT_EQ(views.view_draws(0), 0);
    EXPECT_TRUE(views.needs_refine());
    std::this_thread::sleep_for(ViewRenderer::kQuiet + std::chrono::milliseconds(50));
    views.render(160, 120, camera, style); // still: the whole mesh
    EXPECT_EQ(views.view_draws(0), 1);
    EXPECT_FALSE(views.needs_refine());
    views.render(160, 120, camera, style); // nothing changed: nothing drawn
    EXPECT_EQ(views.view_draws(0) + views.preview_draws(0), 2);
    camera.orbit(0.1f, 0.0f);
    views.render(160, 120, camera, style);
    EXPECT_EQ(views.preview_draws(0), 2);
    h->frame(); // the app's own target is bound again for its frame
}

namespace {

// A view's picture, read back (RGBA, GL row order).
std::vector<std::uint8_t> view_pixels(const ViewRenderer& views, int view, int width, int height) {
    std::vector<std::uint8_t> pixels(std::size_t(width) * std::size_t(height) * 4);
    glBindTexture(GL_TEXTURE_2D, views.texture(view));
    glGetTexImage(GL_TEXTURE_2D, 0, GL_RGBA, GL_UNSIGNED_BYTE, pixels.data());
    glBindTexture(GL_TEXTURE_2D, 0);
    return pixels;
}

// Marching Cubes' mesh of the sphere phantom of `size`^3 as the worker sends it: measured, with
// normals, geometry 1, no preview.
std::shared_ptr<DisplayMesh> sphere_mesh(int size) {
    const Phantom phantom = make_phantom("sphere", size);
    auto mesh = std::make_shared<DisplayMesh>();
    mesh->mesh = marching_cubes(phantom.volume, {phantom.iso, InsideIs::Above});
    mesh->measure_triangles();
    mesh->normals = render::vertex_normals(mesh->mesh);
    mesh->geometry = 1;
    return mesh;
}

// From the front (z up), for the views' 200 x 150 pictures.
render::OrbitCamera front_camera(const DisplayMesh& mesh) {
    return render::frame_bounds(mesh_bounds(mesh.mesh), render::ViewPreset::Front, 200.0f / 150.0f);
}

// Renders until the view shows its whole mesh; returns the renders that took.
int render_until_whole(ViewRenderer& views, const render::OrbitCamera& camera,
                       const render::DrawStyle& style) {
    int renders = 0;
    views.render(200, 150, camera, style); // a new camera: the preview
    std::this_thread::sleep_for(ViewRenderer::kQuiet + std::chrono::milliseconds(50));
    do {
        views.render(200, 150, camera, style);
        ++renders;
    } while (views.needs_refine() && renders < 10000);
    return renders;
}

} // namespace

// The part size follows the rate of the last part: the triangles that fit kPartBudgetMs, at most
// doubled or halved a part. A mesh's remainder (under half a part) leaves it as it is: taken as a
// whole part, a quick remainder doubled the next mesh's first part.
TEST(AppViews, PartSizeFollowsTheLastWholePart) {
    constexpr double budget = ViewRenderer::kPartBudgetMs;
    constexpr std::size_t size = std::size_t(1) << 15;
    EXPECT_EQ(ViewRenderer::next_part_triangles(size, size, budget), size);
    EXPECT_EQ(ViewRenderer::next_part_triangles(size, size, budget / 1.5), size * 3 / 2);
    EXPECT_EQ(ViewRenderer::next_part_triangles(size, size, budget / 10), 2 * size);
    EXPECT_EQ(ViewRenderer::next_part_triangles(size, size, budget * 10), size / 2);
    // Three quarters of a part at the whole part's rate.
    EXPECT_EQ(ViewRenderer::next_part_triangles(size, size * 3 / 4, budget * 3 / 4), size);
    // A remainder, however quick.
    EXPECT_EQ(ViewRenderer::next_part_triangles(size, size / 4, 0.5), size);
    EXPECT_EQ(ViewRenderer::next_part_triangles(ViewRenderer::kMinPartTriangles,
                                                ViewRenderer::kMinPartTriangles, budget * 10),
              ViewRenderer::kMinPartTriangles);
}

// A mesh with more triangles than a part is drawn in parts, one a render, while its preview is
// shown; the finished picture equals the one drawn in one piece, pixel for pixel (the parts
// keep the triangles' order, and each numbers its triangles from its first for the colours).
TEST(AppViews, LargeMeshDrawnInPartsEqualsOneDraw) {
    auto h = make_app(1); // for its GL context
    ASSERT_TRUE(h->run_until(settled));
    auto mesh = sphere_mesh(120);
    mesh->preview = std::make_shared<const PreviewMesh>(make_preview(mesh->mesh));
    ASSERT_FALSE(mesh->preview->indices.empty());
    // From the front (z up): the first triangles (low z) and the last both in the picture.
    const render::OrbitCamera camera = front_camera(*mesh);
    render::DrawStyle style;
    style.shading = render::Shading::Quality; // the colours follow each triangle's index
    std::vector<std::uint8_t> one;
    for (const bool wireframe : {false, true}) { // without and with the geometry shader
        style.wireframe = wireframe;
        ViewRenderer views;
        ASSERT_GT(mesh->mesh.triangle_count(), views.part_triangles());
        views.set_mesh(0, mesh);
        const int renders = render_until_whole(views, camera, style);
        EXPECT_GE(renders, 2) << "drawn in parts";
        EXPECT_EQ(views.view_draws(0), 1);
        EXPECT_GE(views.preview_draws(0), 1);
        const std::vector<std::uint8_t> parts = view_pixels(views, 0, 200, 150);

        auto whole_mesh = std::make_shared<DisplayMesh>(*mesh);
        whole_mesh->preview = nullptr; // no preview: drawn in one piece
        ViewRenderer whole;
        whole.set_mesh(0, whole_mesh);
        EXPECT_EQ(render_until_whole(whole, camera, style), 1);
        EXPECT_EQ(whole.view_draws(0), 1);
        one = view_pixels(whole, 0, 200, 150);
        // The sphere covers a good part of the picture: its pixels differ from the backdrop's.
        ViewRenderer empty;
        empty.render(200, 150, camera, style);
        const std::vector<std::uint8_t> backdrop = view_pixels(empty, 0, 200, 150);
        std::size_t covered = 0;
        for (std::size_t k = 0; k < one.size(); k += 4)
            covered += std::equal(&one[k], &one[k] + 3, &backdrop[k]) ? 0 : 1;
        EXPECT_GT(covered, one.size() / 4 / 4) << "the sphere is in the picture";
        EXPECT_TRUE(parts == one) << "the parts' picture differs from the one drawn in one piece"
                                  << (wireframe ? " (wireframe)" : "");

        // The same parts drawn between frames, as the window draws them while it waits: the
        // same picture, waiting for the next render to be shown.
        ViewRenderer between;
        between.set_mesh(0, mesh);
        between.render(200, 150, camera, style); // the preview
        std::this_thread::sleep_for(ViewRenderer::kQuiet + std::chrono::milliseconds(50));
        between.render(200, 150, camera, style); // the parts start
        ASSERT_TRUE(between.drawing_parts());
        const int renders_before = between.render_count();
        int parts_between = 0;
        while (between.draw_part_between_frames() && parts_between < 10000) ++parts_between;
        EXPECT_GE(parts_between, 1);
        EXPECT_EQ(between.part_draws(), parts_between) << "each part once";
        EXPECT_FALSE(between.drawing_parts());
        EXPECT_FALSE(between.needs_refine());
        EXPECT_TRUE(between.picture_waiting());
        EXPECT_EQ(between.view_draws(0), 1);
        EXPECT_EQ(between.render_count(), renders_before) << "no render between frames";
        EXPECT_TRUE(view_pixels(between, 0, 200, 150) == one)
            << "the parts drawn between frames differ" << (wireframe ? " (wireframe)" : "");
        EXPECT_FALSE(between.draw_part_between_frames()) << "nothing left to draw";
        between.render(200, 150, camera, style);
        EXPECT_FALSE(between.picture_waiting()) << "the frame shows it";
        EXPECT_EQ(between.render_count(), renders_before) << "and draws nothing";
    }

    // Another mesh while the parts are drawn: they start again, after twice the wait (the parts
    // cut short were drawn for nothing), and only a finished picture counts as drawn.
    ViewRenderer views;
    views.set_mesh(0, mesh);
    const auto first_change = std::chrono::steady_clock::now();
    views.render(200, 150, camera, style); // the preview
    std::this_thread::sleep_for(ViewRenderer::kQuiet + std::chrono::milliseconds(50));
    views.render(200, 150, camera, style); // the parts start (no part in that render)
    ASSERT_TRUE(views.needs_refine());
    ASSERT_TRUE(views.drawing_parts());
    auto moved = std::make_shared<DisplayMesh>(*mesh);
    moved->geometry = 2;
    views.set_mesh(0, moved);
    const auto changed = std::chrono::steady_clock::now();
    views.render(200, 150, camera, style);
    EXPECT_TRUE(views.needs_refine());
    EXPECT_EQ(views.view_draws(0), 0);
    EXPECT_EQ(views.quiet(0), 2 * ViewRenderer::kQuiet);
    const int parts_before = views.part_draws();
    std::this_thread::sleep_for(ViewRenderer::kQuiet + std::chrono::milliseconds(50));
    views.render(200, 150, camera, style);
    // Asked only when this thread was not held up past the longer wait (on a loaded machine),
    // neither since the first change (then the second one did not come rapidly, and its parts
    // start at once) nor since the second.
    if (changed - first_change < 2 * ViewRenderer::kQuiet &&
        std::chrono::steady_clock::now() - changed < 2 * ViewRenderer::kQuiet) {
        EXPECT_EQ(views.part_draws(), parts_before) << "no parts within the longer wait";
    }
    std::this_thread::sleep_for(ViewRenderer::kQuiet);
    for (int k = 0; views.needs_refine() && k < 10000; ++k) views.render(200, 150, camera, style);
    EXPECT_EQ(views.view_draws(0), 1);
    EXPECT_GT(views.part_draws(), parts_before);
    EXPECT_EQ(views.quiet(0), ViewRenderer::kQuiet); // a finished picture: back to the short wait
    EXPECT_TRUE(view_pixels(views, 0, 200, 150) == one);
    h->frame(); // the app's own target is bound again for its frame
}

// The views' first pictures are made a render each. A mesh of more than kStagedUploadTriangles
// gets its new buffers over several renders, a part each, which draw nothing (the view keeps its
// picture); the render after draws it. Another mesh while the parts go starts them again: the
// GPU holds neither mesh whole.
TEST(AppViews, LargeMeshSentInPartsBeforeItIsDrawn) {
    auto h = make_app(1); // for its GL context
    ASSERT_TRUE(h->run_until(settled));
    const auto mesh = sphere_mesh(200);
    ASSERT_GT(mesh->mesh.triangle_count(), ViewRenderer::kStagedUploadTriangles);
    const render::OrbitCamera camera = front_camera(*mesh);
    const render::DrawStyle style;
    ViewRenderer views;
    // The views' first pictures are made a render each (fresh memory for their samples).
    views.render(200, 150, camera, style);
    EXPECT_NE(views.texture(0), 0u);
    EXPECT_EQ(views.texture(1), 0u);
    EXPECT_TRUE(views.needs_refine());
    views.render(200, 150, camera, style);
    EXPECT_NE(views.texture(1), 0u);
    EXPECT_FALSE(views.needs_refine());
    const std::vector<std::uint8_t> backdrop = view_pixels(views, 0, 200, 150);
    const int renders = views.render_count(), draws = views.view_draws(0);

    // Sends the parts; true when each render sent one and drew nothing.
    const auto send_parts = [&] {
        bool quiet = true;
        for (int part = 0; part < render::MeshView::upload_parts(mesh->mesh); ++part) {
            quiet = quiet && views.sending() && views.needs_refine();
            views.render(200, 150, camera, style);
            quiet = quiet && views.render_count() == renders &&
                    view_pixels(views, 0, 200, 150) == backdrop;
        }
        return quiet;
    };
    views.set_mesh(0, mesh);
    EXPECT_EQ(views.uploads(0).uploads, 0);
    views.render(200, 150, camera, style); // part 0
    auto other = std::make_shared<DisplayMesh>(*mesh);
    other->geometry = 2; // the same topology, but the GPU holds only a part of the first
    views.set_mesh(0, other);
    EXPECT_TRUE(send_parts());
    EXPECT_FALSE(views.sending());
    EXPECT_EQ(views.uploads(0).uploads, 1);
    EXPECT_EQ(views.view_draws(0), draws);
    views.render(200, 150, camera, style);
    EXPECT_EQ(views.view_draws(0), draws + 1);
    EXPECT_FALSE(views.needs_refine());
    EXPECT_FALSE(view_pixels(views, 0, 200, 150) == backdrop) << "the sphere is drawn";
    h->frame(); // the app's own target is bound again for its frame
}

// The same topology with new positions (a relaxation step) on a mesh of more than
// kStagedUploadTriangles: the changed indices go at once, the positions, normals and quality a
// part a render, and the view is drawn only after the last, as the mesh uploaded whole would be.
TEST(AppViews, LargeMeshUpdateSentInPartsBeforeItIsDrawn) {
    auto h = make_app(1); // for its GL context
    ASSERT_TRUE(h->run_until(settled));
    const auto mesh = sphere_mesh(200);
    ASSERT_GT(mesh->mesh.triangle_count(), ViewRenderer::kStagedUploadTriangles);
    const render::OrbitCamera camera = front_camera(*mesh);
    render::DrawStyle style;
    style.shading = render::Shading::Quality;
    auto moved = std::make_shared<DisplayMesh>(*mesh);
    moved->geometry = 2;
    const glm::vec3 centre = 0.5f * (mesh_bounds(mesh->mesh).min + mesh_bounds(mesh->mesh).max);
    for (glm::vec3& p : moved->mesh.positions) p = centre + 0.8f * (p - centre);
    // Some triangles' corners in another order: runs of changed indices.
    for (std::size_t t = 0; t < 600; t += 2)
        std::swap(moved->mesh.indices[3 * t], moved->mesh.indices[3 * t + 1]);
    moved->measure_triangles();
    moved->normals = render::vertex_normals(moved->mesh);

    ViewRenderer views;
    views.set_mesh(0, mesh);
    render_until_whole(views, camera, style);
    ASSERT_FALSE(views.needs_refine());
    const std::vector<std::uint8_t> before = view_pixels(views, 0, 200, 150);
    const int renders = views.render_count();
    const std::size_t index_bytes = views.uploads(0).index_bytes;
    views.set_mesh(0, moved);
    EXPECT_TRUE(views.sending());
    EXPECT_GT(views.uploads(0).index_bytes, index_bytes) << "the changed runs go at once";
    EXPECT_LT(views.uploads(0).index_bytes - index_bytes, moved->mesh.indices.size() * 4);
    const int parts = render::MeshView::update_parts(moved->mesh);
    for (int part = 0; part < parts; ++part) {
        EXPECT_TRUE(views.sending()) << part;
        EXPECT_EQ(views.uploads(0).updates, 0) << part;
        views.render(200, 150, camera, style);
        EXPECT_EQ(views.render_count(), renders) << "drawn after part " << part;
        EXPECT_TRUE(view_pixels(views, 0, 200, 150) == before) << part;
    }
    EXPECT_FALSE(views.sending());
    EXPECT_EQ(views.uploads(0).updates, 1);
    EXPECT_EQ(views.uploads(0).uploads, 1) << "no new buffers";
    render_until_whole(views, camera, style);
    ViewRenderer fresh;
    fresh.set_mesh(0, moved);
    render_until_whole(fresh, camera, style);
    const std::vector<std::uint8_t> after = view_pixels(views, 0, 200, 150);
    EXPECT_FALSE(after == before);
    EXPECT_TRUE(after == view_pixels(fresh, 0, 200, 150)) << "the update differs from an upload";
    h->frame(); // the app's own target is bound again for its frame
}

// In the window the glue sends a mesh's buffers between frames: render() leaves them, and each
// draw_part_between_frames() sends one part, until the view can be drawn.
TEST(AppViews, WindowSendsMeshBuffersBetweenFrames) {
    auto h = make_app(1); // for its GL context
    ASSERT_TRUE(h->run_until(settled));
    const auto mesh = sphere_mesh(200);
    const render::OrbitCamera camera = front_camera(*mesh);
    const render::DrawStyle style;
    ViewRenderer views;
    views.set_parts_between_frames(true);
    views.render(200, 150, camera, style);
    views.render(200, 150, camera, style); // both views' first pictures
    views.set_mesh(0, mesh);
    const int renders = views.render_count();
    views.render(200, 150, camera, style);
    EXPECT_EQ(views.uploads(0).vertex_bytes, 0u) << "render() sent a part";
    EXPECT_EQ(views.render_count(), renders);
    int parts = 0;
    while (views.sending() && parts < 1000) {
        EXPECT_TRUE(views.draw_part_between_frames());
        ++parts;
    }
    EXPECT_EQ(parts, render::MeshView::upload_parts(mesh->mesh));
    EXPECT_EQ(views.uploads(0).uploads, 1);
    EXPECT_TRUE(views.has_pending_work()) << "the view waits for its frame";
    views.render(200, 150, camera, style);
    EXPECT_EQ(views.render_count(), renders + 1);
    h->frame(); // the app's own target is bound again for its frame
}

// A new volume is framed once its own mesh arrives, at the views' size: not on the old mesh,
// which stays on screen until then.
TEST(AppViews, OpeningAnotherVolumeFramesIt) {
    auto h = make_app(2, "phantom:sphere", 32);
    ASSERT_TRUE(h->run_until(settled));
    App& app = h->app();
    const test::TempFolder temp("snert-app-frame");
    // Large enough that its mesh comes frames after the volume.
    const std::string path = write_nrrd(temp, "ball.nrrd", glm::ivec3(110, 96, 80));
    h->app().open_path(path);
    SourceSpec spec;
    spec.input = path;
    ASSERT_TRUE(h->run_until([&](const App& a) { return settled_on(a, spec); }));
    h->frame();
    const Bounds bounds = mesh_bounds(app.results().mc->mesh);
    const UiRect view = *app.widget_rect("view_mc");
    const render::OrbitCamera expected =
        render::frame_bounds(bounds, render::ViewPreset::Iso, view.width() / view.height());
    EXPECT_NEAR(glm::distance(app.camera().target, expected.target), 0.0f, 1e-4f);
    EXPECT_NEAR(app.camera().distance, expected.distance, 1e-4f * expected.distance);
}

// The screenshot is of the frame after the dialog closed: no dialog and no hint in it, the
// same picture as one asked for without the dialog. Enter in the file field saves; the folder
// is the one used last, and the status line names the whole path.
TEST(AppUi, ScreenshotDialogSavesTheViewsOnly) {
    auto h = make_app(2);
    ASSERT_TRUE(h->run_until(settled));
    App& app = h->app();
    const test::TempFolder temp("snert-app-shot");
    app.settings().output_folder = temp.path().string();
    app.request_screenshot(temp.file("direct.png"));
    h->frame();
    const render::Image direct = render::read_png(temp.file("direct.png"));

    app.perform(Action::Screenshot);
    h->frame();
    h->frame();
    ASSERT_TRUE(app.widget_rect("screenshot_folder"));
    h->tap(key::Enter);
    h->frame();
    const std::string written = temp.file("snert-sphere-32-2.png");
    ASSERT_TRUE(fs::exists(written));
    const render::Image shot = render::read_png(written);
    ASSERT_EQ(shot.width, direct.width);
    ASSERT_EQ(shot.height, direct.height);
    EXPECT_EQ(shot.rgba, direct.rgba);
    EXPECT_NE(app.notices().back().text.find(written), std::string::npos);
    // The window itself shows the hint where the screenshot does not.
    const render::Image window = h->capture();
    const UiRect views = *app.widget_rect("views");
    std::size_t differ = 0;
    for (int y = 0; y < shot.height; ++y)
        for (int x = 0; x < shot.width; ++x)
            differ += std::memcmp(shot.pixel(x, y),
                                  window.pixel(x + int(std::lround(views.x0)),
                                               y + int(std::lround(views.y0))),
                                  4) != 0;
    EXPECT_GT(differ, 200u);
    EXPECT_LT(differ, std::size_t(shot.width) * std::size_t(shot.height) / 20);
}

// Enter exports; Marching Cubes' file carries no iteration number, the net's does.
TEST(AppUi, ExportDialogConfirmsWithEnter) {
    auto h = make_app(3);
    ASSERT_TRUE(h->run_until(settled));
    App& app = h->app();
    const test::TempFolder temp("snert-app-export");
    app.settings().output_folder = temp.path().string();
    app.perform(Action::ExportMeshes);
    h->frame();
    h->frame();
    h->tap(key::Enter);
    EXPECT_TRUE(fs::exists(temp.file("snert-sphere-32-mc.stl")));
    EXPECT_TRUE(fs::exists(temp.file("snert-sphere-32-snert-3.stl")));
    EXPECT_NE(app.notices().back().text.find(temp.file("snert-sphere-32-mc.stl")),
              std::string::npos);
}

// The iso field steps by whole values on an integer volume, a histogram click rounds to them,
// and the iso chosen for a file comes back when it is opened again from the recent list.
TEST(AppInput, IsoStepsSuitTheDataAndAreRememberedPerFile) {
    auto h = make_app(1);
    ASSERT_TRUE(h->run_until(settled));
    App& app = h->app();
    EXPECT_LT(app.iso_step(), 1.0f); // the phantom's values are fractions
    const test::TempFolder temp("snert-app-iso");
    const std::string path = write_nrrd(temp, "ball.nrrd", glm::ivec3(16));
    app.open_path(path);
    SourceSpec spec;
    spec.input = path;
    ASSERT_TRUE(h->run_until([&](const App& a) { return settled_on(a, spec); }));
    EXPECT_EQ(app.iso_step(), 1.0f);

    const UiRect histogram = *app.widget_rect("value_histogram");
    h->click(histogram.x0 + 0.437f * histogram.width(), histogram.centre_y());
    const float clicked = app.settings().parameters.iso;
    EXPECT_FALSE(app.settings().parameters.auto_iso);
    EXPECT_EQ(clicked, std::round(clicked));
    EXPECT_GT(clicked, 10.0f);
    EXPECT_LT(clicked, 200.0f);

    // The field's + button: one step.
    const UiRect field = *app.widget_rect("iso_field");
    const float button = field.height();
    h->click(field.x1 - 0.5f * button, field.centre_y());
    EXPECT_EQ(app.settings().parameters.iso, clicked + 1.0f);
    ASSERT_TRUE(h->run_until([&](const App& a) { return settled_on(a, spec); }));

    app.open({"phantom:sphere", 32});
    ASSERT_TRUE(h->run_until([](const App& a) { return settled_on(a, {"phantom:sphere", 32}); }));
    EXPECT_TRUE(app.settings().parameters.auto_iso);
    app.open(app.settings().recent_files.front());
    EXPECT_FALSE(app.settings().parameters.auto_iso);
    EXPECT_EQ(app.settings().parameters.iso, clicked + 1.0f);
    ASSERT_TRUE(h->run_until([&](const App& a) { return settled_on(a, spec); }));
    EXPECT_EQ(app.results().iso, clicked + 1.0f);
}

TEST(AppUi, EscapeClosesTheHelp) {
    auto h = make_app(1);
    h->tap(key::F1);
    EXPECT_TRUE(h->app().help_open());
    h->tap(key::Escape);
    EXPECT_FALSE(h->app().help_open());
}

// From 1024 x 640 up, the views keep a useful height, the iteration bar fits the window and
// (at 1366 x 768, a common laptop) the side panel needs no scroll bar.
TEST(AppViews, LayoutFitsSmallScreens) {
    for (const auto& [width, height] : {std::pair{1024, 640}, std::pair{1366, 768}}) {
        HeadlessOptions options;
        options.width = width;
        options.height = height;
        options.gl_backend = "osmesa";
        options.app.source = SourceSpec{"phantom:two-spheres", 48};
        HeadlessApp h(options);
        h.app().settings().parameters.relax.max_iterations = 3;
        ASSERT_TRUE(h.run_until(settled));
        h.frame();
        const App& app = h.app();
        const UiRect view = *app.widget_rect("view_net");
        EXPECT_GT(view.height(), 0.25f * float(height)) << width;
        EXPECT_GT(view.width(), 0.3f * float(width)) << width;
        const UiRect run = *app.widget_rect("run_to_convergence");
        EXPECT_LE(run.x1, float(width)) << width;
        EXPECT_GT(app.widget_rect("iteration_slider")->width(), 0.15f * float(width)) << width;
        if (width >= 1366) {
            EXPECT_EQ(app.side_panel_overflow(), 0.0f);
        }
    }
}

// Colour by q60: picked in the toolbar's combo, the views get the worker's per-triangle values
// (no new mesh, one redraw) and the histograms its summary, which agrees with the core's.
TEST(AppViews, ColourByAnotherMeasure) {
    auto h = make_app(2);
    ASSERT_TRUE(h->run_until(settled));
    App& app = h->app();
    h->tap(key::Q); // quality shading shows the combo
    EXPECT_EQ(app.view_renderer().measure(), ShapeMeasure::Quality);
    const int uploads = app.view_renderer().uploads(0).uploads;
    const int draws = app.view_renderer().view_draws(0);
    click_widget(*h, "color_by");
    const UiRect combo = *app.widget_rect("color_by");
    // The list opens under the combo: q, q60, radius ratio, one line each.
    h->click(combo.x0 + 10, combo.y1 + 1.5f * combo.height() + 4);
    h->frame();
    EXPECT_EQ(app.settings().view.color_by, "q60");
    EXPECT_EQ(app.color_by(), ShapeMeasure::Quality60);
    EXPECT_EQ(app.view_renderer().measure(), ShapeMeasure::Quality60);
    EXPECT_EQ(app.view_renderer().uploads(0).uploads, uploads);
    EXPECT_GT(app.view_renderer().view_draws(0), draws);
    const QualityStats core = quality_stats(app.results().mc->mesh);
    EXPECT_NEAR(app.results().mc->summary(ShapeMeasure::Quality60).mean, core.quality60_mean, 1e-6);
    EXPECT_NEAR(app.results().frame->summary(ShapeMeasure::RadiusRatio).mean,
                quality_stats(app.results().frame->mesh).radius_ratio_mean, 1e-6);
}

// Colour by distance: chosen in the combo, the worker measures both meshes (never the UI
// thread), the views, the legend's range and the histograms show the core's numbers, and they
// follow the iteration slider.
TEST(AppViews, ColourByDistance) {
    auto h = make_app(3);
    ASSERT_TRUE(h->run_until(settled));
    App& app = h->app();
    h->tap(key::Q);
    EXPECT_FALSE(app.results().distances); // nothing measured while a shape is shown
    click_widget(*h, "color_by");
    const UiRect combo = *app.widget_rect("color_by");
    // The fourth line of the list: distance to the iso-surface.
    h->click(combo.x0 + 10, combo.y1 + 3.5f * combo.height() + 4);
    h->frame();
    EXPECT_EQ(app.settings().view.color_by, "distance-iso");
    EXPECT_EQ(app.view_renderer().measure(), ShapeMeasure::DistanceIso);
    // Both meshes measured against the frame shown.
    const auto measured = [](const App& a) {
        const auto& d = a.results().distances;
        return settled(a) && d && d->distances->measure == a.color_by() &&
               d->net_geometry == a.results().frame->geometry &&
               d->mc_geometry == a.results().mc->geometry;
    };
    ASSERT_TRUE(h->run_until(measured));
    h->frame();
    const JobResults& r = app.results();
    const Volume& volume = *r.source->volume;
    const std::vector<float> mc = signed_iso_distances(r.mc->mesh, volume, r.iso, InsideIs::Above);
    const std::vector<float> net =
        signed_iso_distances(r.frame->mesh, volume, r.iso, InsideIs::Above);
    const auto same = [](std::span<const float> a, const std::vector<float>& b) {
        return std::equal(a.begin(), a.end(), b.begin(), b.end());
    };
    EXPECT_TRUE(same(app.view_renderer().values(0), mc));
    EXPECT_TRUE(same(app.view_renderer().values(1), net));
    // The legend's range and the histograms: the core's scale and summaries.
    const MeasureScale scale = distance_scale(ShapeMeasure::DistanceIso, mc, net);
    EXPECT_EQ(app.color_scale().low, scale.low);
    EXPECT_EQ(app.color_scale().high, scale.high);
    EXPECT_TRUE(app.color_scale().diverging);
    ASSERT_TRUE(app.shown_summary(0, ShapeMeasure::DistanceIso));
    EXPECT_EQ(app.shown_summary(0, ShapeMeasure::DistanceIso)->histogram,
              summarize_measure(mc, scale).histogram);
    EXPECT_NEAR(app.shown_summary(1, ShapeMeasure::DistanceIso)->mean,
                summarize_measure(net, scale).mean, 1e-9);
    // A small sphere's Marching Cubes lies inside the exact sphere, on the trilinear
    // surface's inner side on average: a small negative mean (voxels).
    EXPECT_LT(app.shown_summary(0, ShapeMeasure::DistanceIso)->mean, 0.0);
    EXPECT_GT(app.shown_summary(0, ShapeMeasure::DistanceIso)->mean, -0.05);

    // The distance to the other mesh, then an earlier iteration: measured again for it.
    app.settings().view.color_by = "distance-other";
    app.show_iteration(1);
    ASSERT_TRUE(h->run_until([&](const App& a) {
        return measured(a) && a.results().frame->iteration == 1 &&
               a.results().distances->iteration == 1;
    }));
    h->frame();
    const PairDistances pair = pair_distances(ShapeMeasure::DistanceOther, r.mc->mesh,
                                              r.frame->mesh, volume, r.iso, InsideIs::Above);
    EXPECT_TRUE(same(app.view_renderer().values(0), pair.first));
    EXPECT_TRUE(same(app.view_renderer().values(1), pair.second));
    EXPECT_EQ(app.color_scale().high, pair.scale.high);
    EXPECT_EQ(app.color_scale().low, 0.0f);
    EXPECT_EQ(app.shown_summary(1, ShapeMeasure::DistanceOther)->histogram,
              pair.second_summary.histogram);
    // Back to q: the shapes' values again, no distance asked for.
    app.settings().view.color_by = "q";
    h->frame();
    EXPECT_TRUE(
        same(app.view_renderer().values(1),
             std::vector<float>(r.frame->shapes.quality.begin(), r.frame->shapes.quality.end())));
}

// A click in a view picks the triangle under the mouse; the panel's numbers are the core's for
// that triangle. Marching Cubes' corners lie on the iso-surface; the net's triangle follows the
// iteration shown.
TEST(AppViews, ClickPicksATriangle) {
    auto h = make_app(4);
    ASSERT_TRUE(h->run_until(settled));
    App& app = h->app();
    const UiRect mc = *app.widget_rect("view_mc");
    h->click(mc.centre_x(), mc.centre_y());
    ASSERT_TRUE(app.picked());
    PickedTriangle p = *app.picked();
    EXPECT_EQ(p.view, 0);
    EXPECT_EQ(p.mesh, app.results().mc);
    const Mesh& m = app.results().mc->mesh;
    ASSERT_LT(p.triangle, m.triangle_count());
    glm::vec3 c[3];
    for (int k = 0; k < 3; ++k) c[k] = m.positions[m.indices[3 * p.triangle + std::size_t(k)]];
    const TriangleShape shape = triangle_shape(c[0], c[1], c[2]);
    EXPECT_EQ(p.shape.quality, shape.quality);
    EXPECT_EQ(p.shape.quality60, shape.quality60);
    EXPECT_EQ(p.shape.radius_ratio, shape.radius_ratio);
    EXPECT_EQ(p.shape.quality, app.results().mc->shapes.quality[p.triangle]);
    EXPECT_NEAR(p.angles[0] + p.angles[1] + p.angles[2], 180.0f, 1e-3f);
    EXPECT_NEAR(std::min({p.angles[0], p.angles[1], p.angles[2]}), shape.min_angle, 1e-3f);
    // The ray through the view's centre: the sphere's nearest point to the eye is in front.
    EXPECT_GT(glm::dot(glm::normalize(c[0] - app.camera().target),
                       glm::normalize(app.camera().eye() - app.camera().target)),
              0.9f);
    for (float d : p.iso_distance) EXPECT_LT(d, 0.05f); // on the phantom's exact sphere
    ASSERT_TRUE(app.widget_rect("pick_panel"));

    // The net: picked at iteration 4, then step back: the same triangle of iteration 3.
    const UiRect net = *app.widget_rect("view_net");
    h->click(net.centre_x(), net.centre_y());
    ASSERT_TRUE(app.picked());
    EXPECT_EQ(app.picked()->view, 1);
    const std::size_t triangle = app.picked()->triangle;
    EXPECT_EQ(app.picked()->shape.quality, app.results().frame->shapes.quality[triangle]);
    app.step(-1);
    ASSERT_TRUE(h->run_until(settled));
    h->frame();
    ASSERT_TRUE(app.picked());
    EXPECT_EQ(app.picked()->mesh->iteration, 3);
    EXPECT_EQ(app.picked()->triangle, triangle);
    EXPECT_EQ(app.picked()->shape.quality, app.results().frame->shapes.quality[triangle]);

    // A click beside the mesh picks nothing; a drag turns the camera and picks nothing new.
    h->click(net.x0 + 3, net.y0 + 3);
    EXPECT_FALSE(app.picked());
    h->drag(net.centre_x(), net.centre_y(), net.centre_x() + 40, net.centre_y());
    EXPECT_FALSE(app.picked());
}

// The explain window follows the mode chosen, and Escape closes it.
TEST(AppUi, ExplainWindowOpensAndCloses) {
    auto h = make_app(1);
    h->app().set_explain_open(true);
    h->frame();
    h->frame();
    EXPECT_TRUE(h->app().widget_rect("explain_window"));
    h->tap(key::Escape);
    EXPECT_FALSE(h->app().explain_open());
}

// View > Copy camera: a snert render command line with the views' camera, which applied to a
// freshly framed camera gives the views' camera back.
TEST(AppViews, CameraCopiesAsACommandLine) {
    auto h = make_app(1);
    ASSERT_TRUE(h->run_until(settled));
    App& app = h->app();
    app.turn_camera(0.4f, -0.2f);
    h->frame();
    const std::string command = app.camera_command();
    EXPECT_EQ(command.rfind("snert render phantom:sphere --size 32 --iso ", 0), 0u) << command;
    const std::string arguments = render::camera_arguments(render::camera_spec_of(app.camera()));
    EXPECT_NE(command.find(" --mode snert --iteration 1 " + arguments + " --out "),
              std::string::npos)
        << command;
    render::OrbitCamera other;
    render::apply_camera_spec(other, render::camera_spec_of(app.camera()),
                              app.results().mc->mesh.positions);
    EXPECT_NEAR(other.yaw, app.camera().yaw, 1e-6f);
    EXPECT_NEAR(other.pitch, app.camera().pitch, 1e-6f);
    EXPECT_EQ(other.target, app.camera().target);
    EXPECT_EQ(other.distance, app.camera().distance);
}
