// Per-triangle values, as an FE export carries them for a viewer to colour by (ParaView's cell
// data): the quality, the smallest and the largest angle, and the distance of the triangle's
// centroid to the accuracy reference (the face-centre accuracy of metrics.h, triangle by
// triangle).
#pragma once

#include <vector>

#include "mesh.h"
#include "metrics.h"
#include "volume.h"

namespace snert {

struct TriangleFields {
    std::vector<float> quality;   // smallest / largest angle (0 when degenerate)
    std::vector<float> min_angle; // degrees (0 when degenerate)
    std::vector<float> max_angle; // degrees (180 when degenerate)
};
// One value per triangle of `mesh`, from triangle_shape(). Throws std::invalid_argument for a
// bad index.
TriangleFields triangle_fields(const Mesh& mesh);

// |reference| at each triangle's centroid, in voxel units: `world_mesh` is taken back to
// `volume`'s index space, where the reference (first-order or analytic, pipeline.h) measures.
// The mean of the result is MethodMetrics::accuracy->faces_mean of the same mesh, up to float
// rounding of the world -> index map. Empty when `reference` is empty.
std::vector<float> centroid_distances(const Mesh& world_mesh, const Volume& volume,
                                      const DistanceFunction& reference);

} // namespace snert
