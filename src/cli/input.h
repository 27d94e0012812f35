// The volume a command works on: a phantom ("phantom:NAME") or a file, plus the segmentation
// options. Shared by every subcommand so they all accept the same inputs.
#pragma once

#include <optional>
#include <set>
#include <string>

#include "args.h"
#include "core/metrics.h"
#include "core/pipeline.h"
#include "core/segmentation.h"
#include "core/volume.h"

namespace snert::cli {

struct Input {
    std::string name; // "phantom:sphere" or the file path
    Volume volume;    // grey values
    float iso = 0.0f; // --iso, or the phantom's / a suggested value
    InsideIs inside = InsideIs::Above;
    std::optional<Segmentation> labels; // --labels FILE --label N: the label's mask
    DistanceFunction reference;         // voxel units
    bool analytic_reference = false;    // true for phantoms
    double reference_volume = 0.0;      // voxels^3, 0 when unknown
};

// Options understood by load_input (add them to a command's option set).
std::set<std::string> input_options();
std::set<std::string> input_switches();

// Loads the first positional argument. Throws UsageError for a missing argument and
// std::runtime_error / std::invalid_argument (naming the file) for bad input.
Input load_input(const Args& args);

// Options of the comparison pipeline (--mode, --iterations, --weights, ...).
std::set<std::string> pipeline_option_names();
PipelineOptions pipeline_options(const Args& args, const Input& input);

} // namespace snert::cli
