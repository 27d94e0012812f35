// snert_app_ui_snapshot OUT.png: drives the app headless (OSMesa) like a user would: waits for
// the two-spheres result, clicks Step back three times, drags the iteration slider to a
// quarter of its length, then checks the state and writes the window to OUT.png. CTest
// compares the picture with tests/snapshots/app_ui_scrub.png (run_ui_snapshot.cmake).
// Exit codes: 0 done, 1 a state check failed, 2 bad arguments.
#include <cmath>
#include <iostream>
#include <string>

#include "app/headless.h"
#include "render/image.h"

using namespace snert;
using namespace snert::app;

namespace {

bool settled(const App& app) {
    const JobResults& r = app.results();
    return r.finished && r.mc && r.frame && r.mc_current && r.frame_current &&
           r.frame->iteration == app.shown_iteration() && r.frame->metrics_complete;
}

int fail(const std::string& what) {
    std::cerr << "snert_app_ui_snapshot: " << what << "\n";
    return 1;
}

void click(HeadlessApp& h, const std::string& id) {
    const UiRect r = *h.app().widget_rect(id);
    h.click(r.centre_x(), r.centre_y());
}

} // namespace

int main(int argc, char** argv) {
    if (argc != 2) {
        std::cerr << "usage: snert_app_ui_snapshot OUT.png\n";
        return 2;
    }
    HeadlessOptions options;
    options.width = 1280;
    options.height = 800;
    options.gl_backend = "osmesa";
    options.app.source = SourceSpec{"phantom:two-spheres", 48};
    options.app.show_timings = false; // wall-clock times differ from run to run
    HeadlessApp h(options);
    App& app = h.app();
    app.settings().parameters.relax.max_iterations = 20;
    app.settings().parameters.relax.epsilon = 0.0f;
    if (!h.run_until(settled)) return fail("no result within the time limit");
    if (app.shown_iteration() != 20) return fail("expected to follow iteration 20");

    for (int i = 0; i < 3; ++i) click(h, "step_back");
    if (app.shown_iteration() != 17) return fail("Step back x3 should show 17");
    const UiRect slider = *app.widget_rect("iteration_slider");
    h.drag(slider.x1 - 3, slider.centre_y(), slider.x0 + 0.25f * slider.width(), slider.centre_y());
    const int k = app.shown_iteration();
    if (k < 3 || k > 7) return fail("the slider at a quarter shows " + std::to_string(k));
    h.move_mouse(2, float(options.height) - 2); // off every widget: no hover, no tooltip
    if (!h.run_until(settled)) return fail("the frame of the chosen iteration never came");
    const JobResults& r = app.results();
    if (r.frame->iteration != k) return fail("the right view does not show the slider's iteration");
    if (r.frame->metrics.quality.mean != r.iterations[std::size_t(k)].quality_mean)
        return fail("the metrics do not follow the chosen iteration");
    for (int i = 0; i < 3; ++i) h.frame();
    render::write_png(argv[1], h.capture());
    std::cout << "iteration " << k << ", mean quality " << r.frame->metrics.quality.mean << " (MC "
              << r.mc->metrics.quality.mean << "): " << argv[1] << "\n";
    return 0;
}
