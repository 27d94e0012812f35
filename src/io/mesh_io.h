// Mesh export: binary STL, Wavefront OBJ, binary PLY, OFF, legacy VTK polydata, and the
// finite-element formats Gmsh MSH 4.1 and Abaqus INP. Files are written to a temporary file
// beside the target and renamed into place, so a failed or interrupted write never leaves a
// half-written file.
//
// What is written, per format (all in the mesh's own units, triangles as wound in the Mesh):
//   .stl  binary, little-endian: 80-byte header (never starting with "solid"), uint32 count,
//         per triangle a float unit normal (zero for a degenerate one), 3 float corners and a
//         zero uint16 attribute;
//   .obj  "v x y z" lines, then "f a b c" with 1-based indices;
//   .ply  binary_little_endian 1.0: vertex float x, y, z; face list uchar int vertex_indices;
//   .off  "OFF", "V F 0", vertex lines, then "3 a b c" (0-based);
//   .vtk  legacy 3.0 ASCII POLYDATA: POINTS (float) and POLYGONS with inline counts, then
//         CELL_DATA: float SCALARS "quality" (smallest / largest angle), "min_angle" and
//         "max_angle" (degrees), and "distance" (voxels, MeshWriteOptions::distance) when given;
//   .msh  Gmsh 4.1 ASCII: $MeshFormat, $PhysicalNames (one physical surface, tag 1, named
//         MeshWriteOptions::name), $Entities (one discrete surface, tag 1, with the mesh's
//         bounding box and that physical group), $Nodes (one block, tags 1..V on the surface)
//         and $Elements (one block of 3-node triangles, type 2, tags 1..F);
//   .inp  Abaqus keywords: *HEADING, *NODE (1-based), *ELEMENT of TYPE=S3 (linear shell) or
//         SFM3D3 (surface element) with ELSET = the name, one line per triangle.
// Text numbers are the shortest decimal that reads back to the same value (std::to_chars);
// MSH, INP and OFF write each float coordinate as the double it is, so readers that parse
// doubles (Gmsh, Abaqus, meshio, TetGen) get the very float. Every format but STL (which has no
// shared vertices) round-trips the Mesh exactly. snert reads no mesh files; the tests read these
// back with tests/support/read_mesh.h and, for MSH, INP and VTK, with meshio and VTK.
#pragma once

#include <span>
#include <string>
#include <vector>

#include "core/mesh.h"
#include "core/names.h"

namespace snert {

enum class MeshFormat { Stl, Obj, Ply, Off, Vtk, Msh, Inp };

// The Abaqus element type of the triangles: S3, a 3-node shell with stiffness (the mesh as a
// structure, or the boundary Abaqus/CAE fills with tetrahedra), or SFM3D3, a surface element
// without stiffness (loads, contact or a skin on a solid).
enum class AbaqusElement { S3, Sfm3d3 };
std::span<const Named<AbaqusElement>> name_table(AbaqusElement);

// What a writer takes beside the mesh; each format uses what it has a place for.
struct MeshWriteOptions {
    // The surface's name: Gmsh's physical group, Abaqus' ELSET, the VTK title. Letters, digits
    // and '_' are kept, anything else becomes '_'; it starts with a letter ("surface" if empty).
    std::string name = "surface";
    AbaqusElement abaqus_element = AbaqusElement::S3; // .inp
    // Per-triangle distance to the accuracy reference in voxels (triangle_fields.h), written as
    // the VTK cell array "distance"; empty: no such array. Else one value per triangle.
    std::vector<float> distance;
};

// Format from the file extension (case-insensitive). Throws std::invalid_argument naming the
// file when the extension is not one of kMeshExtensions.
MeshFormat mesh_format_from_path(const std::string& path);
// ".stl", ".obj", ".ply", ".off", ".vtk", ".msh", ".inp", in MeshFormat's order.
extern const std::vector<std::string> kMeshExtensions;

// Throws std::runtime_error naming the file and the reason on failure, std::invalid_argument
// for an unknown extension, an index out of range or a distance array of the wrong size.
void write_mesh(const Mesh& mesh, const std::string& path, const MeshWriteOptions& options = {});
void write_mesh(const Mesh& mesh, const std::string& path, MeshFormat format,
                const MeshWriteOptions& options = {});

} // namespace snert
