// The comparison figure, headless: Marching Cubes on the left and the relaxed net on the right
// under one shared camera, a title over each view (method, triangle count, mean quality), and
// under both the quality histograms on the same axes and the metrics table. Also the smaller
// layouts: the two views alone, or a single view.
//
//   +---------------------------+---------------------------+
//   |  [] Marching Cubes        |  [] SNERT, 20 iterations  |   title bands
//   |  24,184 triangles · ...   |  18,002 triangles · ...   |
//   +---------------------------+---------------------------+
//   |                           |                           |
//   |        MC view            |        net view           |   3D views, one camera
//   |                           |                           |
//   +---------------------------+---------------------------+
//   |      triangle quality q [colour bar 0..1]  [] q < 0.25 |   legend (quality shading)
//   +---------------------------+---------------------------+
//   |  quality histograms       |  metrics table            |   panels
//   +---------------------------+---------------------------+
//   caption (optional)
//
// layout_figure is pure arithmetic (testable without GL); render_figure draws with a current
// GL context.
#pragma once

#include <span>
#include <string>
#include <vector>

#include "camera.h"
#include "core/mesh.h"
#include "core/pipeline.h"
#include "image.h"
#include "mesh_view.h"

namespace snert::render {

// A rectangle in image pixels, origin at the top-left (ImGui's convention).
struct Rect {
    float x = 0, y = 0, width = 0, height = 0;
    float right() const { return x + width; }
    float bottom() const { return y + height; }
};

// The same rectangle as a GL viewport of a framebuffer `framebuffer_height` pixels high.
Viewport to_viewport(const Rect& rect, int framebuffer_height);

enum class FigureLayout {
    Comparison, // views + histograms + metrics table
    Views,      // views with their titles only
};
// "comparison", "views" (core/names.h: parse_name, name_of, name_choices).
std::span<const Named<FigureLayout>> name_table(FigureLayout);

struct FigureRects {
    std::vector<Rect> titles; // one per view, above it
    std::vector<Rect> views;  // the 3D viewports, equal sizes, left to right
    Rect legend;              // quality legend under the views; empty without one
    Rect histogram;           // Comparison only (else empty)
    Rect table;               // Comparison only
    int table_groups = 1;     // column groups of the metrics table (2 when one would be too tall,
                              // then in the small face)
    Rect caption;             // empty when there is no caption
    float font_px = 0;
};

// The text size of a figure: about 1/42 of the image height (and of 1.33 x its width),
// clamped to [10, 40] pixels.
float figure_font_size(int width, int height);

// Splits a width x height image for `view_count` views (>= 1), with a band for the quality
// legend and a caption line when asked. Throws std::invalid_argument when the image is too
// small to hold the layout (below 160 x 120 for Comparison, 64 x 48 otherwise).
// `font_scale` multiplies the text size (legible labels in a small image), up to 60 pixels.
FigureRects layout_figure(int width, int height, int view_count, FigureLayout layout,
                          bool with_legend, bool with_caption, float font_scale = 1.0f);

// One mesh of the figure.
struct FigureMethod {
    Method method = Method::MarchingCubes;  // colour and default title
    std::string title;                      // shown title; empty: the method's display name
    const Mesh* mesh = nullptr;             // world units; not owned
    const MethodMetrics* metrics = nullptr; // not owned
    // The values of FigureOptions::color_by per triangle, for a distance (pair_distances of
    // core/triangle_distances.h); not owned. Empty for a shape measure: computed here.
    std::span<const float> values;
};

struct FigureOptions {
    int width = 1200;
    int height = 900;
    FigureLayout layout = FigureLayout::Comparison;
    ViewPreset view = ViewPreset::Iso;
    float zoom = 1.0f;       // > 1 moves the shared camera closer (close-ups)
    CameraSpec camera;       // fields set replace the framed camera's (after the zoom)
    float font_scale = 1.0f; // text size against the default for the image size
    DrawStyle style;
    // What quality shading colours and the histograms show (the table keeps every measure).
    ShapeMeasure color_by = ShapeMeasure::Quality;
    std::string caption; // a line of small text under the figure; empty: none
    int samples = 4;     // MSAA samples
};

// Renders the figure with the GL context current on this thread (context.h) and returns it.
// Throws std::invalid_argument for no methods, a missing mesh or a bad size.
Image render_figure(std::span<const FigureMethod> methods, const FigureOptions& options);

} // namespace snert::render
