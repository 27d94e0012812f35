// Mesh metrics: triangle shape, smoothness, topology, area/volume, accuracy, mesh distance.
//
// This work is based on:
//  - the paper's section 3: quality = smallest / largest angle, smoothness = mean |2 pi - sum of
//    incident angles|, accuracy = mean distance to the reference (eq. 7);
//  - Verdict's triangle radius ratio, here normalised to 2 r / R (1 for equilateral);
//  - the divergence theorem for the enclosed volume (sum of signed tetrahedra);
//  - closest point on a triangle by Voronoi regions (Ericson, Real-Time Collision Detection,
//    5.1.5), with the interior case taken as the distance to the plane;
//  - the two-pass chamfer distance transform (Rosenfeld and Pfaltz 1966), with unit weights the
//    exact chessboard distance, to skip empty shells of the search grid.
// Topology and smoothness share one structure: for every vertex, its corners (triangle slots)
// in one array, built by a counting sort. Each vertex then sorts its few neighbours locally,
// which is linear in the mesh size and needs no global edge map.
#include "metrics.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <thread>
#include <tuple>
#include <utility>

#if defined(__SSE2__)
#include <emmintrin.h>
#include <xmmintrin.h>
#endif

#include "cell_lists.h"
#include "huge_pages.h"
#include "parallel.h"
#include "serial_number.h"
#include "vector_angle.h"

namespace snert {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr std::uint32_t kNone = std::numeric_limits<std::uint32_t>::max();

void check_mesh(const Mesh& mesh) {
    if (mesh.indices.size() % 3 != 0)
        throw std::invalid_argument("mesh has " + std::to_string(mesh.indices.size()) +
                                    " indices, not a multiple of 3");
    if (!first_index_out_of_range(mesh)) return;
    const std::uint32_t largest = *std::max_element(mesh.indices.begin(), mesh.indices.end());
    throw std::invalid_argument("mesh index " + std::to_string(largest) + " out of range (" +
                                std::to_string(mesh.positions.size()) + " vertices)");
}

glm::dvec3 corner(const Mesh& mesh, std::size_t triangle, int k) {
    return glm::dvec3(mesh.positions[mesh.indices[3 * triangle + std::size_t(k)]]);
}

// ---------------------------------------------------------------------------------------------
// Per-vertex corner lists.

// Corner c = 3 * triangle + k, k in 0..2. The corners of vertex v are
// corners[offsets[v] .. offsets[v + 1]).
struct VertexCorners {
    std::vector<std::uint32_t> offsets;
    std::vector<std::uint32_t> corners;
};

VertexCorners vertex_corners(const Mesh& mesh) {
    if (mesh.indices.size() >= kNone)
        throw std::invalid_argument("mesh has too many triangles for 32-bit corner ids");
    const std::size_t vertices = mesh.positions.size();
    VertexCorners vc;
    // Counting sort with a one-slot shift: counts land in offsets[v + 2], the prefix sum turns
    // offsets[v + 1] into the start of v, and filling advances it to the end of v. On huge pages:
    // a clinical mesh's lists (12 MB) faulted 4 KiB at a time on this one thread, which took
    // most of the time of every smoothness, topology and border count.
    detail::resize_on_huge_pages(vc.offsets, vertices + 2, std::uint32_t(0));
    for (std::uint32_t v : mesh.indices) ++vc.offsets[v + 2];
    for (std::size_t v = 2; v < vc.offsets.size(); ++v) vc.offsets[v] += vc.offsets[v - 1];
    detail::resize_on_huge_pages(vc.corners, mesh.indices.size());
    for (std::size_t c = 0; c < mesh.indices.size(); ++c)
        vc.corners[vc.offsets[mesh.indices[c] + 1]++] = std::uint32_t(c);
    vc.offsets.pop_back();
    return vc;
}

// What the corners around one vertex say about the mesh there.
struct VertexFan {
    bool collapsed = false;  // a triangle at this vertex repeats a vertex index
    bool single_fan = false; // the triangles form one edge-connected fan (open or closed)
    bool closed = false;     // ... a closed one, every edge shared by exactly two triangles
    // Edges to neighbours with a larger index, so that each edge is counted at one end.
    std::size_t edges = 0, boundary_edges = 0, nonmanifold_edges = 0;
    bool oriented = true; // no edge to a larger neighbour is used twice in one direction
};

// Analyses vertex fans with reusable buffers (one analyser per chunk, no allocation per vertex).
class FanAnalyser {
  public:
    explicit FanAnalyser(const Mesh& mesh) : indices_(mesh.indices) {}

    VertexFan analyse(std::uint32_t v, const std::uint32_t* corners, std::size_t count) {
        VertexFan fan;
        if (count == 0) return fan;
        if (closed_cycle(v, corners, count, fan)) return fan;
        collect(v, corners, count, fan.collapsed);
        bool all_pairs = true, none_above_two = true;
        for (std::size_t begin = 0, end = 0; begin < entries_.size(); begin = end) {
            const std::uint32_t neighbour = entries_[begin].neighbour;
            std::size_t outgoing = 0;
            for (end = begin; end < entries_.size() && entries_[end].neighbour == neighbour;
                 ++end) {
                position_[entries_[end].slot] = std::uint32_t(end);
                outgoing += (entries_[end].slot & 1u) == 0 ? 1 : 0;
            }
            if (neighbour == v) continue; // self-loop of a collapsed triangle
            const std::size_t uses = end - begin;
            if (neighbour > v) {
                ++fan.edges;
                fan.boundary_edges += uses == 1 ? 1 : 0;
                fan.nonmanifold_edges += uses > 2 ? 1 : 0;
                if (outgoing > 1 || uses - outgoing > 1) fan.oriented = false;
            }
            all_pairs = all_pairs && uses == 2;
            none_above_two = none_above_two && uses <= 2;
            if (uses == 2) {
                partner_[begin] = std::uint32_t(begin + 1);
                partner_[begin + 1] = std::uint32_t(begin);
            }
        }
        if (fan.collapsed || !none_above_two) return fan;
        bool cycle = false;
        const std::size_t reached = walk(count, cycle);
        fan.single_fan = reached == count;
        fan.closed = fan.single_fan && cycle && all_pairs;
        return fan;
    }

    // Calls visit(n) for each neighbour n > v joined to v by a boundary edge: the edges that
    // analyse() counts as boundary_edges.
    template <class Visit>
    void for_each_boundary_neighbour(std::uint32_t v, const std::uint32_t* corners,
                                     std::size_t count, Visit&& visit) {
        bool collapsed = false;
        collect(v, corners, count, collapsed);
        for (std::size_t begin = 0, end = 0; begin < entries_.size(); begin = end) {
            const std::uint32_t neighbour = entries_[begin].neighbour;
            for (end = begin + 1; end < entries_.size() && entries_[end].neighbour == neighbour;
                 ++end) {
            }
            if (neighbour > v && end - begin == 1) visit(neighbour);
        }
    }

  private:
    // Nearly every vertex of a surface mesh, settled without sorting its edges: the corners chain
    // into one cycle, each corner's previous neighbour the next one's next, every neighbour once
    // in each role. Then analyse() finds a closed, oriented fan with no boundary or non-manifold
    // edge, which is what this fills in. False for anything else: analyse() decides those.
    static constexpr std::size_t kMaxCycle = 16;
    bool closed_cycle(std::uint32_t v, const std::uint32_t* corners, std::size_t count,
                      VertexFan& fan) const {
        if (count < 3 || count > kMaxCycle) return false;
        std::uint32_t next[kMaxCycle], previous[kMaxCycle];
        for (std::size_t j = 0; j < count; ++j) {
            const std::uint32_t c = corners[j], base = c - c % 3;
            next[j] = indices_[base + (c % 3 + 1) % 3];
            previous[j] = indices_[base + (c % 3 + 2) % 3];
            if (next[j] == v || previous[j] == v || next[j] == previous[j]) return false;
            for (std::size_t k = 0; k < j; ++k)
                if (previous[k] == previous[j]) return false;
        }
        // From corner 0, the corner whose next is this one's previous, until all are met once
        // and the last one's previous is corner 0's next. Then the nexts are the previouses in
        // another order: each neighbour is met by exactly two edges, one each way.
        std::uint32_t met = 1;
        std::size_t current = 0;
        for (std::size_t step = 1; step < count; ++step) {
            std::size_t k = 0;
            while (k < count && next[k] != previous[current]) ++k;
            if (k == count || (met >> k & 1u) != 0) return false;
            met |= 1u << k;
            current = k;
        }
        if (next[0] != previous[current]) return false;
        fan.single_fan = fan.closed = true;
        for (std::size_t j = 0; j < count; ++j) fan.edges += previous[j] > v ? 1 : 0;
        return true;
    }

    // Slot 2 j: outgoing edge v -> next of corner j; slot 2 j + 1: incoming edge previous -> v.
    struct Entry {
        std::uint32_t neighbour;
        std::uint32_t slot;
        bool operator<(const Entry& o) const {
            return neighbour != o.neighbour ? neighbour < o.neighbour : slot < o.slot;
        }
    };

    void collect(std::uint32_t v, const std::uint32_t* corners, std::size_t count,
                 bool& collapsed) {
        entries_.clear();
        for (std::size_t j = 0; j < count; ++j) {
            const std::uint32_t c = corners[j];
            const std::uint32_t base = c - c % 3;
            const std::uint32_t next = indices_[base + (c % 3 + 1) % 3];
            const std::uint32_t previous = indices_[base + (c % 3 + 2) % 3];
            if (next == v || previous == v || next == previous) collapsed = true;
            entries_.push_back({next, std::uint32_t(2 * j)});
            entries_.push_back({previous, std::uint32_t(2 * j + 1)});
        }
        std::sort(entries_.begin(), entries_.end());
        position_.resize(entries_.size());
        partner_.assign(entries_.size(), kNone);
    }

    // Walks from corner 0 across shared edges, first through its incoming edge, then (if the
    // fan is open) through its outgoing edge. With no edge used more than twice each corner has
    // at most two neighbours, so the walk covers exactly the fan of corner 0.
    std::size_t walk(std::size_t count, bool& cycle) const {
        std::size_t reached = 1;
        for (std::uint32_t first_side : {1u, 0u}) {
            std::uint32_t current = 0, leave = first_side;
            while (reached <= count) {
                const std::uint32_t other = partner_[position_[2 * current + leave]];
                if (other == kNone) break;
                const std::uint32_t slot = entries_[other].slot;
                if (slot / 2 == 0) {
                    cycle = true;
                    return reached;
                }
                ++reached;
                current = slot / 2;
                leave = 1 - slot % 2; // leave through the corner's other edge
            }
        }
        return reached;
    }

    const std::vector<std::uint32_t>& indices_;
    std::vector<Entry> entries_;
    std::vector<std::uint32_t> position_; // slot -> index in entries_
    std::vector<std::uint32_t> partner_;  // entry -> the other entry of its edge, or kNone
};

// Interior angle of triangle corner c (radians) with the vertices at `positions`, robust for
// needles (vector_angle.h).
double corner_angle(const Mesh& mesh, std::span<const glm::vec3> positions, std::uint32_t c) {
    const std::uint32_t base = c - c % 3;
    const glm::dvec3 p(positions[mesh.indices[c]]);
    const glm::dvec3 u = glm::dvec3(positions[mesh.indices[base + (c % 3 + 1) % 3]]) - p;
    const glm::dvec3 w = glm::dvec3(positions[mesh.indices[base + (c % 3 + 2) % 3]]) - p;
    return detail::vector_angle(glm::length(glm::cross(u, w)), glm::dot(u, w));
}

constexpr std::size_t kTriangleChunk = 1 << 15;
constexpr std::size_t kVertexChunk = 1 << 14;
constexpr std::size_t kPointChunk = 1 << 12;

} // namespace

// ---------------------------------------------------------------------------------------------
// Triangle quality.

TriangleShape triangle_shape(glm::vec3 a, glm::vec3 b, glm::vec3 c) {
    const glm::dvec3 p[3] = {glm::dvec3(a), glm::dvec3(b), glm::dvec3(c)};
    // Side k is opposite corner k.
    const glm::dvec3 side[3] = {p[2] - p[1], p[0] - p[2], p[1] - p[0]};
    const double length2[3] = {glm::dot(side[0], side[0]), glm::dot(side[1], side[1]),
                               glm::dot(side[2], side[2])};
    double twice_area = glm::length(glm::cross(side[2], -side[1]));
    if (!std::isfinite(twice_area)) twice_area = 0.0;

    TriangleShape shape;
    shape.area = float(0.5 * twice_area);
    const int shortest = int(std::min_element(length2, length2 + 3) - length2);
    const int longest = int(std::max_element(length2, length2 + 3) - length2);
    if (!(twice_area > kDegenerateHeightRatio * length2[longest])) {
        shape.degenerate = true;
        return shape;
    }
    // The smallest angle faces the shortest side, the largest the longest side.
    auto angle_at = [&](int k) {
        return detail::vector_angle(twice_area, -glm::dot(side[(k + 2) % 3], side[(k + 1) % 3]));
    };
    const double smallest = angle_at(shortest);
    const double largest = angle_at(longest);
    shape.quality = float(std::min(1.0, smallest / largest));
    shape.quality60 = float(std::min(1.0, smallest / (kPi / 3.0)));
    shape.min_angle = float(smallest * 180.0 / kPi);
    shape.max_angle = float(largest * 180.0 / kPi);
    // r = A / s and R = abc / (4 A), so 2 r / R = 8 A^2 / (s abc) = 2 (2A)^2 / (s abc).
    const double la = std::sqrt(length2[0]), lb = std::sqrt(length2[1]), lc = std::sqrt(length2[2]);
    const double semi_perimeter = 0.5 * (la + lb + lc);
    shape.radius_ratio =
        float(std::min(1.0, 2.0 * twice_area * twice_area / (semi_perimeter * la * lb * lc)));
    const double longest_length = std::sqrt(length2[longest]);
    shape.aspect_ratio = float(
        std::max(1.0, longest_length * 2.0 * semi_perimeter / (2.0 * std::sqrt(3.0) * twice_area)));
    return shape;
}

std::vector<float> triangle_quality(const Mesh& mesh) {
    check_mesh(mesh);
    std::vector<float> quality(mesh.triangle_count());
    for_each_chunk(quality.size(), kTriangleChunk, [&](std::size_t, std::size_t b, std::size_t e) {
        for (std::size_t t = b; t < e; ++t) {
            const std::uint32_t* i = &mesh.indices[3 * t];
            quality[t] =
                triangle_shape(mesh.positions[i[0]], mesh.positions[i[1]], mesh.positions[i[2]])
                    .quality;
        }
    });
    return quality;
}

bool is_distance(ShapeMeasure measure) {
    return measure == ShapeMeasure::DistanceIso || measure == ShapeMeasure::DistanceOther;
}

std::string_view measure_definition(ShapeMeasure measure) {
    switch (measure) {
    case ShapeMeasure::Quality:
        return "smallest angle / largest angle";
    case ShapeMeasure::Quality60:
        return "smallest angle / 60\xC2\xB0";
    case ShapeMeasure::RadiusRatio:
        return "2 r / R (inradius / circumradius)";
    case ShapeMeasure::DistanceIso:
        return "(I - iso) / |grad I| at the centroid, + outside";
    case ShapeMeasure::DistanceOther:
        break;
    }
    return "centroid to the other method's mesh";
}

MeasureScale measure_scale(ShapeMeasure measure) {
    switch (measure) {
    case ShapeMeasure::DistanceIso:
        return {-1.0f, 1.0f, true, "voxels"};
    case ShapeMeasure::DistanceOther:
        return {0.0f, 1.0f, false, "voxels"};
    default:
        return {};
    }
}

std::span<const float> TriangleMeasures::of(ShapeMeasure measure) const {
    switch (measure) {
    case ShapeMeasure::Quality:
        return quality;
    case ShapeMeasure::Quality60:
        return quality60;
    case ShapeMeasure::RadiusRatio:
        return radius_ratio;
    default:
        return {};
    }
}

TriangleMeasures triangle_measures(const Mesh& mesh) {
    check_mesh(mesh);
    TriangleMeasures m;
    const std::size_t n = mesh.triangle_count();
    // Each frame the app shows has its triangles measured: fresh buffers on huge pages.
    for (std::vector<float>* values :
         {&m.quality, &m.quality60, &m.radius_ratio, &m.min_angle, &m.max_angle})
        detail::resize_on_huge_pages(*values, n);
    for_each_chunk(n, kTriangleChunk, [&](std::size_t, std::size_t b, std::size_t e) {
        for (std::size_t t = b; t < e; ++t) {
            const std::uint32_t* i = &mesh.indices[3 * t];
            const TriangleShape s =
                triangle_shape(mesh.positions[i[0]], mesh.positions[i[1]], mesh.positions[i[2]]);
            m.quality[t] = s.quality;
            m.quality60[t] = s.quality60;
            m.radius_ratio[t] = s.radius_ratio;
            m.min_angle[t] = s.min_angle;
            m.max_angle[t] = s.max_angle;
        }
    });
    return m;
}

MeasureSummary summarize_measure(std::span<const float> values, const MeasureScale& scale) {
    MeasureSummary s;
    double sum = 0; // in triangle order: the same sum on every machine
    std::size_t counted = 0;
    const float bins_per_unit = float(kQualityBins) / (scale.high - scale.low);
    for (const float v : values) {
        if (std::isnan(v)) continue;
        sum += double(v);
        ++counted;
        // Clamped as a float first: an infinite value lands in an end bin too.
        const float position =
            std::clamp((v - scale.low) * bins_per_unit, 0.0f, float(kQualityBins - 1));
        ++s.histogram[std::size_t(position)];
    }
    if (counted > 0) s.mean = sum / double(counted);
    return s;
}

QualityStats quality_stats(const Mesh& mesh) {
    check_mesh(mesh);
    const std::size_t triangles = mesh.triangle_count();
    QualityStats stats;
    if (triangles == 0) return stats;

    struct Partial {
        double quality = 0, quality60 = 0, radius_ratio = 0;
        double min_quality = 1, min_angle = 180;
        std::size_t degenerate = 0, slivers = 0;
        std::array<std::size_t, kQualityBins> histogram{};
        std::size_t below_15 = 0, below_30 = 0, above_120 = 0;
        double radius_min = std::numeric_limits<double>::infinity(), radius_max = 0;
        double aspect_min = std::numeric_limits<double>::infinity(), aspect_max = 0;
    };
    std::vector<Partial> partials((triangles + kTriangleChunk - 1) / kTriangleChunk);
    for_each_chunk(triangles, kTriangleChunk, [&](std::size_t chunk, std::size_t b, std::size_t e) {
        Partial part; // stored once (see surface_distance)
        for (std::size_t t = b; t < e; ++t) {
            const std::uint32_t* i = &mesh.indices[3 * t];
            const TriangleShape s =
                triangle_shape(mesh.positions[i[0]], mesh.positions[i[1]], mesh.positions[i[2]]);
            part.quality += s.quality;
            part.quality60 += s.quality60;
            part.radius_ratio += s.radius_ratio;
            part.min_quality = std::min(part.min_quality, double(s.quality));
            part.min_angle = std::min(part.min_angle, double(s.min_angle));
            part.degenerate += s.degenerate ? 1 : 0;
            part.slivers += double(s.quality) < kSliverQuality ? 1 : 0;
            const int bin = std::min(kQualityBins - 1, int(s.quality * kQualityBins));
            ++part.histogram[std::size_t(std::max(0, bin))];
            part.below_15 += s.min_angle < kFeSmallAngle ? 1 : 0;
            part.below_30 += s.min_angle < kFeNarrowAngle ? 1 : 0;
            part.above_120 += s.max_angle > kFeObtuseAngle ? 1 : 0;
            part.radius_min = std::min(part.radius_min, double(s.radius_ratio));
            part.radius_max = std::max(part.radius_max, double(s.radius_ratio));
            part.aspect_min = std::min(part.aspect_min, double(s.aspect_ratio));
            part.aspect_max = std::max(part.aspect_max, double(s.aspect_ratio));
        }
        partials[chunk] = part;
    });

    Partial total;
    for (const Partial& part : partials) {
        total.quality += part.quality;
        total.quality60 += part.quality60;
        total.radius_ratio += part.radius_ratio;
        total.min_quality = std::min(total.min_quality, part.min_quality);
        total.min_angle = std::min(total.min_angle, part.min_angle);
        total.degenerate += part.degenerate;
        total.slivers += part.slivers;
        for (int i = 0; i < kQualityBins; ++i) total.histogram[i] += part.histogram[i];
        // Counts and extremes: exact in any order.
        total.below_15 += part.below_15;
        total.below_30 += part.below_30;
        total.above_120 += part.above_120;
        total.radius_min = std::min(total.radius_min, part.radius_min);
        total.radius_max = std::max(total.radius_max, part.radius_max);
        total.aspect_min = std::min(total.aspect_min, part.aspect_min);
        total.aspect_max = std::max(total.aspect_max, part.aspect_max);
    }
    const double n = double(triangles);
    stats.mean = total.quality / n;
    stats.min = total.min_quality;
    stats.quality60_mean = total.quality60 / n;
    stats.radius_ratio_mean = total.radius_ratio / n;
    stats.min_angle_min = total.min_angle;
    stats.degenerate = total.degenerate;
    stats.slivers = total.slivers;
    stats.triangles = triangles;
    stats.min_angle_below_15 = total.below_15;
    stats.min_angle_below_30 = total.below_30;
    stats.max_angle_above_120 = total.above_120;
    stats.radius_ratio_min = total.radius_min;
    stats.radius_ratio_max = total.radius_max;
    stats.aspect_ratio_min = total.aspect_min;
    stats.aspect_ratio_max = total.aspect_max;
    stats.histogram = total.histogram;
    return stats;
}

// ---------------------------------------------------------------------------------------------
// Smoothness and topology.

namespace {

// What one analysis of every vertex's fan gives: the topology's counts, the boundary edges off
// the border (with `border`) and the angle deficits (with angle positions). smoothness(),
// topology() and boundary_edges_off_border() each take their part; fan_measures() takes all
// three from one list of each vertex's corners (made on one thread, a sixth of a clinical mesh's
// smoothness) and one analysis of each fan.
struct FanTotals {
    std::size_t referenced = 0, edges = 0, boundary = 0, nonmanifold = 0;
    std::size_t nonmanifold_vertices = 0;
    bool oriented = true;
    std::size_t off_border = 0;
    double deviation = 0; // sum of |2 pi - angle sum| over the interior vertices
    std::size_t interior = 0;
};

struct Border {
    glm::ivec3 dims;
    float margin;
};

FanTotals fan_totals(const Mesh& mesh, const VertexCorners& vc, const Border* border,
                     std::span<const glm::vec3> angle_positions) {
    const std::size_t vertices = mesh.positions.size();
    const glm::vec3 top = border ? glm::vec3(border->dims - 1) - border->margin : glm::vec3(0.0f);
    auto near_border = [&](std::uint32_t v) {
        const glm::vec3 p = mesh.positions[v];
        return glm::any(glm::lessThanEqual(p, glm::vec3(border->margin))) ||
               glm::any(glm::greaterThanEqual(p, top));
    };
    std::vector<FanTotals> partials((vertices + kVertexChunk - 1) / kVertexChunk);
    for_each_chunk(vertices, kVertexChunk, [&](std::size_t chunk, std::size_t b, std::size_t e) {
        FanAnalyser analyser(mesh);
        FanTotals part; // stored once (see surface_distance)
        for (std::size_t v = b; v < e; ++v) {
            const auto u = std::uint32_t(v);
            const std::uint32_t* corners = vc.corners.data() + vc.offsets[v];
            const std::size_t count = vc.offsets[v + 1] - vc.offsets[v];
            if (count == 0) continue;
            const VertexFan fan = analyser.analyse(u, corners, count);
            ++part.referenced;
            part.edges += fan.edges;
            part.boundary += fan.boundary_edges;
            part.nonmanifold += fan.nonmanifold_edges;
            part.oriented = part.oriented && fan.oriented;
            part.nonmanifold_vertices += fan.single_fan ? 0 : 1;
            // Each boundary edge once, from its smaller end (the edges the fan counted).
            if (border && fan.boundary_edges > 0)
                analyser.for_each_boundary_neighbour(u, corners, count, [&](std::uint32_t n) {
                    part.off_border += !near_border(u) || !near_border(n) ? 1 : 0;
                });
            if (angle_positions.empty() || !fan.closed) continue;
            double angle_sum = 0;
            for (std::size_t j = 0; j < count; ++j)
                angle_sum += corner_angle(mesh, angle_positions, corners[j]);
            part.deviation += std::abs(2.0 * kPi - angle_sum);
            ++part.interior;
        }
        partials[chunk] = part;
    });
    FanTotals total;
    for (const FanTotals& part : partials) {
        total.referenced += part.referenced;
        total.edges += part.edges;
        total.boundary += part.boundary;
        total.nonmanifold += part.nonmanifold;
        total.oriented = total.oriented && part.oriented;
        total.nonmanifold_vertices += part.nonmanifold_vertices;
        total.off_border += part.off_border;
        total.deviation += part.deviation;
        total.interior += part.interior;
    }
    return total;
}

double mean_deviation(const FanTotals& total) {
    return total.interior == 0 ? 0.0 : total.deviation / double(total.interior);
}

Topology topology_of(const Mesh& mesh, const FanTotals& total) {
    Topology topo;
    const std::size_t triangles = mesh.triangle_count();
    for (std::size_t t = 0; t < triangles; ++t) {
        const std::uint32_t* i = &mesh.indices[3 * t];
        if (i[0] == i[1] || i[1] == i[2] || i[0] == i[2]) ++topo.collapsed_triangles;
    }
    topo.boundary_edges = total.boundary;
    topo.nonmanifold_edges = total.nonmanifold;
    topo.nonmanifold_vertices = total.nonmanifold_vertices;
    topo.euler = long(total.referenced) - long(total.edges) + long(triangles);
    const bool any = triangles > 0;
    topo.watertight =
        any && total.boundary == 0 && total.nonmanifold == 0 && topo.collapsed_triangles == 0;
    // A fan through a non-manifold edge or a collapsed triangle is not a single fan, so the
    // vertex count covers those cases too; the edge count is checked for clarity.
    topo.manifold = any && total.nonmanifold == 0 && total.nonmanifold_vertices == 0 &&
                    topo.collapsed_triangles == 0;
    topo.oriented = any && total.oriented;
    return topo;
}

} // namespace

double smoothness(const Mesh& mesh) {
    check_mesh(mesh);
    return mean_deviation(fan_totals(mesh, vertex_corners(mesh), nullptr, mesh.positions));
}

Topology topology(const Mesh& mesh) {
    check_mesh(mesh);
    return topology_of(mesh, fan_totals(mesh, vertex_corners(mesh), nullptr, {}));
}

std::size_t boundary_edges_off_border(const Mesh& index_mesh, glm::ivec3 dims, float margin) {
    check_mesh(index_mesh);
    // Each vertex's boundary edges to larger neighbours (so each edge once), from its fan, in
    // parallel: one sort of all edges on one thread took longer than the rest of the topology.
    const Border border{dims, margin};
    return fan_totals(index_mesh, vertex_corners(index_mesh), &border, {}).off_border;
}

FanMeasures fan_measures(const Mesh& index_mesh, glm::ivec3 dims,
                         std::span<const glm::vec3> world_positions) {
    check_mesh(index_mesh);
    if (world_positions.size() != index_mesh.positions.size())
        throw std::invalid_argument("fan measures: " + std::to_string(world_positions.size()) +
                                    " world points for " +
                                    std::to_string(index_mesh.positions.size()) + " vertices");
    const Border border{dims, 1.0f};
    const FanTotals total =
        fan_totals(index_mesh, vertex_corners(index_mesh), &border, world_positions);
    return {topology_of(index_mesh, total), total.off_border, mean_deviation(total)};
}

// ---------------------------------------------------------------------------------------------
// Area and volume.

double surface_area(const Mesh& mesh) {
    check_mesh(mesh);
    double twice_area = 0;
    for (std::size_t t = 0; t < mesh.triangle_count(); ++t) {
        const glm::dvec3 a = corner(mesh, t, 0);
        twice_area += glm::length(glm::cross(corner(mesh, t, 1) - a, corner(mesh, t, 2) - a));
    }
    return 0.5 * twice_area;
}

double enclosed_volume(const Mesh& mesh) {
    check_mesh(mesh);
    if (mesh.indices.empty()) return 0.0;
    const Bounds bounds = mesh_bounds(mesh);
    const glm::dvec3 centre = 0.5 * (glm::dvec3(bounds.min) + glm::dvec3(bounds.max));
    // Each triangle with the centre spans a tetrahedron of signed volume a . (b x c) / 6.
    double six_volume = 0;
    for (std::size_t t = 0; t < mesh.triangle_count(); ++t) {
        const glm::dvec3 a = corner(mesh, t, 0) - centre;
        const glm::dvec3 b = corner(mesh, t, 1) - centre;
        const glm::dvec3 c = corner(mesh, t, 2) - centre;
        six_volume += glm::dot(a, glm::cross(b, c));
    }
    return six_volume / 6.0;
}

// ---------------------------------------------------------------------------------------------
// Accuracy.

namespace {

// Sums of weight * |d|, of weights, and the largest |d|, per chunk.
struct Partial {
    double sum = 0, weight = 0, max = 0;
};

Partial combine(const std::vector<Partial>& partials) {
    Partial total;
    for (const Partial& part : partials) {
        total.sum += part.sum;
        total.weight += part.weight;
        total.max = std::max(total.max, part.max);
    }
    return total;
}

std::span<const glm::vec3> checked_area_positions(const Mesh& mesh,
                                                  std::span<const glm::vec3> area_positions) {
    if (area_positions.empty()) return mesh.positions;
    if (area_positions.size() != mesh.positions.size())
        throw std::invalid_argument("accuracy: " + std::to_string(area_positions.size()) +
                                    " area points for " + std::to_string(mesh.positions.size()) +
                                    " vertices");
    return area_positions;
}

} // namespace

SurfaceDistance surface_distance(const Mesh& mesh, const DistanceFunction& distance,
                                 std::span<const glm::vec3> area_positions, int split) {
    check_mesh(mesh);
    if (split < 1) throw std::invalid_argument("surface distance: split must be at least 1");
    const std::span<const glm::vec3> areas = checked_area_positions(mesh, area_positions);
    auto area_corner = [&](std::size_t t, int k) {
        return glm::dvec3(areas[mesh.indices[3 * t + std::size_t(k)]]);
    };
    // The sub-triangle centroids of a k-fold split, in barycentric coordinates
    // ((i + 1/3) / k, (j + 1/3) / k) for the upright sub-triangles and ((i + 2/3) / k,
    // (j + 2/3) / k) for the inverted ones; each stands for 1 / k^2 of the area.
    const int k = split;
    std::vector<glm::dvec2> samples;
    samples.reserve(std::size_t(k) * std::size_t(k));
    for (int i = 0; i < k; ++i)
        for (int j = 0; i + j < k; ++j) {
            samples.push_back(glm::dvec2(i + 1.0 / 3.0, j + 1.0 / 3.0) / double(k));
            if (i + j < k - 1)
                samples.push_back(glm::dvec2(i + 2.0 / 3.0, j + 2.0 / 3.0) / double(k));
        }
    const std::size_t triangles = mesh.triangle_count();
    std::vector<Partial> partials((triangles + kPointChunk - 1) / kPointChunk);
    for_each_chunk(triangles, kPointChunk, [&](std::size_t chunk, std::size_t b, std::size_t e) {
        Partial part; // stored once: `distance` is opaque, so a field of partials[chunk] would be
                      // written after every call, on a cache line that other threads write
        for (std::size_t t = b; t < e; ++t) {
            const glm::dvec3 a = corner(mesh, t, 0), ab = corner(mesh, t, 1) - a,
                             ac = corner(mesh, t, 2) - a;
            const glm::dvec3 w = area_corner(t, 0);
            const double area =
                0.5 * glm::length(glm::cross(area_corner(t, 1) - w, area_corner(t, 2) - w));
            if (!(area > 0) || !std::isfinite(area)) continue; // no surface to measure
            double sum = 0;
            for (const glm::dvec2& s : samples) {
                const double d = std::abs(double(distance(glm::vec3(a + s.x * ab + s.y * ac))));
                sum += d;
                part.max = std::max(part.max, d);
            }
            part.sum += area * sum / double(samples.size());
            part.weight += area;
        }
        partials[chunk] = part;
    });
    const Partial surface = combine(partials);
    SurfaceDistance result;
    result.mean = surface.weight > 0 ? surface.sum / surface.weight : 0.0;
    result.max = surface.weight > 0 ? surface.max : 0.0;
    return result;
}

Accuracy point_accuracy(const Mesh& mesh, const DistanceFunction& distance) {
    check_mesh(mesh);
    auto measure = [&](std::size_t count, auto point_of) {
        std::vector<Partial> partials((count + kPointChunk - 1) / kPointChunk);
        for_each_chunk(count, kPointChunk, [&](std::size_t chunk, std::size_t b, std::size_t e) {
            Partial part; // stored once, as in surface_distance
            for (std::size_t i = b; i < e; ++i) {
                const double d = std::abs(double(distance(point_of(i))));
                part.sum += d;
                part.max = std::max(part.max, d);
            }
            partials[chunk] = part;
        });
        const Partial total = combine(partials);
        return std::pair(count == 0 ? 0.0 : total.sum / double(count), total.max);
    };
    Accuracy result;
    std::tie(result.vertices_mean, result.vertices_max) =
        measure(mesh.positions.size(), [&](std::size_t v) { return mesh.positions[v]; });
    std::tie(result.faces_mean, result.faces_max) =
        measure(mesh.triangle_count(), [&](std::size_t t) {
            const std::uint32_t* i = &mesh.indices[3 * t];
            return (mesh.positions[i[0]] + mesh.positions[i[1]] + mesh.positions[i[2]]) / 3.0f;
        });
    return result;
}

Accuracy accuracy(const Mesh& mesh, const DistanceFunction& distance,
                  std::span<const glm::vec3> area_positions) {
    checked_area_positions(mesh, area_positions); // before any distance is asked for
    Accuracy result = point_accuracy(mesh, distance);
    const SurfaceDistance surface =
        surface_distance(mesh, distance, area_positions, kSurfaceSampleSplit);
    result.surface_mean = surface.mean;
    result.surface_max = surface.max;
    return result;
}

// ---------------------------------------------------------------------------------------------
// Mesh distance.

struct MeshDistance::Impl {
    struct Candidate {
        double squared_distance; // from the query point to the cell's box
        std::size_t cell;
    };
    // A sphere holding a triangle: most candidates are ruled out by it alone, from 16 bytes. The
    // triangle's flatness rides along in the radius's sign bit (negative: flat).
    struct Sphere {
        glm::vec3 centre;
        float signed_radius;
        float radius() const { return std::abs(signed_radius); }
        bool flat() const { return std::signbit(signed_radius); }
    };
    // The reference (moved in, or borrowed with the map to its measuring space) and each
    // triangle's bounding sphere: 16 bytes a triangle beside the mesh, where a copy of each
    // triangle's corners, normal and sphere took 64 (on a clinical Marching Cubes mesh of 3.5 M
    // triangles, 170 MB less). The normal is worked out only for the few triangles that pass
    // their sphere's test.
    Mesh owned;
    std::span<const glm::vec3> positions;
    std::span<const std::uint32_t> indices;
    std::optional<WorldToIndex> to_space;
    std::vector<Sphere> spheres;
    glm::dvec3 origin{0.0};
    double cell = 1.0, inverse_cell = 1.0;
    glm::ivec3 dims{1};
    double coordinate_size = 0;       // the largest |coordinate| of the triangles' bounding box
    detail::CellLists cell_triangles; // the triangles of each cell
    // Chessboard distance to an occupied block, at most 255 (a lower bound either way), over
    // blocks of 2^shell_shift cells a side, at most kMaxShellBlocks: a byte a cell would add 8 MB
    // at a clinical comparison's peak of memory, which is this distance's. empty_cells() turns it
    // into cells.
    std::vector<std::uint8_t> empty_shells;
    int shell_shift = 0;
    glm::ivec3 shell_dims{1};

    // This grid's own number (no other grid of the process has it), for the per-thread caches
    // of distance(): unlike an address, it is never reused by a later grid.
    std::uint64_t serial = 0;

    static constexpr std::size_t kMaxCells = std::size_t(1) << 23;
    static constexpr std::size_t kMaxShellBlocks = std::size_t(1) << 18;

    explicit Impl(Mesh&& reference);
    Impl(const Mesh& reference, const WorldToIndex& map);
    float distance(glm::vec3 point) const;

  private:
    struct Corners {
        glm::dvec3 a, b, c;
    };
    glm::dvec3 point(std::uint32_t i) const {
        return glm::dvec3(to_space ? (*to_space)(positions[i]) : positions[i]);
    }
    Corners corners(std::size_t t) const {
        const std::uint32_t* i = &indices[3 * t];
        return {point(i[0]), point(i[1]), point(i[2])};
    }
    std::size_t triangle_count() const { return indices.size() / 3; }
    std::size_t cell_index(int x, int y, int z) const {
        return (std::size_t(z) * std::size_t(dims.y) + std::size_t(y)) * std::size_t(dims.x) +
               std::size_t(x);
    }
    glm::ivec3 cell_of(glm::dvec3 p) const {
        // Clamped, then truncated: the floor for the non-negative values left, without
        // glm::floor's dozen instructions a coordinate on the baseline x86-64 target.
        const glm::dvec3 top = glm::dvec3(dims - 1);
        return glm::ivec3(glm::clamp((p - origin) * inverse_cell, glm::dvec3(0.0), top));
    }
    // A triangle's normal n = ab x ac (in double, from the float corners) and whether it is
    // flat (the flatness test of triangle_shape()): a flat one has no reliable plane and is
    // measured as its three edges.
    struct Plane {
        glm::dvec3 n;
        double n2;
        bool flat;
    };
    static bool is_flat(const Corners& t);
    static Plane plane_of(const Corners& t, bool flat) {
        const glm::dvec3 n = glm::cross(t.b - t.a, t.c - t.a);
        return {n, glm::dot(n, n), flat};
    }
    static glm::dvec3 smallest_sphere_centre(const Corners& t);
    static Sphere bounding_sphere(const Corners& t);
    // Whether `sphere` comes nearer to p than `bound` (else no point of its triangle does).
    static bool sphere_within(glm::dvec3 p, const Sphere& sphere, double bound) {
        const glm::dvec3 to_centre = p - glm::dvec3(sphere.centre);
        const double reach = bound + double(sphere.radius());
        return glm::dot(to_centre, to_centre) < reach * reach;
    }
    std::span<const std::uint32_t> spheres_in_reach(std::span<const std::uint32_t> items,
                                                    glm::dvec3 p, double bound,
                                                    std::vector<std::uint32_t>& kept) const;
    // A triangle as the exact test reads it: its corners in the measuring space and its plane.
    struct Measured {
        Corners corners;
        Plane plane;
    };
    const Measured& measured(std::uint32_t triangle) const;
    static bool beyond_plane(glm::dvec3 p, const Corners& t, const Plane& plane, double reach,
                             double bound);
    void build();
    void choose_grid();
    void fill_cells();
    void compute_empty_shells();
    std::size_t block_index(int x, int y, int z) const {
        return (std::size_t(z) * std::size_t(shell_dims.y) + std::size_t(y)) *
                   std::size_t(shell_dims.x) +
               std::size_t(x);
    }
    // A lower bound of the chessboard distance (cells) from cell (x, y, z) to an occupied cell:
    // D blocks apart along an axis are at least scale * D - (scale - 1) cells apart.
    int empty_cells(int x, int y, int z) const {
        const int blocks =
            empty_shells[block_index(x >> shell_shift, y >> shell_shift, z >> shell_shift)];
        const int scale = 1 << shell_shift;
        return blocks == 0 ? 0 : blocks * scale - (scale - 1);
    }
    template <class Visit> void for_each_occupied_cell(glm::ivec3 home, int r, Visit&& visit) const;
    double squared_distance_to_cell(glm::dvec3 p, glm::ivec3 c) const;
    static double squared_distance_to_segment(glm::dvec3 p, glm::dvec3 a, glm::dvec3 b);
    static double squared_distance_to_triangle(glm::dvec3 p, const Corners& t, const Plane& plane);
};

bool MeshDistance::Impl::is_flat(const Corners& t) {
    const double twice_area = glm::length(glm::cross(t.b - t.a, t.c - t.a));
    double longest2 = 0;
    for (const glm::dvec3 edge : {t.b - t.a, t.c - t.b, t.a - t.c})
        longest2 = std::max(longest2, glm::dot(edge, edge));
    return !(twice_area > kDegenerateHeightRatio * longest2);
}

// The centre of the smallest sphere holding the triangle: the midpoint of the longest side when
// the angle facing it is not acute, else the circumcentre. The centroid's sphere is larger around
// an obtuse triangle, and Marching Cubes makes many: on a clinical CT a query passed 5.3 spheres
// instead of 6.5. The radius is measured from the centre taken, so a rounded circumcentre only
// loosens the sphere.
glm::dvec3 MeshDistance::Impl::smallest_sphere_centre(const Corners& t) {
    const glm::dvec3 ab = t.b - t.a, ac = t.c - t.a, bc = t.c - t.b;
    if (glm::dot(ab, ac) <= 0) return 0.5 * (t.b + t.c); // the angle at a
    if (glm::dot(ab, bc) >= 0) return 0.5 * (t.a + t.c); // at b
    if (glm::dot(ac, bc) <= 0) return 0.5 * (t.a + t.b); // at c
    const glm::dvec3 n = glm::cross(ab, ac);
    const glm::dvec3 centre =
        t.a + (glm::dot(ac, ac) * glm::cross(n, ab) + glm::dot(ab, ab) * glm::cross(ac, n)) /
                  (2.0 * glm::dot(n, n));
    if (std::isfinite(centre.x + centre.y + centre.z)) return centre;
    return (t.a + t.b + t.c) / 3.0;
}

MeshDistance::Impl::Sphere MeshDistance::Impl::bounding_sphere(const Corners& t) {
    const glm::dvec3 centre = smallest_sphere_centre(t);
    double farthest2 = 0;
    for (const glm::dvec3 p : {t.a, t.b, t.c})
        farthest2 = std::max(farthest2, glm::dot(p - centre, p - centre));
    // Rounded up so that the float sphere surely holds the corners.
    const float radius = float(std::sqrt(farthest2) * (1.0 + 1e-6) + 1e-6 * glm::length(centre));
    return {glm::vec3(centre), is_flat(t) ? -radius : radius};
}

// Whether the triangle's plane alone keeps it farther from p than `bound` (no point of a triangle
// is nearer than its plane), with a margin of 1e-6 of `reach` (at least |p - a|) for rounding.
// Without a square root or a division: |h| / |n| >= bound + margin, squared.
bool MeshDistance::Impl::beyond_plane(glm::dvec3 p, const Corners& t, const Plane& plane,
                                      double reach, double bound) {
    if (plane.flat) return false;
    const double h = glm::dot(p - t.a, plane.n);
    const double needed = bound + 1e-6 * reach;
    return h * h >= needed * needed * plane.n2;
}

MeshDistance::Impl::Impl(Mesh&& reference)
    : owned(std::move(reference)), positions(owned.positions), indices(owned.indices) {
    check_mesh(owned);
    build();
}

MeshDistance::Impl::Impl(const Mesh& reference, const WorldToIndex& map)
    : positions(reference.positions), indices(reference.indices), to_space(map) {
    check_mesh(reference);
    build();
}

void MeshDistance::Impl::build() {
    serial = next_serial_number();
    if (triangle_count() == 0)
        throw std::invalid_argument("mesh distance: the reference mesh has no triangles");
    if (triangle_count() >= kNone)
        throw std::invalid_argument("mesh distance: too many reference triangles");
    // While the grid is built, the reference's points mapped once: its passes read each corner of
    // each triangle five times, and a point is a corner of about six triangles. The same floats
    // as the map gives; afterwards the queries map the few corners they read.
    const std::span<const glm::vec3> given = positions;
    std::vector<glm::vec3> mapped;
    if (to_space) {
        detail::resize_on_huge_pages(mapped, given.size());
        for_each_chunk(given.size(), kVertexChunk, [&](std::size_t, std::size_t b, std::size_t e) {
            for (std::size_t i = b; i < e; ++i) mapped[i] = (*to_space)(given[i]);
        });
        positions = mapped;
    }
    const std::optional<WorldToIndex> map = std::exchange(to_space, std::nullopt);
    detail::resize_on_huge_pages(spheres, triangle_count());
    for_each_chunk(spheres.size(), kTriangleChunk,
                   [&](std::size_t, std::size_t first, std::size_t last) {
                       for (std::size_t t = first; t < last; ++t)
                           spheres[t] = bounding_sphere(corners(t));
                   });
    choose_grid();
    fill_cells();
    compute_empty_shells();
    positions = given;
    to_space = map;
}

// Cells of about the mean edge length hold a few triangles each; the cell count is capped so the
// grid stays small for long thin or widely spread meshes.
void MeshDistance::Impl::choose_grid() {
    // The bounds and the sum of edges, per chunk of triangles and then over the chunks in order
    // (the same sums whatever the thread count).
    struct Extent {
        glm::dvec3 lo{std::numeric_limits<double>::max()},
            hi{std::numeric_limits<double>::lowest()};
        double edge_sum = 0;
    };
    const std::size_t triangles = triangle_count();
    std::vector<Extent> extents(chunk_count(triangles, kTriangleChunk));
    for_each_chunk(
        triangles, kTriangleChunk, [&](std::size_t chunk, std::size_t first, std::size_t last) {
            Extent x; // kept here, stored once: the chunks' extents share cache lines
            for (std::size_t i = first; i < last; ++i) {
                const Corners t = corners(i);
                for (const glm::dvec3 p : {t.a, t.b, t.c}) {
                    x.lo = glm::min(x.lo, p);
                    x.hi = glm::max(x.hi, p);
                }
                // In float, as the corners are stored.
                const glm::vec3 a(t.a), b(t.b), c(t.c);
                x.edge_sum += glm::distance(a, b) + glm::distance(b, c) + glm::distance(c, a);
            }
            extents[chunk] = x;
        });
    glm::dvec3 lo(std::numeric_limits<double>::max()), hi(std::numeric_limits<double>::lowest());
    double edge_sum = 0;
    for (const Extent& x : extents) {
        lo = glm::min(lo, x.lo);
        hi = glm::max(hi, x.hi);
        edge_sum += x.edge_sum;
    }
    if (!std::isfinite(lo.x + lo.y + lo.z + hi.x + hi.y + hi.z))
        throw std::invalid_argument("mesh distance: the reference mesh has non-finite vertices");
    const glm::dvec3 extent = hi - lo;
    const double largest = std::max({extent.x, extent.y, extent.z});
    cell = edge_sum / (3.0 * double(triangles));
    if (!(cell > largest * 1e-6)) cell = largest > 0 ? largest * 1e-3 : 1.0;
    auto cells_along = [&](double e) { return std::max(1.0, std::ceil(e / cell)); };
    for (;;) {
        const double cells = cells_along(extent.x) * cells_along(extent.y) * cells_along(extent.z);
        if (cells <= double(kMaxCells)) break;
        cell *= 1.1;
    }
    dims = glm::ivec3(int(cells_along(extent.x)), int(cells_along(extent.y)),
                      int(cells_along(extent.z)));
    origin = lo;
    inverse_cell = 1.0 / cell;
    shell_shift = 0;
    const auto blocks_along = [&](int n) { return ((n - 1) >> shell_shift) + 1; };
    while (std::size_t(blocks_along(dims.x)) * std::size_t(blocks_along(dims.y)) *
               std::size_t(blocks_along(dims.z)) >
           kMaxShellBlocks)
        ++shell_shift;
    shell_dims = glm::ivec3(blocks_along(dims.x), blocks_along(dims.y), blocks_along(dims.z));
    const glm::dvec3 size = glm::max(glm::abs(lo), glm::abs(hi));
    coordinate_size = std::max({size.x, size.y, size.z});
}

// Lists each triangle in every cell its bounding box overlaps.
void MeshDistance::Impl::fill_cells() {
    const std::size_t cells = std::size_t(dims.x) * std::size_t(dims.y) * std::size_t(dims.z);
    cell_triangles.build(
        cells, triangle_count(),
        [&](std::size_t first, std::size_t last, auto&& visit) {
            for (std::size_t t = first; t < last; ++t) {
                const auto [a, b, c] = corners(t);
                const glm::ivec3 lo = cell_of(glm::min(a, glm::min(b, c)));
                const glm::ivec3 hi = cell_of(glm::max(a, glm::max(b, c)));
                for (int z = lo.z; z <= hi.z; ++z)
                    for (int y = lo.y; y <= hi.y; ++y)
                        for (int x = lo.x; x <= hi.x; ++x)
                            visit(std::uint32_t(t), cell_index(x, y, z));
            }
        },
        "mesh distance");
}

// Over the blocks, two raster passes, each taking the minimum over the 13 already visited
// neighbours plus one: with unit weights this is the exact chessboard distance to the nearest
// occupied block. Of a block's 13 neighbours 12 lie in rows finished before its own (the row before
// it in its slice and three rows of the slice before): their minimum is taken for a whole row at
// once, in loops the compiler vectorises; the last, the block before it in its row, in a scan.
void MeshDistance::Impl::compute_empty_shells() {
    const std::size_t blocks =
        std::size_t(shell_dims.x) * std::size_t(shell_dims.y) * std::size_t(shell_dims.z);
    constexpr std::uint8_t kFar = std::numeric_limits<std::uint8_t>::max();
    empty_shells.assign(blocks, kFar);
    const std::size_t along_x = std::size_t(dims.x), along_xy = along_x * std::size_t(dims.y);
    cell_triangles.for_each_occupied([&](std::size_t c) {
        const int x = int(c % along_x), y = int(c / along_x % std::size_t(dims.y)),
                  z = int(c / along_xy);
        empty_shells[block_index(x >> shell_shift, y >> shell_shift, z >> shell_shift)] = 0;
    });
    const std::size_t width = std::size_t(shell_dims.x);
    std::vector<std::uint8_t> nearest(width);
    // m[x] = min(m[x], r[x]) in blocks of 16: loops of a known length, which GCC vectorises at -O2.
    const auto min_into = [](std::uint8_t* __restrict m, const std::uint8_t* __restrict r,
                             std::size_t n) {
        constexpr std::size_t kBlock = 16;
        std::size_t x = 0;
        for (; x + kBlock <= n; x += kBlock)
            for (std::size_t k = 0; k < kBlock; ++k) m[x + k] = std::min(m[x + k], r[x + k]);
        for (; x < n; ++x) m[x] = std::min(m[x], r[x]);
    };
    // m[x] = min(m[x], row[x - 1], row[x], row[x + 1]), within the row.
    const auto take_row = [&](std::uint8_t* m, const std::uint8_t* row) {
        min_into(m, row, width);
        min_into(m + 1, row, width - 1);
        min_into(m, row + 1, width - 1);
    };
    // step +1: rows and cells in increasing order; -1: decreasing (the neighbours mirrored).
    const auto pass = [&](int step) {
        for (int zi = 0; zi < shell_dims.z; ++zi)
            for (int yi = 0; yi < shell_dims.y; ++yi) {
                const int z = step > 0 ? zi : shell_dims.z - 1 - zi;
                const int y = step > 0 ? yi : shell_dims.y - 1 - yi;
                const auto row = [&](int ry, int rz) {
                    return &empty_shells[block_index(0, ry, rz)];
                };
                std::fill(nearest.begin(), nearest.end(), kFar);
                const int before_y = y - step, before_z = z - step;
                if (before_y >= 0 && before_y < shell_dims.y)
                    take_row(nearest.data(), row(before_y, z));
                if (before_z >= 0 && before_z < shell_dims.z)
                    for (int ry = y - 1; ry <= y + 1; ++ry)
                        if (ry >= 0 && ry < shell_dims.y)
                            take_row(nearest.data(), row(ry, before_z));
                std::uint8_t* e = row(y, z);
                std::uint8_t previous = kFar; // the cell before in the row, as updated
                for (std::size_t xi = 0; xi < width; ++xi) {
                    const std::size_t x = step > 0 ? xi : width - 1 - xi;
                    if (e[x] != 0) {
                        const std::uint8_t m = std::min(nearest[x], previous);
                        if (m < kFar - 1) e[x] = std::min(e[x], std::uint8_t(m + 1));
                    }
                    previous = e[x];
                }
            }
    };
    pass(+1);
    pass(-1);
}

// Calls visit(cell, index) for the occupied cells at chessboard distance exactly r from `home`.
// Along rows and columns a cell whose distance transform says d jumps d cells at once: no
// occupied cell lies within d - 1 of it. Far from the mesh this makes a shell cost O(r), not
// O(r^2).
template <class Visit>
void MeshDistance::Impl::for_each_occupied_cell(glm::ivec3 home, int r, Visit&& visit) const {
    const glm::ivec3 lo = home - r, hi = home + r;
    const glm::ivec3 clo = glm::max(lo, glm::ivec3(0)), chi = glm::min(hi, dims - 1);
    auto row = [&](int y, int z) {
        for (int x = clo.x; x <= chi.x;) {
            const std::size_t c = cell_index(x, y, z);
            const int skip = empty_cells(x, y, z);
            if (skip == 0 && cell_triangles.occupied(c)) visit(glm::ivec3(x, y, z), c);
            x += std::max(1, skip);
        }
    };
    auto column = [&](int x, int y_first, int y_last, int z) {
        for (int y = y_first; y <= y_last;) {
            const std::size_t c = cell_index(x, y, z);
            const int skip = empty_cells(x, y, z);
            if (skip == 0 && cell_triangles.occupied(c)) visit(glm::ivec3(x, y, z), c);
            y += std::max(1, skip);
        }
    };
    for (int z = clo.z; z <= chi.z; ++z) {
        if (z == lo.z || z == hi.z) { // a whole face of the shell
            for (int y = clo.y; y <= chi.y; ++y) row(y, z);
            continue;
        }
        if (lo.y >= 0) row(lo.y, z);
        if (hi.y < dims.y) row(hi.y, z);
        const int y_first = std::max(lo.y + 1, 0), y_last = std::min(hi.y - 1, dims.y - 1);
        if (lo.x >= 0) column(lo.x, y_first, y_last, z);
        if (hi.x < dims.x) column(hi.x, y_first, y_last, z);
    }
}

double MeshDistance::Impl::squared_distance_to_cell(glm::dvec3 p, glm::ivec3 c) const {
    const glm::dvec3 lo = origin + glm::dvec3(c) * cell;
    const glm::dvec3 d = glm::max(glm::max(lo - p, p - (lo + cell)), glm::dvec3(0.0));
    return glm::dot(d, d);
}

double MeshDistance::Impl::squared_distance_to_segment(glm::dvec3 p, glm::dvec3 a, glm::dvec3 b) {
    const glm::dvec3 ab = b - a;
    const double length2 = glm::dot(ab, ab);
    const double t = length2 > 0 ? std::clamp(glm::dot(p - a, ab) / length2, 0.0, 1.0) : 0.0;
    const glm::dvec3 d = p - (a + t * ab);
    return glm::dot(d, d);
}

// Voronoi regions of the corners and edges; in the face region the distance to the plane.
double MeshDistance::Impl::squared_distance_to_triangle(glm::dvec3 p, const Corners& t,
                                                        const Plane& plane) {
    const auto [a, b, c] = t;
    if (plane.flat)
        return std::min({squared_distance_to_segment(p, a, b), squared_distance_to_segment(p, b, c),
                         squared_distance_to_segment(p, c, a)});
    const glm::dvec3 ab = b - a, ac = c - a, ap = p - a;
    const double d1 = glm::dot(ab, ap), d2 = glm::dot(ac, ap);
    if (d1 <= 0 && d2 <= 0) return glm::dot(ap, ap); // corner a
    const glm::dvec3 bp = p - b;
    const double d3 = glm::dot(ab, bp), d4 = glm::dot(ac, bp);
    if (d3 >= 0 && d4 <= d3) return glm::dot(bp, bp); // corner b
    const glm::dvec3 cp = p - c;
    const double d5 = glm::dot(ab, cp), d6 = glm::dot(ac, cp);
    if (d6 >= 0 && d5 <= d6) return glm::dot(cp, cp); // corner c
    const double vc = d1 * d4 - d3 * d2;
    if (vc <= 0 && d1 >= 0 && d3 <= 0) return squared_distance_to_segment(p, a, b);
    const double vb = d5 * d2 - d1 * d6;
    if (vb <= 0 && d2 >= 0 && d6 <= 0) return squared_distance_to_segment(p, a, c);
    const double va = d3 * d6 - d5 * d4;
    if (va <= 0 && d4 - d3 >= 0 && d5 - d6 >= 0) return squared_distance_to_segment(p, b, c);
    const double height = glm::dot(ap, plane.n);
    return height * height / plane.n2;
}

// The sphere test of a cell's triangles, as a filter: in single precision, four spheres at a time
// where SSE2 is there, and without a branch (it keeps about 4 of the 24 triangles a query reads
// on a clinical CT, at random, and mispredicted branches would cost more than the tests). The
// reach is widened by far more than the float arithmetic can be off (1e-5 of the coordinates'
// size; float rounds to 6e-8 of it), so every triangle that the double test passes is kept, in
// list order, with perhaps a few more that the double test, made again on the few kept, rules
// out: the same distances.
std::span<const std::uint32_t>
MeshDistance::Impl::spheres_in_reach(std::span<const std::uint32_t> items, glm::dvec3 p,
                                     double bound, std::vector<std::uint32_t>& kept) const {
    if (kept.size() < items.size()) kept.resize(items.size());
    const double size = std::max({std::abs(p.x), std::abs(p.y), std::abs(p.z), coordinate_size});
    const float widened = float(bound * (1.0 + 1e-5) + 1e-5 * (size + 1.0));
    const glm::vec3 q(p);
    std::size_t count = 0, i = 0;
#if defined(__SSE2__)
    const __m128 qx = _mm_set1_ps(q.x), qy = _mm_set1_ps(q.y), qz = _mm_set1_ps(q.z);
    const __m128 base = _mm_set1_ps(widened);
    const __m128 magnitude = _mm_castsi128_ps(_mm_set1_epi32(0x7fffffff));
    static_assert(sizeof(Sphere) == 4 * sizeof(float), "a sphere is read as four floats");
    const auto sphere_at = [&](std::size_t k) {
        return _mm_loadu_ps(reinterpret_cast<const float*>(&spheres[items[k]]));
    };
    for (; i + 4 <= items.size(); i += 4) {
        // Each sphere is (x, y, z, signed radius): four of them turned into columns.
        __m128 x = sphere_at(i), y = sphere_at(i + 1), z = sphere_at(i + 2), r = sphere_at(i + 3);
        _MM_TRANSPOSE4_PS(x, y, z, r);
        const __m128 dx = _mm_sub_ps(qx, x), dy = _mm_sub_ps(qy, y), dz = _mm_sub_ps(qz, z);
        const __m128 d2 =
            _mm_add_ps(_mm_add_ps(_mm_mul_ps(dx, dx), _mm_mul_ps(dy, dy)), _mm_mul_ps(dz, dz));
        const __m128 reach = _mm_add_ps(base, _mm_and_ps(r, magnitude));
        const int in = _mm_movemask_ps(_mm_cmplt_ps(d2, _mm_mul_ps(reach, reach)));
        for (int k = 0; k < 4; ++k) {
            kept[count] = items[i + std::size_t(k)];
            count += std::size_t((in >> k) & 1);
        }
    }
#endif
    for (; i < items.size(); ++i) {
        const Sphere& sphere = spheres[items[i]];
        const glm::vec3 d = q - sphere.centre;
        const float reach = widened + sphere.radius();
        kept[count] = items[i];
        count += glm::dot(d, d) < reach * reach ? 1 : 0;
    }
    return std::span<const std::uint32_t>(kept.data(), count);
}

// The triangles that pass a query's sphere test are mostly those of the query before (the next
// sample point of the same triangle, the next vertex): each thread keeps the last ones it
// measured, so that their corners are mapped and their planes worked out once for a run of
// queries rather than once a query. Direct-mapped by triangle number: neighbouring triangles
// have nearby numbers and land in different slots.
const MeshDistance::Impl::Measured& MeshDistance::Impl::measured(std::uint32_t triangle) const {
    constexpr std::size_t kSlots = 128;
    struct Kept {
        std::uint64_t grid = 0; // the serial of the grid whose triangles the slots hold
        std::array<std::uint32_t, kSlots> triangle{};
        std::array<Measured, kSlots> measured{};
    };
    thread_local Kept kept;
    if (kept.grid != serial) {
        kept.grid = serial;
        kept.triangle.fill(kNone);
    }
    const std::size_t slot = triangle % kSlots;
    Measured& m = kept.measured[slot];
    if (kept.triangle[slot] != triangle) {
        kept.triangle[slot] = triangle;
        m.corners = corners(triangle);
        m.plane = plane_of(m.corners, spheres[triangle].flat());
    }
    return m;
}

float MeshDistance::Impl::distance(glm::vec3 point) const {
    if (!std::isfinite(point.x) || !std::isfinite(point.y) || !std::isfinite(point.z))
        return std::numeric_limits<float>::quiet_NaN();
    const glm::dvec3 p(point);
    const glm::ivec3 home = cell_of(p);
    // Queries come in runs of nearby points (a triangle's samples, one vertex after another), so
    // the triangle nearest to this thread's previous point is usually near this one too: its
    // exact distance, taken first, prunes most candidates at once. It is only a start: every
    // test below prunes with a margin far above the rounding of the distances (relative, and
    // absolute for the coordinates' size), so what is returned is the least distance to any
    // triangle, whatever the start and so whatever the thread.
    struct Hint {
        const Impl* owner = nullptr;
        std::uint32_t triangle = 0;
    };
    thread_local Hint hint;
    constexpr double kMargin = 1.0 + 1e-9;
    const double slack_root =
        1e-6 * (coordinate_size + std::max({std::abs(p.x), std::abs(p.y), std::abs(p.z)}));
    const double slack = slack_root * slack_root;
    double best = std::numeric_limits<double>::infinity(); // squared
    // What a lower bound of a squared distance must reach to rule a triangle out, and its root
    // (what a lower bound of the distance itself must reach), kept with `best`.
    const auto beyond = [&](double lower_bound) { return lower_bound >= best * kMargin + slack; };
    double prune_root = best;
    std::uint32_t nearest = 0;
    const auto take = [&](double squared_distance, std::uint32_t triangle) {
        best = squared_distance;
        prune_root = std::sqrt(best * kMargin + slack);
        nearest = triangle;
    };
    // The start's triangle is measured once: met again in a cell, it could only tie with itself.
    std::uint32_t started_from = kNone;
    if (hint.owner == this && hint.triangle < spheres.size()) {
        started_from = hint.triangle;
        const Measured& t = measured(started_from);
        take(squared_distance_to_triangle(p, t.corners, t.plane), started_from);
    }
    // Reused by each thread: no allocation per query.
    thread_local std::vector<Candidate> candidates;
    thread_local std::vector<std::uint32_t> near; // a cell's triangles whose sphere is in reach
    // Shells nearer than the distance transform says are empty are skipped.
    for (int r = empty_cells(home.x, home.y, home.z);; ++r) {
        candidates.clear();
        // A cell of shell r is read when it holds triangles and its box is within reach.
        const auto consider = [&](glm::ivec3 c, std::size_t index) {
            const double d = squared_distance_to_cell(p, c);
            if (!beyond(d)) candidates.push_back({d, index});
        };
        if (r == 0) {
            // The home cell alone, where 94 % of the queries end on a clinical CT (the nets lie
            // about 0.02 voxel from Marching Cubes' surface): no shell walk, no sort.
            const std::size_t c = cell_index(home.x, home.y, home.z);
            if (cell_triangles.occupied(c)) consider(home, c);
        } else {
            if (r == 1) {
                // Shell 1 of a query its home cell did not settle (6 % on the CT): of the 26
                // cells only those across the faces within reach. A face's distance alone is at
                // most the distance to a cell across it (the same arithmetic, a sum of squares),
                // so no cell that the shell's walk would take is left out.
                glm::ivec3 from(0), to(0);
                for (int k = 0; k < 3; ++k) {
                    const auto face_beyond = [&](int c) {
                        const double lo = origin[k] + double(c) * cell;
                        const double d = std::max(std::max(lo - p[k], p[k] - (lo + cell)), 0.0);
                        return beyond(d * d);
                    };
                    if (home[k] > 0 && !face_beyond(home[k] - 1)) from[k] = -1;
                    if (home[k] < dims[k] - 1 && !face_beyond(home[k] + 1)) to[k] = 1;
                }
                for (int dz = from.z; dz <= to.z; ++dz)
                    for (int dy = from.y; dy <= to.y; ++dy)
                        for (int dx = from.x; dx <= to.x; ++dx) {
                            const glm::ivec3 c = home + glm::ivec3(dx, dy, dz);
                            const std::size_t index = cell_index(c.x, c.y, c.z);
                            if (c != home && cell_triangles.occupied(index)) consider(c, index);
                        }
            } else {
                for_each_occupied_cell(home, r, consider);
            }
            // Nearest cells first, so that `best` shrinks early and prunes the rest.
            std::sort(candidates.begin(), candidates.end(),
                      [](const Candidate& x, const Candidate& y) {
                          return x.squared_distance < y.squared_distance;
                      });
        }
        for (const Candidate& candidate : candidates) {
            if (beyond(candidate.squared_distance)) break;
            // The sphere test of every triangle against the bound on entering the cell first
            // (spheres_in_reach), then the few kept, tested again against the bound as it
            // shrinks. A looser bound only lets more through: the least distance is the same.
            const auto kept =
                spheres_in_reach(cell_triangles.items(candidate.cell), p, prune_root, near);
            for (const std::uint32_t id : kept) {
                if (id == started_from) continue;
                const Sphere& sphere = spheres[id];
                if (!sphere_within(p, sphere, prune_root)) continue;
                const double reach = prune_root + double(sphere.radius());
                const Measured& t = measured(id);
                if (beyond_plane(p, t.corners, t.plane, reach + double(sphere.radius()),
                                 prune_root))
                    continue;
                const double d = squared_distance_to_triangle(p, t.corners, t.plane);
                if (d < best) take(d, id);
            }
        }
        // Any cell not yet visited lies beyond a face of the block of shells 0..r that still
        // has cells behind it; the nearest such face bounds the distance of everything left.
        const glm::ivec3 lo = home - r, hi = home + r;
        double bound = std::numeric_limits<double>::infinity();
        for (int k = 0; k < 3; ++k) {
            if (lo[k] > 0) bound = std::min(bound, p[k] - (origin[k] + double(lo[k]) * cell));
            if (hi[k] < dims[k] - 1)
                bound = std::min(bound, origin[k] + double(hi[k] + 1) * cell - p[k]);
        }
        if (bound == std::numeric_limits<double>::infinity()) break; // the whole grid is done
        if (bound >= 0 && beyond(bound * bound)) break;
    }
    hint = {this, nearest};
    return float(std::sqrt(best));
}

MeshDistance::MeshDistance(Mesh reference) : impl_(std::make_shared<Impl>(std::move(reference))) {}

MeshDistance::MeshDistance(const Mesh& reference, const WorldToIndex& to_space)
    : impl_(std::make_shared<Impl>(reference, to_space)) {}

float MeshDistance::operator()(glm::vec3 p) const {
    return impl_->distance(p);
}

} // namespace snert
