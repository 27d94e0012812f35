#include "figure.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include <imgui.h>

#include "core/triangle_distances.h"
#include "imgui_offscreen.h"
#include "panels.h"
#include "target.h"

namespace snert::render {

Viewport to_viewport(const Rect& rect, int framebuffer_height) {
    const int x0 = int(std::lround(rect.x)), x1 = int(std::lround(rect.right()));
    const int y0 = int(std::lround(rect.y)), y1 = int(std::lround(rect.bottom()));
    return {x0, framebuffer_height - y1, x1 - x0, y1 - y0};
}

float figure_font_size(int width, int height) {
    const float by_height = float(height) / 42.0f;
    const float by_width = float(width) / 56.0f;
    return std::clamp(std::round(std::min(by_height, by_width)), 10.0f, 40.0f);
}

namespace {
constexpr Named<FigureLayout> kFigureLayouts[] = {
    {FigureLayout::Comparison, "comparison", "views, histograms and metrics"},
    {FigureLayout::Views, "views", "views only"},
};
} // namespace

std::span<const Named<FigureLayout>> name_table(FigureLayout) {
    return kFigureLayouts;
}

FigureRects layout_figure(int width, int height, int view_count, FigureLayout layout,
                          bool with_legend, bool with_caption, float font_scale) {
    if (view_count < 1) throw std::invalid_argument("a figure needs at least one view");
    const bool panels = layout == FigureLayout::Comparison;
    const int min_width = panels ? 160 : 64, min_height = panels ? 120 : 48;
    if (width < min_width || height < min_height)
        throw std::invalid_argument("image size " + std::to_string(width) + "x" +
                                    std::to_string(height) + " is too small for this layout (" +
                                    "at least " + std::to_string(min_width) + "x" +
                                    std::to_string(min_height) + ")");
    FigureRects r;
    const float f =
        std::clamp(std::round(figure_font_size(width, height) * font_scale), 6.0f, 60.0f);
    r.font_px = f;
    const float w = float(width), h = float(height);
    const float margin = std::round(0.7f * f);
    const float title_height = std::round(3.0f * f);
    const float caption_height = with_caption ? std::round(1.7f * f) : 0.0f;
    const ImVec2 legend = quality_legend_size(f);
    const float legend_height = with_legend ? legend.y + std::round(0.6f * f) : 0.0f;
    // The panels hold the metrics table, and at least 30 % of the height. The table takes one
    // column group, or two (half the rows, and more of the width) when one would leave the
    // views less than about half the image.
    const int groups = metrics_table_height(1, f) + margin > 0.36f * h ? 2 : 1;
    r.table_groups = panels ? groups : 1;
    const float table_font = groups > 1 ? small_font_size(f) : f;
    const float panel_height =
        panels ? std::max(std::round(0.30f * h),
                          std::ceil(metrics_table_height(groups, table_font) + margin + 0.5f * f))
               : 0.0f;
    const float view_height = h - title_height - panel_height - caption_height - legend_height;
    if (view_height < 2.0f * f)
        throw std::invalid_argument("image height " + std::to_string(height) +
                                    " leaves no room for the views");

    const float gap = std::max(2.0f, std::round(0.2f * f));
    const float view_width = std::floor((w - gap * float(view_count - 1)) / float(view_count));
    for (int i = 0; i < view_count; ++i) {
        const float x = float(i) * (view_width + gap);
        r.titles.push_back({x, 0.0f, view_width, title_height});
        r.views.push_back({x, title_height, view_width, view_height});
    }
    const float below_views = title_height + view_height;
    if (with_legend) {
        const float legend_width = std::min(legend.x, w - 2.0f * margin);
        r.legend = {std::round(0.5f * (w - legend_width)), below_views + std::round(0.6f * f),
                    legend_width, legend.y};
    }
    if (panels) {
        const float top = below_views + legend_height + margin;
        const float panel_inner = panel_height - margin - std::round(0.3f * f);
        const float histogram_share = r.table_groups > 1 ? 0.38f : 0.47f;
        const float histogram_width = std::round((w - 3.0f * margin) * histogram_share);
        r.histogram = {margin, top, histogram_width, panel_inner};
        const float table_x = margin + histogram_width + 1.5f * margin;
        r.table = {table_x, top, w - margin - table_x, panel_inner};
    }
    if (with_caption) r.caption = {margin, h - caption_height, w - 2.0f * margin, caption_height};
    return r;
}

namespace {

// Room around the meshes in the views, as a fraction of the half-size.
constexpr float kFigureMargin = 0.09f;

std::vector<glm::vec3> all_vertices(std::span<const FigureMethod> methods) {
    std::vector<glm::vec3> points;
    for (const FigureMethod& m : methods)
        points.insert(points.end(), m.mesh->positions.begin(), m.mesh->positions.end());
    return points;
}

void draw_overlay(const FigureRects& rects, std::span<const PanelMethod> panels,
                  std::span<const PanelMethod> histogram_panels, const FigureOptions& options,
                  const MeasureScale& scale, const FigureFonts& fonts) {
    const ImGuiIO& io = ImGui::GetIO();
    ImGui::SetNextWindowPos(ImVec2(0, 0), ImGuiCond_Always);
    ImGui::SetNextWindowSize(io.DisplaySize, ImGuiCond_Always);
    const ImGuiWindowFlags flags = ImGuiWindowFlags_NoDecoration | ImGuiWindowFlags_NoBackground |
                                   ImGuiWindowFlags_NoSavedSettings | ImGuiWindowFlags_NoInputs |
                                   ImGuiWindowFlags_NoFocusOnAppearing |
                                   ImGuiWindowFlags_NoBringToFrontOnFocus | ImGuiWindowFlags_NoNav;
    ImGui::Begin("snert figure", nullptr, flags);
    ImDrawList* draw = ImGui::GetWindowDrawList();
    auto min_of = [](const Rect& r) { return ImVec2(r.x, r.y); };
    auto max_of = [](const Rect& r) { return ImVec2(r.right(), r.bottom()); };

    for (std::size_t i = 0; i < panels.size(); ++i)
        draw_view_title(draw, min_of(rects.titles[i]), max_of(rects.titles[i]), panels[i], fonts);
    const bool quality = options.style.shading == Shading::Quality;
    if (rects.legend.width > 0.0f)
        draw_quality_legend(draw, min_of(rects.legend), max_of(rects.legend),
                            options.style.quality_threshold, fonts, options.color_by, scale);
    if (options.layout == FigureLayout::Comparison) {
        draw_quality_histograms(draw, min_of(rects.histogram), max_of(rects.histogram),
                                histogram_panels, fonts, quality, options.style.quality_threshold,
                                options.color_by, scale);
        // Two column groups are narrower: their text in the small face, as the app does.
        FigureFonts table_fonts = fonts;
        const bool compact = rects.table_groups > 1;
        if (compact) table_fonts.size = fonts.small->FontSize;
        ImGui::SetCursorScreenPos(min_of(rects.table));
        if (compact) ImGui::PushFont(fonts.small);
        metrics_table("metrics", panels, rects.table_groups, rects.table.width, table_fonts);
        if (compact) ImGui::PopFont();
    }
    if (rects.caption.height > 0) {
        ImGui::PushFont(fonts.small);
        ImGui::SetCursorScreenPos(
            ImVec2(rects.caption.x,
                   rects.caption.y + 0.5f * (rects.caption.height - fonts.small->FontSize)));
        ImGui::PushStyleColor(ImGuiCol_Text, IM_COL32(88, 92, 100, 255));
        ImGui::TextUnformatted(options.caption.c_str());
        ImGui::PopStyleColor();
        ImGui::PopFont();
    }
    ImGui::End();
}

} // namespace

Image render_figure(std::span<const FigureMethod> methods, const FigureOptions& options) {
    if (methods.empty()) throw std::invalid_argument("render_figure: no methods to draw");
    for (const FigureMethod& m : methods)
        if (m.mesh == nullptr) throw std::invalid_argument("render_figure: method without mesh");
    if (!(options.zoom > 0.0f)) throw std::invalid_argument("zoom must be positive");
    const bool legend = options.style.shading == Shading::Quality;
    const FigureRects rects =
        layout_figure(options.width, options.height, int(methods.size()), options.layout, legend,
                      !options.caption.empty(), options.font_scale);

    RenderTarget target(options.width, options.height, options.samples);
    target.bind();
    glClearColor(1.0f, 1.0f, 1.0f, 1.0f);
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);

    MeshRenderer renderer;
    std::vector<MeshView> views(methods.size());
    // The histograms show the measure the colours do: its mean and bins in a copy of the metrics.
    std::vector<MethodMetrics> histogram_metrics(methods.size());
    const bool distance = is_distance(options.color_by);
    // A distance's range suits the meshes drawn, as the app's (pair_distances) does.
    const MeasureScale scale =
        distance ? distance_scale(options.color_by, methods[0].values,
                                  methods.size() > 1 ? methods[1].values : std::span<const float>{})
                 : measure_scale(options.color_by);
    for (std::size_t i = 0; i < methods.size(); ++i) {
        const TriangleMeasures measures =
            distance ? TriangleMeasures{} : triangle_measures(*methods[i].mesh);
        const std::span<const float> values =
            distance ? methods[i].values : measures.of(options.color_by);
        if (distance && values.size() != methods[i].mesh->triangle_count())
            throw std::invalid_argument("render_figure: colouring by " +
                                        std::string(name_of(options.color_by)) +
                                        " needs one value per triangle");
        views[i].upload(*methods[i].mesh, values);
        if (!methods[i].metrics) continue;
        const MeasureSummary summary = summarize_measure(values, scale);
        histogram_metrics[i] = *methods[i].metrics;
        histogram_metrics[i].quality.mean = summary.mean;
        histogram_metrics[i].quality.histogram = summary.histogram;
    }

    // One camera for all views, framing every mesh, so the same region of each is compared.
    OrbitCamera camera =
        frame_points(all_vertices(methods), options.view,
                     rects.views.front().width / rects.views.front().height, kFigureMargin);
    camera.zoom(options.zoom);
    apply_camera_spec(camera, options.camera, all_vertices(methods));
    for (std::size_t i = 0; i < methods.size(); ++i) {
        const Viewport viewport = to_viewport(rects.views[i], options.height);
        renderer.draw_background(viewport, options.style);
        renderer.draw(views[i], camera, viewport,
                      measure_style(options.style, options.color_by, scale));
    }

    std::vector<PanelMethod> panels, histogram_panels;
    for (std::size_t i = 0; i < methods.size(); ++i) {
        const FigureMethod& m = methods[i];
        panels.push_back({m.method, m.title, m.metrics});
        histogram_panels.push_back(
            {m.method, m.title, m.metrics ? &histogram_metrics[i] : nullptr});
    }
    ImGuiOffscreen gui(rects.font_px);
    target.bind();
    gui.draw(options.width, options.height,
             [&] { draw_overlay(rects, panels, histogram_panels, options, scale, gui.fonts()); });
    return target.read();
}

} // namespace snert::render
