// The distances a view can colour a mesh by, one value per triangle, measured at the triangle's
// centroid in voxel units (index space, where the iso-surface and the gradient live): to the
// iso-surface, and to the other method's mesh. The app's worker and `snert render` call
// pair_distances, so the two show the same numbers.
//
// The distance to the iso-surface is signed: the first-order distance (I(c) - iso) / |grad I(c)|
// (the accuracy reference of pipeline.h, eq. 7, without its absolute value), oriented so that
// it is positive outside the object and negative inside. The sign costs nothing (the same one
// sample of value and gradient) and tells which side a mesh lies on: Marching Cubes' chords cut
// inside a convex surface, a relaxed net can settle on either side.
// The distance to the other mesh is unsigned (a nearest-point search, MeshDistance).
#pragma once

#include <span>
#include <vector>

#include "mesh.h"
#include "metrics.h"
#include "segmentation.h"
#include "volume.h"

namespace snert {

// Signed first-order distance of each triangle's centroid of `world_mesh` to the `iso` surface
// of `volume` (positive outside, `inside` tells which side is the object); 0 where the
// gradient vanishes, NaN for a non-finite corner. Throws std::invalid_argument for a bad index.
std::vector<float> signed_iso_distances(const Mesh& world_mesh, const Volume& volume, float iso,
                                        InsideIs inside);

// Distance of each triangle's centroid of `world_mesh` to the nearest point of `other_world`,
// both in world units on `volume`'s grid, measured in index space. All NaN when `other_world`
// has no triangle (there is nothing to measure against).
std::vector<float> distances_to_other_mesh(const Mesh& world_mesh, const Mesh& other_world,
                                           const Volume& volume);

// The scale both views of a distance share: the 98th percentile of |value| over both meshes
// (NaN left out), rounded up to 1, 2 or 5 times a power of ten (at least 0.001 voxel), so that
// the few farthest triangles do not wash out the rest. [-r, r] on the diverging map for
// DistanceIso, [0, r] for DistanceOther.
MeasureScale distance_scale(ShapeMeasure measure, std::span<const float> first,
                            std::span<const float> second);

// The values of a distance measure for both meshes shown side by side (Marching Cubes first,
// the net second), with their summaries over the measure's scale. For DistanceOther each mesh
// is measured against the other one. Empty for a shape measure.
struct PairDistances {
    ShapeMeasure measure = ShapeMeasure::DistanceIso;
    std::vector<float> first, second;
    MeasureScale scale; // distance_scale of both
    MeasureSummary first_summary, second_summary;
};
PairDistances pair_distances(ShapeMeasure measure, const Mesh& first_world,
                             const Mesh& second_world, const Volume& volume, float iso,
                             InsideIs inside);

} // namespace snert
