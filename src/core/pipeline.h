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
#include <string>
#include <vector>

#include "marching_cubes.h"
#include "mesh.h"
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
    TriangulationRule triangulation = TriangulationRule::ShorterDiagonal;
};

struct MethodMetrics {
    std::size_t vertices = 0, triangles = 0;
    QualityStats quality;
    double smoothness = 0;
    std::optional<Accuracy> accuracy; // voxel units; empty where no reference exists
    Topology topology;
    double area = 0, volume = 0; // world units
    double ms = 0;               // time to build the mesh
};

struct MethodResult {
    std::string name; // "mc", "sna", "gradient", "snert"
    Mesh mesh;        // world units
    MethodMetrics metrics;
};

// A reference for accuracy: an unsigned distance in voxel units (index space). For phantoms the
// analytic surface; for real data the first-order distance |I(p) - iso| / |grad I(p)|.
DistanceFunction first_order_distance(const Volume& volume, float iso);

// Measures a mesh given in index space; the mesh's world copy is used for angles and areas.
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

const char* method_name(RelaxMode mode); // "sna", "gradient", "snert"

} // namespace snert
