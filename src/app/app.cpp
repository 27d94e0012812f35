// The app's state and actions, and the frame's outline. The panels are in app_panels.cpp,
// the views and the iteration bar in app_views.cpp, menus and dialogs in app_menus.cpp.
#include "app.h"

#include "render/gl.h" // glad first

#include <algorithm>
#include <cmath>
#include <filesystem>

#include <imgui.h>

#include "io/mesh_io.h"
#include "core/phantom.h"
#include "path_completion.h"
#include "render/panels.h"
#include "view_renderer.h"

namespace snert::app {

namespace {

// How many iterations "run to convergence" may add before it gives up.
constexpr int kConvergenceIterations = 5000;

// Light theme matching the figures (render/panels.h), with ImGui's usual spacing.
void apply_app_style(ImGuiStyle& style, float font_px) {
    ImGui::StyleColorsLight(&style);
    const float unit = font_px / 13.0f;
    style.WindowPadding = ImVec2(std::round(8 * unit), std::round(8 * unit));
    style.FramePadding = ImVec2(std::round(5 * unit), std::round(3 * unit));
    style.ItemSpacing = ImVec2(std::round(7 * unit), std::round(4 * unit));
    style.ItemInnerSpacing = ImVec2(std::round(5 * unit), std::round(4 * unit));
    style.CellPadding = ImVec2(std::round(5 * unit), std::round(2 * unit));
    style.ScrollbarSize = std::round(13 * unit);
    style.GrabMinSize = std::round(12 * unit);
    style.IndentSpacing = std::round(14 * unit);
    style.WindowRounding = 0;
    style.ChildRounding = 0;
    style.FrameRounding = std::round(3 * unit);
    style.GrabRounding = std::round(3 * unit);
    style.PopupRounding = std::round(3 * unit);
    style.WindowBorderSize = 0;
    style.ChildBorderSize = 1;
    ImVec4* c = style.Colors;
    c[ImGuiCol_Text] = ImVec4(0.11f, 0.12f, 0.13f, 1);
    c[ImGuiCol_WindowBg] = ImVec4(0.955f, 0.96f, 0.968f, 1);
    c[ImGuiCol_ChildBg] = ImVec4(0, 0, 0, 0);
    c[ImGuiCol_MenuBarBg] = ImVec4(0.91f, 0.92f, 0.935f, 1);
    c[ImGuiCol_Header] = ImVec4(0.80f, 0.85f, 0.92f, 1);
    c[ImGuiCol_TableRowBgAlt] = ImVec4(0.94f, 0.95f, 0.97f, 1);
}

} // namespace

App::App(AppOptions options) : options_(std::move(options)) {
    settings_ = load_settings(options_.settings_path);
    Parameters& p = settings_.parameters;
    if (!options_.input.empty() && options_.input != p.volume.input) {
        p.volume.input = options_.input;
        p.auto_iso = true; // a saved iso belongs to the saved volume
    }
    if (options_.phantom_size) p.volume.phantom_size = *options_.phantom_size;
    if (phantom_spec_name(p.volume.input).empty()) open_path_text_ = p.volume.input;

    ImGuiIO& io = ImGui::GetIO();
    io.IniFilename = nullptr; // the layout is part of our own settings file
    const float scale = settings_.layout.ui_scale * std::clamp(options_.content_scale, 0.5f, 4.0f);
    fonts_ = render::add_figure_fonts(*io.Fonts, std::round(15.0f * scale));
    apply_app_style(ImGui::GetStyle(), fonts_.size);

    WorkerOptions worker_options;
    worker_options.history_budget_bytes = std::size_t(settings_.history_budget_mb) << 20;
    worker_ = std::make_unique<Worker>(worker_options);
    views_ = std::make_unique<ViewRenderer>();
}

App::~App() = default;

void App::frame() {
    const float dt = ImGui::GetIO().DeltaTime;
    rects_.clear();
    drain_worker();
    handle_shortcuts();
    advance_playback(dt);
    if (notice_timer_ > 0) notice_timer_ -= dt;

    draw_menu_bar();
    const ImGuiViewport* viewport = ImGui::GetMainViewport();
    const float menu_height = ImGui::GetFrameHeight();
    const float status_height = ImGui::GetFrameHeight();
    ImGui::SetNextWindowPos(ImVec2(viewport->Pos.x, viewport->Pos.y + menu_height));
    ImGui::SetNextWindowSize(
        ImVec2(viewport->Size.x, std::max(viewport->Size.y - menu_height - status_height, 1.0f)));
    ImGui::PushStyleVar(ImGuiStyleVar_WindowPadding, ImVec2(0, 0));
    ImGui::PushStyleVar(ImGuiStyleVar_ItemSpacing, ImVec2(0, 0));
    const ImGuiWindowFlags host_flags =
        ImGuiWindowFlags_NoDecoration | ImGuiWindowFlags_NoMove | ImGuiWindowFlags_NoSavedSettings |
        ImGuiWindowFlags_NoBringToFrontOnFocus | ImGuiWindowFlags_NoScrollWithMouse;
    ImGui::Begin("##snert", nullptr, host_flags);
    ImGui::PopStyleVar(2);

    const ImVec2 available = ImGui::GetContentRegionAvail();
    const float splitter = std::round(0.35f * fonts_.size);
    LayoutSettings& layout = settings_.layout;
    if (layout.show_side_panel) {
        layout.side_panel_width = std::clamp(layout.side_panel_width, 12.0f * fonts_.size,
                                             std::max(available.x * 0.6f, 12.0f * fonts_.size));
        ImGui::BeginChild("side panel", ImVec2(layout.side_panel_width, available.y), false);
        draw_side_panel();
        ImGui::EndChild();
        ImGui::SameLine(0, 0);
        ImGui::InvisibleButton("##side splitter", ImVec2(splitter, available.y));
        if (ImGui::IsItemHovered() || ImGui::IsItemActive())
            ImGui::SetMouseCursor(ImGuiMouseCursor_ResizeEW);
        if (ImGui::IsItemActive()) layout.side_panel_width += ImGui::GetIO().MouseDelta.x;
        ImGui::GetWindowDrawList()->AddLine(
            ImVec2(ImGui::GetItemRectMin().x + 0.5f * splitter, ImGui::GetItemRectMin().y),
            ImVec2(ImGui::GetItemRectMin().x + 0.5f * splitter, ImGui::GetItemRectMax().y),
            IM_COL32(200, 204, 212, 255));
        ImGui::SameLine(0, 0);
    }
    const ImVec2 main_size = ImGui::GetContentRegionAvail();
    ImGui::BeginChild("main", main_size, false,
                      ImGuiWindowFlags_NoScrollbar | ImGuiWindowFlags_NoScrollWithMouse);
    float bottom = 0;
    if (layout.show_bottom_panel) {
        layout.bottom_panel_height = std::clamp(layout.bottom_panel_height, 6.0f * fonts_.size,
                                                std::max(main_size.y * 0.65f, 6.0f * fonts_.size));
        bottom = layout.bottom_panel_height + splitter;
    }
    const float views_height = std::max(main_size.y - bottom, 4.0f * fonts_.size);
    draw_main_area(main_size.x, views_height);
    if (layout.show_bottom_panel) {
        // Placed by position, not by the flow, so item spacing cannot push the panel out.
        ImGui::SetCursorPos(ImVec2(0, views_height));
        ImGui::InvisibleButton("##bottom splitter", ImVec2(main_size.x, splitter));
        if (ImGui::IsItemHovered() || ImGui::IsItemActive())
            ImGui::SetMouseCursor(ImGuiMouseCursor_ResizeNS);
        if (ImGui::IsItemActive()) layout.bottom_panel_height -= ImGui::GetIO().MouseDelta.y;
        ImGui::GetWindowDrawList()->AddLine(
            ImVec2(ImGui::GetItemRectMin().x, ImGui::GetItemRectMin().y + 0.5f * splitter),
            ImVec2(ImGui::GetItemRectMax().x, ImGui::GetItemRectMin().y + 0.5f * splitter),
            IM_COL32(200, 204, 212, 255));
        ImGui::SetCursorPos(ImVec2(0, views_height + splitter));
        draw_bottom_panel(std::max(main_size.y - views_height - splitter, 1.0f));
    }
    ImGui::EndChild();
    ImGui::End();

    draw_status_bar();
    draw_help_window();
    draw_dialogs();
    restart_if_changed();
}

// --- Worker -------------------------------------------------------------------------------

void App::drain_worker() {
    for (const Message& message : worker_->drain()) {
        if (!results_.apply(message)) continue;
        if (const auto* volume = std::get_if<VolumeMessage>(&message.payload)) {
            if (settings_.parameters.auto_iso) {
                settings_.parameters.iso = volume->iso;
                requested_.iso = volume->iso; // the same request, now with its value known
            }
            const VolumeSpec& spec = volume->source->spec;
            if (phantom_spec_name(spec.input).empty()) settings_.add_recent(spec.input);
            const std::string key = spec.input + "#" + std::to_string(spec.phantom_size);
            if (key != framed_for_) {
                framed_for_ = key;
                camera_needs_framing_ = true;
            }
        } else if (const auto* done = std::get_if<FinishedMessage>(&message.payload)) {
            if (converge_when_finished_ && !done->converged) {
                converge_when_finished_ = false;
                run_to_convergence();
            }
        }
    }
    views_->set_mesh(0, results_.mc);
    views_->set_mesh(1, results_.frame);
    frame_camera_if_needed();
}

void App::restart_if_changed() {
    if (requested_once_ && settings_.parameters == requested_) return;
    requested_ = settings_.parameters;
    requested_once_ = true;
    results_.start(worker_->request(requested_.request()));
    following_ = true;
    playing_ = false;
    converge_when_finished_ = false;
}

void App::set_parameters(const Parameters& parameters) {
    settings_.parameters = parameters;
}

void App::open(const VolumeSpec& spec) {
    Parameters& p = settings_.parameters;
    if (p.volume == spec) return;
    p.volume = spec;
    p.auto_iso = true;
}

void App::open_path(const std::string& path) {
    const std::string expanded = expand_home(path);
    if (!phantom_spec_name(expanded).empty()) {
        open({expanded, settings_.parameters.volume.phantom_size});
        return;
    }
    if (!openable_path(expanded)) {
        notice(expanded + ": no such file or folder");
        return;
    }
    open_path_text_ = expanded;
    open({expanded, settings_.parameters.volume.phantom_size});
}

void App::on_drop(const std::vector<std::string>& paths) {
    if (!paths.empty()) open_path(paths.front());
}

// --- Iterations ---------------------------------------------------------------------------

int App::shown_iteration() const {
    const int last = std::max(results_.iteration_count() - 1, 0);
    return following_ ? last : std::min(pinned_iteration_, last);
}

void App::show_iteration(int k) {
    const int last = std::max(results_.iteration_count() - 1, 0);
    pinned_iteration_ = std::clamp(k, 0, last);
    following_ = false;
    worker_->show_iteration(results_.generation, pinned_iteration_);
}

void App::step(int delta) {
    playing_ = false;
    show_iteration(shown_iteration() + delta);
}

void App::follow_live() {
    following_ = true;
    worker_->show_iteration(results_.generation, Worker::kLive);
}

void App::set_playing(bool playing) {
    if (playing == playing_) return;
    playing_ = playing;
    play_clock_ = 0;
    if (!playing) return;
    const int last = results_.iteration_count() - 1;
    // Play from the start when at the end; otherwise from the iteration shown.
    const int from = shown_iteration() >= last && results_.finished ? 0 : shown_iteration();
    show_iteration(from);
}

void App::advance_playback(float dt) {
    if (!playing_) return;
    const int last = results_.iteration_count() - 1;
    // Wait for the frame of the iteration shown before moving on, so every iteration is seen
    // even when a frame takes longer than a play step.
    if (!results_.frame || results_.frame->iteration != pinned_iteration_) return;
    play_clock_ += dt;
    const int steps = int(play_clock_ * settings_.play_speed);
    if (steps <= 0) return;
    play_clock_ -= float(steps) / settings_.play_speed;
    if (pinned_iteration_ >= last) {
        if (results_.finished) playing_ = false;
        return;
    }
    show_iteration(std::min(pinned_iteration_ + steps, last));
    if (pinned_iteration_ >= last && results_.finished) playing_ = false;
}

void App::run_to_convergence() {
    playing_ = false;
    if (!results_.finished && results_.error.empty()) converge_when_finished_ = true;
    if (results_.finished && !results_.finished->converged) {
        results_.finished.reset();
        worker_->continue_relaxation(results_.generation, kConvergenceIterations);
        notice("relaxing until the largest move is under epsilon");
    }
    follow_live();
}

// --- Camera and style ---------------------------------------------------------------------

render::DrawStyle App::draw_style() const {
    render::DrawStyle style;
    style.shading = render::parse_shading(settings_.view.shading).value_or(render::Shading::Smooth);
    style.wireframe = settings_.view.wireframe;
    style.quality_threshold = settings_.view.quality_threshold;
    return style;
}

void App::frame_camera_if_needed() {
    if (!camera_needs_framing_) return;
    if (const auto bounds = views_->bounds()) {
        reset_camera();
        camera_needs_framing_ = false;
    }
}

void App::reset_camera() {
    const auto bounds = views_->bounds();
    if (!bounds) return;
    const auto preset =
        render::parse_view_preset(settings_.view.preset).value_or(render::ViewPreset::Iso);
    camera_ = render::frame_bounds(*bounds, preset, view_aspect_);
}

// --- Shortcuts and actions ----------------------------------------------------------------

void App::handle_shortcuts() {
    const ImGuiIO& io = ImGui::GetIO();
    if (io.WantTextInput) return; // typing into a field
    for (const Shortcut& s : shortcuts()) {
        const bool repeat = s.action == Action::StepBack || s.action == Action::StepForward;
        if (io.KeyCtrl == s.ctrl && ImGui::IsKeyPressed(s.key, repeat)) {
            perform(s.action);
            break;
        }
    }
}

void App::perform(Action action) {
    ViewSettings& view = settings_.view;
    switch (action) {
    case Action::PlayPause:
        set_playing(!playing_);
        break;
    case Action::StepBack:
        step(-1);
        break;
    case Action::StepForward:
        step(+1);
        break;
    case Action::FirstIteration:
        playing_ = false;
        show_iteration(0);
        break;
    case Action::LastIteration:
        playing_ = false;
        follow_live();
        break;
    case Action::RunToConvergence:
        run_to_convergence();
        break;
    case Action::ResetCamera:
        reset_camera();
        break;
    case Action::ViewFront:
        view.preset = "front";
        reset_camera();
        break;
    case Action::ViewSide:
        view.preset = "side";
        reset_camera();
        break;
    case Action::ViewTop:
        view.preset = "top";
        reset_camera();
        break;
    case Action::ViewIso:
        view.preset = "iso";
        reset_camera();
        break;
    case Action::ShadingFlat:
        view.shading = "flat";
        break;
    case Action::ShadingSmooth:
        view.shading = "smooth";
        break;
    case Action::ShadingQuality:
        view.shading = "quality";
        break;
    case Action::ToggleWireframe:
        view.wireframe = !view.wireframe;
        break;
    case Action::OpenFile:
        settings_.layout.show_side_panel = true;
        focus_open_field_ = true;
        break;
    case Action::Screenshot:
        screenshot_path_ = default_output_base() + ".png";
        screenshot_dialog_ = true;
        break;
    case Action::ExportMeshes:
        export_base_ = default_output_base();
        export_dialog_ = true;
        break;
    case Action::ToggleSidePanel:
        settings_.layout.show_side_panel = !settings_.layout.show_side_panel;
        break;
    case Action::ToggleBottomPanel:
        settings_.layout.show_bottom_panel = !settings_.layout.show_bottom_panel;
        break;
    case Action::Help:
        help_open_ = !help_open_;
        break;
    case Action::Quit:
        quit_requested_ = true;
        break;
    }
}

// --- Output -------------------------------------------------------------------------------

std::string App::default_output_base() const {
    std::string name = "snert";
    const VolumeSpec& v = settings_.parameters.volume;
    if (const std::string_view phantom = phantom_spec_name(v.input); !phantom.empty())
        name += "-" + std::string(phantom) + "-" + std::to_string(v.phantom_size);
    else
        name += "-" + std::filesystem::path(v.input).stem().string();
    if (results_.frame) name += "-" + std::to_string(results_.frame->iteration);
    return name;
}

void App::request_screenshot(const std::string& path) {
    screenshot_pending_ = true;
    screenshot_pending_path_ = path;
}

std::optional<ScreenshotRequest> App::take_screenshot_request() {
    if (!screenshot_pending_) return std::nullopt;
    screenshot_pending_ = false;
    return ScreenshotRequest{screenshot_pending_path_, views_rect_};
}

bool App::save_screenshot(const render::Image& window_image, const ScreenshotRequest& request,
                          float scale) {
    const int x0 = std::clamp(int(std::lround(request.region.x0 * scale)), 0, window_image.width);
    const int y0 = std::clamp(int(std::lround(request.region.y0 * scale)), 0, window_image.height);
    const int x1 = std::clamp(int(std::lround(request.region.x1 * scale)), x0, window_image.width);
    const int y1 = std::clamp(int(std::lround(request.region.y1 * scale)), y0, window_image.height);
    render::Image crop;
    crop.width = x1 - x0;
    crop.height = y1 - y0;
    crop.rgba.resize(std::size_t(crop.width) * std::size_t(crop.height) * 4);
    for (int y = 0; y < crop.height; ++y)
        std::copy_n(window_image.pixel(x0, y0 + y), std::size_t(crop.width) * 4, crop.pixel(0, y));
    try {
        if (crop.width == 0 || crop.height == 0)
            throw std::runtime_error(request.path + ": nothing to save (the views are hidden)");
        render::write_png(request.path, crop);
    } catch (const std::exception& e) {
        notice(std::string("screenshot failed: ") + e.what());
        return false;
    }
    notice("screenshot saved: " + request.path);
    return true;
}

std::vector<std::string> App::export_meshes(const std::string& base, const std::string& format) {
    std::vector<std::string> written;
    if (results_.mc) {
        const std::string path = base + "-mc." + format;
        write_mesh(results_.mc->mesh, path);
        written.push_back(path);
    }
    if (results_.frame) {
        const std::string path = base + "-" + std::string(name_of(results_.frame->method)) + "-" +
                                 std::to_string(results_.frame->iteration) + "." + format;
        write_mesh(results_.frame->mesh, path);
        written.push_back(path);
    }
    return written;
}

void App::save_settings() const {
    if (options_.settings_path.empty()) return;
    snert::app::save_settings(settings_, options_.settings_path);
}

void App::notice(std::string text) {
    notices_.push_back(std::move(text));
    if (notices_.size() > 20) notices_.erase(notices_.begin());
    notice_timer_ = 5.0f;
}

// --- Queries ------------------------------------------------------------------------------

bool App::animating() const {
    const bool frame_due =
        !following_ && (!results_.frame || results_.frame->iteration != pinned_iteration_);
    return worker_->busy() || worker_->has_messages() || playing_ || frame_due ||
           !requested_once_ || results_.generation != worker_->latest_generation() ||
           notice_timer_ > 0;
}

int App::view_render_count() const {
    return views_->render_count();
}

std::optional<UiRect> App::widget_rect(const std::string& id) const {
    const auto it = rects_.find(id);
    if (it == rects_.end()) return std::nullopt;
    return it->second;
}

void App::record(const std::string& id) {
    const ImVec2 min = ImGui::GetItemRectMin(), max = ImGui::GetItemRectMax();
    rects_[id] = UiRect{min.x, min.y, max.x, max.y};
}

} // namespace snert::app
