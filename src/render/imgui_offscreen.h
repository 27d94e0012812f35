// Dear ImGui without a window: its own ImGui context, the OpenGL 3 renderer backend and no
// platform backend (display size and time are set by hand). Draws into whatever framebuffer
// is bound, typically a RenderTarget.
#pragma once

#include <functional>

#include "fonts.h"

struct ImGuiContext;

namespace snert::render {

class ImGuiOffscreen {
  public:
    // Needs a current GL context (loaded through gl.h). Creates an ImGui context with the
    // figure fonts at `font_px` and the figure style; the ImGui context current before (the
    // app's, say) is current again when this returns. Throws std::runtime_error when the
    // OpenGL 3 backend cannot start.
    explicit ImGuiOffscreen(float font_px);
    ~ImGuiOffscreen();
    ImGuiOffscreen(const ImGuiOffscreen&) = delete;
    ImGuiOffscreen& operator=(const ImGuiOffscreen&) = delete;

    const FigureFonts& fonts() const { return fonts_; }

    // Runs `ui` as two ImGui frames of a width x height display (the first lets windows and
    // tables measure themselves) and draws the second into the bound framebuffer.
    void draw(int width, int height, const std::function<void()>& ui);

  private:
    ImGuiContext* context_ = nullptr;
    FigureFonts fonts_;
};

} // namespace snert::render
