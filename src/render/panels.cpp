#include "panels.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include "colormap.h"

namespace snert::render {

namespace {

constexpr ImU32 kText = IM_COL32(28, 30, 34, 255);
constexpr ImU32 kMutedText = IM_COL32(88, 92, 100, 255);
constexpr ImU32 kAxis = IM_COL32(60, 63, 70, 255);
constexpr ImU32 kGrid = IM_COL32(215, 218, 224, 255);

ImU32 to_u32(glm::vec3 c, float alpha = 1.0f) {
    return ImGui::ColorConvertFloat4ToU32(ImVec4(c.r, c.g, c.b, alpha));
}

std::string format(const char* pattern, double value) {
    char text[64];
    std::snprintf(text, sizeof text, pattern, value);
    return text;
}

ImVec2 text_size(ImFont* font, const std::string& text) {
    return font->CalcTextSizeA(font->FontSize, 1e9f, 0.0f, text.c_str());
}

void text(ImDrawList* draw, ImFont* font, ImVec2 pos, ImU32 color, const std::string& s) {
    draw->AddText(font, font->FontSize, ImVec2(std::round(pos.x), std::round(pos.y)), color,
                  s.c_str());
}

// A step of 1, 2 or 5 times a power of ten that cuts [0, top] into about `count` parts.
double nice_step(double top, int count) {
    const double raw = std::max(top, 1e-9) / count;
    const double magnitude = std::pow(10.0, std::floor(std::log10(raw)));
    const double normalised = raw / magnitude;
    const double step = normalised <= 1.0   ? 1.0
                        : normalised <= 2.0 ? 2.0
                        : normalised <= 5.0 ? 5.0
                                            : 10.0;
    return step * magnitude;
}

} // namespace

std::string method_short_name(Method method) {
    return method == Method::MarchingCubes ? std::string("MC") : std::string(label_of(method));
}

std::string format_count(std::size_t count) {
    // Built front to back: inserting into the string trips GCC 12's -Wrestrict at -O3.
    const std::string digits = std::to_string(count);
    std::string text;
    text.reserve(digits.size() + digits.size() / 3);
    for (std::size_t i = 0; i < digits.size(); ++i) {
        if (i > 0 && (digits.size() - i) % 3 == 0) text += ',';
        text += digits[i];
    }
    return text;
}

ImU32 method_color_u32(Method method, float alpha) {
    return to_u32(method_color(method), alpha);
}

float figure_cell_padding(float font_px) {
    return std::round(2.0f * font_px / 13.0f);
}

void apply_figure_style(ImGuiStyle& style, float font_px) {
    ImGui::StyleColorsLight(&style);
    const float unit = font_px / 13.0f; // ImGui's sizes are made for its 13 px default font
    style.WindowPadding = ImVec2(0, 0);
    style.WindowBorderSize = 0.0f;
    style.WindowRounding = 0.0f;
    style.CellPadding = ImVec2(std::round(5 * unit), figure_cell_padding(font_px));
    style.ItemSpacing = ImVec2(std::round(6 * unit), std::round(3 * unit));
    style.AntiAliasedLines = true;
    style.AntiAliasedFill = true;
    ImVec4* colors = style.Colors;
    colors[ImGuiCol_Text] = ImGui::ColorConvertU32ToFloat4(kText);
    colors[ImGuiCol_WindowBg] = ImVec4(1, 1, 1, 1);
    colors[ImGuiCol_TableHeaderBg] = ImVec4(0, 0, 0, 0);
    colors[ImGuiCol_TableRowBg] = ImVec4(0, 0, 0, 0);
    colors[ImGuiCol_TableRowBgAlt] = ImVec4(0.94f, 0.95f, 0.97f, 1.0f);
    colors[ImGuiCol_TableBorderLight] = ImGui::ColorConvertU32ToFloat4(kGrid);
    colors[ImGuiCol_TableBorderStrong] = ImGui::ColorConvertU32ToFloat4(kAxis);
}

void draw_view_title(ImDrawList* draw, ImVec2 min, ImVec2 max, const PanelMethod& method,
                     const FigureFonts& fonts) {
    const std::string title =
        method.title.empty() ? std::string(label_of(method.method)) : method.title;
    std::string stats;
    if (method.metrics)
        stats = format_count(method.metrics->triangles) + " triangles  \xC2\xB7  mean quality " +
                format("%.3f", method.metrics->quality.mean);
    const ImVec2 title_size = text_size(fonts.bold, title);
    const ImVec2 stats_size = text_size(fonts.regular, stats);
    const float swatch = std::round(0.75f * fonts.size);
    const float gap = std::round(0.4f * fonts.size);
    const float line_gap = std::round(0.15f * fonts.size);
    const float block_height = title_size.y + (stats.empty() ? 0 : line_gap + stats_size.y);
    const float centre_x = 0.5f * (min.x + max.x);
    float y = std::round(0.5f * (min.y + max.y - block_height));

    const float title_width = swatch + gap + title_size.x;
    const float x = std::round(centre_x - 0.5f * title_width);
    const float swatch_y = std::round(y + 0.5f * (title_size.y - swatch));
    draw->AddRectFilled(ImVec2(x, swatch_y), ImVec2(x + swatch, swatch_y + swatch),
                        method_color_u32(method.method), 0.2f * swatch);
    text(draw, fonts.bold, ImVec2(x + swatch + gap, y), kText, title);
    y += title_size.y + line_gap;
    if (!stats.empty())
        text(draw, fonts.regular, ImVec2(centre_x - 0.5f * stats_size.x, y), kMutedText, stats);
}

ImVec2 quality_legend_size(float font_px) {
    return ImVec2(std::round(38.0f * font_px), std::round(2.4f * font_px));
}

void draw_quality_legend(ImDrawList* draw, ImVec2 min, ImVec2 max, float threshold,
                         const FigureFonts& fonts, ShapeMeasure measure,
                         const MeasureScale& scale) {
    const float f = fonts.size;
    const bool distance = is_distance(measure);
    const std::string symbol(label_of(measure));
    std::string caption = measure == ShapeMeasure::Quality ? "triangle quality q"
                          : distance ? symbol + " (" + std::string(scale.unit) + ")"
                                     : "triangle " + symbol;
    // The shapes: the poor-quality swatch; the signed distance: which side is which.
    std::string note = !distance         ? symbol + format(" < %.2f", threshold)
                       : scale.diverging ? "- inside, + outside"
                                         : "";
    const float swatch = distance ? 0.0f : std::round(0.8f * f);
    const float gap = std::round(0.6f * f);
    // caption | bar | swatch + "q < t", centred as a group; the bar takes what is left.
    const auto fixed_width = [&] {
        return text_size(fonts.regular, caption).x + gap + gap + swatch + 0.3f * f +
               text_size(fonts.regular, note).x;
    };
    // A distance's long caption in a narrow view (the app's): the note goes first (the ticks'
    // signs say it too), then the caption shortens to the unit.
    if (distance && max.x - min.x - fixed_width() < 10.0f * f) note.clear();
    if (distance && max.x - min.x - fixed_width() < 10.0f * f)
        caption = "distance (" + std::string(scale.unit) + ")";
    const ImVec2 caption_size = text_size(fonts.regular, caption);
    const float fixed = fixed_width();
    const float bar_width = std::clamp(max.x - min.x - fixed, 4.0f * f, 18.0f * f);
    float x = std::round(0.5f * (min.x + max.x - fixed - bar_width));
    const float bar_height = std::round(0.8f * f);
    const float bar_top = std::round(min.y + 0.2f * f);
    const float text_y = bar_top + 0.5f * (bar_height - caption_size.y);

    text(draw, fonts.regular, ImVec2(x, text_y), kText, caption);
    x += caption_size.x + gap;
    const float bar_left = x, bar_right = x + bar_width;
    const int slices = std::max(8, int(bar_width));
    for (int i = 0; i < slices; ++i) {
        const float t0 = float(i) / slices, t1 = float(i + 1) / slices;
        const float value = scale.low + 0.5f * (t0 + t1) * (scale.high - scale.low);
        draw->AddRectFilled(ImVec2(bar_left + t0 * bar_width, bar_top),
                            ImVec2(bar_left + t1 * bar_width + 0.5f, bar_top + bar_height),
                            to_u32(measure_color(measure, value, threshold, scale)));
    }
    draw->AddRect(ImVec2(bar_left, bar_top), ImVec2(bar_right, bar_top + bar_height), kAxis);
    const float tick_top = bar_top + bar_height;
    // A short bar has room for the ends and the middle of a distance's range only.
    const int tick_step = distance && bar_width < 12.0f * f ? 2 : 1;
    for (int i = 0; i <= 4; i += tick_step) {
        const float t = 0.25f * float(i);
        const float tx = std::round(bar_left + t * bar_width);
        draw->AddLine(ImVec2(tx, tick_top), ImVec2(tx, tick_top + 0.25f * f), kAxis);
        const float value = scale.low + t * (scale.high - scale.low);
        // The last tick of a distance reads "1+": farther triangles take the end colour.
        std::string label = i == 0 ? "0" : i == 4 ? "1" : format("%.2f", t);
        if (distance) {
            // The range's ends read "1+" and "-0.5+": farther triangles take the end colours.
            label = value == 0.0f ? "0" : format("%g", double(std::abs(value)));
            if (value < 0.0f) label = "-" + label;
            if (i == 4 || (i == 0 && value < 0.0f)) label += "+";
        }
        const ImVec2 size = text_size(fonts.small, label);
        text(draw, fonts.small, ImVec2(tx - 0.5f * size.x, tick_top + 0.25f * f), kMutedText,
             label);
    }
    x = bar_right + gap;
    if (!distance) {
        const float swatch_y = std::round(bar_top + 0.5f * (bar_height - swatch));
        draw->AddRectFilled(ImVec2(x, swatch_y), ImVec2(x + swatch, swatch_y + swatch),
                            to_u32(kPoorQualityColor), 0.15f * swatch);
    }
    text(draw, fonts.regular, ImVec2(x + swatch + (distance ? 0.0f : 0.3f * f), text_y), kText,
         note);
}

void draw_quality_histograms(ImDrawList* draw, ImVec2 min, ImVec2 max,
                             std::span<const PanelMethod> methods, const FigureFonts& fonts,
                             bool colormap_axis, float threshold, ShapeMeasure measure,
                             const MeasureScale& scale) {
    const float f = fonts.size;
    // Shares per bin, and the top of the y axis.
    std::vector<std::vector<double>> shares;
    double top = 0.0;
    for (const PanelMethod& m : methods) {
        std::vector<double> s(kQualityBins, 0.0);
        if (m.metrics && m.metrics->triangles > 0)
            for (int b = 0; b < kQualityBins; ++b)
                s[std::size_t(b)] = 100.0 * double(m.metrics->quality.histogram[std::size_t(b)]) /
                                    double(m.metrics->triangles);
        for (double v : s) top = std::max(top, v);
        shares.push_back(std::move(s));
    }
    const double step = nice_step(top, 4);
    const double y_max = std::max(step, std::ceil(top / step - 1e-9) * step);

    // Axes frame: y tick labels on the left, x ticks and caption below, a legend line on top.
    std::string widest = format("%g", y_max);
    const float y_label_width = text_size(fonts.small, widest).x;
    const float plot_left = std::round(min.x + y_label_width + 0.6f * f);
    const float plot_right = std::round(max.x - 0.3f * f);
    // Title line: "triangles (%)" over the y axis; the series legend right-aligned after it, or
    // on a line of its own when both do not fit on one.
    const float swatch = std::round(0.7f * f);
    std::vector<std::string> labels;
    float legend_width = 0.0f;
    for (const PanelMethod& m : methods) {
        labels.push_back(method_short_name(m.method) +
                         (m.metrics ? format(", mean %.3f", m.metrics->quality.mean) : ""));
        legend_width += swatch + 0.35f * f + text_size(fonts.regular, labels.back()).x + 1.0f * f;
    }
    const std::string y_title = "triangles (%)";
    const bool legend_below =
        text_size(fonts.regular, y_title).x + 1.0f * f + legend_width - 1.0f * f > max.x - min.x;
    const float legend_y = legend_below ? std::round(min.y + 1.3f * f) : min.y;
    const float plot_top = std::round(legend_y + 2.6f * f);
    const float strip = colormap_axis ? std::round(0.5f * f) : 0.0f;
    const float plot_bottom = std::round(max.y - 2.5f * f - strip);
    if (plot_right - plot_left < 4 * f || plot_bottom - plot_top < 2 * f) return; // no room

    text(draw, fonts.regular, ImVec2(min.x, min.y), kText, y_title);
    float legend_x = std::round(max.x - legend_width + 1.0f * f);
    for (std::size_t i = 0; i < methods.size(); ++i) {
        const float y = std::round(legend_y + 0.5f * (fonts.regular->FontSize - swatch));
        draw->AddRectFilled(ImVec2(legend_x, y), ImVec2(legend_x + swatch, y + swatch),
                            method_color_u32(methods[i].method), 0.15f * swatch);
        text(draw, fonts.regular, ImVec2(legend_x + swatch + 0.35f * f, legend_y), kText,
             labels[i]);
        legend_x += swatch + 0.35f * f + text_size(fonts.regular, labels[i]).x + 1.0f * f;
    }

    // x of a value of the measure (its scale's range across the axis, clamped to it).
    auto x_of = [&](double v) {
        const double t = std::clamp((v - scale.low) / double(scale.high - scale.low), 0.0, 1.0);
        return float(plot_left + t * (plot_right - plot_left));
    };
    auto y_of = [&](double v) { return float(plot_bottom - v / y_max * (plot_bottom - plot_top)); };

    // Grid and y ticks.
    const int ticks = int(std::floor(y_max / step + 1e-9));
    for (int tick = 0; tick <= ticks; ++tick) {
        const double v = tick * step;
        const float y = std::round(y_of(v));
        draw->AddLine(ImVec2(plot_left, y), ImVec2(plot_right, y), v == 0.0 ? kAxis : kGrid);
        const std::string label = format("%g", v);
        const ImVec2 size = text_size(fonts.small, label);
        text(draw, fonts.small, ImVec2(plot_left - 0.4f * f - size.x, y - 0.5f * size.y),
             kMutedText, label);
    }

    // Bars, side by side within each bin.
    const float bin_width = (plot_right - plot_left) / kQualityBins;
    const float inner = bin_width * 0.84f;
    const float bar_width = inner / float(std::max<std::size_t>(methods.size(), 1));
    for (std::size_t m = 0; m < methods.size(); ++m) {
        const ImU32 color = method_color_u32(methods[m].method);
        for (int b = 0; b < kQualityBins; ++b) {
            const double v = shares[m][std::size_t(b)];
            if (v <= 0.0) continue;
            const float x0 = plot_left + b * bin_width + 0.5f * (bin_width - inner) + m * bar_width;
            draw->AddRectFilled(ImVec2(x0, y_of(v)), ImVec2(x0 + bar_width, y_of(0.0)), color);
        }
    }
    // Means, as vertical lines in the series colour (darkened so they show over the bars).
    for (const PanelMethod& m : methods) {
        if (!m.metrics || m.metrics->triangles == 0) continue;
        const float x = std::round(x_of(m.metrics->quality.mean)) + 0.5f;
        const glm::vec3 c = method_color(m.method) * 0.7f;
        draw->AddLine(ImVec2(x, plot_top), ImVec2(x, plot_bottom), to_u32(c),
                      std::max(1.5f, 0.12f * f));
    }
    draw->AddLine(ImVec2(plot_left, plot_top), ImVec2(plot_left, plot_bottom), kAxis);

    // The q axis: optional colour strip, ticks, caption.
    float below = plot_bottom;
    if (colormap_axis) {
        const int slices = std::max(8, int(plot_right - plot_left) / 2);
        for (int i = 0; i < slices; ++i) {
            const float t0 = float(i) / slices, t1 = float(i + 1) / slices;
            const float value = scale.low + 0.5f * (t0 + t1) * (scale.high - scale.low);
            const float x0 = plot_left + t0 * (plot_right - plot_left);
            const float x1 = plot_left + t1 * (plot_right - plot_left);
            draw->AddRectFilled(ImVec2(x0, plot_bottom + 1),
                                ImVec2(x1 + 0.5f, plot_bottom + 1 + strip),
                                to_u32(measure_color(measure, value, threshold, scale)));
        }
        below += strip + 1;
    }
    // Fifths of [0, 1] for the shapes; quarters of a distance's range (0 on a tick).
    const bool distance = is_distance(measure);
    const int intervals = distance ? 4 : 5;
    for (int i = 0; i <= intervals; ++i) {
        const double v = scale.low + double(i) / intervals * (scale.high - scale.low);
        const float x = std::round(x_of(v));
        draw->AddLine(ImVec2(x, below), ImVec2(x, below + 0.3f * f), kAxis);
        const std::string label =
            distance ? format("%g", std::abs(v) < 1e-9 ? 0.0 : v) : format("%.1f", v);
        const ImVec2 size = text_size(fonts.small, label);
        text(draw, fonts.small, ImVec2(x - 0.5f * size.x, below + 0.35f * f), kMutedText, label);
    }
    // A distance's definition is in the legend's tooltip and the README: too long for the axis.
    const std::string caption =
        distance
            ? std::string(label_of(measure)) + " (" + std::string(scale.unit) + ")"
            : (measure == ShapeMeasure::Quality ? "quality q" : std::string(label_of(measure))) +
                  " = " + std::string(measure_definition(measure));
    const ImVec2 size = text_size(fonts.regular, caption);
    text(draw, fonts.regular, ImVec2(0.5f * (plot_left + plot_right - size.x), max.y - size.y),
         kText, caption);
}

namespace {

// One row of the metrics table. `net` tells a relaxed net from Marching Cubes, which has no
// relaxation to report.
struct Measure {
    const char* label;
    std::string (*value)(const MethodMetrics& m, bool net);
};

std::string yes_no(bool v) {
    return v ? "yes" : "no";
}

std::string accuracy_or_na(const MethodMetrics& m, double Accuracy::*field) {
    return m.accuracy ? format("%.3f", (*m.accuracy).*field) : std::string("n/a");
}

// The rows: size, quality, smoothness, the three accuracies (which points are measured is in
// the label) and the volume error, then what a finite-element mesher needs (the checks and the
// FE-readiness summary), then the relaxation's end.
const std::vector<Measure>& measures() {
    static const std::vector<Measure> list = {
        {"Triangles", [](const MethodMetrics& m, bool) { return format_count(m.triangles); }},
        {"Vertices", [](const MethodMetrics& m, bool) { return format_count(m.vertices); }},
        {"Mean quality",
         [](const MethodMetrics& m, bool) { return format("%.3f", m.quality.mean); }},
        {"Min quality", [](const MethodMetrics& m, bool) { return format("%.3f", m.quality.min); }},
        {"Mean radius ratio",
         [](const MethodMetrics& m, bool) { return format("%.3f", m.quality.radius_ratio_mean); }},
        {"Smallest angle", [](const MethodMetrics& m,
                              bool) { return format("%.1f\xC2\xB0", m.quality.min_angle_min); }},
        {"Slivers (q < 0.1)",
         [](const MethodMetrics& m, bool) {
             const double share = m.triangles ? double(m.quality.slivers) / double(m.triangles) : 0;
             return format("%.2f %%", 100.0 * share);
         }},
        {"Smoothness (rad)",
         [](const MethodMetrics& m, bool) { return format("%.4f", m.smoothness); }},
        {"Accuracy, vertices",
         [](const MethodMetrics& m, bool) { return accuracy_or_na(m, &Accuracy::vertices_mean); }},
        {"Accuracy, faces",
         [](const MethodMetrics& m, bool) { return accuracy_or_na(m, &Accuracy::faces_mean); }},
        {"Accuracy, surface",
         [](const MethodMetrics& m, bool) { return accuracy_or_na(m, &Accuracy::surface_mean); }},
        {"Distance to MC",
         [](const MethodMetrics& m, bool) {
             return m.to_marching_cubes ? format("%.3f", m.to_marching_cubes->surface_mean)
                                        : std::string("n/a");
         }},
        {"Volume error",
         [](const MethodMetrics& m, bool) {
             return m.volume_error ? format("%+.2f %%", 100.0 * *m.volume_error)
                                   : std::string("n/a");
         }},
        {"Degenerate",
         [](const MethodMetrics& m, bool) { return format_count(m.quality.degenerate); }},
        {"Closed / manifold",
         [](const MethodMetrics& m, bool) {
             return yes_no(m.topology.watertight) + " / " + yes_no(m.topology.manifold);
         }},
        {"Non-manifold e / v",
         [](const MethodMetrics& m, bool) {
             return format_count(m.topology.nonmanifold_edges) + " / " +
                    format_count(m.topology.nonmanifold_vertices);
         }},
        {"Self-intersections",
         [](const MethodMetrics& m, bool) { return format_count(m.self_intersections); }},
        {"FE-ready", [](const MethodMetrics& m, bool) { return yes_no(m.fe_ready); }},
        {"Min angle < 15\xC2\xB0",
         [](const MethodMetrics& m, bool) {
             return format("%.2f %%", 100.0 * m.fe.min_angle_below_15);
         }},
        {"Min angle < 30\xC2\xB0",
         [](const MethodMetrics& m, bool) {
             return format("%.2f %%", 100.0 * m.fe.min_angle_below_30);
         }},
        {"Max angle > 120\xC2\xB0",
         [](const MethodMetrics& m, bool) {
             return format("%.2f %%", 100.0 * m.fe.max_angle_above_120);
         }},
        {"Radius ratio range",
         [](const MethodMetrics& m, bool) {
             return format("%.2f", m.fe.radius_ratio_min) + "-" +
                    format("%.2f", m.fe.radius_ratio_max);
         }},
        {"Aspect ratio range",
         [](const MethodMetrics& m, bool) {
             return format("%.2f", m.fe.aspect_ratio_min) + "-" +
                    format("%.3g", m.fe.aspect_ratio_max);
         }},
        {"Euler characteristic",
         [](const MethodMetrics& m, bool) { return std::to_string(m.topology.euler); }},
        {"Iterations, conv.",
         [](const MethodMetrics& m, bool net) {
             return net ? std::to_string(m.iterations) + ", " + yes_no(m.converged)
                        : std::string("n/a");
         }},
        {"Last largest move",
         [](const MethodMetrics& m, bool net) {
             return net ? format("%.1e", m.final_max_move) : std::string("n/a");
         }},
    };
    return list;
}

void right_aligned(const std::string& s) {
    const float width = ImGui::CalcTextSize(s.c_str()).x;
    ImGui::SetCursorPosX(ImGui::GetCursorPosX() +
                         std::max(0.0f, ImGui::GetContentRegionAvail().x - width));
    ImGui::TextUnformatted(s.c_str());
}

} // namespace

float metrics_table_height(int column_groups, float font_px) {
    const int groups = std::max(1, column_groups);
    const int rows = int((measures().size() + std::size_t(groups) - 1) / std::size_t(groups)) + 1;
    // A row is a line of text plus the cell padding above and below; borders add a pixel.
    const float row = font_px + 2.0f * figure_cell_padding(font_px) + 1.0f;
    return float(rows) * row + 2.0f;
}

void metrics_table(const char* id, std::span<const PanelMethod> methods, int column_groups,
                   float width, const FigureFonts& fonts) {
    const int groups = std::max(1, column_groups);
    const int per_group = int(methods.size()) + 1;
    const ImGuiTableFlags flags = ImGuiTableFlags_RowBg | ImGuiTableFlags_BordersInnerH |
                                  ImGuiTableFlags_BordersOuterH | ImGuiTableFlags_NoSavedSettings |
                                  ImGuiTableFlags_SizingStretchProp;
    if (!ImGui::BeginTable(id, groups * per_group, flags, ImVec2(width, 0))) return;
    for (int g = 0; g < groups; ++g) {
        // The measures' names need more of a narrower group.
        ImGui::TableSetupColumn("measure", ImGuiTableColumnFlags_WidthStretch,
                                groups > 1 ? 2.0f : 1.55f);
        for (std::size_t m = 0; m < methods.size(); ++m)
            ImGui::TableSetupColumn(std::string(name_of(methods[m].method)).c_str(),
                                    ImGuiTableColumnFlags_WidthStretch, 1.0f);
    }
    // Header: the methods' names in bold with their colour swatch; in the current face when
    // two groups make the columns too narrow for the bold one.
    ImGui::TableNextRow(ImGuiTableRowFlags_Headers);
    ImGui::PushFont(groups > 1 ? ImGui::GetFont() : fonts.bold);
    for (int g = 0; g < groups; ++g) {
        for (std::size_t m = 0; m < methods.size(); ++m) {
            ImGui::TableSetColumnIndex(g * per_group + 1 + int(m));
            const std::string name = method_short_name(methods[m].method);
            const float swatch = std::round(0.65f * fonts.size);
            const float text_width =
                ImGui::CalcTextSize(name.c_str()).x + swatch + 0.3f * fonts.size;
            ImGui::SetCursorPosX(ImGui::GetCursorPosX() +
                                 std::max(0.0f, ImGui::GetContentRegionAvail().x - text_width));
            const ImVec2 p = ImGui::GetCursorScreenPos();
            const float y = p.y + 0.5f * (fonts.size - swatch);
            ImGui::GetWindowDrawList()->AddRectFilled(
                ImVec2(p.x, y), ImVec2(p.x + swatch, y + swatch),
                method_color_u32(methods[m].method), 0.15f * swatch);
            ImGui::SetCursorPosX(ImGui::GetCursorPosX() + swatch + 0.3f * fonts.size);
            ImGui::TextUnformatted(name.c_str());
        }
    }
    ImGui::PopFont();
    const std::vector<Measure>& list = measures();
    const std::size_t rows = (list.size() + std::size_t(groups) - 1) / std::size_t(groups);
    for (std::size_t r = 0; r < rows; ++r) {
        ImGui::TableNextRow();
        for (int g = 0; g < groups; ++g) {
            const std::size_t k = std::size_t(g) * rows + r;
            if (k >= list.size()) continue;
            ImGui::TableSetColumnIndex(g * per_group);
            ImGui::PushStyleColor(ImGuiCol_Text, kMutedText);
            ImGui::TextUnformatted(list[k].label);
            ImGui::PopStyleColor();
            for (std::size_t m = 0; m < methods.size(); ++m) {
                ImGui::TableSetColumnIndex(g * per_group + 1 + int(m));
                const bool net = methods[m].method != Method::MarchingCubes;
                right_aligned(methods[m].metrics ? list[k].value(*methods[m].metrics, net)
                                                 : std::string("n/a"));
            }
        }
    }
    ImGui::EndTable();
}

} // namespace snert::render
