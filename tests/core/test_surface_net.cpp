#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <random>
#include <set>
#include <string>

#include "core/marching_cubes.h"
#include "core/metrics.h"
#include "core/phantom.h"
#include "core/surface_net.h"
#include "core/triangulation.h"
#include "support/test_meshes.h"

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
    const SurfaceNet net = test::phantom_net(p);
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

namespace {

// Calls visit(index) for every sample on the faces of the grid.
template <class Visit> void for_each_border_sample(glm::ivec3 dims, Visit&& visit) {
    std::size_t i = 0;
    for (int z = 0; z < dims.z; ++z)
        for (int y = 0; y < dims.y; ++y)
            for (int x = 0; x < dims.x; ++x, ++i)
                if (x == 0 || y == 0 || z == 0 || x == dims.x - 1 || y == dims.y - 1 ||
                    z == dims.z - 1)
                    visit(i);
}

// The net's mesh against Marching Cubes' mesh of the same segmentation (MC at 0.5 on the mask).
void expect_dual_of_marching_cubes(const Segmentation& s, const std::string& what) {
    const SurfaceNet net = build_surface_net(s);
    const Mesh mesh = triangulate(net, net.positions);
    const Volume mask = mask_volume(s, make_volume(s.dims));
    const Mesh mc = marching_cubes(mask, {0.5f, InsideIs::Above});
    ASSERT_EQ(mesh.indices.empty(), mc.indices.empty()) << what;
    if (mc.indices.empty()) return;
    const Topology t = topology(mesh), m = topology(mc);
    EXPECT_EQ(t.nonmanifold_edges, 0u) << what;
    EXPECT_TRUE(t.oriented) << what;
    EXPECT_EQ(t.boundary_edges == 0, m.boundary_edges == 0) << what;
    EXPECT_EQ(t.euler, m.euler) << what;
    EXPECT_EQ(t.manifold, m.manifold) << what;
}

} // namespace

TEST(SurfaceNet, NoiseGivesTheDualOfMarchingCubes) {
    std::mt19937 rng(7);
    for (int trial = 0; trial < 2000; ++trial) {
        const glm::ivec3 dims(3 + int(rng() % 5), 3 + int(rng() % 5), 3 + int(rng() % 5));
        Segmentation s = empty_segmentation(dims);
        const unsigned density = 1 + rng() % 7; // inside with probability density / 8
        for (auto& v : s.inside) v = (rng() & 7u) < density ? 1 : 0;
        // An outside border so the surface is closed.
        for_each_border_sample(dims, [&](std::size_t i) { s.inside[i] = 0; });
        expect_dual_of_marching_cubes(s, "trial " + std::to_string(trial));
        if (HasFailure()) break;
    }
}

TEST(SurfaceNet, EveryCaseWithSeveralPiecesGetsOneNodePerPiece) {
    // Each of the 256 cases alone in the middle of a 4^3 grid: the middle cell holds one node
    // per loop of its Marching Cubes case, and the whole net is MC's dual.
    int split_cases = 0;
    for (unsigned mask = 1; mask < 255; ++mask) {
        Segmentation s = empty_segmentation({4, 4, 4});
        for (int k = 0; k < 8; ++k)
            if ((mask >> k) & 1u)
                set_inside(s, 1 + (k & 1), 1 + ((k >> 1) & 1), 1 + ((k >> 2) & 1));
        const SurfaceNet net = build_surface_net(s);
        const int loops = detail::marching_cubes_case(mask).loop_count;
        int in_middle = 0;
        for (std::size_t i = 0; i < net.node_count(); ++i)
            if (net.cells[i] == glm::ivec3(1) && net.pieces[i] != kLinkNodePiece) {
                EXPECT_EQ(net.pieces[i], in_middle) << mask;
                ++in_middle;
                // A piece starts inside its own region.
                const NodeBox box = node_box(net, i);
                EXPECT_TRUE(glm::all(glm::greaterThanEqual(net.positions[i], box.lo)) &&
                            glm::all(glm::lessThanEqual(net.positions[i], box.hi)))
                    << mask;
            }
        EXPECT_EQ(in_middle, loops) << mask;
        split_cases += loops > 1;
        expect_dual_of_marching_cubes(s, "case " + std::to_string(mask));
        if (HasFailure()) break;
    }
    EXPECT_GT(split_cases, 0);
}

TEST(SurfaceNet, PiecesOfOneCellStartApartNearTheirCorners) {
    // Two diagonal inside corners: two corner pieces, each starting at its edges' centroid.
    Segmentation s = empty_segmentation({4, 4, 4});
    set_inside(s, 1, 1, 1);
    set_inside(s, 2, 2, 2);
    const SurfaceNet net = build_surface_net(s);
    std::vector<glm::vec3> starts;
    for (std::size_t i = 0; i < net.node_count(); ++i)
        if (net.cells[i] == glm::ivec3(1)) starts.push_back(net.positions[i] - glm::vec3(1.0f));
    ASSERT_EQ(starts.size(), 2u);
    EXPECT_NEAR(glm::length(starts[0] - glm::vec3(1.0f / 6.0f)), 0.0f, 1e-6f);
    EXPECT_NEAR(glm::length(starts[1] - glm::vec3(5.0f / 6.0f)), 0.0f, 1e-6f);
}

TEST(SurfaceNet, DoubledLinkGetsANodeOfItsOwn) {
    // A ring of voxels around an ambiguous face whose two segments join the same two pieces:
    // without a link node the edge between them would be in four triangles.
    Segmentation s = empty_segmentation({7, 4, 4});
    const char* slices[2] = {"0111110"
                             "0110110",
                             "0100110"
                             "0111110"}; // rows y = 1, 2
    for (int z = 0; z < 2; ++z)
        for (int y = 0; y < 2; ++y)
            for (int x = 0; x < 7; ++x)
                if (slices[z][y * 7 + x] == '1') set_inside(s, x, y + 1, z + 1);
    const SurfaceNet net = build_surface_net(s);
    const auto link_nodes = std::count(net.pieces.begin(), net.pieces.end(), kLinkNodePiece);
    EXPECT_GT(link_nodes, 0);
    EXPECT_FALSE(net.triangles.empty());
    expect_dual_of_marching_cubes(s, "ring");
}

TEST(SurfaceNet, IntegerNoiseThresholdedAtASampleValueIsMarchingCubesDual) {
    // Samples equal to the iso are inside, for the net as for MC.
    std::mt19937 rng(11);
    for (int trial = 0; trial < 500; ++trial) {
        const glm::ivec3 dims(6, 5, 7);
        Volume v = make_volume(dims);
        for (float& x : v.samples) x = float(rng() % 4);
        for_each_border_sample(dims, [&](std::size_t i) { v.samples[i] = 0.0f; });
        expect_dual_of_marching_cubes(segment_threshold(v, 2.0f), "trial " + std::to_string(trial));
        if (HasFailure()) break;
    }
}

TEST(SurfaceNet, TwoSpheresCreaseIsMarchingCubesDual) {
    for (int size : {24, 40, 64}) {
        const Phantom p = make_phantom("two-spheres", size);
        expect_dual_of_marching_cubes(segment_threshold(p.volume, p.iso),
                                      "size " + std::to_string(size));
    }
}

namespace {

// The net of a noise volume of 3 to 7 voxels a side, 2/8 to 6/8 of them inside: its surface
// reaches the volume's border at many places.
SurfaceNet random_net_of_noise(std::mt19937& rng) {
    const glm::ivec3 dims(3 + int(rng() % 5), 3 + int(rng() % 5), 3 + int(rng() % 5));
    Segmentation s = empty_segmentation(dims);
    const unsigned density = 2 + rng() % 5;
    for (auto& v : s.inside) v = (rng() & 7u) < density ? 1 : 0;
    return build_surface_net(s);
}

} // namespace

TEST(SurfaceNet, NoiseReachingTheBorderIsManifold) {
    // Open at the volume border: where a piece leaves the volume twice, a triangle joins its
    // node's two fans, so no vertex is pinched. (The Euler characteristic is MC's only where
    // the surface is closed: bits of surface entirely in border cells have no quad.)
    std::mt19937 rng(13);
    int bridged = 0;
    for (int trial = 0; trial < 1000; ++trial) {
        const SurfaceNet net = random_net_of_noise(rng);
        bridged += net.triangles.empty() ? 0 : 1;
        const Mesh mesh = triangulate(net, net.positions);
        if (mesh.indices.empty()) continue;
        const Topology t = topology(mesh);
        EXPECT_EQ(t.nonmanifold_edges, 0u) << trial;
        EXPECT_EQ(t.nonmanifold_vertices, 0u) << trial;
        EXPECT_TRUE(t.oriented) << trial;
        if (HasFailure()) break;
    }
    EXPECT_GT(bridged, 0);
}

TEST(SurfaceNet, StarsHoldEachNodesPolygonsInOrder) {
    // The stars as their definition has them, on the nets of the test above, where mending the
    // border adds triangles after the stars are first built (and adds them to the stars).
    std::mt19937 rng(13);
    int with_triangles = 0;
    for (int trial = 0; trial < 1000; ++trial) {
        const SurfaceNet net = random_net_of_noise(rng);
        with_triangles += net.triangles.empty() ? 0 : 1;
        std::vector<std::vector<std::uint32_t>> expected(net.node_count());
        std::array<std::uint32_t, 4> c{};
        for (std::uint32_t id = 0; id < net.quads.size() + net.triangles.size(); ++id)
            for (int k = 0, n = polygon_corners(net, id, c); k < n; ++k)
                expected[c[std::size_t(k)]].push_back(id);
        ASSERT_EQ(net.star_offsets.size(), net.node_count() + 1) << trial;
        for (std::uint32_t node = 0; node < net.node_count(); ++node) {
            const std::vector<std::uint32_t> star(net.star.begin() + net.star_offsets[node],
                                                  net.star.begin() + net.star_offsets[node + 1]);
            ASSERT_EQ(star, expected[node]) << "trial " << trial << ", node " << node;
        }
        ASSERT_EQ(net.star_offsets.back(), net.star.size()) << trial;
    }
    EXPECT_GT(with_triangles, 0);
}
