// The app's hooks for the slice view (slice_panel.h): its place beside the 3D views, and the
// crosshair it shares with them.
#include "app.h"

#include <glm/gtc/matrix_transform.hpp>
#include <imgui.h>

#include "core/triangle_pick.h"
#include "slice_panel.h"

namespace snert::app {

void App::show_in_slice(glm::vec3 index_point) {
    slice_view_ = true;
    slice_panel_->show_point(index_point);
}

// A click (no drag) in a 3D view: the surface point under the pointer goes to the slice view;
// in the net's view the node nearest to it is picked and inspected.
void App::pick_for_slice(const UiRect& view, bool net_view) {
    const ImGuiIO& io = ImGui::GetIO();
    if (!ImGui::IsItemDeactivated() || !ImGui::IsMouseReleased(ImGuiMouseButton_Left) ||
        io.MouseDragMaxDistanceSqr[ImGuiMouseButton_Left] > 16.0f)
        return;
    const std::shared_ptr<const DisplayMesh>& shown = net_view ? results_.frame : results_.mc;
    if (!shown || !results_.source || !results_.source->volume) return;
    const glm::mat4 inverse = glm::inverse(
        camera_.projection(view.width() / std::max(1.0f, view.height())) * camera_.view());
    const glm::vec2 ndc(2.0f * (io.MousePos.x - view.x0) / view.width() - 1.0f,
                        1.0f - 2.0f * (io.MousePos.y - view.y0) / view.height());
    glm::vec4 a = inverse * glm::vec4(ndc, -1.0f, 1.0f), b = inverse * glm::vec4(ndc, 1.0f, 1.0f);
    a /= a.w;
    b /= b.w;
    const std::optional<TriangleHit> hit =
        first_hit(shown->mesh, glm::vec3(a), glm::vec3(b) - glm::vec3(a));
    if (!hit) return;
    const Volume& volume = *results_.source->volume;
    slice_view_ = true;
    const std::shared_ptr<const RelaxContext> context =
        results_.net ? results_.net->context : nullptr;
    // The net's mesh vertices are its nodes, in node order.
    if (net_view && context && shown->mesh.positions.size() == context->net->node_count()) {
        const std::uint32_t node = hit->nearest_vertex;
        slice_panel_->show_node(node, context->net->cells[node],
                                world_to_index(volume, shown->mesh.positions[node]));
        return;
    }
    slice_panel_->show_point(world_to_index(volume, hit->point));
}

void App::draw_slice_area(float x, float y, float width, float height) {
    slice_panel_->draw(results_, requested_.inside, shown_iteration(), fonts_, ImVec2(x, y),
                       ImVec2(x + width, y + height));
    rects_["slice_view"] = UiRect{x, y, x + width, y + height};
}

// The slice view's picked point in a 3D view, a yellow ring with a cross where the camera
// projects it; in the net's view also the picked node's path over the iterations.
void App::draw_crosshair(const UiRect& view, bool net_view) {
    if (!results_.source || !results_.source->volume) return;
    const Volume& volume = *results_.source->volume;
    const glm::mat4 to_clip =
        camera_.projection(view.width() / std::max(1.0f, view.height())) * camera_.view();
    auto project = [&](glm::vec3 index_point) -> std::optional<ImVec2> {
        const glm::vec4 clip = to_clip * glm::vec4(index_to_world(volume, index_point), 1.0f);
        if (!(clip.w > 0.0f)) return std::nullopt;
        const glm::vec2 ndc = glm::vec2(clip) / clip.w;
        return ImVec2(view.x0 + (0.5f * ndc.x + 0.5f) * view.width(),
                      view.y0 + (0.5f - 0.5f * ndc.y) * view.height());
    };
    ImDrawList* draw = ImGui::GetWindowDrawList();
    draw->PushClipRect(ImVec2(view.x0, view.y0), ImVec2(view.x1, view.y1), true);
    if (net_view) {
        const std::vector<glm::vec3>& path = slice_panel_->node_path();
        std::optional<ImVec2> previous;
        for (const glm::vec3& q : path) {
            const std::optional<ImVec2> p = project(q);
            if (p && previous) draw->AddLine(*previous, *p, IM_COL32(200, 20, 120, 255), 2.0f);
            if (p) draw->AddCircleFilled(*p, 2.5f, IM_COL32(200, 20, 120, 255));
            previous = p;
        }
    }
    draw->PopClipRect();
    const std::optional<glm::vec3> picked = slice_panel_->crosshair();
    if (!picked) return;
    const std::optional<ImVec2> at = project(*picked);
    if (!at) return;
    const ImVec2 p = *at;
    if (p.x < view.x0 || p.x > view.x1 || p.y < view.y0 || p.y > view.y1) return;
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
