// snert gui: the interactive app (src/app) in a window; also what `snert` alone runs.
#ifdef SNERT_HAVE_APP

#include <algorithm>
#include <iostream>

#include "app/path_completion.h"
#include "app/settings.h"
#include "app/window.h"
#include "args.h"
#include "commands.h"
#include "core/phantom.h"

namespace snert::cli {

namespace {

const char* kHelp = R"(usage: snert gui [VOLUME|phantom:NAME] [options]

Opens the app: Marching Cubes and the relaxed SurfaceNet side by side, the parameters, the
relaxation's iterations to step through. Without an input it opens the volume of the last
session (the two-spheres phantom the first time). Press F1 in the app for its keys.

  --size N            phantom grid size (default: the last one used, 64 the first time)
  --window WxH        window size in pixels (default: the last one used)
  --no-settings       neither read nor write the settings file
                      ($XDG_CONFIG_HOME/snert/settings.ini or ~/.config/snert/settings.ini)
  --screenshot FILE   automation: draw --frames frames once the first result is complete,
                      save the whole window as a PNG and exit (implies --no-settings)
  --frames N          frames drawn before the screenshot (default 10)
)";

// "1280x800" -> {1280, 800}.
std::pair<int, int> parse_window_size(const std::string& text) {
    const auto x = text.find('x');
    try {
        if (x != std::string::npos) {
            std::size_t used_w = 0, used_h = 0;
            const int w = std::stoi(text.substr(0, x), &used_w);
            const int h = std::stoi(text.substr(x + 1), &used_h);
            if (used_w == x && used_h == text.size() - x - 1 && w >= 320 && h >= 240 &&
                w <= 16384 && h <= 16384)
                return {w, h};
        }
    } catch (const std::exception&) {
    }
    throw UsageError("--window wants WIDTHxHEIGHT with at least 320x240, not '" + text + "'");
}

} // namespace

int run_gui(const std::vector<std::string>& argv) {
    const Args args(argv, {"size", "window", "screenshot", "frames"}, {"help", "no-settings"});
    if (args.flag("help")) {
        std::cout << kHelp;
        return 0;
    }
    if (args.positional().size() > 1)
        throw UsageError("unexpected argument '" + args.positional()[1] + "'");
    app::WindowOptions options;
    if (!args.positional().empty()) {
        const std::string input = app::expand_home(args.positional().front());
        const std::string_view phantom = phantom_spec_name(input);
        if (!phantom.empty()) {
            const auto names = phantom_names();
            if (std::find(names.begin(), names.end(), phantom) == names.end())
                throw UsageError("unknown phantom '" + std::string(phantom) + "'");
        } else if (!app::openable_path(input)) {
            throw std::runtime_error(input + ": no such file or folder");
        }
        options.app.input = input;
    }
    if (args.has("size")) options.app.phantom_size = args.integer("size", 64, 8, 1024);
    if (auto size = args.value("window"))
        std::tie(options.width, options.height) = parse_window_size(*size);
    options.screenshot_path = args.value_or("screenshot", "");
    options.frames = args.integer("frames", 10, 1, 100000);
    const bool use_settings = !args.flag("no-settings") && options.screenshot_path.empty();
    if (use_settings) options.app.settings_path = app::default_settings_path();
    options.save_settings = use_settings;
    try {
        return app::run_window(options);
    } catch (const app::NoWindow& e) {
        // No display is not bad input: say so and what works instead.
        std::cerr << "snert gui: " << e.what() << "\n";
        return 1;
    }
}

} // namespace snert::cli

#endif // SNERT_HAVE_APP
