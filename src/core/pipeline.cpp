// The comparison pipeline shared by the CLI, the renderer and the app.
#include "pipeline.h"

#include <chrono>
#include <cmath>

#include "triangle_intersection.h"

namespace snert {

namespace {

double elapsed_ms(std::chrono::steady_clock::time_point since) {
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - since)
        .count();
}

} // namespace

DistanceFunction first_order_distance(const Volume& volume, float iso) {
    // |I(p) - iso| / |grad I(p)|: the distance to the iso-surface if the field were linear.
    return [&volume, iso](glm::vec3 p) {
        const float difference = std::abs(sample_trilinear(volume, p) - iso);
        const float slope = glm::length(gradient_central(volume, p));
        return slope > 1e-12f ? difference / slope : 0.0f;
    };
}

MethodMetrics measure(const Mesh& index_mesh, const Volume& volume,
                      const DistanceFunction& reference) {
    MethodMetrics m;
    const Mesh world = mesh_to_world(index_mesh, volume);
    m.vertices = world.vertex_count();
    m.triangles = world.triangle_count();
    m.quality = quality_stats(world);
    m.smoothness = smoothness(world);
    m.topology = topology(world);
    if (m.topology.boundary_edges > 0)
        m.boundary_edges_off_border = boundary_edges_off_border(index_mesh, volume.dims);
    // In world units: a mirroring or oblique index->world map keeps intersections as they are,
    // and the world mesh is what gets exported and handed to a mesher.
    m.self_intersections = count_self_intersections(world);
    m.fe_ready = m.triangles > 0 && m.boundary_edges_off_border == 0 && m.topology.manifold &&
                 m.self_intersections == 0 && m.quality.degenerate == 0;
    m.area = surface_area(world);
    m.volume = enclosed_volume(world);
    if (reference) m.accuracy = accuracy(index_mesh, reference, &world);
    return m;
}

MethodResult run_marching_cubes(const Volume& volume, const PipelineOptions& options,
                                const DistanceFunction& reference, const Progress& progress) {
    const auto start = std::chrono::steady_clock::now();
    Mesh mesh = marching_cubes(volume, {options.iso, options.inside}, progress);
    const double ms = elapsed_ms(start);
    MethodResult result;
    result.method = Method::MarchingCubes;
    result.metrics = measure(mesh, volume, reference);
    result.metrics.ms = ms;
    result.mesh = mesh_to_world(mesh, volume);
    return result;
}

MethodResult run_surface_net(const Volume& grey, const Segmentation& segmentation,
                             const PipelineOptions& options, const DistanceFunction& reference,
                             const Progress& progress) {
    const auto start = std::chrono::steady_clock::now();
    SurfaceNet net = build_surface_net(segmentation, progress);
    const GreyField field = make_grey_field(grey, options.relax);
    const RelaxResult relaxed = relax(net, &field, options.relax, {}, progress);
    Mesh mesh = triangulate(net, relaxed.positions, options.relax.triangulation, grey.spacing);
    const double ms = elapsed_ms(start);
    MethodResult result;
    result.method = method_of(options.relax.mode);
    result.metrics = measure(mesh, grey, reference);
    result.metrics.ms = ms;
    result.metrics.iterations = int(relaxed.max_moves.size());
    result.metrics.converged = relaxed.converged;
    result.metrics.final_max_move = relaxed.max_moves.empty() ? 0.0 : relaxed.max_moves.back();
    result.metrics.shortened_moves = relaxed.shortened_moves;
    result.mesh = mesh_to_world(mesh, grey);
    return result;
}

} // namespace snert
