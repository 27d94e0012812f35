// Splitting the net's quads into triangles (de Bruin et al., section 2.5).
#include "triangulation.h"

#include <algorithm>
#include <cmath>

#include "huge_pages.h"
#include "parallel.h"

namespace snert {

namespace {

float angle_at(glm::vec3 apex, glm::vec3 a, glm::vec3 b) {
    const glm::vec3 u = a - apex, v = b - apex;
    const float lu = glm::length(u), lv = glm::length(v);
    if (!(lu > 0.0f) || !(lv > 0.0f)) return 0.0f;
    return std::acos(std::clamp(glm::dot(u, v) / (lu * lv), -1.0f, 1.0f));
}

} // namespace

// Delaunay: a-c is the locally Delaunay edge when the angles opposite it sum to at most pi (the
// corners in world units).
bool detail::delaunay_splits_along_ac(glm::vec3 a, glm::vec3 b, glm::vec3 c, glm::vec3 d) {
    return angle_at(b, a, c) + angle_at(d, c, a) <= 3.14159265358979f;
}

// The app makes a mesh of every iteration it shows while the relaxation waits for it: the buffers
// go on huge pages (a clinical net's 15 MB faulted 4 KiB at a time took longer than the
// triangles), and the quads, six indices each at a known place, are split in parallel chunks.
Mesh triangulate(const SurfaceNet& net, std::span<const glm::vec3> positions,
                 TriangulationRule rule, glm::vec3 spacing) {
    constexpr std::size_t kQuadChunk = std::size_t(1) << 15;
    Mesh mesh;
    detail::reserve_mapped_on_huge_pages(mesh.positions, positions.size());
    mesh.positions.assign(positions.begin(), positions.end());
    detail::resize_on_huge_pages(mesh.indices, net.quads.size() * 6 + net.triangles.size() * 3);
    for_each_chunk(net.quads.size(), kQuadChunk, [&](std::size_t, std::size_t b, std::size_t e) {
        std::uint32_t* out = mesh.indices.data() + 6 * b;
        for (std::size_t k = b; k < e; ++k) {
            const auto& q = net.quads[k];
            const bool along_ac = quad_splits_along_ac(
                positions[q[0]], positions[q[1]], positions[q[2]], positions[q[3]], rule, spacing);
            for (const auto& t : quad_triangles(q, along_ac))
                out = std::copy(t.begin(), t.end(), out);
        }
    });
    std::uint32_t* out = mesh.indices.data() + 6 * net.quads.size();
    for (const auto& t : net.triangles) out = std::copy(t.begin(), t.end(), out);
    return mesh;
}

} // namespace snert
