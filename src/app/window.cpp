// GLFW glue: the window, the frame loop, drag-and-drop, automation screenshots.
#include "window.h"

#include "render/gl.h" // glad before GLFW
#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <iostream>
#include <optional>
#include <stdexcept>

#include <imgui.h>
#include <imgui_impl_glfw.h>
#include <imgui_impl_opengl3.h>

#include "render/image.h"
#include "stats_session.h"
#include "view_renderer.h"

namespace snert::app {

namespace {

std::string g_glfw_error; // the last GLFW error, for the message when the window fails

void on_glfw_error(int code, const char* description) {
    char text[32];
    std::snprintf(text, sizeof text, " (0x%x)", code);
    g_glfw_error = std::string(description ? description : "unknown error") + text;
}

// What the window's callbacks reach through its user pointer.
struct WindowState {
    App* app = nullptr;
    // The person's input or the worker's results since the loop last looked: a frame is due at
    // once (set on the worker's thread too).
    std::atomic<bool> event{false};
};

WindowState* state_of(GLFWwindow* window) {
    return static_cast<WindowState*>(glfwGetWindowUserPointer(window));
}

void note_input(GLFWwindow* window) {
    if (WindowState* state = state_of(window)) state->event = true;
}

void on_drop(GLFWwindow* window, int count, const char** paths) {
    note_input(window);
    WindowState* state = state_of(window);
    std::vector<std::string> list(paths, paths + count);
    if (state && state->app) state->app->on_drop(list);
}

// Key presses go to the app as events (ImGui 1.86 only sees the key's state at frame time).
void on_key(GLFWwindow* window, int key, int /*scancode*/, int action, int mods) {
    note_input(window);
    WindowState* state = state_of(window);
    if (state && state->app && (action == GLFW_PRESS || action == GLFW_REPEAT))
        state->app->key_pressed(key, (mods & GLFW_MOD_CONTROL) != 0, action == GLFW_REPEAT);
}

// The other input only wakes the loop for a frame (ImGui's backend, installed after these, calls
// them after its own; it has no cursor callback of its own in 1.86).
void on_mouse_button(GLFWwindow* window, int, int, int) {
    note_input(window);
}
void on_scroll(GLFWwindow* window, double, double) {
    note_input(window);
}
void on_char(GLFWwindow* window, unsigned int) {
    note_input(window);
}
void on_cursor(GLFWwindow* window, double, double) {
    note_input(window);
}
void on_resize(GLFWwindow* window, int, int) {
    note_input(window);
}

// The window's framebuffer (width x height pixels) cleared to the app's background, as each
// frame starts its drawing.
void clear_window(int width, int height) {
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    glViewport(0, 0, width, height);
    glClearColor(kWindowBackground[0], kWindowBackground[1], kWindowBackground[2],
                 kWindowBackground[3]);
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
}

// Owns glfwInit / glfwTerminate and the window.
struct Glfw {
    GLFWwindow* window = nullptr;
    Glfw() {
        glfwSetErrorCallback(on_glfw_error);
        if (!glfwInit())
            throw NoWindow("cannot open a window: " + g_glfw_error +
                           "; without a display, `snert render` draws the same views "
                           "into a PNG");
    }
    ~Glfw() {
        if (window) glfwDestroyWindow(window);
        glfwTerminate();
    }
};

// The frame just drawn into the default framebuffer, rows top to bottom.
render::Image read_window(int width, int height) {
    render::Image image;
    image.width = width;
    image.height = height;
    image.rgba.resize(std::size_t(width) * std::size_t(height) * 4);
    glBindFramebuffer(GL_READ_FRAMEBUFFER, 0);
    glReadBuffer(GL_BACK);
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    std::vector<std::uint8_t> rows(image.rgba.size());
    glReadPixels(0, 0, width, height, GL_RGBA, GL_UNSIGNED_BYTE, rows.data());
    const std::size_t stride = std::size_t(width) * 4;
    for (int y = 0; y < height; ++y) // GL's rows are bottom-up
        std::copy_n(rows.data() + std::size_t(height - 1 - y) * stride, stride,
                    image.rgba.data() + std::size_t(y) * stride);
    for (std::size_t i = 3; i < image.rgba.size(); i += 4) image.rgba[i] = 255; // opaque PNG
    return image;
}

bool first_result_ready(const App& app) {
    const JobResults& r = app.results();
    return !r.error.empty() || !app.load_error().empty() ||
           (r.finished && r.mc && r.frame && r.mc_current && r.frame_current);
}

} // namespace

int run_window(const WindowOptions& options) {
    const bool automation = !options.screenshot_path.empty() || options.stats;
    const Settings saved = load_settings(options.app.settings_path);
    const int width = options.width > 0 ? options.width : saved.layout.window_width;
    const int height = options.height > 0 ? options.height : saved.layout.window_height;

    Glfw glfw;
    glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 3);
    glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 3);
    glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
    glfwWindowHint(GLFW_OPENGL_FORWARD_COMPAT, GLFW_TRUE);
    glfwWindowHint(GLFW_SCALE_TO_MONITOR, GLFW_TRUE);
    glfw.window = glfwCreateWindow(width, height, "snert: Marching Cubes and SNERT side by side",
                                   nullptr, nullptr);
    if (!glfw.window) throw NoWindow("cannot open a window: " + g_glfw_error);
    if (!automation && saved.layout.window_x >= 0 && saved.layout.window_y >= 0)
        glfwSetWindowPos(glfw.window, saved.layout.window_x, saved.layout.window_y);
    glfwMakeContextCurrent(glfw.window);
    glfwSwapInterval(options.stats ? 0 : 1); // stats: measure the work, not the display's rate
    render::load_gl(glfwGetProcAddress);

    IMGUI_CHECKVERSION();
    ImGuiContext* imgui = ImGui::CreateContext();
    AppOptions app_options = options.app;
    float scale_x = 1.0f, scale_y = 1.0f;
    glfwGetWindowContentScale(glfw.window, &scale_x, &scale_y);
    app_options.content_scale = scale_y;
    // A person's window (and the stats session, which measures it) keeps its frames short;
    // a screenshot run only waits for the result.
    app_options.background_worker = options.screenshot_path.empty();
    app_options.parts_between_frames = options.screenshot_path.empty();
    WindowState state;
    app_options.wake = [&state] {
        state.event = true;
        glfwPostEmptyEvent();
    };
    auto app = std::make_unique<App>(app_options);
    state.app = app.get();
    glfwSetWindowUserPointer(glfw.window, &state);
    glfwSetDropCallback(glfw.window, on_drop);
    // Before ImGui's backend, which chains to them.
    glfwSetKeyCallback(glfw.window, on_key);
    glfwSetMouseButtonCallback(glfw.window, on_mouse_button);
    glfwSetScrollCallback(glfw.window, on_scroll);
    glfwSetCharCallback(glfw.window, on_char);
    glfwSetCursorPosCallback(glfw.window, on_cursor);
    glfwSetFramebufferSizeCallback(glfw.window, on_resize);
    ImGui_ImplGlfw_InitForOpenGL(glfw.window, true);
    ImGui_ImplOpenGL3_Init("#version 330 core");
    // What software GL does once, before the first frame rather than in it (60-190 ms there on
    // llvmpipe): ImGui's shaders and font texture, the views' shaders, the window's first
    // buffers (shown cleared, as the first frame would show it before its views).
    ImGui_ImplOpenGL3_CreateDeviceObjects();
    int window_width = 0, window_height = 0;
    glfwGetFramebufferSize(glfw.window, &window_width, &window_height);
    app->warm_up(window_width, window_height);
    clear_window(window_width, window_height);
    glfwSwapBuffers(glfw.window);

    int result = 0;
    int frames_after_result = -1; // automation: counting once the first result is in
    std::optional<StatsSession> stats;
    if (options.stats) stats.emplace();
    const auto started = std::chrono::steady_clock::now();
    auto last_frame = started;
    while (!glfwWindowShouldClose(glfw.window) && !app->quit_requested()) {
        // Sleep until an event, or until the app's frame interval has passed since the last
        // frame (App::frame_interval: a few frames a second while only the worker's progress
        // changes, its results and the person's input waking the loop at once). Screenshots
        // are taken as fast as frames come, and the stats session's turn stands for a drag,
        // whose events would wake every frame.
        const bool polling = !options.screenshot_path.empty() || (stats && stats->turning());
        if (polling) {
            glfwPollEvents();
        } else {
            const auto due_in = [&] {
                double interval = app->frame_interval();
                // Once the comparison is in, the stats session acts between frames, with no
                // events to wake the loop; until then it measures the window as a person would
                // have it.
                if (stats && stats->acting()) interval = std::min(interval, App::kAnimatingFrame);
                return interval -
                       std::chrono::duration<double>(std::chrono::steady_clock::now() - last_frame)
                           .count();
            };
            // A large mesh's parts go on while the loop waits, one at a time (each within the
            // views' part budget), until a frame is due or an event comes. While the worker
            // computes, the parts of a drawing come at the animating rate, as one a frame did: a
            // new iteration cuts a series short, so faster parts would mostly be drawn for
            // nothing. The parts of a mesh's buffers go one after another: the views wait for
            // them.
            double wait = due_in();
            while (wait > 0 && !state.event && app->draw_part_between_frames()) {
                wait = due_in(); // the part may have made a frame due (a mesh sent whole)
                if (wait > 0 && app->worker().busy() && !app->sending_views())
                    glfwWaitEventsTimeout(std::min(App::kAnimatingFrame, wait));
                else
                    glfwPollEvents();
                wait = due_in();
            }
            if (wait > 0 && !state.event)
                glfwWaitEventsTimeout(wait);
            else
                glfwPollEvents();
        }
        // While events stream in (a drag) or the frames follow one another, a part of a mesh's
        // buffers still goes a frame.
        if (app_options.parts_between_frames && (polling || state.event) && app->sending_views())
            app->draw_part_between_frames();
        state.event = false;
        last_frame = std::chrono::steady_clock::now();
        if (glfwGetWindowAttrib(glfw.window, GLFW_ICONIFIED)) {
            glfwWaitEventsTimeout(0.1);
            continue;
        }
        const auto frame_start = std::chrono::steady_clock::now();
        if (stats) stats->before_frame(*app);
        ImGui_ImplOpenGL3_NewFrame();
        ImGui_ImplGlfw_NewFrame();
        ImGui::NewFrame();
        app->frame();
        ImGui::Render();
        int fb_width = 0, fb_height = 0;
        glfwGetFramebufferSize(glfw.window, &fb_width, &fb_height);
        clear_window(fb_width, fb_height);
        ImGui_ImplOpenGL3_RenderDrawData(ImGui::GetDrawData());
        const float scale = ImGui::GetIO().DisplayFramebufferScale.x;
        if (const auto request = app->take_screenshot_request())
            app->save_screenshot(read_window(fb_width, fb_height), *request, scale);

        if (stats) {
            glfwSwapBuffers(glfw.window);
            const std::chrono::duration<double, std::milli> work =
                std::chrono::steady_clock::now() - frame_start;
            stats->after_frame(*app, work.count());
            if (stats->done()) {
                std::cout << stats->table() << stats->json() << std::endl;
                break;
            }
            if (std::chrono::steady_clock::now() - started > std::chrono::minutes(5)) {
                std::cerr << "snert gui: the stats session did not finish in 5 minutes\n"
                          << stats->table();
                result = 1;
                break;
            }
            continue;
        }
        if (automation) {
            // A view still drawn in parts shows its preview: the picture waits for the whole.
            if (frames_after_result < 0 && first_result_ready(*app) &&
                !app->view_renderer().needs_refine())
                frames_after_result = 0;
            if (frames_after_result >= 0 && ++frames_after_result >= options.frames) {
                // The input asked for must be the one shown: no fallback in a screenshot.
                const std::string& error =
                    !app->load_error().empty() ? app->load_error() : app->results().error;
                if (!error.empty()) {
                    std::cerr << "snert gui: " << error << "\n";
                    result = 2;
                } else {
                    render::write_png(options.screenshot_path, read_window(fb_width, fb_height));
                    std::cout << "snert gui: saved " << fb_width << "x" << fb_height
                              << " window to " << options.screenshot_path << "\n";
                }
                break;
            }
            if (std::chrono::steady_clock::now() - started > std::chrono::minutes(5)) {
                std::cerr << "snert gui: no result after 5 minutes; no screenshot written\n";
                result = 1;
                break;
            }
        }
        glfwSwapBuffers(glfw.window);
    }

    if (options.save_settings && !automation) {
        Settings& s = app->settings();
        glfwGetWindowSize(glfw.window, &s.layout.window_width, &s.layout.window_height);
        glfwGetWindowPos(glfw.window, &s.layout.window_x, &s.layout.window_y);
        try {
            app->save_settings();
        } catch (const std::exception& e) {
            std::cerr << "snert gui: settings not saved: " << e.what() << "\n";
        }
    }
    glfwSetWindowUserPointer(glfw.window, nullptr);
    app.reset(); // its GL objects go while the context is current; the worker is joined
    ImGui_ImplOpenGL3_Shutdown();
    ImGui_ImplGlfw_Shutdown();
    ImGui::DestroyContext(imgui);
    return result;
}

} // namespace snert::app
