#include "fe_readiness.h"

#include <algorithm>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

#include "parallel.h"

namespace snert {

namespace {

constexpr std::size_t kChunk = 1 << 14;

struct Partial {
    std::size_t below_15 = 0, below_30 = 0, above_120 = 0;
    double radius_min = std::numeric_limits<double>::infinity(), radius_max = 0;
    double aspect_min = std::numeric_limits<double>::infinity(), aspect_max = 0;
};

} // namespace

FeReadiness fe_readiness(const Mesh& mesh, const Topology& topology,
                         std::size_t self_intersections) {
    if (mesh.indices.size() % 3 != 0)
        throw std::invalid_argument("fe_readiness: index count is not a multiple of 3");
    if (const auto i = first_index_out_of_range(mesh))
        throw std::invalid_argument("fe_readiness: index " + std::to_string(*i) + " out of range");
    FeReadiness fe;
    fe.triangles = mesh.triangle_count();
    fe.closed = topology.watertight;
    fe.manifold = topology.manifold;
    fe.self_intersections = self_intersections;
    if (fe.triangles == 0) return fe;

    // Counts and extremes per chunk: combining them is exact in any order.
    std::vector<Partial> partials(chunk_count(fe.triangles, kChunk));
    for_each_chunk(fe.triangles, kChunk, [&](std::size_t c, std::size_t begin, std::size_t end) {
        Partial p;
        for (std::size_t t = begin; t < end; ++t) {
            const std::uint32_t* i = &mesh.indices[3 * t];
            const TriangleShape s =
                triangle_shape(mesh.positions[i[0]], mesh.positions[i[1]], mesh.positions[i[2]]);
            p.below_15 += s.min_angle < kFeSmallAngle;
            p.below_30 += s.min_angle < kFeNarrowAngle;
            p.above_120 += s.max_angle > kFeObtuseAngle;
            p.radius_min = std::min(p.radius_min, double(s.radius_ratio));
            p.radius_max = std::max(p.radius_max, double(s.radius_ratio));
            p.aspect_min = std::min(p.aspect_min, double(s.aspect_ratio));
            p.aspect_max = std::max(p.aspect_max, double(s.aspect_ratio));
        }
        partials[c] = p;
    });
    Partial all;
    for (const Partial& p : partials) {
        all.below_15 += p.below_15;
        all.below_30 += p.below_30;
        all.above_120 += p.above_120;
        all.radius_min = std::min(all.radius_min, p.radius_min);
        all.radius_max = std::max(all.radius_max, p.radius_max);
        all.aspect_min = std::min(all.aspect_min, p.aspect_min);
        all.aspect_max = std::max(all.aspect_max, p.aspect_max);
    }
    const double n = double(fe.triangles);
    fe.min_angle_below_15 = double(all.below_15) / n;
    fe.min_angle_below_30 = double(all.below_30) / n;
    fe.max_angle_above_120 = double(all.above_120) / n;
    fe.radius_ratio_min = all.radius_min;
    fe.radius_ratio_max = all.radius_max;
    fe.aspect_ratio_min = all.aspect_min;
    fe.aspect_ratio_max = all.aspect_max;
    return fe;
}

} // namespace snert
