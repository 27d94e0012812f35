// A coarse stand-in for a large mesh, drawn while the camera moves: software GL spends its
// time per triangle, and a mesh with more triangles than the view has pixels cannot turn at
// 10 frames a second. Made by vertex clustering: the vertices in each cell of a grid share one
// representative, and the triangles whose three corners stay distinct remain. The indices
// refer to the mesh's own vertices, so the preview follows the relaxation's positions (the
// topology stays) and needs no vertex buffer of its own. GL-free.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "core/mesh.h"

namespace snert::app {

struct PreviewMesh {
    std::vector<std::uint32_t> indices; // into the mesh's vertices, 3 per triangle
    std::vector<std::uint32_t> source;  // per preview triangle: a mesh triangle it stands for
};

// Meshes with more than 2 x `target_triangles` triangles get a preview of about that many;
// smaller ones none (empty).
PreviewMesh make_preview(const Mesh& mesh, std::size_t target_triangles = 6000);

} // namespace snert::app
