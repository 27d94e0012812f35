// Which triangle of a mesh a ray meets first: what a click in a 3D view points at.
#pragma once

#include <cstdint>
#include <optional>

#include <glm/glm.hpp>

#include "mesh.h"

namespace snert {

struct RayHit {
    std::uint32_t triangle = 0;
    float t = 0.0f;                   // origin + t * direction is the point
    glm::vec3 point{0.0f};            // where the ray meets the triangle
    std::uint32_t nearest_vertex = 0; // the triangle's corner nearest to the point
};

// The nearest hit with t > 0 (Moller-Trumbore, both sides of a triangle), or nothing.
std::optional<RayHit> first_hit(const Mesh& mesh, glm::vec3 origin, glm::vec3 direction);

} // namespace snert
