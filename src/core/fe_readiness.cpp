#include "fe_readiness.h"

namespace snert {

// quality_stats() checks the indices (std::invalid_argument).
FeReadiness fe_readiness(const Mesh& mesh, const Topology& topology,
                         std::size_t self_intersections) {
    return fe_readiness(quality_stats(mesh), topology, self_intersections);
}

FeReadiness fe_readiness(const QualityStats& quality, const Topology& topology,
                         std::size_t self_intersections) {
    FeReadiness fe;
    fe.triangles = quality.triangles;
    fe.closed = topology.watertight;
    fe.manifold = topology.manifold;
    fe.self_intersections = self_intersections;
    if (fe.triangles == 0) return fe;
    const double n = double(fe.triangles);
    fe.min_angle_below_15 = double(quality.min_angle_below_15) / n;
    fe.min_angle_below_30 = double(quality.min_angle_below_30) / n;
    fe.max_angle_above_120 = double(quality.max_angle_above_120) / n;
    fe.radius_ratio_min = quality.radius_ratio_min;
    fe.radius_ratio_max = quality.radius_ratio_max;
    fe.aspect_ratio_min = quality.aspect_ratio_min;
    fe.aspect_ratio_max = quality.aspect_ratio_max;
    return fe;
}

} // namespace snert
