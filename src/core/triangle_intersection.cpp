// Exact triangle-triangle intersection and the mesh's self-intersection count.
//
// This work is based on:
//  - Shewchuk, Adaptive Precision Floating-Point Arithmetic and Fast Robust Geometric
//    Predicates (1997): the orient3d / orient2d expressions and their forward error bounds
//    (o3derrboundA, ccwerrboundA), TwoSum, TwoDiff, and Grow-Expansion for the exact sum;
//  - TwoProduct by a fused multiply-add (Ogita, Rump and Oishi 2005);
//  - Devillers and Guigue, Faster Triangle-Triangle Intersection Tests (2002): the rejection of
//    a pair by the sides of the other triangle's plane, which settles almost every pair, and,
//    for pairs in general position, the comparison of the two triangles' segments on the line
//    where their planes cross by orientations alone;
//  - the decomposition of the closed test into edges: two closed triangles (coplanar or not)
//    meet exactly when an edge of one meets the other. Not coplanar, their common points lie on
//    the planes' line, where each triangle is an interval whose ends lie on its edges, and two
//    intervals that overlap share an end of one of them; coplanar, two convex polygons meet
//    when their boundaries cross or one holds the other, whose edges then lie inside it.
// A shared corner p reduces to the edges opposite p: the triangles' common part is convex and
// holds p, and when it holds more than p its boundary runs along an opposite edge (a polygon or
// segment from p bounded only by the sides through p is the point p alone).
//
// Compiled with -ffp-contract=off (src/core/CMakeLists.txt): the error-free transformations and
// the error bounds assume every operation rounds once, as written.
#include "triangle_intersection.h"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <optional>
#include <stdexcept>
#include <string>

#include "cell_lists.h"
#include "huge_pages.h"
#include "parallel.h"

namespace snert {
namespace {

// ---------------------------------------------------------------------------------------------
// Exact arithmetic.

constexpr double kEpsilon = 0x1p-53; // half an ulp of 1: the unit roundoff
constexpr double kOrient3dBound = (7.0 + 56.0 * kEpsilon) * kEpsilon;
constexpr double kOrient2dBound = (3.0 + 16.0 * kEpsilon) * kEpsilon;

struct Two {
    double hi, lo; // hi + lo exactly; hi is the rounded value
};

Two two_sum(double a, double b) {
    const double s = a + b;
    const double bv = s - a;
    const double av = s - bv;
    return {s, (a - av) + (b - bv)};
}

Two two_diff(double a, double b) {
    const double s = a - b;
    const double bv = a - s;
    const double av = s + bv;
    return {s, (a - av) + (bv - b)};
}

Two two_product(double a, double b) {
    const double p = a * b;
    return {p, std::fma(a, b, -p)};
}

// An exact sum of many doubles, kept as a nonoverlapping expansion in increasing magnitude with
// zeros removed (Grow-Expansion); its sign is the sign of its largest component.
template <std::size_t N> class ExactSum {
  public:
    void add(double b) {
        if (b == 0.0) return; // the expansion keeps no zeros; adding one changes nothing
        double q = b;
        std::size_t m = 0;
        for (std::size_t i = 0; i < n_; ++i) { // m <= i: writing e_[m] never clobbers unread parts
            const Two s = two_sum(q, e_[i]);
            q = s.hi;
            if (s.lo != 0.0) e_[m++] = s.lo;
        }
        if (q != 0.0) e_[m++] = q;
        n_ = m;
    }
    // x * y * z exactly: four doubles.
    void add_product(double x, double y, double z, double sign) {
        const Two xy = two_product(x, y);
        const Two h = two_product(xy.hi, z), l = two_product(xy.lo, z);
        add(sign * h.hi);
        add(sign * h.lo);
        add(sign * l.hi);
        add(sign * l.lo);
    }
    void add_product(double x, double y, double sign) {
        const Two xy = two_product(x, y);
        add(sign * xy.hi);
        add(sign * xy.lo);
    }
    int sign() const { return n_ == 0 ? 0 : e_[n_ - 1] > 0 ? 1 : -1; }

  private:
    std::array<double, N> e_{};
    std::size_t n_ = 0;
};

int sign_of(double v) {
    return v > 0 ? 1 : v < 0 ? -1 : 0;
}

// The exact determinant, term by term, with every difference split into hi + lo: 6 products
// of three two-part factors, 8 combinations each, 4 doubles per combination.
int orient3d_exact(glm::dvec3 a, glm::dvec3 b, glm::dvec3 c, glm::dvec3 d) {
    Two ad[3], bd[3], cd[3];
    for (int k = 0; k < 3; ++k) {
        ad[k] = two_diff(a[k], d[k]);
        bd[k] = two_diff(b[k], d[k]);
        cd[k] = two_diff(c[k], d[k]);
    }
    ExactSum<192> sum;
    // det = adz (bdx cdy - cdx bdy) + bdz (cdx ady - adx cdy) + cdz (adx bdy - bdx ady)
    // A zero part gives a zero product. Two floats within a factor 2^28 of each other have an
    // exact difference in double (lo is zero), as a mesh's coordinates nearly always do: then 6
    // products instead of 48, in the coplanar cases a grid's surfaces are full of.
    auto term = [&](const Two& x, const Two& y, const Two& z, double sign) {
        for (double xi : {x.hi, x.lo})
            for (double yi : {y.hi, y.lo})
                for (double zi : {z.hi, z.lo})
                    if (xi != 0.0 && yi != 0.0 && zi != 0.0) sum.add_product(xi, yi, zi, sign);
    };
    term(ad[2], bd[0], cd[1], 1.0);
    term(ad[2], cd[0], bd[1], -1.0);
    term(bd[2], cd[0], ad[1], 1.0);
    term(bd[2], ad[0], cd[1], -1.0);
    term(cd[2], ad[0], bd[1], 1.0);
    term(cd[2], bd[0], ad[1], -1.0);
    return sum.sign();
}

// Exact signs from integers, where the coordinates allow: each axis's coordinates as multiples
// of the finest unit in the last place among them. Every term of a determinant takes one
// difference from each axis, so the units' product (positive) factors out and the integer
// determinant has the same sign. Within a mesh the coordinates along an axis are of one size, and
// the expansions above (up to 48 products summed one double at a time) took 80 ns a call on the
// CT's Marching Cubes mesh at -500, whose count brings millions of tests of four coplanar points
// sharing no coordinate to the exact stage.
__extension__ typedef __int128 Int128;

// The widest exponent spread an axis may have: its differences then stay under 2^40 units (24 bits
// of a float, 15 of spread, one of the difference), a product of three under 2^120, and the
// determinant's sum of six under 2^123: no overflow in 127 bits.
constexpr int kGridSpread = 15;

// Fills units[i] = (values[i] - values[N - 1]) / u exactly, u the unit in the last place of the
// finest nonzero value. False where the values are not all finite normal floats (or zero)
// within kGridSpread binades of each other: the expansions decide then.
template <std::size_t N> bool grid_differences(const float (&values)[N], std::int64_t* units) {
    int finest = 255, coarsest = 0;
    for (const float v : values) {
        if (v == 0.0f) continue;
        const int exponent = int(std::bit_cast<std::uint32_t>(v) >> 23 & 0xffu);
        if (exponent == 0 || exponent == 255) return false; // subnormal, infinite or NaN
        finest = std::min(finest, exponent);
        coarsest = std::max(coarsest, exponent);
    }
    if (coarsest == 0) { // all zero
        std::fill(units, units + N - 1, 0);
        return true;
    }
    if (coarsest - finest > kGridSpread) return false;
    // A float of biased exponent e is a multiple of 2^(e - 150); 1 / u as a double's bits.
    const double scale = std::bit_cast<double>(std::uint64_t(1023 + 150 - finest) << 52);
    for (std::size_t i = 0; i + 1 < N; ++i) // exact: under 2^40 units, and a power of two
        units[i] = std::int64_t((double(values[i]) - double(values[N - 1])) * scale);
    return true;
}

int sign_of(Int128 v) {
    return v > 0 ? 1 : v < 0 ? -1 : 0;
}

// orient3d's sign from integers, or nullopt where grid_differences refuses an axis.
std::optional<int> orient3d_on_grid(glm::vec3 a, glm::vec3 b, glm::vec3 c, glm::vec3 d) {
    std::int64_t x[3], y[3], z[3]; // a, b, c minus d
    if (!grid_differences({a.x, b.x, c.x, d.x}, x) || !grid_differences({a.y, b.y, c.y, d.y}, y) ||
        !grid_differences({a.z, b.z, c.z, d.z}, z))
        return std::nullopt;
    const auto minor = [&](int i, int j) { return Int128(x[i]) * y[j] - Int128(x[j]) * y[i]; };
    return sign_of(z[0] * minor(1, 2) + z[1] * minor(2, 0) + z[2] * minor(0, 1));
}

std::optional<int> orient2d_on_grid(glm::vec2 a, glm::vec2 b, glm::vec2 c) {
    std::int64_t x[2], y[2]; // a, b minus c
    if (!grid_differences({a.x, b.x, c.x}, x) || !grid_differences({a.y, b.y, c.y}, y))
        return std::nullopt;
    return sign_of(Int128(x[0]) * y[1] - Int128(y[0]) * x[1]);
}

int orient2d_exact(glm::dvec2 a, glm::dvec2 b, glm::dvec2 c) {
    const Two acx = two_diff(a.x, c.x), acy = two_diff(a.y, c.y);
    const Two bcx = two_diff(b.x, c.x), bcy = two_diff(b.y, c.y);
    ExactSum<16> sum;
    for (double x : {acx.hi, acx.lo})
        for (double y : {bcy.hi, bcy.lo}) sum.add_product(x, y, 1.0);
    for (double x : {acy.hi, acy.lo})
        for (double y : {bcx.hi, bcx.lo}) sum.add_product(x, y, -1.0);
    return sum.sign();
}

// ---------------------------------------------------------------------------------------------
// Closed segment and triangle tests on exact signs.

glm::vec2 drop_axis(glm::vec3 p, int axis) {
    return axis == 0 ? glm::vec2(p.y, p.z) : axis == 1 ? glm::vec2(p.z, p.x) : glm::vec2(p.x, p.y);
}

// An axis whose dropping keeps triangle abc a triangle (so the projection is one-to-one on its
// plane), or -1 when the corners are collinear: the normal's components are these orient2d's.
int projection_axis(glm::vec3 a, glm::vec3 b, glm::vec3 c) {
    for (int axis = 2; axis >= 0; --axis)
        if (orient2d(drop_axis(a, axis), drop_axis(b, axis), drop_axis(c, axis)) != 0) return axis;
    return -1;
}

bool degenerate(const glm::vec3 t[3]) {
    return projection_axis(t[0], t[1], t[2]) < 0;
}

// r within the box of p and q; for collinear points: r on the closed segment pq.
bool in_box(glm::vec2 p, glm::vec2 q, glm::vec2 r) {
    return std::min(p.x, q.x) <= r.x && r.x <= std::max(p.x, q.x) && std::min(p.y, q.y) <= r.y &&
           r.y <= std::max(p.y, q.y);
}

bool segments_meet_2d(glm::vec2 p, glm::vec2 q, glm::vec2 r, glm::vec2 s) {
    const int o1 = orient2d(p, q, r), o2 = orient2d(p, q, s);
    const int o3 = orient2d(r, s, p), o4 = orient2d(r, s, q);
    if (o1 * o2 < 0 && o3 * o4 < 0) return true;
    return (o1 == 0 && in_box(p, q, r)) || (o2 == 0 && in_box(p, q, s)) ||
           (o3 == 0 && in_box(r, s, p)) || (o4 == 0 && in_box(r, s, q));
}

// Closed point-in-triangle for a non-degenerate 2D triangle: no two strictly opposite sides.
bool point_in_triangle_2d(glm::vec2 p, glm::vec2 a, glm::vec2 b, glm::vec2 c) {
    const int o1 = orient2d(a, b, p), o2 = orient2d(b, c, p), o3 = orient2d(c, a, p);
    return (o1 >= 0 && o2 >= 0 && o3 >= 0) || (o1 <= 0 && o2 <= 0 && o3 <= 0);
}

bool segment_meets_triangle_2d(glm::vec2 p, glm::vec2 q, glm::vec2 a, glm::vec2 b, glm::vec2 c) {
    return point_in_triangle_2d(p, a, b, c) || point_in_triangle_2d(q, a, b, c) ||
           segments_meet_2d(p, q, a, b) || segments_meet_2d(p, q, b, c) ||
           segments_meet_2d(p, q, c, a);
}

// Closed segments in space. Coplanar ones are compared in a projection that is one-to-one on
// their plane; four collinear points along the axis of their largest spread.
bool segments_meet_3d(glm::vec3 p, glm::vec3 q, glm::vec3 r, glm::vec3 s) {
    if (orient3d(p, q, r, s) != 0) return false;
    for (int axis = 2; axis >= 0; --axis) {
        const glm::vec2 p2 = drop_axis(p, axis), q2 = drop_axis(q, axis);
        const glm::vec2 r2 = drop_axis(r, axis), s2 = drop_axis(s, axis);
        if (orient2d(p2, q2, r2) != 0 || orient2d(p2, q2, s2) != 0 || orient2d(p2, r2, s2) != 0 ||
            orient2d(q2, r2, s2) != 0)
            return segments_meet_2d(p2, q2, r2, s2);
    }
    const glm::vec3 lo = glm::min(glm::min(p, q), glm::min(r, s));
    const glm::vec3 hi = glm::max(glm::max(p, q), glm::max(r, s));
    int axis = 0;
    for (int k = 1; k < 3; ++k)
        if (double(hi[k]) - lo[k] > double(hi[axis]) - lo[axis]) axis = k;
    return std::max(std::min(p[axis], q[axis]), std::min(r[axis], s[axis])) <=
           std::min(std::max(p[axis], q[axis]), std::max(r[axis], s[axis]));
}

// Closed segment pq against closed triangle t (a degenerate one is the union of its edges).
bool segment_meets_triangle(glm::vec3 p, glm::vec3 q, const glm::vec3 t[3]) {
    const int axis = projection_axis(t[0], t[1], t[2]);
    if (axis < 0)
        return segments_meet_3d(p, q, t[0], t[1]) || segments_meet_3d(p, q, t[1], t[2]) ||
               segments_meet_3d(p, q, t[2], t[0]);
    const int sp = orient3d(t[0], t[1], t[2], p), sq = orient3d(t[0], t[1], t[2], q);
    if (sp * sq > 0) return false;
    if (sp == 0 && sq == 0)
        return segment_meets_triangle_2d(drop_axis(p, axis), drop_axis(q, axis),
                                         drop_axis(t[0], axis), drop_axis(t[1], axis),
                                         drop_axis(t[2], axis));
    // pq meets the plane in one point, inside the triangle when the line pq passes no edge on
    // the outer side (all three line-edge orientations agree, zeros allowed).
    const int o1 = orient3d(p, q, t[0], t[1]), o2 = orient3d(p, q, t[1], t[2]);
    const int o3 = orient3d(p, q, t[2], t[0]);
    return (o1 >= 0 && o2 >= 0 && o3 >= 0) || (o1 <= 0 && o2 <= 0 && o3 <= 0);
}

// The corners of u not flagged in `skip` lie strictly on one side of the plane of t (which is
// then a proper triangle). u then meets that plane in its skipped corners' hull at most: when
// those are the shared ones, the pair meets in shared corners or the shared edge only. This
// settles almost every pair of a mesh with one to three filtered orient3d.
bool free_corners_off_plane(const glm::vec3 t[3], const glm::vec3 u[3], const bool skip[3]) {
    int side = 0;
    for (int k = 0; k < 3; ++k) {
        if (skip[k]) continue;
        const int s = orient3d(t[0], t[1], t[2], u[k]);
        if (s == 0 || (side != 0 && s != side)) return false;
        side = s;
    }
    return side != 0;
}

// Tests the edges of `t` that do not end in a corner flagged in `skip` against closed `u`.
bool edges_meet(const glm::vec3 t[3], const bool skip[3], const glm::vec3 u[3]) {
    for (int k = 0; k < 3; ++k) {
        const int l = (k + 1) % 3;
        if (!skip[k] && !skip[l] && segment_meets_triangle(t[k], t[l], u)) return true;
    }
    return false;
}

bool distinct_corners(const glm::vec3 t[3]) {
    return t[0] != t[1] && t[1] != t[2] && t[2] != t[0];
}

bool finite(const glm::vec3 t[3]) {
    for (int k = 0; k < 3; ++k)
        if (!std::isfinite(t[k].x) || !std::isfinite(t[k].y) || !std::isfinite(t[k].z))
            return false;
    return true;
}

// Two non-degenerate triangles sharing exactly the corners a[i], a[j] (= two corners of b):
// they overlap beyond the edge only when coplanar with both free corners on one side of it.
bool folded_onto_each_other(glm::vec3 p, glm::vec3 q, glm::vec3 free_a, glm::vec3 free_b) {
    if (orient3d(p, q, free_a, free_b) != 0) return false;
    const int axis = projection_axis(p, q, free_a);
    const glm::vec2 p2 = drop_axis(p, axis), q2 = drop_axis(q, axis);
    return orient2d(p2, q2, drop_axis(free_a, axis)) == orient2d(p2, q2, drop_axis(free_b, axis));
}

// Pairs in general position, settled from orientations alone: every corner that the pair does
// not share lies strictly off the other triangle's plane. A mesh's pairs that the planes' test
// leaves open (their planes cross near both) are nearly all such, and the edge tests below took
// about 20 orient3d a pair where these take 6 to 11. 0: apart, 1: intersecting, -1: not in
// general position (a corner on the other's plane, coplanar, flat), for the edge tests.
//
// Non-coplanar triangles meet only on the line L where their planes cross, and each meets L in
// a segment. With `t0` the corner of t alone on its side of u's plane, t's segment runs from a1
// on edge t0 t1 to a2 on edge t0 t2; likewise u's from b1 on u0 u1 to b2 on u0 u2. The plane
// through t0, t1 and u0 crosses L at a1 alone, and b_j = u0 + m (u_j - u0) with 0 < m < 1 lies on
// the side of that plane that u_j does (orient3d is affine in its last point and zero at u0):
// so orient3d(t0, t1, u0, u_j) tells on which side of a1 along L b_j lies, and orient3d(t0, t1,
// u0, t2) which side a2 is on. The segments miss each other exactly when both b_j lie beyond a1
// (away from a2) or both beyond a2 (away from a1).
//
// From the sides (nonzero) of the unshared corners of each triangle of the other's plane:
// side_t[k] = orient3d(u0, u1, u2, t_k), side_u[k] = orient3d(t0, t1, t2, u_k).
int settle_by_sides(const glm::vec3 t[3], const glm::vec3 u[3], const bool shared_t[3],
                    const bool shared_u[3], int shared, const int side_t[3], const int side_u[3]) {
    // The corner of a straddling triangle alone on its side, or -1 when all its unshared
    // corners lie on one side (then it meets the other's plane in shared corners at most).
    const auto lone = [](const int side[3], const bool skip[3]) {
        int plus = 0, minus = 0;
        for (int k = 0; k < 3; ++k) {
            plus += !skip[k] && side[k] > 0;
            minus += !skip[k] && side[k] < 0;
        }
        if (plus == 0 || minus == 0) return -1;
        const int alone_sign = plus == 1 ? 1 : -1;
        for (int k = 0; k < 3; ++k)
            if (!skip[k] && side[k] == alone_sign) return k;
        return -1;
    };
    const int i = lone(side_t, shared_t), j = lone(side_u, shared_u);
    if (i < 0 || j < 0) return 0;
    if (shared == 0) {
        const glm::vec3 &t0 = t[i], &t1 = t[(i + 1) % 3], &t2 = t[(i + 2) % 3];
        const glm::vec3 &u0 = u[j], &u1 = u[(j + 1) % 3], &u2 = u[(j + 2) % 3];
        const int a2_side = orient3d(t0, t1, u0, t2); // nonzero: u0 lies off t's plane
        if (a2_side == 0) return -1;
        if (orient3d(t0, t1, u0, u1) == -a2_side && orient3d(t0, t1, u0, u2) == -a2_side)
            return 0; // both before a1
        // The plane through t0, t2 and u0 sees a1 on the side -a2_side (two corners swapped).
        if (orient3d(t0, t2, u0, u1) == a2_side && orient3d(t0, t2, u0, u2) == a2_side)
            return 0; // both beyond a2
        return 1;
    }
    if (shared == 1) {
        // Both segments start at the shared corner p, and they overlap beyond p exactly when
        // they leave it the same way along L. With t1, t2 and u1, u2 the unshared corners: the
        // plane through p, t1 and u1 meets t's plane in the line p t1 and L in p alone, so t's
        // segment lies on t2's side of it, and u's, which ends on edge u1 u2, on u2's side.
        int p = 0;
        while (!shared_t[p]) ++p;
        const glm::vec3 &t1 = t[(p + 1) % 3], &t2 = t[(p + 2) % 3];
        int q = 0;
        while (!shared_u[q]) ++q;
        const glm::vec3 &u1 = u[(q + 1) % 3], &u2 = u[(q + 2) % 3];
        const int u_way = orient3d(t[p], t1, u1, u2), t_way = orient3d(t[p], t1, u1, t2);
        if (u_way == 0 || t_way == 0) return -1; // nonzero for proper triangles
        return u_way == t_way ? 1 : 0;
    }
    return 0; // a shared edge, the free corners off the other's plane: no fold
}

// settle_by_sides with the sides taken by orient3d; -1 for a duplicate or a corner on a plane.
int general_position_pair(const glm::vec3 t[3], const glm::vec3 u[3], const bool shared_t[3],
                          const bool shared_u[3], int shared) {
    if (shared == 3) return -1; // a duplicate
    int side_t[3] = {0, 0, 0}, side_u[3] = {0, 0, 0};
    for (int k = 0; k < 3; ++k) {
        if (!shared_u[k] && (side_u[k] = orient3d(t[0], t[1], t[2], u[k])) == 0) return -1;
        if (!shared_t[k] && (side_t[k] = orient3d(u[0], u[1], u[2], t[k])) == 0) return -1;
    }
    return settle_by_sides(t, u, shared_t, shared_u, shared, side_t, side_u);
}

} // namespace

int orient3d(glm::vec3 a, glm::vec3 b, glm::vec3 c, glm::vec3 d) {
    const double adx = double(a.x) - d.x, ady = double(a.y) - d.y, adz = double(a.z) - d.z;
    const double bdx = double(b.x) - d.x, bdy = double(b.y) - d.y, bdz = double(b.z) - d.z;
    const double cdx = double(c.x) - d.x, cdy = double(c.y) - d.y, cdz = double(c.z) - d.z;
    const double bdxcdy = bdx * cdy, cdxbdy = cdx * bdy;
    const double cdxady = cdx * ady, adxcdy = adx * cdy;
    const double adxbdy = adx * bdy, bdxady = bdx * ady;
    const double det = adz * (bdxcdy - cdxbdy) + bdz * (cdxady - adxcdy) + cdz * (adxbdy - bdxady);
    const double permanent = (std::abs(bdxcdy) + std::abs(cdxbdy)) * std::abs(adz) +
                             (std::abs(cdxady) + std::abs(adxcdy)) * std::abs(bdz) +
                             (std::abs(adxbdy) + std::abs(bdxady)) * std::abs(cdz);
    const double bound = kOrient3dBound * permanent;
    if (det > bound || -det > bound) return sign_of(det);
    // Four points with one coordinate in common lie in a plane along two axes: exactly zero,
    // without the expansions (a difference of floats is zero in double only for equal floats).
    // The faces of a net before its relaxation lie in such planes, and their pairs came here by
    // the million: a clinical CT's first net took 10 s to count, its relaxed nets half a second.
    if ((adx == 0 && bdx == 0 && cdx == 0) || (ady == 0 && bdy == 0 && cdy == 0) ||
        (adz == 0 && bdz == 0 && cdz == 0))
        return 0;
    if (const std::optional<int> sign = orient3d_on_grid(a, b, c, d)) return *sign;
    return orient3d_exact(a, b, c, d);
}

int orient2d(glm::vec2 a, glm::vec2 b, glm::vec2 c) {
    const double left = (double(a.x) - c.x) * (double(b.y) - c.y);
    const double right = (double(a.y) - c.y) * (double(b.x) - c.x);
    const double det = left - right;
    const double bound = kOrient2dBound * (std::abs(left) + std::abs(right));
    if (det > bound || -det > bound) return sign_of(det);
    // A factor of each product zero (points along one axis-parallel line, as on a flat net's
    // grid): exactly zero, as above.
    if ((a.x == c.x || b.y == c.y) && (a.y == c.y || b.x == c.x)) return 0;
    if (const std::optional<int> sign = orient2d_on_grid(a, b, c)) return *sign;
    return orient2d_exact(a, b, c);
}

namespace {

bool intersect(const glm::vec3 a[3], const glm::vec3 b[3], bool settle_general_position) {
    // Two coincident corners make no facet (TetGen merges the corners and drops it); the
    // quality metrics count such a triangle as degenerate.
    if (!finite(a) || !finite(b) || !distinct_corners(a) || !distinct_corners(b)) return false;
    bool shared_a[3] = {false, false, false}, shared_b[3] = {false, false, false};
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j)
            if (a[i] == b[j]) shared_a[i] = shared_b[j] = true;
    const int shared = int(shared_a[0]) + int(shared_a[1]) + int(shared_a[2]);
    if (settle_general_position) {
        const int settled = general_position_pair(a, b, shared_a, shared_b, shared);
        if (settled >= 0) return settled == 1;
    }
    if (shared < 3 &&
        (free_corners_off_plane(a, b, shared_b) || free_corners_off_plane(b, a, shared_a)))
        return false;
    const bool none[3] = {false, false, false};
    if (degenerate(a) || degenerate(b)) {
        // A flat triangle that shares two corners with the other lies on the line of the shared
        // edge, in the other's plane: folded onto it, as TetGen sees it too.
        if (shared >= 2) return true;
        return edges_meet(a, shared_a, b) || edges_meet(b, shared_b, a);
    }
    switch (shared) {
    case 0:
        return edges_meet(a, none, b) || edges_meet(b, none, a);
    case 1: // the edges opposite the shared corner
        return edges_meet(a, shared_a, b) || edges_meet(b, shared_b, a);
    case 2: {
        int free_a = 0, free_b = 0;
        while (shared_a[free_a]) ++free_a;
        while (shared_b[free_b]) ++free_b;
        return folded_onto_each_other(a[(free_a + 1) % 3], a[(free_a + 2) % 3], a[free_a],
                                      b[free_b]);
    }
    default: // the same three corners: a duplicate
        return true;
    }
}

} // namespace

bool triangles_intersect(const glm::vec3 a[3], const glm::vec3 b[3]) {
    return intersect(a, b, true);
}

namespace detail {

bool triangles_intersect_by_edges(const glm::vec3 a[3], const glm::vec3 b[3]) {
    return intersect(a, b, false);
}

} // namespace detail

// ---------------------------------------------------------------------------------------------
// The mesh's self-intersections.

namespace {

constexpr std::size_t kTriangleChunk = 1 << 12;
constexpr std::size_t kCellChunk = 1 << 12;
constexpr std::size_t kMaxCells = std::size_t(1) << 22;

struct Box {
    glm::vec3 lo, hi;
};

// The boxes of the triangles, and which have finite corners (the others intersect nothing and
// stay out of the grid). On huge pages: a clinical mesh's boxes (20 MB) faulted 4 KiB at a time
// on the calling thread.
struct TriangleBoxes {
    std::vector<Box> boxes;
    std::vector<std::uint8_t> valid;
};
TriangleBoxes triangle_boxes(const Mesh& mesh) {
    const std::size_t triangles = mesh.triangle_count();
    TriangleBoxes out;
    detail::resize_on_huge_pages(out.boxes, triangles);
    detail::resize_on_huge_pages(out.valid, triangles, std::uint8_t(0));
    for_each_chunk(triangles, kTriangleChunk, [&](std::size_t, std::size_t b, std::size_t e) {
        for (std::size_t t = b; t < e; ++t) {
            glm::vec3 p[3];
            for (int k = 0; k < 3; ++k) p[k] = mesh.positions[mesh.indices[3 * t + std::size_t(k)]];
            out.boxes[t] = {glm::min(p[0], glm::min(p[1], p[2])),
                            glm::max(p[0], glm::max(p[1], p[2]))};
            out.valid[t] = finite(p) ? 1 : 0;
        }
    });
    return out;
}

// A uniform grid over the triangles' boxes, each triangle listed (in increasing order) in every
// cell its box overlaps.
struct BoxGrid {
    glm::dvec3 origin{0.0};
    double inverse_cell = 1.0;
    glm::ivec3 dims{1};
    detail::CellLists triangles;

    glm::ivec3 cell_of(glm::vec3 p) const {
        // Clamped, then truncated: the floor for the non-negative values left (glm::floor is a
        // dozen instructions a coordinate on the baseline x86-64 target, and this runs for
        // every listed partner whose box overlaps).
        const glm::dvec3 f = glm::clamp((glm::dvec3(p) - origin) * inverse_cell, glm::dvec3(0.0),
                                        glm::dvec3(dims - 1));
        return glm::ivec3(f);
    }
    std::size_t index(glm::ivec3 c) const {
        return (std::size_t(c.z) * std::size_t(dims.y) + std::size_t(c.y)) * std::size_t(dims.x) +
               std::size_t(c.x);
    }
};

// Calls visit(cell, index) for every cell the box overlaps.
template <class Visit> void for_each_cell(const BoxGrid& grid, const Box& box, Visit&& visit) {
    const glm::ivec3 lo = grid.cell_of(box.lo), hi = grid.cell_of(box.hi);
    for (int z = lo.z; z <= hi.z; ++z)
        for (int y = lo.y; y <= hi.y; ++y)
            for (int x = lo.x; x <= hi.x; ++x) visit(glm::ivec3(x, y, z), grid.index({x, y, z}));
}

// Cells of about the mean box size hold a few triangles each; the count is capped.
BoxGrid make_grid(const std::vector<Box>& boxes, const std::vector<std::uint8_t>& valid) {
    glm::dvec3 lo(std::numeric_limits<double>::max()), hi(std::numeric_limits<double>::lowest());
    double size_sum = 0;
    std::size_t count = 0;
    for (std::size_t t = 0; t < boxes.size(); ++t) {
        if (!valid[t]) continue;
        lo = glm::min(lo, glm::dvec3(boxes[t].lo));
        hi = glm::max(hi, glm::dvec3(boxes[t].hi));
        const glm::dvec3 e = glm::dvec3(boxes[t].hi) - glm::dvec3(boxes[t].lo);
        size_sum += std::max({e.x, e.y, e.z});
        ++count;
    }
    BoxGrid grid;
    if (count == 0) return grid;
    const glm::dvec3 extent = hi - lo;
    const double largest = std::max({extent.x, extent.y, extent.z});
    double cell = size_sum / double(count);
    if (!(cell > largest * 1e-6)) cell = largest > 0 ? largest * 1e-3 : 1.0;
    auto along = [&](double e) { return std::max(1.0, std::ceil(e / cell)); };
    while (along(extent.x) * along(extent.y) * along(extent.z) > double(kMaxCells)) cell *= 1.1;
    grid.dims = glm::ivec3(int(along(extent.x)), int(along(extent.y)), int(along(extent.z)));
    grid.origin = lo;
    grid.inverse_cell = 1.0 / cell;
    return grid;
}

void fill_grid(BoxGrid& grid, const std::vector<Box>& boxes,
               const std::vector<std::uint8_t>& valid) {
    const std::size_t cells =
        std::size_t(grid.dims.x) * std::size_t(grid.dims.y) * std::size_t(grid.dims.z);
    grid.triangles.build(
        cells, boxes.size(),
        [&](std::size_t first, std::size_t last, auto&& visit) {
            for (std::size_t t = first; t < last; ++t)
                if (valid[t])
                    for_each_cell(grid, boxes[t],
                                  [&](glm::ivec3, std::size_t c) { visit(std::uint32_t(t), c); });
        },
        "self-intersections");
}

// The six comparisons joined bitwise: without a branch, for the pair loop's branch-free keeping.
bool boxes_overlap(const Box& a, const Box& b) {
    return bool(int(a.lo.x <= b.hi.x) & int(b.lo.x <= a.hi.x) & int(a.lo.y <= b.hi.y) &
                int(b.lo.y <= a.hi.y) & int(a.lo.z <= b.hi.z) & int(b.lo.z <= a.hi.z));
}

// The side of a triangle's plane a point lies on, certified by orient3d's forward error bound,
// with the plane's part of the determinant worked out once for all of a triangle's partners.
// det[q - t0; t1 - t0; t2 - t0], expanded along its first row, has the shape and so the error
// bound of orient3d's expression (and the opposite sign, which the callers do not need).
class PlaneSide {
  public:
    explicit PlaneSide(const glm::vec3 t[3]) : origin_(t[0]) {
        const glm::dvec3 e1 = glm::dvec3(t[1]) - origin_, e2 = glm::dvec3(t[2]) - origin_;
        const double yz = e1.y * e2.z, zy = e1.z * e2.y, zx = e1.z * e2.x, xz = e1.x * e2.z,
                     xy = e1.x * e2.y, yx = e1.y * e2.x;
        normal_ = {yz - zy, zx - xz, xy - yx};
        magnitude_ = {std::abs(yz) + std::abs(zy), std::abs(zx) + std::abs(xz),
                      std::abs(xy) + std::abs(yx)};
    }
    // +1 or -1 where the sign is certain, 0 where it is not (on the plane, near it, non-finite).
    int of(glm::vec3 q) const {
        const glm::dvec3 w = glm::dvec3(q) - origin_;
        const double det = (w.x * normal_.x + w.y * normal_.y) + w.z * normal_.z;
        const double permanent = (std::abs(w.x) * magnitude_.x + std::abs(w.y) * magnitude_.y) +
                                 std::abs(w.z) * magnitude_.z;
        const double bound = kOrient3dBound * permanent;
        return det > bound ? 1 : -det > bound ? -1 : 0;
    }

  private:
    glm::dvec3 origin_, normal_, magnitude_;
};

// Whether triangles t and u (corner indices given) certainly do not meet: the corners of u that
// are not corners of t lie strictly on one side of t's plane. This is the test with which
// triangles_intersect settles almost every pair, here without its set-up; false means only
// "not settled here".
bool apart_by_plane(const PlaneSide& plane_of_t, const std::uint32_t* t, const std::uint32_t* u,
                    const glm::vec3 u_corners[3]) {
    int side = 0;
    for (int k = 0; k < 3; ++k) {
        if (u[k] == t[0] || u[k] == t[1] || u[k] == t[2]) continue; // shared: on the plane
        const int s = plane_of_t.of(u_corners[k]);
        if (s == 0 || (side != 0 && s != side)) return false;
        side = s;
    }
    return side != 0;
}

// triangles_intersect's settling of a pair in general position, from the planes' sides (a sixth
// of a clinical mesh's pairs got this far, and triangles_intersect set them up and took six
// orient3d). The sides are taken again here: apart_by_plane stops at the first sign that settles
// nothing, and taking all of them there, for every pair, was 2-4 % slower than this. Where each
// unshared corner (by index) lies certainly off the other's plane, the pair is one that
// triangles_intersect settles from its sides, and the same way: no corner is non-finite (PlaneSide
// is uncertain then), no triangle is flat or has coincident corners (its plane would be uncertain
// for every point), and an unshared corner has no other corner's position (it would lie on the
// plane). PlaneSide's sign is orient3d's negated. -1 where a side is uncertain: triangles_intersect
// decides.
int settled_by_plane_sides(const PlaneSide& plane_of_t, const std::uint32_t* t_index,
                           const glm::vec3 p[3], const PlaneSide& plane_of_u,
                           const std::uint32_t* u_index, const glm::vec3 q[3]) {
    bool shared_t[3], shared_u[3];
    int shared_in_t = 0, shared_in_u = 0;
    for (int k = 0; k < 3; ++k) {
        shared_t[k] =
            t_index[k] == u_index[0] || t_index[k] == u_index[1] || t_index[k] == u_index[2];
        shared_u[k] =
            u_index[k] == t_index[0] || u_index[k] == t_index[1] || u_index[k] == t_index[2];
        shared_in_t += shared_t[k] ? 1 : 0;
        shared_in_u += shared_u[k] ? 1 : 0;
    }
    // A repeated index (a collapsed triangle) or a duplicate: triangles_intersect's own cases.
    if (shared_in_t != shared_in_u || shared_in_t == 3) return -1;
    int side_t[3] = {0, 0, 0}, side_u[3] = {0, 0, 0};
    for (int k = 0; k < 3; ++k) {
        if (!shared_u[k] && (side_u[k] = -plane_of_t.of(q[k])) == 0) return -1;
        if (!shared_t[k] && (side_t[k] = -plane_of_u.of(p[k])) == 0) return -1;
    }
    return settle_by_sides(p, q, shared_t, shared_u, shared_in_t, side_t, side_u);
}

// Whether mesh triangles t (corners p, its plane given) and u (corners q) meet: the planes'
// test each way first, then triangles_intersect's settling from the sides, then
// triangles_intersect.
bool pair_intersects(const PlaneSide& plane_of_t, const std::uint32_t* t_index,
                     const glm::vec3 p[3], const std::uint32_t* u_index, const glm::vec3 q[3]) {
    if (apart_by_plane(plane_of_t, t_index, u_index, q)) return false;
    const PlaneSide plane_of_u(q);
    if (apart_by_plane(plane_of_u, u_index, t_index, p)) return false;
    if (const int settled = settled_by_plane_sides(plane_of_t, t_index, p, plane_of_u, u_index, q);
        settled >= 0)
        return settled == 1;
    return triangles_intersect(p, q);
}

void check_indices(const Mesh& mesh) {
    if (mesh.indices.size() % 3 != 0)
        throw std::invalid_argument("mesh has " + std::to_string(mesh.indices.size()) +
                                    " indices, not a multiple of 3");
    if (mesh.triangle_count() >= std::numeric_limits<std::uint32_t>::max())
        throw std::invalid_argument("self-intersections: too many triangles");
    if (const auto i = first_index_out_of_range(mesh))
        throw std::invalid_argument("mesh index " + std::to_string(*i) + " out of range (" +
                                    std::to_string(mesh.positions.size()) + " vertices)");
}

} // namespace

namespace {

// Every intersecting pair (t, u), t < u; with `subject`, only pairs with a triangle marked in it.
// Cell by cell: each pair is examined in the cell that holds the lowest corner of its boxes'
// overlap, max(lo_t, lo_u), whose cell is max(cell_of(lo_t), cell_of(lo_u)) (cell_of is monotone
// in each coordinate). A cell's triangles are read once into a small local list, box, first cell
// and mark, and their pairs tested from there: examined from each triangle, the lists of its
// cells were searched for it and their boxes read again for every triangle of the cell, at
// scattered places (30 % of this pass's samples on the CT's Marching Cubes mesh).
SelfIntersections find_intersections(const Mesh& mesh, const std::vector<std::uint8_t>* subject,
                                     std::size_t max_pairs) {
    check_indices(mesh);
    const std::size_t triangles = mesh.triangle_count();
    if (subject && subject->size() != triangles)
        throw std::invalid_argument("intersections: one mark per triangle expected");
    auto corners = [&](std::size_t t, glm::vec3 out[3]) {
        for (int k = 0; k < 3; ++k) out[k] = mesh.positions[mesh.indices[3 * t + std::size_t(k)]];
    };
    const TriangleBoxes boxed = triangle_boxes(mesh);
    const std::vector<Box>& boxes = boxed.boxes;
    const std::vector<std::uint8_t>& valid = boxed.valid;
    BoxGrid grid = make_grid(boxes, valid);
    fill_grid(grid, boxes, valid);
    auto marked = [&](std::size_t t) { return subject == nullptr || (*subject)[t] != 0; };

    // A triangle of the cell at hand, as its pairs there read it.
    struct Listed {
        Box box;
        glm::ivec3 first_cell; // the cell of the box's lowest corner
        std::uint32_t id;
        bool marked;
    };
    struct Partial {
        std::size_t count = 0;
        std::vector<std::pair<std::uint32_t, std::uint32_t>> pairs; // the least, at most max_pairs
    };
    const std::size_t cells =
        std::size_t(grid.dims.x) * std::size_t(grid.dims.y) * std::size_t(grid.dims.z);
    const std::size_t along_xy = std::size_t(grid.dims.x) * std::size_t(grid.dims.y);
    std::vector<Partial> partials(chunk_count(cells, kCellChunk));
    for_each_chunk(cells, kCellChunk, [&](std::size_t chunk, std::size_t b, std::size_t e) {
        Partial& part = partials[chunk];
        std::vector<Listed> listed;
        std::vector<std::uint32_t> overlapping; // places in `listed` whose box meets one's
        grid.triangles.for_each_occupied_in(b, e, [&](std::size_t c) {
            const std::span<const std::uint32_t> items = grid.triangles.items(c);
            if (items.size() < 2) return;
            const glm::ivec3 cell(int(c % std::size_t(grid.dims.x)),
                                  int(c / std::size_t(grid.dims.x) % std::size_t(grid.dims.y)),
                                  int(c / along_xy));
            listed.clear();
            for (const std::uint32_t id : items)
                listed.push_back({boxes[id], grid.cell_of(boxes[id].lo), id, marked(id)});
            if (overlapping.size() < listed.size()) overlapping.resize(listed.size());
            // The list is in increasing order: t is the smaller of each pair.
            for (std::size_t i = 0; i + 1 < listed.size(); ++i) {
                const Listed& t = listed[i];
                // The boxes' test for the rest of the list first, without a branch (a cheap test
                // passes a few in five or six, at random, and mispredicted branches would cost
                // more than the tests), then the other tests for the few kept.
                std::size_t kept = 0;
                for (std::size_t j = i + 1; j < listed.size(); ++j) {
                    overlapping[kept] = std::uint32_t(j);
                    kept += boxes_overlap(t.box, listed[j].box) ? 1 : 0;
                }
                glm::vec3 p[3], q[3];
                std::optional<PlaneSide> plane_of_t; // once t has a partner to test
                for (std::size_t k = 0; k < kept; ++k) {
                    const Listed& u = listed[overlapping[k]];
                    if (!(t.marked || u.marked) || glm::max(t.first_cell, u.first_cell) != cell)
                        continue;
                    if (!plane_of_t) {
                        corners(t.id, p);
                        plane_of_t.emplace(p);
                    }
                    corners(u.id, q);
                    if (!pair_intersects(*plane_of_t, &mesh.indices[3 * std::size_t(t.id)], p,
                                         &mesh.indices[3 * std::size_t(u.id)], q))
                        continue;
                    ++part.count;
                    part.pairs.emplace_back(t.id, u.id);
                }
            }
            // Only the least max_pairs of all are kept, so of each chunk's too.
            if (part.pairs.size() > 64 && part.pairs.size() / 2 > max_pairs) {
                std::sort(part.pairs.begin(), part.pairs.end());
                part.pairs.resize(max_pairs);
            }
        });
        std::sort(part.pairs.begin(), part.pairs.end());
        if (part.pairs.size() > max_pairs) part.pairs.resize(max_pairs);
    });
    SelfIntersections result;
    for (const Partial& part : partials) {
        result.count += part.count;
        result.pairs.insert(result.pairs.end(), part.pairs.begin(), part.pairs.end());
    }
    std::sort(result.pairs.begin(), result.pairs.end());
    if (result.pairs.size() > max_pairs) result.pairs.resize(max_pairs);
    return result;
}

// The pairs with a marked triangle when few are marked: the grid holds the marked triangles
// alone (a small region, a small grid) and every triangle is looked up in it, so a try that
// changed a few hundred triangles costs a pass over the boxes, not a grid of the whole mesh. A
// pair is examined once: in the cell of the lowest corner of its boxes' overlap, from the
// unmarked triangle, or from the larger index when both are marked.
SelfIntersections few_marked_intersections(const Mesh& mesh,
                                           const std::vector<std::uint8_t>& subject,
                                           std::size_t max_pairs) {
    const std::size_t triangles = mesh.triangle_count();
    auto corners = [&](std::size_t t, glm::vec3 out[3]) {
        for (int k = 0; k < 3; ++k) out[k] = mesh.positions[mesh.indices[3 * t + std::size_t(k)]];
    };
    const TriangleBoxes boxed = triangle_boxes(mesh);
    const std::vector<Box>& boxes = boxed.boxes;
    const std::vector<std::uint8_t>& valid = boxed.valid;
    std::vector<std::uint8_t> in_grid(triangles, 0);
    for (std::size_t t = 0; t < triangles; ++t) in_grid[t] = valid[t] && subject[t] ? 1 : 0;
    BoxGrid grid = make_grid(boxes, in_grid);
    fill_grid(grid, boxes, in_grid);
    Box region{glm::vec3(std::numeric_limits<float>::max()),
               glm::vec3(std::numeric_limits<float>::lowest())};
    for (std::size_t t = 0; t < triangles; ++t)
        if (in_grid[t])
            region = {glm::min(region.lo, boxes[t].lo), glm::max(region.hi, boxes[t].hi)};

    struct Partial {
        std::size_t count = 0;
        std::vector<std::pair<std::uint32_t, std::uint32_t>> pairs;
    };
    std::vector<Partial> partials(chunk_count(triangles, kTriangleChunk));
    for_each_chunk(triangles, kTriangleChunk, [&](std::size_t chunk, std::size_t b, std::size_t e) {
        Partial& part = partials[chunk];
        for (std::size_t u = b; u < e; ++u) {
            if (!valid[u] || !boxes_overlap(boxes[u], region)) continue;
            glm::vec3 p[3], q[3];
            corners(u, p);
            const PlaneSide plane_of_u(p);
            const std::uint32_t* u_index = &mesh.indices[3 * u];
            const glm::ivec3 first_u = grid.cell_of(boxes[u].lo);
            for_each_cell(grid, boxes[u], [&](glm::ivec3 cell, std::size_t c) {
                for (const std::uint32_t t : grid.triangles.items(c)) {
                    if (t == u || (subject[u] && t > u) || !boxes_overlap(boxes[t], boxes[u]) ||
                        glm::max(first_u, grid.cell_of(boxes[t].lo)) != cell)
                        continue;
                    corners(t, q);
                    if (pair_intersects(plane_of_u, u_index, p, &mesh.indices[3 * std::size_t(t)],
                                        q)) {
                        ++part.count;
                        part.pairs.emplace_back(std::min(std::uint32_t(u), t),
                                                std::max(std::uint32_t(u), t));
                    }
                }
            });
        }
    });
    SelfIntersections result;
    for (const Partial& part : partials) {
        result.count += part.count;
        result.pairs.insert(result.pairs.end(), part.pairs.begin(), part.pairs.end());
    }
    std::sort(result.pairs.begin(), result.pairs.end());
    if (result.pairs.size() > max_pairs) result.pairs.resize(max_pairs);
    return result;
}

} // namespace

SelfIntersections self_intersections(const Mesh& mesh, std::size_t max_pairs) {
    return find_intersections(mesh, nullptr, max_pairs);
}

SelfIntersections intersections_involving(const Mesh& mesh,
                                          const std::vector<std::uint8_t>& subject,
                                          std::size_t max_pairs) {
    check_indices(mesh);
    if (subject.size() != mesh.triangle_count())
        throw std::invalid_argument("intersections: one mark per triangle expected");
    // A grid of the whole mesh pays off once a good share of it is marked.
    const auto marked = std::size_t(
        std::count_if(subject.begin(), subject.end(), [](std::uint8_t m) { return m != 0; }));
    if (marked * 8 < subject.size()) return few_marked_intersections(mesh, subject, max_pairs);
    return find_intersections(mesh, &subject, max_pairs);
}

std::size_t count_self_intersections(const Mesh& mesh) {
    return self_intersections(mesh, 0).count;
}

} // namespace snert
