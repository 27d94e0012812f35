// The side panel (the input, iso value, relaxation parameters, progress) and the bottom panel
// (quality histograms with the metrics table, and the convergence plots).
#include "app.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>
#include <string_view>

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

// The head of a label, for a narrow combo: "SNERT: projected averaging ..." -> "SNERT",
// "ray-box (shorten the move)" -> "ray-box".
std::string short_label(std::string_view label) {
    return std::string(label.substr(0, std::min(label.find(": "), label.find(" ("))));
}

// A combo over an option enum: shows the labels of its name table (core/names.h), the whole
// label in the list and as the tooltip, its head in the narrow box.
template <class E> bool name_combo(const char* label, E& value) {
    bool changed = false;
    const std::string full(label_of(value));
    const bool open = ImGui::BeginCombo(label, short_label(full).c_str());
    if (!open && ImGui::IsItemHovered() && short_label(full) != full)
        ImGui::SetTooltip("%s", full.c_str());
    if (open) {
        for (const Named<E>& row : name_table(E{})) {
            if (ImGui::Selectable(std::string(row.label).c_str(), row.value == value)) {
                changed = row.value != value;
                value = row.value;
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

constexpr ImU32 kErrorColor = IM_COL32(190, 30, 30, 255);
constexpr ImU32 kWarningColor = IM_COL32(160, 90, 0, 255);
constexpr ImU32 kNoteColor = IM_COL32(88, 92, 100, 255);

void coloured_text(ImU32 color, const std::string& text) {
    ImGui::PushStyleColor(ImGuiCol_Text, color);
    ImGui::TextWrapped("%s", text.c_str());
    ImGui::PopStyleColor();
}

// A path field with Tab completion; the candidates of the last Tab are listed under it, and a
// click takes one (a folder continues the path). Returns true when Enter was pressed or a file
// was picked from the list.
bool path_field(const char* id, const char* hint, std::string& text,
                std::vector<std::string>& candidates, float width, bool& focus) {
    if (focus) {
        ImGui::SetKeyboardFocusHere();
        focus = false;
    }
    CompletionState completion{&candidates};
    ImGui::SetNextItemWidth(width);
    bool entered = ImGui::InputTextWithHint(id, hint, &text,
                                            ImGuiInputTextFlags_EnterReturnsTrue |
                                                ImGuiInputTextFlags_CallbackCompletion,
                                            complete_callback, &completion);
    return entered;
}

// The list under a path field after Tab. Returns the file picked (empty: none).
std::string completion_list(const char* id, std::string& text, std::vector<std::string>& candidates,
                            bool field_active, bool& focus) {
    if (candidates.empty()) return {};
    ImGui::BeginChild(id,
                      ImVec2(0, std::min(6.5f, float(candidates.size()) + 0.5f) *
                                    ImGui::GetTextLineHeightWithSpacing()),
                      true);
    std::string picked;
    for (const std::string& c : candidates)
        if (ImGui::Selectable(c.c_str())) picked = c;
    ImGui::EndChild();
    if (!picked.empty()) {
        text = picked;
        candidates.clear();
        if (picked.back() == '/') {
            focus = true;
            return {};
        }
        return picked;
    }
    if (!field_active && !ImGui::IsWindowFocused(ImGuiFocusedFlags_ChildWindows) &&
        ImGui::IsMouseClicked(ImGuiMouseButton_Left))
        candidates.clear();
    return {};
}

// One line for an input in the recent lists: the file, then its options.
std::string recent_label(const SourceSpec& spec) {
    namespace fs = std::filesystem;
    std::string text = spec.input;
    if (spec.raw) {
        const RawOptions& r = *spec.raw;
        text += "  (raw " + std::string(scalar_type_name(r.type)) + " " + std::to_string(r.dims.x) +
                "x" + std::to_string(r.dims.y) + "x" + std::to_string(r.dims.z) + ")";
    }
    if (!spec.series_uid.empty()) text += "  (series " + spec.series_uid + ")";
    if (spec.isotropic) {
        char edge[32];
        std::snprintf(edge, sizeof edge, "%g", double(*spec.isotropic));
        text += *spec.isotropic > 0.0f ? "  (cubic voxels of " + std::string(edge) + " mm)"
                                       : "  (cubic voxels)";
    }
    if (!spec.labels.empty()) {
        text += "  (labels " + fs::path(spec.labels).filename().string();
        if (spec.label) text += ", label " + std::to_string(*spec.label);
        text += ")";
    }
    return text;
}

std::string label_entry_text(const LabelEntry& e) {
    std::string text = std::to_string(e.value);
    if (!e.name.empty()) text += "  " + e.name;
    return text + "  (" + render::format_count(e.voxels) + " voxels)";
}

std::string series_text(const DicomSeries& s) {
    std::string text = s.description.empty() ? std::string("(no description)") : s.description;
    text += "  \xC2\xB7  " + std::to_string(s.files) + " files  \xC2\xB7  " + s.uid;
    return text;
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
    side_panel_overflow_ = ImGui::GetScrollMaxY();
    ImGui::EndChild();
}

void App::draw_volume_section() {
    const SourceSpec& requested = settings_.parameters.volume;
    const Source* shown = results_.source.get();
    if (shown) {
        ImGui::PushFont(fonts_.bold);
        ImGui::TextWrapped("%s", shown->title.c_str());
        ImGui::PopFont();
        coloured_text(kNoteColor, shown->description);
        for (const std::string& warning : shown->warnings) coloured_text(kWarningColor, warning);
    }
    if (!load_error_.empty()) {
        coloured_text(kErrorColor, "Could not open: " + load_error_);
        record("load_error");
        if (ImGui::SmallButton("Dismiss")) load_error_.clear();
    } else if (!loaded_ || !(*loaded_ == requested)) {
        ImGui::PushStyleColor(ImGuiCol_Text, kNoteColor);
        ImGui::TextWrapped("opening %s...", recent_label(requested).c_str());
        ImGui::PopStyleColor();
    }
    ImGui::Spacing();

    // Phantoms: synthetic volumes with an exact reference surface.
    const std::string current_phantom(phantom_spec_name(requested.input));
    const int phantom_size = phantom_size_;
    ImGui::SetNextItemWidth(-FLT_MIN);
    const std::string preview = current_phantom.empty()
                                    ? "Phantom..."
                                    : "Phantom: " + phantom_label(current_phantom, phantom_size);
    if (ImGui::BeginCombo("##phantom", preview.c_str())) {
        for (const std::string& name : phantom_names())
            if (ImGui::Selectable(phantom_label(name, phantom_size).c_str(),
                                  name == current_phantom))
                open({"phantom:" + name, phantom_size});
        ImGui::Separator();
        ImGui::TextDisabled("grid size");
        for (int size : kPhantomSizes) {
            ImGui::SameLine();
            if (ImGui::RadioButton(std::to_string(size).c_str(), phantom_size == size)) {
                phantom_size_ = size;
                if (!current_phantom.empty()) open({requested.input, size});
            }
        }
        ImGui::EndCombo();
    }
    record("phantom_combo");
    draw_open_fields();
    ImGui::Spacing();
}

// A file: typed (Tab completes), picked from the recent ones, or dropped on the window; read as
// headerless raw data when asked; with a label map beside it; a DICOM folder's series.
void App::draw_open_fields() {
    const float open_width = 4.0f * fonts_.size;
    const bool entered =
        path_field("##open path", "volume file or DICOM folder", form_.path, completions_,
                   ImGui::GetContentRegionAvail().x - open_width - ImGui::GetStyle().ItemSpacing.x,
                   focus_open_field_);
    record("open_field");
    if (ImGui::IsItemHovered())
        ImGui::SetTooltip("NRRD, NIfTI, MetaImage, VTK, a DICOM folder or .dcm, or headerless "
                          "raw data.\nTab completes the path; you can also drop a file onto the "
                          "window.");
    const bool field_active = ImGui::IsItemActive();
    ImGui::SameLine();
    bool open_now = ImGui::Button("Open", ImVec2(-FLT_MIN, 0)) || entered;
    record("open_button");
    bool focus_again = false;
    if (!completion_list("completions", form_.path, completions_, field_active, focus_again)
             .empty())
        open_now = true;
    if (focus_again) focus_open_field_ = true;

    if (!settings_.recent_files.empty()) {
        ImGui::SetNextItemWidth(-FLT_MIN);
        if (ImGui::BeginCombo("##recent", "Recent files...")) {
            for (const SourceSpec& spec : settings_.recent_files)
                if (ImGui::Selectable(recent_label(spec).c_str())) open(spec);
            ImGui::EndCombo();
        }
    }
    draw_raw_options();
    draw_series_list();
    draw_label_map();
    draw_cubic_voxels();
    if (open_now) open_form();
}

// Resampling to cubic voxels (io/isotropic.h): a thick-sliced scan's cells, and the net's
// triangles with them, are no longer stretched. Applied at once to the file shown.
void App::draw_cubic_voxels() {
    const SourceSpec& requested = settings_.parameters.volume;
    if (requested.is_phantom() && form_.path.empty()) return;
    const auto apply = [&] {
        if (requested.is_phantom()) return; // taken by the next Open
        SourceSpec spec = requested;
        if (form_.cubic)
            spec.isotropic = form_.cubic_edge;
        else
            spec.isotropic.reset();
        open(spec);
    };
    if (ImGui::Checkbox("Cubic voxels", &form_.cubic)) apply();
    record("cubic_checkbox");
    if (ImGui::IsItemHovered())
        ImGui::SetTooltip("Resample the volume to cubic voxels before anything else (grey "
                          "values linearly; a label's mask linearly, cut at 0.5), so thick "
                          "slices do not stretch the triangles. Refused, saying why, when the "
                          "new grid would not fit in memory.");
    ImGui::SameLine();
    ImGui::SetNextItemWidth(5.0f * fonts_.size);
    ImGui::BeginDisabled(!form_.cubic);
    ImGui::InputFloat("mm edge", &form_.cubic_edge, 0.0f, 0.0f,
                      form_.cubic_edge > 0.0f ? "%.4g" : "smallest");
    record("cubic_edge");
    if (!(form_.cubic_edge >= 0.0f) || !std::isfinite(form_.cubic_edge)) form_.cubic_edge = 0.0f;
    if (ImGui::IsItemDeactivatedAfterEdit()) apply();
    ImGui::EndDisabled();
    if (ImGui::IsItemHovered(ImGuiHoveredFlags_AllowWhenDisabled))
        ImGui::SetTooltip("the edge of the new voxels in mm; 0: the smallest spacing");
}

void App::draw_raw_options() {
    // Only once there is a file to read (a phantom shown, nothing typed: nothing to say).
    if (form_.path.empty() && !form_.raw) return;
    ImGui::Checkbox("Headerless raw data", &form_.raw);
    record("raw_checkbox");
    if (ImGui::IsItemHovered())
        ImGui::SetTooltip("A file of bare samples (or a numbered series of slice files): give "
                          "the grid, the sample type, the byte order and the spacing, then "
                          "Open.");
    if (!form_.raw) return;
    RawOptions& r = form_.raw_options;
    ImGui::Indent();
    ImGui::InputInt3("Dims (x y z)", &r.dims.x);
    record("raw_dims");
    r.dims = glm::max(r.dims, glm::ivec3(1));
    if (ImGui::BeginCombo("Sample type", scalar_type_name(r.type))) {
        for (int t = int(ScalarType::UInt8); t <= int(ScalarType::Float64); ++t)
            if (ImGui::Selectable(scalar_type_name(ScalarType(t)), ScalarType(t) == r.type))
                r.type = ScalarType(t);
        ImGui::EndCombo();
    }
    record("raw_type");
    ImGui::InputFloat3("Spacing (mm)", &r.spacing.x, "%.4g");
    for (int i = 0; i < 3; ++i)
        if (!(r.spacing[i] > 0.0f) || !std::isfinite(r.spacing[i])) r.spacing[i] = 1.0f;
    int big = r.endian == Endian::Big ? 1 : 0;
    ImGui::RadioButton("little-endian", &big, 0);
    ImGui::SameLine();
    ImGui::RadioButton("big-endian", &big, 1);
    r.endian = big ? Endian::Big : Endian::Little;
    // What the file must hold: the whole grid, or one slice of a numbered series.
    const std::uintmax_t slice =
        std::uintmax_t(r.dims.x) * std::uintmax_t(r.dims.y) * scalar_type_size(r.type);
    const std::uintmax_t whole = slice * std::uintmax_t(r.dims.z);
    std::error_code error;
    const std::uintmax_t size = std::filesystem::file_size(expand_home(form_.path), error);
    ImGui::PushFont(fonts_.small);
    if (error)
        ImGui::TextDisabled("needs %s bytes", render::format_count(whole).c_str());
    else if (size == whole)
        ImGui::TextDisabled("the file holds exactly these %s bytes",
                            render::format_count(whole).c_str());
    else if (size == slice && r.dims.z > 1)
        ImGui::TextDisabled("one slice of a numbered series (%s bytes each)",
                            render::format_count(slice).c_str());
    else
        coloured_text(kErrorColor, "needs " + render::format_count(whole) +
                                       " bytes; the file has " + render::format_count(size));
    ImGui::PopFont();
    ImGui::Unindent();
}

// A label map on the grey image's grid: Open lists its labels (the grey is thresholded until
// one is picked); picking a label segments it and suggests the iso of its boundary.
void App::draw_label_map() {
    const SourceSpec& requested = settings_.parameters.volume;
    if (requested.is_phantom() && form_.path.empty()) return;
    // Captions on the left: the two rows belong together, apart from the grey image's path.
    const float caption_width = ImGui::CalcTextSize("Label map").x + fonts_.size * 0.6f;
    const float clear_width = ImGui::GetFrameHeight();
    ImGui::AlignTextToFramePadding();
    ImGui::TextUnformatted("Label map");
    ImGui::SameLine(caption_width);
    bool focus = false;
    const bool entered = path_field(
        "##labels path", "none: threshold the grey", form_.labels, label_completions_,
        ImGui::GetContentRegionAvail().x - clear_width - ImGui::GetStyle().ItemSpacing.x, focus);
    record("labels_field");
    if (ImGui::IsItemHovered())
        ImGui::SetTooltip("A segmentation on the same grid as the grey image (e.g. "
                          "TotalSegmentator's output): Enter or Open lists its labels; pick one "
                          "to mesh it. Tab completes the path.");
    const bool active = ImGui::IsItemActive();
    ImGui::SameLine();
    ImGui::BeginDisabled(form_.labels.empty() && requested.labels.empty());
    if (ImGui::Button("x", ImVec2(-FLT_MIN, 0))) {
        form_.labels.clear();
        label_completions_.clear();
        if (!requested.labels.empty()) {
            SourceSpec spec = requested;
            spec.labels.clear();
            spec.label.reset();
            open(spec);
        }
    }
    ImGui::EndDisabled();
    if (ImGui::IsItemHovered(ImGuiHoveredFlags_AllowWhenDisabled))
        ImGui::SetTooltip("no label map: threshold the grey values");
    bool focus_again = false;
    const bool picked =
        !completion_list("label completions", form_.labels, label_completions_, active, focus_again)
             .empty();
    if (entered || picked) open_form();

    // The labels of the map shown (when it is the one asked for).
    const Source* shown = results_.source.get();
    if (requested.labels.empty() || !shown || shown->spec.labels != requested.labels) return;
    const std::vector<LabelEntry>& labels = shown->labels_present;
    std::string preview = "threshold the grey (no label)";
    for (const LabelEntry& e : labels)
        if (requested.label && e.value == *requested.label) preview = label_entry_text(e);
    ImGui::AlignTextToFramePadding();
    ImGui::TextUnformatted("Label");
    ImGui::SameLine(caption_width);
    ImGui::SetNextItemWidth(-FLT_MIN);
    if (ImGui::BeginCombo("##label", preview.c_str(), ImGuiComboFlags_HeightLarge)) {
        static ImGuiTextFilter filter; // one combo open at a time
        if (labels.size() > 12) {
            if (ImGui::IsWindowAppearing()) ImGui::SetKeyboardFocusHere();
            ImGui::SetNextItemWidth(-FLT_MIN);
            if (ImGui::InputTextWithHint("##label filter", "type to filter: a number or a name",
                                         filter.InputBuf, IM_ARRAYSIZE(filter.InputBuf)))
                filter.Build();
        }
        if (ImGui::Selectable("threshold the grey (no label)", !requested.label))
            choose_label(std::nullopt);
        for (const LabelEntry& e : labels) {
            const std::string text = label_entry_text(e);
            if (!filter.PassFilter(text.c_str())) continue;
            if (ImGui::Selectable(text.c_str(), requested.label && *requested.label == e.value))
                choose_label(e.value);
        }
        ImGui::EndCombo();
    }
    record("label_combo");
    if (ImGui::IsItemHovered())
        ImGui::SetTooltip("%zu labels in the map; the surface is the boundary of the one "
                          "picked",
                          labels.size());
}

void App::draw_series_list() {
    if (series_.folder.empty()) return;
    ImGui::PushFont(fonts_.small);
    if (series_.scanning) {
        ImGui::TextDisabled("looking for DICOM series in %s...", series_.folder.c_str());
    } else if (!series_.error.empty()) {
        coloured_text(kNoteColor, series_.error);
    }
    ImGui::PopFont();
    if (series_.series.empty()) return;
    const SourceSpec& requested = settings_.parameters.volume;
    const bool this_folder = requested.input == series_.folder;
    std::string preview = "largest: " + series_text(series_.series.front());
    for (const DicomSeries& s : series_.series)
        if (this_folder && s.uid == requested.series_uid) preview = series_text(s);
    ImGui::AlignTextToFramePadding();
    ImGui::TextUnformatted("Series");
    ImGui::SameLine(ImGui::CalcTextSize("Label map").x + fonts_.size * 0.6f);
    ImGui::SetNextItemWidth(-FLT_MIN);
    if (ImGui::BeginCombo("##series", preview.c_str(), ImGuiComboFlags_HeightLarge)) {
        for (const DicomSeries& s : series_.series)
            if (ImGui::Selectable(series_text(s).c_str(),
                                  this_folder && s.uid == requested.series_uid))
                choose_series(s.uid);
        ImGui::EndCombo();
    }
    record("series_combo");
    if (ImGui::IsItemHovered())
        ImGui::SetTooltip("%zu DICOM series in %s", series_.series.size(), series_.folder.c_str());
}

void App::draw_iso_section() {
    Parameters& p = settings_.parameters;
    const float width = ImGui::GetContentRegionAvail().x;
    if (results_.source) {
        const Histogram& h = results_.source->histogram;
        const float step = iso_step();
        if (const auto value = value_histogram_plot("##value histogram", h, p.iso, step,
                                                    ImVec2(width, 2.0f * fonts_.size), fonts_)) {
            p.iso = *value;
            p.auto_iso = false;
        }
        record("value_histogram");
        // A field, not a slider: a click does not jump, the buttons step by the data's step
        // (whole values for integer volumes), a typed value applies on Enter.
        const int decimals = std::clamp(int(-std::floor(std::log10(step))), 0, 6);
        char format[16];
        std::snprintf(format, sizeof format, "%%.%df", decimals);
        float iso = p.iso;
        ImGui::SetNextItemWidth(width - ImGui::CalcTextSize("Suggested").x - 3.0f * fonts_.size);
        if (ImGui::InputFloat("##iso", &iso, step, 10.0f * step, format,
                              ImGuiInputTextFlags_EnterReturnsTrue) &&
            std::isfinite(iso)) {
            p.iso = iso;
            p.auto_iso = false;
        }
        record("iso_field");
        if (ImGui::IsItemHovered())
            ImGui::SetTooltip("the grey value of the surface: Marching Cubes interpolates it, "
                              "the segmentation thresholds at it. Type a value and press Enter, "
                              "or step with - and +; a click on the histogram sets it too.");
        ImGui::SameLine();
        if (ImGui::Checkbox("Suggested", &p.auto_iso) && p.auto_iso) p.iso = results_.iso;
        if (ImGui::IsItemHovered())
            ImGui::SetTooltip("suggested: %s", results_.source->iso_reason.c_str());
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
    bool close_border = p.closes_border();
    if (ImGui::Checkbox("Close surfaces at the border", &close_border))
        p.close_border = close_border;
    record("close_border_checkbox");
    help_marker("The volume is treated as surrounded by one layer of outside, so a surface that "
                "reaches the border is closed there, by Marching Cubes and by the net alike, and "
                "the caps are relaxed like the rest (what an FE mesher needs: a closed surface). "
                "On by default for a label map, off for grey values (--close-border on the "
                "command line).");
}

void App::draw_relaxation_section() {
    Parameters& p = settings_.parameters;
    RelaxOptions& r = p.relax;
    name_combo("Mode", r.mode);
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
    name_combo("Schedule", r.schedule);
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
    name_combo("Constraint", r.constraint);
    help_marker("Every node stays inside its own cell: ray-box shortens the move along its own "
                "direction; clipping each coordinate is the original SurfaceNet's rule.");
    ImGui::BeginDisabled(r.mode == RelaxMode::Averaging);
    name_combo("Gradient of", r.gradient);
    help_marker("How the grey-value gradient is estimated; a Gaussian derivative (sigma in "
                "voxels) is steadier on noisy data; the trilinear field's own gradient reads only "
                "the 8 samples of the node's cell (fastest).");
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
    name_combo("Triangles", p.triangulation);
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
    // One line (wrapped only when narrow): the panel should fit 768 pixels without scrolling.
    if (results_.net)
        state += "  \xC2\xB7  net: " + render::format_count(results_.net->nodes) + " nodes, " +
                 render::format_count(results_.net->quads) + " quads";
    ImGui::PushStyleColor(ImGuiCol_Text, ImGui::GetStyleColorVec4(ImGuiCol_TextDisabled));
    ImGui::TextWrapped("%s", state.c_str());
    ImGui::PopStyleColor();
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
        compactness_tab_open_ = false;
        if (ImGui::BeginTabItem("Compactness")) {
            compactness_tab_open_ = true;
            draw_compactness_tab();
            ImGui::EndTabItem();
        }
        record("tab_compactness");
        ImGui::EndTabBar();
    }
    ImGui::EndChild();
}

void App::draw_quality_tab() {
    const std::shared_ptr<const DisplayMesh> mc = shown_mc(), net = shown_net();
    std::vector<render::PanelMethod> methods;
    if (mc) methods.push_back({Method::MarchingCubes, "Marching Cubes", &mc->metrics});
    // The frame's mesh is measured alone; where the relaxation stands at that iteration comes
    // from the iteration history.
    MethodMetrics frame_metrics;
    if (net) {
        frame_metrics = net->metrics;
        const int k = net->iteration;
        frame_metrics.iterations = k;
        if (k >= 0 && k < results_.iteration_count())
            frame_metrics.final_max_move = results_.iterations[std::size_t(k)].max_move;
        frame_metrics.converged =
            results_.finished && results_.finished->converged && k == results_.finished->iterations;
        methods.push_back({net->method,
                           std::string(label_of(net->method)) + ", iteration " + std::to_string(k),
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
    // The histograms show the measure the views colour by (the worker summed each one).
    const ShapeMeasure measure = color_by();
    const DisplayMesh* shown[2] = {results_.mc.get(), results_.frame.get()};
    std::array<MethodMetrics, 2> histogram_metrics;
    std::vector<render::PanelMethod> histogram_methods = methods;
    for (std::size_t i = 0, m = 0; i < 2; ++i) {
        if (!shown[i]) continue;
        histogram_metrics[i] = *methods[m].metrics;
        const MeasureSummary* summary = shown_summary(int(i), measure);
        histogram_metrics[i].quality.mean = summary ? summary->mean : 0.0;
        if (summary) histogram_metrics[i].quality.histogram = summary->histogram;
        // Not measured yet (a distance on its way): no series, rather than a wrong one.
        histogram_methods[m++].metrics = summary ? &histogram_metrics[i] : nullptr;
    }
    render::draw_quality_histograms(ImGui::GetWindowDrawList(),
                                    ImVec2(start.x + pad, start.y + pad),
                                    ImVec2(start.x + pad + histogram_width, start.y + inner_height),
                                    histogram_methods, fonts_, settings_.view.shading == "quality",
                                    settings_.view.quality_threshold, measure, color_scale());
    const float table_x = start.x + 2.5f * pad + histogram_width;
    const float table_width = start.x + available.x - pad - table_x;
    // Two column groups (half the rows) when one group is too tall; the smaller face when the
    // table is too narrow for the measures' names at the regular size.
    render::FigureFonts table_fonts = fonts_;
    const bool compact = table_width < 40.0f * fonts_.size;
    if (compact) table_fonts.size = fonts_.small->FontSize;
    // Two groups where one is too tall and the width holds two; else one that scrolls (and
    // never narrower than its names and numbers: scrolled sideways on a small screen).
    const float group_width = 19.0f * table_fonts.size;
    const bool one_fits = render::metrics_table_height(1, table_fonts.size) <= inner_height - pad;
    const int groups = one_fits || table_width < 2 * group_width ? 1 : 2;
    const float inner_width = std::max(table_width - fonts_.size, group_width);
    ImGui::SetCursorScreenPos(ImVec2(table_x, start.y + pad));
    ImGui::BeginChild("metrics", ImVec2(table_width, inner_height - pad), false,
                      ImGuiWindowFlags_HorizontalScrollbar);
    if (compact) ImGui::PushFont(fonts_.small);
    // A mesh not measured yet (Marching Cubes just made, a step a moment ago) has its histogram
    // but no table column.
    std::span<const render::PanelMethod> table_methods = methods;
    const bool measuring_mc = mc && !mc->metrics_complete;
    const bool measuring_net = net && !net->metrics_complete;
    if (measuring_net) table_methods = table_methods.first(table_methods.size() - 1);
    if (measuring_mc) table_methods = table_methods.subspan(1);
    render::metrics_table("metrics table", table_methods, groups, inner_width, table_fonts);
    if (measuring_mc) ImGui::TextDisabled("measuring Marching Cubes...");
    if (measuring_net)
        ImGui::TextDisabled("measuring %s, iteration %d...",
                            std::string(label_of(net->method)).c_str(), net->iteration);
    if (compact) ImGui::PopFont();
    ImGui::EndChild();
}

void App::draw_convergence_tab() {
    const std::vector<IterationStats>& it = results_.iterations;
    if (it.empty()) {
        ImGui::TextDisabled("  the curves appear while the net relaxes");
        return;
    }
    // The largest moves come with the iterations; the other numbers once measured (in order,
    // after the relaxation).
    std::vector<float> max_move, quality, smooth, accuracy;
    for (const IterationStats& s : it) {
        max_move.push_back(s.max_move);
        if (!s.measured || quality.size() + 1 < max_move.size()) continue;
        quality.push_back(float(s.quality_mean));
        smooth.push_back(float(s.smoothness));
        accuracy.push_back(float(s.accuracy_vertices));
    }
    // Marching Cubes' line once it is measured (its smoothness comes with the metrics).
    const MethodMetrics* mc =
        results_.mc && results_.mc->metrics_complete ? &results_.mc->metrics : nullptr;
    const ImU32 color = render::method_color_u32(method_of(settings_.parameters.relax.mode));
    const bool has_accuracy = !accuracy.empty() && accuracy.front() >= 0;
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

// The equal-count switch and the compactness curves: accuracy and quality against the share of
// the triangles kept, for both methods (computed by the worker once the job is finished).
void App::draw_compactness_tab() {
    const float pad = std::round(0.6f * fonts_.size);
    ImGui::SetCursorPos(ImVec2(ImGui::GetCursorPosX() + pad, ImGui::GetCursorPosY() + pad));
    ImGui::Checkbox("Equal triangle count", &equal_count_);
    record("equal_count");
    if (ImGui::IsItemHovered())
        ImGui::SetTooltip("show both meshes reduced to the smaller triangle count (meshoptimizer's "
                          "simplifier, checked: closed, manifold, no self-intersection), every "
                          "metric measured again; the paper's comparison at the same count");
    const auto& c = results_.compactness;
    ImGui::SameLine(0, 2 * pad);
    if (!c) {
        ImGui::TextDisabled(results_.finished ? "reducing the meshes..."
                                              : "the curves appear once the relaxation is done");
        return;
    }
    if (!c->mc_equal || !c->net_equal) {
        ImGui::TextDisabled("no surface to reduce");
        return;
    }
    ImGui::Text("equal count: %zu triangles (tries refused: MC %zu, %s %zu)", c->equal_count,
                std::size_t(c->mc_report.refusals),
                std::string(label_of(c->net_equal->method)).c_str(),
                std::size_t(c->net_report.refusals));
    if (equal_count_ && !showing_equal_count())
        ImGui::TextDisabled("  the reduced meshes are of the last iteration: go there to see them");
    const ImU32 mc_color = render::method_color_u32(Method::MarchingCubes);
    const ImU32 net_color = render::method_color_u32(c->net_equal->method);
    const std::string net_label(label_of(c->net_equal->method));
    auto series = [](const std::vector<CompactnessPoint>& curve, double CompactnessPoint::*field) {
        std::vector<CompactnessSeries::Point> points;
        for (const CompactnessPoint& p : curve) points.push_back({p.fraction, float(p.*field)});
        return points;
    };
    const std::vector<CompactnessSeries::Point> mc_acc =
        series(c->mc_curve, &CompactnessPoint::accuracy_mean);
    const std::vector<CompactnessSeries::Point> net_acc =
        series(c->net_curve, &CompactnessPoint::accuracy_mean);
    const std::vector<CompactnessSeries::Point> mc_max =
        series(c->mc_curve, &CompactnessPoint::accuracy_max);
    const std::vector<CompactnessSeries::Point> net_max =
        series(c->net_curve, &CompactnessPoint::accuracy_max);
    const std::vector<CompactnessSeries::Point> mc_q =
        series(c->mc_curve, &CompactnessPoint::quality_mean);
    const std::vector<CompactnessSeries::Point> net_q =
        series(c->net_curve, &CompactnessPoint::quality_mean);
    const CompactnessPlot plots[3] = {
        {"Mean distance (voxels)",
         "mean distance between the reduced and the full surface, both ways (lower is "
         "better), against the share of the triangles kept",
         {{mc_acc, mc_color, "MC"}, {net_acc, net_color, net_label}}},
        {"Largest distance (voxels)",
         "largest sampled distance between the reduced and the unreduced surface (lower is "
         "better)",
         {{mc_max, mc_color, "MC"}, {net_max, net_color, net_label}}},
        {"Mean quality",
         "smallest / largest angle, averaged over the triangles (higher is better)",
         {{mc_q, mc_color, "MC"}, {net_q, net_color, net_label}}},
    };
    const ImVec2 available = ImGui::GetContentRegionAvail();
    const float width = (available.x - pad * 4) / 3;
    const float height = std::max(available.y - pad, 5.0f * fonts_.size);
    ImGui::SetCursorPos(ImVec2(ImGui::GetCursorPosX() + pad, ImGui::GetCursorPosY() + pad));
    for (int i = 0; i < 3; ++i) {
        if (i > 0) ImGui::SameLine(0, pad);
        const std::string id = "##compactness" + std::to_string(i);
        compactness_plot(id.c_str(), plots[i], ImVec2(width, height), fonts_);
        record("compactness_plot_" + std::to_string(i));
    }
}

} // namespace snert::app
