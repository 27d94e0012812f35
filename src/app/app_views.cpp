// The main area: the toolbar, the two linked 3D views with their titles, and the iteration bar.
#include "app.h"

#include "render/gl.h" // glad first

#include <algorithm>
#include <cmath>
#include <cstdio>

#include <imgui.h>

#include "render/panels.h"
#include "view_renderer.h"

namespace snert::app {

namespace {

constexpr ImU32 kHint = IM_COL32(80, 86, 96, 255);

// The title a view shows above it: the iteration the slider shows, even while its mesh is on
// its way (the view then says "updating...").
std::string net_title(const DisplayMesh& frame, int shown, const JobResults& results) {
    std::string title =
        std::string(label_of(frame.method)) + "  \xC2\xB7  iteration " + std::to_string(shown);
    if (results.iteration_count() > 0)
        title += " of " + std::to_string(results.iteration_count() - 1);
    return title;
}

void centred_text(ImDrawList* draw, ImFont* font, ImVec2 min, ImVec2 max, ImU32 color,
                  const std::string& text) {
    const ImVec2 size =
        font->CalcTextSizeA(font->FontSize, max.x - min.x, max.x - min.x, text.c_str());
    const ImVec2 at(std::round(0.5f * (min.x + max.x - size.x)),
                    std::round(0.5f * (min.y + max.y - size.y)));
    draw->AddText(font, font->FontSize, at, color, text.c_str(), nullptr, max.x - min.x);
}

// A small translucent label (for "updating" and hints) at `at`.
void tag(ImDrawList* draw, ImFont* font, ImVec2 at, ImU32 color, const std::string& text) {
    const ImVec2 size = font->CalcTextSizeA(font->FontSize, 1e9f, 0, text.c_str());
    const float pad = 0.3f * font->FontSize;
    draw->AddRectFilled(ImVec2(at.x - pad, at.y - 0.5f * pad),
                        ImVec2(at.x + size.x + pad, at.y + size.y + 0.5f * pad),
                        IM_COL32(255, 255, 255, 200), pad);
    draw->AddText(font, font->FontSize, at, color, text.c_str());
}

Action shading_action(render::Shading shading) {
    switch (shading) {
    case render::Shading::Flat:
        return Action::ShadingFlat;
    case render::Shading::Smooth:
        return Action::ShadingSmooth;
    case render::Shading::Quality:
        break;
    }
    return Action::ShadingQuality;
}

Action preset_action(render::ViewPreset preset) {
    switch (preset) {
    case render::ViewPreset::Front:
        return Action::ViewFront;
    case render::ViewPreset::Side:
        return Action::ViewSide;
    case render::ViewPreset::Top:
        return Action::ViewTop;
    case render::ViewPreset::Iso:
        break;
    }
    return Action::ViewIso;
}

} // namespace

void App::draw_main_area(float width, float height) {
    ImGui::BeginChild("views area", ImVec2(width, height), false,
                      ImGuiWindowFlags_NoScrollbar | ImGuiWindowFlags_NoScrollWithMouse);
    const float pad = std::round(0.4f * fonts_.size);
    ImGui::SetCursorPos(ImVec2(pad, pad));
    draw_toolbar();
    const float bar_height = ImGui::GetFrameHeightWithSpacing() + 2 * pad;
    const float views_top = ImGui::GetCursorPosY() + pad;
    ImGui::SetCursorPos(ImVec2(0, views_top));
    draw_views(width, std::max(height - views_top - bar_height, 2.0f * fonts_.size));
    ImGui::SetCursorPos(ImVec2(pad, ImGui::GetCursorPosY() + pad));
    draw_iteration_bar();
    ImGui::EndChild();
}

void App::draw_toolbar() {
    ViewSettings& view = settings_.view;
    ImGui::PushStyleVar(ImGuiStyleVar_ItemSpacing, ImGui::GetStyle().ItemInnerSpacing);
    ImGui::AlignTextToFramePadding();
    ImGui::TextUnformatted("Shading");
    ImGui::SameLine();
    for (const Named<render::Shading>& row : name_table(render::Shading{})) {
        const Action action = shading_action(row.value);
        if (ImGui::RadioButton(std::string(row.label).c_str(), view.shading == row.name))
            perform(action);
        if (ImGui::IsItemHovered())
            ImGui::SetTooltip("%s  (%s)", shortcut_for(action).description,
                              shortcut_for(action).keys);
        ImGui::SameLine();
    }
    ImGui::Checkbox("Wireframe", &view.wireframe);
    if (ImGui::IsItemHovered()) ImGui::SetTooltip("draw the triangle edges  (W)");
    if (view.shading == "quality") {
        // The measure the colours (and the histograms) show, and the red threshold.
        ImGui::SameLine();
        const ShapeMeasure measure = color_by();
        const std::string symbol(label_of(measure));
        // As wide as the longest shape's label, wider only for the distance shown.
        const float label_width =
            std::max(ImGui::CalcTextSize("radius ratio").x, ImGui::CalcTextSize(symbol.c_str()).x);
        ImGui::SetNextItemWidth(label_width + ImGui::GetFrameHeight() +
                                2 * ImGui::GetStyle().FramePadding.x);
        if (ImGui::BeginCombo("##color by", symbol.c_str())) {
            for (const Named<ShapeMeasure>& row : name_table(ShapeMeasure{})) {
                const std::string item =
                    std::string(row.label) + " = " + std::string(measure_definition(row.value));
                if (ImGui::Selectable(item.c_str(), row.value == measure))
                    view.color_by = std::string(row.name);
            }
            ImGui::EndCombo();
        }
        record("color_by");
        if (ImGui::IsItemHovered())
            ImGui::SetTooltip("colour the triangles by %s = %s", symbol.c_str(),
                              std::string(measure_definition(measure)).c_str());
        // A distance has no poor-quality red: its scale is fixed (core/metrics.h).
        if (!is_distance(measure)) {
            ImGui::SameLine();
            ImGui::SetNextItemWidth(8.5f * fonts_.size);
            const std::string format = "red: " + symbol + " < %.2f";
            ImGui::SliderFloat("##threshold", &view.quality_threshold, 0.0f, 0.6f, format.c_str());
            if (ImGui::IsItemHovered())
                ImGui::SetTooltip("triangles whose %s is under this value are drawn red",
                                  symbol.c_str());
        }
    }
    // The camera group on a second row when the first has no room for it.
    float camera_width = ImGui::CalcTextSize("Camera").x + ImGui::CalcTextSize("Reset").x +
                         2 * ImGui::GetStyle().FramePadding.x;
    for (const Named<render::ViewPreset>& row : name_table(render::ViewPreset{}))
        camera_width += ImGui::CalcTextSize(std::string(row.label).c_str()).x +
                        2 * ImGui::GetStyle().FramePadding.x + ImGui::GetStyle().ItemSpacing.x;
    camera_width += 2 * ImGui::GetStyle().ItemSpacing.x;
    const float right_edge = ImGui::GetWindowPos().x + ImGui::GetWindowContentRegionMax().x;
    if (right_edge - ImGui::GetItemRectMax().x - 2.0f * fonts_.size > camera_width) {
        ImGui::SameLine(0, 2.0f * fonts_.size);
    } else {
        ImGui::SetCursorPosX(ImGui::GetCursorPosX() + std::round(0.4f * fonts_.size));
    }
    ImGui::AlignTextToFramePadding();
    ImGui::TextUnformatted("Camera");
    ImGui::SameLine();
    for (const Named<render::ViewPreset>& row : name_table(render::ViewPreset{})) {
        const Action action = preset_action(row.value);
        if (ImGui::Button(std::string(row.label).c_str())) perform(action);
        if (ImGui::IsItemHovered())
            ImGui::SetTooltip("%s  (%s)", shortcut_for(action).description,
                              shortcut_for(action).keys);
        ImGui::SameLine();
    }
    if (ImGui::Button("Reset")) reset_camera();
    if (ImGui::IsItemHovered())
        ImGui::SetTooltip("frame both meshes again  (R, or double-click a view)");
    ImGui::PopStyleVar();
}

void App::draw_views(float width, float height) {
    const float f = fonts_.size;
    if (slice_view_) {
        // The slice view takes the right part; the 3D views keep at least 16 lines of width.
        const float slice_width =
            std::round(std::max(0.0f, std::min(0.45f * width, width - 16 * f)));
        const ImVec2 at = ImGui::GetCursorScreenPos();
        if (slice_width > 12 * f) {
            draw_slice_area(at.x + width - slice_width, at.y, slice_width, height);
            ImGui::SetCursorScreenPos(at);
            width -= slice_width + std::round(0.3f * f);
        }
    }
    const float title_height = std::round(2.9f * f);
    const float gap = std::round(0.3f * f);
    const float view_width = std::floor((width - gap) / 2.0f);
    const float view_height = std::max(height - title_height, f);
    const ImVec2 origin = ImGui::GetCursorScreenPos();
    ImDrawList* draw = ImGui::GetWindowDrawList();

    // 3D: drawn now into the views' targets (only when something changed), shown as images.
    const ImVec2 scale = ImGui::GetIO().DisplayFramebufferScale;
    view_aspect_ = view_width / view_height;
    frame_camera_if_needed();
    views_->set_measure(color_by());
    views_->render(int(std::lround(view_width * scale.x)), int(std::lround(view_height * scale.y)),
                   camera_, render::measure_style(draw_style(), color_by(), color_scale()));

    const std::shared_ptr<const DisplayMesh> meshes[2] = {shown_mc(), shown_net()};
    const bool current[2] = {results_.mc_current, results_.frame_current && meshes[1] &&
                                                      meshes[1]->iteration == shown_iteration()};
    const bool busy = !results_.finished && results_.error.empty();
    for (int i = 0; i < 2; ++i) {
        const float x = origin.x + float(i) * (view_width + gap);
        const ImVec2 title_min(x, origin.y), title_max(x + view_width, origin.y + title_height);
        const ImVec2 view_min(x, origin.y + title_height),
            view_max(x + view_width, origin.y + title_height + view_height);
        draw->AddRectFilled(title_min, title_max, IM_COL32(255, 255, 255, 255));
        if (meshes[i]) {
            const std::string title =
                i == 0 ? "Marching Cubes" : net_title(*meshes[i], shown_iteration(), results_);
            render::draw_view_title(draw, title_min, title_max,
                                    {meshes[i]->method, title, &meshes[i]->metrics}, fonts_);
        } else {
            const std::string name =
                i == 0 ? "Marching Cubes"
                       : std::string(label_of(method_of(settings_.parameters.relax.mode)));
            centred_text(draw, fonts_.bold, title_min, title_max, IM_COL32(28, 30, 34, 255), name);
        }
        // No picture before the views' first render (their pictures are made a frame each).
        if (const unsigned texture = views_->texture(i); texture != 0)
            draw->AddImage(ImTextureID(std::intptr_t(texture)), view_min, view_max, ImVec2(0, 1),
                           ImVec2(1, 0));
        if (slice_view_)
            draw_crosshair(UiRect{view_min.x, view_min.y, view_max.x, view_max.y}, i == 1);
        ImGui::SetCursorScreenPos(view_min);
        ImGui::InvisibleButton(i == 0 ? "##view mc" : "##view net", ImVec2(view_width, view_height),
                               ImGuiButtonFlags_MouseButtonLeft |
                                   ImGuiButtonFlags_MouseButtonRight |
                                   ImGuiButtonFlags_MouseButtonMiddle);
        record(i == 0 ? "view_mc" : "view_net");
        view_rects_[std::size_t(i)] = UiRect{view_min.x, view_min.y, view_max.x, view_max.y};
        handle_view_input(i, view_rects_[std::size_t(i)]);
        if (slice_view_) pick_for_slice(view_rects_[std::size_t(i)], i == 1);
        // The picked triangle, outlined where it is now.
        if (picked_ && picked_->view == i && picked_->mesh == meshes[i]) {
            const glm::mat4 to_clip = camera_.projection(view_width / view_height) * camera_.view();
            ImVec2 corners[3];
            bool in_front = true;
            for (int k = 0; k < 3; ++k) {
                const glm::vec4 c = to_clip * glm::vec4(picked_->corners[std::size_t(k)], 1.0f);
                in_front = in_front && c.w > 0;
                corners[k] = ImVec2(view_min.x + (0.5f + 0.5f * c.x / c.w) * view_width,
                                    view_min.y + (0.5f - 0.5f * c.y / c.w) * view_height);
            }
            if (in_front) {
                draw->PushClipRect(view_min, view_max, true);
                draw->AddPolyline(corners, 3, IM_COL32(255, 255, 255, 255), ImDrawFlags_Closed,
                                  4.0f);
                draw->AddPolyline(corners, 3, IM_COL32(214, 0, 120, 255), ImDrawFlags_Closed, 2.0f);
                draw->PopClipRect();
            }
        }

        // Overlays: what is happening when there is nothing (yet) to see.
        if (!meshes[i]) {
            const std::string text = !results_.error.empty() ? results_.error
                                     : i == 0                ? "computing Marching Cubes..."
                                                             : "relaxing the SurfaceNet...";
            centred_text(draw, fonts_.regular, view_min, view_max,
                         results_.error.empty() ? kHint : IM_COL32(190, 30, 30, 255), text);
        } else if (!current[i] && (busy || i == 1)) {
            tag(draw, fonts_.small, ImVec2(view_min.x + 0.5f * f, view_min.y + 0.4f * f), kHint,
                "updating...");
        }
        if (i == 1 && meshes[i] && results_.frame_recomputed)
            tag(draw, fonts_.small, ImVec2(view_max.x - 8.5f * f, view_min.y + 0.4f * f), kHint,
                "recomputed from a keyframe");
    }
    // How to move the camera, for people who have not read the help: in the left view, as much
    // of it as fits there.
    if (!capturing_) {
        static const char* const hints[] = {
            "drag: turn  \xC2\xB7  right-drag: pan  \xC2\xB7  wheel: zoom  \xC2\xB7  double-click: "
            "reset",
            "drag: turn  \xC2\xB7  right-drag: pan  \xC2\xB7  wheel: zoom",
            "drag: turn  \xC2\xB7  wheel: zoom"};
        for (const char* hint : hints) {
            const float w = fonts_.small->CalcTextSizeA(fonts_.small->FontSize, 1e9f, 0, hint).x;
            if (w + 1.6f * f > view_width) continue;
            tag(draw, fonts_.small,
                ImVec2(origin.x + 0.6f * f, origin.y + title_height + view_height - 1.6f * f),
                kHint, hint);
            break;
        }
    }

    // The quality legend in the right view, as in the figures.
    if (settings_.view.shading == "quality") {
        const ImVec2 legend = render::quality_legend_size(fonts_.size);
        const float margin = std::round(0.6f * f);
        const float right = origin.x + 2 * view_width + gap - margin;
        const float bottom = origin.y + title_height + view_height - margin;
        const float legend_width = std::min(legend.x, view_width - 2 * margin);
        if (legend_width > 6 * f && view_height > legend.y + 4 * f) {
            // On a white card, drawn last: readable over any part of the mesh.
            const float pad = std::round(0.3f * f);
            draw->AddRectFilled(ImVec2(right - legend_width - pad, bottom - legend.y - pad),
                                ImVec2(right + pad, bottom + pad), IM_COL32(255, 255, 255, 235),
                                pad);
            draw->AddRect(ImVec2(right - legend_width - pad, bottom - legend.y - pad),
                          ImVec2(right + pad, bottom + pad), IM_COL32(200, 204, 212, 255), pad);
            render::draw_quality_legend(draw, ImVec2(right - legend_width, bottom - legend.y),
                                        ImVec2(right, bottom), settings_.view.quality_threshold,
                                        fonts_, color_by(), color_scale());
        }
    }
    views_rect_ = UiRect{origin.x, origin.y, origin.x + 2 * view_width + gap,
                         origin.y + title_height + view_height};
    rects_["views"] = views_rect_;
    ImGui::SetCursorScreenPos(ImVec2(origin.x, origin.y + title_height + view_height));
    ImGui::Dummy(ImVec2(width, 0));
}

void App::handle_view_input(int view, const UiRect& area) {
    const ImGuiIO& io = ImGui::GetIO();
    // A click (the mouse hardly moved while down) picks a triangle; a drag turns the camera.
    if (ImGui::IsItemDeactivated() && ImGui::IsMouseReleased(ImGuiMouseButton_Left) &&
        io.MouseDragMaxDistanceSqr[ImGuiMouseButton_Left] < 9.0f)
        pick(view, io.MousePos.x, io.MousePos.y);
    if (ImGui::IsItemHovered()) {
        if (io.MouseWheel != 0) camera_.zoom(std::pow(1.12f, io.MouseWheel));
        if (ImGui::IsMouseDoubleClicked(ImGuiMouseButton_Left)) reset_camera();
    }
    if (!ImGui::IsItemActive()) return;
    const ImVec2 d = io.MouseDelta;
    if (d.x == 0 && d.y == 0) return;
    const bool pan = ImGui::IsMouseDown(ImGuiMouseButton_Right) ||
                     ImGui::IsMouseDown(ImGuiMouseButton_Middle) || io.KeyShift;
    const float h = std::max(area.height(), 1.0f);
    if (pan) {
        camera_.pan(-d.x / h, d.y / h);
    } else {
        // A drag across the view's height turns the camera by about 180 degrees.
        camera_.orbit(-d.x / h * 3.14159f, d.y / h * 3.14159f);
    }
}

void App::draw_iteration_bar() {
    const int count = results_.iteration_count();
    const int last = std::max(count - 1, 0);
    const int shown = shown_iteration();
    const bool has_net = count > 0;
    ImGui::AlignTextToFramePadding();
    ImGui::TextUnformatted("Relaxation");
    ImGui::SameLine();
    ImGui::BeginDisabled(!has_net);
    auto button = [&](const char* label, const char* id, Action action) {
        const bool pressed = ImGui::Button(label);
        record(id);
        if (ImGui::IsItemHovered(ImGuiHoveredFlags_AllowWhenDisabled))
            ImGui::SetTooltip("%s  (%s)", shortcut_for(action).description,
                              shortcut_for(action).keys);
        ImGui::SameLine();
        return pressed;
    };
    if (button("|<", "first", Action::FirstIteration)) perform(Action::FirstIteration);
    if (button(" < ", "step_back", Action::StepBack)) step(-1);
    if (button(playing_ ? "Pause" : " Play ", "play", Action::PlayPause)) set_playing(!playing_);
    if (button(" > ", "step_forward", Action::StepForward)) step(+1);
    if (button(">|", "last", Action::LastIteration)) perform(Action::LastIteration);

    char format[64];
    std::snprintf(format, sizeof format, "iteration %%d of %d", last);
    int value = shown;
    const float run_width =
        ImGui::CalcTextSize("Run to convergence").x + 2 * ImGui::GetStyle().FramePadding.x;
    std::string state;
    if (!results_.error.empty())
        state = "failed";
    else if (!results_.finished)
        state = results_.frame && results_.frame->last ? "measuring iterations..."
                : has_net                              ? "relaxing..."
                                                       : "computing...";
    else if (results_.finished->converged)
        state = "converged at " + std::to_string(results_.finished->iterations);
    else
        state = "stopped at max. iterations";
    // The state only where the slider keeps room (the status line says it too).
    const float state_width = std::max(ImGui::CalcTextSize(state.c_str()).x, 12.0f * fonts_.size) +
                              ImGui::GetStyle().ItemSpacing.x;
    const float slider_room = ImGui::GetContentRegionAvail().x - run_width -
                              ImGui::GetStyle().ItemSpacing.x - std::round(0.4f * fonts_.size);
    const bool show_state = slider_room - state_width >= 14.0f * fonts_.size;
    ImGui::SetNextItemWidth(
        std::max(slider_room - (show_state ? state_width : 0.0f), 6.0f * fonts_.size));
    if (ImGui::SliderInt("##iteration", &value, 0, last, format, ImGuiSliderFlags_AlwaysClamp)) {
        playing_ = false;
        show_iteration(value);
    }
    record("iteration_slider");
    if (ImGui::IsItemHovered(ImGuiHoveredFlags_AllowWhenDisabled))
        ImGui::SetTooltip("drag to any iteration of the relaxation; the right view and every "
                          "number follow it");
    ImGui::SameLine();
    const bool converged = results_.finished && results_.finished->converged;
    ImGui::BeginDisabled(converged && following_);
    if (ImGui::Button("Run to convergence")) run_to_convergence();
    ImGui::EndDisabled();
    record("run_to_convergence");
    if (ImGui::IsItemHovered(ImGuiHoveredFlags_AllowWhenDisabled))
        ImGui::SetTooltip("relax further until the largest move is under epsilon, then show "
                          "the last iteration  (C)");
    ImGui::EndDisabled();
    if (show_state) {
        ImGui::SameLine();
        ImGui::AlignTextToFramePadding();
        ImGui::TextDisabled("%s", state.c_str());
    }
}

} // namespace snert::app
