// snert gui: the interactive app (src/app) in a window; also what `snert` alone runs. It takes
// the input and pipeline options of the other commands and hands them to the app as they were
// parsed (app::AppOptions); what is not given stays the app's saved choice.
#ifdef SNERT_HAVE_APP

#include <algorithm>
#include <iostream>
#include <memory>

#include "app/path_completion.h"
#include "app/settings.h"
#include "app/window.h"
#include "commands.h"
#include "core/input_error.h"
#include "core/phantom.h"
#include "options.h"

namespace snert::cli {

namespace {

// "1280x800" -> {1280, 800}; an error message for a CLI11 validator, or empty.
std::string parse_window_size(const std::string& text, std::pair<int, int>* size) {
    const auto x = text.find('x');
    try {
        if (x != std::string::npos) {
            std::size_t used_w = 0, used_h = 0;
            const int w = std::stoi(text.substr(0, x), &used_w);
            const int h = std::stoi(text.substr(x + 1), &used_h);
            if (used_w == x && used_h == text.size() - x - 1 && w >= 320 && h >= 240 &&
                w <= 16384 && h <= 16384) {
                if (size) *size = {w, h};
                return {};
            }
        }
    } catch (const std::exception&) {
    }
    return "wants WIDTHxHEIGHT with at least 320x240, not '" + text + "'";
}

struct GuiArgs {
    InputArgs input;
    PipelineArgs pipeline;
    std::string window, screenshot;
    int frames = 10;
    bool no_settings = false;
    bool stats = false;
    CLI::App* command = nullptr;
};

// Whether any relaxation option was given (else the app keeps its saved ones).
bool pipeline_given(const GuiArgs& args) {
    for (const CLI::Option* o : args.command->get_options())
        if (o->get_group() == args.pipeline.o_iterations->get_group() && o->count() > 0)
            return true;
    return false;
}

// The relaxation of the app's settings with the options given on the command line put over it:
// an option not given keeps the last session's choice.
RelaxOptions given_over(RelaxOptions relax, const GuiArgs& args) {
    const RelaxOptions& given = args.pipeline.relax;
    struct Field {
        const char* flag;
        void (*copy)(RelaxOptions& to, const RelaxOptions& from);
    };
    static constexpr Field kFields[] = {
        {"--iterations",
         [](RelaxOptions& t, const RelaxOptions& f) { t.max_iterations = f.max_iterations; }},
        {"--smoothing-weight",
         [](RelaxOptions& t, const RelaxOptions& f) { t.smoothing_weight = f.smoothing_weight; }},
        {"--gradient-weight",
         [](RelaxOptions& t, const RelaxOptions& f) { t.gradient_weight = f.gradient_weight; }},
        {"--schedule", [](RelaxOptions& t, const RelaxOptions& f) { t.schedule = f.schedule; }},
        {"--constraint",
         [](RelaxOptions& t, const RelaxOptions& f) { t.constraint = f.constraint; }},
        {"--gradient", [](RelaxOptions& t, const RelaxOptions& f) { t.gradient = f.gradient; }},
        {"--sigma",
         [](RelaxOptions& t, const RelaxOptions& f) { t.gradient_sigma = f.gradient_sigma; }},
        {"--epsilon", [](RelaxOptions& t, const RelaxOptions& f) { t.epsilon = f.epsilon; }},
        {"--triangulation",
         [](RelaxOptions& t, const RelaxOptions& f) { t.triangulation = f.triangulation; }},
        {"--guard", [](RelaxOptions& t, const RelaxOptions& f) { t.keep_valid = f.keep_valid; }},
    };
    for (const Field& field : kFields)
        if (args.command->count(field.flag) > 0) field.copy(relax, given);
    if (args.pipeline.mode) relax.mode = *args.pipeline.mode;
    return relax;
}

// The parsed command line as the app's options.
app::WindowOptions window_options(const GuiArgs& args) {
    app::WindowOptions options;
    InputChoice choice = input_choice(args.input);
    if (!choice.spec.input.empty()) {
        choice.spec.input = app::expand_home(choice.spec.input);
        const std::string_view phantom = phantom_spec_name(choice.spec.input);
        if (!phantom.empty()) {
            const auto names = phantom_names();
            if (std::find(names.begin(), names.end(), phantom) == names.end())
                throw InputError("unknown phantom '" + std::string(phantom) + "'");
        } else if (!app::openable_path(choice.spec.input)) {
            throw InputError(choice.spec.input + ": no such file or folder");
        }
        options.app.source = choice.spec;
    } else if (args.input.o_size->count()) {
        throw CLI::ValidationError("--size", "needs a phantom:NAME to apply to");
    }
    options.app.iso = choice.iso;
    options.app.inside = choice.inside;
    options.app.close_border = choice.close_border;
    const bool use_settings = !args.no_settings && args.screenshot.empty() && !args.stats;
    if (use_settings) options.app.settings_path = app::default_settings_path();
    options.save_settings = use_settings;
    if (pipeline_given(args)) {
        PipelineOptions pipeline = pipeline_options(args.pipeline, choice.iso.value_or(0.0f),
                                                    choice.inside.value_or(InsideIs::Above));
        const app::Parameters saved = app::load_settings(options.app.settings_path).parameters;
        RelaxOptions relax = saved.relax;
        relax.triangulation = saved.triangulation;
        pipeline.relax = given_over(relax, args);
        options.app.pipeline = pipeline;
    }
    if (!args.window.empty()) {
        std::pair<int, int> size;
        parse_window_size(args.window, &size);
        options.width = size.first;
        options.height = size.second;
    }
    options.screenshot_path = args.screenshot;
    options.frames = args.frames;
    options.stats = args.stats;
    return options;
}

} // namespace

Runner add_gui(CLI::App& app) {
    auto args = std::make_shared<GuiArgs>();
    CLI::App* command =
        app.add_subcommand("gui", "open the interactive app (also: snert with no command)");
    args->command = command;
    command->footer(
        "Opens the app: Marching Cubes and the relaxed SurfaceNet side by side, the "
        "parameters, the relaxation's iterations to step through. Without VOLUME it opens the "
        "volume of the last session (the two-spheres phantom the first time); options not "
        "given keep the last session's choices. Press F1 in the app for its keys.\n");
    add_input_options(*command, args->input, true);
    add_pipeline_options(*command, args->pipeline);
    const char* group = "Window";
    command->add_option("--window", args->window, "window size in pixels (default: the last one)")
        ->check(
            CLI::Validator([](std::string& text) { return parse_window_size(text, nullptr); }, ""))
        ->type_name("WxH")
        ->group(group);
    command
        ->add_flag("--no-settings", args->no_settings,
                   "neither read nor write the settings file ($XDG_CONFIG_HOME/snert/"
                   "settings.ini or ~/.config/snert/settings.ini)")
        ->group(group);
    command
        ->add_option("--screenshot", args->screenshot,
                     "automation: draw --frames frames once the first result is complete, save "
                     "the whole window as a PNG and exit (implies --no-settings)")
        ->type_name("FILE.png")
        ->group(group);
    command->add_option("--frames", args->frames, "frames drawn before the screenshot")
        ->check(CLI::Range(1, 100000))
        ->type_name("N")
        ->capture_default_str()
        ->group(group);
    command
        ->add_flag("--stats", args->stats,
                   "automation: run a scripted session (wait for the comparison, step back and "
                   "forth, turn the camera), print its timings as a table and JSON, and exit "
                   "(implies --no-settings)")
        ->group(group);
    return [args] {
        if (!args->screenshot.empty()) check_output(args->screenshot, {".png"});
        const app::WindowOptions options = window_options(*args);
        try {
            return app::run_window(options);
        } catch (const app::NoWindow& e) {
            // No display is not bad input: say so and what works instead.
            std::cerr << "snert gui: " << e.what() << "\n";
            return 1;
        }
    };
}

} // namespace snert::cli

#endif // SNERT_HAVE_APP
