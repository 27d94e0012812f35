// The side panel (volume, iso value, relaxation parameters, progress) and the bottom panel
// (quality histograms with the metrics table, and the convergence plots).
#include "app.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include <imgui.h>
#include <imgui_stdlib.h>

#include "core/phantom.h"
#include "path_completion.h"
#include "plots.h"
#include "render/panels.h"

namespace snert::app {

namespace {

constexpr int kPhantomSizes[] = {32, 48, 64, 96, 128};

// A "(?)" after the previous item that explains it on hover.
void help_marker(const char* text) {
    ImGui::SameLine();
    ImGui::TextDisabled("(?)");
    if (ImGui::IsItemHovered()) {
        ImGui::BeginTooltip();
        ImGui::PushTextWrapPos(ImGui::GetFontSize() * 26.0f);
        ImGui::TextUnformatted(text);
        ImGui::PopTextWrapPos();
        ImGui::EndTooltip();
    }
}

// A combo over a small set of enum values.
template <class T>
bool enum_combo(const char* label, T& value,
                std::initializer_list<std::pair<T, const char*>> items) {
    const char* preview = items.begin()->second;
    for (const auto& [v, name] : items)
        if (v == value) preview = name;
    bool changed = false;
    if (ImGui::BeginCombo(label, preview)) {
        for (const auto& [v, name] : items) {
            if (ImGui::Selectable(name, v == value)) {
                changed = v != value;
                value = v;
            }
        }
        ImGui::EndCombo();
    }
    return changed;
}

// Tab in the open field completes the path (the candidates are kept for the list under it).
struct CompletionState {
    std::vector<std::string>* candidates;
};
int complete_callback(ImGuiInputTextCallbackData* data) {
    if (data->EventFlag != ImGuiInputTextFlags_CallbackCompletion) return 0;
    auto* state = static_cast<CompletionState*>(data->UserData);
    const PathCompletion completion =
        complete_path(std::string(data->Buf, std::size_t(data->BufTextLen)));
    *state->candidates = completion.candidates;
    if (completion.completed.size() > std::size_t(data->BufTextLen)) {
        data->DeleteChars(0, data->BufTextLen);
        data->InsertChars(0, completion.completed.c_str());
    }
    return 0;
}

std::string phantom_label(const std::string& name, int size) {
    return name + "  (" + std::to_string(size) + "\xC2\xB3)";
}

} // namespace

void App::draw_side_panel() {
    ImGui::PushStyleVar(ImGuiStyleVar_WindowPadding, ImGui::GetStyle().WindowPadding);
    ImGui::BeginChild("side content", ImVec2(0, 0), false, ImGuiWindowFlags_AlwaysUseWindowPadding);
    ImGui::PopStyleVar();
    ImGui::PushItemWidth(-8.5f * fonts_.size);
    if (ImGui::CollapsingHeader("Volume", ImGuiTreeNodeFlags_DefaultOpen)) draw_volume_section();
    if (ImGui::CollapsingHeader("Iso-surface", ImGuiTreeNodeFlags_DefaultOpen)) draw_iso_section();
    if (ImGui::CollapsingHeader("Relaxation (SurfaceNet)", ImGuiTreeNodeFlags_DefaultOpen))
        draw_relaxation_section();
    if (ImGui::CollapsingHeader("Progress", ImGuiTreeNodeFlags_DefaultOpen))
        draw_progress_section();
    ImGui::PopItemWidth();
    ImGui::EndChild();
}

void App::draw_volume_section() {
    const Parameters& p = settings_.parameters;
    if (results_.source) {
        ImGui::PushFont(fonts_.bold);
        ImGui::TextWrapped("%s", results_.source->title.c_str());
        ImGui::PopFont();
        ImGui::PushStyleColor(ImGuiCol_Text, IM_COL32(88, 92, 100, 255));
        ImGui::TextWrapped("%s", results_.source->description.c_str());
        ImGui::PopStyleColor();
    } else {
        ImGui::TextDisabled("loading %s...", p.volume.input.c_str());
    }
    ImGui::Spacing();

    // Phantoms: synthetic volumes with an exact reference surface.
    const std::string current_phantom(phantom_spec_name(p.volume.input));
    ImGui::SetNextItemWidth(-FLT_MIN);
    const std::string preview =
        current_phantom.empty()
            ? "Phantom..."
            : "Phantom: " + phantom_label(current_phantom, p.volume.phantom_size);
    if (ImGui::BeginCombo("##phantom", preview.c_str())) {
        for (const std::string& name : phantom_names())
            if (ImGui::Selectable(phantom_label(name, p.volume.phantom_size).c_str(),
                                  name == current_phantom))
                open({"phantom:" + name, p.volume.phantom_size});
        ImGui::Separator();
        ImGui::TextDisabled("grid size");
        for (int size : kPhantomSizes) {
            ImGui::SameLine();
            if (ImGui::RadioButton(std::to_string(size).c_str(), p.volume.phantom_size == size)) {
                VolumeSpec spec = p.volume;
                spec.phantom_size = size;
                if (!current_phantom.empty())
                    open(spec);
                else
                    settings_.parameters.volume.phantom_size = size;
            }
        }
        ImGui::EndCombo();
    }
    record("phantom_combo");

    // A file: typed (Tab completes), picked from the recent ones, or dropped on the window.
    if (focus_open_field_) {
        ImGui::SetKeyboardFocusHere();
        focus_open_field_ = false;
    }
    CompletionState completion{&completions_};
    ImGui::SetNextItemWidth(-4.0f * fonts_.size);
    const bool entered = ImGui::InputTextWithHint(
        "##open path", "volume file or DICOM folder", &open_path_text_,
        ImGuiInputTextFlags_EnterReturnsTrue | ImGuiInputTextFlags_CallbackCompletion,
        complete_callback, &completion);
    record("open_field");
    if (ImGui::IsItemHovered())
        ImGui::SetTooltip("NRRD, NIfTI, MetaImage, VTK or a DICOM folder.\nTab completes the "
                          "path; you can also drop a file onto the window.");
    const bool field_active = ImGui::IsItemActive();
    ImGui::SameLine();
    if (ImGui::Button("Open", ImVec2(-FLT_MIN, 0)) || entered) {
        completions_.clear();
        open_path(open_path_text_);
    }
    if (!completions_.empty()) {
        // The candidates of the last Tab; a click takes one (a folder continues the path).
        ImGui::BeginChild("completions",
                          ImVec2(0, std::min(6.5f, float(completions_.size()) + 0.5f) *
                                        ImGui::GetTextLineHeightWithSpacing()),
                          true);
        std::string picked;
        for (const std::string& c : completions_)
            if (ImGui::Selectable(c.c_str())) picked = c;
        ImGui::EndChild();
        if (!picked.empty()) {
            open_path_text_ = picked;
            completions_.clear();
            if (picked.back() == '/')
                focus_open_field_ = true;
            else
                open_path(picked);
        }
        if (!field_active && !ImGui::IsWindowFocused(ImGuiFocusedFlags_ChildWindows) &&
            ImGui::IsMouseClicked(ImGuiMouseButton_Left) && picked.empty())
            completions_.clear();
    }
    if (!settings_.recent_files.empty()) {
        ImGui::SetNextItemWidth(-FLT_MIN);
        if (ImGui::BeginCombo("##recent", "Recent files...")) {
            for (const std::string& path : settings_.recent_files)
                if (ImGui::Selectable(path.c_str())) open_path(path);
            ImGui::EndCombo();
        }
    }
    if (!can_load_files()) ImGui::TextDisabled("(this build reads phantoms only)");
    ImGui::Spacing();
}

void App::draw_iso_section() {
    Parameters& p = settings_.parameters;
    const float width = ImGui::GetContentRegionAvail().x;
    if (results_.source) {
        const ValueHistogram& h = results_.source->histogram;
        if (const auto value = value_histogram_plot("##value histogram", h, p.iso,
                                                    ImVec2(width, 3.6f * fonts_.size), fonts_)) {
            p.iso = *value;
            p.auto_iso = false;
        }
        record("value_histogram");
        float iso = p.iso;
        ImGui::SetNextItemWidth(width - ImGui::CalcTextSize("Suggested").x - 3.0f * fonts_.size);
        if (ImGui::SliderFloat("##iso", &iso, h.lo, h.hi, "iso %.4g")) {
            p.iso = iso;
            p.auto_iso = false;
        }
        record("iso_slider");
        if (ImGui::IsItemHovered())
            ImGui::SetTooltip("the grey value of the surface: Marching Cubes interpolates it, "
                              "the segmentation thresholds at it (Ctrl+click to type)");
        ImGui::SameLine();
        if (ImGui::Checkbox("Suggested", &p.auto_iso) && p.auto_iso) p.iso = results_.iso;
        if (ImGui::IsItemHovered())
            ImGui::SetTooltip("phantoms: their own iso; files: Otsu's threshold of the histogram");
    }
    int inside = p.inside == InsideIs::Above ? 0 : 1;
    ImGui::TextUnformatted("Object is");
    ImGui::SameLine();
    ImGui::RadioButton("brighter", &inside, 0);
    ImGui::SameLine();
    ImGui::RadioButton("darker", &inside, 1);
    help_marker("Inside the object: the samples at or above the iso value (bone in CT, the "
                "phantoms) or at or below it (air, CSF in a T1 MRI).");
    p.inside = inside == 0 ? InsideIs::Above : InsideIs::Below;
    ImGui::Spacing();
}

void App::draw_relaxation_section() {
    Parameters& p = settings_.parameters;
    RelaxOptions& r = p.relax;
    enum_combo("Mode", r.mode,
               {{RelaxMode::Snert, "SNERT"},
                {RelaxMode::Averaging, "SNA (averaging)"},
                {RelaxMode::Gradient, "Gradient only"}});
    help_marker(
        "SNA: each node moves towards the mean of its neighbours (paper eq. 1-2): "
        "smooth but it shrinks. Gradient: each node moves onto the iso-surface along the "
        "gradient (eq. 3-4). SNERT: both, the smoothing kept within the surface (eq. 5-6).");
    ImGui::BeginDisabled(r.mode == RelaxMode::Gradient);
    ImGui::SliderFloat("Smoothing", &r.smoothing_weight, 0.0f, 2.0f, "%.2f");
    ImGui::EndDisabled();
    help_marker("Weight of the averaging term (eq. 1 / eq. 5).");
    ImGui::BeginDisabled(r.mode == RelaxMode::Averaging);
    ImGui::SliderFloat("Gradient", &r.gradient_weight, 0.0f, 2.0f, "%.2f");
    ImGui::EndDisabled();
    help_marker(
        "Weight of the gradient term d g that pulls nodes onto the iso-surface (eq. 4 / 6).");
    ImGui::BeginDisabled(r.mode != RelaxMode::Snert);
    enum_combo(
        "Schedule", r.schedule,
        {{Schedule::Simultaneous, "both at once"}, {Schedule::SmoothingFirst, "one, then other"}});
    help_marker("SNERT only: apply both terms in one step, or smooth first and end every "
                "iteration with the favoured goal.");
    if (r.schedule == Schedule::SmoothingFirst) {
        int favour = r.favour_accuracy ? 0 : 1;
        ImGui::TextUnformatted("End with");
        ImGui::SameLine();
        ImGui::RadioButton("accuracy", &favour, 0);
        ImGui::SameLine();
        ImGui::RadioButton("smoothness", &favour, 1);
        r.favour_accuracy = favour == 0;
    }
    ImGui::EndDisabled();
    enum_combo("Constraint", r.constraint,
               {{Constraint::RayBox, "ray-box"}, {Constraint::Clip, "clip x, y, z"}});
    help_marker("Every node stays inside its own cell: ray-box shortens the move along its own "
                "direction; clipping each coordinate is the original SurfaceNet's rule.");
    ImGui::BeginDisabled(r.mode == RelaxMode::Averaging);
    enum_combo(
        "Gradient of", r.gradient,
        {{GradientMethod::Central, "central diff."}, {GradientMethod::Gaussian, "Gaussian"}});
    help_marker("How the grey-value gradient is estimated; a Gaussian derivative (sigma in "
                "voxels) is steadier on noisy data.");
    if (r.gradient == GradientMethod::Gaussian)
        ImGui::SliderFloat("Sigma", &r.gradient_sigma, 0.3f, 4.0f, "%.2f voxels");
    ImGui::EndDisabled();
    ImGui::SliderInt("Max. iterations", &r.max_iterations, 0, 2000, "%d",
                     ImGuiSliderFlags_Logarithmic);
    record("max_iterations");
    help_marker("The relaxation stops after this many iterations, or earlier when the largest "
                "node move falls under epsilon.");
    ImGui::SliderFloat("Epsilon", &r.epsilon, 1e-6f, 1e-1f, "%.1e voxels",
                       ImGuiSliderFlags_Logarithmic);
    help_marker("Convergence: stop when no node moves farther than this in an iteration.");
    enum_combo("Triangles", p.triangulation,
               {{TriangulationRule::ShorterDiagonal, "shorter diagonal"},
                {TriangulationRule::Delaunay, "Delaunay"}});
    help_marker("Each quad of the net is split into two triangles along its shorter diagonal, or "
                "by the Delaunay criterion.");
    if (ImGui::Button("Default parameters")) {
        const Parameters defaults;
        r = defaults.relax;
        p.triangulation = defaults.triangulation;
    }
    ImGui::Spacing();
}

void App::draw_progress_section() {
    const JobProgress& progress = worker_->progress();
    const bool ours = progress.generation.load() == results_.generation;
    const Stage stage = ours ? Stage(progress.stage.load()) : Stage::Idle;
    struct Row {
        Stage stage;
        const char* label;
    };
    const Row rows[] = {{Stage::Load, "Load"},
                        {Stage::Segment, "Segment"},
                        {Stage::MarchingCubes, "Marching Cubes"},
                        {Stage::Net, "SurfaceNet"},
                        {Stage::Relax, "Relaxation"}};
    // Compact rows in the smaller face: the panel should fit a laptop screen without scrolling.
    ImGui::PushFont(fonts_.small);
    ImGui::PushStyleVar(ImGuiStyleVar_FramePadding, ImVec2(ImGui::GetStyle().FramePadding.x, 1.0f));
    const float label_width = ImGui::CalcTextSize("Marching Cubes").x + fonts_.size;
    for (const Row& row : rows) {
        float fraction = ours ? progress.fraction[std::size_t(row.stage)].load() : 0.0f;
        std::string overlay;
        if (row.stage == Stage::Relax && ours) {
            const int k = progress.iteration.load(), n = progress.max_iterations.load();
            overlay = std::to_string(k) + " / " + std::to_string(n);
            if (n > 0) fraction = std::max(fraction, float(k) / float(n));
            if (results_.finished) fraction = 1.0f;
        }
        ImGui::TextUnformatted(row.label);
        ImGui::SameLine(label_width);
        ImGui::PushStyleColor(ImGuiCol_PlotHistogram, stage == row.stage
                                                          ? ImVec4(0.0f, 0.45f, 0.70f, 1.0f)
                                                          : ImVec4(0.55f, 0.62f, 0.72f, 1.0f));
        ImGui::ProgressBar(fraction, ImVec2(-FLT_MIN, 0.0f),
                           overlay.empty() ? nullptr : overlay.c_str());
        ImGui::PopStyleColor();
    }
    ImGui::PopStyleVar();
    std::string state = results_.error.empty() ? stage_name(stage) : "failed: " + results_.error;
    if (results_.finished && !options_.show_timings) state = "done";
    if (results_.finished && options_.show_timings) {
        char text[96];
        std::snprintf(text, sizeof text, "done in %.0f ms", results_.finished->ms);
        state = text;
    }
    ImGui::TextDisabled("%s", state.c_str());
    if (results_.net)
        ImGui::TextDisabled("net: %s nodes, %s quads",
                            render::format_count(results_.net->nodes).c_str(),
                            render::format_count(results_.net->quads).c_str());
    ImGui::PopFont();
}

void App::draw_bottom_panel(float height) {
    ImGui::BeginChild("bottom panel", ImVec2(0, height), false, ImGuiWindowFlags_NoScrollbar);
    const float pad = std::round(0.5f * fonts_.size);
    ImGui::SetCursorPos(ImVec2(pad, 0));
    if (ImGui::BeginTabBar("bottom tabs")) {
        const bool first = !tab_restored_; // select the saved tab once
        const ImGuiTabItemFlags quality_flags =
            first && settings_.layout.bottom_tab == 0 ? ImGuiTabItemFlags_SetSelected : 0;
        const ImGuiTabItemFlags convergence_flags =
            first && settings_.layout.bottom_tab == 1 ? ImGuiTabItemFlags_SetSelected : 0;
        tab_restored_ = true;
        if (ImGui::BeginTabItem("Quality & metrics", nullptr, quality_flags)) {
            settings_.layout.bottom_tab = 0;
            draw_quality_tab();
            ImGui::EndTabItem();
        }
        record("tab_quality");
        if (ImGui::BeginTabItem("Convergence", nullptr, convergence_flags)) {
            settings_.layout.bottom_tab = 1;
            draw_convergence_tab();
            ImGui::EndTabItem();
        }
        record("tab_convergence");
        ImGui::EndTabBar();
    }
    ImGui::EndChild();
}

void App::draw_quality_tab() {
    std::vector<render::PanelMethod> methods;
    if (results_.mc) methods.push_back({Method::MarchingCubes, "Marching Cubes", &results_.mc->metrics});
    // The frame's mesh is measured alone; where the relaxation stands at that iteration comes
    // from the iteration history.
    MethodMetrics frame_metrics;
    if (results_.frame) {
        frame_metrics = results_.frame->metrics;
        const int k = results_.frame->iteration;
        frame_metrics.iterations = k;
        if (k >= 0 && k < results_.iteration_count())
            frame_metrics.final_max_move = results_.iterations[std::size_t(k)].max_move;
        frame_metrics.converged =
            results_.finished && results_.finished->converged && k == results_.finished->iterations;
        methods.push_back({results_.frame->method,
                           std::string(label_of(results_.frame->method)) + ", iteration " +
                               std::to_string(k),
                           &frame_metrics});
    }
    if (methods.empty()) {
        ImGui::TextDisabled("  the histograms and the metrics appear when the meshes are ready");
        return;
    }
    const float pad = std::round(0.6f * fonts_.size);
    const ImVec2 start = ImGui::GetCursorScreenPos();
    const ImVec2 available = ImGui::GetContentRegionAvail();
    // The histogram's legend needs about 29 em; the rest goes to the table.
    const float histogram_width = std::clamp(std::round(0.45f * (available.x - 3 * pad)),
                                             28.0f * fonts_.size, 38.0f * fonts_.size);
    const float inner_height = std::max(available.y - pad, 4.0f * fonts_.size);
    render::draw_quality_histograms(
        ImGui::GetWindowDrawList(), ImVec2(start.x + pad, start.y + pad),
        ImVec2(start.x + pad + histogram_width, start.y + inner_height), methods, fonts_,
        settings_.view.shading == "quality", settings_.view.quality_threshold);
    const float table_x = start.x + 2.5f * pad + histogram_width;
    const float table_width = start.x + available.x - pad - table_x;
    // Two column groups (half the rows) when one group is too tall; the smaller face when the
    // table is too narrow for the measures' names at the regular size.
    render::FigureFonts table_fonts = fonts_;
    const bool compact = table_width < 40.0f * fonts_.size;
    if (compact) table_fonts.size = fonts_.small->FontSize;
    const int groups =
        render::metrics_table_height(1, table_fonts.size) <= inner_height - pad ? 1 : 2;
    ImGui::SetCursorScreenPos(ImVec2(table_x, start.y + pad));
    ImGui::BeginChild("metrics", ImVec2(table_width, inner_height - pad), false);
    if (compact) ImGui::PushFont(fonts_.small);
    render::metrics_table("metrics table", methods, groups, table_width - fonts_.size, table_fonts);
    if (compact) ImGui::PopFont();
    ImGui::EndChild();
}

void App::draw_convergence_tab() {
    const std::vector<IterationStats>& it = results_.iterations;
    if (it.empty()) {
        ImGui::TextDisabled("  the curves appear while the net relaxes");
        return;
    }
    std::vector<float> max_move, quality, smooth, accuracy;
    for (const IterationStats& s : it) {
        max_move.push_back(s.max_move);
        quality.push_back(float(s.quality_mean));
        smooth.push_back(float(s.smoothness));
        accuracy.push_back(float(s.accuracy_vertices));
    }
    const MethodMetrics* mc = results_.mc ? &results_.mc->metrics : nullptr;
    const ImU32 color = render::method_color_u32(method_of(settings_.parameters.relax.mode));
    const bool has_accuracy = it.front().accuracy_vertices >= 0;
    std::vector<ConvergencePlot> plots = {
        {"Largest move (voxels)",
         "how far the farthest node moved in the iteration; the "
         "relaxation stops when it falls under epsilon; logarithmic axis",
         max_move, 1, shown_iteration(), std::nullopt, true, color},
        {"Mean quality", "smallest / largest angle, averaged over the triangles (higher is better)",
         quality, 0, shown_iteration(),
         mc ? std::optional<float>(float(mc->quality.mean)) : std::nullopt, false, color},
        {"Smoothness (rad)",
         "mean |2 pi - angle sum| at the vertices (lower is smoother); "
         "logarithmic axis",
         smooth, 0, shown_iteration(),
         mc ? std::optional<float>(float(mc->smoothness)) : std::nullopt, true, color},
    };
    if (has_accuracy)
        plots.push_back({"Accuracy (voxels)",
                         results_.analytic_reference
                             ? "mean distance of the vertices to the exact surface of the phantom "
                               "(lower is better); logarithmic axis"
                             : "mean first-order distance |I - iso| / |grad I| of the vertices to "
                               "the iso-surface (lower is better); logarithmic axis",
                         accuracy, 0, shown_iteration(),
                         mc && mc->accuracy
                             ? std::optional<float>(float(mc->accuracy->vertices_mean))
                             : std::nullopt,
                         true, color});
    const float pad = std::round(0.6f * fonts_.size);
    const ImVec2 available = ImGui::GetContentRegionAvail();
    const float width = (available.x - pad * float(plots.size() + 1)) / float(plots.size());
    const float height = std::max(available.y - pad, 5.0f * fonts_.size);
    ImGui::SetCursorPos(ImVec2(ImGui::GetCursorPosX() + pad, ImGui::GetCursorPosY() + pad));
    for (std::size_t i = 0; i < plots.size(); ++i) {
        if (i > 0) ImGui::SameLine(0, pad);
        const std::string id = "##plot" + std::to_string(i);
        if (const auto k = convergence_plot(id.c_str(), plots[i], ImVec2(width, height), fonts_)) {
            playing_ = false;
            if (*k != shown_iteration() || following_) show_iteration(*k);
        }
        record("plot_" + std::to_string(i));
    }
}

} // namespace snert::app
