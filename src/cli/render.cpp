// snert render: the side-by-side comparison (or one of its views) drawn offscreen into a PNG,
// with no window and no display: OSMesa or EGL (surfaceless), see render/context.h.
#ifdef SNERT_HAVE_RENDER

#include <cmath>
#include <iostream>
#include <memory>
#include <span>

#include "commands.h"
#include "options.h"
#include "progress_line.h"
#include "render/context.h"
#include "render/figure.h"
#include "render/image.h"
#include "render/panels.h"
#include "report.h"

namespace snert::cli {

namespace {

// What the picture holds: the whole figure or its views (render::FigureLayout), or one view.
enum class RenderLayout { Comparison, Views, Mc, Net };
constexpr Named<RenderLayout> kRenderLayouts[] = {
    {RenderLayout::Comparison, "comparison", "views, histograms and metrics"},
    {RenderLayout::Views, "views", "the two views only"},
    {RenderLayout::Mc, "mc", "the Marching Cubes view only"},
    {RenderLayout::Net, "net", "the net's view only"},
};
std::span<const Named<RenderLayout>> name_table(RenderLayout) {
    return kRenderLayouts;
}

render::FigureLayout figure_layout(RenderLayout layout) {
    return layout == RenderLayout::Comparison ? render::FigureLayout::Comparison
                                              : render::FigureLayout::Views;
}

// The net's title: the method, and the iteration when one was asked for.
std::string net_title(Method method, std::optional<int> iteration) {
    std::string name(label_of(method));
    if (!iteration) return name;
    if (*iteration == 0) return name + ", initial net";
    return name + ", iteration " + std::to_string(*iteration);
}

std::string caption(const Source& source, float iso, InsideIs inside,
                    const PipelineOptions& options, Method net, bool exact_iterations,
                    const Measured& m) {
    const glm::ivec3 d = read_dims(source);
    std::string text = m.name + "  \xC2\xB7  " + std::to_string(d.x) + "\xC3\x97" +
                       std::to_string(d.y) + "\xC3\x97" + std::to_string(d.z) + " samples";
    text += "  \xC2\xB7  iso " + format_number(iso);
    if (inside == InsideIs::Below) text += " (inside below)";
    text += "  \xC2\xB7  " + std::string(label_of(net)) + " relaxation, ";
    if (exact_iterations)
        text += std::to_string(options.relax.max_iterations) + " iterations";
    else
        text += "at most " + std::to_string(options.relax.max_iterations) + " iterations";
    // What the table's accuracies are distances to (in voxels).
    text += m.reference.analytic ? "  \xC2\xB7  accuracy: voxels to the exact surface"
                                 : "  \xC2\xB7  accuracy: first-order voxels to the iso-surface";
    return text;
}

} // namespace

Runner add_render(CLI::App& app) {
    struct Args {
        InputArgs input;
        PipelineArgs pipeline;
        std::string out;
        render::FigureOptions figure;
        RenderLayout layout = RenderLayout::Comparison;
        int iteration = 0;
        CLI::Option* o_iteration = nullptr;
        std::string gl = "auto";
        bool no_caption = false;
        bool quiet = false;
    };
    auto args = std::make_shared<Args>();
    CLI::App* command = app.add_subcommand(
        "render", "draw the side-by-side comparison into a PNG, without a window");
    command->footer("Draws Marching Cubes (left) and the relaxed SurfaceNet (right) under one "
                    "camera, with the quality histograms and the metrics table. Needs no "
                    "display.\n");
    add_input_options(*command, args->input);
    add_pipeline_options(*command, args->pipeline);
    add_quiet_option(*command, args->quiet);
    render::FigureOptions& f = args->figure;
    const char* group = "Picture";
    command->add_option("--out", args->out, "the picture to write (replaced atomically)")
        ->required()
        ->type_name("FILE.png")
        ->group(group);
    command->add_option("--width", f.width, "image width in pixels")
        ->check(CLI::Range(16, 8192))
        ->type_name("W")
        ->capture_default_str()
        ->group(group);
    command->add_option("--height", f.height, "image height in pixels")
        ->check(CLI::Range(16, 8192))
        ->type_name("H")
        ->capture_default_str()
        ->group(group);
    add_name_option(*command, "--view", f.view, "camera preset framing the meshes")->group(group);
    command->add_option("--zoom", f.zoom, "move the camera Z times closer, for close-ups")
        ->check(CLI::PositiveNumber)
        ->type_name("Z")
        ->capture_default_str()
        ->group(group);
    add_name_option(*command, "--shading", f.style.shading,
                    "facets, smooth surface, or colour by triangle quality (smallest / largest "
                    "angle)")
        ->group(group);
    command
        ->add_option("--threshold", f.style.quality_threshold,
                     "quality shading: triangles with quality under Q in red")
        ->check(CLI::Range(0.0, 1.0))
        ->type_name("Q")
        ->capture_default_str()
        ->group(group);
    command->add_flag("--wireframe", f.style.wireframe, "draw the triangle edges over the surface")
        ->group(group);
    add_name_option(*command, "--layout", args->layout,
                    "the whole figure, the two views only, or a single view")
        ->group(group);
    args->o_iteration =
        command
            ->add_option("--iteration", args->iteration,
                         "show the net after K relaxation iterations (0: the initial net); "
                         "sets --iterations K and --epsilon 0")
            ->check(CLI::Range(0, 100000))
            ->type_name("K")
            ->group(group);
    args->o_iteration->excludes(args->pipeline.o_iterations);
    args->o_iteration->excludes(args->pipeline.o_epsilon);
    std::vector<std::string> backends = render::offscreen_backends();
    backends.push_back("auto");
    CLI::Validator backend = CLI::IsMember(backends);
    backend.description("");
    std::string backend_names;
    for (const std::string& b : backends) backend_names += (backend_names.empty() ? "" : "|") + b;
    command->add_option("--gl", args->gl, "offscreen OpenGL (auto: OSMesa, else EGL)")
        ->check(backend)
        ->type_name(backend_names)
        ->capture_default_str()
        ->group(group);
    command->add_option("--samples", f.samples, "multisampling: samples per pixel")
        ->check(CLI::Range(1, 16))
        ->type_name("N")
        ->capture_default_str()
        ->group(group);
    command
        ->add_flag("--no-caption", args->no_caption,
                   "leave out the line describing input and parameters")
        ->group(group);

    return [args] {
        // Everything about the picture is checked before any work.
        const InputChoice choice = input_choice(args->input);
        check_output(args->out, {".png"});
        render::FigureOptions figure = args->figure;
        figure.layout = figure_layout(args->layout);
        const bool captioned = !args->no_caption;
        const bool two_views =
            args->layout == RenderLayout::Comparison || args->layout == RenderLayout::Views;
        try {
            render::layout_figure(figure.width, figure.height, two_views ? 2 : 1, figure.layout,
                                  figure.style.shading == render::Shading::Quality, captioned);
        } catch (const std::invalid_argument& e) {
            throw CLI::ValidationError("--width/--height", e.what());
        }
        // Fails early (and clearly) when no offscreen OpenGL is available.
        const std::unique_ptr<render::GlContext> context =
            render::create_offscreen_context(args->gl);

        const ProgressLine progress("render", args->quiet);
        Source source = open_input(choice, progress.stage("reading"));
        const float iso = choice.iso.value_or(source.suggested_iso);
        const InsideIs inside = choice.inside.value_or(source.suggested_inside);
        source = close_border_if_chosen(std::move(source), choice, iso, inside);
        PipelineOptions pipeline = pipeline_options(args->pipeline, iso, inside);
        std::optional<int> iteration;
        if (args->o_iteration->count()) {
            iteration = args->iteration;
            pipeline.relax.max_iterations = args->iteration;
            pipeline.relax.epsilon = 0.0f; // exactly K iterations, however small the moves
        }
        const Method net = method_of(pipeline.relax.mode);
        const Measured m = measured(source, iso);

        std::vector<MethodResult> results;
        if (args->layout != RenderLayout::Net)
            results.push_back(run_source_method(Method::MarchingCubes, source, pipeline, m,
                                                progress.stage("Marching Cubes")));
        if (args->layout != RenderLayout::Mc)
            results.push_back(run_source_method(net, source, pipeline, m,
                                                progress.stage(std::string(label_of(net)))));
        for (const MethodResult& r : results) require_surface(r, m);
        measure_against_marching_cubes(results, *source.volume);

        std::vector<render::FigureMethod> methods;
        methods.reserve(results.size());
        for (const MethodResult& r : results)
            methods.push_back(
                {r.method, r.method == Method::MarchingCubes ? "" : net_title(r.method, iteration),
                 &r.mesh, &r.metrics});
        if (captioned)
            figure.caption = caption(source, iso, inside, pipeline, net, iteration.has_value(), m);
        const render::Image image = render::render_figure(methods, figure);
        render::write_png(args->out, image);
        std::cerr << "wrote " << args->out << ": " << image.width << "x" << image.height << " ("
                  << context->backend() << ")\n";
        return 0;
    };
}

} // namespace snert::cli

#endif // SNERT_HAVE_RENDER
