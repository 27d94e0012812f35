// The comparison pipeline shared by the CLI, the renderer and the app: one volume in, Marching
// Cubes and the relaxed SurfaceNets out, each with its metrics.
//
//   volume -> segmentation -> MC (grey values at iso)         -> Mesh -> metrics
//                          -> SurfaceNet -> relaxation -> triangulation -> Mesh -> metrics
//
// Meshes are returned in world units (millimetres); accuracies are reported in voxel units
// (index space), the paper's unit.
#pragma once

#include <functional>
#include <memory>
#include <optional>
#include <span>
#include <vector>

#include "fe_readiness.h"
#include "marching_cubes.h"
#include "mesh.h"
#include "names.h"
#include "metrics.h"
#include "progress.h"
#include "relaxation.h"
#include "segmentation.h"
#include "surface_net.h"
#include "triangulation.h"
#include "volume.h"

namespace snert {

// What measure() measures, beyond what every mesh gets.
struct MeasureOptions {
    // Volume enclosed by the reference surface (voxels^3, index space); 0: unknown, and
    // MethodMetrics::volume_error stays empty.
    double reference_volume = 0.0;
    // Only what the app's convergence plots show after every iteration: the counts, quality,
    // smoothness and the accuracy at the vertices and centroids (point_accuracy); the checks
    // (topology, border, self-intersections, FE-readiness), area, volume and volume error keep
    // their defaults.
    bool convergence_only = false;
    bool operator==(const MeasureOptions&) const = default;
};

struct PipelineOptions {
    float iso = 0.0f; // Marching Cubes' iso (0.5 on a label mask)
    InsideIs inside = InsideIs::Above;
    RelaxOptions relax;     // relax.iso: the grey iso of the gradient term (eq. 3)
    MeasureOptions measure; // how run_marching_cubes and run_surface_net measure their mesh
    bool operator==(const PipelineOptions&) const = default;
};

// What an FE mesher needs of a surface (DESIGN.md, issue 8), all of it measured by measure():
// closed, or open only where the object leaves the volume (boundary_edges_off_border == 0);
// manifold (edges and vertices); no self-intersecting triangle pair; no zero-area triangle.
struct MethodMetrics {
    std::size_t vertices = 0, triangles = 0;
    QualityStats quality; // world units: slivers (q < 0.1), the smallest angle, degenerate ones
    double smoothness = 0;
    std::optional<Accuracy> accuracy; // voxel units; empty where no reference exists
    Topology topology;                // closed (watertight) and manifold are separate facts
    std::size_t boundary_edges_off_border = 0; // holes inside the volume (best 0)
    std::size_t self_intersections = 0;        // intersecting triangle pairs, as TetGen -d (best 0)
    bool fe_ready = false;                     // all of the above, see the comment on the struct
    double area = 0, volume = 0;               // world units
    // The FE-readiness summary: angle shares, ratio ranges, and the checks above again.
    FeReadiness fe;
    // (enclosed volume - reference volume) / reference volume, both in index space (voxels^3);
    // empty where the reference's volume is unknown (MeasureOptions::reference_volume).
    std::optional<double> volume_error;
    // Distance to the Marching Cubes surface of the same comparison (voxel units, index space):
    // how far a net moved from MC's iso-surface, on real data where no exact surface exists.
    // Set by measure_against_marching_cubes() on the nets; empty for MC itself.
    std::optional<Accuracy> to_marching_cubes;
    double ms = 0; // time to build the mesh
    // Relaxation, for the nets (left at these defaults for Marching Cubes).
    int iterations = 0;              // relaxation iterations done
    bool converged = false;          // stopped because the largest move fell under epsilon
    double final_max_move = 0;       // the largest node move of the last iteration (voxels)
    std::size_t shortened_moves = 0; // node moves shortened to keep the mesh valid (summed)
};

struct MethodResult {
    Method method = Method::MarchingCubes;
    Mesh mesh; // world units
    MethodMetrics metrics;
};

// A reference for accuracy: an unsigned distance in voxel units (index space). For phantoms the
// analytic surface; for real data the first-order distance |I(p) - iso| / |grad I(p)|. The
// function shares ownership of the volume, so it stays valid however long it is kept.
DistanceFunction first_order_distance(std::shared_ptr<const Volume> volume, float iso);

// Measures a mesh given in index space; the mesh's world copy is used for angles and areas (and
// the areas that weight the surface accuracy), the index-space mesh for accuracy, the border
// and the volume error. The one measurement of every mesh: the pipeline's, and the app's frames
// and convergence numbers. Leaves ms and the relaxation fields at their defaults.
MethodMetrics measure(const Mesh& index_mesh, const Volume& volume,
                      const DistanceFunction& reference, const MeasureOptions& what = {});

// measure(), for a mesh not needed in index space afterwards: `mesh` comes back in world units
// (as mesh_to_world makes it), so that one copy of it is held instead of two.
MethodMetrics measure_into_world(Mesh& mesh, const Volume& volume,
                                 const DistanceFunction& reference,
                                 const MeasureOptions& what = {});

// Marching Cubes' mesh of a comparison in index space, not measured: the grey values at
// options.iso, or the label's mask at 0.5 where one gives the topology (as 3D Slicer does). The
// first half of run_method's Marching Cubes, for a caller that shows the mesh before its metrics
// are done (the app); measure_into_world(mesh, grey, ...) is the second half.
Mesh marching_cubes_mesh(const Volume& grey, const Segmentation* mask,
                         const PipelineOptions& options, const Progress& progress = {});

// Marching Cubes, measured.
MethodResult run_marching_cubes(const Volume& volume, const PipelineOptions& options,
                                const DistanceFunction& reference, const Progress& progress = {});

// A relaxed net (mode from options.relax.mode), triangulated, measured. `segmentation` gives
// the topology; `grey` the gradient term (may be the same volume that was thresholded).
MethodResult run_surface_net(const Volume& grey, const Segmentation& segmentation,
                             const PipelineOptions& options, const DistanceFunction& reference,
                             const Progress& progress = {});

// What a caller sees of run_surface_net while it runs (the app's worker); every member optional.
struct NetObserver {
    // Once the net is built and the gradient field made, before the first iteration. Both are
    // shared, so the observer may keep them to redo or continue iterations later (relax_step,
    // relax() with a RelaxStart); the field points to the call's `grey`.
    std::function<void(std::shared_ptr<const SurfaceNet> net,
                       std::shared_ptr<const GreyField> field)>
        on_net;
    IterationCallback on_iteration; // every iteration's positions (relax()); false stops
    // The relaxation's progress; the call's `progress` then covers building the net only.
    std::optional<Progress> relax_progress;
};

// run_surface_net, observed: the same result, with `observer` told of the net and of every
// iteration as they happen. Without `mask` the grey values are thresholded at options.iso /
// options.inside as the net is built (the net of segment_threshold's mask, node for node, without
// its byte a voxel).
MethodResult run_surface_net(const Volume& grey, const Segmentation* mask,
                             const PipelineOptions& options, const DistanceFunction& reference,
                             const Progress& progress, const NetObserver& observer);

// One method on one volume, as the CLI, the renderer and the app run it. `options.iso` is the
// grey iso (also the gradient term's: relax.iso is set to it) and `method` picks the net's
// mode. Without `mask` the grey values are thresholded at options.iso / options.inside; with
// it, the mask (on the grey image's grid) gives the topology: Marching Cubes runs on the mask
// at 0.5, as 3D Slicer does, and the net's gradient term uses the grey values.
MethodResult run_method(Method method, const Volume& grey, const Segmentation* mask,
                        const PipelineOptions& options, const DistanceFunction& reference,
                        const Progress& progress = {});

// The distance of `mesh` to `reference`, both in world units on `volume`'s grid, in voxel units
// (index space): at the vertices, the face centres and over the surface, as accuracy() measures
// it. Empty when `reference` has no triangle.
std::optional<Accuracy> distance_to_mesh(const Mesh& mesh, const Mesh& reference,
                                         const Volume& volume);

// Fills MethodMetrics::to_marching_cubes of every net in `results` with distance_to_mesh() to
// the Marching Cubes mesh among them. Nothing happens without a Marching Cubes result.
void measure_against_marching_cubes(std::span<MethodResult> results, const Volume& volume);

} // namespace snert
