#include "input.h"

#include <stdexcept>

#include "core/phantom.h"
#include "input_file.h"

namespace snert::cli {

std::set<std::string> input_options() {
    std::set<std::string> names = {"size", "iso", "inside", "labels", "label"};
    for (const auto& n : file_input_options()) names.insert(n);
    return names;
}

std::set<std::string> input_switches() {
    return {"help"};
}

Input load_input(const Args& args) {
    if (args.positional().empty())
        throw UsageError("missing input: give phantom:NAME or a volume file");
    if (args.positional().size() > 1)
        throw UsageError("unexpected argument '" + args.positional()[1] + "'");
    const std::string spec = args.positional().front();
    Input input;
    input.name = spec;
    input.inside = args.choice("inside", "above", {"above", "below"}) == "above" ? InsideIs::Above
                                                                                 : InsideIs::Below;
    if (const std::string_view name = phantom_spec_name(spec); !name.empty()) {
        Phantom phantom = make_phantom(name, args.integer("size", 64, 8, 1024));
        input.volume = std::move(phantom.volume);
        input.iso = args.number("iso", phantom.iso);
        input.reference = phantom.reference_distance;
        input.analytic_reference = true;
        input.reference_volume = phantom.reference_volume;
        if (args.has("labels")) throw UsageError("--labels needs a volume file, not a phantom");
        return input;
    }
    if (args.has("size")) throw UsageError("--size applies to phantoms only");
    load_file_input(spec, args, input);
    return input;
}

std::set<std::string> pipeline_option_names() {
    return {
        "mode",     "iterations", "smoothing-weight", "gradient-weight", "schedule", "constraint",
        "gradient", "sigma",      "epsilon",          "triangulation",   "guard"};
}

PipelineOptions pipeline_options(const Args& args, const Input& input) {
    PipelineOptions o;
    o.iso = input.iso;
    o.inside = input.inside;
    RelaxOptions& r = o.relax;
    const std::string mode = args.choice("mode", "snert", {"sna", "gradient", "snert"});
    r.mode = mode == "sna"        ? RelaxMode::Averaging
             : mode == "gradient" ? RelaxMode::Gradient
                                  : RelaxMode::Snert;
    r.max_iterations = args.integer("iterations", r.max_iterations, 0, 100000);
    r.smoothing_weight = args.number("smoothing-weight", r.smoothing_weight);
    r.gradient_weight = args.number("gradient-weight", r.gradient_weight);
    r.schedule = args.choice("schedule", "simultaneous", {"simultaneous", "smoothing-first"}) ==
                         "simultaneous"
                     ? Schedule::Simultaneous
                     : Schedule::SmoothingFirst;
    r.constraint = args.choice("constraint", "raybox", {"raybox", "clip"}) == "raybox"
                       ? Constraint::RayBox
                       : Constraint::Clip;
    r.gradient = args.choice("gradient", "central", {"central", "gaussian"}) == "central"
                     ? GradientMethod::Central
                     : GradientMethod::Gaussian;
    r.gradient_sigma = args.number("sigma", r.gradient_sigma);
    if (!(r.gradient_sigma > 0.0f)) throw UsageError("--sigma must be positive");
    r.keep_valid = args.choice("guard", "on", {"on", "off"}) == "on";
    r.epsilon = args.number("epsilon", r.epsilon);
    if (r.epsilon < 0.0f) throw UsageError("--epsilon must not be negative");
    r.triangulation = args.choice("triangulation", "shorter", {"shorter", "delaunay"}) == "shorter"
                          ? TriangulationRule::ShorterDiagonal
                          : TriangulationRule::Delaunay;
    r.iso = o.iso;
    return o;
}

} // namespace snert::cli
