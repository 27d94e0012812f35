// Exact predicates against integer arithmetic, triangle pairs made by hand for every rule of
// triangle_intersection.h, and the mesh count against all pairs.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <utility>

#include "core/triangle_intersection.h"
#include "support/test_meshes.h"

namespace snert {
namespace {

using V = glm::vec3;

// The answer must not depend on the order of the triangles or the rotation of their corners.
void expect_pair(bool expected, V a0, V a1, V a2, V b0, V b1, V b2) {
    const V a[3] = {a0, a1, a2}, b[3] = {b0, b1, b2};
    for (int r = 0; r < 3; ++r)
        for (int s = 0; s < 3; ++s) {
            const V ar[3] = {a[r], a[(r + 1) % 3], a[(r + 2) % 3]};
            const V bs[3] = {b[s], b[(s + 1) % 3], b[(s + 2) % 3]};
            EXPECT_EQ(triangles_intersect(ar, bs), expected) << "rotation " << r << ", " << s;
            EXPECT_EQ(triangles_intersect(bs, ar), expected)
                << "swapped, rotation " << r << ", " << s;
        }
}

// ---------------------------------------------------------------------------------------------
// Exact signs: points on a 2^-20 grid, so the determinant scaled by 2^60 is an integer.

constexpr double kGrid = 0x1p-20;
__extension__ typedef __int128 Int128; // products of three 25-bit differences

int exact_orient3d(V a, V b, V c, V d) {
    auto k = [](float v) { return Int128(std::llround(double(v) / kGrid)); };
    const Int128 adx = k(a.x) - k(d.x), ady = k(a.y) - k(d.y), adz = k(a.z) - k(d.z);
    const Int128 bdx = k(b.x) - k(d.x), bdy = k(b.y) - k(d.y), bdz = k(b.z) - k(d.z);
    const Int128 cdx = k(c.x) - k(d.x), cdy = k(c.y) - k(d.y), cdz = k(c.z) - k(d.z);
    const Int128 det = adx * (bdy * cdz - bdz * cdy) - ady * (bdx * cdz - bdz * cdx) +
                       adz * (bdx * cdy - bdy * cdx);
    return det > 0 ? 1 : det < 0 ? -1 : 0;
}

TEST(Orient, ExactOnNearlyCoplanarPoints) {
    std::mt19937 rng(7);
    // Combinations a + s (b - a) + t (c - a) with small integer s, t stay on the grid and
    // within float's 24 bits: exactly coplanar before the nudge.
    std::uniform_int_distribution<int> coord(-(1 << 20), (1 << 20));
    std::uniform_int_distribution<int> unit(-2, 3);
    std::uniform_int_distribution<int> nudge(-2, 2);
    auto on_grid = [](double units) { return float(std::round(units) * kGrid); };
    int zeros = 0, filter_hard = 0;
    for (int i = 0; i < 20000; ++i) {
        const V a(coord(rng) * kGrid, coord(rng) * kGrid, coord(rng) * kGrid);
        const V b(coord(rng) * kGrid, coord(rng) * kGrid, coord(rng) * kGrid);
        const V c(coord(rng) * kGrid, coord(rng) * kGrid, coord(rng) * kGrid);
        // d near the plane of a, b, c: off by a few grid steps at most.
        const double s = unit(rng), t = unit(rng); // integers
        V d;
        for (int k = 0; k < 3; ++k)
            d[k] = on_grid((a[k] + s * (b[k] - a[k]) + t * (c[k] - a[k])) / kGrid + nudge(rng));
        const int expected = exact_orient3d(a, b, c, d);
        ASSERT_EQ(orient3d(a, b, c, d), expected) << i;
        zeros += expected == 0;
        const glm::dvec3 ad = glm::dvec3(a) - glm::dvec3(d), bd = glm::dvec3(b) - glm::dvec3(d),
                         cd = glm::dvec3(c) - glm::dvec3(d);
        const double naive = glm::dot(ad, glm::cross(bd, cd));
        filter_hard += (naive > 0) - (naive < 0) != expected;
    }
    EXPECT_GT(zeros, 0);       // exactly coplanar cases were among them
    EXPECT_GT(filter_hard, 0); // and cases where plain double arithmetic gets the sign wrong
}

// The exact stage takes integers when each axis's coordinates lie within 15 binades of each
// other, and the expansions beyond. A lattice tetrahedron of volume 1/6 (or a flat one) sheared
// by integer matrices of determinant 1 keeps its determinant, 1 or 0, under coordinates of
// millions of grid steps: a determinant far below the filter's bound, which only an exact stage
// gets right. Moved so that one coordinate is a few steps from zero (or not), an axis's spread
// falls on either side of the limit.
TEST(Orient, ExactAcrossTheIntegerStagesLimit) {
    std::mt19937 rng(13);
    std::uniform_int_distribution<int> shear(-90, 90), offset(-(1 << 22), 1 << 22);
    std::uniform_int_distribution<int> pick(0, 3), axis(0, 2), near_zero(-3, 3);
    int decided = 0, decided_2d = 0;
    for (int i = 0; i < 20000; ++i) {
        glm::dvec3 p[4] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
        if (i % 5 == 0) p[3] = {1, 1, 0};         // flat: determinant 0
        for (int round = 0; round < 3; ++round) { // x += n y, y += n z, z += n x: determinant 1
            const double n[3] = {double(shear(rng)), double(shear(rng)), double(shear(rng))};
            for (glm::dvec3& q : p) {
                q.x += n[0] * q.y;
                q.y += n[1] * q.z;
                q.z += n[2] * q.x;
            }
        }
        glm::dvec3 move(offset(rng), offset(rng), offset(rng));
        const int k = pick(rng), a = axis(rng);
        if (i % 2 == 0) move[a] = near_zero(rng) - p[k][a]; // p[k] a few steps from zero on a
        V q[4];
        bool on_grid = true;
        for (int j = 0; j < 4; ++j)
            for (int c = 0; c < 3; ++c) {
                const double units = p[j][c] + move[c];
                q[j][c] = float(units * kGrid);
                on_grid = on_grid && double(q[j][c]) == units * kGrid && std::abs(units) < 0x1p40;
            }
        if (!on_grid) continue; // a coordinate beyond a float's 24 bits
        const int expected = exact_orient3d(q[0], q[1], q[2], q[3]);
        ASSERT_EQ(orient3d(q[0], q[1], q[2], q[3]), expected) << i;
        ASSERT_EQ(orient3d(q[3], q[2], q[1], q[0]), expected) << i; // two swaps: the same sign
        decided += expected != 0;
        // The same in the plane: a lattice triangle of area 1/2 (or a flat one), sheared. Products
        // of two floats' differences are exact in double, so the filter settles all but the flat
        // ones, which reach the exact stage and must come out 0.
        glm::dvec2 t[3] = {{0, 0}, {1, 0}, {0, 1}};
        if (i % 5 == 0) t[2] = {2, 0};
        for (int round = 0; round < 3; ++round) { // x += n y, y += n x, x += n y
            const double n = shear(rng);
            for (glm::dvec2& r : t) r[round % 2] += n * r[1 - round % 2];
        }
        glm::vec2 u[3];
        for (int j = 0; j < 3; ++j)
            for (int c = 0; c < 2; ++c) {
                const double units = t[j][c] + move[c];
                u[j][c] = float(units * kGrid);
                on_grid = on_grid && double(u[j][c]) == units * kGrid;
            }
        if (!on_grid) continue;
        const int expected_2d = -exact_orient3d(V(u[0], 0), V(u[1], 0), V(u[2], 0), V(0, 0, 1));
        ASSERT_EQ(orient2d(u[0], u[1], u[2]), expected_2d) << i; // above z = 0: orient3d flips
        decided_2d += expected_2d != 0;
    }
    EXPECT_GT(decided, 5000);
    EXPECT_GT(decided_2d, 5000);
}

TEST(Orient, ExactWhereDifferencesNeedTwoDoubles) {
    // Corners 2^60 times apart: a - d does not fit one double (its lo part is not zero), and the
    // filter's error bound dwarfs the determinant, so the exact sum decides with every part.
    const float big = 0x1p30f, small = 0x1p-30f;
    const V a(big, 0, 0), b(0, big, 0), c(-big, -big, 0); // counter-clockwise seen from +z
    for (const float z : {0.0f, 0x1p-60f, -0x1p-60f, 0x1p-100f}) {
        const V d(small, 3 * small, z);
        const int expected = z > 0 ? -1 : z < 0 ? 1 : 0;
        EXPECT_EQ(orient3d(a, b, c, d), expected) << z;
        EXPECT_EQ(orient3d(d, c, b, a), expected) << z; // two swaps: the same sign
    }
}

TEST(Orient, Orient2dNearCollinear) {
    // Shewchuk's example: points near the line y = x, an ulp apart, against (12, 12), (24, 24).
    const float ulp = std::nextafter(0.5f, 1.0f) - 0.5f;
    for (int i = 0; i < 64; ++i)
        for (int j = 0; j < 64; ++j) {
            const glm::vec2 p(0.5f + float(i) * ulp, 0.5f + float(j) * ulp);
            const int expected = i < j ? 1 : i > j ? -1 : 0; // left of the line y = x: ccw
            ASSERT_EQ(orient2d(p, {12.0f, 12.0f}, {24.0f, 24.0f}), expected) << i << " " << j;
        }
}

// Points sharing a coordinate lie in an axis-aligned plane (or on an axis-parallel line): the
// predicates answer 0 without their exact stage, and points off that plane or line by one grid
// step still get the exact sign, whatever the size of the other coordinates.
TEST(Orient, PointsSharingACoordinateAreExactlyCoplanar) {
    std::mt19937 rng(11);
    std::uniform_int_distribution<int> coord(-(1 << 20), (1 << 20));
    std::uniform_int_distribution<int> step(-1, 1);
    const auto on_grid = [&] { return float(coord(rng) * kGrid); };
    int off = 0;
    for (int i = 0; i < 20000; ++i) {
        const int axis = i % 3;
        const float shared = on_grid();
        V p[4];
        for (V& q : p) {
            q = V(on_grid(), on_grid(), on_grid());
            q[axis] = shared;
        }
        ASSERT_EQ(orient3d(p[0], p[1], p[2], p[3]), 0) << i;
        ASSERT_EQ(orient3d(p[3], p[1], p[0], p[2]), 0) << i;
        // One corner a grid step off the plane: the sign of the exact determinant.
        p[i % 4][axis] = float((double(shared) / kGrid + step(rng)) * kGrid);
        off += p[i % 4][axis] != shared;
        ASSERT_EQ(orient3d(p[0], p[1], p[2], p[3]), exact_orient3d(p[0], p[1], p[2], p[3])) << i;
        // In the plane: three points on a line parallel to an axis, then one moved off it.
        const glm::vec2 a(shared, on_grid()), b(shared, on_grid()), c(shared, on_grid());
        ASSERT_EQ(orient2d(a, b, c), 0) << i;
        ASSERT_EQ(orient2d({a.y, a.x}, {b.y, b.x}, {c.y, c.x}), 0) << i;
        const glm::vec2 moved(shared + float(kGrid), c.y);
        const int expected = exact_orient3d(V(a, 0), V(b, 0), V(moved, 0), V(0, 0, 1));
        ASSERT_EQ(orient2d(a, b, moved), -expected) << i; // d above: orient3d = -orient2d
    }
    EXPECT_GT(off, 10000); // most cases had a corner off the plane
}

TEST(Orient, Orient3dSignConvention) {
    // d above (on the normal's side of) the counter-clockwise triangle: negative.
    EXPECT_EQ(orient3d({0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}), -1);
    EXPECT_EQ(orient3d({0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, -1}), 1);
    EXPECT_EQ(orient3d({0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {5, 7, 0}), 0);
}

// ---------------------------------------------------------------------------------------------
// Pairs without a shared corner.

TEST(TriangleIntersection, Disjoint) {
    expect_pair(false, {0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {1, 0, 1}, {0, 1, 1});
    // Planes cross, triangles do not reach each other.
    expect_pair(false, {0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {2, 2, -1}, {3, 2, 1}, {2, 3, 1});
}

TEST(TriangleIntersection, Crossing) {
    // Two triangles through each other like links of a chain.
    expect_pair(true, {-1, 0, 0}, {1, 0, 0}, {0, 2, 0}, {0, 1, -1}, {0, 1, 1}, {0, -1, 0});
}

TEST(TriangleIntersection, Piercing) {
    // A thin triangle stabs the middle of a big one.
    expect_pair(true, {0, 0, 0}, {4, 0, 0}, {0, 4, 0}, {1, 1, -1}, {1.1f, 1, 1}, {1, 1.1f, 1});
}

TEST(TriangleIntersection, TouchingCounts) {
    // A corner of b on the face of a, b above: touching counts, as in TetGen.
    expect_pair(true, {0, 0, 0}, {4, 0, 0}, {0, 4, 0}, {1, 1, 0}, {1, 2, 1}, {2, 1, 1});
    // A corner of b on an edge of a.
    expect_pair(true, {0, 0, 0}, {4, 0, 0}, {0, 4, 0}, {2, 0, 0}, {2, -1, 1}, {3, -1, 1});
    // An edge of b lying across a.
    expect_pair(true, {0, 0, 0}, {4, 0, 0}, {0, 4, 0}, {1, -1, 0}, {1, 3, 0}, {1, 1, 2});
    // A corner on a corner at the same position is shared (below); one float step away it is not.
    const float up = std::nextafter(0.0f, 1.0f);
    expect_pair(false, {0, 0, 0}, {4, 0, 0}, {0, 4, 0}, {1, 1, up}, {1, 2, 1}, {2, 1, 1});
}

TEST(TriangleIntersection, Coplanar) {
    // Overlapping, nested and disjoint in the plane z = 0.
    expect_pair(true, {0, 0, 0}, {4, 0, 0}, {0, 4, 0}, {1, 1, 0}, {5, 1, 0}, {1, 5, 0});
    expect_pair(true, {0, 0, 0}, {4, 0, 0}, {0, 4, 0}, {1, 1, 0}, {2, 1, 0}, {1, 2, 0});
    expect_pair(false, {0, 0, 0}, {4, 0, 0}, {0, 4, 0}, {3, 3, 0}, {5, 3, 0}, {3, 5, 0});
    // Disjoint in a tilted plane (x + y + z = 3), where the 2D projection decides.
    expect_pair(false, {3, 0, 0}, {0, 3, 0}, {0, 0, 3}, {4, 1, -2}, {5, 0, -2}, {5, 1, -3});
    // Coplanar, touching along part of an edge.
    expect_pair(true, {0, 0, 0}, {4, 0, 0}, {0, 4, 0}, {1, 0, 0}, {2, 0, 0}, {1, -1, 0});
}

// ---------------------------------------------------------------------------------------------
// Shared corners and edges.

TEST(TriangleIntersection, SharedEdge) {
    const V p{0, 0, 0}, q{1, 0, 0};
    expect_pair(false, p, q, {0, 1, 0}, q, p, {0, 0, 1});        // right dihedral
    expect_pair(false, p, q, {0, 1, 0}, q, p, {0, -1, 0});       // flat, opposite sides
    expect_pair(false, p, q, {0, 1, 0}, q, p, {0.5f, 1, 0.01f}); // very sharp dihedral
    expect_pair(true, p, q, {0, 1, 0}, q, p, {0.5f, 1, 0});      // folded flat onto each other
    expect_pair(true, p, q, {0, 1, 0}, p, q, {3, 2, 0});         // folded, the other winding
}

TEST(TriangleIntersection, SharedVertex) {
    const V p{0, 0, 0};
    // Two faces of a fan: meet only at p.
    expect_pair(false, p, {1, 0, 0}, {0, 1, 0}, p, {0, 0, 1}, {-1, 0, 0});
    // b pierces a near p (b's opposite edge passes under a, b's plane crosses a).
    expect_pair(true, p, {4, 0, 0}, {0, 4, 0}, p, {1, 1, 1}, {1, 1, -1});
    // b touches a's opposite edge.
    expect_pair(true, p, {4, 0, 0}, {0, 4, 0}, p, {2, 2, 0}, {2, 2, 3});
    // Coplanar, overlapping sectors.
    expect_pair(true, p, {4, 0, 0}, {0, 4, 0}, p, {4, 1, 0}, {4, 4, 0});
    // Coplanar, sectors meeting only at p.
    expect_pair(false, p, {4, 0, 0}, {0, 4, 0}, p, {-1, -1, 0}, {-1, -4, 0});
    // Coplanar, an edge of one running along an edge of the other beyond p.
    expect_pair(true, p, {4, 0, 0}, {0, 4, 0}, p, {2, 0, 0}, {2, -1, 0});
    // Not coplanar, an edge along an edge beyond p.
    expect_pair(true, p, {4, 0, 0}, {0, 4, 0}, p, {2, 0, 0}, {2, 0, 1});
}

TEST(TriangleIntersection, Duplicate) {
    expect_pair(true, {0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 0}, {0, 1, 0}, {1, 0, 0});
}

TEST(TriangleIntersection, NearDegenerate) {
    // A needle one float step from being flat, crossing a big triangle.
    const float e = std::nextafter(1.0f, 2.0f) - 1.0f;
    expect_pair(true, {0, 0, 0}, {4, 0, 0}, {0, 4, 0}, {1, 1, -1}, {1, 1, 1}, {1 + e, 1, 1});
    // A tilted triangle and its copy lifted by 1e-6 in z (more than the rounding of the sums):
    // the copy lies strictly above a's plane, a hair's breadth away.
    const V a0{0.1f, 0.2f, 0.3f}, a1{1.7f, 0.4f, 0.9f}, a2{0.3f, 1.9f, 0.2f};
    const V up{0.0f, 0.0f, 1e-6f};
    expect_pair(false, a0, a1, a2, a0 + up, a1 + up, a2 + up);
    // The same copy hinged at a0: it touches a at the shared corner only.
    expect_pair(false, a0, a1, a2, a0, a1 + up, a2 + up);
    // Lowered instead of lifted at one corner, the hinged copy crosses a near that corner's edge.
    expect_pair(true, a0, a1, a2, a0, a1 + up, a2 - up);
    // The exact collinear case: a flat triangle across a (treated as its edges).
    expect_pair(true, {0, 0, 0}, {4, 0, 0}, {0, 4, 0}, {1, 1, -1}, {1, 1, 0}, {1, 1, 1});
    expect_pair(false, {0, 0, 0}, {4, 0, 0}, {0, 4, 0}, {1, 1, 1}, {1, 1, 2}, {1, 1, 3});
    // Flat along a shared edge (its third corner on the edge): folded onto the other, as TetGen
    // reports it; with two coincident corners it is a mere segment on the edge.
    expect_pair(true, {0, 0, 0}, {4, 0, 0}, {0, 4, 0}, {0, 0, 0}, {2, 0, 0}, {4, 0, 0});
    expect_pair(false, {0, 0, 0}, {4, 0, 0}, {0, 4, 0}, {0, 0, 0}, {0, 0, 0}, {4, 0, 0});
    // Two coincident corners: no facet, even where the segment pierces the other triangle.
    expect_pair(false, {0, 0, 0}, {4, 0, 0}, {0, 4, 0}, {1, 1, -1}, {1, 1, -1}, {1, 1, 1});
    // Flat, one shared corner, the rest pointing away: touches only there.
    expect_pair(false, {0, 0, 0}, {4, 0, 0}, {0, 4, 0}, {0, 0, 0}, {-1, -1, 0}, {-2, -2, 0});
}

TEST(TriangleIntersection, NonFiniteIntersectsNothing) {
    const float nan = std::nanf("");
    expect_pair(false, {0, 0, 0}, {4, 0, 0}, {0, 4, 0}, {1, 1, -1}, {1, 1, 1}, {nan, 1, 1});
}

TEST(TriangleIntersection, OrderFreeOnASmallGrid) {
    // Corners on a 3 x 3 x 3 grid: shared corners, coplanar and collinear cases galore. The
    // answer may not depend on which triangle comes first, on rotation or on winding.
    std::mt19937 rng(11);
    std::uniform_int_distribution<int> coord(0, 2);
    auto corner = [&] { return V(float(coord(rng)), float(coord(rng)), float(coord(rng))); };
    int hits = 0;
    for (int i = 0; i < 3000; ++i) {
        const V a[3] = {corner(), corner(), corner()}, b[3] = {corner(), corner(), corner()};
        const bool base = triangles_intersect(a, b);
        hits += base;
        const V a_reversed[3] = {a[0], a[2], a[1]};
        ASSERT_EQ(triangles_intersect(a_reversed, b), base) << i;
        for (int r = 0; r < 3; ++r) {
            const V br[3] = {b[r], b[(r + 1) % 3], b[(r + 2) % 3]};
            ASSERT_EQ(triangles_intersect(br, a), base) << i;
        }
    }
    EXPECT_GT(hits, 300);
    EXPECT_LT(hits, 2900);
}

TEST(TriangleIntersection, GeneralPositionShortcutAgreesWithTheEdgeTests) {
    // Random pairs with no, one and two shared corners, in a unit box (most pairs in general
    // position, crossing or not), on a 3 x 3 x 3 grid (coplanar and collinear corners) and on a
    // fine grid around one plane (signs the filter cannot settle): triangles_intersect, which
    // settles pairs in general position from orientations alone, against the edge tests.
    std::mt19937 rng(23);
    std::uniform_real_distribution<float> unit(0.0f, 1.0f);
    std::uniform_int_distribution<int> small(0, 2), fine(-3, 3), pick(0, 2);
    const auto unit_corner = [&] { return V(unit(rng), unit(rng), unit(rng)); };
    const auto grid_corner = [&] {
        return V(float(small(rng)), float(small(rng)), float(small(rng)));
    };
    const auto near_plane_corner = [&] {
        return V(unit(rng), unit(rng), 0.5f + float(fine(rng)) * 0x1p-22f);
    };
    int outcomes[3][2] = {}; // [shared corners][intersecting]
    for (int i = 0; i < 60000; ++i) {
        const int kind = i % 3;
        const auto corner = [&] {
            return kind == 0 ? unit_corner() : kind == 1 ? grid_corner() : near_plane_corner();
        };
        V a[3] = {corner(), corner(), corner()}, b[3] = {corner(), corner(), corner()};
        const int shared = (i / 3) % 3;
        const int from = pick(rng);
        if (shared >= 1) b[0] = a[from];
        // Two shared: b = (a[from], b1, a[from + 1]), wound against a as in a mesh.
        if (shared == 2) b[2] = a[(from + 1) % 3];
        const bool expected = detail::triangles_intersect_by_edges(a, b);
        ASSERT_EQ(triangles_intersect(a, b), expected) << "pair " << i;
        ASSERT_EQ(triangles_intersect(b, a), expected) << "pair " << i << ", swapped";
        if (kind == 0) ++outcomes[shared][expected ? 1 : 0];
    }
    // Both answers in each case, many times over: the shortcut's every branch was taken.
    for (int shared = 0; shared < 2; ++shared)
        for (int hit = 0; hit < 2; ++hit) EXPECT_GT(outcomes[shared][hit], 500) << shared << hit;
    EXPECT_GT(outcomes[2][0], 5000);
}

// ---------------------------------------------------------------------------------------------
// Mesh counts.

// The mesh's intersecting pairs by triangles_intersect on every pair, the count's reference.
std::size_t intersecting_pairs_one_by_one(const Mesh& mesh) {
    std::size_t count = 0;
    for (std::size_t t = 0; t < mesh.triangle_count(); ++t)
        for (std::size_t u = t + 1; u < mesh.triangle_count(); ++u) {
            glm::vec3 a[3], b[3];
            for (int k = 0; k < 3; ++k) {
                a[k] = mesh.positions[mesh.indices[3 * t + std::size_t(k)]];
                b[k] = mesh.positions[mesh.indices[3 * u + std::size_t(k)]];
            }
            count += triangles_intersect(a, b) ? 1 : 0;
        }
    return count;
}

TEST(SelfIntersections, ClosedSphereHasNone) {
    const Mesh mesh = test::phantom_mc("sphere", 32);
    ASSERT_GT(mesh.triangle_count(), 1000u);
    EXPECT_EQ(count_self_intersections(mesh), 0u);
}

TEST(SelfIntersections, PushedThroughVertex) {
    Mesh mesh = test::phantom_mc("sphere", 32);
    // The vertex farthest along +x, mirrored through the centre and beyond the far side: its
    // triangles become spikes that pierce the opposite wall.
    std::size_t far = 0;
    for (std::size_t v = 0; v < mesh.positions.size(); ++v)
        if (mesh.positions[v].x > mesh.positions[far].x) far = v;
    const glm::vec3 centre(15.5f);
    mesh.positions[far] = centre - 1.3f * (mesh.positions[far] - centre);
    const SelfIntersections found = self_intersections(mesh, 8);
    EXPECT_GT(found.count, 0u);
    ASSERT_FALSE(found.pairs.empty());
    for (const auto& [t, u] : found.pairs) EXPECT_LT(t, u);
    // Every pair involves one of the moved vertex's triangles.
    for (const auto& [t, u] : found.pairs) {
        bool moved = false;
        for (int k = 0; k < 3; ++k)
            moved = moved || mesh.indices[3 * t + std::size_t(k)] == far ||
                    mesh.indices[3 * u + std::size_t(k)] == far;
        EXPECT_TRUE(moved);
    }
}

TEST(SelfIntersections, GridMatchesAllPairs) {
    // A small sphere with every vertex jittered hard: many intersecting pairs, all kinds.
    Mesh mesh = test::phantom_mc("sphere", 12);
    std::mt19937 rng(3);
    std::uniform_real_distribution<float> jitter(-0.6f, 0.6f);
    for (glm::vec3& p : mesh.positions) p += glm::vec3(jitter(rng), jitter(rng), jitter(rng));
    const std::size_t brute = intersecting_pairs_one_by_one(mesh);
    EXPECT_GT(brute, 0u);
    const SelfIntersections found = self_intersections(mesh, 1u << 20);
    EXPECT_EQ(found.count, brute);
    EXPECT_EQ(found.pairs.size(), brute);
    EXPECT_TRUE(std::is_sorted(found.pairs.begin(), found.pairs.end()));
    // A cap keeps the least pairs (each part of the grid drops its larger ones as it goes, past
    // twice the cap and 64) and the whole count.
    ASSERT_GT(brute, 100u);
    for (const std::size_t cap : {1u, 7u, 60u}) {
        const SelfIntersections capped = self_intersections(mesh, cap);
        EXPECT_EQ(capped.count, brute);
        ASSERT_EQ(capped.pairs.size(), cap);
        EXPECT_TRUE(std::equal(capped.pairs.begin(), capped.pairs.end(), found.pairs.begin()))
            << cap;
    }
}

TEST(SelfIntersections, GridMatchesAllPairsOnALattice) {
    // Corners on a 3 x 3 x 2 lattice, each lattice point twice (two vertices at one position):
    // exactly coplanar pairs everywhere, corners shared by index and by position alone, which
    // the count's shortcuts (a shared index lies on the plane) must tell apart.
    Mesh mesh;
    for (int copy = 0; copy < 2; ++copy)
        for (int z = 0; z < 2; ++z)
            for (int y = 0; y < 3; ++y)
                for (int x = 0; x < 3; ++x) mesh.positions.emplace_back(x, y, z);
    std::mt19937 rng(17);
    std::uniform_int_distribution<std::uint32_t> vertex(0,
                                                        std::uint32_t(mesh.positions.size()) - 1);
    while (mesh.triangle_count() < 400) {
        const std::uint32_t a = vertex(rng), b = vertex(rng), c = vertex(rng);
        if (mesh.positions[a] == mesh.positions[b] || mesh.positions[b] == mesh.positions[c] ||
            mesh.positions[c] == mesh.positions[a])
            continue;
        mesh.indices.insert(mesh.indices.end(), {a, b, c});
    }
    const std::size_t brute = intersecting_pairs_one_by_one(mesh);
    const std::size_t pairs = mesh.triangle_count() * (mesh.triangle_count() - 1) / 2;
    EXPECT_GT(brute, pairs / 10);
    EXPECT_LT(brute, pairs);
    EXPECT_EQ(count_self_intersections(mesh), brute);
    // The few-marked path (a grid of the marked triangles alone) against the same pairs.
    std::vector<std::uint8_t> marked(mesh.triangle_count(), 0);
    for (std::size_t t = 0; t < marked.size(); t += 25) marked[t] = 1;
    std::size_t with_marked = 0;
    for (const auto& [t, u] : self_intersections(mesh, pairs).pairs)
        with_marked += marked[t] || marked[u];
    EXPECT_EQ(intersections_involving(mesh, marked, pairs).count, with_marked);
}

TEST(SelfIntersections, CornerOnTheOtherPlaneTouches) {
    // Triangle abc, and a triangle with one corner exactly in abc's plane and inside it (a
    // quarter along each side from a) and the two others well off the plane on one side: they
    // touch, so the pair intersects. On a 2^-20 grid the determinants need more than a double's
    // 53 bits, and in plain double arithmetic the touching corner's side often comes out
    // nonzero, either way.
    std::mt19937 rng(23);
    std::uniform_int_distribution<int> coord(0, 1 << 20);
    auto on_grid = [&] { return float(coord(rng)) * 0x1p-20f; };
    int pairs = 0, rounded = 0;
    while (pairs < 500) {
        const V a(on_grid(), on_grid(), on_grid()), b(on_grid(), on_grid(), on_grid()),
            c(on_grid(), on_grid(), on_grid());
        const glm::vec3 n = glm::cross(b - a, c - a);
        if (glm::length(n) < 0.05f) continue;
        const V d = a + 0.25f * (b - a) + 0.25f * (c - a); // exact: a 2^-22 grid, under 1
        const V lift = 0.5f * glm::normalize(n);
        const Mesh mesh{{a, b, c, d, d + lift + 0.3f * (b - a), d + lift + 0.3f * (c - a)},
                        {0, 1, 2, 3, 4, 5}};
        ASSERT_EQ(count_self_intersections(mesh), 1u) << pairs;
        const glm::dvec3 w = glm::dvec3(d) - glm::dvec3(a);
        rounded += glm::dot(w, glm::cross(glm::dvec3(b) - glm::dvec3(a),
                                          glm::dvec3(c) - glm::dvec3(a))) != 0.0;
        ++pairs;
    }
    EXPECT_GT(rounded, 50); // plain double arithmetic put d off the plane that often
}

TEST(SelfIntersections, InvolvingMarkedTrianglesMatchesTheFullList) {
    // The jittered sphere again; every third triangle marked (the whole mesh's grid), then every
    // twentieth (a grid of the marked ones alone): exactly the full list's pairs with a marked
    // triangle, in the same order, each once (also where both are marked).
    Mesh mesh = test::phantom_mc("sphere", 12);
    std::mt19937 rng(5);
    std::uniform_real_distribution<float> jitter(-0.6f, 0.6f);
    for (glm::vec3& p : mesh.positions) p += glm::vec3(jitter(rng), jitter(rng), jitter(rng));
    const SelfIntersections all = self_intersections(mesh, 1u << 20);
    for (const std::size_t stride : {3u, 20u}) {
        SCOPED_TRACE(stride);
        std::vector<std::uint8_t> marked(mesh.triangle_count(), 0);
        for (std::size_t t = 0; t < marked.size(); t += stride) marked[t] = 1;
        std::vector<std::pair<std::uint32_t, std::uint32_t>> expected;
        std::size_t both = 0;
        for (const auto& [t, u] : all.pairs)
            if (marked[t] || marked[u]) {
                expected.emplace_back(t, u);
                both += marked[t] && marked[u];
            }
        if (stride == 3) {
            ASSERT_GT(both, 0u);
        }
        ASSERT_GT(expected.size(), 5u);
        ASSERT_LT(expected.size(), all.pairs.size());
        const SelfIntersections some = intersections_involving(mesh, marked, 1u << 20);
        EXPECT_EQ(some.count, expected.size());
        EXPECT_EQ(some.pairs, expected);
        const SelfIntersections capped = intersections_involving(mesh, marked, 5);
        EXPECT_EQ(capped.count, expected.size());
        EXPECT_EQ(capped.pairs, std::vector(expected.begin(), expected.begin() + 5));
    }
    EXPECT_THROW(intersections_involving(mesh, std::vector<std::uint8_t>(3, 1)),
                 std::invalid_argument);
}

TEST(SelfIntersections, EmptyAndBadMesh) {
    EXPECT_EQ(count_self_intersections(Mesh{}), 0u);
    Mesh bad;
    bad.positions = {{0, 0, 0}};
    bad.indices = {0, 0, 1};
    EXPECT_THROW(count_self_intersections(bad), std::invalid_argument);
}

} // namespace
} // namespace snert
