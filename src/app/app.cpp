// The app's state and actions, and the frame's outline. The panels are in app_panels.cpp,
// the views and the iteration bar in app_views.cpp, menus and dialogs in app_menus.cpp.
#include "app.h"

#include "render/gl.h" // glad first

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>

#include <imgui.h>

#include "core/phantom.h"
#include "io/mesh_export.h"
#include "path_completion.h"
#include "render/panels.h"
#include "slice_panel.h"
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
    c[ImGuiCol_WindowBg] = ImVec4(kWindowBackground[0], kWindowBackground[1], kWindowBackground[2],
                                  kWindowBackground[3]);
    c[ImGuiCol_ChildBg] = ImVec4(0, 0, 0, 0);
    c[ImGuiCol_MenuBarBg] = ImVec4(0.91f, 0.92f, 0.935f, 1);
    c[ImGuiCol_Header] = ImVec4(0.80f, 0.85f, 0.92f, 1);
    c[ImGuiCol_TableRowBgAlt] = ImVec4(0.94f, 0.95f, 0.97f, 1);
}

} // namespace

App::App(AppOptions options)
    : options_(std::move(options)), slice_panel_(std::make_unique<SlicePanel>()) {
    settings_ = load_settings(options_.settings_path);
    Parameters& p = settings_.parameters;
    // The saved input loaded in its session (only such inputs are saved): what a failed open
    // of the command line's input goes back to.
    fallback_ = p.volume;
    if (options_.source && !(*options_.source == p.volume)) {
        before_open_ = IsoChoice{p.auto_iso, p.iso, p.inside}; // the saved input's, for a fallback
        if (closes_border_by_default(*options_.source) != closes_border_by_default(p.volume))
            p.close_border.reset(); // a label map closes by default, grey values do not
        p.volume = *options_.source;
        // A saved iso belongs to the saved volume; this one may have its own from before.
        const auto remembered = settings_.iso_by_input.find(format_source_line(p.volume));
        p.auto_iso = remembered == settings_.iso_by_input.end();
        if (!p.auto_iso) p.iso = remembered->second;
    }
    if (options_.close_border) p.close_border = *options_.close_border;
    if (options_.iso) {
        p.iso = *options_.iso;
        p.auto_iso = false;
    }
    if (options_.inside) p.inside = *options_.inside;
    if (options_.pipeline) {
        p.relax = options_.pipeline->relax;
        p.triangulation = options_.pipeline->relax.triangulation;
    }
    if (fallback_ == p.volume) fallback_ = Parameters().volume;
    if (p.volume.is_phantom()) phantom_size_ = p.volume.phantom_size;
    sync_form(p.volume);
    scan_series(p.volume.input);

    ImGuiIO& io = ImGui::GetIO();
    io.IniFilename = nullptr; // the layout is part of our own settings file
    const float scale = settings_.layout.ui_scale * std::clamp(options_.content_scale, 0.5f, 4.0f);
    fonts_ = render::add_figure_fonts(*io.Fonts, std::round(15.0f * scale));
    apply_app_style(ImGui::GetStyle(), fonts_.size);

    WorkerOptions worker_options;
    worker_options.history_budget_bytes = std::size_t(settings_.history_budget_mb) << 20;
    worker_options.give_way_to_the_ui = options_.background_worker;
    worker_options.on_message = options_.wake;
    worker_ = std::make_unique<Worker>(worker_options);
    views_ = std::make_unique<ViewRenderer>();
    views_->set_parts_between_frames(options_.parts_between_frames);
}

App::~App() = default;

void App::warm_up(int width, int height) {
    views_->warm_up(width, height);
}

bool App::slice_view_shown() const {
    return slice_view_;
}

const SlicePanel& App::slice_panel() const {
    return *slice_panel_;
}

void App::frame() {
    const float dt = ImGui::GetIO().DeltaTime;
    rects_.clear();
    // A screenshot asked for in the last frame is taken of this one, drawn without the dialog
    // that asked for it (closed now) and without the hints over the views.
    capturing_ = screenshot_pending_;
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
        ImGuiWindowFlags_NoBringToFrontOnFocus | ImGuiWindowFlags_NoScrollWithMouse |
        ImGuiWindowFlags_NoBackground;
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
        // At most about 40 % of the height: the views keep theirs on a small screen.
        layout.bottom_panel_height = std::clamp(layout.bottom_panel_height, 6.0f * fonts_.size,
                                                std::max(main_size.y * 0.4f, 6.0f * fonts_.size));
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
    if (!capturing_) {
        draw_pick_panel();
        draw_explain_window();
        draw_help_window();
        draw_about_window();
    }
    draw_dialogs();
    remember_iso();
    restart_if_changed();
}

// --- Worker -------------------------------------------------------------------------------

void App::drain_worker() {
    poll_series();
    for (const Message& message : worker_->drain()) {
        if (!results_.apply(message)) continue;
        if (const auto* volume = std::get_if<VolumeMessage>(&message.payload)) {
            if (settings_.parameters.auto_iso) {
                settings_.parameters.iso = volume->iso;
                requested_.iso = volume->iso; // the same request, now with its value known
            }
            source_loaded(*volume->source);
        } else if (const auto* done = std::get_if<FinishedMessage>(&message.payload)) {
            if (converge_when_finished_ && !done->converged) {
                converge_when_finished_ = false;
                run_to_convergence();
            }
        } else if (const auto* failed = std::get_if<FailedMessage>(&message.payload)) {
            // No volume came before the failure: the input did not load.
            if (!results_.source_current) load_failed(failed->error);
        }
    }
    // The compactness takes minutes on a large scan: made only while someone looks at it.
    if ((equal_count_ || compactness_tab_open_) && results_.generation != compactness_asked_) {
        worker_->want_compactness(results_.generation);
        compactness_asked_ = results_.generation;
    }
    // Distances are measured on the worker, and only while one is chosen.
    worker_->set_color_by(color_by());
    views_->set_mesh(0, shown_mc());
    views_->set_mesh(1, shown_net());
    views_->set_distances(results_.distances);
}

// The iso chosen by hand for the input shown, kept for when it is opened again.
void App::remember_iso() {
    const Parameters& p = settings_.parameters;
    if (!loaded_ || !(*loaded_ == p.volume) || p.volume.is_phantom()) return;
    const std::string key = format_source_line(p.volume);
    if (p.auto_iso)
        settings_.iso_by_input.erase(key);
    else
        settings_.iso_by_input[key] = p.iso;
}

bool App::showing_equal_count() const {
    const auto& c = results_.compactness;
    return equal_count_ && c && c->mc_equal && c->net_equal && results_.frame &&
           results_.frame->iteration == c->net_equal->iteration;
}

std::shared_ptr<const DisplayMesh> App::shown_mc() const {
    return showing_equal_count() ? results_.compactness->mc_equal : results_.mc;
}

std::shared_ptr<const DisplayMesh> App::shown_net() const {
    return showing_equal_count() ? results_.compactness->net_equal : results_.frame;
}

void App::source_loaded(const Source& source) {
    const SourceSpec& spec = source.spec;
    const bool changed = !loaded_ || !(*loaded_ == spec);
    loaded_ = spec;
    before_open_.reset(); // load_error_ stays: it may be why this one is shown
    settings_.add_recent(spec);
    if (!changed) return;
    sync_form(spec);
    // A label's boundary says which side is the object (an organ darker than around it); a
    // threshold of the grey keeps the side the user chose.
    if (source.mask && settings_.parameters.auto_iso)
        settings_.parameters.inside = source.suggested_inside;
    std::error_code error;
    if (!std::filesystem::is_directory(spec.input, error)) series_ = {};
    const std::string key = format_source_line(spec) + "#" + std::to_string(spec.phantom_size);
    if (key != framed_for_) {
        framed_for_ = key;
        camera_needs_framing_ = true;
    }
}

// The input asked for did not load: say why, and go back to the last one that did (or, at
// the start, to the saved one, then the default phantom), with the iso choice it had.
void App::load_failed(const std::string& error) {
    load_error_ = error;
    notice(error, true);
    Parameters& p = settings_.parameters;
    const SourceSpec failed = requested_.volume;
    SourceSpec back = loaded_ ? *loaded_ : fallback_;
    if (!loaded_) fallback_ = Parameters().volume; // should the saved one fail too
    if (back == failed) return;                    // nothing else to show: the error stays
    p.volume = back;
    if (before_open_) {
        p.auto_iso = before_open_->auto_iso;
        p.iso = before_open_->iso;
        p.inside = before_open_->inside;
        before_open_.reset();
    }
    sync_form(back);
}

void App::sync_form(const SourceSpec& spec) {
    form_.path = spec.is_phantom() ? std::string() : spec.input;
    form_.raw = spec.raw.has_value();
    if (spec.raw) form_.raw_options = *spec.raw;
    form_.labels = spec.labels;
    if (!spec.is_phantom()) {
        form_.cubic = spec.isotropic.has_value();
        if (spec.isotropic) form_.cubic_edge = *spec.isotropic;
    }
    completions_.clear();
    label_completions_.clear();
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

void App::open(const SourceSpec& spec) {
    Parameters& p = settings_.parameters;
    if (spec.is_phantom()) phantom_size_ = spec.phantom_size;
    if (p.volume == spec) return;
    if (!before_open_) before_open_ = IsoChoice{p.auto_iso, p.iso, p.inside};
    // Between a label map and grey values the default applies again (on for label maps).
    if (closes_border_by_default(spec) != closes_border_by_default(p.volume))
        p.close_border.reset();
    p.volume = spec;
    const auto remembered = settings_.iso_by_input.find(format_source_line(spec));
    p.auto_iso = remembered == settings_.iso_by_input.end();
    if (!p.auto_iso) p.iso = remembered->second;
    load_error_.clear();
    scan_series(spec.input);
}

void App::open_path(const std::string& path) {
    const std::string expanded = expand_home(path);
    SourceSpec spec;
    spec.input = expanded;
    if (spec.is_phantom()) spec.phantom_size = phantom_size_;
    if (!spec.is_phantom()) {
        if (!openable_path(expanded)) {
            notice(expanded + ": no such file or folder", true);
            return;
        }
        if (form_.raw && !std::filesystem::is_directory(expanded)) spec.raw = form_.raw_options;
        if (form_.cubic) spec.isotropic = form_.cubic_edge;
    }
    form_.path = spec.is_phantom() ? std::string() : expanded;
    open(spec);
}

void App::open_form() {
    completions_.clear();
    label_completions_.clear();
    const std::string path = expand_home(form_.path);
    if (path.empty()) {
        notice("type the path of a volume file or DICOM folder first", true);
        return;
    }
    const SourceSpec& shown = settings_.parameters.volume;
    SourceSpec spec;
    spec.input = path;
    if (spec.is_phantom()) spec.phantom_size = phantom_size_;
    if (!spec.is_phantom()) {
        if (!openable_path(path)) {
            notice(path + ": no such file or folder", true);
            return;
        }
        if (form_.raw && !std::filesystem::is_directory(path)) spec.raw = form_.raw_options;
        if (form_.cubic) spec.isotropic = form_.cubic_edge;
        if (path == shown.input) spec.series_uid = shown.series_uid;
        spec.labels = expand_home(form_.labels);
        if (!spec.labels.empty() && !openable_path(spec.labels)) {
            notice(spec.labels + ": no such label map", true);
            return;
        }
        // The label stays chosen while the label map does; a new map lists its labels first.
        if (!spec.labels.empty() && spec.labels == shown.labels) spec.label = shown.label;
    }
    form_.path = spec.is_phantom() ? std::string() : path;
    form_.labels = spec.labels;
    open(spec);
}

void App::choose_label(std::optional<int> label) {
    SourceSpec spec = settings_.parameters.volume;
    if (spec.labels.empty()) return;
    spec.label = label;
    open(spec);
}

void App::choose_series(const std::string& uid) {
    if (series_.folder.empty()) return;
    SourceSpec spec;
    spec.input = series_.folder;
    spec.series_uid = uid;
    if (form_.cubic) spec.isotropic = form_.cubic_edge;
    form_.path = spec.input;
    open(spec);
}

// DICOM folders: their series are listed by a child process (io/dicom_series.h), which takes
// a while on a large folder, so off the UI thread; the frame polls the result.
void App::scan_series(const std::string& folder) {
    std::error_code error;
    if (folder.empty() || !std::filesystem::is_directory(folder, error)) return;
    if (series_.folder == folder &&
        (series_.scanning || !series_.error.empty() || !series_.series.empty()))
        return;
    if (series_scan_.valid()) stale_scans_.push_back(std::move(series_scan_));
    series_ = {};
    series_.folder = folder;
    series_.scanning = true;
    series_scan_ = std::async(std::launch::async, [folder] { return list_dicom_series(folder); });
}

void App::poll_series() {
    std::erase_if(stale_scans_, [](const std::future<std::vector<DicomSeries>>& f) {
        return f.wait_for(std::chrono::seconds(0)) == std::future_status::ready;
    });
    if (!series_scan_.valid() ||
        series_scan_.wait_for(std::chrono::seconds(0)) != std::future_status::ready)
        return;
    series_.scanning = false;
    try {
        series_.series = series_scan_.get();
        if (series_.series.empty()) series_.error = series_.folder + ": no DICOM series";
    } catch (const std::exception& e) {
        series_.error = e.what();
    }
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
    style.shading =
        parse_name<render::Shading>(settings_.view.shading).value_or(render::Shading::Smooth);
    style.wireframe = settings_.view.wireframe;
    style.quality_threshold = settings_.view.quality_threshold;
    return style;
}

// Called once the views' size is known (view_aspect_), so the new volume fills them. The
// meshes of the input shown before stay until the new ones arrive: framing waits for a mesh of
// the current job, or it would frame the old volume.
ShapeMeasure App::color_by() const {
    return parse_name<ShapeMeasure>(settings_.view.color_by).value_or(ShapeMeasure::Quality);
}

MeasureScale App::color_scale() const {
    const ShapeMeasure measure = color_by();
    const std::optional<DistanceMessage>& d = results_.distances;
    if (is_distance(measure) && d && d->distances && d->distances->measure == measure)
        return d->distances->scale;
    return measure_scale(measure);
}

const MeasureSummary* App::shown_summary(int view, ShapeMeasure measure) const {
    const DisplayMesh* mesh = view == 0 ? results_.mc.get() : results_.frame.get();
    if (!mesh) return nullptr;
    if (!is_distance(measure)) return &mesh->summary(measure);
    const std::optional<DistanceMessage>& d = results_.distances;
    if (!d || !d->distances || d->distances->measure != measure) return nullptr;
    if (view == 0 && d->mc_geometry == mesh->geometry) return &d->distances->first_summary;
    if (view == 1 && d->net_geometry == mesh->geometry) return &d->distances->second_summary;
    return nullptr;
}

void App::frame_camera_if_needed() {
    if (!camera_needs_framing_) return;
    const bool mc = results_.mc && !results_.mc->mesh.positions.empty();
    const bool current = mc ? results_.mc_current : results_.frame && results_.frame_current;
    if (!current || !views_->bounds()) return;
    reset_camera();
    camera_needs_framing_ = false;
}

void App::reset_camera() {
    const auto bounds = views_->bounds();
    if (!bounds) return;
    const auto preset =
        parse_name<render::ViewPreset>(settings_.view.preset).value_or(render::ViewPreset::Iso);
    camera_ = render::frame_bounds(*bounds, preset, view_aspect_);
}

// --- Shortcuts and actions ----------------------------------------------------------------

void App::handle_shortcuts() {
    std::vector<KeyPress> presses;
    presses.swap(key_presses_);
    if (ImGui::GetIO().WantTextInput) return; // typing into a field
    for (const KeyPress& press : presses) {
        for (const Shortcut& s : shortcuts()) {
            if (press.ctrl == s.ctrl && press.key == s.key) {
                const bool repeats =
                    s.action == Action::StepBack || s.action == Action::StepForward;
                if (!press.repeat || repeats) perform(s.action);
                break;
            }
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
        view.preset = name_of(render::ViewPreset::Front);
        reset_camera();
        break;
    case Action::ViewSide:
        view.preset = name_of(render::ViewPreset::Side);
        reset_camera();
        break;
    case Action::ViewTop:
        view.preset = name_of(render::ViewPreset::Top);
        reset_camera();
        break;
    case Action::ViewIso:
        view.preset = name_of(render::ViewPreset::Iso);
        reset_camera();
        break;
    case Action::ShadingFlat:
        view.shading = name_of(render::Shading::Flat);
        break;
    case Action::ShadingSmooth:
        view.shading = name_of(render::Shading::Smooth);
        break;
    case Action::ShadingQuality:
        view.shading = name_of(render::Shading::Quality);
        break;
    case Action::ToggleWireframe:
        view.wireframe = !view.wireframe;
        break;
    case Action::OpenFile:
        settings_.layout.show_side_panel = true;
        focus_open_field_ = true;
        break;
    case Action::Screenshot:
        screenshot_path_ = default_output_base() +
                           (results_.frame ? "-" + std::to_string(shown_iteration()) : "") + ".png";
        dialog_folder_ = output_folder();
        screenshot_dialog_ = true;
        break;
    case Action::ExportMeshes:
        export_base_ = default_output_base();
        dialog_folder_ = output_folder();
        export_dialog_ = true;
        break;
    case Action::ToggleSidePanel:
        settings_.layout.show_side_panel = !settings_.layout.show_side_panel;
        break;
    case Action::ToggleBottomPanel:
        settings_.layout.show_bottom_panel = !settings_.layout.show_bottom_panel;
        break;
    case Action::ToggleSliceView:
        slice_view_ = !slice_view_;
        break;
    case Action::NextSlice:
    case Action::PreviousSlice:
        slice_panel_->step_slice(action == Action::NextSlice ? +1 : -1);
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
    const SourceSpec& v = loaded_ ? *loaded_ : settings_.parameters.volume;
    if (const std::string_view phantom = phantom_spec_name(v.input); !phantom.empty())
        name += "-" + std::string(phantom) + "-" + std::to_string(v.phantom_size);
    else
        name += "-" + std::filesystem::path(v.input).stem().string();
    if (v.label) name += "-label" + std::to_string(*v.label);
    return name;
}

std::string App::output_folder() const {
    namespace fs = std::filesystem;
    std::error_code error;
    const std::string& last = settings_.output_folder;
    if (!last.empty() && fs::is_directory(last, error)) return last;
    return fs::current_path(error).string();
}

float App::iso_step() const {
    if (!results_.source) return 1.0f;
    const Source& source = *results_.source;
    if (source.info && source.info->scalar_type.find("int") != std::string::npos) return 1.0f;
    const double range = double(source.histogram.hi) - double(source.histogram.lo);
    if (!(range > 0)) return 1.0f;
    return float(std::pow(10.0, std::floor(std::log10(range / 1000.0))));
}

void App::request_screenshot(const std::string& path) {
    screenshot_pending_ = true;
    screenshot_pending_path_ = path;
}

std::optional<ScreenshotRequest> App::take_screenshot_request() {
    if (!screenshot_pending_ || !capturing_) return std::nullopt;
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
        notice(std::string("screenshot failed: ") + e.what(), true);
        return false;
    }
    std::error_code error;
    notice("screenshot saved: " +
           std::filesystem::absolute(request.path, error).lexically_normal().string());
    return true;
}

std::vector<std::string> App::export_meshes(const std::string& base, const std::string& format,
                                            AbaqusElement element) {
    std::vector<std::string> written;
    std::error_code error;
    const std::string absolute_base =
        std::filesystem::absolute(base, error).lexically_normal().string();
    auto write = [&](const DisplayMesh& shown, const std::string& path) {
        if (results_.source)
            export_mesh(shown.mesh, shown.method, *results_.source, results_.iso, path, element);
        else
            write_mesh(shown.mesh, path);
        written.push_back(path);
    };
    // The meshes shown: with the equal-count switch on, the reduced pair, named as such.
    const std::string reduced = showing_equal_count() ? "-equal-count" : "";
    if (const auto mc = shown_mc()) write(*mc, absolute_base + "-mc" + reduced + "." + format);
    if (const auto net = shown_net())
        write(*net, absolute_base + "-" + std::string(name_of(net->method)) + "-" +
                        std::to_string(net->iteration) + reduced + "." + format);
    return written;
}

Settings App::settings_to_save() const {
    Settings saved = settings_;
    // Never an input that did not (or did not yet) load: the next session would start on it.
    saved.parameters.volume = loaded_ ? *loaded_ : fallback_;
    if (before_open_) {
        saved.parameters.auto_iso = before_open_->auto_iso;
        saved.parameters.iso = before_open_->iso;
        saved.parameters.inside = before_open_->inside;
    }
    return saved;
}

void App::save_settings() const {
    if (options_.settings_path.empty()) return;
    snert::app::save_settings(settings_to_save(), options_.settings_path);
}

void App::notice(std::string text, bool error) {
    notices_.push_back({std::move(text), error});
    if (notices_.size() > 20) notices_.erase(notices_.begin());
    notice_timer_ = 5.0f;
}

// --- Queries ------------------------------------------------------------------------------

bool App::animating() const {
    return frame_interval() < kIdleFrame;
}

double App::frame_interval() const {
    const bool frame_due =
        !following_ && (!results_.frame || results_.frame->iteration != pinned_iteration_);
    // A view's buffers go between frames (draw_part_between_frames), part after part.
    if (views_->sending()) return kAnimatingFrame;
    if (views_->has_pending_work() || views_->picture_waiting()) return kSendingFrame;
    if (worker_->has_results() || playing_ || frame_due || !requested_once_ ||
        results_.generation != worker_->latest_generation() || notice_timer_ > 0 ||
        screenshot_pending_)
        return kAnimatingFrame;
    // A view waiting to draw its whole mesh notices the wait is over at the next frame; a view
    // drawing its parts draws them between frames (draw_part_between_frames); an iteration's
    // numbers (messages that are no results) wait for the next of these frames.
    if (worker_->busy() || views_->needs_refine() || worker_->has_messages()) return kProgressFrame;
    return kIdleFrame;
}

bool App::draw_part_between_frames() {
    return views_->draw_part_between_frames();
}

bool App::sending_views() const {
    return views_->sending();
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
