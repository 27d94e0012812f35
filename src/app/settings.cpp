// The settings file: one table of fields drives both reading and writing, so they cannot
// drift apart.
#include "settings.h"

#include <algorithm>
#include <cmath>
#include <charconv>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <sstream>

#include "io/atomic_file.h"

namespace snert::app {

namespace {

struct Field {
    const char* key;
    std::function<std::string(const Settings&)> get;
    std::function<bool(Settings&, const std::string&)> set; // false: value not accepted
};

bool parse_float(const std::string& text, float& out) {
    float value = 0;
    const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
    if (error != std::errc() || end != text.data() + text.size() || !std::isfinite(value))
        return false;
    out = value;
    return true;
}

bool parse_int(const std::string& text, int& out) {
    int value = 0;
    const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
    if (error != std::errc() || end != text.data() + text.size()) return false;
    out = value;
    return true;
}

// Shortest text that reads back as the same float.
std::string float_text(float v) {
    char buffer[32];
    const auto result = std::to_chars(buffer, buffer + sizeof buffer, v);
    return std::string(buffer, result.ptr);
}

// A float field with an accepted range.
template <class Member> Field float_field(const char* key, Member member, float lo, float hi) {
    return {key, [member](const Settings& s) { return float_text(member(s)); },
            [member, lo, hi](Settings& s, const std::string& text) {
                float v = 0;
                if (!parse_float(text, v) || v < lo || v > hi) return false;
                member(s) = v;
                return true;
            }};
}

template <class Member> Field int_field(const char* key, Member member, int lo, int hi) {
    return {key, [member](const Settings& s) { return std::to_string(member(s)); },
            [member, lo, hi](Settings& s, const std::string& text) {
                int v = 0;
                if (!parse_int(text, v) || v < lo || v > hi) return false;
                member(s) = v;
                return true;
            }};
}

template <class Member> Field bool_field(const char* key, Member member) {
    return {key, [member](const Settings& s) { return std::string(member(s) ? "true" : "false"); },
            [member](Settings& s, const std::string& text) {
                if (text != "true" && text != "false") return false;
                member(s) = text == "true";
                return true;
            }};
}

// An enum (or string) field with its names.
template <class T, class Member>
Field choice_field(const char* key, Member member, std::vector<std::pair<T, const char*>> names) {
    return {key,
            [member, names](const Settings& s) {
                const T value = member(s);
                for (const auto& [v, name] : names)
                    if (v == value) return std::string(name);
                return std::string(names.front().second);
            },
            [member, names](Settings& s, const std::string& text) {
                for (const auto& [v, name] : names) {
                    if (text == name) {
                        member(s) = v;
                        return true;
                    }
                }
                return false;
            }};
}

template <class Member>
Field string_field(const char* key, Member member, std::vector<std::string> allowed = {}) {
    return {key, [member](const Settings& s) { return std::string(member(s)); },
            [member, allowed](Settings& s, const std::string& text) {
                if (!allowed.empty() &&
                    std::find(allowed.begin(), allowed.end(), text) == allowed.end())
                    return false;
                member(s) = text;
                return true;
            }};
}

// Accessor of one member, usable on a const and a mutable Settings.
#define SNERT_MEMBER(expr)                                                                         \
    [](auto& s) -> auto& {                                                                         \
        return s.expr;                                                                             \
    }

const std::vector<Field>& fields() {
    static const std::vector<Field> table = {
        string_field("volume", SNERT_MEMBER(parameters.volume.input)),
        int_field("phantom_size", SNERT_MEMBER(parameters.volume.phantom_size), 8, 1024),
        bool_field("auto_iso", SNERT_MEMBER(parameters.auto_iso)),
        float_field("iso", SNERT_MEMBER(parameters.iso), -1e30f, 1e30f),
        choice_field<InsideIs>("inside", SNERT_MEMBER(parameters.inside),
                               {{InsideIs::Above, "above"}, {InsideIs::Below, "below"}}),
        choice_field<RelaxMode>("mode", SNERT_MEMBER(parameters.relax.mode),
                                {{RelaxMode::Snert, "snert"},
                                 {RelaxMode::Averaging, "sna"},
                                 {RelaxMode::Gradient, "gradient"}}),
        float_field("smoothing_weight", SNERT_MEMBER(parameters.relax.smoothing_weight), 0, 10),
        float_field("gradient_weight", SNERT_MEMBER(parameters.relax.gradient_weight), 0, 10),
        choice_field<Schedule>("schedule", SNERT_MEMBER(parameters.relax.schedule),
                               {{Schedule::Simultaneous, "simultaneous"},
                                {Schedule::SmoothingFirst, "smoothing-first"}}),
        bool_field("favour_accuracy", SNERT_MEMBER(parameters.relax.favour_accuracy)),
        choice_field<Constraint>("constraint", SNERT_MEMBER(parameters.relax.constraint),
                                 {{Constraint::RayBox, "raybox"}, {Constraint::Clip, "clip"}}),
        choice_field<GradientMethod>(
            "gradient", SNERT_MEMBER(parameters.relax.gradient),
            {{GradientMethod::Central, "central"}, {GradientMethod::Gaussian, "gaussian"}}),
        float_field("sigma", SNERT_MEMBER(parameters.relax.gradient_sigma), 0.1f, 10),
        int_field("iterations", SNERT_MEMBER(parameters.relax.max_iterations), 0, 100000),
        float_field("epsilon", SNERT_MEMBER(parameters.relax.epsilon), 0, 1),
        choice_field<TriangulationRule>("triangulation", SNERT_MEMBER(parameters.triangulation),
                                        {{TriangulationRule::ShorterDiagonal, "shorter"},
                                         {TriangulationRule::Delaunay, "delaunay"}}),
        string_field("shading", SNERT_MEMBER(view.shading), {"flat", "smooth", "quality"}),
        bool_field("wireframe", SNERT_MEMBER(view.wireframe)),
        float_field("quality_threshold", SNERT_MEMBER(view.quality_threshold), 0, 1),
        string_field("view", SNERT_MEMBER(view.preset), {"front", "side", "top", "iso"}),
        int_field("window_width", SNERT_MEMBER(layout.window_width), 320, 16384),
        int_field("window_height", SNERT_MEMBER(layout.window_height), 240, 16384),
        int_field("window_x", SNERT_MEMBER(layout.window_x), -1, 65535),
        int_field("window_y", SNERT_MEMBER(layout.window_y), -1, 65535),
        float_field("side_panel_width", SNERT_MEMBER(layout.side_panel_width), 150, 2000),
        float_field("bottom_panel_height", SNERT_MEMBER(layout.bottom_panel_height), 80, 2000),
        bool_field("show_side_panel", SNERT_MEMBER(layout.show_side_panel)),
        bool_field("show_bottom_panel", SNERT_MEMBER(layout.show_bottom_panel)),
        int_field("bottom_tab", SNERT_MEMBER(layout.bottom_tab), 0, 1),
        float_field("ui_scale", SNERT_MEMBER(layout.ui_scale), 0.5f, 3),
        float_field("play_speed", SNERT_MEMBER(play_speed), 0.5f, 240),
        int_field("history_budget_mb", SNERT_MEMBER(history_budget_mb), 0, 1 << 20),
    };
    return table;
}

#undef SNERT_MEMBER

std::string trim(const std::string& text) {
    const auto first = text.find_first_not_of(" \t\r");
    if (first == std::string::npos) return {};
    const auto last = text.find_last_not_of(" \t\r");
    return text.substr(first, last - first + 1);
}

bool same_relax(const RelaxOptions& a, const RelaxOptions& b) {
    return a.mode == b.mode && a.smoothing_weight == b.smoothing_weight &&
           a.gradient_weight == b.gradient_weight && a.schedule == b.schedule &&
           a.favour_accuracy == b.favour_accuracy && a.constraint == b.constraint &&
           a.gradient == b.gradient && a.gradient_sigma == b.gradient_sigma && a.iso == b.iso &&
           a.max_iterations == b.max_iterations && a.epsilon == b.epsilon;
}

} // namespace

JobRequest Parameters::request() const {
    JobRequest job;
    job.volume = volume;
    if (!auto_iso) job.iso = iso;
    job.options.inside = inside;
    job.options.relax = relax;
    job.options.relax.triangulation = triangulation;
    return job;
}

bool Parameters::operator==(const Parameters& other) const {
    return volume == other.volume && auto_iso == other.auto_iso && iso == other.iso &&
           inside == other.inside && same_relax(relax, other.relax) &&
           triangulation == other.triangulation;
}

void Settings::add_recent(const std::string& path) {
    if (path.empty()) return;
    recent_files.erase(std::remove(recent_files.begin(), recent_files.end(), path),
                       recent_files.end());
    recent_files.insert(recent_files.begin(), path);
    if (recent_files.size() > kMaxRecent) recent_files.resize(kMaxRecent);
}

std::string default_settings_path() {
    namespace fs = std::filesystem;
    if (const char* xdg = std::getenv("XDG_CONFIG_HOME"); xdg && *xdg)
        return (fs::path(xdg) / "snert" / "settings.ini").string();
    if (const char* home = std::getenv("HOME"); home && *home)
        return (fs::path(home) / ".config" / "snert" / "settings.ini").string();
    return {};
}

Settings parse_settings(const std::string& text) {
    Settings s;
    std::istringstream in(text);
    std::string line;
    while (std::getline(in, line)) {
        line = trim(line);
        if (line.empty() || line[0] == '#') continue;
        const auto equals = line.find('=');
        if (equals == std::string::npos) continue;
        const std::string key = trim(line.substr(0, equals));
        const std::string value = trim(line.substr(equals + 1));
        if (key == "recent") {
            if (!value.empty() && s.recent_files.size() < Settings::kMaxRecent)
                s.recent_files.push_back(value);
            continue;
        }
        for (const Field& f : fields()) {
            if (key == f.key) {
                f.set(s, value); // a bad value keeps the default
                break;
            }
        }
    }
    return s;
}

std::string format_settings(const Settings& settings) {
    std::ostringstream out;
    out << "# snert settings: written by the app on exit; unknown keys and bad values are "
           "ignored\n";
    for (const Field& f : fields()) out << f.key << " = " << f.get(settings) << "\n";
    for (const std::string& path : settings.recent_files) out << "recent = " << path << "\n";
    return out.str();
}

Settings load_settings(const std::string& path) {
    if (path.empty()) return {};
    std::ifstream in(path, std::ios::binary);
    if (!in) return {};
    std::ostringstream text;
    text << in.rdbuf();
    return parse_settings(text.str());
}

void save_settings(const Settings& settings, const std::string& path) {
    namespace fs = std::filesystem;
    std::error_code error;
    const fs::path folder = fs::path(path).parent_path();
    if (!folder.empty()) fs::create_directories(folder, error);
    if (error)
        throw std::runtime_error(path + ": cannot create the folder (" + error.message() + ")");
    const std::string text = format_settings(settings);
    write_file_atomically(path, [&](std::ostream& out) { out << text; });
}

} // namespace snert::app
