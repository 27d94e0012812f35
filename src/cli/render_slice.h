// snert render --slice: the slice view with both meshes' cross-sections, zoomed in the paper's
// Fig. 1 picture, and with --node one node's last move taken apart (render/slice_figure.h).
#pragma once

#ifdef SNERT_HAVE_RENDER

#include <string>

#include <CLI/CLI.hpp>

#include "core/window_level.h"
#include "options.h"

namespace snert::cli {

struct SliceArgs {
    std::string slice;        // AXIS:INDEX; empty: no slice view
    std::string node;         // I,J,K: a cell; empty: no inspection
    std::string window_level; // W,L; empty: the preset's
    WindowPreset preset = WindowPreset::Auto;
};

// Adds --slice, --node, --window-level and --preset to the render command (group `group`).
void add_slice_options(CLI::App& command, SliceArgs& args, const char* group);

// Parses --zoom X,Y,W,H (slice samples) as the slice window; throws CLI::ValidationError.
struct SliceZoom {
    float x = 0, y = 0, width = 0, height = 0;
};
SliceZoom parse_slice_zoom(const std::string& text);

// What the render command hands over for a slice picture.
struct SliceRender {
    InputChoice input;
    PipelineArgs pipeline;
    SliceArgs slice;
    std::optional<SliceZoom> zoom;
    std::optional<int> iteration;
    std::string out;
    int width = 1100, height = 760, samples = 4;
    std::string gl = "auto";
    bool caption = true;
    bool quiet = false;
};
int run_slice_render(const SliceRender& render);

} // namespace snert::cli

#endif // SNERT_HAVE_RENDER
