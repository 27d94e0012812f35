// Small meshes with known answers (area, volume, orientation, topology), and the two surfaces
// of a phantom, for tests of every layer.
#pragma once

#include <string>

#include <glm/glm.hpp>

#include "core/mesh.h"
#include "core/phantom.h"
#include "core/surface_net.h"

namespace snert::test {

// The unit cube [0, 1]^3: 8 vertices, two triangles a face, outward (counter-clockwise seen from
// outside). Area 6, volume 1.
Mesh unit_cube();
// The corner tetrahedron (0,0,0), (1,0,0), (0,1,0), (0,0,1), outward. Volume 1/6.
Mesh tetrahedron();
// Vertices at centre +- r along x, y and z: eight equilateral faces, outward.
Mesh octahedron(glm::vec3 centre = glm::vec3(0.0f), float r = 1.0f);
// Icosahedron subdivided `levels` times, vertices pushed onto the unit sphere, outward.
Mesh icosphere(int levels);
// n x n unit squares in the plane z = 0, each split into two triangles facing +z.
Mesh flat_grid(int n);
// A square [-half, half]^2 in the plane z = 0 facing +z, split into two right triangles.
Mesh square(float half = 1.0f);

// The same mesh with every triangle's winding reversed.
Mesh flipped(Mesh m);
// The same mesh moved by `offset`.
Mesh translated(Mesh m, glm::vec3 offset);

// Marching Cubes of a phantom at its iso value (inside above), in voxel units.
Mesh phantom_mc(const Phantom& phantom);
Mesh phantom_mc(const std::string& name, int size);
// The SurfaceNet of a phantom's threshold segmentation at its iso value, before relaxation.
SurfaceNet phantom_net(const Phantom& phantom);

} // namespace snert::test
