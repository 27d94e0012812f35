// Picking a triangle in a 3D view: the ray from the eye through the clicked pixel, the first
// triangle of the shown mesh it meets (core/triangle_pick.h), and the panel that describes it.
#include "app.h"

#include <cmath>
#include <limits>

#include <glm/gtc/matrix_transform.hpp>
#include <imgui.h>

#include "core/triangle_pick.h"

namespace snert::app {

bool App::pick(int view, float x, float y) {
    const UiRect& area = view_rects_[std::size_t(view)];
    const std::shared_ptr<const DisplayMesh> mesh = view == 0 ? results_.mc : results_.frame;
    if (!mesh || area.width() <= 0 || area.height() <= 0) return false;
    // Normalised device coordinates of the pixel, then back through the camera.
    const float nx = 2.0f * (x - area.x0) / area.width() - 1.0f;
    const float ny = 1.0f - 2.0f * (y - area.y0) / area.height();
    const glm::mat4 inverse =
        glm::inverse(camera_.projection(area.width() / area.height()) * camera_.view());
    const glm::vec4 near = inverse * glm::vec4(nx, ny, -1.0f, 1.0f);
    const glm::vec4 far = inverse * glm::vec4(nx, ny, 1.0f, 1.0f);
    const glm::vec3 origin = glm::vec3(near) / near.w;
    const std::optional<TriangleHit> hit =
        first_hit(mesh->mesh, origin, glm::vec3(far) / far.w - origin);
    if (!hit) {
        picked_.reset();
        return false;
    }
    picked_ = PickedTriangle{};
    picked_->view = view;
    picked_->triangle = hit->triangle;
    measure_picked(mesh);
    return true;
}

// The picked triangle's numbers on `mesh` (the view's mesh now: another iteration keeps the
// same triangle of the net).
void App::measure_picked(std::shared_ptr<const DisplayMesh> mesh) {
    PickedTriangle& p = *picked_;
    if (!mesh || p.triangle >= mesh->mesh.triangle_count()) {
        picked_.reset();
        return;
    }
    p.mesh = std::move(mesh);
    const Mesh& m = p.mesh->mesh;
    for (int k = 0; k < 3; ++k)
        p.corners[std::size_t(k)] = m.positions[m.indices[3 * p.triangle + std::size_t(k)]];
    p.angles = triangle_angles(p.corners[0], p.corners[1], p.corners[2]);
    p.shape = triangle_shape(p.corners[0], p.corners[1], p.corners[2]);
    p.iso_distance.fill(std::numeric_limits<float>::quiet_NaN());
    if (!results_.source || !results_.source->volume) return;
    // Three evaluations of the reference the metrics use (voxels, index space).
    const AccuracyReference reference = accuracy_reference(*results_.source, results_.iso);
    if (!reference.distance) return;
    for (int k = 0; k < 3; ++k)
        p.iso_distance[std::size_t(k)] = std::abs(reference.distance(
            world_to_index(*results_.source->volume, p.corners[std::size_t(k)])));
}

void App::draw_pick_panel() {
    if (!picked_ || capturing_) return;
    const std::shared_ptr<const DisplayMesh> shown =
        picked_->view == 0 ? results_.mc : results_.frame;
    if (shown != picked_->mesh) measure_picked(shown);
    if (!picked_) return;
    const PickedTriangle& p = *picked_;
    const UiRect& area = view_rects_[std::size_t(p.view)];
    // In the view's top-left corner, in the small face: the framed mesh stays in sight.
    ImGui::SetNextWindowPos(ImVec2(area.x0 + 0.3f * fonts_.size, area.y0 + 0.3f * fonts_.size),
                            ImGuiCond_Appearing);
    ImGui::PushFont(fonts_.small);
    bool open = true;
    ImGui::PushStyleVar(ImGuiStyleVar_WindowBorderSize, 1.0f);
    ImGui::SetNextWindowBgAlpha(0.94f);
    const bool visible =
        ImGui::Begin("Triangle", &open,
                     ImGuiWindowFlags_AlwaysAutoResize | ImGuiWindowFlags_NoCollapse |
                         ImGuiWindowFlags_NoFocusOnAppearing | ImGuiWindowFlags_NoSavedSettings);
    ImGui::PopStyleVar();
    if (visible) {
        record("pick_panel");
        const std::string from = p.view == 0
                                     ? std::string("Marching Cubes")
                                     : std::string(label_of(p.mesh->method)) + ", iteration " +
                                           std::to_string(p.mesh->iteration);
        ImGui::Text("triangle %zu of %s", p.triangle, from.c_str());
        ImGui::Text("angles  %.1f\xC2\xB0  %.1f\xC2\xB0  %.1f\xC2\xB0", double(p.angles[0]),
                    double(p.angles[1]), double(p.angles[2]));
        if (p.shape.degenerate) ImGui::TextDisabled("degenerate (no area)");
        ImGui::Text("q %.3f   q60 %.3f   2r/R %.3f", double(p.shape.quality),
                    double(p.shape.quality60), double(p.shape.radius_ratio));
        if (ImGui::IsItemHovered())
            ImGui::SetTooltip("q = smallest / largest angle, q60 = smallest angle / 60\xC2\xB0, "
                              "2r/R = inradius / circumradius x 2 (1 for an equilateral one)");
        if (std::isnan(p.iso_distance[0]))
            ImGui::TextDisabled("no iso-surface to measure against");
        else
            ImGui::Text("to the iso-surface  %.3f  %.3f  %.3f voxels", double(p.iso_distance[0]),
                        double(p.iso_distance[1]), double(p.iso_distance[2]));
    }
    ImGui::End();
    ImGui::PopFont();
    if (!open) picked_.reset();
}

} // namespace snert::app
