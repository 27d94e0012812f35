#include "options.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <stdexcept>
#include <vector>

#include "core/input_error.h"
#include "core/phantom.h"
#include "io/atomic_file.h"
#include "io/raw_options_text.h"
#include "io/load_volume.h"

namespace snert::cli {

std::string format_number(double value) {
    char text[32];
    std::snprintf(text, sizeof text, "%g", value);
    return text;
}

namespace {

std::string check_dims(std::string& text) {
    glm::ivec3 dims{0};
    return parse_raw_dims(text, dims);
}

std::string check_spacing(std::string& text) {
    glm::vec3 spacing{0.0f};
    return parse_raw_spacing(text, spacing);
}

std::string check_raw_type(std::string& text) {
    try {
        const ScalarType type = parse_scalar_type(text);
        if (type == ScalarType::UInt64 || type == ScalarType::Int64)
            return "64-bit integers are not offered for raw data";
    } catch (const std::invalid_argument& e) {
        return e.what();
    }
    return {};
}

std::string check_endian(std::string& text) {
    try {
        parse_endian(text);
    } catch (const std::invalid_argument& e) {
        return e.what();
    }
    return {};
}

// The raw sample types offered: every stored type but the 64-bit integers.
std::string raw_type_choices() {
    std::string text;
    for (const ScalarType t :
         {ScalarType::UInt8, ScalarType::Int8, ScalarType::UInt16, ScalarType::Int16,
          ScalarType::UInt32, ScalarType::Int32, ScalarType::Float32, ScalarType::Float64})
        text += (text.empty() ? "" : "|") + std::string(scalar_type_name(t));
    return text;
}

const CLI::Validator kFinite(
    [](std::string& text) -> std::string {
        try {
            std::size_t used = 0;
            const double v = std::stod(text, &used);
            if (used == text.size() && std::isfinite(v)) return {};
        } catch (const std::exception&) {
        }
        return "'" + text + "' is not a finite number";
    },
    "");

// --isotropic's edge: nothing (the smallest spacing) or a positive number of millimetres.
std::string check_edge(std::string& text) {
    if (text.empty()) return {};
    try {
        std::size_t used = 0;
        const double v = std::stod(text, &used);
        if (used == text.size() && std::isfinite(v) && v > 0.0) return {};
    } catch (const std::exception&) {
    }
    return "'" + text + "' is not a positive number of millimetres";
}

constexpr const char* kInputGroup = "Input";
constexpr const char* kPipelineGroup = "Relaxation";

} // namespace

void add_input_options(CLI::App& command, InputArgs& a, bool optional_input) {
    a.o_input = command.add_option(
        "VOLUME", a.input,
        "phantom:NAME (" +
            [] {
                std::string names;
                for (const std::string& n : phantom_names())
                    names += (names.empty() ? "" : ", ") + n;
                return names;
            }() +
            "), a volume file (NRRD, NIfTI, MetaImage, VTK, Analyze), a DICOM folder or .dcm, "
            "or headerless raw data with --raw");
    a.o_input->type_name("");
    if (!optional_input) a.o_input->required();
    a.o_size = command.add_option("--size", a.size, "phantom grid size N (N^3 voxels)")
                   ->check(CLI::Range(8, 1024))
                   ->type_name("N")
                   ->capture_default_str()
                   ->group(kInputGroup);
    a.o_iso = command
                  .add_option("--iso", a.iso,
                              "iso value of the grey image (default: the phantom's, the label "
                              "boundary's, or Otsu's threshold)")
                  ->check(kFinite)
                  ->type_name("V")
                  ->group(kInputGroup);
    add_name_option<InsideIs>(
        command, "--inside", [&a](InsideIs v) { a.inside = v; },
        "inside is I >= iso (above) or I <= iso (below) (default: above, or the label's side)")
        ->group(kInputGroup);
    a.o_raw = command
                  .add_option("--raw", a.raw,
                              "read VOLUME as headerless raw samples of this size (one file, or "
                              "a numbered slice series starting at VOLUME)")
                  ->check(CLI::Validator(check_dims, ""))
                  ->type_name("X,Y,Z")
                  ->group(kInputGroup);
    a.o_raw_type = command.add_option("--raw-type", a.raw_type, "stored sample type of --raw")
                       ->check(CLI::Validator(check_raw_type, ""))
                       ->type_name(raw_type_choices())
                       ->group(kInputGroup);
    a.o_raw_spacing =
        command.add_option("--raw-spacing", a.raw_spacing, "voxel size of --raw in mm")
            ->check(CLI::Validator(check_spacing, ""))
            ->type_name("X,Y,Z")
            ->default_str("1,1,1")
            ->group(kInputGroup);
    a.o_raw_endian = command.add_option("--raw-endian", a.raw_endian, "byte order of --raw")
                         ->check(CLI::Validator(check_endian, ""))
                         ->type_name("little|big")
                         ->default_str("little")
                         ->group(kInputGroup);
    a.o_series = command
                     .add_option("--series", a.series,
                                 "DICOM folder: the series with this SeriesInstanceUID "
                                 "(default: the largest)")
                     ->type_name("UID")
                     ->group(kInputGroup);
    a.o_labels = command
                     .add_option("--labels", a.labels,
                                 "a label map on the grey image's grid: segment by --label "
                                 "instead of thresholding (the net's gradient uses the grey)")
                     ->type_name("FILE")
                     ->group(kInputGroup);
    a.o_label = command.add_option("--label", a.label, "the label of --labels to extract")
                    ->type_name("N")
                    ->group(kInputGroup);
    a.o_isotropic = add_isotropic_option(command, a.isotropic)->group(kInputGroup);
    a.o_close_border =
        command
            .add_flag("--close-border,!--no-close-border", a.close_border,
                      "treat the volume as surrounded by one layer of outside, so every surface "
                      "that reaches the border is closed there (default: on with --labels, off "
                      "for grey values)")
            ->group(kInputGroup);
    a.o_raw->needs(a.o_raw_type);
    a.o_raw_type->needs(a.o_raw);
    a.o_raw_spacing->needs(a.o_raw);
    a.o_raw_endian->needs(a.o_raw);
    a.o_series->excludes(a.o_raw);
    a.o_labels->needs(a.o_label);
    a.o_label->needs(a.o_labels);
}

CLI::Option* add_isotropic_option(CLI::App& command, std::string& text) {
    return command
        .add_option("--isotropic", text,
                    "resample to cubic voxels of MM mm (default: the smallest spacing) before "
                    "anything else: grey values linearly, a label's mask linearly, cut at 0.5")
        ->expected(0, 1)
        ->check(CLI::Validator(check_edge, ""))
        ->type_name("[MM]");
}

std::optional<float> isotropic_edge(const CLI::Option* option, const std::string& text) {
    if (!option->count()) return std::nullopt;
    return text.empty() ? 0.0f : std::stof(text); // checked by the option's validator
}

InputChoice input_choice(const InputArgs& a) {
    InputChoice c;
    c.spec.input = a.input;
    if (a.o_iso->count()) c.iso = a.iso;
    c.inside = a.inside;
    if (a.o_close_border && a.o_close_border->count()) c.close_border = a.close_border;
    if (c.spec.is_phantom()) {
        for (const CLI::Option* o : {a.o_raw, a.o_raw_type, a.o_raw_spacing, a.o_raw_endian,
                                     a.o_series, a.o_labels, a.o_label, a.o_isotropic})
            if (o->count())
                throw CLI::ValidationError(o->get_name(),
                                           "applies to volume files, not to " + a.input);
        c.spec.phantom_size = a.size;
        return c;
    }
    if (a.o_size->count() && !a.input.empty())
        throw CLI::ValidationError("--size",
                                   "applies to phantoms only, not to the file " + a.input);
    if (a.o_raw->count()) {
        RawOptions raw;
        parse_raw_dims(a.raw, raw.dims); // checked by the option's validator
        raw.type = parse_scalar_type(a.raw_type);
        if (a.o_raw_spacing->count()) parse_raw_spacing(a.raw_spacing, raw.spacing);
        if (a.o_raw_endian->count()) raw.endian = parse_endian(a.raw_endian);
        c.spec.raw = raw;
    }
    c.spec.isotropic = isotropic_edge(a.o_isotropic, a.isotropic);
    c.spec.series_uid = a.series;
    c.spec.labels = a.labels;
    if (a.o_label->count()) c.spec.label = a.label;
    return c;
}

bool closes_border(const InputChoice& choice) {
    return choice.close_border.value_or(closes_border_by_default(choice.spec));
}

Source close_border_if_chosen(Source source, const InputChoice& choice, float iso,
                              InsideIs inside) {
    if (!closes_border(choice)) return source;
    return close_border(std::move(source), iso, inside);
}

Source open_input(const InputChoice& choice, const Progress& progress) {
    Source source;
    try {
        source = open_source(choice.spec, progress);
    } catch (const std::invalid_argument& e) {
        throw InputError(e.what());
    } catch (const InputError&) {
        throw;
    } catch (const std::runtime_error& e) {
        throw InputError(e.what());
    }
    if (source.info)
        std::cerr << "snert: " << choice.spec.input << ": " << source.description << "\n";
    for (const std::string& warning : source.warnings)
        std::cerr << "snert: warning: " << warning << "\n";
    if (!choice.iso && !source.spec.is_phantom())
        std::cerr << "snert: no --iso given; using " << source.iso_reason << "\n";
    return source;
}

void add_pipeline_options(CLI::App& command, PipelineArgs& a, bool with_mode) {
    RelaxOptions& r = a.relax;
    if (with_mode)
        a.o_mode = add_name_option<RelaxMode>(
                       command, "--mode", [&a](RelaxMode m) { a.mode = m; },
                       "the net to run beside Marching Cubes (default: SNA and SNERT)")
                       ->group(kPipelineGroup);
    a.o_iterations =
        command.add_option("--iterations", r.max_iterations, "relaxation iterations, at most")
            ->check(CLI::Range(0, 100000))
            ->type_name("K")
            ->capture_default_str()
            ->group(kPipelineGroup);
    command.add_option("--smoothing-weight", r.smoothing_weight, "weight of the averaging term")
        ->check(kFinite)
        ->type_name("W")
        ->capture_default_str()
        ->group(kPipelineGroup);
    command.add_option("--gradient-weight", r.gradient_weight, "weight of the gradient term")
        ->check(kFinite)
        ->type_name("W")
        ->capture_default_str()
        ->group(kPipelineGroup);
    add_name_option(command, "--schedule", r.schedule,
                    "both terms at once, or smoothing first, ending with the gradient term")
        ->group(kPipelineGroup);
    add_name_option(command, "--constraint", r.constraint, "how a move is kept inside its cell")
        ->group(kPipelineGroup);
    add_name_option(command, "--gradient", r.gradient, "gradient of the grey values")
        ->group(kPipelineGroup);
    command.add_option("--sigma", r.gradient_sigma, "sigma of --gradient gaussian, in voxels")
        ->check(CLI::PositiveNumber)
        ->type_name("S")
        ->capture_default_str()
        ->group(kPipelineGroup);
    a.o_epsilon =
        command.add_option("--epsilon", r.epsilon, "stop when the largest move is under E voxels")
            ->check(CLI::NonNegativeNumber)
            ->type_name("E")
            ->capture_default_str()
            ->group(kPipelineGroup);
    add_name_option(command, "--triangulation", r.triangulation, "how the quads are split")
        ->group(kPipelineGroup);
    command
        .add_option("--guard", r.keep_valid,
                    "refuse moves that make the mesh self-intersect or add slivers")
        ->type_name("on|off")
        ->default_str("on")
        ->group(kPipelineGroup);
}

PipelineOptions pipeline_options(const PipelineArgs& a, float iso, InsideIs inside) {
    PipelineOptions o;
    o.iso = iso;
    o.inside = inside;
    o.relax = a.relax;
    if (a.mode) o.relax.mode = *a.mode;
    o.relax.iso = iso;
    return o;
}

namespace {

// A whole number of triangles >= 1, as text; empty when it is not one.
std::optional<std::size_t> parse_count(const std::string& text) {
    if (text.empty() || text.size() > 12 ||
        !std::all_of(text.begin(), text.end(), [](unsigned char c) { return std::isdigit(c); }))
        return std::nullopt;
    const auto n = std::size_t(std::stoull(text));
    if (n == 0) return std::nullopt;
    return n;
}

} // namespace

void add_equal_count_option(CLI::App& command, EqualCountArgs& args) {
    args.option =
        command
            .add_option("--equal-count", args.value,
                        "reduce every mesh to N triangles (without N: to the smallest count "
                        "among them) with meshoptimizer's simplifier, and measure them again")
            ->expected(0, 1)
            ->check(CLI::Validator(
                [](std::string& text) -> std::string {
                    if (text.empty() || parse_count(text)) return {};
                    return "must be a whole number of triangles >= 1, not '" + text + "'";
                },
                ""))
            ->type_name("[N]")
            ->group("Compactness");
}

std::optional<std::optional<std::size_t>> equal_count_request(const EqualCountArgs& args) {
    if (!args.option || args.option->count() == 0) return std::nullopt;
    return std::optional<std::optional<std::size_t>>(parse_count(args.value));
}

void check_output(const std::string& path, std::initializer_list<const char*> extensions) {
    std::string lower = path;
    std::transform(lower.begin(), lower.end(), lower.begin(),
                   [](unsigned char c) { return char(std::tolower(c)); });
    const bool known = std::any_of(extensions.begin(), extensions.end(), [&](const char* ext) {
        const std::string e(ext);
        return lower.size() > e.size() && lower.compare(lower.size() - e.size(), e.size(), e) == 0;
    });
    if (!known) {
        std::string list;
        for (const char* ext : extensions) list += (list.empty() ? "" : ", ") + std::string(ext);
        throw InputError(path + ": unknown extension (use " + list + ")");
    }
    try {
        check_writable(path);
    } catch (const std::runtime_error& e) {
        throw InputError(e.what());
    }
}

CLI::Option* add_json_option(CLI::App& command, std::string& path) {
    return command
        .add_option("--json", path,
                    "also write the metrics as JSON to FILE (.json), or to standard output "
                    "with '-' (the table then goes to standard error)")
        ->type_name("FILE|-")
        ->group("Output");
}

} // namespace snert::cli
