// The 2D parts of a comparison figure, drawn with Dear ImGui: view titles, the quality legend,
// the two quality histograms on one pair of axes, and the metrics table. The headless
// renderer (figure.h) and the app call the same functions, so a PNG and the window agree.
//
// Functions taking an ImDrawList* draw into the given rectangle (screen pixels, origin top-left)
// and need no window layout; metrics_table is a widget at the current cursor of the current
// window. All need a current ImGui context whose atlas holds the FigureFonts.
#pragma once

#include <cstddef>
#include <span>
#include <string>
#include <string_view>

#include <imgui.h>

#include "core/pipeline.h"
#include "fonts.h"

namespace snert::render {

// One method as the panels show it.
struct PanelMethod {
    Method method = Method::MarchingCubes;  // picks the colour and the default title
    std::string title;                      // shown title, e.g. "SNERT, 20 iterations"
    const MethodMetrics* metrics = nullptr; // not owned; must outlive the call
};

// "MC", "SNA", "Gradient", "SNERT": for legends and table headers (titles use label_of).
std::string method_short_name(Method method);
// 1234567 -> "1,234,567".
std::string format_count(std::size_t count);

// The colour of a method's series (colormap.h's method_color) as an ImGui colour.
ImU32 method_color_u32(Method method, float alpha = 1.0f);

// Light, print-friendly ImGui colours and spacing scaled to the font size.
void apply_figure_style(ImGuiStyle& style, float font_px);
// The vertical cell padding of tables in that style.
float figure_cell_padding(float font_px);

// Title block of a view: a colour swatch and the bold title on the first line, then
// "N triangles · mean quality Q" centred under it.
void draw_view_title(ImDrawList* draw, ImVec2 min, ImVec2 max, const PanelMethod& method,
                     const FigureFonts& fonts);

// The legend of quality shading on one line: the caption "triangle quality q" (or the measure
// coloured by), a horizontal colour bar over [0, 1] with ticks under it (red below the
// threshold, as on the meshes), and "red: q < threshold", centred in the rectangle.
// A distance (core/metrics.h) shows its range `scale` in voxels, on its map, and for the signed
// one which side is which, instead of the red threshold.
void draw_quality_legend(ImDrawList* draw, ImVec2 min, ImVec2 max, float threshold,
                         const FigureFonts& fonts, ShapeMeasure measure = ShapeMeasure::Quality,
                         const MeasureScale& scale = {});
// The size draw_quality_legend needs with regular text of `font_px` pixels.
ImVec2 quality_legend_size(float font_px);

// Quality histograms of all methods on the same axes: share of triangles (percent) per bin of
// q over [0, 1] (kQualityBins bins), bars side by side per bin, a vertical line at each mean.
// With `colormap_axis` a strip of the quality colours runs under the q axis (threshold red).
// The metrics' quality histogram and mean are those of `measure` (the axis is named after it),
// binned over `scale` (summarize_measure's bins).
void draw_quality_histograms(ImDrawList* draw, ImVec2 min, ImVec2 max,
                             std::span<const PanelMethod> methods, const FigureFonts& fonts,
                             bool colormap_axis, float threshold,
                             ShapeMeasure measure = ShapeMeasure::Quality,
                             const MeasureScale& scale = {});

// The metrics table: one column per method, one row per measure; `column_groups` = 2 puts
// the rows into two side-by-side groups (half the height, for wide figures).
// `width` is the table's width in pixels.
void metrics_table(const char* id, std::span<const PanelMethod> methods, int column_groups,
                   float width, const FigureFonts& fonts);
// The height metrics_table takes with this many column groups, regular text of `font_px`
// pixels and the figure style (apply_figure_style).
float metrics_table_height(int column_groups, float font_px);
inline float metrics_table_height(int column_groups, const FigureFonts& fonts) {
    return metrics_table_height(column_groups, fonts.size);
}

} // namespace snert::render
