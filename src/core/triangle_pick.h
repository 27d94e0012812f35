// Which triangle of a mesh a ray meets first, and what can be said about one triangle: its
// three angles and its shape (metrics.h). The app's views pick triangles with it (a click is a
// ray from the eye through the pixel); plain CPU work over every triangle, run once per click.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>

#include <glm/glm.hpp>

#include "mesh.h"
#include "metrics.h"

namespace snert {

struct TriangleHit {
    std::size_t triangle = 0;         // index into mesh.indices / 3
    float distance = 0;               // along the ray, in units of |direction|
    glm::vec3 point{0.0f};            // where the ray meets it
    std::uint32_t nearest_vertex = 0; // the triangle's corner nearest to the point
};

// The nearest triangle the ray origin + t * direction (t > 0) meets, from either side;
// nullopt when it meets none (or direction is zero). Degenerate triangles are never hit.
std::optional<TriangleHit> first_hit(const Mesh& mesh, glm::vec3 origin, glm::vec3 direction);

// The angles at corners a, b and c, in degrees (summing to 180; all 0 when degenerate).
std::array<float, 3> triangle_angles(glm::vec3 a, glm::vec3 b, glm::vec3 c);

} // namespace snert
