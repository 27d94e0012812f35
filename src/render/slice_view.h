// The slice view: one slice of the volume with window/level, the segmentation over it, and the
// cross-sections of both meshes as curves in their method colours. Zoomed in far enough it
// becomes the paper's Fig. 1: voxel centres as dots (filled inside the object), cell borders,
// the surface cells shaded, the net's nodes of those cells as circles and their links as lines,
// Marching Cubes' contour for comparison. With a node inspection it draws the node's cell box
// and the vectors of its move as arrows (eqs. 1-6), projected on the slice.
//
// Drawn with an ImDrawList, so `snert render --slice` (slice_figure.h) and the app's slice view
// are the same code. Needs a current ImGui context whose atlas holds the FigureFonts.
#pragma once

#include <optional>
#include <span>
#include <string>
#include <vector>

#include <glm/glm.hpp>
#include <imgui.h>

#include "core/names.h"
#include "core/node_inspection.h"
#include "core/slice.h"
#include "fonts.h"
#include "io/source.h"

namespace snert::render {

struct SliceContour {
    Method method = Method::MarchingCubes;
    std::vector<Segment2> segments; // slice coordinates
};

// The net's part in the slice (Fig. 1) at one iteration.
struct SliceNetView {
    Method method = Method::Snert;
    const SurfaceNet* net = nullptr;      // not owned; null: no net drawn
    std::span<const glm::vec3> positions; // the iteration's positions, one per node
    SliceNet layer;
};

struct SliceScene {
    SlicePlane plane;
    glm::ivec2 size{0};               // samples along u and v
    glm::vec2 spacing{1.0f};          // world distance between samples along u and v
    ImTextureID image = nullptr;      // the slice's pixels (slice_pixels, SliceTexture)
    std::vector<std::uint8_t> inside; // per slice sample (0/1), for the voxel dots; may be empty
    std::string segmentation = "segmentation (inside)"; // its legend entry (segmentation_legend)
    std::vector<SliceContour> contours;                 // Marching Cubes first
    SliceNetView net;
    const NodeInspection* inspection = nullptr; // not owned; the node's last move
    std::optional<glm::vec2> crosshair;         // slice coordinates
};

// The legend entry of a source's segmentation: "label 5 liver (label map)" for a label's mask,
// else "inside at iso V".
std::string segmentation_legend(const Source& source, float iso);

// The part of the slice shown: u in [min.x, min.x + size.x], v likewise (sample u covers
// [u - 0.5, u + 0.5]).
struct SliceWindow {
    glm::vec2 min{0.0f};
    glm::vec2 size{1.0f};
};
SliceWindow whole_slice(glm::ivec2 size);
// A window of `cells` x `cells` around a slice point (the node inspection's default).
SliceWindow window_around(glm::vec2 centre, float cells);

// Slice coordinates <-> screen pixels in a rectangle: the window fitted with the samples'
// aspect (spacing), centred; v grows downwards on the axial slice (image rows) and upwards on
// the others (z up).
struct SliceMapping {
    ImVec2 origin;         // screen point of slice point (0, 0)
    glm::vec2 scale{1.0f}; // pixels per sample along u and v (signed: negative v is upwards)
    ImVec2 to_screen(glm::vec2 uv) const {
        return {origin.x + uv.x * scale.x, origin.y + uv.y * scale.y};
    }
    glm::vec2 to_slice(ImVec2 p) const {
        return {(p.x - origin.x) / scale.x, (p.y - origin.y) / scale.y};
    }
    float pixels_per_sample() const { return std::min(std::abs(scale.x), std::abs(scale.y)); }
};
SliceMapping map_slice(ImVec2 min, ImVec2 max, const SliceScene& scene, const SliceWindow& window);

// From this many pixels per sample on, the view draws the cells (Fig. 1).
inline constexpr float kCellDetailPixels = 14.0f;

void draw_slice_view(ImDrawList* draw, ImVec2 min, ImVec2 max, const SliceScene& scene,
                     const SliceWindow& window, const FigureFonts& fonts);

// The legend of what draw_slice_view drew (every colour, line and arrow), then the node
// inspection's values, top-down from `min`; returns the height used.
float draw_slice_legend(ImDrawList* draw, ImVec2 min, float width, const SliceScene& scene,
                        bool cells_shown, const FigureFonts& fonts);

// The nearest node of the net's layer to a screen point within `radius` pixels, or nothing.
std::optional<std::uint32_t> pick_slice_node(const SliceScene& scene, const SliceMapping& mapping,
                                             ImVec2 point, float radius);

} // namespace snert::render
