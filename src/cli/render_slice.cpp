// snert render --slice (see render_slice.h): the pipeline runs as for the 3D figure, the net's
// last iteration kept for the node inspector, then the slice view is drawn headless.
#ifdef SNERT_HAVE_RENDER

#include "render_slice.h"

#include <cstdio>
#include <iostream>
#include <memory>
#include <sstream>

#include "core/input_error.h"
#include "core/node_inspection.h"
#include "core/pipeline.h"
#include "core/slice.h"
#include "core/window_level.h"
#include "progress_line.h"
#include "render/context.h"
#include "render/image.h"
#include "render/slice_figure.h"
#include "report.h"

namespace snert::cli {

namespace {

// "A,B,C..." as `count` numbers; empty when the text is not that.
std::vector<float> numbers(const std::string& text, std::size_t count) {
    std::vector<float> out;
    std::stringstream in(text);
    std::string item;
    while (std::getline(in, item, ',')) {
        std::size_t used = 0;
        try {
            out.push_back(std::stof(item, &used));
        } catch (const std::exception&) {
            return {};
        }
        if (used != item.size() || !std::isfinite(out.back())) return {};
    }
    if (out.size() != count) return {};
    return out;
}

SlicePlane parse_plane(const std::string& text) {
    const std::size_t colon = text.find(':');
    const auto axis = parse_name<SliceAxis>(text.substr(0, colon));
    const std::vector<float> index =
        colon == std::string::npos ? std::vector<float>{} : numbers(text.substr(colon + 1), 1);
    if (!axis || index.empty() || index[0] != std::floor(index[0]))
        throw CLI::ValidationError("--slice", "'" + text + "' is not AXIS:INDEX (AXIS: " +
                                                  name_choices<SliceAxis>() + ")");
    return {*axis, int(index[0])};
}

glm::ivec3 parse_cell(const std::string& text) {
    const std::vector<float> v = numbers(text, 3);
    if (v.empty() || v[0] != std::floor(v[0]) || v[1] != std::floor(v[1]) ||
        v[2] != std::floor(v[2]))
        throw CLI::ValidationError("--node", "'" + text + "' is not a cell I,J,K");
    return {int(v[0]), int(v[1]), int(v[2])};
}

std::string number(float v) {
    char text[32];
    std::snprintf(text, sizeof text, "%.4g", double(v));
    return text;
}

} // namespace

void add_slice_options(CLI::App& command, SliceArgs& args, const char* group) {
    command
        .add_option("--slice", args.slice,
                    "draw one slice instead of the 3D views: its grey values, the segmentation "
                    "and both meshes' cross-sections (AXIS: " +
                        name_choices<SliceAxis>() + ")")
        ->type_name("AXIS:INDEX")
        ->group(group);
    command
        .add_option("--node", args.node,
                    "with --slice: take the last move of the node of cell I,J,K apart into the "
                    "paper's vectors (eqs. 1-6)")
        ->type_name("I,J,K")
        ->group(group);
    command.add_option("--window-level", args.window_level, "with --slice: grey window and level")
        ->type_name("W,L")
        ->group(group);
    add_name_option(command, "--preset", args.preset, "with --slice: window/level preset")
        ->group(group);
}

SliceZoom parse_slice_zoom(const std::string& text) {
    const std::vector<float> v = numbers(text, 4);
    if (v.empty() || !(v[2] > 0.0f) || !(v[3] > 0.0f))
        throw CLI::ValidationError("--zoom", "with --slice, '" + text +
                                                 "' is not a window X,Y,W,H of the slice "
                                                 "(W and H positive)");
    return {v[0], v[1], v[2], v[3]};
}

int run_slice_render(const SliceRender& r) {
    const SlicePlane requested = parse_plane(r.slice.slice);
    const std::optional<glm::ivec3> cell =
        r.slice.node.empty() ? std::nullopt : std::optional(parse_cell(r.slice.node));
    std::optional<WindowLevel> wl;
    if (!r.slice.window_level.empty()) {
        const std::vector<float> v = numbers(r.slice.window_level, 2);
        if (v.empty() || !(v[0] > 0.0f))
            throw CLI::ValidationError("--window-level",
                                       "'" + r.slice.window_level + "' is not W,L with W > 0");
        wl = WindowLevel{v[0], v[1]};
    }
    check_output(r.out, {".png"});
    const std::unique_ptr<render::GlContext> context = render::create_offscreen_context(r.gl);

    const ProgressLine progress("render", r.quiet);
    const Source source = open_input(r.input, progress.stage("reading"));
    const Volume& volume = *source.volume;
    const Measured m = measured(source, r.input.iso.value_or(source.suggested_iso));
    const int count = slice_count(volume, requested.axis);
    if (requested.index < 0 || requested.index >= count)
        throw InputError(m.name + ": " + std::string(name_of(requested.axis)) + " slice " +
                         std::to_string(requested.index) + " is outside 0.." +
                         std::to_string(count - 1));
    const float iso = m.iso;
    const InsideIs inside = r.input.inside.value_or(source.suggested_inside);
    PipelineOptions options = pipeline_options(r.pipeline, iso, inside);
    if (r.iteration) {
        options.relax.max_iterations = *r.iteration;
        options.relax.epsilon = 0.0f;
    }
    const Method net_method = method_of(options.relax.mode);

    MethodResult mc = run_source_method(Method::MarchingCubes, source, options, m,
                                        progress.stage("Marching Cubes"));
    require_surface(mc, m);
    // The net as run_method runs it, observed: its last iteration is kept for the inspector.
    PipelineOptions net_options = options;
    net_options.relax.iso = iso;
    net_options.measure.reference_volume = m.reference.volume;
    std::shared_ptr<const SurfaceNet> net;
    std::shared_ptr<const GreyField> field;
    std::vector<glm::vec3> before, after;
    int iteration = 0;
    NetObserver observer;
    observer.on_net = [&](std::shared_ptr<const SurfaceNet> n, std::shared_ptr<const GreyField> f) {
        net = std::move(n);
        field = std::move(f);
        after = net->positions;
    };
    observer.on_iteration = [&](const RelaxIteration& it, std::span<const glm::vec3> positions) {
        before.swap(after);
        after.assign(positions.begin(), positions.end());
        iteration = it.iteration;
        return true;
    };
    const MethodResult relaxed =
        run_surface_net(volume, source.mask.get(), net_options, m.reference.distance,
                        progress.stage(std::string(label_of(net_method))), observer);
    require_surface(relaxed, m);

    render::SliceFigure figure;
    render::SliceScene& scene = figure.scene;
    scene.plane = requested;
    scene.size = slice_size(volume.dims, requested.axis);
    const glm::ivec2 axes = plane_axes(requested.axis);
    scene.spacing = {volume.spacing[axes.x], volume.spacing[axes.y]};
    const Slice slice = extract_slice(volume, requested);
    scene.inside = slice_inside(slice, source.mask.get(), iso, inside);
    scene.segmentation = render::segmentation_legend(source, iso);
    const WindowLevel window = wl.value_or(window_preset(r.slice.preset, volume));
    figure.pixels = slice_pixels(slice, window, scene.inside);
    scene.contours.push_back(
        {Method::MarchingCubes, mesh_cross_section(mc.mesh, volume, requested)});
    scene.contours.push_back({net_method, mesh_cross_section(relaxed.mesh, volume, requested)});
    scene.net = {net_method, net.get(), after, net_in_slice(*net, requested)};

    std::optional<NodeInspection> inspection;
    if (cell) {
        const std::optional<std::uint32_t> node = node_of_cell(*net, *cell);
        if (!node)
            throw InputError(m.name + ": cell (" + r.slice.node +
                             ") holds no node of the net (not a surface cell at this iso)");
        if (iteration > 0)
            inspection =
                inspect_node(*net, field.get(), net_options.relax, iteration, before, after, *node);
        else
            std::cerr << "note: iteration 0 has no move to take apart; the node is shown\n";
        scene.crosshair = index_to_slice(requested.axis, after[*node]);
    }
    if (inspection) scene.inspection = &*inspection;

    if (r.zoom)
        figure.window = {{r.zoom->x, r.zoom->y}, {r.zoom->width, r.zoom->height}};
    else if (cell)
        // The node's cell and half a cell around it: the arrows are a fraction of a cell.
        figure.window =
            render::window_around(index_to_slice(requested.axis, glm::vec3(*cell) + 0.5f), 2.0f);
    else
        figure.window = render::whole_slice(scene.size);

    figure.title = source.title + "  \xC2\xB7  " + std::string(name_of(requested.axis)) +
                   " slice " + std::to_string(requested.index) + " of 0.." +
                   std::to_string(count - 1) + "  \xC2\xB7  " + std::string(label_of(net_method)) +
                   ", iteration " + std::to_string(iteration);
    if (r.caption)
        figure.caption = "iso " + format_number(iso) + "  \xC2\xB7  window " +
                         number(window.window) + ", level " + number(window.level) +
                         "  \xC2\xB7  constraint " +
                         std::string(label_of(options.relax.constraint)) +
                         "  \xC2\xB7  coordinates: voxel index";
    figure.width = r.width;
    figure.height = r.height;
    figure.samples = r.samples;
    render::Image image;
    try {
        image = render::render_slice_figure(figure);
    } catch (const std::invalid_argument& e) {
        throw CLI::ValidationError("--width/--height", e.what());
    }
    render::write_png(r.out, image);
    std::cerr << "wrote " << r.out << ": " << image.width << "x" << image.height << " ("
              << context->backend() << ")\n";
    return 0;
}

} // namespace snert::cli

#endif // SNERT_HAVE_RENDER
