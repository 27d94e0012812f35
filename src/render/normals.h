// Smooth shading's vertex normals. Header-only and GL-free, so the app's worker can make them
// off the UI thread without linking the renderer.
#pragma once

#include <vector>

#include <glm/glm.hpp>

#include "core/huge_pages.h"
#include "core/mesh.h"

namespace snert::render {

// Area-weighted vertex normals (unit length; +z for a vertex with no area around it), the
// normals of smooth shading. Winding gives the direction: counter-clockwise seen from outside.
// On huge pages: the app makes them for every frame it shows, and a clinical mesh's 5 MB of
// fresh memory faulted 4 KiB at a time took two thirds of the 17 ms (6-8 ms so).
inline std::vector<glm::vec3> vertex_normals(const Mesh& mesh) {
    std::vector<glm::vec3> normals;
    detail::resize_on_huge_pages(normals, mesh.positions.size(), glm::vec3(0.0f));
    for (std::size_t t = 0; t + 2 < mesh.indices.size(); t += 3) {
        const std::uint32_t a = mesh.indices[t], b = mesh.indices[t + 1], c = mesh.indices[t + 2];
        // The cross product's length is twice the area: summing it weights by area.
        const glm::vec3 n = glm::cross(mesh.positions[b] - mesh.positions[a],
                                       mesh.positions[c] - mesh.positions[a]);
        normals[a] += n;
        normals[b] += n;
        normals[c] += n;
    }
    for (glm::vec3& n : normals) {
        const float length = glm::length(n);
        n = length > 0.0f ? n / length : glm::vec3(0.0f, 0.0f, 1.0f);
    }
    return normals;
}

} // namespace snert::render
