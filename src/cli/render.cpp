// snert render: the side-by-side comparison (or one of its views) drawn offscreen into a PNG,
// with no window and no display: OSMesa or EGL (surfaceless), see render/context.h.
#ifdef SNERT_HAVE_RENDER

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>

#include "commands.h"
#include "core/phantom.h"
#include "methods.h"
#include "render/context.h"
#include "render/figure.h"
#include "render/image.h"
#include "render/panels.h"

namespace snert::cli {

namespace {

const char* kHelp = R"(usage: snert render VOLUME|phantom:NAME --out FILE.png [options]

Draws Marching Cubes (left) and the relaxed SurfaceNet (right) under one camera, with the
quality histograms and the metrics table, into a PNG. Needs no display.

  --out FILE.png       the picture to write (replaced atomically)
  --width W --height H image size in pixels (default 1200 x 900)
  --view front|side|top|iso      camera preset framing the meshes (default iso)
  --zoom Z             move the camera Z times closer, for close-ups (default 1)
  --shading flat|smooth|quality  facets, smooth surface, or colour by triangle quality
                       (smallest / largest angle; default smooth)
  --threshold Q        quality shading: triangles with quality under Q in red (default 0.25)
  --wireframe          draw the triangle edges over the surface
  --layout comparison|views|mc|net   the whole figure (default), the two views only, or a
                       single view
  --iteration K        show the net after K relaxation iterations (0: the initial net);
                       sets --iterations K and --epsilon 0
  --gl osmesa|egl|auto offscreen OpenGL (default auto: OSMesa, else EGL)
  --samples N          multisampling, 1 to 16 samples per pixel (default 4)
  --no-caption         leave out the line describing input and parameters

Input and pipeline options are those of `snert compare` (--size, --iso, --inside, --labels,
--label, --mode sna|gradient|snert, --iterations, --smoothing-weight, ...).
)";

bool ends_with_png(const std::string& path) {
    if (path.size() < 4) return false;
    std::string tail = path.substr(path.size() - 4);
    for (char& c : tail) c = char(std::tolower(static_cast<unsigned char>(c)));
    return tail == ".png";
}

std::string format_number(double value) {
    char text[32];
    std::snprintf(text, sizeof text, "%g", value);
    return text;
}

// The net's title: the method, and the iteration when one was asked for.
std::string net_title(Method method, const Args& args, int iteration) {
    std::string name(label_of(method));
    if (!args.has("iteration")) return name;
    if (iteration == 0) return name + ", initial net";
    return name + ", iteration " + std::to_string(iteration);
}

std::string caption(const Input& input, const PipelineOptions& options, Method net,
                    const Args& args) {
    const glm::ivec3 d = input.volume.dims;
    std::string text = input.name + "  \xC2\xB7  " + std::to_string(d.x) + "\xC3\x97" +
                       std::to_string(d.y) + "\xC3\x97" + std::to_string(d.z) + " samples";
    text += "  \xC2\xB7  iso " + format_number(input.iso);
    if (input.inside == InsideIs::Below) text += " (inside below)";
    text += "  \xC2\xB7  " + std::string(label_of(net)) + " relaxation, ";
    if (args.has("iteration"))
        text += std::to_string(options.relax.max_iterations) + " iterations";
    else
        text += "at most " + std::to_string(options.relax.max_iterations) + " iterations";
    // What the table's accuracies are distances to (in voxels).
    text += input.analytic_reference
                ? "  \xC2\xB7  accuracy: voxels to the exact surface"
                : "  \xC2\xB7  accuracy: first-order voxels to the iso-surface";
    return text;
}

} // namespace

int run_render(const std::vector<std::string>& argv) {
    std::set<std::string> options = input_options();
    for (const auto& n : pipeline_option_names()) options.insert(n);
    for (const char* n : {"out", "width", "height", "view", "zoom", "shading", "threshold",
                          "layout", "iteration", "gl", "samples"})
        options.insert(n);
    std::set<std::string> switches = input_switches();
    switches.insert("wireframe");
    switches.insert("no-caption");
    const Args args(argv, options, switches);
    if (args.flag("help")) {
        std::cout << kHelp;
        return 0;
    }

    // Everything about the picture is checked before any work.
    const auto out = args.value("out");
    if (!out) throw UsageError("missing --out FILE.png");
    if (!ends_with_png(*out)) throw UsageError("--out must name a .png file, not '" + *out + "'");
    const std::filesystem::path folder = std::filesystem::path(*out).parent_path();
    if (!folder.empty() && !std::filesystem::is_directory(folder))
        throw std::runtime_error(*out + ": the folder " + folder.string() + " does not exist");
    render::FigureOptions figure;
    figure.width = args.integer("width", 1200, 16, 8192);
    figure.height = args.integer("height", 900, 16, 8192);
    figure.view =
        *render::parse_view_preset(args.choice("view", "iso", {"front", "side", "top", "iso"}));
    figure.zoom = args.number("zoom", 1.0f);
    if (!(figure.zoom > 0.0f) || !std::isfinite(figure.zoom))
        throw UsageError("--zoom must be a positive number");
    figure.style.shading =
        *render::parse_shading(args.choice("shading", "smooth", {"flat", "smooth", "quality"}));
    figure.style.quality_threshold = args.number("threshold", 0.25f);
    if (!(figure.style.quality_threshold >= 0.0f && figure.style.quality_threshold <= 1.0f))
        throw UsageError("--threshold must be in [0, 1]");
    figure.style.wireframe = args.flag("wireframe");
    figure.samples = args.integer("samples", 4, 1, 16);
    const std::string layout =
        args.choice("layout", "comparison", {"comparison", "views", "mc", "net"});
    figure.layout =
        layout == "comparison" ? render::FigureLayout::Comparison : render::FigureLayout::Views;
    const std::string gl = args.choice("gl", "auto", {"osmesa", "egl", "auto"});
    const int iteration = args.integer("iteration", 0, 0, 100000);
    if (args.has("iteration") && args.has("iterations"))
        throw UsageError("give --iteration or --iterations, not both");
    if (args.has("iteration") && args.has("epsilon"))
        throw UsageError("--iteration sets --epsilon 0; give one of them");
    const bool captioned = !args.flag("no-caption");
    // An image too small for the layout is a usage error; found before any work.
    render::layout_figure(figure.width, figure.height,
                          layout == "comparison" || layout == "views" ? 2 : 1, figure.layout,
                          figure.style.shading == render::Shading::Quality, captioned);
    // Fails early (and clearly) when no offscreen OpenGL is available.
    const std::unique_ptr<render::GlContext> context = render::create_offscreen_context(gl);

    const Input input = load_input(args);
    PipelineOptions pipeline = pipeline_options(args, input);
    if (args.has("iteration")) {
        pipeline.relax.max_iterations = iteration;
        pipeline.relax.epsilon = 0.0f; // exactly K iterations, however small the moves
    }
    const Method net = method_of(pipeline.relax.mode);

    std::vector<MethodResult> results;
    if (layout != "net") results.push_back(run_method(input, pipeline, Method::MarchingCubes));
    if (layout != "mc") results.push_back(run_method(input, pipeline, net));
    for (const MethodResult& r : results) require_surface(r, input);

    std::vector<render::FigureMethod> methods;
    methods.reserve(results.size());
    for (const MethodResult& r : results)
        methods.push_back({r.method,
                           r.method == Method::MarchingCubes ? "" : net_title(r.method, args, iteration),
                           &r.mesh, &r.metrics});
    if (captioned) figure.caption = caption(input, pipeline, net, args);
    const render::Image image = render::render_figure(methods, figure);
    render::write_png(*out, image);
    std::cerr << "wrote " << *out << ": " << image.width << "x" << image.height << " ("
              << context->backend() << ")\n";
    return 0;
}

} // namespace snert::cli

#endif // SNERT_HAVE_RENDER
