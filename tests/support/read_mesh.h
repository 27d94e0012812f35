// Reads back the mesh files snert writes (src/io/mesh_io.h), for round-trip tests and for
// comparing what the app or the CLI wrote with the mesh it measured. Not part of the product:
// snert itself reads no mesh files.
//
// What is read is exactly what write_mesh writes:
//   .stl  binary (84-byte header, uint32 count, 50 bytes per facet); corners with
//         bit-identical positions (-0 taken as +0) are merged, so the result is indexed;
//   .obj  "v x y z" and "f a b c" lines (1-based; "#" comments and other lines ignored);
//   .ply  binary_little_endian 1.0, vertex float x y z, face list uchar int vertex_indices;
//   .off  "OFF", "V F E", V vertex lines, F "3 a b c" lines (0-based);
//   .vtk  legacy ASCII POLYDATA: POINTS and POLYGONS with inline counts, then CELL_DATA with
//         float SCALARS (default lookup table), one value per triangle.
// The FE formats (.msh, .inp) are read back by meshio in tests/cli/fe_formats_test.py.
// Variants only other tools write (ASCII STL, ASCII or big-endian PLY, other PLY properties,
// VTK 5.1, triangle strips, polygons, negative OBJ indices, OFF comments) are refused.
//
// The reader is as strict as a product reader: every count is checked against the file's size
// before memory is reserved, every index against the vertex count, so a truncated or wrong file
// fails the test instead of reading as a smaller mesh.
#pragma once

#include <map>
#include <string>
#include <vector>

#include "core/mesh.h"

// In namespace snert (not snert::test) so that tests written against the former
// snert::read_mesh keep calling it unqualified.
namespace snert {

// Throws std::runtime_error "PATH: [line N: ]reason" for a missing, truncated or malformed
// file, and std::invalid_argument for an extension other than .stl .obj .ply .off .vtk.
Mesh read_mesh(const std::string& path);

// The cell arrays of a .vtk file snert wrote, by name. Throws as read_mesh does.
using VtkCellData = std::map<std::string, std::vector<float>>;
VtkCellData read_vtk_cell_data(const std::string& path);

} // namespace snert
