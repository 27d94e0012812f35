// The app's slice view (beside the 3D views): one slice of the volume with window/level, the
// segmentation, both meshes' cross-sections and, zoomed in, the net's cells and nodes (the
// paper's Fig. 1); a click on a node takes its move at the shown iteration apart (core's node
// inspector) in the panel beside it. The drawing is render/slice_view.h, the same as
// `snert render --slice`.
//
// Mouse: wheel zooms about the pointer, left-drag pans, a left click picks a node (or puts the
// crosshair), right-drag sets window (horizontal) and level (vertical), double-click shows the
// whole slice. PageUp / PageDown step through the slices.
#pragma once

#include <cstdint>
#include <future>
#include <memory>
#include <optional>
#include <stop_token>
#include <vector>

#include <glm/glm.hpp>
#include <imgui.h>

#include "core/node_inspection.h"
#include "core/slice.h"
#include "core/window_level.h"
#include "job_results.h"
#include "render/fonts.h"
#include "render/slice_texture.h"
#include "render/slice_view.h"

namespace snert::app {

class SlicePanel {
  public:
    SlicePanel();
    ~SlicePanel();
    SlicePanel(const SlicePanel&) = delete;
    SlicePanel& operator=(const SlicePanel&) = delete;

    // Draws the controls, the view and its legend in [min, max] (screen pixels) of the current
    // window and handles the mouse over the view. `iteration`: the one the net's view shows.
    void draw(const JobResults& results, InsideIs inside, int iteration,
              const render::FigureFonts& fonts, ImVec2 min, ImVec2 max);
    void step_slice(int delta); // PageUp / PageDown
    // Shows an index-space point picked elsewhere (a 3D view): the slice through its nearest
    // sample plane, the crosshair on it, and the window moved to hold it.
    void show_point(glm::vec3 index_point);
    // Picks `node` (of cell `cell`, at `position`, index space) as a click in a 3D view does:
    // the slice through its cell's layer, the node inspected.
    void show_node(std::uint32_t node, glm::ivec3 cell, glm::vec3 position);
    // The picked point (index space) for the 3D views' crosshair; empty: none.
    std::optional<glm::vec3> crosshair() const;
    std::optional<std::uint32_t> picked_node() const { return node_; }
    const std::optional<NodeInspection>& inspection() const { return inspection_; }
    // The picked node's positions (index space) at iterations 0, 1, ..., for the 3D view.
    const std::vector<glm::vec3>& node_path() const { return path_; }

    // What the background task hands back.
    struct Inspected {
        NodeInspection inspection;
        std::vector<glm::vec3> path;
    };
    SlicePlane plane() const { return plane_; }
    // What the last frame drew, and where (tests click on nodes with these).
    const render::SliceScene& scene() const { return scene_; }
    const render::SliceMapping& mapping() const { return mapping_; }

  private:
    void update_volume(const JobResults& results, InsideIs inside);
    void update_net(const JobResults& results, int iteration);
    void handle_mouse(const render::SliceMapping& mapping, ImVec2 min, ImVec2 max, bool clicked);

    // The volume shown, and what was made from it.
    std::shared_ptr<const Source> source_;
    float iso_ = 0.0f;
    InsideIs inside_ = InsideIs::Above;
    SlicePlane plane_;
    WindowLevel window_level_;
    int preset_ = 0; // index in the WindowPreset names
    render::SliceWindow window_;
    render::SliceTexture texture_;
    bool texture_stale_ = true;
    render::SliceScene scene_;
    render::SliceMapping mapping_;
    bool contours_stale_ = true;
    // Held, not only compared: a new mesh can never take an old one's address unnoticed.
    std::shared_ptr<const DisplayMesh> contour_meshes_[2];

    // The net at the shown iteration, and the picked node's inspection.
    std::vector<glm::vec3> positions_;
    std::shared_ptr<const DisplayMesh> positions_of_;
    std::optional<std::uint32_t> node_;
    std::optional<glm::vec2> crosshair_; // slice coordinates
    std::optional<NodeInspection> inspection_;
    std::vector<glm::vec3> path_;
    struct InspectionKey {
        const void* context = nullptr;
        std::uint32_t node = 0;
        int iteration = -1;
        int last = -1;
        bool operator==(const InspectionKey&) const = default;
    };
    InspectionKey inspected_, pending_key_;
    std::future<Inspected> pending_;
    std::stop_source stop_; // asked to stop when the panel goes
};

} // namespace snert::app
