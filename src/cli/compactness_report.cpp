#include "compactness_report.h"

#include <algorithm>
#include <cstdio>
#include <ostream>

namespace snert::cli {

EqualCountRun reduce_sources_to_equal_count(std::span<MethodResult> results,
                                            std::optional<std::size_t> requested,
                                            const Source& source, const PipelineOptions& pipeline,
                                            const Measured& m) {
    EqualCountRun run;
    run.requested = requested;
    run.target = equal_count_target(results, requested);
    // As run_source_method measured them: the reference's volume for the volume error.
    MeasureOptions what = pipeline.measure;
    what.reference_volume = m.reference.volume;
    run.reports =
        reduce_to_equal_count(results, run.target, *source.volume, m.reference.distance, what);
    for (const DecimationReport& r : run.reports) run.reached = std::max(run.reached, r.achieved);
    return run;
}

nlohmann::json decimation_json(const DecimationReport& r) {
    return {{"original", r.original},
            {"requested", r.requested},
            {"achieved", r.achieved},
            {"steps", r.steps},
            {"refusals", r.refusals},
            {"refused",
             {{"topology", r.refused_topology},
              {"intersections", r.refused_intersections},
              {"flips", r.refused_flips},
              {"degenerate", r.refused_degenerate}}},
            {"vanished_components", r.vanished_components},
            {"vanished_triangles", r.vanished_triangles},
            {"stalled", r.stalled},
            {"euler_change", r.euler_change},
            {"error", r.error}};
}

nlohmann::json equal_count_json(const EqualCountRun& run) {
    return {{"triangles", run.reached},
            {"target", run.target},
            {"requested", run.requested ? nlohmann::json(*run.requested) : nlohmann::json()}};
}

nlohmann::json compactness_json(std::span<const CompactnessPoint> curve) {
    nlohmann::json list = nlohmann::json::array();
    for (const CompactnessPoint& p : curve)
        list.push_back({{"fraction", p.fraction},
                        {"triangles", p.triangles},
                        {"accuracy_mean", p.accuracy_mean},
                        {"accuracy_max", p.accuracy_max},
                        {"quality_mean", p.quality_mean},
                        {"refusals", p.refusals}});
    return list;
}

void print_equal_count(std::ostream& out, const EqualCountRun& run,
                       std::span<const MethodResult> results) {
    out << "  equal triangle count: " << run.reached;
    if (run.reached != run.target) out << " (asked: " << run.target << ")";
    out << (run.requested ? " (--equal-count)" : " (the smallest of the meshes' counts)")
        << "; the metrics are of the reduced meshes (meshoptimizer's simplifier, checked)\n";
    for (std::size_t i = 0; i < results.size() && i < run.reports.size(); ++i) {
        const DecimationReport& r = run.reports[i];
        out << "    " << name_of(results[i].method) << ": " << r.original << " -> " << r.achieved
            << " triangles, " << r.refusals << " tries refused";
        if (r.refusals > 0)
            out << " (topology " << r.refused_topology << ", intersections "
                << r.refused_intersections << ", flips " << r.refused_flips << ", degenerate "
                << r.refused_degenerate << ")";
        if (r.vanished_components > 0)
            out << "; " << r.vanished_components << " specks removed (" << r.vanished_triangles
                << " triangles: too small for their share)";
        if (r.stalled) out << "; stopped short of the count: no further step passed the checks";
        out << "\n";
    }
}

void print_compactness(std::ostream& out, std::span<const Method> methods,
                       std::span<const std::vector<CompactnessPoint>> curves) {
    char line[256];
    std::snprintf(line, sizeof line, "  %-8s %8s %9s %9s %9s %7s\n", "method", "share%",
                  "triangles", "acc_mean", "acc_max", "q");
    out << "compactness (each mesh reduced from its own full mesh)\n" << line;
    for (std::size_t i = 0; i < methods.size() && i < curves.size(); ++i)
        for (const CompactnessPoint& p : curves[i]) {
            std::snprintf(line, sizeof line, "  %-8s %8.0f %9zu %9.2e %9.2e %7.3f\n",
                          std::string(name_of(methods[i])).c_str(), 100.0 * p.fraction, p.triangles,
                          p.accuracy_mean, p.accuracy_max, p.quality_mean);
            out << line;
        }
    out << "  acc_mean, acc_max: distance between the reduced and the full mesh in voxels (mean "
           "of both directions, largest sample); q = smallest / largest angle\n";
}

} // namespace snert::cli
