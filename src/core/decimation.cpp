// Decimation with meshoptimizer's simplifier, checked step by step.
//
// This work is based on:
// Michael Garland and Paul S. Heckbert. Surface simplification using quadric error metrics. 1997
// (through meshoptimizer's meshopt_simplify, which implements it).
#include "decimation.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <unordered_map>
#include <utility>

#include <meshoptimizer.h>

#include "metrics.h"
#include "parallel.h"
#include "triangle_intersection.h"

namespace snert {

namespace {

using Indices = std::vector<std::uint32_t>;

// A triangle as a key that keeps its orientation: rotated so its smallest index comes first.
std::uint64_t triangle_key_part(std::uint32_t a, std::uint32_t b) {
    return (std::uint64_t(a) << 32) | b;
}
struct TriangleKey {
    std::uint32_t a, b, c;
    bool operator==(const TriangleKey&) const = default;
};
struct TriangleKeyHash {
    std::size_t operator()(const TriangleKey& k) const {
        // Mixed so that the low bits (the slot) depend on every index.
        std::uint64_t h =
            (triangle_key_part(k.a, k.b) ^ (std::uint64_t(k.c) << 21)) * 0x9E3779B97F4A7C15ull;
        h ^= h >> 29;
        h *= 0xBF58476D1CE4E5B9ull;
        return std::size_t(h ^ (h >> 32));
    }
};
TriangleKey triangle_key(const std::uint32_t* t) {
    if (t[1] < t[0] && t[1] < t[2]) return {t[1], t[2], t[0]};
    if (t[2] < t[0] && t[2] < t[1]) return {t[2], t[0], t[1]};
    return {t[0], t[1], t[2]};
}

void mark_boundary(const std::vector<std::uint32_t>& indices, std::vector<std::uint8_t>& boundary);

// What the result is checked against: facts of the input mesh.
struct Reference {
    std::vector<glm::vec3> normals;     // area-weighted vertex normals of the input
    std::vector<std::uint8_t> boundary; // 1: the vertex is on an input boundary edge
    bool manifold = false, oriented = false;
    long euler = 0;
};

Reference make_reference(const Mesh& mesh) {
    Reference r;
    r.normals.assign(mesh.positions.size(), glm::vec3(0.0f));
    r.boundary.assign(mesh.positions.size(), 0);
    for (std::size_t t = 0; t < mesh.triangle_count(); ++t) {
        const std::uint32_t* i = &mesh.indices[3 * t];
        const glm::vec3 n = glm::cross(mesh.positions[i[1]] - mesh.positions[i[0]],
                                       mesh.positions[i[2]] - mesh.positions[i[0]]);
        for (int k = 0; k < 3; ++k) r.normals[i[k]] += n;
    }
    mark_boundary(mesh.indices, r.boundary);
    const Topology topo = topology(mesh);
    r.manifold = topo.manifold;
    r.oriented = topo.oriented;
    r.euler = topo.euler;
    return r;
}

// An undirected edge of a triangle, with its direction in that triangle.
struct HalfEdge {
    std::uint32_t lo, hi;
    bool forward; // lo -> hi in the triangle
    bool operator<(const HalfEdge& o) const {
        return lo != o.lo ? lo < o.lo : hi != o.hi ? hi < o.hi : forward < o.forward;
    }
};

// Vertices where a candidate breaks a rule, and how many triangles/edges each rule flagged.
struct Verdict {
    std::vector<std::uint32_t> vertices;
    std::size_t topology = 0, intersections = 0, flips = 0, degenerate = 0;
    bool ok() const { return vertices.empty(); }
};

void mark_boundary(const Indices& indices, std::vector<std::uint8_t>& boundary) {
    std::vector<HalfEdge> edges;
    edges.reserve(indices.size());
    for (std::size_t t = 0; t + 2 < indices.size(); t += 3)
        for (int k = 0; k < 3; ++k) {
            const std::uint32_t a = indices[t + k], b = indices[t + (k + 1) % 3];
            if (a != b) edges.push_back({std::min(a, b), std::max(a, b), a < b});
        }
    std::sort(edges.begin(), edges.end());
    for (std::size_t i = 0; i < edges.size();) {
        std::size_t j = i;
        while (j < edges.size() && edges[j].lo == edges[i].lo && edges[j].hi == edges[i].hi) ++j;
        if (j - i == 1) boundary[edges[i].lo] = boundary[edges[i].hi] = 1;
        i = j;
    }
}

// The triangles of one mesh as a set of oriented keys.
// A set of triangles, open addressing with linear probing: built and probed for every triangle of
// every try, where a node-based set's allocations would cost more than the checks themselves.
class TriangleSet {
  public:
    TriangleSet() = default;
    explicit TriangleSet(std::size_t count) {
        std::size_t size = 16;
        while (size < 2 * count) size *= 2;
        slots_.assign(size, kEmpty);
    }
    void insert(const TriangleKey& k) {
        for (std::size_t s = slot_of(k);; s = (s + 1) & (slots_.size() - 1)) {
            if (slots_[s] == k) return;
            if (slots_[s] == kEmpty) {
                slots_[s] = k;
                return;
            }
        }
    }
    bool contains(const TriangleKey& k) const {
        if (slots_.empty()) return false;
        for (std::size_t s = slot_of(k);; s = (s + 1) & (slots_.size() - 1)) {
            if (slots_[s] == k) return true;
            if (slots_[s] == kEmpty) return false;
        }
    }

  private:
    static constexpr TriangleKey kEmpty{~0u, ~0u, ~0u}; // no triangle has three equal corners
    std::size_t slot_of(const TriangleKey& k) const {
        return TriangleKeyHash{}(k) & (slots_.size() - 1);
    }
    std::vector<TriangleKey> slots_;
};

TriangleSet triangle_set(const Indices& c) {
    TriangleSet set(c.size() / 3);
    for (std::size_t t = 0; t < c.size(); t += 3) set.insert(triangle_key(&c[t]));
    return set;
}

// What a try changed, against the mesh it was made from: the candidate's new triangles, and the
// vertices of every triangle that came or went. Only there can an edge or a fan have changed.
struct Change {
    std::vector<std::uint8_t> is_new;  // per candidate triangle
    std::vector<std::uint8_t> touched; // per vertex
};

// `c` is what the collapses made of `changed`, the mesh's triangles: only those can be new or
// gone.
Change change_of(const Indices& c, const Indices& changed, const TriangleSet& from_set,
                 std::size_t vertex_count) {
    Change ch;
    ch.is_new.assign(c.size() / 3, 0);
    ch.touched.assign(vertex_count, 0);
    for (std::size_t t = 0; t < ch.is_new.size(); ++t) {
        const std::uint32_t* i = &c[3 * t];
        if (from_set.contains(triangle_key(i))) continue;
        ch.is_new[t] = 1;
        for (int k = 0; k < 3; ++k) ch.touched[i[k]] = 1;
    }
    const TriangleSet made_set = triangle_set(c);
    for (std::size_t t = 0; t < changed.size(); t += 3)
        if (!made_set.contains(triangle_key(&changed[t])))
            for (int k = 0; k < 3; ++k) ch.touched[changed[t + k]] = 1;
    return ch;
}

// Edges of three or more triangles, edges used twice in one direction, new boundary edges;
// among the edges between touched vertices (the only ones whose triangles changed).
void check_edges(const Indices& c, const Change& ch, const Reference& ref, Verdict& v) {
    std::vector<HalfEdge> edges;
    for (std::size_t t = 0; t < c.size(); t += 3)
        for (int k = 0; k < 3; ++k) {
            const std::uint32_t a = c[t + k], b = c[t + (k + 1) % 3];
            if (a != b && ch.touched[a] && ch.touched[b])
                edges.push_back({std::min(a, b), std::max(a, b), a < b});
        }
    std::sort(edges.begin(), edges.end());
    for (std::size_t i = 0; i < edges.size();) {
        std::size_t j = i;
        while (j < edges.size() && edges[j].lo == edges[i].lo && edges[j].hi == edges[i].hi) ++j;
        const std::size_t n = j - i;
        const std::uint32_t lo = edges[i].lo, hi = edges[i].hi;
        const bool bad = (n >= 3 && ref.manifold) ||
                         (n == 2 && ref.oriented && edges[i].forward == edges[i + 1].forward) ||
                         (n == 1 && !(ref.boundary[lo] && ref.boundary[hi]));
        if (bad) {
            ++v.topology;
            v.vertices.push_back(lo);
            v.vertices.push_back(hi);
        }
        i = j;
    }
}

// The connected components of a mesh (over shared vertices) and the triangle count of each. A
// collapse never joins two components, so a candidate's triangles are counted in the components
// of the mesh it was made from.
struct Components {
    std::vector<std::uint32_t> of_vertex; // component of each vertex (unused: any)
    std::vector<std::size_t> triangles;
};

// Fills `triangles` of `comp` for the mesh `c` (whose vertices it labels).
void count_components(const Indices& c, Components& comp) {
    std::fill(comp.triangles.begin(), comp.triangles.end(), 0);
    for (std::size_t t = 0; t < c.size(); t += 3) ++comp.triangles[comp.of_vertex[c[t]]];
}

Components components(const Indices& c, std::size_t vertex_count) {
    std::vector<std::uint32_t> parent(vertex_count);
    for (std::size_t i = 0; i < vertex_count; ++i) parent[i] = std::uint32_t(i);
    auto root = [&](std::uint32_t x) {
        while (parent[x] != x) x = parent[x] = parent[parent[x]];
        return x;
    };
    for (std::size_t t = 0; t < c.size(); t += 3) {
        parent[root(c[t + 1])] = root(c[t]);
        parent[root(c[t + 2])] = root(c[t]);
    }
    Components comp;
    comp.of_vertex.assign(vertex_count, 0);
    std::vector<std::uint32_t> id(vertex_count, ~0u);
    std::uint32_t count = 0;
    for (std::size_t i = 0; i < vertex_count; ++i) {
        const std::uint32_t r = root(std::uint32_t(i));
        if (id[r] == ~0u) id[r] = count++;
        comp.of_vertex[i] = id[r];
    }
    comp.triangles.assign(count, 0);
    count_components(c, comp);
    return comp;
}

// A vertex is manifold when the far edges of its triangles (its link) form one path or cycle.
// Only touched vertices: no other fan changed.
void check_fans(const Indices& c, const Change& ch, Verdict& v) {
    std::vector<std::uint32_t> local_of(ch.touched.size(), ~0u), verts;
    for (std::uint32_t i = 0; i < ch.touched.size(); ++i)
        if (ch.touched[i]) {
            local_of[i] = std::uint32_t(verts.size());
            verts.push_back(i);
        }
    std::vector<std::uint32_t> start(verts.size() + 1, 0);
    for (const std::uint32_t i : c)
        if (local_of[i] != ~0u) ++start[local_of[i] + 1];
    for (std::size_t i = 0; i < verts.size(); ++i) start[i + 1] += start[i];
    std::vector<std::uint32_t> tris(start.back());
    std::vector<std::uint32_t> fill(start.begin(), start.end() - 1);
    for (std::size_t k = 0; k < c.size(); ++k)
        if (local_of[c[k]] != ~0u) tris[fill[local_of[c[k]]]++] = std::uint32_t(k / 3);
    std::vector<std::uint32_t> link, parent;
    std::vector<int> degree;
    for (std::uint32_t lv = 0; lv < verts.size(); ++lv) {
        const std::uint32_t vert = verts[lv];
        if (start[lv] == start[lv + 1]) continue;
        link.clear();
        degree.clear();
        parent.clear();
        auto local = [&](std::uint32_t x) {
            for (std::size_t i = 0; i < link.size(); ++i)
                if (link[i] == x) return i;
            link.push_back(x);
            degree.push_back(0);
            parent.push_back(std::uint32_t(link.size() - 1));
            return link.size() - 1;
        };
        auto root = [&](std::size_t x) {
            while (parent[x] != x) x = parent[x] = parent[parent[x]];
            return x;
        };
        bool bad = false;
        for (std::uint32_t k = start[lv]; k < start[lv + 1]; ++k) {
            const std::uint32_t* t = &c[3 * tris[k]];
            const int at = t[0] == vert ? 0 : t[1] == vert ? 1 : 2;
            const std::uint32_t b = t[(at + 1) % 3], d = t[(at + 2) % 3];
            if (b == vert || d == vert || b == d) {
                bad = true; // a collapsed triangle
                break;
            }
            const std::size_t lb = local(b), ld = local(d);
            ++degree[lb];
            ++degree[ld];
            parent[root(lb)] = std::uint32_t(root(ld));
        }
        std::size_t roots = 0;
        for (std::size_t i = 0; i < link.size() && !bad; ++i) {
            bad = degree[i] > 2;
            roots += root(i) == i;
        }
        if (bad || roots != 1) {
            ++v.topology;
            v.vertices.push_back(vert);
        }
    }
}

// Checks the candidate `trial.indices`, made from `from` (whose triangles are `from_set`, whose
// components `before` counts). Everything in `from` passed already, so only what changed is
// examined: new triangles for flips, degeneracy and intersections (against all triangles, near
// ones found through a grid), touched vertices for edges and fans.
Verdict check(const Mesh& trial, const Indices& changed, const Reference& ref, const Indices& from,
              const TriangleSet& from_set, const TriangleSet* previous, const Components& before) {
    Verdict v;
    const Indices& c = trial.indices;
    const Change ch = change_of(c, changed, from_set, trial.positions.size());
    // What a refused try of this step already passed is not examined again: a triangle's flip
    // and shape, and whether two triangles intersect, depend on their corners alone (no vertex
    // moves). `previous` holds the triangles of the refused try that touch nothing it flagged,
    // so only the others are examined (on the first try, the new ones: those of `from` passed
    // before); a triangle that failed is examined again if a retry makes it again.
    std::vector<std::uint8_t> examine = ch.is_new;
    if (previous)
        for (std::size_t t = 0; t < examine.size(); ++t)
            examine[t] = !previous->contains(triangle_key(&c[3 * t]));
    for (std::size_t t = 0; t < ch.is_new.size(); ++t) {
        if (!ch.is_new[t] || !examine[t]) continue;
        const std::uint32_t* i = &c[3 * t];
        const glm::vec3 a = trial.positions[i[0]], b = trial.positions[i[1]],
                        d = trial.positions[i[2]];
        const bool degenerate = triangle_shape(a, b, d).degenerate;
        // The input's normals around the corners: a new triangle facing against them is flipped.
        const glm::vec3 around = ref.normals[i[0]] + ref.normals[i[1]] + ref.normals[i[2]];
        const bool flipped = glm::dot(glm::cross(b - a, d - a), around) <= 0.0f;
        v.degenerate += degenerate;
        v.flips += flipped && !degenerate;
        if (degenerate || flipped) v.vertices.insert(v.vertices.end(), i, i + 3);
    }
    check_edges(c, ch, ref, v);
    if (ref.manifold) check_fans(c, ch, v);
    // Only pairs with a new triangle: the others were there before and passed (or, present in
    // the input, are not the decimation's doing).
    const SelfIntersections x =
        intersections_involving(trial, examine, std::numeric_limits<std::size_t>::max());
    for (const auto& [s, t] : x.pairs) {
        if (!ch.is_new[s] && !ch.is_new[t]) continue;
        ++v.intersections;
        for (const std::uint32_t u : {s, t})
            if (ch.is_new[u]) v.vertices.insert(v.vertices.end(), &c[3 * u], &c[3 * u] + 3);
    }
    // A component that would vanish is kept whole (specks went before the first step).
    Components after = before;
    count_components(c, after);
    std::vector<std::uint8_t> keep(before.triangles.size(), 0);
    for (std::size_t k = 0; k < before.triangles.size(); ++k)
        if (before.triangles[k] > 0 && after.triangles[k] == 0) {
            ++v.topology;
            keep[k] = 1;
        }
    for (const std::uint32_t i : from)
        if (keep[before.of_vertex[i]]) v.vertices.push_back(i);
    return v;
}

void check_indices(const Mesh& mesh) {
    if (mesh.indices.size() % 3 != 0)
        throw std::invalid_argument("decimate: index count is not a multiple of 3");
    if (first_index_out_of_range(mesh)) throw std::invalid_argument("decimate: index out of range");
}

// Patches: the triangles of a step grouped by the cell of a grid their centroid falls in, each
// simplified on its own with its rim locked. A refused collapse then sends back only its own
// patch for another try (one simplification of the whole mesh let every retry collapse
// differently everywhere, so new refusals kept coming until the retries ran out), and the patches
// of a try run in parallel, each writing its own result: the order of the patches, and so the
// result, does not depend on the thread count. The cells hold about kPatchTriangles triangles
// (their side from the mean triangle area) and move by half a side from one step to the next, so
// that a rim locked in one step lies inside a patch in the next.
constexpr double kPatchTriangles = 1024;

struct Patches {
    std::vector<std::uint32_t> of_triangle; // patch of each triangle
    std::size_t count = 0;
};

Patches make_patches(const std::vector<glm::vec3>& positions, const Indices& c, bool shifted) {
    Patches p;
    const std::size_t n = c.size() / 3;
    p.of_triangle.assign(n, 0);
    if (n == 0) return p;
    double area = 0.0;
    glm::dvec3 low(std::numeric_limits<double>::infinity());
    for (std::size_t t = 0; t < c.size(); t += 3) {
        const glm::dvec3 a = positions[c[t]], b = positions[c[t + 1]], d = positions[c[t + 2]];
        area += 0.5 * glm::length(glm::cross(b - a, d - a));
        low = glm::min(low, glm::min(a, glm::min(b, d)));
    }
    const double side = std::sqrt(kPatchTriangles * area / double(n));
    p.count = 1;
    if (!(side > 0.0) || !std::isfinite(side)) return p;
    const double offset = shifted ? 0.5 * side : 0.0;
    std::unordered_map<std::uint64_t, std::uint32_t> id_of;
    for (std::size_t t = 0; t < n; ++t) {
        const std::uint32_t* i = &c[3 * t];
        const glm::dvec3 centre = (glm::dvec3(positions[i[0]]) + glm::dvec3(positions[i[1]]) +
                                   glm::dvec3(positions[i[2]])) /
                                  3.0;
        const glm::dvec3 cell = glm::floor((centre - low + offset) / side);
        std::uint64_t key = 0;
        for (int k = 0; k < 3; ++k)
            key = (key << 21) | (std::uint64_t(std::clamp(cell[k], 0.0, 2097151.0)) & 0x1FFFFF);
        const auto [it, added] = id_of.try_emplace(key, std::uint32_t(id_of.size()));
        p.of_triangle[t] = it->second;
    }
    p.count = id_of.size();
    return p;
}

// One patch simplified: its triangles (mesh indices) towards `goal` triangles, with meshoptimizer
// on a copy of the patch's own vertices (so a call costs what the patch holds, not the mesh), its
// rim locked. `error_left` in mesh units; the error reached comes back in mesh units too.
struct PatchResult {
    Indices indices;
    float error = 0.0f;
};

PatchResult simplify_patch(const Indices& triangles, const std::vector<glm::vec3>& positions,
                           std::size_t goal, float error_left) {
    Indices vertices = triangles;
    std::sort(vertices.begin(), vertices.end());
    vertices.erase(std::unique(vertices.begin(), vertices.end()), vertices.end());
    std::vector<glm::vec3> local_positions(vertices.size());
    for (std::size_t v = 0; v < vertices.size(); ++v) local_positions[v] = positions[vertices[v]];
    Indices local(triangles.size());
    for (std::size_t k = 0; k < triangles.size(); ++k)
        local[k] = std::uint32_t(std::lower_bound(vertices.begin(), vertices.end(), triangles[k]) -
                                 vertices.begin());
    const float* xyz = &local_positions[0].x;
    const float scale = meshopt_simplifyScale(xyz, vertices.size(), sizeof(glm::vec3));
    const float relative = std::isfinite(error_left) && scale > 0.0f ? error_left / scale : 1e10f;
    Indices simplified(local.size());
    float relative_error = 0.0f;
    simplified.resize(meshopt_simplify(simplified.data(), local.data(), local.size(), xyz,
                                       vertices.size(), sizeof(glm::vec3), goal * 3, relative,
                                       unsigned(meshopt_SimplifyLockBorder), &relative_error));
    PatchResult result;
    result.indices.resize(simplified.size());
    for (std::size_t k = 0; k < simplified.size(); ++k) result.indices[k] = vertices[simplified[k]];
    result.error = relative_error * scale;
    return result;
}

// 1 for each vertex among `vertices`.
std::vector<std::uint8_t> flags_of(const std::vector<std::uint32_t>& vertices,
                                   std::size_t vertex_count) {
    std::vector<std::uint8_t> flagged(vertex_count, 0);
    for (const std::uint32_t v : vertices) flagged[v] = 1;
    return flagged;
}

// The triangles of `c` with no flagged corner.
TriangleSet triangles_clear_of(const Indices& c, const std::vector<std::uint8_t>& flagged) {
    TriangleSet set(c.size() / 3);
    for (std::size_t t = 0; t < c.size(); t += 3)
        if (!flagged[c[t]] && !flagged[c[t + 1]] && !flagged[c[t + 2]])
            set.insert(triangle_key(&c[t]));
    return set;
}

// The smallest patch that is split again; a smaller one still breaking a rule keeps its
// triangles as they are.
constexpr std::size_t kSmallestSplitPatch = 16;

// Where a try breaks a rule, the collapsed patches holding a `flagged` vertex are halved (at
// the median of their triangles' centres along their longest side) and simplified again, each
// half alone, so that what breaks is confined to ever smaller patches while the rest keeps its
// collapses; a patch too small to halve keeps its triangles. On a noisy scan the same few
// hundred thin places break every try, and freezing around each (the earlier way) took most of
// the mesh out of the last steps. Returns how many patches changed; `dirty` gets the halves.
std::size_t split_patches(const std::vector<std::uint8_t>& flagged, const Indices& current,
                          const std::vector<glm::vec3>& positions, Patches& patches,
                          std::vector<Indices>& patch_in, std::vector<PatchResult>& patch_out,
                          std::vector<std::uint8_t>& dirty) {
    const std::size_t count = patches.count;
    std::vector<std::uint8_t> split(count, 0);
    std::size_t changed = 0;
    for (std::size_t p = 0; p < count; ++p) {
        if (patch_out[p].indices.size() == patch_in[p].size()) continue; // nothing collapsed
        if (std::none_of(patch_in[p].begin(), patch_in[p].end(),
                         [&](std::uint32_t v) { return flagged[v] != 0; }))
            continue;
        ++changed;
        if (patch_in[p].size() / 3 > kSmallestSplitPatch)
            split[p] = 1;
        else
            patch_out[p] = PatchResult{patch_in[p], 0.0f};
    }
    // The triangles of each patch to split, by their index in `current`.
    std::vector<std::vector<std::uint32_t>> members(count);
    for (std::size_t t = 0; t < current.size(); t += 3)
        if (split[patches.of_triangle[t / 3]])
            members[patches.of_triangle[t / 3]].push_back(std::uint32_t(t / 3));
    for (std::size_t p = 0; p < count; ++p) {
        if (!split[p]) continue;
        std::vector<std::pair<glm::vec3, std::uint32_t>> centres;
        glm::vec3 low(std::numeric_limits<float>::infinity()), high(-low);
        for (const std::uint32_t t : members[p]) {
            const std::uint32_t* i = &current[3 * t];
            const glm::vec3 c = (positions[i[0]] + positions[i[1]] + positions[i[2]]) / 3.0f;
            centres.emplace_back(c, t);
            low = glm::min(low, c);
            high = glm::max(high, c);
        }
        const glm::vec3 side = high - low;
        const int axis = side.x >= side.y && side.x >= side.z ? 0 : side.y >= side.z ? 1 : 2;
        const auto middle = centres.begin() + std::ptrdiff_t(centres.size() / 2);
        // Ties broken by the triangle's index: the halves do not depend on the order found.
        std::nth_element(centres.begin(), middle, centres.end(), [&](const auto& a, const auto& b) {
            return a.first[axis] != b.first[axis] ? a.first[axis] < b.first[axis]
                                                  : a.second < b.second;
        });
        const auto half = std::uint32_t(patches.count++);
        for (auto it = middle; it != centres.end(); ++it) patches.of_triangle[it->second] = half;
        dirty[p] = 1;
    }
    patch_in.resize(patches.count);
    patch_out.resize(patches.count);
    dirty.resize(patches.count, 1);
    return changed;
}

Mesh compact(const Mesh& mesh, const Indices& indices) {
    std::vector<std::uint32_t> remap(mesh.positions.size(), 0);
    for (const std::uint32_t i : indices) remap[i] = 1;
    Mesh out;
    for (std::size_t i = 0; i < remap.size(); ++i) {
        if (!remap[i]) continue;
        remap[i] = std::uint32_t(out.positions.size());
        out.positions.push_back(mesh.positions[i]);
    }
    out.indices.reserve(indices.size());
    for (const std::uint32_t i : indices) out.indices.push_back(remap[i]);
    return out;
}

} // namespace

Decimated decimate(const Mesh& mesh, const DecimationOptions& options) {
    check_indices(mesh);
    DecimationReport report;
    report.original = mesh.triangle_count();
    report.requested = options.target_triangles;
    const std::size_t target = options.target_triangles;
    const bool error_only = target == 0;
    if ((!error_only && report.original <= target) || report.original == 0 ||
        !(options.max_error > 0.0f)) {
        report.achieved = report.original;
        return {mesh, report};
    }
    const Reference ref = make_reference(mesh);
    const std::size_t vertex_count = mesh.positions.size();
    // Specks: components of the input too small to keep a closed shape at the target's share of
    // their triangles (under a tetrahedron's 4); they may vanish unless every component is kept.
    const Components input_components = components(mesh.indices, vertex_count);
    const double share = error_only ? 1.0 : double(target) / double(report.original);
    std::vector<std::uint8_t> speck(input_components.triangles.size(), 0);
    if (!options.keep_every_component && !error_only)
        for (std::size_t k = 0; k < speck.size(); ++k)
            speck[k] = double(input_components.triangles[k]) * share < 4.0;

    const double step_share = std::clamp(options.step_share, 1e-3, 1.0);
    Mesh work;
    work.positions = mesh.positions;
    // Specks go first, whole: left to the collapses they fold into flat pillows that every
    // step's first try refuses.
    Indices current;
    current.reserve(mesh.indices.size());
    for (std::size_t t = 0; t < mesh.indices.size(); t += 3)
        if (!speck[input_components.of_vertex[mesh.indices[t]]])
            current.insert(current.end(), &mesh.indices[t], &mesh.indices[t] + 3);
    Indices patched, simplified;
    double step = step_share; // of the triangles one step removes; halved after a failed step
    int shrinks = 0;          // halvings since the last accepted step

    while (true) {
        const std::size_t n = current.size() / 3;
        if (!error_only && n <= target) break;
        const float error_left = options.max_error - report.error;
        if (!(error_left > 0.0f)) break;
        const Components before = components(current, vertex_count);
        const TriangleSet current_set = triangle_set(current);
        TriangleSet previous; // the candidate of the step's last refused try
        const auto removed = std::size_t(std::ceil(double(n) * step));
        std::size_t goal = removed >= n ? 0 : n - removed;
        if (!error_only) goal = std::max(goal, target);
        Patches patches = make_patches(mesh.positions, current, report.steps % 2 == 1);
        std::vector<Indices> patch_in(patches.count);
        std::vector<PatchResult> patch_out(patches.count);
        std::vector<std::uint8_t> dirty(patches.count, 1); // to be simplified (again)
        bool accepted = false;
        float retry_error = error_left; // the deviation a patch simplified (again) may reach
        for (int attempt = 0;; ++attempt) {
            for (Indices& part : patch_in) part.clear();
            for (std::size_t t = 0; t < current.size(); t += 3) {
                Indices& part = patch_in[patches.of_triangle[t / 3]];
                part.insert(part.end(), &current[t], &current[t] + 3);
            }
            // The patches' goals add up to the step's goal: each patch gets goal / n of its
            // triangles, rounded on the running sum (per-patch rounding up stopped a step a few
            // triangles short of a count, with nothing left to ask of any patch).
            std::vector<std::size_t> patch_goal(patches.count);
            std::uint64_t before_patch = 0;
            for (std::size_t p = 0; p < patches.count; ++p) {
                const std::uint64_t after_patch = before_patch + patch_in[p].size() / 3;
                patch_goal[p] = std::size_t(std::uint64_t(goal) * after_patch / n -
                                            std::uint64_t(goal) * before_patch / n);
                before_patch = after_patch;
            }
            for_each_chunk(patches.count, 1, [&](std::size_t, std::size_t p, std::size_t) {
                if (!dirty[p]) return;
                const std::size_t size = patch_in[p].size() / 3;
                patch_out[p] = patch_goal[p] < size ? simplify_patch(patch_in[p], mesh.positions,
                                                                     patch_goal[p], retry_error)
                                                    : PatchResult{patch_in[p], 0.0f};
            });
            patched.clear();
            simplified.clear();
            float step_error = 0.0f;
            for (std::size_t p = 0; p < patches.count; ++p) {
                patched.insert(patched.end(), patch_in[p].begin(), patch_in[p].end());
                simplified.insert(simplified.end(), patch_out[p].indices.begin(),
                                  patch_out[p].indices.end());
                step_error = std::max(step_error, patch_out[p].error);
            }
            if (simplified.size() >= patched.size()) break; // nothing more to collapse
            work.indices = simplified;
            const Verdict verdict = check(work, patched, ref, current, current_set,
                                          attempt > 0 ? &previous : nullptr, before);
            if (verdict.ok()) {
                current = work.indices;
                report.error += step_error;
                ++report.steps;
                accepted = true;
                break;
            }
            ++report.refusals;
            report.refused_topology += verdict.topology;
            report.refused_intersections += verdict.intersections;
            report.refused_flips += verdict.flips;
            report.refused_degenerate += verdict.degenerate;
            const std::vector<std::uint8_t> flagged = flags_of(verdict.vertices, vertex_count);
            previous = triangles_clear_of(work.indices, flagged);
            std::fill(dirty.begin(), dirty.end(), 0);
            if (split_patches(flagged, current, mesh.positions, patches, patch_in, patch_out,
                              dirty) == 0)
                break;
            // The halves may deviate no more than the patches that passed: squeezed between
            // locked rims towards the same share, they would spend the step's error where the
            // rest needed less (an icosphere under an error goal then kept 10 270 of 20 480
            // triangles instead of under half).
            float kept_error = 0.0f;
            for (std::size_t p = 0; p < patches.count; ++p)
                if (!dirty[p]) kept_error = std::max(kept_error, patch_out[p].error);
            if (kept_error > 0.0f) retry_error = std::min(error_left, kept_error);
        }
        if (accepted) {
            step = step_share;
            shrinks = 0;
            continue;
        }
        // Every patch had to keep its triangles: a smaller step from the same mesh asks fewer
        // collapses of each patch.
        step *= 0.5;
        if (double(n) * step < 1.0 || ++shrinks > options.max_shrinks) break;
    }
    Components after = input_components;
    count_components(current, after);
    for (std::size_t k = 0; k < after.triangles.size(); ++k)
        if (input_components.triangles[k] > 0 && after.triangles[k] == 0) {
            ++report.vanished_components;
            report.vanished_triangles += input_components.triangles[k];
        }
    Decimated result{compact(mesh, current), report};
    result.report.achieved = result.mesh.triangle_count();
    result.report.euler_change = topology(result.mesh).euler - ref.euler;
    if (!error_only && result.report.achieved > target) result.report.stalled = true;
    return result;
}

} // namespace snert
