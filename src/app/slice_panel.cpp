// The app's slice view (see slice_panel.h).
#include "slice_panel.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <span>
#include <string>

#include "core/names.h"
#include "core/segmentation.h"
#include "shortcuts.h"

namespace snert::app {

namespace {

// An index-space copy of a world mesh (DisplayMesh meshes are in world units).
Mesh index_mesh(const Mesh& world, const Volume& volume) {
    Mesh index = world;
    for (glm::vec3& p : index.positions) p = world_to_index(volume, p);
    return index;
}

// Iteration `k`'s move of `node` and the node's path over iterations 0..last, redone from the
// net: relax() is deterministic, so the positions equal those the worker had bit for bit.
SlicePanel::Inspected inspect(std::shared_ptr<const RelaxContext> c, std::uint32_t node, int k,
                              int last, std::stop_token stop) {
    SlicePanel::Inspected r;
    RelaxOptions options = c->options;
    options.max_iterations = std::max(k, last);
    options.epsilon = 0.0f;
    std::vector<glm::vec3> before = c->net->positions, after;
    r.path.push_back(before[node]);
    relax(
        *c->net, c->grey.get(), options,
        [&](const RelaxIteration& it, std::span<const glm::vec3> positions) {
            r.path.push_back(positions[node]);
            if (it.iteration == k - 1) before.assign(positions.begin(), positions.end());
            if (it.iteration == k) after.assign(positions.begin(), positions.end());
            return true;
        },
        Progress{stop, {}});
    r.inspection = inspect_node(*c->net, c->grey.get(), c->options, k, before, after, node);
    return r;
}

} // namespace

SlicePanel::SlicePanel() = default;

SlicePanel::~SlicePanel() {
    // A long inspection (a large net, many iterations) stops at its next iteration.
    stop_.request_stop();
    if (pending_.valid()) pending_.wait();
}

std::optional<glm::vec3> SlicePanel::crosshair() const {
    if (!crosshair_) return std::nullopt;
    return slice_to_index(plane_, *crosshair_);
}

void SlicePanel::step_slice(int delta) {
    if (!source_) return;
    const int count = slice_count(*source_->volume, plane_.axis);
    const int index = std::clamp(plane_.index + delta, 0, count - 1);
    if (index == plane_.index) return;
    plane_.index = index;
    texture_stale_ = contours_stale_ = true;
}

void SlicePanel::show_point(glm::vec3 index_point) {
    if (!source_) return;
    const int n = normal_axis(plane_.axis);
    const int count = slice_count(*source_->volume, plane_.axis);
    const int index = std::clamp(int(std::lround(index_point[n])), 0, count - 1);
    if (index != plane_.index) {
        plane_.index = index;
        texture_stale_ = contours_stale_ = true;
    }
    crosshair_ = index_to_slice(plane_.axis, index_point);
    const glm::vec2 lo = window_.min, hi = window_.min + window_.size;
    if (glm::any(glm::lessThan(*crosshair_, lo)) || glm::any(glm::greaterThan(*crosshair_, hi)))
        window_.min = *crosshair_ - 0.5f * window_.size;
}

void SlicePanel::show_node(std::uint32_t node, glm::ivec3 cell, glm::vec3 position) {
    if (!source_) return;
    const int n = normal_axis(plane_.axis);
    show_point(position);
    const int count = slice_count(*source_->volume, plane_.axis);
    const int layer = std::clamp(cell[n], 0, count - 1);
    if (layer != plane_.index) {
        plane_.index = layer;
        texture_stale_ = contours_stale_ = true;
    }
    node_ = node;
}

void SlicePanel::update_volume(const JobResults& results, InsideIs inside) {
    if (!results.source || !results.source->volume) return;
    const bool new_volume = results.source != source_;
    if (!new_volume && iso_ == results.iso && inside_ == inside) return;
    source_ = results.source;
    iso_ = results.iso;
    inside_ = inside;
    const Volume& v = *source_->volume;
    scene_.segmentation = render::segmentation_legend(*source_, results.iso);
    if (new_volume) {
        plane_.index = slice_count(v, plane_.axis) / 2;
        window_level_ = window_preset(WindowPreset(preset_), v);
        window_ = render::whole_slice(slice_size(v.dims, plane_.axis));
        node_.reset();
        crosshair_.reset();
        inspection_.reset();
        inspected_ = {};
    }
    texture_stale_ = contours_stale_ = true;
}

void SlicePanel::update_net(const JobResults& results, int iteration) {
    const std::shared_ptr<const RelaxContext> context =
        results.net ? results.net->context : nullptr;
    const std::shared_ptr<const DisplayMesh>& frame = results.frame;
    // The nodes at the shown iteration: the frame's vertices are the nodes, in node order.
    if (frame != positions_of_) {
        positions_of_ = frame;
        positions_.clear();
        if (frame && context && frame->mesh.positions.size() == context->net->node_count())
            positions_ = index_mesh(frame->mesh, *source_->volume).positions;
    }
    scene_.net = {};
    if (context && !positions_.empty()) {
        scene_.net.method = frame->method;
        scene_.net.net = context->net.get();
        scene_.net.positions = positions_;
        scene_.net.layer = net_in_slice(*context->net, plane_);
    }
    // The picked node's inspection follows the iteration slider, computed off the UI thread.
    if (pending_.valid() &&
        pending_.wait_for(std::chrono::seconds(0)) == std::future_status::ready) {
        try {
            Inspected done = pending_.get();
            inspection_ = std::move(done.inspection);
            path_ = std::move(done.path);
        } catch (const std::exception&) {
            inspection_.reset();
            path_.clear();
        }
        inspected_ = pending_key_;
    }
    const int last = results.iteration_count() - 1;
    const InspectionKey want{context.get(), node_.value_or(0), iteration, last};
    if (!node_ || !context || iteration < 1 || node_ >= context->net->node_count()) {
        inspection_.reset();
        path_.clear();
        inspected_ = {};
    } else if (!(want == inspected_) && !pending_.valid()) {
        pending_key_ = want;
        pending_ = std::async(std::launch::async, inspect, context, *node_, iteration, last,
                              stop_.get_token());
    }
    scene_.inspection = inspection_ && inspected_ == want ? &*inspection_ : nullptr;
}

void SlicePanel::draw(const JobResults& results, InsideIs inside, int iteration,
                      const render::FigureFonts& fonts, ImVec2 min, ImVec2 max) {
    ImDrawList* draw = ImGui::GetWindowDrawList();
    const float f = fonts.size;
    draw->AddRectFilled(min, max, IM_COL32(255, 255, 255, 255));
    update_volume(results, inside);
    if (!source_) {
        draw->AddText(ImVec2(min.x + f, min.y + f), IM_COL32(120, 120, 120, 255), "no volume yet");
        return;
    }
    const Volume& v = *source_->volume;

    // Controls: axis, slice, window preset.
    ImGui::SetCursorScreenPos(ImVec2(min.x + 0.3f * f, min.y + 0.25f * f));
    ImGui::PushID("slice view");
    ImGui::SetNextItemWidth(7.0f * f);
    if (ImGui::BeginCombo("##axis", std::string(label_of(plane_.axis)).c_str())) {
        for (const Named<SliceAxis>& a : name_table(SliceAxis{}))
            if (ImGui::Selectable(std::string(a.label).c_str(), a.value == plane_.axis)) {
                plane_.axis = a.value;
                plane_.index = slice_count(v, a.value) / 2;
                window_ = render::whole_slice(slice_size(v.dims, a.value));
                texture_stale_ = contours_stale_ = true;
            }
        ImGui::EndCombo();
    }
    ImGui::SameLine();
    const float preset_width = 9.0f * f;
    ImGui::SetNextItemWidth(
        std::max(4.0f * f, max.x - ImGui::GetCursorScreenPos().x - preset_width - 1.0f * f));
    int index = plane_.index;
    if (ImGui::SliderInt("##slice", &index, 0, slice_count(v, plane_.axis) - 1, "slice %d"))
        step_slice(index - plane_.index);
    ImGui::SameLine();
    ImGui::SetNextItemWidth(preset_width);
    const auto presets = name_table(WindowPreset{});
    if (ImGui::BeginCombo("##window", std::string(presets[std::size_t(preset_)].label).c_str())) {
        for (std::size_t i = 0; i < presets.size(); ++i)
            if (ImGui::Selectable(std::string(presets[i].label).c_str(), int(i) == preset_)) {
                preset_ = int(i);
                window_level_ = window_preset(presets[i].value, v);
                texture_stale_ = true;
            }
        ImGui::EndCombo();
    }
    ImGui::PopID();
    const float top = ImGui::GetCursorScreenPos().y + 0.2f * f;

    // The slice's pixels and the meshes' cross-sections, remade when they change.
    scene_.plane = plane_;
    scene_.size = slice_size(v.dims, plane_.axis);
    const glm::ivec2 axes = plane_axes(plane_.axis);
    scene_.spacing = {v.spacing[axes.x], v.spacing[axes.y]};
    if (texture_stale_) {
        const Slice slice = extract_slice(v, plane_);
        scene_.inside = slice_inside(slice, source_->mask.get(), iso_, inside_);
        texture_.upload(slice_pixels(slice, window_level_, scene_.inside), scene_.size.x,
                        scene_.size.y);
        texture_stale_ = false;
    }
    scene_.image = texture_.id();
    const std::shared_ptr<const DisplayMesh> meshes[2] = {results.mc, results.frame};
    if (contours_stale_ || meshes[0] != contour_meshes_[0] || meshes[1] != contour_meshes_[1]) {
        scene_.contours.clear();
        for (const std::shared_ptr<const DisplayMesh>& m : meshes)
            if (m) scene_.contours.push_back({m->method, mesh_cross_section(m->mesh, v, plane_)});
        contour_meshes_[0] = meshes[0];
        contour_meshes_[1] = meshes[1];
        contours_stale_ = false;
    }
    update_net(results, iteration);
    scene_.crosshair = crosshair_;

    // The view on the left, its legend and the node's values on the right.
    const float legend_width = std::clamp(0.36f * (max.x - min.x), 11.0f * f, 22.0f * f);
    const ImVec2 view_min(min.x, top), view_max(max.x - legend_width - 0.6f * f, max.y);
    if (view_max.x - view_min.x < 4.0f * f || view_max.y - view_min.y < 4.0f * f) return;
    render::draw_slice_view(draw, view_min, view_max, scene_, window_, fonts);
    const render::SliceMapping mapping = render::map_slice(view_min, view_max, scene_, window_);
    mapping_ = mapping;
    // The legend and the node's values scroll when they do not fit.
    ImGui::SetCursorScreenPos(ImVec2(view_max.x + 0.3f * f, top));
    ImGui::BeginChild("##slice legend", ImVec2(max.x - view_max.x - 0.3f * f, max.y - top));
    {
        const ImVec2 at = ImGui::GetCursorScreenPos();
        const float inner = ImGui::GetContentRegionAvail().x - 0.4f * f;
        float used = render::draw_slice_legend(
            ImGui::GetWindowDrawList(), ImVec2(at.x + 0.2f * f, at.y + 0.2f * f), inner, scene_,
            mapping.pixels_per_sample() >= render::kCellDetailPixels, fonts);
        if (node_ && !scene_.inspection && iteration >= 1) {
            ImGui::GetWindowDrawList()->AddText(ImVec2(at.x + 0.2f * f, at.y + used + 0.5f * f),
                                                IM_COL32(88, 92, 100, 255),
                                                "taking the move apart...");
            used += 1.5f * f;
        }
        if (!node_)
            ImGui::GetWindowDrawList()->AddText(ImVec2(at.x + 0.2f * f, at.y + used + 0.5f * f),
                                                IM_COL32(88, 92, 100, 255),
                                                "click a node to take its move apart");
        ImGui::Dummy(ImVec2(inner, used + 2.0f * f));
    }
    ImGui::EndChild();
    ImGui::SetCursorScreenPos(view_min);
    const bool clicked = ImGui::InvisibleButton(
        "##slice view area", ImVec2(view_max.x - view_min.x, view_max.y - view_min.y),
        ImGuiButtonFlags_MouseButtonLeft | ImGuiButtonFlags_MouseButtonRight);
    handle_mouse(mapping, view_min, view_max, clicked);
}

void SlicePanel::handle_mouse(const render::SliceMapping& mapping, ImVec2 min, ImVec2 max,
                              bool clicked) {
    const ImGuiIO& io = ImGui::GetIO();
    const glm::vec2 under = mapping.to_slice(io.MousePos);
    if (ImGui::IsItemHovered()) {
        if (io.MouseWheel != 0.0f) {
            // Zoom about the point under the pointer.
            const float factor = std::pow(0.85f, io.MouseWheel);
            window_.min = under + (window_.min - under) * factor;
            window_.size *= factor;
        }
        if (ImGui::IsMouseDoubleClicked(ImGuiMouseButton_Left))
            window_ = render::whole_slice(scene_.size);
    }
    // A left click (no drag) picks the nearest node, or puts the crosshair where no node is.
    if (clicked && ImGui::IsMouseReleased(ImGuiMouseButton_Left) &&
        io.MouseDragMaxDistanceSqr[ImGuiMouseButton_Left] < 16.0f) {
        node_ = render::pick_slice_node(scene_, mapping, io.MousePos, 12.0f);
        crosshair_ = node_ && *node_ < positions_.size()
                         ? index_to_slice(plane_.axis, positions_[*node_])
                         : under;
    }
    if (!ImGui::IsItemActive()) return;
    const ImVec2 d = io.MouseDelta;
    if (ImGui::IsMouseDragging(ImGuiMouseButton_Left, 4.0f)) {
        window_.min -= glm::vec2(d.x / mapping.scale.x, d.y / mapping.scale.y);
    } else if (ImGui::IsMouseDragging(ImGuiMouseButton_Right, 4.0f)) {
        // Window and level in steps proportional to the window: fine control at any range.
        const float step = window_level_.window / std::max(1.0f, max.x - min.x);
        window_level_.window = std::max(1e-6f, window_level_.window + d.x * step);
        window_level_.level -= d.y * step;
        texture_stale_ = true;
    }
}

} // namespace snert::app
