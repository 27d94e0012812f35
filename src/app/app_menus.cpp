// Menus, the status line, the Help window and the screenshot / export dialogs.
#include "app.h"

#include <cstdio>

#include <imgui.h>
#include <imgui_stdlib.h>

#include "core/phantom.h"
#include "render/panels.h"

namespace snert::app {

namespace {

constexpr const char* kExportFormats[] = {"stl", "obj", "ply", "off", "vtk"};

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
            for (const std::string& path : settings_.recent_files)
                if (ImGui::MenuItem(path.c_str())) open_path(path);
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
        const VolumeSpec& v = settings_.parameters.volume;
        for (const std::string& name : phantom_names()) {
            const std::string size = std::to_string(v.phantom_size) + "\xC2\xB3";
            if (ImGui::MenuItem(name.c_str(), size.c_str(), v.input == "phantom:" + name))
                open({"phantom:" + name, v.phantom_size});
        }
        ImGui::Separator();
        if (ImGui::BeginMenu("Grid size")) {
            for (int size : {32, 48, 64, 96, 128}) {
                const std::string label = std::to_string(size) + "\xC2\xB3 voxels";
                if (ImGui::MenuItem(label.c_str(), nullptr, v.phantom_size == size)) {
                    VolumeSpec spec = v;
                    spec.phantom_size = size;
                    if (!phantom_spec_name(v.input).empty())
                        open(spec);
                    else
                        settings_.parameters.volume.phantom_size = size;
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
        ImGui::Separator();
        menu_action(*this, "Parameter panel", Action::ToggleSidePanel,
                    settings_.layout.show_side_panel);
        menu_action(*this, "Bottom panel", Action::ToggleBottomPanel,
                    settings_.layout.show_bottom_panel);
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
    char iso[48];
    std::snprintf(iso, sizeof iso, "  \xC2\xB7  iso %.4g", settings_.parameters.iso);
    text += iso;
    text +=
        "  \xC2\xB7  " + std::string(label_of(method_of(settings_.parameters.relax.mode)));
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
    if (notice_timer_ > 0 && !notices_.empty()) {
        ImGui::PushStyleColor(ImGuiCol_Text, IM_COL32(0, 100, 160, 255));
        ImGui::TextUnformatted(notices_.back().c_str());
        ImGui::PopStyleColor();
    } else {
        ImGui::TextUnformatted(status_text().c_str());
    }
    ImGui::SameLine(std::max(ImGui::GetWindowWidth() - help_width - fonts_.size, 0.0f));
    ImGui::TextDisabled("%s", help.c_str());
    ImGui::End();
}

void App::draw_help_window() {
    if (!help_open_) return;
    const ImGuiViewport* viewport = ImGui::GetMainViewport();
    ImGui::SetNextWindowPos(ImVec2(viewport->Pos.x + 0.5f * viewport->Size.x,
                                   viewport->Pos.y + 0.5f * viewport->Size.y),
                            ImGuiCond_Appearing, ImVec2(0.5f, 0.5f));
    ImGui::SetNextWindowSize(ImVec2(40.0f * fonts_.size, 0), ImGuiCond_Appearing);
    ImGui::PushStyleVar(ImGuiStyleVar_WindowBorderSize, 1.0f);
    const bool visible =
        ImGui::Begin("Help: snert", &help_open_,
                     ImGuiWindowFlags_NoCollapse | ImGuiWindowFlags_AlwaysAutoResize);
    ImGui::PopStyleVar();
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
    ImGui::SetNextWindowPos(centre, ImGuiCond_Appearing, ImVec2(0.5f, 0.5f));
    if (ImGui::BeginPopupModal("Save screenshot", nullptr, ImGuiWindowFlags_AlwaysAutoResize)) {
        ImGui::TextUnformatted("A PNG of the two views with their titles, at screen resolution.");
        ImGui::SetNextItemWidth(30.0f * fonts_.size);
        if (ImGui::IsWindowAppearing()) ImGui::SetKeyboardFocusHere();
        const bool enter =
            ImGui::InputText("File", &screenshot_path_, ImGuiInputTextFlags_EnterReturnsTrue);
        if (ImGui::Button("Save") || enter) {
            request_screenshot(screenshot_path_);
            ImGui::CloseCurrentPopup();
        }
        ImGui::SameLine();
        if (ImGui::Button("Cancel") || ImGui::IsKeyPressed(key::Escape)) ImGui::CloseCurrentPopup();
        ImGui::EndPopup();
    }
    ImGui::SetNextWindowPos(centre, ImGuiCond_Appearing, ImVec2(0.5f, 0.5f));
    if (ImGui::BeginPopupModal("Export meshes", nullptr, ImGuiWindowFlags_AlwaysAutoResize)) {
        ImGui::TextUnformatted("Writes the two meshes shown (world units, millimetres):");
        ImGui::SetNextItemWidth(30.0f * fonts_.size);
        if (ImGui::IsWindowAppearing()) ImGui::SetKeyboardFocusHere();
        ImGui::InputText("Name", &export_base_);
        ImGui::SetNextItemWidth(8.0f * fonts_.size);
        ImGui::Combo("Format", &export_format_, kExportFormats, IM_ARRAYSIZE(kExportFormats));
        const std::string format = kExportFormats[export_format_];
        if (results_.mc) ImGui::BulletText("%s-mc.%s", export_base_.c_str(), format.c_str());
        if (results_.frame)
            ImGui::BulletText("%s-%s-%d.%s", export_base_.c_str(), std::string(name_of(results_.frame->method)).c_str(),
                              results_.frame->iteration, format.c_str());
        if (ImGui::Button("Export")) {
            try {
                const auto written = export_meshes(export_base_, format);
                notice("exported " + std::to_string(written.size()) +
                       " meshes: " + (written.empty() ? std::string() : written.back()));
            } catch (const std::exception& e) {
                notice(std::string("export failed: ") + e.what());
            }
            ImGui::CloseCurrentPopup();
        }
        ImGui::SameLine();
        if (ImGui::Button("Cancel") || ImGui::IsKeyPressed(key::Escape)) ImGui::CloseCurrentPopup();
        ImGui::EndPopup();
    }
}

} // namespace snert::app
