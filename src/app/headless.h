// The app without a window, for tests and automation: an offscreen GL context (OSMesa or EGL,
// render/context.h), Dear ImGui with the OpenGL 3 backend and no platform backend, and input
// that a test scripts (mouse position and buttons, keys) instead of a window system.
//
// Each frame() runs one full app frame into an offscreen target of the window's size;
// capture() reads it back. Time is scripted too (dt per frame), so playback is reproducible;
// the worker runs on its own thread as in the real app, so tests wait with run_until().
#pragma once

#include <functional>
#include <memory>
#include <string>

#include "app.h"
#include "render/image.h"

namespace snert::app {

struct HeadlessOptions {
    int width = 1280, height = 800;
    std::string gl_backend = "auto"; // "osmesa", "egl" or "auto" (render/context.h)
    AppOptions app;
};

class HeadlessApp {
  public:
    // Throws std::runtime_error when no offscreen GL context can be made.
    explicit HeadlessApp(HeadlessOptions options);
    ~HeadlessApp();
    HeadlessApp(const HeadlessApp&) = delete;
    HeadlessApp& operator=(const HeadlessApp&) = delete;

    App& app() { return *app_; }

    // One frame with the current input; dt is the frame's time in seconds.
    void frame(float dt = 1.0f / 60.0f);
    // Frames until `done(app)` holds (true) or `timeout_s` of wall time passed (false).
    bool run_until(const std::function<bool(const App&)>& done, double timeout_s = 120.0);

    // Scripted input; takes effect at the next frame.
    void move_mouse(float x, float y);
    void mouse_button(int button, bool down); // 0 left, 1 right, 2 middle
    void key(int code, bool down);            // shortcuts.h key codes
    void set_ctrl(bool down);
    void wheel(float steps);
    // Whole gestures (several frames each): press and release at a point; press at one point,
    // move to another in `steps` frames, release; press and release a key.
    void click(float x, float y);
    void drag(float x0, float y0, float x1, float y1, int steps = 8);
    void tap(int code, bool ctrl = false);
    // Types UTF-8 text into the focused field (one frame).
    void type(const std::string& text);

    // The last frame as an image (rows top to bottom).
    render::Image capture() const;

  private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
    std::unique_ptr<App> app_;
};

} // namespace snert::app
