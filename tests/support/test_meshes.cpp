#include "support/test_meshes.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <map>
#include <utility>
#include <vector>

#include "core/marching_cubes.h"
#include "core/segmentation.h"

namespace snert::test {

Mesh unit_cube() {
    Mesh m;
    for (int i = 0; i < 8; ++i)
        m.positions.push_back({float(i & 1), float(i >> 1 & 1), float(i >> 2)});
    const std::uint32_t quads[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4},
                                       {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
    for (const auto& q : quads)
        m.indices.insert(m.indices.end(), {q[0], q[1], q[2], q[0], q[2], q[3]});
    return m;
}

Mesh tetrahedron() {
    Mesh m;
    m.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    m.indices = {0, 2, 1, 0, 1, 3, 0, 3, 2, 1, 2, 3};
    return m;
}

Mesh octahedron(glm::vec3 centre, float r) {
    Mesh m;
    m.positions = {centre + glm::vec3(r, 0, 0), centre + glm::vec3(-r, 0, 0),
                   centre + glm::vec3(0, r, 0), centre + glm::vec3(0, -r, 0),
                   centre + glm::vec3(0, 0, r), centre + glm::vec3(0, 0, -r)};
    m.indices = {0, 2, 4, 2, 1, 4, 1, 3, 4, 3, 0, 4, 2, 0, 5, 1, 2, 5, 3, 1, 5, 0, 3, 5};
    return m;
}

Mesh icosphere(int levels) {
    const float g = (1.0f + std::sqrt(5.0f)) / 2.0f;
    Mesh m;
    m.positions = {{-1, g, 0},  {1, g, 0},  {-1, -g, 0}, {1, -g, 0}, {0, -1, g},  {0, 1, g},
                   {0, -1, -g}, {0, 1, -g}, {g, 0, -1},  {g, 0, 1},  {-g, 0, -1}, {-g, 0, 1}};
    m.indices = {0, 11, 5,  0, 5,  1, 0, 1, 7, 0, 7,  10, 0, 10, 11, 1, 5, 9, 5, 11,
                 4, 11, 10, 2, 10, 7, 6, 7, 1, 8, 3,  9,  4, 3,  4,  2, 3, 2, 6, 3,
                 6, 8,  3,  8, 9,  4, 9, 5, 2, 4, 11, 6,  2, 10, 8,  6, 7, 9, 8, 1};
    for (int level = 0; level < levels; ++level) {
        std::map<std::pair<std::uint32_t, std::uint32_t>, std::uint32_t> midpoints;
        auto midpoint = [&](std::uint32_t a, std::uint32_t b) {
            const auto key = std::minmax(a, b);
            const auto found = midpoints.find(key);
            if (found != midpoints.end()) return found->second;
            m.positions.push_back((m.positions[a] + m.positions[b]) * 0.5f);
            return midpoints[key] = std::uint32_t(m.positions.size() - 1);
        };
        std::vector<std::uint32_t> finer;
        for (std::size_t t = 0; t < m.indices.size(); t += 3) {
            const std::uint32_t a = m.indices[t], b = m.indices[t + 1], c = m.indices[t + 2];
            const std::uint32_t ab = midpoint(a, b), bc = midpoint(b, c), ca = midpoint(c, a);
            finer.insert(finer.end(), {a, ab, ca, b, bc, ab, c, ca, bc, ab, bc, ca});
        }
        m.indices = std::move(finer);
    }
    for (glm::vec3& p : m.positions) p = glm::normalize(p);
    return m;
}

Mesh flat_grid(int n) {
    Mesh m;
    for (int y = 0; y <= n; ++y)
        for (int x = 0; x <= n; ++x) m.positions.push_back({float(x), float(y), 0.0f});
    auto id = [n](int x, int y) { return std::uint32_t(y * (n + 1) + x); };
    for (int y = 0; y < n; ++y)
        for (int x = 0; x < n; ++x)
            m.indices.insert(m.indices.end(), {id(x, y), id(x + 1, y), id(x + 1, y + 1), id(x, y),
                                               id(x + 1, y + 1), id(x, y + 1)});
    return m;
}

Mesh square(float half) {
    Mesh m;
    m.positions = {{-half, -half, 0}, {half, -half, 0}, {half, half, 0}, {-half, half, 0}};
    m.indices = {0, 1, 2, 0, 2, 3};
    return m;
}

Mesh flipped(Mesh m) {
    for (std::size_t t = 0; t + 2 < m.indices.size(); t += 3)
        std::swap(m.indices[t + 1], m.indices[t + 2]);
    return m;
}

Mesh translated(Mesh m, glm::vec3 offset) {
    for (glm::vec3& p : m.positions) p += offset;
    return m;
}

Mesh phantom_mc(const Phantom& phantom) {
    return marching_cubes(phantom.volume, {phantom.iso, InsideIs::Above});
}

Mesh phantom_mc(const std::string& name, int size) {
    return phantom_mc(make_phantom(name, size));
}

SurfaceNet phantom_net(const Phantom& phantom) {
    return build_surface_net(segment_threshold(phantom.volume, phantom.iso));
}

} // namespace snert::test
