// Keeping every iteration's mesh valid (contract: the header).
#include "mesh_guard.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstring>
#include <stdexcept>
#include <vector>

#include "huge_pages.h"
#include "parallel.h"
#include "prefetch.h"
#include "triangle_intersection.h"

namespace snert {

namespace {

using Triangle = std::array<std::uint32_t, 3>;

// Whether quad `id` splits along its first diagonal at positions p (triangulate()'s choice).
bool splits_along_ac(const SurfaceNet& net, std::uint32_t id, std::span<const glm::vec3> p,
                     TriangulationRule rule, glm::vec3 spacing) {
    const auto& q = net.quads[id];
    return quad_splits_along_ac(p[q[0]], p[q[1]], p[q[2]], p[q[3]], rule, spacing);
}

// The triangles of polygon `id` (a quad split as `along_ac` says, or a fixed triangle): 1 or 2.
int split_polygon(const SurfaceNet& net, std::uint32_t id, bool along_ac, Triangle out[2]) {
    if (id >= net.quads.size()) {
        out[0] = net.triangles[id - net.quads.size()];
        return 1;
    }
    const auto triangles = quad_triangles(net.quads[id], along_ac);
    out[0] = triangles[0];
    out[1] = triangles[1];
    return 2;
}

// True when triangle (a, b, c) is surely no sliver: its smallest / largest angle ratio is at
// least 0.1, shown without an angle. The largest angle, at the corner facing the longest side, is
// at most 90 degrees where its cosine is not negative, at most 120 where it is not below -1/2,
// and at most 180 - 2 x the smallest in any case; so a smallest angle of 9.1, 12.1 or 15.1
// degrees gives a ratio of at least 0.1008. The tenth of a degree is far more than float
// rounding moves either test: a triangle near a limit is at worst sent to the exact measure,
// never passed wrongly. The smallest angle faces the shortest side: its sine is 2 area / (product
// of the two longer sides), compared squared, like the cosine, so no square root is taken. On
// coordinates, so that the blocks below run it four triangles at a time. (A smallest angle of 18
// degrees, the test before, left 3.6 % of a relaxed net's triangles on the CT at 200 and 8.2 % at
// -500 to the exact measure; this one 0.6 % and 0.1 %.)
inline bool surely_no_sliver_coordinates(float ax, float ay, float az, float bx, float by, float bz,
                                         float cx, float cy, float cz) {
    const float abx = bx - ax, aby = by - ay, abz = bz - az;
    const float bcx = cx - bx, bcy = cy - by, bcz = cz - bz;
    const float cax = ax - cx, cay = ay - cy, caz = az - cz;
    const float ab2 = abx * abx + aby * aby + abz * abz;
    const float bc2 = bcx * bcx + bcy * bcy + bcz * bcz;
    const float ca2 = cax * cax + cay * cay + caz * caz;
    // ab x (-ca), twice the area's vector.
    const float nx = aby * -caz - -cay * abz, ny = abz * -cax - -caz * abx,
                nz = abx * -cay - -cax * aby;
    const float twice_area2 = nx * nx + ny * ny + nz * nz;
    float shortest2 = ab2, longest2 = ab2;
    shortest2 = bc2 < shortest2 ? bc2 : shortest2;
    shortest2 = ca2 < shortest2 ? ca2 : shortest2;
    longest2 = bc2 > longest2 ? bc2 : longest2;
    longest2 = ca2 > longest2 ? ca2 : longest2;
    const float middle2 = ab2 + bc2 + ca2 - shortest2 - longest2;
    // 2 s m cos(largest) for the shortest and middle sides s and m, and (s m)^2.
    const float cosine = shortest2 + middle2 - longest2;
    const float sm2 = shortest2 * middle2;
    // sin^2 of 15.1, 12.1 and 9.1 degrees.
    float needed = 0.0678626f;
    needed = cosine * cosine <= sm2 ? 0.0439399f : needed; // cos >= -1/2 (or > 0, below)
    needed = cosine >= 0.0f ? 0.0250140f : needed;
    // Strictly: a triangle of no area (corners that coincide, or sides that underflow) goes to
    // the exact measure, which calls it degenerate.
    return twice_area2 > needed * (longest2 * middle2);
}

} // namespace

bool detail::surely_no_sliver(glm::vec3 a, glm::vec3 b, glm::vec3 c) {
    return surely_no_sliver_coordinates(a.x, a.y, a.z, b.x, b.y, b.z, c.x, c.y, c.z);
}

namespace {

// Smallest / largest angle (world units), as the metrics measure it (triangle_shape), but
// cheap for the many triangles that are surely no sliver: they count as 1.
float sliver_quality(glm::vec3 a, glm::vec3 b, glm::vec3 c) {
    if (detail::surely_no_sliver(a, b, c)) return 1.0f;
    return triangle_shape(a, b, c).quality;
}

// surely_no_sliver_coordinates for kTriangleBlock triangles at once, corner k of triangle t at
// (x[k][t], y[k][t], z[k][t]): 1 where it holds (no sliver), else 0. A loop of a fixed length
// over the triangles, which the compiler runs four at a time.
constexpr int kTriangleBlock = 16;
struct TriangleBlock {
    float x[3][kTriangleBlock], y[3][kTriangleBlock], z[3][kTriangleBlock];
    void set(int t, const glm::vec3& a, const glm::vec3& b, const glm::vec3& c) {
        x[0][t] = a.x, y[0][t] = a.y, z[0][t] = a.z;
        x[1][t] = b.x, y[1][t] = b.y, z[1][t] = b.z;
        x[2][t] = c.x, y[2][t] = c.y, z[2][t] = c.z;
    }
};
void no_slivers(const TriangleBlock& block, int (&no_sliver)[kTriangleBlock]) {
    for (int t = 0; t < kTriangleBlock; ++t)
        no_sliver[t] = int(surely_no_sliver_coordinates(
            block.x[0][t], block.y[0][t], block.z[0][t], block.x[1][t], block.y[1][t],
            block.z[1][t], block.x[2][t], block.y[2][t], block.z[2][t]));
}

// Positions of the nodes in index space (for the split) and in world space (for the checks):
// stored (`world`), or mapped from index space when asked (`to_world`, for the step's old
// positions: read only where a new polygon looks worse, so not worth 12 bytes a node).
struct Points {
    std::span<const glm::vec3> index, world;
    const IndexToWorld* to_world = nullptr;
    glm::vec3 world_at(std::uint32_t node) const {
        return to_world != nullptr ? (*to_world)(index[node]) : world[node];
    }
};

float polygon_quality(const SurfaceNet& net, std::uint32_t id, Points p, bool along_ac) {
    if (id >= net.quads.size()) {
        const auto& t = net.triangles[id - net.quads.size()];
        return std::min(1.0f, sliver_quality(p.world_at(t[0]), p.world_at(t[1]), p.world_at(t[2])));
    }
    // A quad's corners read once, its two triangles taken from them in place.
    const auto& q = net.quads[id];
    const glm::vec3 c[4] = {p.world_at(q[0]), p.world_at(q[1]), p.world_at(q[2]), p.world_at(q[3])};
    float quality = 1.0f;
    for (const auto& k : kQuadSplitCorners[along_ac ? 1 : 0])
        quality = std::min(quality, sliver_quality(c[k[0]], c[k[1]], c[k[2]]));
    return quality;
}

// A triangle of the cell being checked, with what the pair test needs precomputed.
struct TriangleData {
    Triangle nodes;
    glm::vec3 corner[3];
    glm::dvec3 normal;  // (b - a) x (c - a), in double
    double normal_size; // |n.x| + |n.y| + |n.z|: no square root, and at least |n|
    glm::vec3 lo, hi;   // bounding box
};

TriangleData triangle_data(const Triangle& t, std::span<const glm::vec3> p) {
    TriangleData d;
    d.nodes = t;
    for (int k = 0; k < 3; ++k) d.corner[k] = p[t[std::size_t(k)]];
    const glm::dvec3 a0(d.corner[0]);
    d.normal = glm::cross(glm::dvec3(d.corner[1]) - a0, glm::dvec3(d.corner[2]) - a0);
    d.normal_size = std::abs(d.normal.x) + std::abs(d.normal.y) + std::abs(d.normal.z);
    d.lo = glm::min(d.corner[0], glm::min(d.corner[1], d.corner[2]));
    d.hi = glm::max(d.corner[0], glm::max(d.corner[1], d.corner[2]));
    return d;
}

// True when the corners of `b` that are not corners of `a` lie strictly on one side of a's
// plane, decided in double with a wide margin (else false: the exact test decides). Then b
// meets a's plane at most in shared corners, so the two cannot intersect: the cheap early-out
// of Moller's test, for the many pairs around one node that share a corner or an edge.
bool separated_by_plane(const TriangleData& a, const TriangleData& b) {
    if (!(a.normal_size > 0.0)) return false;
    const glm::dvec3 a0(a.corner[0]);
    int below = 0, above = 0;
    for (int k = 0; k < 3; ++k) {
        const std::uint32_t n = b.nodes[std::size_t(k)];
        if (n == a.nodes[0] || n == a.nodes[1] || n == a.nodes[2]) continue;
        const glm::dvec3 w = glm::dvec3(b.corner[k]) - a0;
        const double d = glm::dot(a.normal, w);
        // Float inputs: the rounding error of d is far below 1e-9 of |n| |w|.
        if (std::abs(d) <= 1e-9 * a.normal_size * (std::abs(w.x) + std::abs(w.y) + std::abs(w.z)))
            return false;
        (d < 0.0 ? below : above) += 1;
    }
    return below == 0 || above == 0;
}

void mark(std::vector<std::uint8_t>& flags, std::uint32_t node) {
    std::atomic_ref<std::uint8_t>(flags[node]).store(1, std::memory_order_relaxed);
}

// Appends the index of every set flag to `out`, in increasing order, clearing the flags when
// `clear` says so. A round sets a few thousand of some 400 000 flags: eight are looked at at
// once, the set ones of a word listed without a branch (one a byte mispredicted on such sparse
// flags), and the list comes out sorted, where sorting the gathered indices took 3-4 ms a step.
void list_set_flags(std::vector<std::uint8_t>& flags, std::vector<std::uint32_t>& out, bool clear) {
    const std::size_t n = flags.size();
    std::uint8_t* const f = flags.data();
    std::size_t i = 0;
    for (; i + 8 <= n; i += 8) {
        std::uint64_t eight = 0;
        std::memcpy(&eight, f + i, 8);
        if (eight == 0) continue;
        // Without a branch a flag: each index is written, and the count moves past it if set.
        std::uint32_t set[8];
        int count = 0;
        for (int k = 0; k < 8; ++k) {
            set[count] = std::uint32_t(i) + std::uint32_t(k);
            count += f[i + std::size_t(k)] != 0 ? 1 : 0;
        }
        out.insert(out.end(), set, set + count);
        if (clear) std::memset(f + i, 0, 8);
    }
    for (; i < n; ++i)
        if (f[i] != 0) {
            out.push_back(std::uint32_t(i));
            if (clear) f[i] = 0;
        }
}

// True when a plane through one edge of `a`, perpendicular to `a`, has `a`'s third corner
// strictly on one side and every corner of `b` strictly on the other, or on the plane when it is
// a shared corner of that edge (decided in double with a wide margin). Then the two meet at most
// in that shared edge or corner. This settles the coplanar and nearly coplanar neighbours of a
// flat region, which the triangles' own planes cannot separate.
bool separated_by_edge_plane(const TriangleData& a, const TriangleData& b) {
    if (!(a.normal_size > 0.0)) return false;
    for (int i = 0; i < 3; ++i) {
        const int j = (i + 1) % 3, k = (i + 2) % 3;
        const glm::dvec3 origin(a.corner[i]);
        const glm::dvec3 m = glm::cross(glm::dvec3(a.corner[j]) - origin, a.normal);
        const double m1 = std::abs(m.x) + std::abs(m.y) + std::abs(m.z);
        const glm::dvec3 wk = glm::dvec3(a.corner[k]) - origin;
        const double side = glm::dot(wk, m);
        if (std::abs(side) <= 1e-9 * m1 * (std::abs(wk.x) + std::abs(wk.y) + std::abs(wk.z)))
            continue;
        bool separated = true;
        for (int c = 0; c < 3 && separated; ++c) {
            const std::uint32_t n = b.nodes[std::size_t(c)];
            if (n == a.nodes[std::size_t(i)] || n == a.nodes[std::size_t(j)]) continue;
            if (n == a.nodes[std::size_t(k)]) separated = false;
            const glm::dvec3 w = glm::dvec3(b.corner[c]) - origin;
            const double d = glm::dot(w, m);
            separated = separated && (d > 0.0) != (side > 0.0) &&
                        std::abs(d) > 1e-9 * m1 * (std::abs(w.x) + std::abs(w.y) + std::abs(w.z));
        }
        if (separated) return true;
    }
    return false;
}

// Two triangles that share an edge fold onto each other when their normals point nearly opposite
// ways: the surface doubles back and the two nearly overlap (dihedral angle under 10 degrees).
// Not an intersection, but an FE mesher cannot recover such a pair (TetGen stops with "two
// facets nearly overlap"), so a move that makes a fold, or a fold worse, is refused like one.
constexpr double kFoldCos = 0.98480775301220802; // cos(10 degrees)

// Cosine of the angle between the normals of the triangles `a` and `b` at the world points of `p`.
double normal_cos(const Triangle& a, const Triangle& b, const Points& p) {
    const auto normal = [&](const Triangle& t) {
        const glm::dvec3 o(p.world_at(t[0]));
        return glm::cross(glm::dvec3(p.world_at(t[1])) - o, glm::dvec3(p.world_at(t[2])) - o);
    };
    const glm::dvec3 na = normal(a), nb = normal(b);
    const double size = std::sqrt(glm::dot(na, na) * glm::dot(nb, nb));
    return size > 0.0 ? glm::dot(na, nb) / size : 1.0;
}

// A node's star as the star test reads it, fixed for the net and so worked out once: 0 when the
// pair tests decide (see stars_are_embedded), else, for the k-th quad of the closed fan
// around the node, kStarCodeBits bits from bit kStarCodeBits * k: its place in the node's star
// (3 bits) and the node's corner in it (2 bits); the fan's size less 3 from bit 30 (a code is
// never 0: the second quad's place is not). Chaining the fan every step took a tenth of the
// test's time (a search with a branch a comparison).
constexpr int kStarCodeBits = 5;
constexpr int kStarSizeShift = 30;
std::uint32_t star_size(std::uint32_t code) {
    return (code >> kStarSizeShift) + 3;
}
std::uint32_t star_code(const SurfaceNet& net, std::uint32_t node) {
    const std::uint32_t first = net.star_offsets[node], size = net.star_offsets[node + 1] - first;
    if (size < 3 || size > 6) return 0;
    int at[6];
    std::uint32_t next[6], prev[6];
    for (std::uint32_t k = 0; k < size; ++k) {
        const std::uint32_t id = net.star[first + k];
        if (id >= net.quads.size()) return 0; // a fixed triangle
        const std::array<std::uint32_t, 4>& c = net.quads[id];
        at[k] = -1;
        for (int i = 0; i < 4; ++i)
            if (c[std::size_t(i)] == node) at[k] = i;
        if (at[k] < 0) return 0;
        next[k] = c[std::size_t((at[k] + 1) & 3)];
        prev[k] = c[std::size_t((at[k] + 3) & 3)];
    }
    // Around a node inside the surface the quads chain up into one closed fan: the quad after
    // one is the one whose `next` is its `prev` (they share that edge, wound oppositely).
    std::uint32_t order[6] = {0};
    unsigned used = 1;
    for (std::uint32_t k = 1; k < size; ++k) {
        std::uint32_t j = 0;
        while (j < size && ((used >> j & 1u) != 0 || next[j] != prev[order[k - 1]])) ++j;
        if (j == size) return 0;
        used |= 1u << j;
        order[k] = j;
    }
    if (next[order[0]] != prev[order[size - 1]]) return 0;
    std::uint32_t code = (size - 3) << kStarSizeShift;
    for (std::uint32_t k = 0; k < size; ++k)
        code |= (order[k] | std::uint32_t(at[order[k]]) << 3) << (kStarCodeBits * k);
    return code;
}

// The star test runs on kStarLanes stars at once, one a lane of GCC's vector types (SSE on
// x86-64): every operation of the test is then one instruction for all of them, with no shuffle.
// Run on one star, its operations were spread over the rim's corners a few at a time, with the
// corners' arrays copied and rotated between them: 70-78 ns a star on the CT's net at 200, 45 a
// star four at a time (a driver, one thread). A lane's floats are worked out as one star alone
// would work them out, so a lane's verdict does not depend on its neighbours.
constexpr int kStarLanes = 4;
using StarFloats = float __attribute__((vector_size(4 * kStarLanes)));
using StarMask = int __attribute__((vector_size(4 * kStarLanes))); // 0 or -1 a lane

// Lane by lane: -1 when the triangles of node `nodes[j]`'s star (its polygons split as
// `along_ac` says) certainly meet only in shared corners and edges, shown without testing pairs:
// projected along the star's mean normal, every triangle keeps its orientation and the star's rim
// turns once around the node, monotonically. Then the projection is one-to-one on the star (the
// rim is a star-shaped polygon around the node and each polygon fills its own wedge of it), so no
// two triangles can meet in space (nor fold: see upright below), and the pair tests of check_cell
// would find nothing. Decided in float with a wide margin; 0 when unsure, and the pairs are
// tested. On a smooth surface this settles nearly every cell.
//
// Only for a closed star of N quads, 3 <= N <= 6 (`codes[j]`, star_code's): 99.4-99.6 % of the
// nodes of the CT's nets at 200 and -500 (a node on the volume border, a non-manifold one, a star
// with a fixed triangle or an unusually large one gets the pair tests). The tests' results are
// joined without branches.
template <int N>
StarMask stars_are_embedded(const SurfaceNet& net, const std::uint32_t (&nodes)[kStarLanes],
                            const std::uint32_t (&codes)[kStarLanes],
                            const std::vector<std::uint8_t>& along_ac,
                            std::span<const glm::vec3> p) {
    constexpr int kRim = 2 * N;
    // The rim from the node: corner 2k is the fan's quad k's corner after the node in winding
    // order (`next`), 2k + 1 its opposite corner, 2k + 2 the next quad's `next`, which is this
    // one's corner before the node. `through[k]`: quad k splits through the node (along its a-c
    // diagonal with the node at a or c).
    StarFloats rx[kRim], ry[kRim], rz[kRim];
    StarMask through[N];
    for (int j = 0; j < kStarLanes; ++j) {
        const std::uint32_t node = nodes[j], code = codes[j], first = net.star_offsets[node];
        const glm::vec3 centre = p[node];
        for (int k = 0; k < N; ++k) {
            const unsigned slot = code >> (kStarCodeBits * k) & 7u,
                           at = code >> (kStarCodeBits * k + 3) & 3u;
            const std::uint32_t id = net.star[first + slot];
            const std::array<std::uint32_t, 4>& c = net.quads[id];
            through[k][j] = (along_ac[id] != 0) == (at % 2 == 0) ? -1 : 0;
            const glm::vec3 a = p[c[(at + 1) & 3u]] - centre, b = p[c[(at + 2) & 3u]] - centre;
            rx[2 * k][j] = a.x, ry[2 * k][j] = a.y, rz[2 * k][j] = a.z;
            rx[2 * k + 1][j] = b.x, ry[2 * k + 1][j] = b.y, rz[2 * k + 1][j] = b.z;
        }
    }
    // turn k = rim k x rim k + 1: the rim's turn from one corner to the next, and the normal of
    // the triangle between them and the node (the two triangles of a quad split through it).
    StarFloats tx[kRim], ty[kRim], tz[kRim];
    for (int k = 0; k < kRim; ++k) {
        const int s = (k + 1) % kRim;
        tx[k] = ry[k] * rz[s] - ry[s] * rz[k];
        ty[k] = rz[k] * rx[s] - rz[s] * rx[k];
        tz[k] = rx[k] * ry[s] - rx[s] * ry[k];
    }
    // The triangles of a quad split through its `next` and its corner before the node instead:
    // (node, next, before) and (next, opposite, before). Formed for every quad, kept for those
    // split so.
    StarFloats ox[2][N], oy[2][N], oz[2][N];
    for (int k = 0; k < N; ++k) {
        const int n = 2 * k, q = 2 * k + 1, v = (2 * k + 2) % kRim;
        ox[0][k] = ry[n] * rz[v] - ry[v] * rz[n];
        oy[0][k] = rz[n] * rx[v] - rz[v] * rx[n];
        oz[0][k] = rx[n] * ry[v] - rx[v] * ry[n];
        const StarFloats ax = rx[q] - rx[n], ay = ry[q] - ry[n], az = rz[q] - rz[n];
        const StarFloats bx = rx[v] - rx[n], by = ry[v] - ry[n], bz = rz[v] - rz[n];
        ox[1][k] = ay * bz - by * az;
        oy[1][k] = az * bx - bz * ax;
        oz[1][k] = ax * by - bx * ay;
    }
    // The star's normal: the sum of its triangles' normals, quad by quad in the fan's order.
    StarFloats nx{}, ny{}, nz{};
    for (int k = 0; k < N; ++k) {
        const StarMask t = through[k];
        nx = t ? (nx + tx[2 * k]) + tx[2 * k + 1] : nx + (ox[0][k] + ox[1][k]);
        ny = t ? (ny + ty[2 * k]) + ty[2 * k + 1] : ny + (oy[0][k] + oy[1][k]);
        nz = t ? (nz + tz[2 * k]) + tz[2 * k + 1] : nz + (oz[0][k] + oz[1][k]);
    }
    // positive(x, size2): x > 0 beyond float rounding, x being a product of vectors whose squared
    // sizes multiply to size2, and of the normal. Compared squared: no square roots.
    constexpr float kMargin2 = 1e-8f; // (1e-4)^2
    const StarFloats normal2 = nx * nx + ny * ny + nz * nz;
    const auto positive = [&](StarFloats x, StarFloats size2) {
        return (x > 0.0f) & (x * x > kMargin2 * size2 * normal2);
    };
    // Every triangle within 85 degrees of the mean normal: then no two of them fold onto each
    // other (normals more than 170 degrees apart, kFoldCos), which the pair test refuses.
    constexpr float kCos85Squared = 0.00759612f;
    const auto upright = [&](StarFloats x, StarFloats y, StarFloats z) {
        const StarFloats along = x * nx + y * ny + z * nz;
        const StarFloats size2 = x * x + y * y + z * z;
        return positive(along, size2) & (along * along > kCos85Squared * size2 * normal2);
    };
    StarMask embedded = through[0] | ~through[0]; // every lane -1
    for (int k = 0; k < N; ++k)
        embedded &= through[k] ? upright(tx[2 * k], ty[2 * k], tz[2 * k]) &
                                     upright(tx[2 * k + 1], ty[2 * k + 1], tz[2 * k + 1])
                               : upright(ox[0][k], oy[0][k], oz[0][k]) &
                                     upright(ox[1][k], oy[1][k], oz[1][k]);
    // Every turn of the rim is positive (under half a turn) ...
    StarFloats rim2[kRim];
    for (int k = 0; k < kRim; ++k) rim2[k] = rx[k] * rx[k] + ry[k] * ry[k] + rz[k] * rz[k];
    for (int k = 0; k < kRim; ++k)
        embedded &= positive(tx[k] * nx + ty[k] * ny + tz[k] * nz, rim2[k] * rim2[(k + 1) % kRim]);
    // ... and only the last one comes back to the first corner's direction: one turn in all.
    // The turn from the first corner to corner k, (rim 0 x rim k) . normal, is
    // rim k . (normal x rim 0).
    const StarFloats ax = ny * rz[0] - ry[0] * nz, ay = nz * rx[0] - rz[0] * nx,
                     az = nx * ry[0] - rx[0] * ny;
    StarFloats turn_from_first[kRim];
    for (int k = 0; k < kRim; ++k) turn_from_first[k] = rx[k] * ax + ry[k] * ay + rz[k] * az;
    for (int k = 1; k + 1 < kRim; ++k)
        embedded &= positive(turn_from_first[k], rim2[k] * rim2[0]) |
                    positive(-turn_from_first[k + 1], rim2[0] * rim2[k + 1]);
    return embedded;
}

// stars_are_embedded for stars of `quads` quads. Not inlined: in the guard's loop over the cells,
// the arrays of its four versions joined the loop's own frame, and a step took longer.
[[gnu::noinline]] StarMask stars_are_embedded(std::uint32_t quads, const SurfaceNet& net,
                                              const std::uint32_t (&nodes)[kStarLanes],
                                              const std::uint32_t (&codes)[kStarLanes],
                                              const std::vector<std::uint8_t>& along_ac,
                                              std::span<const glm::vec3> p) {
    switch (quads) {
    case 3:
        return stars_are_embedded<3>(net, nodes, codes, along_ac, p);
    case 4:
        return stars_are_embedded<4>(net, nodes, codes, along_ac, p);
    case 5:
        return stars_are_embedded<5>(net, nodes, codes, along_ac, p);
    default:
        return stars_are_embedded<6>(net, nodes, codes, along_ac, p);
    }
}

// The later rounds of a step read about one polygon in forty and one cell in ten (around the
// nodes moved back), in increasing order: neighbours in a list rarely share quads or corners, the
// hardware's prefetchers cannot guess the next, and every read waited on memory. On the CT at 200
// a late step's later rounds took 4 times the first round's time a cell and 11 times its time a
// polygon. So each loop over such a list asks ahead in stages, kStageAhead items apart: for the
// farthest item what leads to its data (a node's star offsets, then its star, then a polygon's
// quad), and for nearer ones the data that the stage before has brought by then.
constexpr std::size_t kStageAhead = 4;

// For the list of polygons `ids` at i (< end): the quad two stages ahead, and through
// `corner_data(corner)` what the loop reads of the corners one stage ahead.
template <class CornerData>
void prefetch_polygons_ahead(const SurfaceNet& net, std::span<const std::uint32_t> ids,
                             std::size_t i, std::size_t end, CornerData&& corner_data) {
    if (const std::size_t far = i + 2 * kStageAhead; far < end && ids[far] < net.quads.size())
        detail::prefetch(&net.quads[ids[far]]);
    if (const std::size_t near = i + kStageAhead; near < end && ids[near] < net.quads.size())
        for (const std::uint32_t corner : net.quads[ids[near]]) corner_data(corner);
}

// The first entry of `node`'s star, once its offsets are at hand (a node without polygons at the
// net's end has none).
void prefetch_star(const SurfaceNet& net, std::uint32_t node) {
    if (const std::uint32_t k = net.star_offsets[node]; k < net.star.size())
        detail::prefetch(&net.star[k]);
}

// For the list of nodes `nodes` at i (< end): their stars' offsets two stages ahead, and the
// stars themselves one stage ahead.
void prefetch_node_stars_ahead(const SurfaceNet& net, std::span<const std::uint32_t> nodes,
                               std::size_t i, std::size_t end) {
    if (const std::size_t far = i + 2 * kStageAhead; far < end)
        detail::prefetch(&net.star_offsets[nodes[far]]);
    if (const std::size_t near = i + kStageAhead; near < end) prefetch_star(net, nodes[near]);
}

// For the list of cells `cells` at i (< end), whose nodes `cell_starts` gives, what the star test
// reads of each node's star: its offsets and its star four and three stages ahead, the star's
// quads two stages ahead and their corners' points `p` one stage ahead.
void prefetch_stars_ahead(const SurfaceNet& net, std::span<const std::uint32_t> cell_starts,
                          std::span<const std::uint32_t> cells, std::size_t i, std::size_t end,
                          std::span<const glm::vec3> p) {
    const auto node = [&](std::size_t stages) {
        return cell_starts[cells[i + stages * kStageAhead]];
    };
    const auto star = [&](std::size_t stages) {
        const std::uint32_t n = node(stages);
        return std::span<const std::uint32_t>(net.star).subspan(
            net.star_offsets[n], net.star_offsets[n + 1] - net.star_offsets[n]);
    };
    const auto ahead = [&](std::size_t stages) { return i + stages * kStageAhead < end; };
    if (ahead(4)) detail::prefetch(&net.star_offsets[node(4)]);
    if (ahead(3)) prefetch_star(net, node(3));
    if (ahead(2))
        for (const std::uint32_t id : star(2))
            if (id < net.quads.size()) detail::prefetch(&net.quads[id]);
    if (ahead(1))
        for (const std::uint32_t id : star(1))
            if (id < net.quads.size())
                for (const std::uint32_t corner : net.quads[id]) detail::prefetch(&p[corner]);
}

// Cells waiting for the star test, gathered by their star's size until kStarLanes of one size
// are there (or the cells run out: the lanes left are filled with the first cell again). The net,
// the splits and the points are passed to each call: held as members, they were read again
// through the queue after every store into its batches, and a step took a fifth longer.
class StarQueue {
  public:
    // Queues `cell` (node `node`, star_code `code`); calls unsure(c) for each cell c whose star
    // the test could not settle, once a batch has run.
    template <class Unsure>
    void push(const SurfaceNet& net, std::uint32_t cell, std::uint32_t node, std::uint32_t code,
              const std::vector<std::uint8_t>& along_ac, std::span<const glm::vec3> p,
              Unsure&& unsure) {
        const std::uint32_t size = star_size(code);
        Batch& b = batches_[size - 3];
        b.cells[b.count] = cell, b.nodes[b.count] = node, b.codes[b.count] = code;
        if (++b.count == kStarLanes) run(net, size, along_ac, p, unsure);
    }
    template <class Unsure>
    void finish(const SurfaceNet& net, const std::vector<std::uint8_t>& along_ac,
                std::span<const glm::vec3> p, Unsure&& unsure) {
        for (std::uint32_t size = 3; size <= 6; ++size)
            if (batches_[size - 3].count > 0) run(net, size, along_ac, p, unsure);
    }

  private:
    struct Batch {
        std::uint32_t cells[kStarLanes], nodes[kStarLanes], codes[kStarLanes];
        int count = 0;
    };
    template <class Unsure>
    void run(const SurfaceNet& net, std::uint32_t size, const std::vector<std::uint8_t>& along_ac,
             std::span<const glm::vec3> p, Unsure&& unsure) {
        Batch& b = batches_[size - 3];
        for (int j = b.count; j < kStarLanes; ++j) b.nodes[j] = b.nodes[0], b.codes[j] = b.codes[0];
        const StarMask embedded = stars_are_embedded(size, net, b.nodes, b.codes, along_ac, p);
        for (int j = 0; j < b.count; ++j)
            if (embedded[j] == 0) unsure(b.cells[j]);
        b.count = 0;
    }
    Batch batches_[4]; // stars of 3, 4, 5 and 6 quads
};

} // namespace

bool detail::star_surely_embedded(const SurfaceNet& net, std::uint32_t node,
                                  const std::vector<std::uint8_t>& along_ac,
                                  std::span<const glm::vec3> world) {
    if (node >= net.node_count() || net.star_offsets.size() != net.node_count() + 1 ||
        along_ac.size() != net.quads.size() || world.size() != net.node_count())
        throw std::invalid_argument("star test: a net, a split a quad and a point a node expected");
    const std::uint32_t code = star_code(net, node);
    if (code == 0) return false;
    // The same star in every lane.
    std::uint32_t nodes[kStarLanes], codes[kStarLanes];
    std::fill(std::begin(nodes), std::end(nodes), node);
    std::fill(std::begin(codes), std::end(codes), code);
    return stars_are_embedded(star_size(code), net, nodes, codes, along_ac, world)[0] != 0;
}

namespace {

int shared_corners(const Triangle& a, const Triangle& b) {
    int shared = 0;
    for (const std::uint32_t n : a) shared += n == b[0] || n == b[1] || n == b[2];
    return shared;
}

// Checks every pair of triangles of the polygons around `cell_nodes` (the nodes of one cell),
// except pairs of polygons that did not change (`changed`, per polygon) since a check that
// passed them. Marks the nodes of intersecting pairs in `refused`.
void check_cell(const SurfaceNet& net, std::span<const std::uint32_t> cell_nodes,
                const std::vector<std::uint8_t>& along_ac,
                const std::vector<std::uint8_t>& old_along_ac, Points old_p, Points new_p,
                const std::vector<std::uint8_t>& changed, std::vector<std::uint32_t>& polygons,
                std::vector<TriangleData>& triangles, std::vector<std::uint32_t>& owner,
                std::vector<std::uint8_t>& refused) {
    polygons.clear();
    for (std::uint32_t n : cell_nodes)
        polygons.insert(polygons.end(), net.star.begin() + net.star_offsets[n],
                        net.star.begin() + net.star_offsets[n + 1]);
    std::sort(polygons.begin(), polygons.end());
    polygons.erase(std::unique(polygons.begin(), polygons.end()), polygons.end());
    triangles.clear();
    owner.clear(); // first triangle of each polygon, and one past the last at the end
    for (std::uint32_t id : polygons) {
        owner.push_back(std::uint32_t(triangles.size()));
        Triangle t[2];
        const int count = split_polygon(net, id, id < along_ac.size() && along_ac[id] != 0, t);
        for (int k = 0; k < count; ++k) triangles.push_back(triangle_data(t[k], new_p.world));
    }
    owner.push_back(std::uint32_t(triangles.size()));
    // A pair of polygons is checked in one cell only: that of the lowest node they share (link
    // nodes aside: their polygons also hold the two pieces they link), or in every cell they
    // meet in when they share none (pieces of one cell).
    const auto in_cell = [&](std::uint32_t n) {
        return std::find(cell_nodes.begin(), cell_nodes.end(), n) != cell_nodes.end();
    };
    for (std::size_t i = 0; i < polygons.size(); ++i) {
        std::array<std::uint32_t, 4> ci{};
        const int ni = polygon_corners(net, polygons[i], ci);
        for (std::size_t j = i; j < polygons.size(); ++j) {
            if (!changed[polygons[i]] && !changed[polygons[j]]) continue;
            std::array<std::uint32_t, 4> cj{};
            const int nj = polygon_corners(net, polygons[j], cj);
            std::uint32_t lowest = UINT32_MAX;
            for (int x = 0; x < ni; ++x)
                for (int y = 0; y < nj; ++y)
                    if (ci[std::size_t(x)] == cj[std::size_t(y)] &&
                        net.pieces[ci[std::size_t(x)]] != kLinkNodePiece)
                        lowest = std::min(lowest, ci[std::size_t(x)]);
            if (lowest != UINT32_MAX && !in_cell(lowest)) continue;
            for (std::uint32_t u = owner[i]; u < owner[i + 1]; ++u)
                for (std::uint32_t v = i == j ? u + 1 : owner[j]; v < owner[j + 1]; ++v) {
                    const TriangleData& ta = triangles[u];
                    const TriangleData& tb = triangles[v];
                    if (glm::any(glm::lessThan(ta.hi, tb.lo)) ||
                        glm::any(glm::lessThan(tb.hi, ta.lo)))
                        continue;
                    if (shared_corners(ta.nodes, tb.nodes) == 2) {
                        // Neighbours across an edge meet only there; a fold is what can go
                        // wrong between them.
                        // A pair that was not in the mesh before (a quad's diagonal flipped)
                        // counts as unfolded then.
                        const auto same_split = [&](std::size_t polygon) {
                            const std::uint32_t id = polygons[polygon];
                            return id >= along_ac.size() || along_ac[id] == old_along_ac[id];
                        };
                        const double now = normal_cos(ta.nodes, tb.nodes, new_p);
                        if (now < -kFoldCos && (!same_split(i) || !same_split(j) ||
                                                now < normal_cos(ta.nodes, tb.nodes, old_p))) {
                            // Every corner of both polygons: a fold a flipped diagonal shows
                            // may come from a corner that is in neither triangle.
                            for (int k = 0; k < ni; ++k) mark(refused, ci[std::size_t(k)]);
                            for (int k = 0; k < nj; ++k) mark(refused, cj[std::size_t(k)]);
                            continue;
                        }
                    }
                    if (separated_by_plane(ta, tb) || separated_by_plane(tb, ta)) continue;
                    if (separated_by_edge_plane(ta, tb) || separated_by_edge_plane(tb, ta))
                        continue;
                    if (!triangles_intersect(ta.corner, tb.corner)) continue;
                    for (std::uint32_t n : ta.nodes) mark(refused, n);
                    for (std::uint32_t n : tb.nodes) mark(refused, n);
                }
        }
    }
}

// For the polygons `ids` (every polygon when empty): records how each quad splits at the new
// positions in `along_ac`, and marks the nodes of those that became slivers (or worse ones) in
// `refused`.
void check_quality(const SurfaceNet& net, TriangulationRule rule, glm::vec3 spacing, Points old_p,
                   Points new_p, std::span<const std::uint32_t> ids,
                   std::vector<std::uint8_t>& along_ac, std::vector<std::uint8_t>& refused) {
    const std::size_t polygons = ids.empty() ? net.quads.size() + net.triangles.size() : ids.size();
    const auto split_of = [&](std::uint32_t id) {
        const bool split_new = splits_along_ac(net, id, new_p.index, rule, spacing);
        along_ac[id] = split_new ? 1 : 0;
        return split_new;
    };
    // What follows a polygon's quality at the new positions, q.
    const auto check = [&](std::uint32_t id, float q) {
        if (q >= float(kSliverQuality)) return;
        const bool split_old =
            id < net.quads.size() && splits_along_ac(net, id, old_p.index, rule, spacing);
        if (q >= polygon_quality(net, id, old_p, split_old)) return;
        std::array<std::uint32_t, 4> corners{};
        const int count = polygon_corners(net, id, corners);
        for (int k = 0; k < count; ++k) mark(refused, corners[std::size_t(k)]);
    };
    for_each_chunk(polygons, 4096, [&](std::size_t, std::size_t b, std::size_t e) {
        std::size_t i = b;
        // Every quad (the first round): in blocks, both triangles' first test side by side
        // (polygon_quality gives 1 where both pass), the rare quad that fails it measured alone.
        constexpr std::size_t kQuads = kTriangleBlock / 2;
        const std::size_t block_end = ids.empty() ? std::min(e, net.quads.size()) : b;
        for (; i + kQuads <= block_end; i += kQuads) {
            TriangleBlock block;
            bool split[kQuads];
            for (std::size_t j = 0; j < kQuads; ++j) {
                const auto id = std::uint32_t(i + j);
                split[j] = split_of(id);
                const auto& q = net.quads[id];
                const auto& c = kQuadSplitCorners[split[j] ? 1 : 0];
                for (int t = 0; t < 2; ++t)
                    block.set(int(2 * j) + t, new_p.world_at(q[c[t][0]]),
                              new_p.world_at(q[c[t][1]]), new_p.world_at(q[c[t][2]]));
            }
            int no_sliver[kTriangleBlock];
            no_slivers(block, no_sliver);
            for (std::size_t j = 0; j < kQuads; ++j) {
                if (no_sliver[2 * j] & no_sliver[2 * j + 1]) continue;
                const auto id = std::uint32_t(i + j);
                check(id, polygon_quality(net, id, new_p, split[j]));
            }
        }
        for (; i < e; ++i) {
            if (!ids.empty())
                prefetch_polygons_ahead(net, ids, i, e, [&](std::uint32_t corner) {
                    detail::prefetch(&new_p.index[corner]);
                    detail::prefetch(&new_p.world[corner]);
                });
            const auto id = ids.empty() ? std::uint32_t(i) : ids[i];
            const bool split_new = id < net.quads.size() && split_of(id);
            check(id, polygon_quality(net, id, new_p, split_new));
        }
    });
}

// Marks the obtuse corner of triangle (a, b, c) (points in shape space, nodes `nodes`) when it is
// a sliver.
void mark_sliver_apex(const glm::vec3& a, const glm::vec3& b, const glm::vec3& c,
                      const std::uint32_t (&nodes)[3], std::vector<std::uint8_t>& apex) {
    if (sliver_quality(a, b, c) >= float(kSliverQuality)) return;
    const glm::vec3* p[3] = {&a, &b, &c};
    for (int k = 0; k < 3; ++k)
        if (glm::dot(*p[(k + 1) % 3] - *p[k], *p[(k + 2) % 3] - *p[k]) < 0.0f) mark(apex, nodes[k]);
}

} // namespace

std::vector<std::uint8_t> sliver_apexes(const SurfaceNet& net, TriangulationRule rule,
                                        glm::vec3 shape, std::span<const glm::vec3> positions,
                                        std::span<const std::uint8_t> splits) {
    if (!splits.empty() && splits.size() != net.quads.size())
        throw std::invalid_argument("sliver apexes: splits are not one per quad");
    std::vector<std::uint8_t> apex; // a step's fresh buffer: on huge pages, not 4 KiB ones
    detail::assign_on_huge_pages(apex, net.node_count(), std::uint8_t(0));
    const std::size_t quads = net.quads.size();
    // Every step's first pass over all triangles, which nearly never meets a sliver: a quad's four
    // corners are scaled once and its two triangles taken from them in place (the triangles
    // copied out of split_polygon stalled on their own stores).
    for_each_chunk(
        quads + net.triangles.size(), 4096, [&](std::size_t, std::size_t b, std::size_t e) {
            // A quad's corners in shape space and its split's triangles.
            const auto quad_corners = [&](std::size_t quad,
                                          glm::vec3(&p)[4]) -> const std::uint8_t(&)[2][3] {
                const auto& q = net.quads[quad];
                for (int k = 0; k < 4; ++k) p[k] = positions[q[std::size_t(k)]] * shape;
                const bool along = splits.empty() ? splits_along_ac(net, std::uint32_t(quad),
                                                                    positions, rule, shape)
                                                  : splits[quad] != 0;
                return kQuadSplitCorners[along ? 1 : 0];
            };
            const auto mark_quad = [&](std::size_t quad, const glm::vec3(&p)[4],
                                       const std::uint8_t(&split)[2][3], int triangle) {
                const auto& q = net.quads[quad];
                const auto& c = split[triangle];
                mark_sliver_apex(p[c[0]], p[c[1]], p[c[2]], {q[c[0]], q[c[1]], q[c[2]]}, apex);
            };
            // Quads in blocks: both triangles' first test side by side, the rare triangle that
            // fails it measured alone.
            constexpr std::size_t kQuads = kTriangleBlock / 2;
            std::size_t i = b;
            const std::size_t end = std::min(e, quads);
            for (; i + kQuads <= end; i += kQuads) {
                TriangleBlock block;
                for (std::size_t j = 0; j < kQuads; ++j) {
                    glm::vec3 p[4];
                    const auto& split = quad_corners(i + j, p);
                    for (int t = 0; t < 2; ++t)
                        block.set(int(2 * j) + t, p[split[t][0]], p[split[t][1]], p[split[t][2]]);
                }
                int no_sliver[kTriangleBlock];
                no_slivers(block, no_sliver);
                for (std::size_t j = 0; j < kQuads; ++j) {
                    if (no_sliver[2 * j] & no_sliver[2 * j + 1]) continue;
                    glm::vec3 p[4];
                    const auto& split = quad_corners(i + j, p);
                    for (int t = 0; t < 2; ++t) mark_quad(i + j, p, split, t);
                }
            }
            for (; i < end; ++i) {
                glm::vec3 p[4];
                const auto& split = quad_corners(i, p);
                for (int t = 0; t < 2; ++t) mark_quad(i, p, split, t);
            }
            for (i = std::max(b, quads); i < e; ++i) {
                const auto& t = net.triangles[i - quads];
                mark_sliver_apex(positions[t[0]] * shape, positions[t[1]] * shape,
                                 positions[t[2]] * shape, {t[0], t[1], t[2]}, apex);
            }
        });
    return apex;
}

glm::vec3 sliver_relief(const SurfaceNet& net, TriangulationRule rule, glm::vec3 shape,
                        std::span<const glm::vec3> positions, std::uint32_t node) {
    if (net.star_offsets.size() != net.node_count() + 1) return glm::vec3(0.0f);
    glm::vec3 push(0.0f);
    const glm::vec3 p = positions[node] * shape;
    for (std::uint32_t k = net.star_offsets[node]; k < net.star_offsets[node + 1]; ++k) {
        const std::uint32_t id = net.star[k];
        Triangle t[2];
        const bool along =
            id < net.quads.size() && splits_along_ac(net, id, positions, rule, shape);
        const int count = split_polygon(net, id, along, t);
        for (int j = 0; j < count; ++j) {
            int at = -1;
            for (int c = 0; c < 3; ++c)
                if (t[j][std::size_t(c)] == node) at = c;
            if (at < 0) continue;
            const glm::vec3 a = positions[t[j][std::size_t((at + 1) % 3)]] * shape;
            const glm::vec3 b = positions[t[j][std::size_t((at + 2) % 3)]] * shape;
            if (sliver_quality(p, a, b) >= float(kSliverQuality)) continue;
            // The node at the obtuse corner of a cap: lift it off the opposite side, towards the
            // right isosceles triangle of a flat net (height half the side).
            const glm::vec3 ab = b - a;
            const float base = glm::length(ab);
            if (!(base > 0.0f) || glm::dot(a - p, b - p) >= 0.0f) continue;
            const glm::vec3 foot = a + ab * (glm::dot(p - a, ab) / (base * base));
            const float height = glm::length(p - foot), wanted = 0.5f * base;
            if (height < 1e-4f * base || height >= wanted) continue;
            push += (wanted - height) * (p - foot) / height;
        }
    }
    return push / shape;
}

// The net's cells and the step's buffers (see the header), and where the last step left the
// nodes: `along_ac` holds their splits while `ended_at` names that buffer.
struct MeshGuardScratch::Impl {
    // Cells: runs of nodes with the same cell (cell_starts: the first node of each), plus the
    // border copies of their nodes (appended at the end of the net, sorted by cell). A link node
    // needs no place: its polygons all hold a node of its cell.
    const SurfaceNet* net = nullptr;
    std::size_t net_nodes = 0, net_polygons = 0; // the net's size when it was taken
    std::vector<std::uint32_t> cell_starts;
    std::vector<std::pair<glm::ivec3, std::uint32_t>> copies;
    // Per cell: star_code of its node when it holds one alone, else 0 (its pairs are tested).
    std::vector<std::uint32_t> star_codes;
    std::vector<std::uint32_t> cell_of; // node -> cell (index of cell_starts), made when needed
    std::vector<glm::vec3> new_world;
    std::vector<std::uint8_t> changed, refused, shortened, along_ac, old_along_ac;
    std::vector<std::uint8_t> is_dirty; // a flag a cell, all clear between rounds
    std::vector<std::uint32_t> changed_ids, dirty_cells, moved;
    const glm::vec3* ended_at = nullptr;
    std::size_t ended_size = 0;
    TriangulationRule rule{};
    glm::vec3 spacing{0.0f};

    static constexpr std::uint32_t kNoCell = UINT32_MAX;

    void use_net(const SurfaceNet& n);
    void cell_nodes(std::size_t c, std::vector<std::uint32_t>& out) const;
    void make_cell_of();
};

MeshGuardScratch::MeshGuardScratch() : impl_(std::make_unique<Impl>()) {}
MeshGuardScratch::~MeshGuardScratch() = default;
MeshGuardScratch::MeshGuardScratch(MeshGuardScratch&&) noexcept = default;
MeshGuardScratch& MeshGuardScratch::operator=(MeshGuardScratch&&) noexcept = default;

std::span<const std::uint8_t>
MeshGuardScratch::splits_at(std::span<const glm::vec3> positions) const {
    if (!impl_ || impl_->ended_at == nullptr || positions.data() != impl_->ended_at ||
        positions.size() != impl_->ended_size)
        return {};
    return impl_->along_ac;
}

namespace {

bool cell_less(glm::ivec3 a, glm::ivec3 b) {
    return a.z != b.z ? a.z < b.z : a.y != b.y ? a.y < b.y : a.x < b.x;
}

} // namespace

void MeshGuardScratch::Impl::use_net(const SurfaceNet& n) {
    const std::size_t polygons = n.quads.size() + n.triangles.size();
    if (net == &n && net_nodes == n.node_count() && net_polygons == polygons) return;
    net = &n;
    net_nodes = n.node_count();
    net_polygons = polygons;
    ended_at = nullptr;
    cell_of.clear();
    const std::size_t nodes = n.node_count();
    detail::assign_on_huge_pages(cell_starts,
                                 std::size_t(std::count(n.pieces.begin(), n.pieces.end(), 0)));
    copies.clear();
    for (std::uint32_t i = 0, c = 0; i < nodes; ++i) {
        if (n.pieces[i] == 0) cell_starts[c++] = i;
        if (n.pieces[i] == kBorderCopyPiece) copies.push_back({n.cells[i], i});
    }
    std::sort(copies.begin(), copies.end(), [&](const auto& a, const auto& b) {
        return cell_less(a.first, b.first) || (a.first == b.first && a.second < b.second);
    });
    detail::assign_on_huge_pages(star_codes, cell_starts.size(), 0u);
    for_each_chunk(cell_starts.size(), 4096, [&](std::size_t, std::size_t b, std::size_t e) {
        std::vector<std::uint32_t> members;
        for (std::size_t c = b; c < e; ++c) {
            cell_nodes(c, members);
            star_codes[c] = members.size() == 1 ? star_code(n, members[0]) : 0;
        }
    });
}

void MeshGuardScratch::Impl::cell_nodes(std::size_t c, std::vector<std::uint32_t>& out) const {
    out.clear();
    const std::size_t nodes = net->node_count();
    const std::uint32_t first = cell_starts[c];
    out.push_back(first);
    for (std::uint32_t n = first + 1;
         n < nodes && net->pieces[n] != 0 && net->pieces[n] < kBorderCopyPiece; ++n)
        out.push_back(n);
    const glm::ivec3 cell = net->cells[first];
    auto it = std::lower_bound(copies.begin(), copies.end(), cell,
                               [&](const auto& e, glm::ivec3 v) { return cell_less(e.first, v); });
    for (; it != copies.end() && it->first == cell; ++it) out.push_back(it->second);
}

// Once per net: the later rounds of every step look up the cells of a few nodes.
void MeshGuardScratch::Impl::make_cell_of() {
    if (!cell_of.empty()) return;
    detail::assign_on_huge_pages(cell_of, net->node_count(), kNoCell);
    std::vector<std::uint32_t> members;
    for (std::size_t c = 0; c < cell_starts.size(); ++c) {
        cell_nodes(c, members);
        for (std::uint32_t n : members) cell_of[n] = std::uint32_t(c);
    }
}

std::size_t keep_mesh_valid(const SurfaceNet& net, TriangulationRule rule, glm::vec3 spacing,
                            const IndexToWorld& to_world, std::span<const glm::vec3> old_positions,
                            std::span<glm::vec3> new_positions, MeshGuardScratch* scratch) {
    const std::size_t nodes = net.node_count();
    if (net.star_offsets.size() != nodes + 1) return 0; // a net without polygons
    MeshGuardScratch own;
    MeshGuardScratch::Impl& s = *(scratch != nullptr ? scratch : &own)->impl_;
    s.use_net(net);
    // The splits the last step left, when this step starts where it ended (with the same rule).
    const bool carried = s.ended_at == old_positions.data() &&
                         s.ended_size == old_positions.size() && s.rule == rule &&
                         s.spacing == spacing && s.along_ac.size() == net.quads.size();
    s.ended_at = nullptr;
    s.rule = rule;
    s.spacing = spacing;
    // Every entry is written below: sized only when the net's size changed, not zeroed each step.
    if (s.new_world.size() != nodes) detail::assign_on_huge_pages(s.new_world, nodes);
    std::vector<glm::vec3>& new_world = s.new_world;
    for_each_chunk(nodes, 4096, [&](std::size_t, std::size_t b, std::size_t e) {
        for (std::size_t i = b; i < e; ++i) new_world[i] = to_world(new_positions[i]);
    });
    const Points old_p{old_positions, {}, &to_world}, new_p{new_positions, new_world};

    // The first round checks every polygon and cell. A later one only what the refused moves
    // changed: the polygons around the nodes moved back (`changed`, also as flags for
    // check_cell's pairs) and the cells of those polygons' nodes (`dirty_cells`); on real scans a
    // step takes several rounds, each with a few nodes.
    const std::size_t polygon_count = net.quads.size() + net.triangles.size();
    std::vector<std::uint8_t>& changed = s.changed;
    detail::assign_on_huge_pages(changed, polygon_count, std::uint8_t(1));
    std::vector<std::uint32_t>& changed_ids = s.changed_ids;
    std::vector<std::uint32_t>& dirty_cells = s.dirty_cells;
    std::vector<std::uint32_t>& moved = s.moved;
    changed_ids.clear();
    dirty_cells.clear();
    std::vector<std::uint8_t>& refused = s.refused;
    std::vector<std::uint8_t>& shortened = s.shortened;
    std::vector<std::uint8_t>& along_ac = s.along_ac;
    std::vector<std::uint8_t>& old_along_ac = s.old_along_ac;
    detail::assign_on_huge_pages(refused, nodes, std::uint8_t(0));
    detail::assign_on_huge_pages(shortened, nodes, std::uint8_t(0));
    // How each quad splits at the old positions: the mesh the step starts from.
    if (carried) {
        std::swap(along_ac, old_along_ac);
    } else {
        detail::assign_on_huge_pages(old_along_ac, net.quads.size(), std::uint8_t(0));
        for_each_chunk(net.quads.size(), 4096, [&](std::size_t, std::size_t b, std::size_t e) {
            for (std::size_t id = b; id < e; ++id)
                old_along_ac[id] =
                    splits_along_ac(net, std::uint32_t(id), old_positions, rule, spacing) ? 1 : 0;
        });
    }
    detail::assign_on_huge_pages(along_ac, net.quads.size(), std::uint8_t(0));
    constexpr int kHalvings = 2, kMaxRounds = 64;
    bool settled = false; // the last round moved nothing: along_ac is the final positions' split
    for (int round = 0; round < kMaxRounds; ++round) {
        check_quality(net, rule, spacing, old_p, new_p, changed_ids, along_ac, refused);
        constexpr std::size_t kChunk = 1024;
        const std::size_t cells = round == 0 ? s.cell_starts.size() : dirty_cells.size();
        for_each_chunk(cells, kChunk, [&](std::size_t, std::size_t b, std::size_t e) {
            std::vector<std::uint32_t> polygons, members, owner;
            std::vector<TriangleData> triangles;
            const auto check_pairs = [&](std::size_t cell) {
                s.cell_nodes(cell, members);
                check_cell(net, members, along_ac, old_along_ac, old_p, new_p, changed, polygons,
                           triangles, owner, refused);
            };
            StarQueue stars;
            for (std::size_t i = b; i < e; ++i) {
                if (round > 0)
                    prefetch_stars_ahead(net, s.cell_starts, dirty_cells, i, e, new_p.world);
                const std::uint32_t cell = round == 0 ? std::uint32_t(i) : dirty_cells[i];
                if (const std::uint32_t code = s.star_codes[cell]; code != 0)
                    stars.push(net, cell, s.cell_starts[cell], code, along_ac, new_p.world,
                               check_pairs);
                else
                    check_pairs(cell);
            }
            stars.finish(net, along_ac, new_p.world, check_pairs);
        });
        // Shorten the refused moves, and check again around them.
        moved.clear();
        list_set_flags(refused, moved, true);
        std::erase_if(moved, [&](std::uint32_t n) { return new_positions[n] == old_positions[n]; });
        for (const std::uint32_t n : moved) {
            shortened[n] = 1;
            new_positions[n] = round < kHalvings
                                   ? old_positions[n] + 0.5f * (new_positions[n] - old_positions[n])
                                   : old_positions[n];
            new_world[n] = to_world(new_positions[n]);
        }
        if (moved.empty()) {
            settled = true;
            break;
        }
        if (round == 0)
            std::fill(changed.begin(), changed.end(), 0);
        else
            for (std::uint32_t id : changed_ids) changed[id] = 0;
        changed_ids.clear();
        // The polygons around the moved nodes and then their cells are flagged on every thread
        // (each flag is only ever set, so the order does not matter) and listed in increasing
        // order. These gathers asked for one sparse polygon or node after another and waited
        // on memory at each (7 ms of a step on one thread): they ask ahead, as above.
        constexpr std::size_t kGatherChunk = 512;
        for_each_chunk(moved.size(), kGatherChunk, [&](std::size_t, std::size_t b, std::size_t e) {
            for (std::size_t i = b; i < e; ++i) {
                prefetch_node_stars_ahead(net, moved, i, e);
                for (std::uint32_t k = net.star_offsets[moved[i]];
                     k < net.star_offsets[moved[i] + 1]; ++k)
                    mark(changed, net.star[k]);
            }
        });
        list_set_flags(changed, changed_ids, false);
        if (changed_ids.empty()) {
            settled = true; // the nodes moved back hold no polygon
            break;
        }
        s.make_cell_of();
        if (s.is_dirty.size() != s.cell_starts.size()) s.is_dirty.assign(s.cell_starts.size(), 0);
        for_each_chunk(
            changed_ids.size(), kGatherChunk, [&](std::size_t, std::size_t b, std::size_t e) {
                for (std::size_t i = b; i < e; ++i) {
                    prefetch_polygons_ahead(net, changed_ids, i, e, [&](std::uint32_t corner) {
                        detail::prefetch(&s.cell_of[corner]);
                    });
                    std::array<std::uint32_t, 4> corners{};
                    const int count = polygon_corners(net, changed_ids[i], corners);
                    for (int k = 0; k < count; ++k)
                        if (const std::uint32_t c = s.cell_of[corners[std::size_t(k)]];
                            c != MeshGuardScratch::Impl::kNoCell)
                            mark(s.is_dirty, c);
                }
            });
        dirty_cells.clear();
        list_set_flags(s.is_dirty, dirty_cells, true);
    }
    // Out of rounds: the last moves' polygons were not split again.
    if (!settled)
        for (const std::uint32_t id : changed_ids)
            if (id < net.quads.size())
                along_ac[id] = splits_along_ac(net, id, new_positions, rule, spacing) ? 1 : 0;
    s.ended_at = new_positions.data();
    s.ended_size = new_positions.size();
    return std::size_t(std::count(shortened.begin(), shortened.end(), 1));
}

} // namespace snert
