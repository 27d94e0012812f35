// Convergence curves and the value histogram.
#include "plots.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <vector>

namespace snert::app {

namespace {

constexpr ImU32 kFrame = IM_COL32(200, 204, 212, 255);
constexpr ImU32 kPlotBackground = IM_COL32(255, 255, 255, 255);
constexpr ImU32 kText = IM_COL32(28, 30, 34, 255);
constexpr ImU32 kMuted = IM_COL32(100, 104, 112, 255);
constexpr ImU32 kMarker = IM_COL32(213, 94, 0, 255);     // same orange family as MC, but a line
constexpr ImU32 kReference = IM_COL32(230, 159, 0, 255); // Marching Cubes' series colour
constexpr ImU32 kIso = IM_COL32(213, 40, 40, 255);

std::string number(double v) {
    char text[32];
    const double a = std::abs(v);
    if (a == 0) return "0";
    if (a < 1e-3 || a >= 1e5)
        std::snprintf(text, sizeof text, "%.1e", v);
    else if (a < 0.1)
        std::snprintf(text, sizeof text, "%.4f", v);
    else
        std::snprintf(text, sizeof text, "%.3g", v);
    return text;
}

void dashed_line(ImDrawList* draw, ImVec2 a, ImVec2 b, ImU32 color, float dash) {
    const float length = std::hypot(b.x - a.x, b.y - a.y);
    if (length <= 0) return;
    const ImVec2 d((b.x - a.x) / length, (b.y - a.y) / length);
    for (float t = 0; t < length; t += 2 * dash) {
        const float e = std::min(t + dash, length);
        draw->AddLine(ImVec2(a.x + d.x * t, a.y + d.y * t), ImVec2(a.x + d.x * e, a.y + d.y * e),
                      color, 1.5f);
    }
}

// The widget's rectangle and whether the left button is held on it.
struct Area {
    ImVec2 min, max;
    bool pressed = false;
    bool hovered = false;
};

Area place(const char* id, ImVec2 size) {
    Area a;
    a.min = ImGui::GetCursorScreenPos();
    ImGui::InvisibleButton(id, size);
    a.max = ImVec2(a.min.x + size.x, a.min.y + size.y);
    a.pressed = ImGui::IsItemActive() && ImGui::IsMouseDown(ImGuiMouseButton_Left);
    a.hovered = ImGui::IsItemHovered();
    return a;
}

} // namespace

std::optional<int> convergence_plot(const char* id, const ConvergencePlot& plot, ImVec2 size,
                                    const render::FigureFonts& fonts) {
    const Area area = place(id, size);
    ImDrawList* draw = ImGui::GetWindowDrawList();
    const float f = fonts.size;
    ImFont* small = fonts.small;
    draw->AddText(fonts.bold, fonts.bold->FontSize, area.min, kText, plot.title.c_str());
    // The value at the iteration shown, right-aligned on the title line.
    if (plot.marker >= 0 && plot.marker < int(plot.values.size())) {
        const std::string value = number(plot.values[std::size_t(plot.marker)]);
        const float w =
            fonts.regular->CalcTextSizeA(fonts.regular->FontSize, 1e9f, 0, value.c_str()).x;
        draw->AddText(fonts.regular, fonts.regular->FontSize,
                      ImVec2(area.max.x - w - 0.4f * f, area.min.y), kMarker, value.c_str());
    }

    // Plot box: room for the title above and the axis labels left and below.
    const ImVec2 box_min(area.min.x + 3.6f * f, area.min.y + 1.5f * f);
    const ImVec2 box_max(area.max.x - 0.4f * f, area.max.y - 1.3f * f);
    if (box_max.x - box_min.x < 10 || box_max.y - box_min.y < 10) return std::nullopt;
    draw->AddRectFilled(box_min, box_max, kPlotBackground);
    draw->AddRect(box_min, box_max, kFrame);

    const int n = int(plot.values.size());
    const int first = std::min(plot.first_iteration, std::max(n - 1, 0));
    const int last = std::max(n - 1, first + 1);
    auto to_y_value = [&](float v) { return plot.log_scale ? std::log10(std::max(v, 1e-12f)) : v; };

    // Value range over the drawn values and the reference line.
    float lo = 1e30f, hi = -1e30f;
    for (int k = first; k < n; ++k) {
        const float v = plot.values[std::size_t(k)];
        if (!std::isfinite(v) || (plot.log_scale && v <= 0)) continue;
        lo = std::min(lo, to_y_value(v));
        hi = std::max(hi, to_y_value(v));
    }
    if (plot.reference && std::isfinite(*plot.reference) &&
        (!plot.log_scale || *plot.reference > 0)) {
        lo = std::min(lo, to_y_value(*plot.reference));
        hi = std::max(hi, to_y_value(*plot.reference));
    }
    const bool has_values = lo <= hi;
    if (!has_values) lo = 0, hi = 1;
    const bool non_negative = !plot.log_scale && lo >= 0;
    if (hi - lo < 1e-9f) {
        const float pad = std::max(std::abs(hi) * 0.05f, 1e-6f);
        lo -= pad;
        hi += pad;
    } else {
        const float pad = 0.06f * (hi - lo);
        lo -= pad;
        hi += pad;
    }
    if (non_negative) lo = std::max(lo, 0.0f); // no negative axis for a measure that cannot be
    auto x_of = [&](int k) {
        return box_min.x + (box_max.x - box_min.x) * float(k - first) / float(last - first);
    };
    auto y_of = [&](float v) {
        return box_max.y - (box_max.y - box_min.y) * (to_y_value(v) - lo) / (hi - lo);
    };
    auto unscaled = [&](float y) { return plot.log_scale ? std::pow(10.0f, y) : y; };

    // Axis labels: the value range at the left, the iteration range below.
    const std::string top = number(unscaled(hi)), bottom = number(unscaled(lo));
    const float label_x = area.min.x;
    draw->AddText(small, small->FontSize, ImVec2(label_x, box_min.y), kMuted, top.c_str());
    draw->AddText(small, small->FontSize, ImVec2(label_x, box_max.y - small->FontSize), kMuted,
                  bottom.c_str());
    const std::string left = std::to_string(first), right = std::to_string(last);
    draw->AddText(small, small->FontSize, ImVec2(box_min.x, box_max.y + 0.15f * f), kMuted,
                  left.c_str());
    const float right_width = small->CalcTextSizeA(small->FontSize, 1e9f, 0, right.c_str()).x;
    draw->AddText(small, small->FontSize, ImVec2(box_max.x - right_width, box_max.y + 0.15f * f),
                  kMuted, right.c_str());
    const char* axis = "iteration";
    const float axis_width = small->CalcTextSizeA(small->FontSize, 1e9f, 0, axis).x;
    draw->AddText(small, small->FontSize,
                  ImVec2(0.5f * (box_min.x + box_max.x - axis_width), box_max.y + 0.15f * f),
                  kMuted, axis);

    draw->PushClipRect(box_min, box_max, true);
    if (plot.reference && std::isfinite(*plot.reference) &&
        (!plot.log_scale || *plot.reference > 0)) {
        const float y = y_of(*plot.reference);
        dashed_line(draw, ImVec2(box_min.x, y), ImVec2(box_max.x, y), kReference, 0.4f * f);
        const std::string label = "MC " + number(*plot.reference);
        draw->AddText(small, small->FontSize, ImVec2(box_min.x + 0.3f * f, y - small->FontSize - 1),
                      kReference, label.c_str());
    }
    std::vector<ImVec2> points;
    for (int k = first; k < n; ++k) {
        const float v = plot.values[std::size_t(k)];
        if (!std::isfinite(v) || (plot.log_scale && v <= 0)) continue;
        points.emplace_back(x_of(k), y_of(v));
    }
    if (points.size() >= 2)
        draw->AddPolyline(points.data(), int(points.size()), plot.color, 0, 2.0f);
    if (points.size() == 1) draw->AddCircleFilled(points[0], 2.5f, plot.color);
    if (plot.marker >= first && plot.marker < n) {
        const float x = x_of(plot.marker);
        draw->AddLine(ImVec2(x, box_min.y), ImVec2(x, box_max.y), kMarker, 1.5f);
        const float v = plot.values[std::size_t(plot.marker)];
        if (std::isfinite(v) && (!plot.log_scale || v > 0))
            draw->AddCircleFilled(ImVec2(x, y_of(v)), 3.5f, kMarker);
    }
    draw->PopClipRect();

    // Hover: the value at the iteration under the mouse; press or drag: pick it.
    const ImVec2 mouse = ImGui::GetIO().MousePos;
    const float t = (mouse.x - box_min.x) / std::max(box_max.x - box_min.x, 1.0f);
    const int k = std::clamp(int(std::lround(float(first) + t * float(last - first))), first,
                             std::max(n - 1, first));
    if (area.hovered && n > 0 && k < n) {
        ImGui::BeginTooltip();
        ImGui::Text("iteration %d: %s", k, number(plot.values[std::size_t(k)]).c_str());
        if (!plot.hint.empty()) ImGui::TextDisabled("%s", plot.hint.c_str());
        ImGui::TextDisabled("click or drag to show an iteration");
        ImGui::EndTooltip();
    }
    if (area.pressed && n > 0) return k;
    return std::nullopt;
}

std::optional<float> value_histogram_plot(const char* id, const Histogram& histogram, float iso,
                                          float step, ImVec2 size,
                                          const render::FigureFonts& fonts) {
    const Area area = place(id, size);
    ImDrawList* draw = ImGui::GetWindowDrawList();
    draw->AddRectFilled(area.min, area.max, kPlotBackground);
    draw->AddRect(area.min, area.max, kFrame);
    const std::size_t bins = histogram.counts.size();
    // double: hi - lo can exceed the float range (core/volume_stats.h).
    const double range = double(histogram.hi) - double(histogram.lo);
    if (bins == 0) return std::nullopt;

    // Logarithmic heights: a CT's air and soft tissue peaks would hide everything else.
    float top = 0;
    for (const std::uint64_t c : histogram.counts) top = std::max(top, std::log1p(float(c)));
    const float inner_min_y = area.min.y + 2, inner_max_y = area.max.y - 1;
    const float bar = (area.max.x - area.min.x) / float(bins);
    for (std::size_t i = 0; i < bins; ++i) {
        const float h = top > 0 ? std::log1p(float(histogram.counts[i])) / top : 0;
        if (h <= 0) continue;
        const float x0 = area.min.x + bar * float(i), x1 = x0 + std::max(bar, 1.0f);
        draw->AddRectFilled(ImVec2(x0, inner_max_y - h * (inner_max_y - inner_min_y)),
                            ImVec2(x1, inner_max_y), IM_COL32(120, 130, 150, 255));
    }
    auto x_of = [&](float v) {
        return range > 0 ? area.min.x + float(double(area.max.x - area.min.x) *
                                              (double(v) - double(histogram.lo)) / range)
                         : area.min.x;
    };
    const float x = std::clamp(x_of(iso), area.min.x, area.max.x);
    draw->AddLine(ImVec2(x, area.min.y), ImVec2(x, area.max.y), kIso, 2.0f);
    ImFont* small = fonts.small;
    const std::string lo = number(histogram.lo), hi = number(histogram.hi);
    draw->AddText(small, small->FontSize, ImVec2(area.min.x + 2, area.min.y + 1), kMuted,
                  lo.c_str());
    const float hi_width = small->CalcTextSizeA(small->FontSize, 1e9f, 0, hi.c_str()).x;
    draw->AddText(small, small->FontSize, ImVec2(area.max.x - hi_width - 2, area.min.y + 1), kMuted,
                  hi.c_str());

    const ImVec2 mouse = ImGui::GetIO().MousePos;
    const float t =
        std::clamp((mouse.x - area.min.x) / std::max(area.max.x - area.min.x, 1.0f), 0.0f, 1.0f);
    // Rounded to the data's step: a click means "about here", not 40.87.
    const double raw = double(histogram.lo) + double(t) * range;
    const float value =
        step > 0 ? float(std::round(raw / double(step)) * double(step)) : float(raw);
    if (area.hovered) {
        ImGui::BeginTooltip();
        ImGui::Text("value %s", number(value).c_str());
        ImGui::TextDisabled("the volume's histogram (log counts); click to set the iso value");
        ImGui::EndTooltip();
    }
    if (area.pressed && range > 0) return value;
    return std::nullopt;
}

void compactness_plot(const char* id, const CompactnessPlot& plot, ImVec2 size,
                      const render::FigureFonts& fonts) {
    const Area area = place(id, size);
    if (area.hovered && !plot.hint.empty()) ImGui::SetTooltip("%s", plot.hint.c_str());
    ImDrawList* draw = ImGui::GetWindowDrawList();
    const float f = fonts.size;
    ImFont* small = fonts.small;
    draw->AddText(fonts.bold, fonts.bold->FontSize, area.min, kText, plot.title.c_str());
    // The legend: each series' label in its colour, right-aligned on the title line.
    float legend_x = area.max.x - 0.6f * f;
    for (auto s = plot.series.rbegin(); s != plot.series.rend(); ++s) {
        if (s->label.empty()) continue;
        const float w = small->CalcTextSizeA(small->FontSize, 1e9f, 0, s->label.c_str()).x;
        legend_x -= w;
        draw->AddText(small, small->FontSize, ImVec2(legend_x, area.min.y + 0.1f * f), s->color,
                      s->label.c_str());
        legend_x -= 0.8f * f;
    }
    const ImVec2 box_min(area.min.x + 3.6f * f, area.min.y + 1.5f * f);
    const ImVec2 box_max(area.max.x - 0.6f * f, area.max.y - 1.3f * f);
    if (box_max.x - box_min.x < 10 || box_max.y - box_min.y < 10) return;
    draw->AddRectFilled(box_min, box_max, kPlotBackground);
    draw->AddRect(box_min, box_max, kFrame);

    double share_lo = 1.0, share_hi = 1.0;
    float lo = 1e30f, hi = -1e30f;
    for (const CompactnessSeries& s : plot.series)
        for (const CompactnessSeries::Point& p : s.points) {
            if (!(p.share > 0) || !std::isfinite(p.value)) continue;
            share_lo = std::min(share_lo, p.share);
            share_hi = std::max(share_hi, p.share);
            lo = std::min(lo, p.value);
            hi = std::max(hi, p.value);
        }
    if (lo > hi) lo = 0, hi = 1;
    const float pad = hi - lo < 1e-9f ? std::max(std::abs(hi) * 0.05f, 1e-6f) : 0.06f * (hi - lo);
    lo = std::max(lo - pad, lo >= 0 ? 0.0f : lo - pad);
    hi += pad;
    const double log_lo = std::log(share_lo),
                 log_span = std::max(std::log(share_hi) - log_lo, 1e-9);
    auto x_of = [&](double share) {
        return box_min.x + (box_max.x - box_min.x) * float((std::log(share) - log_lo) / log_span);
    };
    auto y_of = [&](float v) { return box_max.y - (box_max.y - box_min.y) * (v - lo) / (hi - lo); };

    const std::string top = number(hi), bottom = number(lo);
    draw->AddText(small, small->FontSize, ImVec2(area.min.x, box_min.y), kMuted, top.c_str());
    draw->AddText(small, small->FontSize, ImVec2(area.min.x, box_max.y - small->FontSize), kMuted,
                  bottom.c_str());
    // The levels on the axis below, as percentages.
    for (const CompactnessSeries& s : plot.series) {
        for (const CompactnessSeries::Point& p : s.points) {
            char label[16];
            std::snprintf(label, sizeof label, "%g %%", 100.0 * p.share);
            const float w = small->CalcTextSizeA(small->FontSize, 1e9f, 0, label).x;
            const float x = std::clamp(x_of(p.share) - 0.5f * w, box_min.x, box_max.x - w);
            draw->AddText(small, small->FontSize, ImVec2(x, box_max.y + 0.15f * f), kMuted, label);
        }
        break; // the levels are the same for every series
    }
    draw->PushClipRect(box_min, box_max, true);
    for (const CompactnessSeries& s : plot.series) {
        std::vector<ImVec2> line;
        for (const CompactnessSeries::Point& p : s.points)
            if (p.share > 0 && std::isfinite(p.value))
                line.push_back(ImVec2(x_of(p.share), y_of(p.value)));
        std::sort(line.begin(), line.end(), [](ImVec2 a, ImVec2 b) { return a.x < b.x; });
        if (line.size() > 1) draw->AddPolyline(line.data(), int(line.size()), s.color, 0, 2.0f);
        for (const ImVec2 q : line) draw->AddCircleFilled(q, 0.22f * f, s.color);
    }
    draw->PopClipRect();
}

} // namespace snert::app
