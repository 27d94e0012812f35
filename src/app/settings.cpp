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
#include <optional>
#include <sstream>
#include <stdexcept>
#include <string_view>

#include <glm/glm.hpp>

#include "io/atomic_file.h"
#include "io/raw_options_text.h"

namespace snert::app {

namespace {

struct Field {
    const char* key;
    std::function<std::string(const Settings&)> get;
    std::function<bool(Settings&, const std::string&)> set; // false: value not accepted
    bool optional = false; // not written when get() is empty (an option that is not set)
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

// An enum field, stored by its name (core/names.h).
template <class E, class Member> Field choice_field(const char* key, Member member) {
    return {key, [member](const Settings& s) { return std::string(name_of(member(s))); },
            [member](Settings& s, const std::string& text) {
                const std::optional<E> value = parse_name<E>(text);
                if (value) member(s) = *value;
                return value.has_value();
            }};
}

// Every machine name of an enum's table (core/names.h), for string_field's allowed values.
template <class E> std::vector<std::string> names_of() {
    std::vector<std::string> names;
    for (const Named<E>& row : name_table(E{})) names.emplace_back(row.name);
    return names;
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

// One option of an input (SourceSpec): its text, empty when the option is not set.
struct SpecField {
    const char* key;
    std::function<std::string(const SourceSpec&)> get;
    std::function<bool(SourceSpec&, const std::string&)> set; // false: value not accepted
};

// The raw options, created (with the defaults) by the first raw_* key that is read.
RawOptions& raw_of(SourceSpec& spec) {
    if (!spec.raw) spec.raw.emplace();
    return *spec.raw;
}

// The options of an input beyond its path and phantom size, in the order they are written.
const std::vector<SpecField>& spec_fields() {
    static const std::vector<SpecField> table = {
        {"raw",
         [](const SourceSpec& s) { return s.raw ? raw_dims_text(s.raw->dims) : std::string(); },
         [](SourceSpec& s, const std::string& text) {
             return parse_raw_dims(text, raw_of(s).dims).empty();
         }},
        {"raw_type",
         [](const SourceSpec& s) {
             return s.raw ? std::string(scalar_type_name(s.raw->type)) : std::string();
         },
         [](SourceSpec& s, const std::string& text) {
             try {
                 const ScalarType type = parse_scalar_type(text);
                 raw_of(s).type = type;
                 return true;
             } catch (const std::invalid_argument&) {
                 return false;
             }
         }},
        {"raw_spacing",
         [](const SourceSpec& s) {
             return s.raw ? raw_spacing_text(s.raw->spacing) : std::string();
         },
         [](SourceSpec& s, const std::string& text) {
             return parse_raw_spacing(text, raw_of(s).spacing).empty();
         }},
        {"raw_endian",
         [](const SourceSpec& s) {
             return s.raw ? std::string(endian_name(s.raw->endian)) : std::string();
         },
         [](SourceSpec& s, const std::string& text) {
             try {
                 raw_of(s).endian = parse_endian(text);
                 return true;
             } catch (const std::invalid_argument&) {
                 return false;
             }
         }},
        {"series", [](const SourceSpec& s) { return s.series_uid; },
         [](SourceSpec& s, const std::string& text) {
             s.series_uid = text;
             return true;
         }},
        {"labels", [](const SourceSpec& s) { return s.labels; },
         [](SourceSpec& s, const std::string& text) {
             s.labels = text;
             return true;
         }},
        {"label", [](const SourceSpec& s) { return s.label ? std::to_string(*s.label) : ""; },
         [](SourceSpec& s, const std::string& text) {
             int v = 0;
             if (!parse_int(text, v)) return false;
             s.label = v;
             return true;
         }},
        {"isotropic",
         [](const SourceSpec& s) { return s.isotropic ? float_text(*s.isotropic) : ""; },
         [](SourceSpec& s, const std::string& text) {
             float edge = 0.0f;
             if (!parse_float(text, edge) || !(edge >= 0.0f)) return false;
             s.isotropic = edge;
             return true;
         }},
    };
    return table;
}

// Raw options without their dimensions (a raw_type line alone) cannot be read: dropped.
void drop_incomplete_raw(SourceSpec& spec) {
    if (spec.raw && glm::any(glm::lessThan(spec.raw->dims, glm::ivec3(1)))) spec.raw.reset();
}

// The settings' fields of the current input's options.
std::vector<Field> volume_option_fields() {
    std::vector<Field> fields;
    for (const SpecField& f : spec_fields())
        fields.push_back(
            {f.key, [f](const Settings& s) { return f.get(s.parameters.volume); },
             [f](Settings& s, const std::string& text) { return f.set(s.parameters.volume, text); },
             true});
    return fields;
}

// Accessor of one member, usable on a const and a mutable Settings.
#define SNERT_MEMBER(expr)                                                                         \
    [](auto& s) -> auto& {                                                                         \
        return s.expr;                                                                             \
    }

const std::vector<Field>& fields() {
    static const std::vector<Field> table = [] {
        std::vector<Field> t = {
            string_field("volume", SNERT_MEMBER(parameters.volume.input)),
            int_field("phantom_size", SNERT_MEMBER(parameters.volume.phantom_size), 8, 1024),
        };
        for (Field& f : volume_option_fields()) t.push_back(std::move(f));
        for (Field& f : std::vector<Field>{
                 bool_field("auto_iso", SNERT_MEMBER(parameters.auto_iso)),
                 float_field("iso", SNERT_MEMBER(parameters.iso), -1e30f, 1e30f),
                 choice_field<InsideIs>("inside", SNERT_MEMBER(parameters.inside)),
                 // true or false once chosen in the app; absent: the input's default.
                 Field{"close_border",
                       [](const Settings&s) {
                           const std::optional<bool>& c = s.parameters.close_border;
                           return c ? std::string(*c ? "true" : "false") : std::string();
                       },
                       [](Settings&s, const std::string&text) {
                           if (text != "true" && text != "false") return false;
                           s.parameters.close_border = text == "true";
                           return true;
                       },
                       true},
                 choice_field<RelaxMode>("mode", SNERT_MEMBER(parameters.relax.mode)),
                 float_field("smoothing_weight", SNERT_MEMBER(parameters.relax.smoothing_weight), 0,
                             10),
                 float_field("gradient_weight", SNERT_MEMBER(parameters.relax.gradient_weight), 0,
                             10),
                 choice_field<Schedule>("schedule", SNERT_MEMBER(parameters.relax.schedule)),
                 bool_field("favour_accuracy", SNERT_MEMBER(parameters.relax.favour_accuracy)),
                 choice_field<Constraint>("constraint", SNERT_MEMBER(parameters.relax.constraint)),
                 choice_field<GradientMethod>("gradient", SNERT_MEMBER(parameters.relax.gradient)),
                 float_field("sigma", SNERT_MEMBER(parameters.relax.gradient_sigma), 0.1f, 10),
                 int_field("iterations", SNERT_MEMBER(parameters.relax.max_iterations), 0, 100000),
                 float_field("epsilon", SNERT_MEMBER(parameters.relax.epsilon), 0, 1),
                 choice_field<TriangulationRule>("triangulation",
                                                 SNERT_MEMBER(parameters.triangulation)),
                 string_field("shading", SNERT_MEMBER(view.shading), {"flat", "smooth", "quality"}),
                 bool_field("wireframe", SNERT_MEMBER(view.wireframe)),
                 float_field("quality_threshold", SNERT_MEMBER(view.quality_threshold), 0, 1),
                 string_field("color_by", SNERT_MEMBER(view.color_by), names_of<ShapeMeasure>()),
                 string_field("view", SNERT_MEMBER(view.preset), {"front", "side", "top", "iso"}),
                 int_field("window_width", SNERT_MEMBER(layout.window_width), 320, 16384),
                 int_field("window_height", SNERT_MEMBER(layout.window_height), 240, 16384),
                 int_field("window_x", SNERT_MEMBER(layout.window_x), -1, 65535),
                 int_field("window_y", SNERT_MEMBER(layout.window_y), -1, 65535),
                 float_field("side_panel_width", SNERT_MEMBER(layout.side_panel_width), 150, 2000),
                 float_field("bottom_panel_height", SNERT_MEMBER(layout.bottom_panel_height), 80,
                             2000),
                 bool_field("show_side_panel", SNERT_MEMBER(layout.show_side_panel)),
                 bool_field("show_bottom_panel", SNERT_MEMBER(layout.show_bottom_panel)),
                 int_field("bottom_tab", SNERT_MEMBER(layout.bottom_tab), 0, 1),
                 float_field("ui_scale", SNERT_MEMBER(layout.ui_scale), 0.5f, 3),
                 float_field("play_speed", SNERT_MEMBER(play_speed), 0.5f, 240),
                 string_field("output_folder", SNERT_MEMBER(output_folder)),
                 int_field("history_budget_mb", SNERT_MEMBER(history_budget_mb), 0, 1 << 20),
             })
            t.push_back(std::move(f));
        return t;
    }();
    return table;
}

#undef SNERT_MEMBER

std::string trim(const std::string& text) {
    const auto first = text.find_first_not_of(" \t\r");
    if (first == std::string::npos) return {};
    const auto last = text.find_last_not_of(" \t\r");
    return text.substr(first, last - first + 1);
}

} // namespace

JobRequest Parameters::request() const {
    JobRequest job;
    job.volume = volume;
    if (!auto_iso) job.iso = iso;
    job.options.inside = inside;
    job.close_border = closes_border();
    job.options.relax = relax;
    job.options.relax.triangulation = triangulation;
    return job;
}

bool Parameters::closes_border() const {
    return close_border.value_or(closes_border_by_default(volume));
}

bool Parameters::operator==(const Parameters& other) const {
    return volume == other.volume && auto_iso == other.auto_iso && iso == other.iso &&
           inside == other.inside && close_border == other.close_border && relax == other.relax &&
           triangulation == other.triangulation;
}

void Settings::add_recent(const SourceSpec& spec) {
    if (spec.input.empty() || spec.is_phantom()) return;
    recent_files.erase(std::remove(recent_files.begin(), recent_files.end(), spec),
                       recent_files.end());
    recent_files.insert(recent_files.begin(), spec);
    if (recent_files.size() > kMaxRecent) recent_files.resize(kMaxRecent);
}

namespace {
constexpr std::string_view kLineSeparator = " | ";
} // namespace

std::string format_source_line(const SourceSpec& spec) {
    std::string line = spec.input;
    for (const SpecField& f : spec_fields())
        if (const std::string value = f.get(spec); !value.empty())
            line += std::string(kLineSeparator) + f.key + "=" + value;
    return line;
}

std::optional<SourceSpec> parse_source_line(const std::string& line) {
    SourceSpec spec;
    std::size_t at = line.find(kLineSeparator);
    spec.input = trim(line.substr(0, at));
    if (spec.input.empty()) return std::nullopt;
    while (at != std::string::npos) {
        const std::size_t start = at + kLineSeparator.size();
        at = line.find(kLineSeparator, start);
        const std::string item = line.substr(start, at == std::string::npos ? at : at - start);
        const auto equals = item.find('=');
        if (equals == std::string::npos) return std::nullopt;
        const std::string key = trim(item.substr(0, equals));
        const auto f = std::find_if(spec_fields().begin(), spec_fields().end(),
                                    [&](const SpecField& sf) { return key == sf.key; });
        if (f == spec_fields().end() || !f->set(spec, trim(item.substr(equals + 1))))
            return std::nullopt;
    }
    if (spec.raw && glm::any(glm::lessThan(spec.raw->dims, glm::ivec3(1)))) return std::nullopt;
    return spec;
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
            const std::optional<SourceSpec> spec = parse_source_line(value);
            if (spec && s.recent_files.size() < Settings::kMaxRecent &&
                std::find(s.recent_files.begin(), s.recent_files.end(), *spec) ==
                    s.recent_files.end())
                s.recent_files.push_back(*spec);
            continue;
        }
        if (key == "recent_iso") { // "190 carotid.vtk | ...": the iso, then the input's line
            const auto space = value.find(' ');
            float iso = 0;
            if (space != std::string::npos && parse_float(value.substr(0, space), iso)) {
                const std::optional<SourceSpec> spec = parse_source_line(value.substr(space + 1));
                if (spec) s.iso_by_input[format_source_line(*spec)] = iso;
            }
            continue;
        }
        for (const Field& f : fields()) {
            if (key == f.key) {
                f.set(s, value); // a bad value keeps the default
                break;
            }
        }
    }
    drop_incomplete_raw(s.parameters.volume);
    return s;
}

std::string format_settings(const Settings& settings) {
    std::ostringstream out;
    out << "# snert settings: written by the app on exit; unknown keys and bad values are "
           "ignored\n";
    for (const Field& f : fields()) {
        const std::string value = f.get(settings);
        if (!f.optional || !value.empty()) out << f.key << " = " << value << "\n";
    }
    for (const SourceSpec& spec : settings.recent_files)
        out << "recent = " << format_source_line(spec) << "\n";
    for (const SourceSpec& spec : settings.recent_files) {
        const auto iso = settings.iso_by_input.find(format_source_line(spec));
        if (iso == settings.iso_by_input.end()) continue;
        char number[32];
        std::snprintf(number, sizeof number, "%.9g", double(iso->second));
        out << "recent_iso = " << number << " " << iso->first << "\n";
    }
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
