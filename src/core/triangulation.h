// Triangulation of the SurfaceNet's quads (de Bruin et al., section 2.5). Each quad splits
// into two triangles along its shorter diagonal, or by the Delaunay criterion (the diagonal
// whose two opposite angles sum to less than pi). Recomputed after every iteration, because
// the node positions change. The mesh's vertices are the net's nodes, in node order.
#pragma once

#include <span>

#include <glm/glm.hpp>

#include "mesh.h"
#include "surface_net.h"

namespace snert {

enum class TriangulationRule { ShorterDiagonal, Delaunay };

Mesh triangulate(const SurfaceNet& net, std::span<const glm::vec3> positions,
                 TriangulationRule rule = TriangulationRule::ShorterDiagonal);

} // namespace snert
