#include <gtest/gtest.h>

#include <algorithm>
#include <set>

#include "core/metrics.h"
#include "core/phantom.h"
#include "core/surface_net.h"
#include "core/triangulation.h"

using namespace snert;

namespace {

Segmentation empty_segmentation(glm::ivec3 dims) {
    return {dims, std::vector<std::uint8_t>(std::size_t(dims.x) * dims.y * dims.z, 0)};
}

void set_inside(Segmentation& s, int x, int y, int z) {
    s.inside[s.index(x, y, z)] = 1;
}

bool linked(const SurfaceNet& net, std::uint32_t a, std::uint32_t b) {
    for (std::uint32_t k = net.link_offsets[a]; k < net.link_offsets[a + 1]; ++k)
        if (net.links[k] == b) return true;
    return false;
}

glm::vec3 quad_normal(const SurfaceNet& net, const std::array<std::uint32_t, 4>& q) {
    const glm::vec3 a = net.positions[q[0]], b = net.positions[q[1]], c = net.positions[q[2]],
                    d = net.positions[q[3]];
    return glm::cross(c - a, d - b); // for a planar quad: twice its area along the normal
}

} // namespace

TEST(SurfaceNet, SingleVoxelGivesACube) {
    Segmentation s = empty_segmentation({3, 3, 3});
    set_inside(s, 1, 1, 1);
    const SurfaceNet net = build_surface_net(s);
    EXPECT_EQ(net.node_count(), 8u);
    EXPECT_EQ(net.link_count(), 12u);
    ASSERT_EQ(net.quads.size(), 6u);
    for (const auto& q : net.quads) {
        glm::vec3 centre(0.0f);
        for (auto id : q) centre += net.positions[id] / 4.0f;
        // Outward: the normal points away from the inside voxel at (1, 1, 1).
        EXPECT_GT(glm::dot(quad_normal(net, q), centre - glm::vec3(1.0f)), 0.0f);
    }
    for (std::size_t i = 0; i < net.node_count(); ++i)
        EXPECT_EQ(net.positions[i], glm::vec3(net.cells[i]) + 0.5f);
}

TEST(SurfaceNet, BoxHasExactCounts) {
    // A k^3 block of inside voxels: 6 k^2 boundary faces give 6 k^2 quads; the surface cells
    // are those touching the block: (k + 1)^3 - (k - 1)^3.
    for (int k = 1; k <= 4; ++k) {
        Segmentation s = empty_segmentation({k + 4, k + 4, k + 4});
        for (int z = 2; z < 2 + k; ++z)
            for (int y = 2; y < 2 + k; ++y)
                for (int x = 2; x < 2 + k; ++x) set_inside(s, x, y, z);
        const SurfaceNet net = build_surface_net(s);
        EXPECT_EQ(net.quads.size(), std::size_t(6 * k * k)) << k;
        EXPECT_EQ(net.node_count(),
                  std::size_t((k + 1) * (k + 1) * (k + 1) - (k - 1) * (k - 1) * (k - 1)))
            << k;
        const Mesh mesh = triangulate(net, net.positions);
        const Topology t = topology(mesh);
        EXPECT_TRUE(t.watertight) << k;
        EXPECT_TRUE(t.oriented) << k;
        EXPECT_EQ(t.euler, 2) << k;
        EXPECT_GT(enclosed_volume(mesh), 0.0) << k;
    }
}

TEST(SurfaceNet, OneVoxelPlateKeepsItsSidesApart) {
    Segmentation s = empty_segmentation({5, 6, 6});
    for (int z = 0; z < 6; ++z)
        for (int y = 0; y < 6; ++y) set_inside(s, 2, y, z);
    const SurfaceNet net = build_surface_net(s);
    // Cells x = 1 and x = 2 are on the two sides of the plate: never linked to each other.
    for (std::uint32_t a = 0; a < net.node_count(); ++a)
        for (std::uint32_t k = net.link_offsets[a]; k < net.link_offsets[a + 1]; ++k) {
            const glm::ivec3 d = net.cells[net.links[k]] - net.cells[a];
            EXPECT_EQ(d.x, 0) << "link across the plate";
        }
    EXPECT_EQ(net.node_count(), std::size_t(2 * 5 * 5));
}

TEST(SurfaceNet, LinksAreSymmetricAndQuadEdgesAreLinks) {
    const Phantom p = make_phantom("two-spheres", 24);
    const SurfaceNet net = build_surface_net(segment_threshold(p.volume, p.iso));
    ASSERT_GT(net.node_count(), 100u);
    for (std::uint32_t a = 0; a < net.node_count(); ++a) {
        EXPECT_LE(net.link_offsets[a + 1] - net.link_offsets[a], 6u);
        for (std::uint32_t k = net.link_offsets[a]; k < net.link_offsets[a + 1]; ++k)
            EXPECT_TRUE(linked(net, net.links[k], a));
    }
    for (const auto& q : net.quads)
        for (int i = 0; i < 4; ++i) EXPECT_TRUE(linked(net, q[i], q[(i + 1) % 4]));
    const Topology t = topology(triangulate(net, net.positions));
    EXPECT_TRUE(t.watertight);
    EXPECT_TRUE(t.oriented);
    EXPECT_EQ(t.euler, 2);
}

TEST(SurfaceNet, EmptyAndFullVolumes) {
    Segmentation empty = empty_segmentation({6, 6, 6});
    EXPECT_EQ(build_surface_net(empty).node_count(), 0u);
    Segmentation full = empty;
    std::fill(full.inside.begin(), full.inside.end(), 1);
    const SurfaceNet net = build_surface_net(full);
    EXPECT_EQ(net.node_count(), 0u);
    EXPECT_TRUE(net.quads.empty());
    EXPECT_EQ(build_surface_net(empty_segmentation({1, 5, 5})).node_count(), 0u);
}

TEST(Triangulation, ShorterDiagonalAndDelaunay) {
    // One quad, a kite: a-c is the short diagonal, but the angles opposite a-c are obtuse.
    SurfaceNet net;
    net.cells.assign(4, glm::ivec3(0));
    net.positions = {{0, 0, 0}, {1, -0.2f, 0}, {2, 0, 0}, {1, 3, 0}};
    net.quads = {{0, 1, 2, 3}};
    const Mesh shorter = triangulate(net, net.positions, TriangulationRule::ShorterDiagonal);
    // b-d has length 3.2, a-c has 2: split along a-c.
    EXPECT_EQ(shorter.indices, (std::vector<std::uint32_t>{0, 1, 2, 0, 2, 3}));
    // Angle at b is about 157 degrees, at d about 37: sum > 180, so a-c is not Delaunay.
    const Mesh delaunay = triangulate(net, net.positions, TriangulationRule::Delaunay);
    EXPECT_EQ(delaunay.indices, (std::vector<std::uint32_t>{0, 1, 3, 1, 2, 3}));
    // Both keep the quad's winding (+z).
    for (const Mesh* m : {&shorter, &delaunay})
        for (std::size_t t = 0; t < 2; ++t) {
            const glm::vec3 a = m->positions[m->indices[3 * t]];
            const glm::vec3 b = m->positions[m->indices[3 * t + 1]];
            const glm::vec3 c = m->positions[m->indices[3 * t + 2]];
            EXPECT_GT(glm::cross(b - a, c - a).z, 0.0f);
        }
}
