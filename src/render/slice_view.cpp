// The slice view and its legend, drawn with ImGui's draw lists (see slice_view.h).
#include "slice_view.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include "panels.h"

namespace snert::render {

namespace {

// The colours of everything the view draws; the legend uses the same table.
constexpr ImU32 kCellBorder = IM_COL32(110, 170, 255, 150);
constexpr ImU32 kSurfaceCell = IM_COL32(190, 110, 255, 80);
constexpr ImU32 kVoxelInside = IM_COL32(20, 20, 20, 255);
constexpr ImU32 kVoxelOutline = IM_COL32(255, 255, 255, 230);
// As slice_pixels blends kSegmentationColour over the grey.
constexpr ImU32 kSegmentation = IM_COL32(77, 217, 89, 110);
constexpr ImU32 kCellBox = IM_COL32(255, 255, 255, 255);
constexpr ImU32 kCrosshair = IM_COL32(255, 230, 0, 200);
constexpr ImU32 kLegendText = IM_COL32(30, 32, 36, 255);
constexpr ImU32 kMutedText = IM_COL32(88, 92, 100, 255);

struct Arrow {
    const char* symbol; // as the paper writes it
    const char* meaning;
    ImU32 colour;
};
// a, a_p, d g, the sum, c by ray-box, c by clipping.
constexpr Arrow kArrows[] = {
    {"a", "averaging vector (eq. 1)", IM_COL32(40, 90, 230, 255)},
    {"a_p", "a projected on the plane normal to g (eq. 5)", IM_COL32(0, 185, 215, 255)},
    {"d g", "gradient step to the iso-surface (eqs. 3-4)", IM_COL32(225, 30, 30, 255)},
    {"sum", "the unconstrained move, weighted sum", IM_COL32(170, 60, 210, 255)},
    {"c ray-box", "constrained move: shortened along itself (eq. 2 / 6)",
     IM_COL32(30, 165, 70, 255)},
    {"c clip", "constrained move: x, y, z clipped (original SurfaceNet)",
     IM_COL32(245, 145, 0, 255)},
};

std::string format_vec(glm::vec3 v) {
    char text[96];
    std::snprintf(text, sizeof text, "(%+.3f, %+.3f, %+.3f)  |%.3f|", double(v.x), double(v.y),
                  double(v.z), double(glm::length(v)));
    return text;
}

void draw_arrow(ImDrawList* draw, ImVec2 from, ImVec2 to, ImU32 colour, float thickness) {
    const float dx = to.x - from.x, dy = to.y - from.y;
    const float length = std::sqrt(dx * dx + dy * dy);
    if (length < 0.5f) {
        draw->AddCircleFilled(from, 1.5f * thickness, colour);
        return;
    }
    const float ux = dx / length, uy = dy / length;
    const float head = std::min(4.5f * thickness, 0.45f * length);
    const ImVec2 base(to.x - ux * head, to.y - uy * head);
    draw->AddLine(from, base, colour, thickness);
    const float w = 0.5f * head;
    draw->AddTriangleFilled(to, ImVec2(base.x - uy * w, base.y + ux * w),
                            ImVec2(base.x + uy * w, base.y - ux * w), colour);
}

// The 3D index-space vector v at p, projected on the slice: its screen end point.
ImVec2 screen_end(const SliceMapping& m, SliceAxis axis, glm::vec3 p, glm::vec3 v) {
    return m.to_screen(index_to_slice(axis, p + v));
}

void dashed_line(ImDrawList* draw, ImVec2 a, ImVec2 b, ImU32 colour, float thickness, float dash) {
    const float dx = b.x - a.x, dy = b.y - a.y;
    const float length = std::sqrt(dx * dx + dy * dy);
    const int n = std::max(1, int(length / dash));
    for (int i = 0; i < n; i += 2) {
        const float t0 = float(i) / float(n), t1 = float(std::min(i + 1, n)) / float(n);
        draw->AddLine(ImVec2(a.x + t0 * dx, a.y + t0 * dy), ImVec2(a.x + t1 * dx, a.y + t1 * dy),
                      colour, thickness);
    }
}

} // namespace

std::string segmentation_legend(const Source& source, float iso) {
    if (source.mask && source.spec.label) {
        std::string text = "label " + std::to_string(*source.spec.label);
        for (const LabelEntry& e : source.labels_present)
            if (e.value == *source.spec.label && !e.name.empty()) text += " " + e.name;
        return text + " (label map)";
    }
    char text[64];
    std::snprintf(text, sizeof text, "inside at iso %g", double(iso));
    return text;
}

SliceWindow whole_slice(glm::ivec2 size) {
    return {glm::vec2(-0.5f), glm::vec2(size)};
}

SliceWindow window_around(glm::vec2 centre, float cells) {
    return {centre - 0.5f * cells, glm::vec2(cells)};
}

SliceMapping map_slice(ImVec2 min, ImVec2 max, const SliceScene& scene, const SliceWindow& window) {
    const float w = std::max(1.0f, max.x - min.x), h = std::max(1.0f, max.y - min.y);
    const glm::vec2 spacing = glm::max(scene.spacing, glm::vec2(1e-6f));
    const glm::vec2 world = window.size * spacing / std::min(spacing.x, spacing.y);
    const float pixels = std::min(w / world.x, h / world.y); // per smallest spacing
    SliceMapping m;
    m.scale = pixels * spacing / std::min(spacing.x, spacing.y);
    const bool up = scene.plane.axis != SliceAxis::Axial;
    const ImVec2 centre(0.5f * (min.x + max.x), 0.5f * (min.y + max.y));
    const glm::vec2 mid = window.min + 0.5f * window.size;
    if (up) m.scale.y = -m.scale.y;
    m.origin = ImVec2(centre.x - mid.x * m.scale.x, centre.y - mid.y * m.scale.y);
    return m;
}

void draw_slice_view(ImDrawList* draw, ImVec2 min, ImVec2 max, const SliceScene& scene,
                     const SliceWindow& window, const FigureFonts& fonts) {
    draw->AddRectFilled(min, max, IM_COL32(24, 26, 30, 255));
    draw->PushClipRect(min, max, true);
    const SliceMapping m = map_slice(min, max, scene, window);
    const SliceAxis axis = scene.plane.axis;
    if (scene.image != nullptr)
        draw->AddImage(scene.image, m.to_screen(glm::vec2(-0.5f)),
                       m.to_screen(glm::vec2(scene.size) - 0.5f));

    // The visible samples.
    const glm::vec2 a = m.to_slice(min), b = m.to_slice(max);
    const glm::vec2 lo = glm::max(glm::floor(glm::min(a, b)), glm::vec2(0.0f));
    const glm::vec2 hi = glm::min(glm::ceil(glm::max(a, b)), glm::vec2(scene.size - 1));
    const float pixels = m.pixels_per_sample();
    const bool cells = pixels >= kCellDetailPixels;
    const float line = std::clamp(pixels / 40.0f, 1.5f, 3.0f);

    if (cells) {
        // Fig. 1: surface cells, cell borders through the voxel centres, the centres as dots.
        for (const glm::ivec2 c : scene.net.layer.surface_cells)
            draw->AddRectFilled(m.to_screen(glm::vec2(c)), m.to_screen(glm::vec2(c) + 1.0f),
                                kSurfaceCell);
        for (float u = lo.x; u <= hi.x; ++u)
            draw->AddLine(m.to_screen({u, lo.y}), m.to_screen({u, hi.y}), kCellBorder, 1.0f);
        for (float v = lo.y; v <= hi.y; ++v)
            draw->AddLine(m.to_screen({lo.x, v}), m.to_screen({hi.x, v}), kCellBorder, 1.0f);
        const float dot = std::clamp(0.07f * pixels, 2.5f, 6.0f);
        for (int v = int(lo.y); v <= int(hi.y); ++v)
            for (int u = int(lo.x); u <= int(hi.x); ++u) {
                const ImVec2 p = m.to_screen({float(u), float(v)});
                const std::size_t i = std::size_t(v) * std::size_t(scene.size.x) + std::size_t(u);
                const bool inside = i < scene.inside.size() && scene.inside[i] != 0;
                draw->AddCircleFilled(p, dot + 1.0f, kVoxelOutline);
                draw->AddCircleFilled(p, dot, inside ? kVoxelInside : kVoxelOutline);
                if (!inside) draw->AddCircle(p, dot, kVoxelInside, 0, 1.0f);
            }
    }

    // The meshes' cross-sections; zoomed in, the net is drawn as its nodes and links instead.
    for (const SliceContour& c : scene.contours) {
        if (cells && c.method != Method::MarchingCubes && scene.net.net != nullptr) continue;
        const ImU32 colour = method_color_u32(c.method);
        const float thickness = c.method == Method::MarchingCubes ? line + 0.5f : line;
        for (const Segment2& s : c.segments)
            draw->AddLine(m.to_screen(s.a), m.to_screen(s.b), colour, thickness);
    }

    if (cells && scene.net.net != nullptr && !scene.net.positions.empty()) {
        const ImU32 colour = method_color_u32(scene.net.method);
        const auto& P = scene.net.positions;
        for (const auto& l : scene.net.layer.links)
            draw->AddLine(m.to_screen(index_to_slice(axis, P[l[0]])),
                          m.to_screen(index_to_slice(axis, P[l[1]])), colour, line);
        const float r = std::clamp(0.09f * pixels, 3.5f, 9.0f);
        for (const std::uint32_t i : scene.net.layer.nodes) {
            const ImVec2 p = m.to_screen(index_to_slice(axis, P[i]));
            draw->AddCircleFilled(p, r, IM_COL32(255, 255, 255, 255));
            draw->AddCircle(p, r, colour, 0, line);
        }
    }

    if (const NodeInspection* n = scene.inspection) {
        // The cell box the constraint keeps the node in, then the arrows of its move.
        const ImVec2 p0 = m.to_screen(index_to_slice(axis, n->box.lo));
        const ImVec2 p1 = m.to_screen(index_to_slice(axis, n->box.hi));
        draw->AddRect(ImVec2(std::min(p0.x, p1.x), std::min(p0.y, p1.y)),
                      ImVec2(std::max(p0.x, p1.x), std::max(p0.y, p1.y)), IM_COL32(0, 0, 0, 255),
                      0.0f, 0, line + 2.0f);
        draw->AddRect(ImVec2(std::min(p0.x, p1.x), std::min(p0.y, p1.y)),
                      ImVec2(std::max(p0.x, p1.x), std::max(p0.y, p1.y)), kCellBox, 0.0f, 0, line);
        const float t = std::max(2.0f, line);
        for (const SubStepInspection& s : n->sub_steps) {
            const ImVec2 from = m.to_screen(index_to_slice(axis, s.from));
            const MoveTerms& v = s.terms;
            const glm::vec3 vectors[] = {
                v.a, v.a_p, v.dg, v.move, s.ray_box - s.from, s.clip - s.from};
            // The sum dashed; clipping under ray-box and wider, so both show where they agree.
            for (const int k : {0, 1, 2, 3, 5, 4}) {
                if (vectors[k] == glm::vec3(0.0f)) continue;
                const ImVec2 to = screen_end(m, axis, s.from, vectors[k]);
                const float width = k == 5 ? 2.2f * t : t;
                if (k == 3) dashed_line(draw, from, to, kArrows[k].colour, width, 6.0f);
                draw_arrow(draw,
                           k == 3 ? ImVec2(from.x + 0.8f * (to.x - from.x),
                                           from.y + 0.8f * (to.y - from.y))
                                  : from,
                           to, kArrows[k].colour, width);
            }
            draw->AddCircleFilled(from, t + 2.0f, IM_COL32(0, 0, 0, 255));
        }
        // Where the relaxation put the node: a cross.
        const ImVec2 e = m.to_screen(index_to_slice(axis, n->after));
        const float x = 2.5f * t;
        draw->AddLine(ImVec2(e.x - x, e.y - x), ImVec2(e.x + x, e.y + x), IM_COL32(0, 0, 0, 255),
                      t);
        draw->AddLine(ImVec2(e.x - x, e.y + x), ImVec2(e.x + x, e.y - x), IM_COL32(0, 0, 0, 255),
                      t);
    }

    if (scene.crosshair) {
        const ImVec2 c = m.to_screen(*scene.crosshair);
        draw->AddLine(ImVec2(min.x, c.y), ImVec2(max.x, c.y), kCrosshair, 1.0f);
        draw->AddLine(ImVec2(c.x, min.y), ImVec2(c.x, max.y), kCrosshair, 1.0f);
    }

    // Which slice, and which way the axes run.
    const glm::ivec2 axes = plane_axes(axis);
    const char* names = "xyz";
    char label[128];
    std::snprintf(label, sizeof label, "%s %d  \xC2\xB7  %c to the right, %c %s",
                  std::string(name_of(axis)).c_str(), scene.plane.index, names[axes.x],
                  names[axes.y], axis == SliceAxis::Axial ? "down" : "up");
    ImFont* font = fonts.small != nullptr ? fonts.small : ImGui::GetFont();
    const ImVec2 size = font->CalcTextSizeA(font->FontSize, 1e9f, 0.0f, label);
    const float pad = 0.3f * font->FontSize;
    draw->AddRectFilled(ImVec2(min.x, min.y),
                        ImVec2(min.x + size.x + 2 * pad, min.y + size.y + 2 * pad),
                        IM_COL32(0, 0, 0, 170));
    draw->AddText(font, font->FontSize, ImVec2(min.x + pad, min.y + pad),
                  IM_COL32(255, 255, 255, 255), label);
    draw->PopClipRect();
}

float draw_slice_legend(ImDrawList* draw, ImVec2 min, float width, const SliceScene& scene,
                        bool cells_shown, const FigureFonts& fonts) {
    ImFont* regular = fonts.regular != nullptr ? fonts.regular : ImGui::GetFont();
    ImFont* bold = fonts.bold != nullptr ? fonts.bold : regular;
    ImFont* small = fonts.small != nullptr ? fonts.small : regular;
    const float f = regular->FontSize;
    const float swatch = 1.8f * f;
    const float row = 1.35f * f;
    float y = min.y;
    auto text = [&](ImFont* font, float x, const std::string& s, ImU32 colour) {
        draw->AddText(font, font->FontSize, ImVec2(x, y), colour, s.c_str(), nullptr,
                      width - (x - min.x));
    };
    auto heading = [&](const std::string& s) {
        text(bold, min.x, s, kLegendText);
        y += row;
    };
    // One legend row: a swatch drawn by `icon` in [x, x + swatch] at the row's middle.
    auto entry = [&](const std::string& label, auto icon) {
        const float mid = y + 0.5f * f + 1.0f;
        icon(ImVec2(min.x, mid), ImVec2(min.x + swatch, mid));
        const ImVec2 size =
            regular->CalcTextSizeA(f, 1e9f, width - swatch - 0.6f * f, label.c_str());
        text(regular, min.x + swatch + 0.6f * f, label, kLegendText);
        y += std::max(row, size.y + 0.35f * f);
    };
    auto line_icon = [&](ImU32 colour, float thickness) {
        return [=](ImVec2 a, ImVec2 b) { draw->AddLine(a, b, colour, thickness); };
    };

    heading("Legend");
    for (const SliceContour& c : scene.contours) {
        if (cells_shown && c.method != Method::MarchingCubes && scene.net.net != nullptr) continue;
        entry(std::string(label_of(c.method)) + " cross-section",
              line_icon(method_color_u32(c.method), 3.0f));
    }
    if (!scene.inside.empty())
        entry(scene.segmentation, [&](ImVec2 a, ImVec2 b) {
            draw->AddRectFilled(ImVec2(a.x, a.y - 0.4f * f), ImVec2(b.x, b.y + 0.4f * f),
                                kSegmentation);
        });
    if (cells_shown) {
        if (scene.net.net != nullptr) {
            const ImU32 c = method_color_u32(scene.net.method);
            entry(std::string(label_of(scene.net.method)) +
                      " nodes and links of the cells between planes " +
                      std::to_string(scene.net.layer.layer) + " and " +
                      std::to_string(scene.net.layer.layer + 1) + " (projected)",
                  [&](ImVec2 a, ImVec2 b) {
                      draw->AddLine(a, b, c, 2.5f);
                      const ImVec2 mid(0.5f * (a.x + b.x), a.y);
                      draw->AddCircleFilled(mid, 0.3f * f, IM_COL32(255, 255, 255, 255));
                      draw->AddCircle(mid, 0.3f * f, c, 0, 2.0f);
                  });
        }
        entry("surface cell (holds a node)", [&](ImVec2 a, ImVec2 b) {
            draw->AddRectFilled(ImVec2(a.x, a.y - 0.4f * f), ImVec2(b.x, b.y + 0.4f * f),
                                IM_COL32(60, 60, 60, 255));
            draw->AddRectFilled(ImVec2(a.x, a.y - 0.4f * f), ImVec2(b.x, b.y + 0.4f * f),
                                kSurfaceCell);
        });
        entry("cell border (between voxel centres)", line_icon(kCellBorder, 2.0f));
        entry("voxel centre: inside / outside", [&](ImVec2 a, ImVec2 b) {
            const float r = 0.25f * f;
            const ImVec2 p(a.x + 0.25f * (b.x - a.x), a.y), q(a.x + 0.75f * (b.x - a.x), a.y);
            draw->AddCircleFilled(p, r, kVoxelInside);
            draw->AddCircleFilled(q, r, kVoxelOutline);
            draw->AddCircle(q, r, kVoxelInside, 0, 1.0f);
        });
    }
    if (scene.crosshair) entry("crosshair (the picked point)", line_icon(kCrosshair, 2.0f));

    const NodeInspection* n = scene.inspection;
    if (n == nullptr) return y - min.y;
    y += 0.5f * f;
    heading("Node " + std::to_string(n->node) + ", cell (" + std::to_string(n->cell.x) + ", " +
            std::to_string(n->cell.y) + ", " + std::to_string(n->cell.z) + "), iteration " +
            std::to_string(n->iteration));
    entry("the node's cell box (the constraint)", [&](ImVec2 a, ImVec2 b) {
        draw->AddRect(ImVec2(a.x, a.y - 0.45f * f), ImVec2(b.x, b.y + 0.45f * f),
                      IM_COL32(0, 0, 0, 255), 0.0f, 0, 2.0f);
    });
    for (const Arrow& arrow : kArrows)
        entry(std::string(arrow.symbol) + ": " + arrow.meaning, [&](ImVec2 a, ImVec2 b) {
            if (&arrow == &kArrows[3]) dashed_line(draw, a, b, arrow.colour, 2.5f, 4.0f);
            draw_arrow(draw, &arrow == &kArrows[3] ? ImVec2(a.x + 0.6f * (b.x - a.x), a.y) : a, b,
                       arrow.colour, 2.5f);
        });
    entry("where the relaxation put the node", [&](ImVec2 a, ImVec2 b) {
        const ImVec2 c(0.5f * (a.x + b.x), a.y);
        const float x = 0.3f * f;
        draw->AddLine(ImVec2(c.x - x, c.y - x), ImVec2(c.x + x, c.y + x), IM_COL32(0, 0, 0, 255),
                      2.0f);
        draw->AddLine(ImVec2(c.x - x, c.y + x), ImVec2(c.x + x, c.y - x), IM_COL32(0, 0, 0, 255),
                      2.0f);
    });
    {
        const char* note = "Arrows: projections on the slice, true length. Values: index space "
                           "(voxels), |length|.";
        text(small, min.x, note, kMutedText);
        y += small->CalcTextSizeA(small->FontSize, 1e9f, width, note).y + 0.3f * small->FontSize;
    }

    const float vf = small->FontSize;
    auto value = [&](const std::string& name, const std::string& v) {
        draw->AddText(small, vf, ImVec2(min.x, y), kLegendText, name.c_str());
        draw->AddText(small, vf, ImVec2(min.x + 5.5f * vf, y), kLegendText, v.c_str());
        y += 1.25f * vf;
    };
    value("p", format_vec(n->before));
    for (std::size_t s = 0; s < n->sub_steps.size(); ++s) {
        const SubStepInspection& sub = n->sub_steps[s];
        if (n->sub_steps.size() > 1) {
            y += 0.3f * vf;
            text(bold, min.x,
                 std::string(s == 0 ? "first" : "second") + " sub-step (" +
                     (sub.sub_step.smoothing ? "smoothing" : "gradient") + ")",
                 kLegendText);
            y += row;
        }
        const MoveTerms& t = sub.terms;
        value("a", format_vec(t.a));
        value("a_p", format_vec(t.a_p));
        char d[64];
        std::snprintf(d, sizeof d, "%.3f", double(t.d));
        value("g", format_vec(t.g));
        value("d", d);
        value("d g", format_vec(t.dg));
        if (t.relief != glm::vec3(0.0f)) value("relief", format_vec(t.relief));
        value("sum", format_vec(t.move));
        value("c ray-box", format_vec(sub.ray_box - sub.from));
        value("c clip", format_vec(sub.clip - sub.from));
    }
    value("moved", format_vec(n->after - n->before));
    if (n->damping < 1.0f) {
        char d[64];
        std::snprintf(d, sizeof d, "x %.3f", double(n->damping));
        value("damping", d);
    }
    if (n->shortened) {
        text(small, min.x, "the mesh guard shortened this move", kMutedText);
        y += 1.25f * vf;
    }
    return y - min.y;
}

std::optional<std::uint32_t> pick_slice_node(const SliceScene& scene, const SliceMapping& mapping,
                                             ImVec2 point, float radius) {
    std::optional<std::uint32_t> best;
    float best_d2 = radius * radius;
    for (const std::uint32_t i : scene.net.layer.nodes) {
        if (i >= scene.net.positions.size()) continue;
        const ImVec2 p =
            mapping.to_screen(index_to_slice(scene.plane.axis, scene.net.positions[i]));
        const float d2 = (p.x - point.x) * (p.x - point.x) + (p.y - point.y) * (p.y - point.y);
        if (d2 <= best_d2) best_d2 = d2, best = i;
    }
    return best;
}

} // namespace snert::render
