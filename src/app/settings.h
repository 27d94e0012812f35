// What the app remembers between runs: the parameters (with the whole input: file, raw options,
// DICOM series, label map and label), the view options, the layout and the recent inputs, as a
// small text file (key = value lines) in the user's configuration folder. The app stores only
// inputs that loaded, so a bad file never becomes the next session's start.
//
// GL-free: enums and view options are stored by their names (core/names.h: "snert", "raybox";
// the renderer's "smooth", "iso") and parsed by the app.
// Reading never fails: a missing file gives the defaults, and an unknown key or a bad value is
// skipped (the rest of the file still applies), so an old or hand-edited file cannot stop the
// app from starting. Writing is atomic (io/atomic_file.h).
#pragma once

#include <cstddef>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "io/source.h"
#include "worker.h"

namespace snert::app {

// The pipeline's parameters as the panel edits them (DESIGN.md).
struct Parameters {
    SourceSpec volume{"phantom:two-spheres", 64};
    bool auto_iso = true; // use the input's suggested iso (the phantom's, a label's, Otsu's)
    float iso = 0.0f;     // used when !auto_iso
    InsideIs inside = InsideIs::Above;
    // Close the surfaces at the volume border (io/source.h's close_border); empty: the input's
    // default (closes_border_by_default: on for a label map).
    std::optional<bool> close_border;
    RelaxOptions relax; // mode, weights, schedule, constraint, gradient, iterations, eps
    TriangulationRule triangulation = TriangulationRule::ShorterDiagonal;

    JobRequest request() const;
    bool closes_border() const; // close_border, or the input's default
    bool operator==(const Parameters&) const;
};

struct ViewSettings {
    std::string shading = "quality"; // "flat", "smooth", "quality" (render/mesh_view.h)
    bool wireframe = false;
    float quality_threshold = 0.25f; // triangles under it are highlighted in quality shading
    std::string preset = "iso";      // "front", "side", "top", "iso"
    std::string color_by = "q";      // the measure quality shading and the histograms show:
                                     // "q", "q60", "radius-ratio", "distance-iso",
                                     // "distance-other" (core/names.h)
};

struct LayoutSettings {
    int window_width = 1440, window_height = 900;
    int window_x = -1, window_y = -1; // -1: let the window system place it
    float side_panel_width = 330.0f;  // pixels (at scale 1)
    float bottom_panel_height = 300.0f;
    bool show_side_panel = true;
    bool show_bottom_panel = true;
    int bottom_tab = 0;    // 0 histograms + metrics, 1 convergence plots
    float ui_scale = 1.0f; // text size factor
};

struct Settings {
    Parameters parameters;
    ViewSettings view;
    LayoutSettings layout;
    std::vector<SourceSpec> recent_files; // inputs that loaded (files, not phantoms), newest
                                          // first, at most kMaxRecent
    // The iso value last chosen by hand for an input (format_source_line's key), so reopening a
    // recent file keeps its iso; kept for the recent inputs only.
    std::map<std::string, float> iso_by_input;
    std::string output_folder;   // where screenshots and exports were last written
    float play_speed = 10.0f;    // iterations per second while playing
    int history_budget_mb = 256; // memory for stored iterations

    static constexpr std::size_t kMaxRecent = 10;
    // Puts `spec` first in recent_files (removing an equal older entry), keeping kMaxRecent.
    void add_recent(const SourceSpec& spec);
};

// One input on one line, as the settings file keeps its recent inputs: the path, then
// " | key=value" for each option that is set, named as on the command line (raw=64,64,32,
// raw_type=uint16, raw_spacing=1,1,2.5, raw_endian=big, series=UID, labels=PATH, label=5); the
// current input is stored under the same keys. A plain path reads back as itself.
// parse_source_line gives nothing for an empty line or a bad option.
std::string format_source_line(const SourceSpec& spec);
std::optional<SourceSpec> parse_source_line(const std::string& line);

// The settings file: $XDG_CONFIG_HOME/snert/settings.ini, else ~/.config/snert/settings.ini;
// empty when neither variable is set (the app then keeps nothing).
std::string default_settings_path();

// Parses the text of a settings file over the defaults.
Settings parse_settings(const std::string& text);
std::string format_settings(const Settings& settings);

// Reads `path` (defaults when it does not exist or cannot be read).
Settings load_settings(const std::string& path);
// Writes `path` atomically, creating its folder. Throws std::runtime_error naming the file.
void save_settings(const Settings& settings, const std::string& path);

} // namespace snert::app
