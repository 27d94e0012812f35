// The distance of each triangle's centroid to the accuracy reference (the face-centre accuracy
// of metrics.h, triangle by triangle), as an FE export carries it for a viewer to colour by
// (ParaView's cell data) beside the shape measures of metrics.h's triangle_measures.
#pragma once

#include <vector>

#include "mesh.h"
#include "metrics.h"
#include "volume.h"

namespace snert {

// |reference| at each triangle's centroid, in voxel units: `world_mesh` is taken back to
// `volume`'s index space, where the reference (first-order or analytic, pipeline.h) measures.
// The mean of the result is MethodMetrics::accuracy->faces_mean of the same mesh, up to float
// rounding of the world -> index map. Empty when `reference` is empty.
std::vector<float> centroid_distances(const Mesh& world_mesh, const Volume& volume,
                                      const DistanceFunction& reference);

} // namespace snert
