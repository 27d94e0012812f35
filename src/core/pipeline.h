// The comparison pipeline shared by the CLI, the renderer and the app: one volume in, Marching
// Cubes and the relaxed SurfaceNets out, each with its metrics.
//
//   volume -> segmentation -> MC (grey values at iso)         -> Mesh -> metrics
//                          -> SurfaceNet -> relaxation -> triangulation -> Mesh -> metrics
//
// Meshes are returned in world units (millimetres); accuracies are reported in voxel units
// (index space), the paper's unit.
#pragma once

#include <optional>
#include <vector>

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

struct PipelineOptions {
    float iso = 0.0f; // Marching Cubes' iso (0.5 on a label mask)
    InsideIs inside = InsideIs::Above;
    RelaxOptions relax; // relax.iso: the grey iso of the gradient term (eq. 3)
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
    double ms = 0;                             // time to build the mesh
    // Relaxation, for the nets (left at these defaults for Marching Cubes).
    int iterations = 0;              // relaxation iterations done
    bool converged = false;          // stopped because the largest move fell under epsilon
    double final_max_move = 0;       // the largest node move of the last iteration (voxels)
    std::size_t shortened_moves = 0; // node moves shortened to keep the mesh valid (summed)
};

struct MethodResult {
    Method method = Method::MarchingCubes;
    Mesh mesh;        // world units
    MethodMetrics metrics;
};

// A reference for accuracy: an unsigned distance in voxel units (index space). For phantoms the
// analytic surface; for real data the first-order distance |I(p) - iso| / |grad I(p)|.
DistanceFunction first_order_distance(const Volume& volume, float iso);

// Measures a mesh given in index space; the mesh's world copy is used for angles and areas (and
// the areas that weight the surface accuracy), the index-space mesh for accuracy and the border.
MethodMetrics measure(const Mesh& index_mesh, const Volume& volume,
                      const DistanceFunction& reference);

// Marching Cubes, measured.
MethodResult run_marching_cubes(const Volume& volume, const PipelineOptions& options,
                                const DistanceFunction& reference, const Progress& progress = {});

// A relaxed net (mode from options.relax.mode), triangulated, measured. `segmentation` gives
// the topology; `grey` the gradient term (may be the same volume that was thresholded).
MethodResult run_surface_net(const Volume& grey, const Segmentation& segmentation,
                             const PipelineOptions& options, const DistanceFunction& reference,
                             const Progress& progress = {});

} // namespace snert
