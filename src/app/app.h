// The interactive app: Marching Cubes and the relaxed SurfaceNet side by side, the parameters
// that make them, and the relaxation's iterations to step through.
//
// Input: whatever the CLI opens (io/source.h: a phantom, a volume file, a DICOM folder and one
// of its series, headerless raw data, a label map beside the grey image with one label). The
// app keeps the last input that loaded: when opening another one fails, the error is shown in
// red, the old input (and its meshes) stay, and parameter changes keep running on it; only
// inputs that loaded are remembered (settings, recent list).
//
// Screen (all panels are parts of one window; the splitters between them can be dragged):
//
//   File  View  Phantoms  Help                                                   menu bar
//   +-------------+------------------------------------------------------------+
//   | Volume      |  shading / wireframe / camera presets                 toolbar |
//   |  open, info |  +-------------------------+-------------------------+        |
//   | Iso value   |  | Marching Cubes          | SNERT, iteration k      |  titles|
//   |  histogram  |  |      view               |      view     [legend]  |  views |
//   | Relaxation  |  +-------------------------+-------------------------+        |
//   |  parameters |  |< < [play] > >|  ----slider----  k / n   [Run to convergence] |
//   | Progress    |  +-----------------------------------------------------------+ |
//   |  per stage  |  | [Quality & metrics] [Convergence]  histograms | table / plots |
//   +-------------+------------------------------------------------------------+
//   status line
//
// App holds the UI state and draws one ImGui frame per call to frame(); the platform glue
// (window.h: a GLFW window; headless.h: an offscreen context for tests) owns the GL and ImGui
// contexts and the frame loop. The computation runs in the background Worker; frame() drains
// its results once and never waits for it. The 3D views are drawn into offscreen targets only
// when something they show changed.
#pragma once

#include <array>
#include <functional>
#include <future>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "core/pipeline.h"
#include "io/dicom_series.h"
#include "io/mesh_io.h"
#include "io/source.h"
#include "job_results.h"
#include "render/camera.h"
#include "render/fonts.h"
#include "render/image.h"
#include "render/mesh_view.h"
#include "settings.h"
#include "shortcuts.h"
#include "worker.h"

namespace snert::app {

class ViewRenderer;
class SlicePanel;

// The window's background: the glue clears to it and the app's host window, which covers the
// window, draws no background of its own (with software GL, filling it again costs as much as
// the clear).
inline constexpr std::array<float, 4> kWindowBackground{0.955f, 0.96f, 0.968f, 1.0f};

// What the command line (snert gui) or a test asks for; each given item overrides the saved
// settings for this session (and is saved on exit like a choice made in the window).
struct AppOptions {
    std::optional<SourceSpec> source; // the input; empty: the saved one
    std::optional<float> iso;         // a fixed iso value; empty: the saved choice
    std::optional<InsideIs> inside;   // which side is the object; empty: the saved choice
    std::optional<bool> close_border; // close surfaces at the border; empty: the saved choice
    // The relaxation's options (mode, weights, schedule, constraint, gradient, iterations,
    // epsilon, triangulation); iso and inside come from the two members above.
    std::optional<PipelineOptions> pipeline;
    std::string settings_path;      // read at start, written by save_settings(); empty: none
    bool show_timings = true;       // false: no wall-clock times on screen (snapshot tests)
    float content_scale = 1.0f;     // the monitor's scale (HiDPI): multiplies the text size
    bool background_worker = false; // the worker gives way to the window (WorkerOptions)
    // The glue sends the views' mesh buffers between frames (draw_part_between_frames), where
    // the views' render otherwise sends a part a frame.
    bool parts_between_frames = false;
    std::function<void()> wake; // WorkerOptions::on_message: wakes the glue's loop
};

// The Open panel's fields that are not applied until Open is pressed (the label and the DICOM
// series are pickers that open at once). Kept in step with the input shown.
struct OpenForm {
    std::string path; // the path field: a volume file, a DICOM folder or a .dcm
    bool raw = false; // headerless raw data: read `path` with raw_options
    RawOptions raw_options{glm::ivec3(64), ScalarType::UInt16, glm::vec3(1.0f), Endian::Little};
    std::string labels; // the label map field: a label volume on the grey image's grid
    // Resampling to cubic voxels (SourceSpec::isotropic): applied at once to the file shown,
    // and kept for the next file opened (a phantom's voxels are cubic already).
    bool cubic = false;
    float cubic_edge = 0.0f; // mm; 0: the smallest spacing
};

// A message in the status line: an outcome (screenshot saved) or an error (red).
struct Notice {
    std::string text;
    bool error = false;
};

// The DICOM series of a folder, listed off the UI thread (io/dicom_series.h).
struct SeriesList {
    std::string folder;
    bool scanning = false;
    std::vector<DicomSeries> series; // largest first
    std::string error;               // the scan failed (one line)
};

// A rectangle in window pixels, origin at the top-left.
struct UiRect {
    float x0 = 0, y0 = 0, x1 = 0, y1 = 0;
    float width() const { return x1 - x0; }
    float height() const { return y1 - y0; }
    float centre_x() const { return 0.5f * (x0 + x1); }
    float centre_y() const { return 0.5f * (y0 + y1); }
};

// A triangle clicked in a 3D view and what the pick panel says about it (core/triangle_pick.h,
// core/metrics.h): its angles, its shape by each measure, its corners' distances to the
// iso-surface. Follows the iteration shown: the same triangle of the view's current mesh.
struct PickedTriangle {
    int view = 0; // 0 Marching Cubes, 1 the net
    std::shared_ptr<const DisplayMesh> mesh;
    std::size_t triangle = 0;
    std::array<glm::vec3, 3> corners{}; // world millimetres
    std::array<float, 3> angles{};      // degrees, at the three corners
    TriangleShape shape;
    std::array<float, 3> iso_distance{}; // voxels, |first-order distance|; NaN: no reference
};

// A screenshot the glue takes after rendering the frame: `region` of the window (the views
// with their titles), saved as a PNG at `path`.
struct ScreenshotRequest {
    std::string path;
    UiRect region;
};

class App {
  public:
    // Needs a current GL context (loaded) and a current ImGui context whose font atlas has not
    // been built yet: adds the fonts (render/fonts.h) at `ui_scale` and sets the style.
    explicit App(AppOptions options);
    ~App();
    App(const App&) = delete;
    App& operator=(const App&) = delete;

    // One frame of UI: call between ImGui::NewFrame and ImGui::Render, GL context current.
    // May draw into the app's offscreen view targets; the glue binds its own framebuffer
    // before rendering ImGui's draw data.
    void frame();
    // Before the first frame (the window's glue, its framebuffer's size): the views' shaders
    // compiled by one draw of each kind (ViewRenderer::warm_up), so that no frame carries it.
    void warm_up(int width, int height);

    // --- Actions (menus, buttons, shortcuts, drag-and-drop and tests all come here) ---
    // Opens `spec` (restarts the computation at the next frame). Should it fail to load, the
    // app goes back to the input shown before and says why (load_error()).
    void open(const SourceSpec& spec);
    // A file or DICOM folder, read as headerless raw data when the form's raw box is ticked.
    void open_path(const std::string& path);
    void open_form(); // what the Open panel's fields say (the Open button, Enter)
    // The label map's label to extract; empty: threshold the grey values (and list the labels).
    void choose_label(std::optional<int> label);
    void choose_series(const std::string& uid);          // a series of the DICOM folder shown
    void on_drop(const std::vector<std::string>& paths); // opens the first one
    void perform(Action action);
    void show_iteration(int k); // pin the right view to iteration k (clamped)
    void step(int delta);       // +/- iterations from the one shown
    void follow_live();         // show the newest iteration and keep following
    void set_playing(bool playing);
    void run_to_convergence();
    void reset_camera();
    // What a click in a 3D view does: picks the triangle under window point (x, y) of `view`
    // (0 Marching Cubes, 1 the net); false (and nothing picked) when no triangle is there.
    bool pick(int view, float x, float y);
    const std::optional<PickedTriangle>& picked() const { return picked_; }
    bool explain_open() const { return explain_open_; }
    // The `snert render` command line that draws the input shown with the views' camera
    // (View > Copy camera as command line puts it on the clipboard).
    std::string camera_command() const;
    void set_explain_open(bool open) { explain_open_ = open; }
    void turn_camera(float delta_yaw, float delta_pitch) { camera_.orbit(delta_yaw, delta_pitch); }
    // A key went down (or repeats): shortcuts act on these events, not on the key's state at
    // frame time, so a press and release between two slow frames is not lost.
    // Repeats (a key held down) step through the iterations only.
    void key_pressed(int key, bool ctrl, bool repeat = false) {
        key_presses_.push_back({key, ctrl, repeat});
    }
    // Replaces the parameters; a change restarts the computation at the next frame.
    void set_parameters(const Parameters& parameters);
    void request_screenshot(const std::string& path);
    // Writes the shown meshes as <base>-mc.<format> and <base>-<method>-<k>.<format> with
    // io's export_mesh, as `snert export` does (`element`: the triangles' type in an .inp);
    // returns the files written (absolute paths). Throws std::runtime_error naming a file that
    // failed.
    std::vector<std::string> export_meshes(const std::string& base, const std::string& format,
                                           AbaqusElement element = AbaqusElement::S3);

    // --- State for the glue and the tests ---
    const Settings& settings() const { return settings_; }
    Settings& settings() { return settings_; }
    // What save_settings() writes: the settings with the last input that loaded.
    Settings settings_to_save() const;
    // The Open panel's fields (tests fill them as a user would type).
    OpenForm& form() { return form_; }
    const OpenForm& form() const { return form_; }
    // The input last loaded in this session (what a failed open falls back to).
    const std::optional<SourceSpec>& loaded_source() const { return loaded_; }
    // Why the last open failed (one line, names the input); empty after one that loaded.
    const std::string& load_error() const { return load_error_; }
    // The DICOM series of the folder last opened; empty folder: none listed.
    const SeriesList& series_list() const { return series_; }
    const JobResults& results() const { return results_; }
    const Worker& worker() const { return *worker_; }
    int shown_iteration() const; // the iteration the slider shows
    bool following() const { return following_; }
    bool playing() const { return playing_; }
    bool equal_count() const { return equal_count_; }
    void set_equal_count(bool on) { equal_count_ = on; }
    bool quit_requested() const { return quit_requested_; }
    bool help_open() const { return help_open_; }
    const render::OrbitCamera& camera() const { return camera_; }
    // How often the 3D views were redrawn (they are redrawn only when something changed).
    int view_render_count() const;
    // The views' renderer: per-view draws and uploads (view_renderer.h), for tests.
    const ViewRenderer& view_renderer() const { return *views_; }
    render::DrawStyle draw_style() const;
    ShapeMeasure color_by() const; // the measure the colours and the histograms show
    // The histogram panel's summary of `measure` for Marching Cubes (0) or the net's frame (1):
    // a distance's from the worker's DistanceMessage measured on that mesh; null while there is
    // none (no mesh, or its distances not measured yet).
    const MeasureSummary* shown_summary(int view, ShapeMeasure measure) const;
    // The range the colours, the legend and the histograms span: the worker's for a distance
    // (pair_distances), [0, 1] for a shape.
    MeasureScale color_scale() const;
    // True while something is changing (a job, playback, a frame on its way): keep drawing
    // frames; otherwise the glue may sleep until the next input event.
    bool animating() const;
    // How long the glue may wait for an event before it draws the next frame, in seconds:
    // kAnimatingFrame while something moves on screen, kProgressFrame while only the worker's
    // progress bar and iteration numbers do (its results wake the loop through
    // AppOptions::wake), kIdleFrame otherwise. Software GL draws the window with the processor
    // the worker computes with.
    // While a view's new buffers or its update are sent, a part at a time between frames
    // (draw_part_between_frames), kAnimatingFrame. While a view's sent mesh waits to be drawn
    // (ViewRenderer::has_pending_work), kSendingFrame: the frames follow one another, and the
    // new mesh is shown a frame's work later; so too once a view's whole mesh was finished
    // between frames, to show it.
    static constexpr double kAnimatingFrame = 1.0 / 15, kProgressFrame = 1.0 / 3, kIdleFrame = 0.5;
    static constexpr double kSendingFrame = 0.0;
    double frame_interval() const;
    // The next part of a view's buffers to send, else of a view's whole mesh to draw
    // (ViewRenderer::draw_part_between_frames), for the glue to do while it waits for the next
    // frame; false when there is none.
    bool draw_part_between_frames();
    // Parts of a view's buffers are being sent: the glue sends them one after another (each a
    // few milliseconds), where it spaces the parts of a drawing while the worker computes.
    bool sending_views() const;
    // The rectangle a named widget had in the last frame ("step_forward", "step_back",
    // "play", "iteration_slider", "run_to_convergence", "views", "iso_slider", ...).
    std::optional<UiRect> widget_rect(const std::string& id) const;
    std::optional<ScreenshotRequest> take_screenshot_request();
    // Crops the rendered window (`window_image`, framebuffer pixels, `scale` per window pixel)
    // to the request's region and writes the PNG; reports the outcome in the status line.
    // Returns false (with the reason in notices()) when the file could not be written.
    bool save_screenshot(const render::Image& window_image, const ScreenshotRequest& request,
                         float scale);
    // The one-line status under the panels ("two-spheres 64^3 - SNERT - converged ...").
    std::string status_text() const;
    // Saves the settings (with the glue's window geometry already stored in settings()).
    void save_settings() const;
    // Messages for the user (screenshot saved, export failed...), newest last.
    const std::vector<Notice>& notices() const { return notices_; }
    // The text of the Open field (tests of its completion).
    const std::string& open_field_text() const { return form_.path; }
    bool about_open() const { return about_open_; }
    // The slice view beside the 3D views (View menu, V).
    bool slice_view_shown() const;
    // Shows an index-space point (picked in a 3D view) in the slice view, opening it.
    void show_in_slice(glm::vec3 index_point);
    const SlicePanel& slice_panel() const;
    // How far the side panel's content runs past its height in the last frame (0: no scroll
    // bar needed).
    float side_panel_overflow() const { return side_panel_overflow_; }
    // The iso value's step: 1 for a volume stored as integers, else a power of ten about a
    // thousandth of the value range. The field steps by it; histogram clicks round to it.
    float iso_step() const;
    // The folder the screenshot and export dialogs write into (the last one used, else the
    // working folder), absolute.
    std::string output_folder() const;
    void show_about() { about_open_ = true; }

  private:
    // Frame parts (app.cpp, app_panels.cpp, app_views.cpp, app_menus.cpp).
    void drain_worker();
    void restart_if_changed();
    void advance_playback(float dt);
    void handle_shortcuts();
    void draw_menu_bar();
    void draw_side_panel();
    void draw_volume_section();
    void draw_open_fields();
    void draw_raw_options();
    void draw_label_map();
    void draw_cubic_voxels();
    void draw_series_list();
    void draw_iso_section();
    void draw_relaxation_section();
    void draw_progress_section();
    void draw_main_area(float width, float height);
    void draw_toolbar();
    void draw_views(float width, float height);
    void draw_iteration_bar();
    void draw_bottom_panel(float height);
    void draw_quality_tab();
    void draw_convergence_tab();
    void draw_compactness_tab();
    // The meshes the views and the metrics show: the job's, or with the "equal triangle count"
    // switch on, both reduced to one count (once measured, and while the last iteration shows).
    std::shared_ptr<const DisplayMesh> shown_mc() const;
    std::shared_ptr<const DisplayMesh> shown_net() const;
    bool showing_equal_count() const;
    void draw_status_bar();
    void draw_help_window();
    void draw_about_window();
    void draw_dialogs();
    void handle_view_input(int view, const UiRect& area);
    void measure_picked(std::shared_ptr<const DisplayMesh> mesh);
    void draw_pick_panel();
    void draw_explain_window();
    void record(const std::string& id); // the last item's rectangle under `id`
    void notice(std::string text, bool error = false);
    void source_loaded(const Source& source);
    void load_failed(const std::string& error);
    void sync_form(const SourceSpec& spec);
    void scan_series(const std::string& folder);
    void poll_series();
    void frame_camera_if_needed();
    void remember_iso();
    std::string default_output_base() const;

    AppOptions options_;
    Settings settings_;
    render::FigureFonts fonts_;
    std::unique_ptr<Worker> worker_;
    std::unique_ptr<ViewRenderer> views_;
    JobResults results_;
    Parameters requested_; // what the worker was last asked for
    bool requested_once_ = false;

    // Iterations.
    bool following_ = true;    // the right view follows the newest iteration
    int pinned_iteration_ = 0; // the chosen iteration when not following
    bool playing_ = false;
    float play_clock_ = 0.0f;             // seconds accumulated towards the next iteration
    bool converge_when_finished_ = false; // "run to convergence" pressed while still running

    bool equal_count_ = false;            // the "equal triangle count" switch
    bool compactness_tab_open_ = false;   // the Compactness tab was drawn in the last frame
    std::uint64_t compactness_asked_ = 0; // the job whose compactness the worker was asked for

    // Camera.
    render::OrbitCamera camera_;
    std::string framed_for_; // the volume the camera was last framed on
    bool camera_needs_framing_ = true;
    float view_aspect_ = 1.0f;

    // Input. `loaded_` is the last input that loaded; `fallback_` what a failed first open
    // goes back to (the saved input, then the default phantom). `before_open_` holds the iso
    // choice the open replaced, restored when it fails.
    std::optional<SourceSpec> loaded_;
    SourceSpec fallback_;
    int phantom_size_ = 64; // of the phantoms the menus open (a file's spec keeps the default)
    struct IsoChoice {
        bool auto_iso = true;
        float iso = 0.0f;
        InsideIs inside = InsideIs::Above;
    };
    std::optional<IsoChoice> before_open_;
    std::string load_error_;
    OpenForm form_;
    SeriesList series_;
    std::future<std::vector<DicomSeries>> series_scan_;
    std::vector<std::future<std::vector<DicomSeries>>> stale_scans_; // finish, then dropped

    // Panels and dialogs.
    std::vector<std::string> completions_;
    std::vector<std::string> label_completions_;
    bool focus_open_field_ = false;
    bool help_open_ = false;
    bool about_open_ = false;
    bool screenshot_dialog_ = false, export_dialog_ = false;
    std::string screenshot_path_, export_base_;
    int export_format_ = 0, export_abaqus_element_ = 0;
    bool quit_requested_ = false;
    std::optional<ScreenshotRequest> screenshot_request_;
    bool screenshot_pending_ = false;
    std::string screenshot_pending_path_;
    bool capturing_ = false;    // this frame is the screenshot's: no hints, no windows over it
    std::string dialog_folder_; // the dialogs' folder field
    std::vector<Notice> notices_;
    float notice_timer_ = 0.0f;
    bool tab_restored_ = false; // the saved bottom tab was selected
    std::map<std::string, UiRect> rects_;
    struct KeyPress {
        int key = 0;
        bool ctrl = false;
        bool repeat = false;
    };
    std::vector<KeyPress> key_presses_; // since the last frame, oldest first
    UiRect views_rect_;                 // views + titles, for screenshots
    std::unique_ptr<SlicePanel> slice_panel_;
    bool slice_view_ = false;
    void draw_slice_area(float x, float y, float width, float height);
    void draw_crosshair(const UiRect& view, bool net_view);
    void pick_for_slice(const UiRect& view, bool net_view);
    float side_panel_overflow_ = 0.0f;
    std::optional<PickedTriangle> picked_;
    std::array<UiRect, 2> view_rects_{}; // the two 3D views in the last frame
    bool explain_open_ = false;
};

} // namespace snert::app
