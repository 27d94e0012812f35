// Small plots of the app, drawn with ImGui's draw lists: the convergence curves of the
// relaxation and the value histogram beside the iso slider. Each is an interactive widget:
// pressing or dragging the left mouse button on it picks an iteration or an iso value.
#pragma once

#include <optional>
#include <span>
#include <string>
#include <vector>

#include <imgui.h>

#include "render/fonts.h"
#include "core/volume_stats.h"

namespace snert::app {

struct ConvergencePlot {
    std::string title;              // "Mean quality"
    std::string hint;               // tooltip: what the curve means and which way is better
    std::span<const float> values;  // [k] = value after iteration k
    int first_iteration = 0;        // first k drawn (max move has no value at 0)
    int marker = -1;                // the iteration shown in the views
    std::optional<float> reference; // Marching Cubes' value, drawn dashed
    bool log_scale = false;
    ImU32 color = IM_COL32(0, 114, 178, 255);
};

// Draws the plot into the next `size` of the current window. Returns the iteration under the
// mouse while the left button is pressed on it.
std::optional<int> convergence_plot(const char* id, const ConvergencePlot& plot, ImVec2 size,
                                    const render::FigureFonts& fonts);

// One method's compactness curve: values against the share of the triangles kept.
struct CompactnessSeries {
    struct Point {
        double share = 1.0; // of the unreduced triangles, (0, 1]
        float value = 0.0f;
    };
    std::span<const Point> points;
    ImU32 color = IM_COL32(0, 114, 178, 255);
    std::string label; // the method, in the legend on the title line
};

struct CompactnessPlot {
    std::string title;
    std::string hint; // tooltip
    std::vector<CompactnessSeries> series;
};

// Draws the curves into the next `size` of the current window: the share kept on a logarithmic
// axis (5 % left, 100 % right), a dot at every level, the value range at the left.
void compactness_plot(const char* id, const CompactnessPlot& plot, ImVec2 size,
                      const render::FigureFonts& fonts);

// The volume's value histogram (logarithmic counts) with a line at `iso`. Returns the value
// under the mouse, rounded to a multiple of `step` (none when 0), while the left button is
// pressed on it.
std::optional<float> value_histogram_plot(const char* id, const Histogram& histogram, float iso,
                                          float step, ImVec2 size,
                                          const render::FigureFonts& fonts);

} // namespace snert::app
