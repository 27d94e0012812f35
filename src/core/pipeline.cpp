// The comparison pipeline shared by the CLI, the renderer and the app.
#include "pipeline.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <utility>

#include "serial_number.h"
#include "triangle_intersection.h"

namespace snert {

namespace {

double elapsed_ms(std::chrono::steady_clock::time_point since) {
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - since)
        .count();
}

} // namespace

DistanceFunction first_order_distance(std::shared_ptr<const Volume> volume, float iso) {
    if (!volume) return {};
    const std::uint64_t number = next_serial_number(); // tags each thread's kept cell (below)
    // |I(p) - iso| / |grad I(p)|: the distance to the iso-surface if the field were linear.
    return [volume = std::move(volume), iso, number](glm::vec3 p) {
        // The accuracy asks for the vertices in order and then for a triangle's points one after
        // another, spread over a few neighbouring cells: each thread keeps the corners of the
        // cells around the last points (the same result in a fraction of the time).
        thread_local struct {
            std::uint64_t number = 0;
            CellCornerCache corners;
        } kept;
        if (kept.number != number) kept = {number, CellCornerCache{}};
        const ValueGradient here = sample_value_gradient(*volume, p, kept.corners);
        const float difference = std::abs(here.value - iso);
        const float slope = glm::length(here.gradient);
        return slope > 1e-12f ? difference / slope : 0.0f;
    };
}

MethodMetrics measure_into_world(Mesh& mesh, const Volume& volume,
                                 const DistanceFunction& reference, const MeasureOptions& what) {
    MethodMetrics m;
    m.vertices = mesh.vertex_count();
    m.triangles = mesh.triangle_count();
    if (what.convergence_only) {
        // The convergence plots show the accuracy at the vertices and the centroids only.
        if (reference) m.accuracy = point_accuracy(mesh, reference);
        place_in_world(mesh, volume);
        m.quality = quality_stats(mesh);
        m.smoothness = smoothness(mesh);
        return m;
    }
    // Index space first: the accuracy (weighted by the world areas), the border, the volume error.
    std::vector<glm::vec3> world = points_to_world(mesh.positions, volume);
    if (reference) m.accuracy = accuracy(mesh, reference, world);
    // The connectivity (the same in either space: a mirroring map flips every triangle), the
    // border and the smoothness of the world mesh (orientation does not matter to it) at once.
    const FanMeasures fans = fan_measures(mesh, volume.dims, world);
    m.topology = fans.topology;
    m.boundary_edges_off_border = fans.boundary_edges_off_border;
    m.smoothness = fans.smoothness;
    // In index space, the reference's unit (the world volume differs by the voxel volume).
    if (what.reference_volume > 0)
        m.volume_error = (enclosed_volume(mesh) - what.reference_volume) / what.reference_volume;
    place_in_world(mesh, volume, std::move(world));
    m.quality = quality_stats(mesh);
    // In world units: a mirroring or oblique index->world map keeps intersections as they are,
    // and the world mesh is what gets exported and handed to a mesher.
    m.self_intersections = count_self_intersections(mesh);
    m.fe_ready = m.triangles > 0 && m.boundary_edges_off_border == 0 && m.topology.manifold &&
                 m.self_intersections == 0 && m.quality.degenerate == 0;
    m.fe = fe_readiness(m.quality, m.topology, m.self_intersections); // from quality's pass
    m.area = surface_area(mesh);
    m.volume = enclosed_volume(mesh);
    return m;
}

MethodMetrics measure(const Mesh& index_mesh, const Volume& volume,
                      const DistanceFunction& reference, const MeasureOptions& what) {
    Mesh mesh = index_mesh;
    return measure_into_world(mesh, volume, reference, what);
}

Mesh marching_cubes_mesh(const Volume& grey, const Segmentation* mask,
                         const PipelineOptions& options, const Progress& progress) {
    if (mask) return marching_cubes(mask_volume(*mask, grey), {0.5f, InsideIs::Above}, progress);
    return marching_cubes(grey, {options.iso, options.inside}, progress);
}

namespace {

// Marching Cubes on the grey values or the label's mask, measured. The mask's volume has the
// grey volume's grid, so measuring against the grey volume is the same (and it is let go first).
MethodResult measured_marching_cubes(const Volume& grey, const Segmentation* mask,
                                     const PipelineOptions& options,
                                     const DistanceFunction& reference, const Progress& progress) {
    const auto start = std::chrono::steady_clock::now();
    Mesh mesh = marching_cubes_mesh(grey, mask, options, progress);
    const double ms = elapsed_ms(start);
    MethodResult result;
    result.method = Method::MarchingCubes;
    result.metrics = measure_into_world(mesh, grey, reference, options.measure);
    result.metrics.ms = ms;
    result.mesh = std::move(mesh);
    return result;
}

} // namespace

MethodResult run_marching_cubes(const Volume& volume, const PipelineOptions& options,
                                const DistanceFunction& reference, const Progress& progress) {
    return measured_marching_cubes(volume, nullptr, options, reference, progress);
}

MethodResult run_surface_net(const Volume& grey, const Segmentation& segmentation,
                             const PipelineOptions& options, const DistanceFunction& reference,
                             const Progress& progress) {
    return run_surface_net(grey, &segmentation, options, reference, progress, NetObserver{});
}

namespace {

// The relaxation, triangulation and metrics of a built net (its build began at `start`). The net
// is let go (unless an observer keeps it) before the mesh is measured: on a clinical CT the net
// and its positions weigh more than the mesh, and measuring is the run's peak of memory.
MethodResult relax_net(const Volume& grey, std::shared_ptr<const SurfaceNet> net,
                       std::chrono::steady_clock::time_point start, const PipelineOptions& options,
                       const DistanceFunction& reference, const Progress& progress,
                       const NetObserver& observer) {
    auto field = std::make_shared<const GreyField>(make_grey_field(grey, options.relax));
    if (observer.on_net) observer.on_net(net, field);
    RelaxResult relaxed = relax(*net, field.get(), options.relax, observer.on_iteration,
                                observer.relax_progress.value_or(progress));
    Mesh mesh = triangulate(*net, relaxed.positions, options.relax.triangulation, grey.spacing);
    const double ms = elapsed_ms(start);
    relaxed.positions = {};
    net.reset();
    field.reset();
    MethodResult result;
    result.method = method_of(options.relax.mode);
    result.metrics = measure_into_world(mesh, grey, reference, options.measure);
    result.metrics.ms = ms;
    result.metrics.iterations = int(relaxed.max_moves.size());
    result.metrics.converged = relaxed.converged;
    result.metrics.final_max_move = relaxed.max_moves.empty() ? 0.0 : relaxed.max_moves.back();
    result.metrics.shortened_moves = relaxed.shortened_moves;
    result.mesh = std::move(mesh);
    return result;
}

} // namespace

MethodResult run_surface_net(const Volume& grey, const Segmentation* mask,
                             const PipelineOptions& options, const DistanceFunction& reference,
                             const Progress& progress, const NetObserver& observer) {
    const auto start = std::chrono::steady_clock::now();
    // Without a mask the threshold is classified as the net is built: no byte a voxel (100 MiB
    // on a 512 x 512 x 400 CT) for the relaxation and the metrics to find in use.
    auto net = std::make_shared<const SurfaceNet>(
        mask ? build_surface_net(*mask, progress)
             : build_surface_net(grey, options.iso, options.inside, progress));
    return relax_net(grey, std::move(net), start, options, reference, progress, observer);
}

MethodResult run_method(Method method, const Volume& grey, const Segmentation* mask,
                        const PipelineOptions& base, const DistanceFunction& reference,
                        const Progress& progress) {
    PipelineOptions options = base;
    options.relax.iso = base.iso;
    if (const auto mode = relax_mode_of(method)) options.relax.mode = *mode;
    // The label's mask, where there is one, decides the topology.
    if (method == Method::MarchingCubes)
        return measured_marching_cubes(grey, mask, options, reference, progress);
    return run_surface_net(grey, mask, options, reference, progress, NetObserver{});
}

namespace {

// accuracy() of the index-space copy of a world mesh, weighted by its world areas.
Accuracy distance_in_voxels(const Mesh& index_mesh, std::span<const glm::vec3> world_positions,
                            const MeshDistance& to_reference) {
    return accuracy(
        index_mesh, [&](glm::vec3 p) { return to_reference(p); }, world_positions);
}

} // namespace

std::optional<Accuracy> distance_to_mesh(const Mesh& mesh, const Mesh& reference,
                                         const Volume& volume) {
    if (reference.triangle_count() == 0) return std::nullopt;
    const MeshDistance to_reference(reference, world_to_index_map(volume));
    const Mesh index{points_to_index(mesh.positions, volume), mesh.indices};
    return distance_in_voxels(index, mesh.positions, to_reference);
}

void measure_against_marching_cubes(std::span<MethodResult> results, const Volume& volume) {
    const auto mc = std::find_if(results.begin(), results.end(), [](const MethodResult& r) {
        return r.method == Method::MarchingCubes;
    });
    if (mc == results.end() || mc->mesh.triangle_count() == 0) return;
    // One grid for every net, over MC's world mesh as seen in index space (not a copy of it).
    const MeshDistance to_mc(mc->mesh, world_to_index_map(volume));
    for (MethodResult& r : results) {
        if (r.method == Method::MarchingCubes) continue;
        // The index-space copy borrows the net's triangles and gives them back: a clinical
        // mesh's triangles are not held twice at the comparison's peak of memory.
        Mesh index{points_to_index(r.mesh.positions, volume), std::move(r.mesh.indices)};
        try {
            r.metrics.to_marching_cubes = distance_in_voxels(index, r.mesh.positions, to_mc);
        } catch (...) {
            r.mesh.indices = std::move(index.indices);
            throw;
        }
        r.mesh.indices = std::move(index.indices);
    }
}

} // namespace snert
