// The app's hooks for the slice view (slice_panel.h): its place beside the 3D views, and the
// crosshair it shares with them.
#include "app.h"

#include <glm/gtc/matrix_transform.hpp>
#include <imgui.h>

#include "slice_panel.h"

namespace snert::app {

void App::draw_slice_area(float x, float y, float width, float height) {
    slice_panel_->draw(results_, requested_.inside, shown_iteration(), fonts_, ImVec2(x, y),
                       ImVec2(x + width, y + height));
    rects_["slice_view"] = UiRect{x, y, x + width, y + height};
}

// The slice view's picked point in a 3D view: a yellow ring with a cross, where the camera
// projects it.
void App::draw_crosshair(const UiRect& view) {
    const std::optional<glm::vec3> picked = slice_panel_->crosshair();
    if (!picked || !results_.source || !results_.source->volume) return;
    const glm::vec3 world = index_to_world(*results_.source->volume, *picked);
    const glm::vec4 clip = camera_.projection(view.width() / std::max(1.0f, view.height())) *
                           camera_.view() * glm::vec4(world, 1.0f);
    if (!(clip.w > 0.0f)) return;
    const glm::vec2 ndc = glm::vec2(clip) / clip.w;
    const ImVec2 p(view.x0 + (0.5f * ndc.x + 0.5f) * view.width(),
                   view.y0 + (0.5f - 0.5f * ndc.y) * view.height());
    if (p.x < view.x0 || p.x > view.x1 || p.y < view.y0 || p.y > view.y1) return;
    ImDrawList* draw = ImGui::GetWindowDrawList();
    const float r = 0.6f * fonts_.size;
    const ImU32 outline = IM_COL32(0, 0, 0, 200), colour = IM_COL32(255, 230, 0, 255);
    for (const auto& [c, t] : {std::pair{outline, 4.0f}, std::pair{colour, 2.0f}}) {
        draw->AddCircle(p, r, c, 0, t);
        draw->AddLine(ImVec2(p.x - 2 * r, p.y), ImVec2(p.x - r, p.y), c, t);
        draw->AddLine(ImVec2(p.x + r, p.y), ImVec2(p.x + 2 * r, p.y), c, t);
        draw->AddLine(ImVec2(p.x, p.y - 2 * r), ImVec2(p.x, p.y - r), c, t);
        draw->AddLine(ImVec2(p.x, p.y + r), ImVec2(p.x, p.y + 2 * r), c, t);
    }
}

} // namespace snert::app
