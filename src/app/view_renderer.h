// The app's two 3D views: Marching Cubes and the relaxed net, each drawn by the renderer
// (render/mesh_view.h) into its own offscreen target under one shared camera. The textures are
// shown by ImGui; they are redrawn only when a mesh, the camera, the style or the size changed
// (software GL makes every redraw count).
//
// Needs the GL context current on the UI thread; the meshes come from the worker as
// DisplayMesh (world units, quality per triangle) and are uploaded once each.
#pragma once

#include <array>
#include <chrono>
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
    static constexpr std::chrono::milliseconds kQuiet{200};
    // A mesh with more triangles than one frame can draw (the part size, adapted to what the
    // last part cost) is drawn in parts over several frames into a second target, shown when
    // complete, with its preview shown meanwhile.
    static constexpr double kPartBudgetMs = 12.0;
    static constexpr std::size_t kFirstPartTriangles = std::size_t(1) << 13;
    static constexpr std::size_t kMinPartTriangles = std::size_t(1) << 12;
    static constexpr std::size_t kMaxPartTriangles = std::size_t(1) << 26;
    // A view's new mesh that cut its parts short (the relaxation playing faster than a clinical
    // mesh can be drawn) doubles how long the view waits, still, before it starts them again, up
    // to kLongestQuiet; a finished picture brings it back to kQuiet. The parts cut short were
    // drawn for nothing, and they took the processor from the worker.
    static constexpr std::chrono::milliseconds kLongestQuiet{3200};
    static constexpr int kSamples = 4; // multisampling of the views' targets
    // Above this many triangles (about 4 MB of buffers, 20 ms of llvmpipe's) a mesh's new
    // buffers are sent over several renders (MeshView::upload_parts).
    static constexpr std::size_t kStagedUploadTriangles = std::size_t(1) << 17;

    ViewRenderer();
    ~ViewRenderer();

    // Draws a small mesh once in every way a view draws one (backdrop, mesh, wireframe, preview,
    // part, resolve) into a target of width x height (the window's size: no view is larger).
    // Software GL compiles a shader's code at the first draw that needs it, and sizes its
    // working memory to the largest target drawn: done here, before the window's first frame,
    // that frame does not carry it (the first view's first draw took 25 ms, the next 3.5). The
    // app keeps the memory it frees (the `gui` command's malloc settings), so this target's
    // pages then serve the views' own pictures.
    void warm_up(int width, int height);

    // Uploads a view's mesh when it is a different one (null clears the view): nothing for the
    // same geometry (a frame's measured version), positions, normals and quality only for the
    // same topology (another iteration), everything otherwise. A mesh of more than
    // kStagedUploadTriangles gets its new buffers (MeshView::upload_part), or the rest of its
    // update after the changed indices (MeshView::update_part), from the next render()s or
    // draw_part_between_frames() calls, one part each, and is drawn after; its view keeps its
    // last picture meanwhile.
    void set_mesh(int view, std::shared_ptr<const DisplayMesh> mesh);
    bool has_mesh(int view) const { return meshes_[std::size_t(view)] != nullptr; }
    // The view's picture shows its mesh (whole or its preview): sent and drawn since set_mesh.
    bool shows_mesh(int view) const {
        const auto v = std::size_t(view);
        return meshes_[v] && next_part_[v] == kNoUpload && !dirty_[v];
    }
    // What the camera frames: the bounds of Marching Cubes' mesh, else of the net's; nullopt
    // when there is none.
    std::optional<Bounds> bounds() const;
    // The per-triangle measure the colours show (quality shading); a change sends the views'
    // new values (computed by the worker, DisplayMesh) and redraws them.
    void set_measure(ShapeMeasure measure);
    ShapeMeasure measure() const { return measure_; }
    // The worker's distances of the pair (the newest DistanceMessage): while the measure is a
    // distance, a view shows them when they were measured on its mesh (same geometry), else its
    // triangles are drawn unmeasured (the surface colour) until they come.
    void set_distances(const std::optional<DistanceMessage>& distances);
    // The values a view's colours show now (what was sent to the GPU).
    std::span<const float> values(int view) const;

    // Draws the views at width x height pixels each: a view whose mesh changed, or both when
    // the camera, the style or the size did; otherwise their last pictures stay. Leaves the
    // framebuffer binding at 0 afterwards (the caller binds its own).
    // While the camera moves (it differs from the last render's) or a view's mesh changes in
    // quick succession (the relaxation playing), a mesh with a preview is drawn as its preview;
    // once nothing changed for kQuiet, the whole mesh is drawn again. A mesh too large for one
    // frame shows its preview until its parts, one a frame, are all drawn.
    // Each render() does one of the costly things only (with software GL each takes a good part
    // of a frame): a part of a large mesh's buffers (none with set_parts_between_frames), the
    // views' drawing (a view whose buffers are being sent keeps its picture; with one view's new
    // picture made first), starting a view's parts (its second picture cleared, made the first
    // time), or one part.
    void render(int width, int height, const render::OrbitCamera& camera,
                const render::DrawStyle& style);
    // The next part of a view's buffers to send, else the next part of a view's whole mesh, as
    // a render() would draw it, with the last render's camera and style: the window does these
    // while it waits for its next frame, so a large mesh does not take a frame (the UI drawn
    // and swapped, 10-20 ms of software GL) a part. False when there is neither. A view's last
    // part leaves picture_waiting() true until the next render().
    bool draw_part_between_frames();
    // The window sends a mesh's buffers between frames (draw_part_between_frames): render() then
    // leaves them to it, and a frame is the UI's alone. False (the default): render() sends them.
    void set_parts_between_frames(bool between) { parts_between_frames_ = between; }
    // A view's whole mesh was finished between frames, and no frame has shown it yet.
    bool picture_waiting() const { return picture_waiting_; }
    // A view does not show its whole mesh yet (it shows the preview, its mesh is still being
    // sent, or it waits for its picture): later render()s draw it even if nothing moves.
    bool needs_refine() const {
        return refine_[0] || refine_[1] || sending() || dirty_[0] || dirty_[1];
    }
    // True while a view's new buffers or its update are sent, a part at a time.
    bool sending() const { return next_part_[0] != kNoUpload || next_part_[1] != kNoUpload; }
    // There is work for the views: a part to send (by the next render(), or between frames with
    // set_parts_between_frames), or a view whose mesh changed to draw.
    bool has_pending_work() const { return sending() || dirty_[0] || dirty_[1]; }
    // True while a view's whole mesh is being drawn in parts, a part a frame or between frames.
    bool drawing_parts() const { return drawing_parts_[0] || drawing_parts_[1]; }
    // Triangles a part holds now (tests; it adapts to the time parts take).
    std::size_t part_triangles() const { return part_triangles_; }
    // The next part's size after a part of `size` triangles drew `drawn` of them (fewer at a
    // mesh's end) in `ms`: towards kPartBudgetMs, at most doubled or halved a part.
    static std::size_t next_part_triangles(std::size_t size, std::size_t drawn, double ms);
    // The picture of a view (GL convention: row 0 at the bottom); 0 before the first render.
    unsigned texture(int view) const;
    // Calls of render() that drew anything (tests check that an unchanged frame draws nothing).
    int render_count() const { return render_count_; }
    // Times a view was drawn, and what its mesh sent to the GPU.
    int view_draws(int view) const { return view_draws_[std::size_t(view)]; }
    int preview_draws(int view) const { return preview_draws_[std::size_t(view)]; }
    // Parts drawn (of both views) and the milliseconds they took, glFinish included.
    int part_draws() const { return part_draws_; }
    double part_ms() const { return part_ms_; }
    double largest_part_ms() const { return largest_part_ms_; }
    // How long view `view` waits, still, before it draws its whole mesh (kQuiet unless backed off).
    std::chrono::milliseconds quiet(int view) const { return quiet_[std::size_t(view)]; }
    const render::UploadCounters& uploads(int view) const {
        return views_[std::size_t(view)].counters();
    }

  private:
    bool send_next_part();
    void upload_preview(std::size_t view);
    void upload_values(std::size_t view); // the same mesh, the values of another measure
    // The runs of `mesh`'s indices that differ from `previous`'s: the worker's when it compared
    // the same two, else compared here.
    static std::vector<render::IndexRun> changed_runs(const DisplayMesh& mesh,
                                                      const DisplayMesh& previous);
    void draw_whole(std::size_t view, const render::Viewport& viewport,
                    const render::OrbitCamera& camera, const render::DrawStyle& style,
                    bool preview);
    void start_parts(std::size_t view, const render::Viewport& viewport,
                     const render::DrawStyle& style);
    void draw_next_part(std::size_t view, const render::Viewport& viewport,
                        const render::OrbitCamera& camera, const render::DrawStyle& style);

    render::MeshRenderer renderer_;
    std::array<render::MeshView, kViews> views_;
    std::array<std::shared_ptr<const DisplayMesh>, kViews> meshes_;
    std::array<std::unique_ptr<render::RenderTarget>, kViews> targets_;
    std::array<bool, kViews> dirty_{true, true};
    std::array<bool, kViews> refine_{false, false};                   // drawn as the preview
    std::array<std::unique_ptr<render::RenderTarget>, kViews> parts_; // the whole mesh, in parts
    std::array<bool, kViews> drawing_parts_{false, false};
    std::array<bool, kViews> parts_due_{false, false}; // start the parts at the next render()
    // The next part of a view's new buffers or update to send (MeshView::upload_part or
    // update_part), or kNoUpload.
    static constexpr int kNoUpload = -1;
    std::array<int, kViews> next_part_{kNoUpload, kNoUpload};
    std::array<bool, kViews> updating_{false, false}; // the parts are an update's (same topology)
    std::array<std::size_t, kViews> parts_drawn_{};   // triangles drawn into parts_
    std::size_t part_triangles_ = kFirstPartTriangles;
    std::array<std::chrono::steady_clock::time_point, kViews> last_change_{};
    std::array<std::chrono::milliseconds, kViews> quiet_{kQuiet, kQuiet};
    std::array<std::shared_ptr<const PreviewMesh>, kViews> previews_; // uploaded
    std::array<int, kViews> view_draws_{}, preview_draws_{};
    int part_draws_ = 0;
    double part_ms_ = 0, largest_part_ms_ = 0;
    bool picture_waiting_ = false;
    bool parts_between_frames_ = false;
    render::OrbitCamera last_camera_;
    render::DrawStyle last_style_;
    int render_count_ = 0;
    ShapeMeasure measure_ = ShapeMeasure::Quality;
    std::optional<DistanceMessage> distances_;
    mutable std::array<std::vector<float>, kViews> unmeasured_; // NaN per triangle
};

} // namespace snert::app
