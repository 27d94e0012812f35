// What the commands report of their runs: the metrics of each method as a table (people) and
// as JSON (scripts; the schema of DESIGN.md's CLI contract), and where the numbers came from
// (the provenance: version, input, iso, every relaxation parameter).
#pragma once

#include <functional>
#include <iosfwd>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/pipeline.h"
#include "io/source.h"

namespace snert::cli {

// What the metrics of a run were measured against.
struct Measured {
    std::string name; // the input as given ("phantom:sphere", a path)
    float iso = 0.0f; // the grey iso
    AccuracyReference reference;
    bool mask = false; // a label map gave the segmentation
};
Measured measured(const Source& source, float iso);

// The methods compare runs: Marching Cubes and the net of --mode, or MC, SNA and SNERT.
std::vector<Method> compared_methods(std::optional<RelaxMode> mode);

// Runs `method` on the source (core's run_method, with the label's mask when there is one).
MethodResult run_source_method(Method method, const Source& source, const PipelineOptions& options,
                               const Measured& measured, const Progress& progress = {});

// Throws InputError naming the input when the method produced no triangle: the volume is all
// inside or all outside at this iso, which is bad input, not a result to report.
void require_surface(const MethodResult& result, const Measured& measured);

// The compared methods' results, in compared_methods' order, each net measured against Marching
// Cubes; `stage` gives each method's progress. The nets run before Marching Cubes: a net's build
// and relaxation are the comparison's peak of memory, and so they do not also hold MC's mesh
// (15 MB on a clinical CT at the bone iso). Throws as require_surface.
std::vector<MethodResult> run_compared_methods(const std::vector<Method>& methods,
                                               const Source& source, const PipelineOptions& options,
                                               const Measured& measured,
                                               const std::function<Progress(Method)>& stage);

// What the accuracies are measured against, in words.
std::string accuracy_against(const Measured& measured);

// One object per method, DESIGN.md's schema; accuracies in voxel units, null without reference.
nlohmann::json method_json(const MethodResult& result, const Measured& measured);

// The FE-readiness summary as the "fe" object of method_json: the angle shares (fractions of
// the triangles), the radius and aspect ratio ranges (the aspect ratio null when infinite, a
// degenerate triangle), closed, manifold, self_intersections.
nlohmann::json fe_json(const FeReadiness& fe);

// Three fixed-width tables, one row per method each: quality and accuracy, topology and
// FE-readiness, the FE summary, each followed by a line saying what the columns mean and
// their units.
void print_table(std::ostream& out, const std::string& title,
                 const std::vector<MethodResult>& results, const Measured& measured);

// ---- Provenance --------------------------------------------------------------------------------

// The input as asked for: {"phantom": NAME, "size": N} or {"path": ..., "raw": {...},
// "series": UID, "labels": FILE, "label": N, "label_name": NAME}, with the grid read.
nlohmann::json input_json(const Source& source);

// Every relaxation parameter, under the names of the command line.
nlohmann::json relaxation_json(const RelaxOptions& relax);

// {"version", "command", "input", "iso", "inside", "relaxation"}: the JSON's "provenance".
nlohmann::json provenance_json(std::string_view command, nlohmann::json input,
                               std::optional<float> iso, std::optional<InsideIs> inside,
                               const RelaxOptions& relax);

// Writes JSON (pretty, 2 spaces) atomically to `path`, or to standard output for "-".
void write_json(const std::string& path, const nlohmann::json& json);

} // namespace snert::cli
