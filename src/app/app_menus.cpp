// Menus, the status line, the Help and About windows and the screenshot / export dialogs.
#include "app.h"

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <optional>
#include <string>

#include <imgui.h>
#include <imgui_stdlib.h>

#include "core/phantom.h"
#include "path_completion.h"
#include "render/panels.h"

namespace snert::app {

namespace {

constexpr const char* kExportFormats[] = {"stl", "obj", "ply", "off", "vtk", "msh", "inp"};

#ifndef SNERT_VERSION
#define SNERT_VERSION "unknown"
#endif

// A window the user opened from a menu: centred on the screen when it appears, `width` wide,
// bordered, closed by its title bar's button. Returns ImGui::Begin's result; call End always.
bool begin_centred_window(const char* title, bool* open, float width) {
    const ImGuiViewport* viewport = ImGui::GetMainViewport();
    ImGui::SetNextWindowPos(ImVec2(viewport->Pos.x + 0.5f * viewport->Size.x,
                                   viewport->Pos.y + 0.5f * viewport->Size.y),
                            ImGuiCond_Appearing, ImVec2(0.5f, 0.5f));
    ImGui::SetNextWindowSize(ImVec2(width, 0), ImGuiCond_Appearing);
    ImGui::PushStyleVar(ImGuiStyleVar_WindowBorderSize, 1.0f);
    const bool visible =
        ImGui::Begin(title, open, ImGuiWindowFlags_NoCollapse | ImGuiWindowFlags_AlwaysAutoResize);
    ImGui::PopStyleVar();
    return visible;
}

// `text` cut at the end with an ellipsis so that it fits `width` pixels in the current font.
std::string fit_text(const std::string& text, float width) {
    if (ImGui::CalcTextSize(text.c_str()).x <= width) return text;
    const std::string ellipsis = "\xE2\x80\xA6";
    std::size_t n = text.size();
    while (n > 0) {
        --n;
        while (n > 0 && (static_cast<unsigned char>(text[n]) & 0xC0) == 0x80) --n; // UTF-8
        const std::string cut = text.substr(0, n) + ellipsis;
        if (ImGui::CalcTextSize(cut.c_str()).x <= width) return cut;
    }
    return ellipsis;
}

bool menu_action(App& app, const char* label, Action action, bool selected = false,
                 bool enabled = true) {
    if (ImGui::MenuItem(label, shortcut_for(action).keys, selected, enabled)) {
        app.perform(action);
        return true;
    }
    return false;
}

} // namespace

void App::draw_menu_bar() {
    if (!ImGui::BeginMainMenuBar()) return;
    if (ImGui::BeginMenu("File")) {
        menu_action(*this, "Open volume file...", Action::OpenFile);
        if (ImGui::BeginMenu("Recent files", !settings_.recent_files.empty())) {
            for (const SourceSpec& spec : settings_.recent_files)
                if (ImGui::MenuItem(format_source_line(spec).c_str())) open(spec);
            ImGui::EndMenu();
        }
        ImGui::Separator();
        menu_action(*this, "Save screenshot of the views...", Action::Screenshot);
        menu_action(*this, "Export meshes...", Action::ExportMeshes, false,
                    results_.mc != nullptr || results_.frame != nullptr);
        ImGui::Separator();
        menu_action(*this, "Quit", Action::Quit);
        ImGui::EndMenu();
    }
    if (ImGui::BeginMenu("Phantoms")) {
        const SourceSpec& v = settings_.parameters.volume;
        for (const std::string& name : phantom_names()) {
            const std::string size = std::to_string(phantom_size_) + "\xC2\xB3";
            if (ImGui::MenuItem(name.c_str(), size.c_str(), v.input == "phantom:" + name))
                open({"phantom:" + name, phantom_size_});
        }
        ImGui::Separator();
        if (ImGui::BeginMenu("Grid size")) {
            for (int size : {32, 48, 64, 96, 128}) {
                const std::string label = std::to_string(size) + "\xC2\xB3 voxels";
                if (ImGui::MenuItem(label.c_str(), nullptr, phantom_size_ == size)) {
                    phantom_size_ = size;
                    if (v.is_phantom()) open({v.input, size});
                }
            }
            ImGui::EndMenu();
        }
        ImGui::EndMenu();
    }
    if (ImGui::BeginMenu("View")) {
        const ViewSettings& view = settings_.view;
        menu_action(*this, "Flat shading", Action::ShadingFlat, view.shading == "flat");
        menu_action(*this, "Smooth shading", Action::ShadingSmooth, view.shading == "smooth");
        menu_action(*this, "Quality colours", Action::ShadingQuality, view.shading == "quality");
        menu_action(*this, "Wireframe", Action::ToggleWireframe, view.wireframe);
        ImGui::Separator();
        menu_action(*this, "Front", Action::ViewFront);
        menu_action(*this, "Side", Action::ViewSide);
        menu_action(*this, "Top", Action::ViewTop);
        menu_action(*this, "Iso", Action::ViewIso);
        menu_action(*this, "Reset camera", Action::ResetCamera);
        if (ImGui::MenuItem("Copy camera as command line")) {
            const std::string command = camera_command();
            ImGui::SetClipboardText(command.c_str());
            notice("copied: " + command);
        }
        ImGui::Separator();
        menu_action(*this, "Parameter panel", Action::ToggleSidePanel,
                    settings_.layout.show_side_panel);
        menu_action(*this, "Bottom panel", Action::ToggleBottomPanel,
                    settings_.layout.show_bottom_panel);
        menu_action(*this, "Slice view", Action::ToggleSliceView, slice_view_);
        ImGui::EndMenu();
    }
    if (ImGui::BeginMenu("Iterations")) {
        menu_action(*this, playing_ ? "Pause" : "Play", Action::PlayPause);
        menu_action(*this, "Step back", Action::StepBack);
        menu_action(*this, "Step forward", Action::StepForward);
        menu_action(*this, "First iteration", Action::FirstIteration);
        menu_action(*this, "Newest iteration", Action::LastIteration, following_);
        menu_action(*this, "Run to convergence", Action::RunToConvergence);
        ImGui::Separator();
        ImGui::SetNextItemWidth(8.0f * fonts_.size);
        ImGui::SliderFloat("Play speed", &settings_.play_speed, 1.0f, 60.0f, "%.0f iterations/s",
                           ImGuiSliderFlags_Logarithmic);
        ImGui::EndMenu();
    }
    if (ImGui::BeginMenu("Help")) {
        menu_action(*this, "Keys, mouse and what you see", Action::Help, help_open_);
        if (ImGui::MenuItem("Explain the methods", nullptr, explain_open_))
            explain_open_ = !explain_open_;
        ImGui::Separator();
        if (ImGui::MenuItem("About snert")) about_open_ = true;
        ImGui::EndMenu();
    }
    ImGui::EndMainMenuBar();
}

std::string App::status_text() const {
    std::string text;
    if (results_.source)
        text = results_.source->title;
    else
        text = settings_.parameters.volume.input;
    if (results_.source && results_.source->spec.label)
        text += ", label " + std::to_string(*results_.source->spec.label);
    char iso[48];
    std::snprintf(iso, sizeof iso, "  \xC2\xB7  iso %.4g", settings_.parameters.iso);
    text += iso;
    text += "  \xC2\xB7  " + std::string(label_of(method_of(settings_.parameters.relax.mode)));
    if (!results_.error.empty()) {
        text += "  \xC2\xB7  failed: " + results_.error;
    } else if (results_.finished) {
        const int n = results_.finished->iterations;
        text += results_.finished->converged
                    ? "  \xC2\xB7  converged after " + std::to_string(n) + " iterations"
                    : "  \xC2\xB7  " + std::to_string(n) + " iterations (the maximum)";
    } else {
        const JobProgress& p = worker_->progress();
        text += "  \xC2\xB7  ";
        text += p.generation.load() == results_.generation ? stage_name(Stage(p.stage.load()))
                                                           : "starting";
        text += "...";
    }
    return text;
}

void App::draw_status_bar() {
    const ImGuiViewport* viewport = ImGui::GetMainViewport();
    const float height = ImGui::GetFrameHeight();
    ImGui::SetNextWindowPos(ImVec2(viewport->Pos.x, viewport->Pos.y + viewport->Size.y - height));
    ImGui::SetNextWindowSize(ImVec2(viewport->Size.x, height));
    ImGui::PushStyleVar(ImGuiStyleVar_WindowPadding,
                        ImVec2(0.5f * fonts_.size, ImGui::GetStyle().FramePadding.y));
    ImGui::PushStyleColor(ImGuiCol_WindowBg, ImGui::GetStyleColorVec4(ImGuiCol_MenuBarBg));
    ImGui::Begin("##status", nullptr,
                 ImGuiWindowFlags_NoDecoration | ImGuiWindowFlags_NoMove |
                     ImGuiWindowFlags_NoSavedSettings | ImGuiWindowFlags_NoFocusOnAppearing |
                     ImGuiWindowFlags_NoNav);
    ImGui::PopStyleColor();
    ImGui::PopStyleVar();
    const std::string help = "F1: keys and help";
    const float help_width = ImGui::CalcTextSize(help.c_str()).x;
    const float help_x = std::max(ImGui::GetWindowWidth() - help_width - fonts_.size, 0.0f);
    // The message ends (with an ellipsis) before the hint, which is never drawn over.
    const float text_width = std::max(help_x - ImGui::GetCursorPosX() - fonts_.size, 0.0f);
    if (notice_timer_ > 0 && !notices_.empty()) {
        const Notice& n = notices_.back();
        ImGui::PushStyleColor(ImGuiCol_Text,
                              n.error ? IM_COL32(190, 30, 30, 255) : IM_COL32(0, 100, 160, 255));
        ImGui::TextUnformatted(fit_text(n.text, text_width).c_str());
        ImGui::PopStyleColor();
        if (ImGui::IsItemHovered()) ImGui::SetTooltip("%s", n.text.c_str());
    } else {
        ImGui::TextUnformatted(fit_text(status_text(), text_width).c_str());
    }
    ImGui::SameLine(help_x);
    ImGui::TextDisabled("%s", help.c_str());
    ImGui::End();
}

std::string App::camera_command() const {
    const SourceSpec& v = loaded_ ? *loaded_ : settings_.parameters.volume;
    auto quoted = [](const std::string& text) {
        if (text.find_first_of(" '\"$\\") == std::string::npos) return text;
        std::string out(1, '\'');
        for (const char c : text) {
            if (c == '\'')
                out.append("'\\''");
            else
                out.push_back(c);
        }
        out.push_back('\'');
        return out;
    };
    std::string command = "snert render " + quoted(v.input);
    if (v.is_phantom()) command += " --size " + std::to_string(v.phantom_size);
    if (!v.labels.empty()) command += " --labels " + quoted(v.labels);
    if (v.label) command += " --label " + std::to_string(*v.label);
    char iso[48];
    std::snprintf(iso, sizeof iso, " --iso %.9g", double(results_.iso));
    command += iso;
    if (settings_.parameters.inside == InsideIs::Below) command += " --inside below";
    command.append(" --mode ").append(name_of(settings_.parameters.relax.mode));
    // The iteration shown, exactly (snert render --iteration K relaxes K times).
    if (results_.frame) command.append(" --iteration ").append(std::to_string(shown_iteration()));
    command.append(" ").append(render::camera_arguments(render::camera_spec_of(camera_)));
    command.append(" --out snert-view.png");
    return command;
}

void App::draw_help_window() {
    if (!help_open_) return;
    if (ImGui::IsKeyPressed(key::Escape) && !ImGui::GetIO().WantTextInput) {
        help_open_ = false;
        return;
    }
    const bool visible = begin_centred_window("Help: snert", &help_open_, 40.0f * fonts_.size);
    if (visible) {
        ImGui::PushTextWrapPos(38.0f * fonts_.size);
        ImGui::PushFont(fonts_.bold);
        ImGui::TextUnformatted("What you see");
        ImGui::PopFont();
        ImGui::TextWrapped(
            "Left: the Marching Cubes surface of the volume at the iso value. Right: the "
            "SurfaceNet of the same segmentation, relaxed iteration by iteration (SNERT, SNA "
            "or gradient only). Both views share one camera. Under them: the triangle-quality "
            "histograms of both meshes on the same axes, the metrics table, and (second tab) "
            "how the relaxation converges. Every change of a parameter on the left restarts "
            "the computation in the background; the window never waits for it.");
        ImGui::Spacing();
        ImGui::PushFont(fonts_.bold);
        ImGui::TextUnformatted("Mouse");
        ImGui::PopFont();
        ImGui::TextUnformatted("drag in a view: turn the camera     right- or shift-drag: pan\n"
                               "wheel: zoom     double-click: frame both meshes again\n"
                               "click or drag on a convergence plot: show that iteration\n"
                               "click on the value histogram: set the iso value\n"
                               "drop a volume file onto the window: open it");
        ImGui::Spacing();
        ImGui::PushFont(fonts_.bold);
        ImGui::TextUnformatted("Keys");
        ImGui::PopFont();
        if (ImGui::BeginTable("keys", 2, ImGuiTableFlags_RowBg | ImGuiTableFlags_SizingFixedFit)) {
            const auto list = shortcuts();
            for (std::size_t i = 0; i < list.size(); ++i) {
                // An action with two keys is one row: "F1, H".
                std::string keys = list[i].keys;
                while (i + 1 < list.size() && list[i + 1].action == list[i].action)
                    keys += std::string(", ") + list[++i].keys;
                ImGui::TableNextRow();
                ImGui::TableNextColumn();
                ImGui::PushFont(fonts_.bold);
                ImGui::TextUnformatted(keys.c_str());
                ImGui::PopFont();
                ImGui::TableNextColumn();
                ImGui::TextUnformatted(list[i].description);
            }
            ImGui::EndTable();
        }
        ImGui::Spacing();
        ImGui::TextDisabled("Settings and layout are saved on exit (%s).",
                            options_.settings_path.empty() ? "not in this session"
                                                           : options_.settings_path.c_str());
        ImGui::PopTextWrapPos();
    }
    ImGui::End();
}

// What each method does, in the paper's terms, for reading along: Marching Cubes and the mode
// chosen in the panel stand out, the other modes are greyed.
void App::draw_explain_window() {
    if (!explain_open_) return;
    if (ImGui::IsKeyPressed(key::Escape) && !ImGui::GetIO().WantTextInput) {
        explain_open_ = false;
        return;
    }
    const bool visible =
        begin_centred_window("Explain: the methods", &explain_open_, 36.0f * fonts_.size);
    if (visible) {
        record("explain_window");
        struct Paragraph {
            const char* title;
            std::optional<RelaxMode> mode; // empty: Marching Cubes, always shown
            const char* text;
        };
        static const Paragraph paragraphs[] = {
            {"Marching Cubes (left view)", std::nullopt,
             "Every cell of 2 x 2 x 2 voxels that the iso-surface crosses gets a vertex on each "
             "cut edge, where the linear interpolation of the two grey values reaches the iso "
             "value, and triangles from a fixed table of cut patterns. The vertices lie on the "
             "surface, but the triangles follow the grid: slivers wherever the surface passes "
             "close to a voxel."},
            {"SNA: SurfaceNet averaging (eqs. 1-2)", RelaxMode::Averaging,
             "A SurfaceNet has one node in every surface cell, linked to the nodes of the "
             "neighbouring surface cells. Each iteration moves a node by the averaging vector "
             "a, the mean of its linked neighbours minus the node (eq. 1), constrained to its "
             "cell by c (eq. 2). The net becomes smooth with well-shaped triangles, but it "
             "shrinks: averaging pulls a curved surface inwards."},
            {"Gradient step (eqs. 3-4)", RelaxMode::Gradient,
             "Each node moves along the grey values' gradient g by the distance d that a linear "
             "model of the grey values predicts to the iso value (eqs. 3-4): the step d g puts "
             "it on the iso-surface. Alone it makes the net accurate but keeps the grid's "
             "stair steps."},
            {"SNERT: both, in the surface (eqs. 5-6)", RelaxMode::Snert,
             "The averaging vector is projected onto the surface's tangent plane, a_p (eq. 5), "
             "so it smooths without shrinking, and the gradient step d g keeps the node on the "
             "iso-surface; the weighted sum is constrained to the cell by c (eq. 6). The mesh "
             "is as accurate as Marching Cubes' with far better triangles."},
        };
        const RelaxMode mode = settings_.parameters.relax.mode;
        ImGui::PushTextWrapPos(34.0f * fonts_.size);
        for (const Paragraph& p : paragraphs) {
            const bool current = !p.mode || *p.mode == mode;
            ImGui::PushFont(fonts_.bold);
            if (current)
                ImGui::TextUnformatted(p.title);
            else
                ImGui::TextDisabled("%s", p.title);
            ImGui::PopFont();
            if (p.mode && *p.mode == mode) {
                ImGui::SameLine();
                ImGui::TextColored(ImVec4(0.0f, 0.40f, 0.63f, 1.0f), "(the mode chosen)");
            }
            ImGui::PushStyleColor(
                ImGuiCol_Text,
                ImGui::GetStyleColorVec4(current ? ImGuiCol_Text : ImGuiCol_TextDisabled));
            ImGui::TextWrapped("%s", p.text);
            ImGui::PopStyleColor();
            ImGui::Spacing();
        }
        ImGui::TextDisabled("Equation numbers: de Bruin et al., MICCAI 2000 (Help > About).");
        ImGui::PopTextWrapPos();
    }
    ImGui::End();
}

void App::draw_about_window() {
    if (!about_open_) return;
    const bool visible = begin_centred_window("About snert", &about_open_, 32.0f * fonts_.size);
    if (visible) {
        ImGui::PushTextWrapPos(30.0f * fonts_.size);
        ImGui::PushFont(fonts_.bold);
        ImGui::TextUnformatted("snert " SNERT_VERSION);
        ImGui::PopFont();
        ImGui::TextWrapped("Marching Cubes and SurfaceNets with Extended Relaxation and "
                           "Triangulation (SNERT) side by side: both surfaces of a CT, MRI or "
                           "phantom volume, measured, with the relaxation to step through.");
        ImGui::Spacing();
        ImGui::TextDisabled("The method:");
        ImGui::TextWrapped("P. W. de Bruin, F. M. Vos, F. H. Post, S. F. Frisken-Gibson and "
                           "A. M. Vossepoel, Improving Triangle Mesh Quality with SurfaceNets. "
                           "Medical Image Computing and Computer-Assisted Intervention (MICCAI "
                           "2000), LNCS 1935, Springer.");
        ImGui::Spacing();
        if (ImGui::Button("Close") || ImGui::IsKeyPressed(key::Escape)) about_open_ = false;
        ImGui::PopTextWrapPos();
    }
    ImGui::End();
}

void App::draw_dialogs() {
    if (screenshot_dialog_) {
        ImGui::OpenPopup("Save screenshot");
        screenshot_dialog_ = false;
    }
    if (export_dialog_) {
        ImGui::OpenPopup("Export meshes");
        export_dialog_ = false;
    }
    const ImGuiViewport* viewport = ImGui::GetMainViewport();
    const ImVec2 centre(viewport->Pos.x + 0.5f * viewport->Size.x,
                        viewport->Pos.y + 0.5f * viewport->Size.y);
    // Both dialogs: the folder (the last one used, else the working folder) and a file name;
    // the full path is shown before and reported after; Enter in a field confirms.
    auto folder_field = [&] {
        ImGui::SetNextItemWidth(30.0f * fonts_.size);
        return ImGui::InputText("Folder", &dialog_folder_, ImGuiInputTextFlags_EnterReturnsTrue);
    };
    auto in_folder = [&](const std::string& name) {
        return (std::filesystem::path(expand_home(dialog_folder_)) / name).lexically_normal();
    };
    auto remember_folder = [&] {
        std::error_code error;
        settings_.output_folder = std::filesystem::absolute(expand_home(dialog_folder_), error)
                                      .lexically_normal()
                                      .string();
    };
    ImGui::SetNextWindowPos(centre, ImGuiCond_Appearing, ImVec2(0.5f, 0.5f));
    if (ImGui::BeginPopupModal("Save screenshot", nullptr, ImGuiWindowFlags_AlwaysAutoResize)) {
        ImGui::TextUnformatted("A PNG of the two views with their titles, at screen resolution.");
        bool enter = folder_field();
        record("screenshot_folder");
        ImGui::SetNextItemWidth(30.0f * fonts_.size);
        if (ImGui::IsWindowAppearing()) ImGui::SetKeyboardFocusHere();
        enter |= ImGui::InputText("File", &screenshot_path_, ImGuiInputTextFlags_EnterReturnsTrue);
        record("screenshot_file");
        const std::string path = in_folder(screenshot_path_).string();
        ImGui::TextDisabled("writes %s", path.c_str());
        if (ImGui::Button("Save") || enter) {
            remember_folder();
            request_screenshot(path);
            ImGui::CloseCurrentPopup();
        }
        ImGui::SameLine();
        if (ImGui::Button("Cancel") || ImGui::IsKeyPressed(key::Escape)) ImGui::CloseCurrentPopup();
        ImGui::EndPopup();
    }
    ImGui::SetNextWindowPos(centre, ImGuiCond_Appearing, ImVec2(0.5f, 0.5f));
    if (ImGui::BeginPopupModal("Export meshes", nullptr, ImGuiWindowFlags_AlwaysAutoResize)) {
        ImGui::TextUnformatted("Writes the two meshes shown (world units, millimetres):");
        bool enter = folder_field();
        record("export_folder");
        ImGui::SetNextItemWidth(30.0f * fonts_.size);
        if (ImGui::IsWindowAppearing()) ImGui::SetKeyboardFocusHere();
        enter |= ImGui::InputText("Name", &export_base_, ImGuiInputTextFlags_EnterReturnsTrue);
        record("export_name");
        ImGui::SetNextItemWidth(8.0f * fonts_.size);
        ImGui::Combo("Format", &export_format_, kExportFormats, IM_ARRAYSIZE(kExportFormats));
        const std::string format = kExportFormats[export_format_];
        const auto elements = name_table(AbaqusElement{});
        if (format == "inp") {
            ImGui::SameLine();
            ImGui::SetNextItemWidth(12.0f * fonts_.size);
            const std::string preview(elements[std::size_t(export_abaqus_element_)].label);
            if (ImGui::BeginCombo("Element", preview.c_str())) {
                for (std::size_t k = 0; k < elements.size(); ++k)
                    if (ImGui::Selectable(std::string(elements[k].label).c_str(),
                                          int(k) == export_abaqus_element_))
                        export_abaqus_element_ = int(k);
                ImGui::EndCombo();
            }
        } else if (format == "vtk") {
            ImGui::TextUnformatted("cell data: quality, min_angle, max_angle, distance");
        }
        const std::string base = in_folder(export_base_).string();
        const char* reduced = showing_equal_count() ? "-equal-count" : "";
        if (results_.mc) ImGui::BulletText("%s-mc%s.%s", base.c_str(), reduced, format.c_str());
        if (results_.frame)
            ImGui::BulletText("%s-%s-%d%s.%s", base.c_str(),
                              std::string(name_of(results_.frame->method)).c_str(),
                              results_.frame->iteration, reduced, format.c_str());
        if (ImGui::Button("Export") || enter) {
            try {
                remember_folder();
                const auto written = export_meshes(
                    base, format, elements[std::size_t(export_abaqus_element_)].value);
                std::string list;
                for (const std::string& file : written) list += (list.empty() ? "" : ", ") + file;
                notice("exported " + std::to_string(written.size()) + " meshes: " + list);
            } catch (const std::exception& e) {
                notice(std::string("export failed: ") + e.what(), true);
            }
            ImGui::CloseCurrentPopup();
        }
        ImGui::SameLine();
        if (ImGui::Button("Cancel") || ImGui::IsKeyPressed(key::Escape)) ImGui::CloseCurrentPopup();
        ImGui::EndPopup();
    }
}

} // namespace snert::app
