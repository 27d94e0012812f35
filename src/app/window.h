// The app in a window: the thin GLFW glue around App (app.h). Creates the window and its GL
// 3.3 core context, runs ImGui's GLFW and OpenGL 3 backends, forwards dropped files, sleeps
// while nothing changes, and stores the window's size and place in the settings on exit.
#pragma once

#include <stdexcept>
#include <string>

#include "app.h"

namespace snert::app {

// No window could be opened (no display, no GL 3.3): not the input's fault.
struct NoWindow : std::runtime_error {
    using std::runtime_error::runtime_error;
};

struct WindowOptions {
    AppOptions app;
    int width = 0, height = 0;   // window size; 0: the saved size
    std::string screenshot_path; // non-empty: automation mode (see run_window)
    int frames = 10;             // automation: frames drawn after the first result
    bool save_settings = true;   // write the settings on exit
    bool stats = false;          // run the scripted session of stats_session.h, print, exit
};

// Runs the app until the window is closed (or Quit). In automation mode (screenshot_path
// set) it draws `frames` frames after the first complete result (both meshes and the end of the
// relaxation), writes the whole window as a PNG and returns 0; an input that does not load or a
// failed job returns 2 after printing the error (no screenshot of a fallback). Throws NoWindow
// when no window can be opened (no display), with GLFW's reason; std::runtime_error naming the
// file when the screenshot cannot be written. In stats mode it runs StatsSession's script,
// prints its table and JSON to stdout and returns 0 (1 when it did not finish in 5 minutes).
int run_window(const WindowOptions& options);

} // namespace snert::app
