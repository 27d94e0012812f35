#include "imgui_offscreen.h"

#include "gl.h" // glad before the backend header

#include <stdexcept>

#include <imgui.h>
#include <imgui_impl_opengl3.h>

#include "panels.h"

namespace snert::render {

namespace {
// Makes `context` current for a scope and restores the previous one.
class ContextScope {
  public:
    explicit ContextScope(ImGuiContext* context) : previous_(ImGui::GetCurrentContext()) {
        ImGui::SetCurrentContext(context);
    }
    ~ContextScope() { ImGui::SetCurrentContext(previous_); }
    ContextScope(const ContextScope&) = delete;
    ContextScope& operator=(const ContextScope&) = delete;

  private:
    ImGuiContext* previous_;
};
} // namespace

ImGuiOffscreen::ImGuiOffscreen(float font_px) {
    ContextScope scope(ImGui::GetCurrentContext());
    context_ = ImGui::CreateContext(); // CreateContext makes it current only when none was
    ImGui::SetCurrentContext(context_);
    ImGuiIO& io = ImGui::GetIO();
    io.IniFilename = nullptr; // nothing to remember between runs
    io.LogFilename = nullptr;
    fonts_ = add_figure_fonts(*io.Fonts, font_px);
    apply_figure_style(ImGui::GetStyle(), font_px);
    if (!ImGui_ImplOpenGL3_Init("#version 330 core")) {
        ImGui::DestroyContext(context_);
        context_ = nullptr;
        throw std::runtime_error("cannot start the ImGui OpenGL 3 backend");
    }
}

ImGuiOffscreen::~ImGuiOffscreen() {
    if (context_ == nullptr) return;
    {
        ContextScope scope(context_);
        ImGui_ImplOpenGL3_Shutdown();
    }
    ImGui::DestroyContext(context_);
}

void ImGuiOffscreen::draw(int width, int height, const std::function<void()>& ui) {
    ContextScope scope(context_);
    ImGuiIO& io = ImGui::GetIO();
    io.DisplaySize = ImVec2(float(width), float(height));
    io.DisplayFramebufferScale = ImVec2(1.0f, 1.0f);
    io.DeltaTime = 1.0f / 60.0f;
    for (int frame = 0; frame < 2; ++frame) {
        ImGui_ImplOpenGL3_NewFrame();
        ImGui::NewFrame();
        ui();
        ImGui::Render();
    }
    ImGui_ImplOpenGL3_RenderDrawData(ImGui::GetDrawData());
    check_gl("ImGui rendering");
}

} // namespace snert::render
