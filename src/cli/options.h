// The command line's options, declared with CLI11 and shared by the subcommands: the input
// (what to open, how to segment it), the comparison pipeline's parameters and the output
// files. Every enum option is parsed through its name table (core/names.h), so the names on
// the command line, in the help, in the JSON and in the app are the same.
//
// Rules between options are declared (needs / excludes) where CLI11 can see them; the rules
// that depend on the input's kind (a phantom or a file) are checked by input_choice() after
// parsing. Both report a CLI::ParseError: a usage error, exit code 2.
#pragma once

#include <functional>
#include <initializer_list>
#include <optional>
#include <string>

#include <CLI/CLI.hpp>

#include "core/names.h"
#include "core/pipeline.h"
#include "io/source.h"

namespace snert::cli {

// "250", "0.5", "1e-04": a number as people write it (printf's %g).
std::string format_number(double value);

// An option whose value is one of the names of E's table (core/names.h); `set` receives the
// parsed value. The help shows the choices; a wrong name is a CLI::ValidationError listing them.
template <class E>
CLI::Option* add_name_option(CLI::App& command, const std::string& flag, std::function<void(E)> set,
                             const std::string& help) {
    const std::string choices = name_choices<E>();
    return command
        .add_option_function<std::string>(
            flag, [set](const std::string& text) { set(*parse_name<E>(text)); }, help)
        ->check(CLI::Validator(
            [](std::string& text) -> std::string {
                if (parse_name<E>(text)) return {};
                return "must be one of " + name_choices<E>() + ", not '" + text + "'";
            },
            ""))
        ->type_name(choices);
}

// The same for a variable holding the default, shown in the help.
template <class E>
CLI::Option* add_name_option(CLI::App& command, const std::string& flag, E& value,
                             const std::string& help) {
    return add_name_option<E>(
               command, flag, [&value](E v) { value = v; }, help)
        ->default_str(std::string(name_of(value)));
}

// ---- Input -------------------------------------------------------------------------------------

// The input options as parsed; see add_input_options.
struct InputArgs {
    std::string input; // VOLUME: phantom:NAME, a volume file, a DICOM folder or a .dcm
    int size = 64;
    float iso = 0.0f;
    std::optional<InsideIs> inside;
    std::string raw, raw_type, raw_spacing, raw_endian, series, labels;
    int label = 0;
    bool close_border = false; // --close-border / --no-close-border, when given
    CLI::Option *o_input = nullptr, *o_size = nullptr, *o_iso = nullptr, *o_raw = nullptr,
                *o_raw_type = nullptr, *o_raw_spacing = nullptr, *o_raw_endian = nullptr,
                *o_series = nullptr, *o_labels = nullptr, *o_label = nullptr,
                *o_close_border = nullptr;
    std::string isotropic; // --isotropic [MM]: the edge as typed, empty: the smallest spacing
    CLI::Option* o_isotropic = nullptr;
};

// VOLUME (required unless `optional_input`), --size, --iso, --inside, --raw, --raw-type,
// --raw-spacing, --raw-endian, --series, --labels, --label, --isotropic, --close-border: what
// every command that reads a volume accepts, the app included.
void add_input_options(CLI::App& command, InputArgs& args, bool optional_input = false);

// --isotropic [MM] into `text` (empty: the smallest spacing); add_input_options declares it,
// and bench beside its --volume. isotropic_edge: what it asks for (empty: not given).
CLI::Option* add_isotropic_option(CLI::App& command, std::string& text);
std::optional<float> isotropic_edge(const CLI::Option* option, const std::string& text);

// What the input options ask for.
struct InputChoice {
    SourceSpec spec;
    std::optional<float> iso;         // --iso; empty: the source's suggestion
    std::optional<InsideIs> inside;   // --inside; empty: the source's suggestion
    std::optional<bool> close_border; // --close-border / --no-close-border; empty: the default
};

// Whether the surfaces are closed at the volume border: --close-border or --no-close-border
// where given, else on for a label map and off for grey values (as 3D Slicer pads a label map).
bool closes_border(const InputChoice& choice);

// The opened input, closed at the border (io/source.h's close_border) where closes_border()
// says so, at the iso and inside rule chosen; else `source` as it is (nothing copied).
Source close_border_if_chosen(Source source, const InputChoice& choice, float iso, InsideIs inside);

// After parsing. Throws CLI::ValidationError for options that do not apply to the input: a
// phantom with --raw, --series, --labels or --isotropic (its voxels are cubic already), a file
// with --size.
InputChoice input_choice(const InputArgs& args);

// Opens the input (open_source). What it throws about the input (a missing or bad file, an
// unknown phantom, a label that does not occur) becomes an InputError. Writes to stderr the
// file's description, the loader's warnings and, when --iso is not given, which iso was chosen
// and why.
Source open_input(const InputChoice& choice, const Progress& progress = {});

// ---- Pipeline ----------------------------------------------------------------------------------

// The pipeline options as parsed; see add_pipeline_options.
struct PipelineArgs {
    RelaxOptions relax;
    std::optional<RelaxMode> mode; // --mode; empty: the command's default
    CLI::Option *o_mode = nullptr, *o_iterations = nullptr, *o_epsilon = nullptr;
};

// --mode (unless `with_mode` is false), --iterations, --smoothing-weight, --gradient-weight,
// --schedule, --constraint, --gradient, --sigma, --epsilon, --triangulation, --guard.
void add_pipeline_options(CLI::App& command, PipelineArgs& args, bool with_mode = true);

// The pipeline's options for the chosen iso and inside rule.
PipelineOptions pipeline_options(const PipelineArgs& args, float iso, InsideIs inside);

// ---- Equal triangle count ---------------------------------------------------------------------

// --equal-count [N], as parsed: the option and its text ("" when given without N).
struct EqualCountArgs {
    std::string value;
    CLI::Option* option = nullptr;
};

// --equal-count [N]: reduce the meshes to N triangles, or without N to the smallest count among
// them (core/compactness.h). Without N, VOLUME must come first or N be given as --equal-count=N.
void add_equal_count_option(CLI::App& command, EqualCountArgs& args);

// Empty when --equal-count is not given; else the count asked for (empty: the smallest).
std::optional<std::optional<std::size_t>> equal_count_request(const EqualCountArgs& args);

// ---- Outputs -----------------------------------------------------------------------------------

// Checks an output path before any work: its extension is one of `extensions` (".png",
// ".stl", ...; compared without regard to case) and its folder exists and is writable
// (check_writable). Throws InputError naming the path.
void check_output(const std::string& path, std::initializer_list<const char*> extensions);

// --json FILE|- : where `path` is "-" the JSON goes to standard output.
CLI::Option* add_json_option(CLI::App& command, std::string& path);

} // namespace snert::cli
