// Compactness: equal-count comparisons and compactness curves, by decimation.
#include "compactness.h"

#include <algorithm>
#include <cmath>

namespace snert {

namespace {

Mesh to_index(const Mesh& world, const Volume& volume) {
    Mesh index = world;
    for (glm::vec3& p : index.positions) p = world_to_index(volume, p);
    return index;
}

} // namespace

std::size_t equal_count_target(std::span<const MethodResult> results,
                               std::optional<std::size_t> requested) {
    if (requested) return *requested;
    std::size_t smallest = 0;
    for (const MethodResult& r : results)
        if (smallest == 0 || r.mesh.triangle_count() < smallest) smallest = r.mesh.triangle_count();
    return smallest;
}

std::vector<DecimationReport> reduce_to_equal_count(std::span<MethodResult> results,
                                                    std::size_t target, const Volume& volume,
                                                    const DistanceFunction& reference,
                                                    const MeasureOptions& what) {
    std::optional<Mesh> unreduced_mc;
    for (const MethodResult& r : results)
        if (r.method == Method::MarchingCubes) unreduced_mc = r.mesh;
    // Reduce all; where one stops short (its checks refuse further steps), reduce the others
    // again from their full meshes to the count it reached, so the counts stay equal.
    std::vector<Decimated> reduced;
    std::size_t reached = 0;
    for (const MethodResult& r : results) {
        DecimationOptions options;
        options.target_triangles = target;
        reduced.push_back(decimate(r.mesh, options));
        reached = std::max(reached, reduced.back().report.achieved);
    }
    for (std::size_t i = 0; i < results.size(); ++i)
        if (reduced[i].report.achieved < reached && reached > target) {
            DecimationOptions options;
            options.target_triangles = reached;
            reduced[i] = decimate(results[i].mesh, options);
        }
    std::vector<DecimationReport> reports;
    for (std::size_t i = 0; i < results.size(); ++i) {
        MethodResult& r = results[i];
        Decimated& d = reduced[i];
        reports.push_back(d.report);
        if (d.report.achieved == d.report.original) continue; // unchanged: metrics stand
        MethodMetrics m = measure(to_index(d.mesh, volume), volume, reference, what);
        m.ms = r.metrics.ms;
        m.iterations = r.metrics.iterations;
        m.converged = r.metrics.converged;
        m.final_max_move = r.metrics.final_max_move;
        m.shortened_moves = r.metrics.shortened_moves;
        m.to_marching_cubes = r.metrics.to_marching_cubes;
        r.mesh = std::move(d.mesh);
        r.metrics = std::move(m);
    }
    if (unreduced_mc)
        for (MethodResult& r : results)
            if (r.method != Method::MarchingCubes)
                r.metrics.to_marching_cubes = distance_to_mesh(r.mesh, *unreduced_mc, volume);
    return reports;
}

std::vector<CompactnessPoint> compactness_curve(const Mesh& mesh, const Volume& volume) {
    std::vector<CompactnessPoint> curve;
    const std::size_t full = mesh.triangle_count();
    if (full == 0) return curve;
    const Mesh full_index = to_index(mesh, volume);
    const MeshDistance to_full(full_index);
    Mesh level = mesh;
    int refusals = 0;
    for (const double fraction : kCompactnessFractions) {
        CompactnessPoint p;
        p.fraction = fraction;
        const auto target =
            std::max<std::size_t>(1, std::size_t(std::llround(fraction * double(full))));
        if (target < level.triangle_count()) {
            DecimationOptions options;
            options.target_triangles = target;
            Decimated d = decimate(level, options);
            refusals += d.report.refusals;
            level = std::move(d.mesh);
        }
        p.triangles = level.triangle_count();
        p.quality_mean = quality_stats(level).mean;
        p.refusals = refusals;
        if (p.triangles < full) {
            const Mesh level_index = to_index(level, volume);
            // Reduced to unreduced: how far the coarse triangles cut away from the surface
            // (kSurfaceSampleSplit^2 points on each coarse triangle); unreduced to reduced: what
            // the coarse surface lost (a bump, a thin part), at the centroids of the unreduced
            // triangles, each a fraction of a voxel across: nine points on each would cost nine
            // times as much for the same figure within a small share of a voxel.
            const SurfaceDistance there = surface_distance(
                level_index, [&](glm::vec3 q) { return to_full(q); }, level.positions,
                kSurfaceSampleSplit);
            const MeshDistance to_level(level_index);
            const SurfaceDistance back = surface_distance(
                full_index, [&](glm::vec3 q) { return to_level(q); }, mesh.positions, 1);
            p.accuracy_mean = 0.5 * (there.mean + back.mean);
            p.accuracy_max = std::max(there.max, back.max);
        }
        curve.push_back(p);
    }
    return curve;
}

} // namespace snert
