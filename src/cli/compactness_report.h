// What compare and render report of compactness: the equal-count reduction (core/compactness.h)
// of each method, and the compactness curves, as JSON and as short tables.
#pragma once

#include <iosfwd>
#include <optional>
#include <span>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/compactness.h"
#include "report.h"

namespace snert::cli {

// Reduces `results` to the count --equal-count asked for (`requested`; empty: the smallest
// count among them) and measures them again as the pipeline measured them. Returns the count and
// one report per result.
struct EqualCountRun {
    std::size_t target = 0;  // the count asked for (or the smallest)
    std::size_t reached = 0; // the count the meshes share (above target where one stopped short)
    std::optional<std::size_t> requested;
    std::vector<DecimationReport> reports;
};
EqualCountRun reduce_sources_to_equal_count(std::span<MethodResult> results,
                                            std::optional<std::size_t> requested,
                                            const Source& source, const PipelineOptions& pipeline,
                                            const Measured& measured);

// {"original", "requested", "achieved", "steps", "refusals", "refused": {"topology",
// "intersections", "flips", "degenerate"}, "vanished_components", "vanished_triangles",
// "stalled", "euler_change", "error"} (error in world units, mm).
nlohmann::json decimation_json(const DecimationReport& report);

// {"triangles": reached, "target": target, "requested": N or null}
nlohmann::json equal_count_json(const EqualCountRun& run);

// A list of {"fraction", "triangles", "accuracy_mean", "accuracy_max", "quality_mean",
// "refusals"}, accuracies in voxels.
nlohmann::json compactness_json(std::span<const CompactnessPoint> curve);

// One line: the count, where it came from, and what each method's reduction refused.
void print_equal_count(std::ostream& out, const EqualCountRun& run,
                       std::span<const MethodResult> results);

// One row per method and level: triangles, accuracy and quality.
void print_compactness(std::ostream& out, std::span<const Method> methods,
                       std::span<const std::vector<CompactnessPoint>> curves);

} // namespace snert::cli
