// Mesh export: binary STL, Wavefront OBJ, binary PLY, OFF and legacy VTK polydata.
// Files are written to a temporary file beside the target and renamed into place, so a failed
// or interrupted write never leaves a half-written file.
//
// What is written, per format (all in the mesh's own units, triangles as wound in the Mesh):
//   .stl  binary, little-endian: 80-byte header (never starting with "solid"), uint32 count,
//         per triangle a float unit normal (zero for a degenerate one), 3 float corners and a
//         zero uint16 attribute;
//   .obj  "v x y z" lines, then "f a b c" with 1-based indices;
//   .ply  binary_little_endian 1.0: vertex float x, y, z; face list uchar int vertex_indices;
//   .off  "OFF", "V F 0", vertex lines, then "3 a b c" (0-based);
//   .vtk  legacy 3.0 ASCII POLYDATA: POINTS (float) and POLYGONS with inline counts.
// Text numbers are the shortest decimal that reads back to the same float (std::to_chars), so
// every format but STL (which has no shared vertices) round-trips the Mesh exactly. snert
// reads no mesh files; the tests read these back with tests/support/read_mesh.h.
#pragma once

#include <string>

#include "core/mesh.h"

namespace snert {

enum class MeshFormat { Stl, Obj, Ply, Off, Vtk };

// Format from the file extension (case-insensitive). Throws std::invalid_argument naming the
// file when the extension is not one of .stl .obj .ply .off .vtk.
MeshFormat mesh_format_from_path(const std::string& path);

// Throws std::runtime_error naming the file and the reason on failure, std::invalid_argument
// for an unknown extension or an index out of range.
void write_mesh(const Mesh& mesh, const std::string& path);
void write_mesh(const Mesh& mesh, const std::string& path, MeshFormat format);

} // namespace snert
