// Running the methods a command asks for on an Input, and reporting their metrics as a table
// and as JSON (the schema of DESIGN.md's CLI contract).
#pragma once

#include <iosfwd>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/pipeline.h"
#include "input.h"

namespace snert::cli {

// The methods named on the command line: "mc" plus the nets. --mode X runs MC and X only;
// without it, MC, SNA and SNERT (the paper's Table 1).
std::vector<Method> requested_methods(const Args& args);

// Runs one method ("mc", "sna", "gradient" or "snert") on the input. A label map (input.labels)
// gives the segmentation: MC then runs on the mask at 0.5 and the net's gradient term uses the
// grey values at input.iso.
MethodResult run_method(const Input& input, const PipelineOptions& options,
                        Method method, const Progress& progress = {});

// Throws std::runtime_error naming the input when the method produced no triangle: the volume is
// all inside or all outside at this iso, which is bad input, not a result to report.
void require_surface(const MethodResult& result, const Input& input);

// What the accuracies are measured against, in words: the phantom's exact surface, or the grey
// values' iso-surface (first-order distance), also when a label map gave the segmentation.
std::string accuracy_against(const Input& input);

// One object per method, DESIGN.md's schema; accuracies in voxel units, null without reference.
nlohmann::json method_json(const MethodResult& result, const Input& input);

// Two fixed-width tables, one row per method each: quality and accuracy, then topology and
// FE-readiness, each followed by a line saying what the columns mean.
void print_table(std::ostream& out, const std::string& title,
                 const std::vector<MethodResult>& results, const Input& input);

// Writes JSON atomically (pretty, 2 spaces).
void write_json(const std::string& path, const nlohmann::json& json);

} // namespace snert::cli
