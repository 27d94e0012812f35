// snert render: the side-by-side comparison (or one of its views) drawn offscreen into a PNG,
// with no window and no display: OSMesa or EGL (surfaceless), see render/context.h.
#ifdef SNERT_HAVE_RENDER

#include <cmath>
#include <iostream>
#include <memory>
#include <span>

#include "commands.h"
#include "core/triangle_distances.h"
#include "compactness_report.h"
#include "io/camera_file.h"
#include "options.h"
#include "progress_line.h"
#include "render/context.h"
#include "render/figure.h"
#include "render/image.h"
#include "render/panels.h"
#include "render_slice.h"
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
        EqualCountArgs equal_count;
        bool quiet = false;
        std::string zoom; // Z, or with --slice X,Y,W,H
        SliceArgs slice;
        float azimuth = 0, elevation = 0, roll = 0, distance = 0;
        std::vector<float> target;
        std::string camera_file;
        CLI::Option *o_azimuth = nullptr, *o_elevation = nullptr, *o_roll = nullptr,
                    *o_distance = nullptr, *o_target = nullptr;
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
    add_equal_count_option(*command, args->equal_count);
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
    command
        ->add_option("--zoom", args->zoom,
                     "move the camera Z times closer, for close-ups; with --slice the part of "
                     "the slice shown, X,Y,W,H in samples")
        ->type_name("Z|X,Y,W,H")
        ->default_str("1")
        ->group(group);
    add_slice_options(*command, args->slice, group);
    add_name_option(*command, "--shading", f.style.shading,
                    "facets, smooth surface, or colour by triangle quality (smallest / largest "
                    "angle)")
        ->group(group);
    add_name_option(*command, "--color-by", f.color_by,
                    "what quality shading and the histograms show: q (smallest / largest "
                    "angle), q60 (smallest angle / 60 degrees), radius-ratio (2 r / R), "
                    "distance-iso (signed first-order distance to the iso-surface, voxels, + "
                    "outside) or distance-other (to the other method's mesh, voxels)")
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
    // A camera by hand (the app's View > Copy camera writes these); each one given replaces
    // the framed camera's, after --view and --zoom.
    args->o_azimuth = command
                          ->add_option("--azimuth", args->azimuth,
                                       "camera: degrees around +z (0 looks from -y, the front)")
                          ->type_name("DEG")
                          ->group(group);
    args->o_elevation =
        command->add_option("--elevation", args->elevation, "camera: degrees above the xy plane")
            ->check(CLI::Range(-90.0, 90.0))
            ->type_name("DEG")
            ->group(group);
    args->o_roll =
        command->add_option("--roll", args->roll, "camera: degrees about the viewing direction")
            ->type_name("DEG")
            ->group(group);
    args->o_target = command
                         ->add_option("--target", args->target,
                                      "camera: the point looked at (world millimetres)")
                         ->delimiter(',')
                         ->expected(3)
                         ->type_name("X,Y,Z")
                         ->group(group);
    args->o_distance =
        command
            ->add_option("--distance", args->distance, "camera: eye to target (world millimetres)")
            ->check(CLI::PositiveNumber)
            ->type_name("D")
            ->group(group);
    command
        ->add_option("--camera", args->camera_file,
                     "camera from a JSON file {azimuth, elevation, roll, target: [x, y, z], "
                     "distance}; the options above override it")
        ->type_name("FILE.json")
        ->group(group);
    command
        ->add_option("--font-scale", f.font_scale,
                     "text size against the default for the image size (1.5: larger labels "
                     "in a small image)")
        ->check(CLI::Range(0.5, 4.0))
        ->type_name("S")
        ->capture_default_str()
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
        if (!args->slice.slice.empty()) {
            SliceRender slice{choice, args->pipeline, args->slice};
            if (!args->zoom.empty()) slice.zoom = parse_slice_zoom(args->zoom);
            if (args->o_iteration->count()) slice.iteration = args->iteration;
            slice.out = args->out;
            slice.width = args->figure.width;
            slice.height = args->figure.height;
            slice.samples = args->figure.samples;
            slice.gl = args->gl;
            slice.caption = !args->no_caption;
            slice.quiet = args->quiet;
            return run_slice_render(slice);
        }
        if (!args->slice.node.empty())
            throw CLI::ValidationError("--node", "needs --slice (the node is shown in a slice)");
        render::FigureOptions figure = args->figure;
        if (!args->zoom.empty()) {
            try {
                std::size_t used = 0;
                figure.zoom = std::stof(args->zoom, &used);
                if (used != args->zoom.size()) throw std::invalid_argument("trailing text");
            } catch (const std::exception&) {
                figure.zoom = 0.0f;
            }
            if (!(figure.zoom > 0.0f) || !std::isfinite(figure.zoom))
                throw CLI::ValidationError("--zoom", "'" + args->zoom +
                                                         "' is not a positive number (X,Y,W,H "
                                                         "needs --slice)");
        }
        figure.layout = figure_layout(args->layout);
        if (!args->camera_file.empty()) {
            try {
                figure.camera = read_camera_file(args->camera_file);
            } catch (const std::runtime_error& e) {
                throw CLI::ValidationError("--camera", e.what());
            }
        }
        if (args->o_azimuth->count()) figure.camera.azimuth = args->azimuth;
        if (args->o_elevation->count()) figure.camera.elevation = args->elevation;
        if (args->o_roll->count()) figure.camera.roll = args->roll;
        if (args->o_distance->count()) figure.camera.distance = args->distance;
        if (args->o_target->count())
            figure.camera.target = glm::vec3(args->target[0], args->target[1], args->target[2]);
        const bool captioned = !args->no_caption;
        const bool two_views =
            args->layout == RenderLayout::Comparison || args->layout == RenderLayout::Views;
        try {
            render::layout_figure(figure.width, figure.height, two_views ? 2 : 1, figure.layout,
                                  figure.style.shading == render::Shading::Quality, captioned,
                                  figure.font_scale);
        } catch (const std::invalid_argument& e) {
            throw CLI::ValidationError("--width/--height", e.what());
        }
        if (figure.color_by == ShapeMeasure::DistanceOther && !two_views)
            throw CLI::ValidationError("--color-by",
                                       "distance-other needs both meshes (--layout comparison "
                                       "or views)");
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

        std::vector<Method> shown;
        if (args->layout != RenderLayout::Net) shown.push_back(Method::MarchingCubes);
        if (args->layout != RenderLayout::Mc) shown.push_back(net);
        std::vector<MethodResult> results =
            run_compared_methods(shown, source, pipeline, m, [&](Method method) {
                return progress.stage(std::string(label_of(method)));
            });
        std::optional<EqualCountRun> equal;
        if (const auto request = equal_count_request(args->equal_count)) {
            equal = reduce_sources_to_equal_count(results, *request, source, pipeline, m);
            print_equal_count(std::cerr, *equal, results);
        }

        // Colouring by a distance: the values the app's worker computes (pair_distances).
        std::vector<std::vector<float>> distances(results.size());
        if (figure.color_by == ShapeMeasure::DistanceOther) {
            PairDistances pair = pair_distances(figure.color_by, results[0].mesh, results[1].mesh,
                                                *source.volume, iso, inside);
            distances[0] = std::move(pair.first);
            distances[1] = std::move(pair.second);
        } else if (figure.color_by == ShapeMeasure::DistanceIso) {
            for (std::size_t i = 0; i < results.size(); ++i)
                distances[i] = signed_iso_distances(results[i].mesh, *source.volume, iso, inside);
        }
        std::vector<render::FigureMethod> methods;
        methods.reserve(results.size());
        for (std::size_t i = 0; i < results.size(); ++i) {
            const MethodResult& r = results[i];
            methods.push_back(
                {r.method, r.method == Method::MarchingCubes ? "" : net_title(r.method, iteration),
                 &r.mesh, &r.metrics, distances[i]});
        }
        if (captioned) {
            figure.caption = caption(source, iso, inside, pipeline, net, iteration.has_value(), m);
            if (equal)
                figure.caption +=
                    "  \xC2\xB7  reduced to " + std::to_string(equal->target) + " triangles";
        }
        const render::Image image = render::render_figure(methods, figure);
        render::write_png(args->out, image);
        std::cerr << "wrote " << args->out << ": " << image.width << "x" << image.height << " ("
                  << context->backend() << ")\n";
        return 0;
    };
}

} // namespace snert::cli

#endif // SNERT_HAVE_RENDER
