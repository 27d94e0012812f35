// The app in an offscreen context with scripted input.
#include "headless.h"

#include "render/gl.h" // glad first

#include <chrono>
#include <thread>

#include <imgui.h>
#include <imgui_impl_opengl3.h>

#include "render/context.h"
#include "render/target.h"
#include "shortcuts.h"

namespace snert::app {

struct HeadlessApp::Impl {
    HeadlessOptions options;
    std::unique_ptr<render::GlContext> gl;
    ImGuiContext* imgui = nullptr;
    std::unique_ptr<render::RenderTarget> target;
    bool backend_ready = false;
};

namespace {

// ImGui's navigation keys, mapped to the GLFW key codes our shortcuts use (as the GLFW backend
// maps them), so text fields and keyboard navigation behave as in the window.
void map_keys(ImGuiIO& io) {
    io.KeyMap[ImGuiKey_Tab] = key::Tab;
    io.KeyMap[ImGuiKey_LeftArrow] = key::Left;
    io.KeyMap[ImGuiKey_RightArrow] = key::Right;
    io.KeyMap[ImGuiKey_UpArrow] = key::Up;
    io.KeyMap[ImGuiKey_DownArrow] = key::Down;
    io.KeyMap[ImGuiKey_Home] = key::Home;
    io.KeyMap[ImGuiKey_End] = key::End;
    io.KeyMap[ImGuiKey_Enter] = key::Enter;
    io.KeyMap[ImGuiKey_Escape] = key::Escape;
    io.KeyMap[ImGuiKey_Space] = key::Space;
    io.KeyMap[ImGuiKey_Backspace] = 259;
    io.KeyMap[ImGuiKey_Delete] = 261;
}

} // namespace

HeadlessApp::HeadlessApp(HeadlessOptions options) : impl_(std::make_unique<Impl>()) {
    impl_->options = std::move(options);
    impl_->gl = render::create_offscreen_context(impl_->options.gl_backend);
    impl_->imgui = ImGui::CreateContext();
    ImGui::SetCurrentContext(impl_->imgui);
    ImGuiIO& io = ImGui::GetIO();
    io.DisplaySize = ImVec2(float(impl_->options.width), float(impl_->options.height));
    io.DisplayFramebufferScale = ImVec2(1, 1);
    map_keys(io);
    app_ = std::make_unique<App>(impl_->options.app);
    if (!ImGui_ImplOpenGL3_Init("#version 330 core"))
        throw std::runtime_error("cannot start the ImGui OpenGL 3 backend");
    impl_->backend_ready = true;
    impl_->target =
        std::make_unique<render::RenderTarget>(impl_->options.width, impl_->options.height, 1);
}

HeadlessApp::~HeadlessApp() {
    ImGui::SetCurrentContext(impl_->imgui);
    impl_->gl->make_current();
    app_.reset(); // GL objects and the worker, while the context still exists
    impl_->target.reset();
    if (impl_->backend_ready) ImGui_ImplOpenGL3_Shutdown();
    ImGui::DestroyContext(impl_->imgui);
}

void HeadlessApp::frame(float dt) {
    ImGui::SetCurrentContext(impl_->imgui);
    ImGuiIO& io = ImGui::GetIO();
    io.DeltaTime = dt;
    ImGui_ImplOpenGL3_NewFrame();
    ImGui::NewFrame();
    app_->frame();
    ImGui::Render();
    impl_->target->bind();
    glClearColor(kWindowBackground[0], kWindowBackground[1], kWindowBackground[2],
                 kWindowBackground[3]);
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    ImGui_ImplOpenGL3_RenderDrawData(ImGui::GetDrawData());
    if (const auto request = app_->take_screenshot_request())
        app_->save_screenshot(capture(), *request, 1.0f);
    io.MouseWheel = 0;
}

bool HeadlessApp::run_until(const std::function<bool(const App&)>& done, double timeout_s) {
    const auto deadline =
        std::chrono::steady_clock::now() + std::chrono::duration<double>(timeout_s);
    while (std::chrono::steady_clock::now() < deadline) {
        frame();
        if (done(*app_)) return true;
        // At most about 60 frames a second, as a window with vsync draws: software GL draws
        // every frame on the CPUs the worker needs.
        std::this_thread::sleep_for(std::chrono::milliseconds(16));
    }
    return false;
}

void HeadlessApp::move_mouse(float x, float y) {
    ImGui::SetCurrentContext(impl_->imgui);
    ImGui::GetIO().MousePos = ImVec2(x, y);
}

void HeadlessApp::mouse_button(int button, bool down) {
    ImGui::SetCurrentContext(impl_->imgui);
    ImGui::GetIO().MouseDown[button] = down;
}

void HeadlessApp::key(int code, bool down) {
    ImGui::SetCurrentContext(impl_->imgui);
    ImGuiIO& io = ImGui::GetIO();
    if (down && !io.KeysDown[code]) app_->key_pressed(code, io.KeyCtrl);
    io.KeysDown[code] = down;
}

void HeadlessApp::set_ctrl(bool down) {
    ImGui::SetCurrentContext(impl_->imgui);
    ImGui::GetIO().KeyCtrl = down;
}

void HeadlessApp::wheel(float steps) {
    ImGui::SetCurrentContext(impl_->imgui);
    ImGui::GetIO().MouseWheel += steps;
}

void HeadlessApp::click(float x, float y) {
    move_mouse(x, y);
    frame();
    mouse_button(0, true);
    frame();
    mouse_button(0, false);
    frame();
}

void HeadlessApp::drag(float x0, float y0, float x1, float y1, int steps) {
    move_mouse(x0, y0);
    frame();
    mouse_button(0, true);
    frame();
    for (int i = 1; i <= steps; ++i) {
        const float t = float(i) / float(steps);
        move_mouse(x0 + t * (x1 - x0), y0 + t * (y1 - y0));
        frame();
    }
    mouse_button(0, false);
    frame();
}

void HeadlessApp::tap(int code, bool ctrl) {
    set_ctrl(ctrl);
    key(code, true);
    frame();
    key(code, false);
    set_ctrl(false);
    frame();
}

void HeadlessApp::type(const std::string& text) {
    ImGui::SetCurrentContext(impl_->imgui);
    ImGui::GetIO().AddInputCharactersUTF8(text.c_str());
    frame();
}

render::Image HeadlessApp::capture() const {
    return impl_->target->read();
}

} // namespace snert::app
