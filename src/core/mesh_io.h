// Mesh export: binary STL, Wavefront OBJ, binary PLY, OFF and legacy VTK polydata.
// Files are written to a temporary file beside the target and renamed into place, so a failed
// or interrupted write never leaves a half-written file.
#pragma once

#include <string>

#include "mesh.h"

namespace snert {

enum class MeshFormat { Stl, Obj, Ply, Off, Vtk };

// Format from the file extension (case-insensitive). Throws std::invalid_argument naming the
// file when the extension is not one of .stl .obj .ply .off .vtk.
MeshFormat mesh_format_from_path(const std::string& path);

// Throws std::runtime_error naming the file and the reason on failure.
void write_mesh(const Mesh& mesh, const std::string& path);
void write_mesh(const Mesh& mesh, const std::string& path, MeshFormat format);

// Reads what write_mesh wrote (for round-trip tests and for comparing meshes).
Mesh read_mesh(const std::string& path);

} // namespace snert
