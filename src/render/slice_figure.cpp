#include "slice_figure.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "figure.h"
#include "gl.h"
#include "imgui_offscreen.h"
#include "slice_texture.h"
#include "target.h"

namespace snert::render {

Image render_slice_figure(const SliceFigure& figure) {
    if (figure.width < 320 || figure.height < 240)
        throw std::invalid_argument("image size " + std::to_string(figure.width) + "x" +
                                    std::to_string(figure.height) +
                                    " is too small for the slice view (at least 320x240)");
    const glm::ivec2 size = figure.scene.size;
    if (figure.pixels.size() != std::size_t(size.x) * std::size_t(size.y) * 4)
        throw std::invalid_argument("render_slice_figure: pixels do not match the slice");
    const float f = figure_font_size(figure.width, figure.height);
    const float w = float(figure.width), h = float(figure.height);
    const float margin = std::round(0.7f * f);
    const float title_height = std::round(2.2f * f);
    const float caption_height = figure.caption.empty() ? 0.0f : std::round(1.7f * f);
    const float legend_width = std::round(std::clamp(0.36f * w, 16.0f * f, 30.0f * f));
    const ImVec2 view_min(margin, title_height);
    const ImVec2 view_max(w - legend_width - 2.0f * margin, h - caption_height - margin);

    RenderTarget target(figure.width, figure.height, figure.samples);
    target.bind();
    glClearColor(1.0f, 1.0f, 1.0f, 1.0f);
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    SliceTexture texture;
    texture.upload(figure.pixels, size.x, size.y);
    SliceScene scene = figure.scene;
    scene.image = texture.id();

    ImGuiOffscreen gui(f);
    target.bind();
    gui.draw(figure.width, figure.height, [&] {
        const FigureFonts& fonts = gui.fonts();
        ImDrawList* draw = ImGui::GetForegroundDrawList();
        draw->AddText(fonts.bold, fonts.bold->FontSize,
                      ImVec2(margin, 0.5f * (title_height - fonts.bold->FontSize)),
                      IM_COL32(30, 32, 36, 255), figure.title.c_str());
        draw_slice_view(draw, view_min, view_max, scene, figure.window, fonts);
        const SliceMapping m = map_slice(view_min, view_max, scene, figure.window);
        draw_slice_legend(draw, ImVec2(view_max.x + margin, title_height), legend_width, scene,
                          m.pixels_per_sample() >= kCellDetailPixels, fonts);
        if (!figure.caption.empty())
            draw->AddText(fonts.small, fonts.small->FontSize,
                          ImVec2(margin, h - caption_height +
                                             0.5f * (caption_height - fonts.small->FontSize)),
                          IM_COL32(88, 92, 100, 255), figure.caption.c_str());
    });
    return target.read();
}

} // namespace snert::render
