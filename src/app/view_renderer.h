// The app's two 3D views: Marching Cubes and the relaxed net, each drawn by the renderer
// (render/mesh_view.h) into its own offscreen target under one shared camera. The textures are
// shown by ImGui; they are redrawn only when a mesh, the camera, the style or the size changed
// (software GL makes every redraw count).
//
// Needs the GL context current on the UI thread; the meshes come from the worker as
// DisplayMesh (world units, quality per triangle) and are uploaded once each.
#pragma once

#include <array>
#include <optional>
#include <memory>

#include "render/camera.h"
#include "render/mesh_view.h"
#include "render/target.h"
#include "worker.h"

namespace snert::app {

class ViewRenderer {
  public:
    static constexpr int kViews = 2; // 0: Marching Cubes, 1: the net

    ViewRenderer();
    ~ViewRenderer();

    // Uploads a view's mesh when it is a different one (null clears the view).
    void set_mesh(int view, std::shared_ptr<const DisplayMesh> mesh);
    bool has_mesh(int view) const { return meshes_[std::size_t(view)] != nullptr; }
    // Bounds of both meshes together (what the camera frames); nullopt when there is none.
    std::optional<Bounds> bounds() const;

    // Draws both views at width x height pixels each if anything changed since the last call.
    // Leaves the framebuffer binding at 0 afterwards (the caller binds its own).
    void render(int width, int height, const render::OrbitCamera& camera,
                const render::DrawStyle& style);
    // The picture of a view (GL convention: row 0 at the bottom); 0 before the first render.
    unsigned texture(int view) const;
    // Renders performed so far (tests check that an unchanged frame draws nothing).
    int render_count() const { return render_count_; }

  private:
    render::MeshRenderer renderer_;
    std::array<render::MeshView, kViews> views_;
    std::array<std::shared_ptr<const DisplayMesh>, kViews> meshes_;
    std::array<std::unique_ptr<render::RenderTarget>, kViews> targets_;
    bool dirty_ = true;
    render::OrbitCamera last_camera_;
    render::DrawStyle last_style_;
    int render_count_ = 0;
};

} // namespace snert::app
