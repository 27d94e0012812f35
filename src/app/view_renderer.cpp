// The two 3D views, redrawn on change only.
#include "view_renderer.h"

#include "render/gl.h"

#include <algorithm>
#include <limits>
#include <utility>

namespace snert::app {

namespace {

bool same_camera(const render::OrbitCamera& a, const render::OrbitCamera& b) {
    return a.target == b.target && a.distance == b.distance && a.yaw == b.yaw &&
           a.pitch == b.pitch && a.roll == b.roll && a.fov_y == b.fov_y &&
           a.near_plane == b.near_plane && a.far_plane == b.far_plane;
}

bool same_style(const render::DrawStyle& a, const render::DrawStyle& b) {
    return a.shading == b.shading && a.wireframe == b.wireframe &&
           a.quality_threshold == b.quality_threshold && a.surface_color == b.surface_color &&
           a.line_color == b.line_color && a.line_width == b.line_width &&
           a.background_top == b.background_top && a.background_bottom == b.background_bottom &&
           a.value_low == b.value_low && a.value_high == b.value_high && a.diverging == b.diverging;
}

} // namespace

ViewRenderer::ViewRenderer() = default;
ViewRenderer::~ViewRenderer() = default;

std::vector<render::IndexRun> ViewRenderer::changed_runs(const DisplayMesh& mesh,
                                                         const DisplayMesh& previous) {
    if (mesh.changed_since != 0 && mesh.changed_since == previous.geometry)
        return mesh.changed_runs;
    if (mesh.mesh.indices.size() != previous.mesh.indices.size()) return {}; // update() refuses
    return render::changed_index_runs(mesh.mesh.indices, previous.mesh.indices);
}

void ViewRenderer::set_mesh(int view, std::shared_ptr<const DisplayMesh> mesh) {
    const auto v = std::size_t(view);
    auto& slot = meshes_[v];
    if (slot == mesh) return;
    const bool same_geometry =
        slot && mesh && mesh->geometry != 0 && slot->geometry == mesh->geometry;
    const std::shared_ptr<const DisplayMesh> previous = std::exchange(slot, std::move(mesh));
    if (same_geometry) return;
    dirty_[v] = true;
    // Until its last part is sent, the GPU does not hold the previous mesh's indices. A mesh
    // whose update was still being sent has its indices there (they go first): its positions,
    // normals and quality, the rest of an update, are sent again whole anyway.
    const bool uploading = next_part_[v] != kNoUpload && !updating_[v];
    next_part_[v] = kNoUpload;
    updating_[v] = false;
    if (!slot) {
        views_[v] = render::MeshView();
        upload_preview(v);
        return;
    }
    const bool staged = slot->mesh.triangle_count() > kStagedUploadTriangles;
    if (!uploading && previous && views_[v].can_update(slot->mesh)) {
        const std::vector<render::IndexRun> runs = changed_runs(*slot, *previous);
        if (staged) { // the rest sent by the next render()s or between frames, one part each
            views_[v].begin_update(slot->mesh, runs);
            next_part_[v] = 0;
            updating_[v] = true;
            return;
        }
        views_[v].update(slot->mesh, runs, values(view), slot->normals);
    } else {
        previews_[v] = nullptr; // new buffers hold no preview
        if (staged) {
            next_part_[v] = 0;
            return;
        }
        views_[v].upload(slot->mesh, values(view), slot->normals);
    }
    upload_preview(v);
}

std::span<const float> ViewRenderer::values(int view) const {
    const auto v = std::size_t(view);
    const auto& mesh = meshes_[v];
    if (!mesh) return {};
    if (!is_distance(measure_)) return mesh->values(measure_);
    if (distances_ && distances_->distances && distances_->distances->measure == measure_) {
        const PairDistances& pair = *distances_->distances;
        if (v == 0 && distances_->mc_geometry == mesh->geometry) return pair.first;
        if (v == 1 && distances_->net_geometry == mesh->geometry) return pair.second;
    }
    unmeasured_[v].assign(mesh->mesh.triangle_count(), std::numeric_limits<float>::quiet_NaN());
    return unmeasured_[v];
}

void ViewRenderer::upload_values(std::size_t v) {
    const auto& mesh = meshes_[v];
    if (!mesh) return;
    if (next_part_[v] != kNoUpload) {
        // A mesh still being sent takes the values shown when its quality goes (its last
        // parts): begun already, they go again.
        const int parts = updating_[v] ? render::MeshView::update_parts(mesh->mesh)
                                       : render::MeshView::upload_parts(mesh->mesh);
        next_part_[v] =
            std::min(next_part_[v], parts - render::MeshView::quality_parts(mesh->mesh));
        return;
    }
    // The same mesh: only the per-triangle values change (no index is sent).
    if (!views_[v].update(mesh->mesh, {}, values(int(v)), mesh->normals)) {
        views_[v].upload(mesh->mesh, values(int(v)), mesh->normals);
        previews_[v] = nullptr;
    }
    upload_preview(v);
    dirty_[v] = true;
}

void ViewRenderer::set_measure(ShapeMeasure measure) {
    if (measure == measure_) return;
    measure_ = measure;
    for (std::size_t v = 0; v < meshes_.size(); ++v) upload_values(v);
}

void ViewRenderer::set_distances(const std::optional<DistanceMessage>& distances) {
    const auto pair = [](const std::optional<DistanceMessage>& d) {
        return d ? d->distances.get() : nullptr;
    };
    if (pair(distances) == pair(distances_)) return;
    distances_ = distances;
    if (!is_distance(measure_)) return;
    for (std::size_t v = 0; v < meshes_.size(); ++v) upload_values(v);
}

// The preview's triangles when they are new; their quality (the triangles they stand for) with
// every new mesh.
void ViewRenderer::upload_preview(std::size_t v) {
    const auto& mesh = meshes_[v];
    const std::shared_ptr<const PreviewMesh> preview =
        mesh && mesh->preview && !mesh->preview->source.empty() ? mesh->preview : nullptr;
    if (!preview) {
        if (previews_[v]) views_[v].set_preview({}, {});
        previews_[v] = nullptr;
        return;
    }
    std::vector<float> quality(preview->source.size());
    const std::span<const float> shown = values(int(v));
    for (std::size_t t = 0; t < quality.size(); ++t) quality[t] = shown[preview->source[t]];
    if (previews_[v] == preview) {
        views_[v].set_preview_quality(quality);
    } else {
        views_[v].set_preview(preview->indices, quality);
        previews_[v] = preview;
    }
}

std::optional<Bounds> ViewRenderer::bounds() const {
    // Marching Cubes' when it is there: the camera must not depend on whether the net's first
    // frame arrived in the same frame as Marching Cubes or later (the net, its dual, has about
    // the same bounds).
    for (const auto& m : meshes_)
        if (m && !m->mesh.positions.empty()) return mesh_bounds(m->mesh);
    return std::nullopt;
}

void ViewRenderer::warm_up(int width, int height) {
    Mesh mesh; // a tetrahedron
    mesh.positions = {
        {0.0f, 0.0f, 0.0f}, {1.0f, 0.0f, 0.0f}, {0.0f, 1.0f, 0.0f}, {0.0f, 0.0f, 1.0f}};
    mesh.indices = {0, 2, 1, 0, 1, 3, 0, 3, 2, 1, 2, 3};
    render::MeshView view;
    view.upload(mesh);
    const std::uint32_t preview[] = {0, 2, 1};
    const float preview_quality[] = {1.0f};
    view.set_preview(preview, preview_quality);
    width = std::max(width, 1);
    height = std::max(height, 1);
    const render::RenderTarget target(width, height, kSamples);
    const render::Viewport viewport{0, 0, width, height};
    const render::OrbitCamera camera =
        render::frame_bounds(mesh_bounds(mesh), render::ViewPreset::Front, viewport.aspect());
    render::DrawStyle style;
    renderer_.draw_background(viewport, style);
    for (const bool wireframe : {false, true}) {
        style.wireframe = wireframe;
        renderer_.draw(view, camera, viewport, style, false);
        renderer_.draw(view, camera, viewport, style, true);
        renderer_.draw_part(view, camera, viewport, style, 1, 2);
    }
    target.resolve();
    glFinish();
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
}

// One part of a large mesh's new buffers or of its update: that is the render's work, or the
// window's between frames. The view is drawn by the render after its last part.
bool ViewRenderer::send_next_part() {
    for (std::size_t v = 0; v < kViews; ++v) {
        if (next_part_[v] == kNoUpload) continue;
        const DisplayMesh& mesh = *meshes_[v];
        const int part = next_part_[v]++;
        const int parts = updating_[v] ? render::MeshView::update_parts(mesh.mesh)
                                       : render::MeshView::upload_parts(mesh.mesh);
        // The quality goes last: the values shown then.
        const std::span<const float> quality =
            part >= parts - render::MeshView::quality_parts(mesh.mesh) ? values(int(v))
                                                                       : std::span<const float>();
        if (updating_[v])
            views_[v].update_part(part, mesh.mesh, quality, mesh.normals);
        else
            views_[v].upload_part(part, mesh.mesh, quality, mesh.normals);
        if (next_part_[v] == parts) {
            next_part_[v] = kNoUpload;
            updating_[v] = false;
            upload_preview(v);
        }
        return true;
    }
    return false;
}

void ViewRenderer::render(int width, int height, const render::OrbitCamera& camera,
                          const render::DrawStyle& style) {
    picture_waiting_ = false; // this frame shows it
    // Once the views have pictures (their targets are made): until then a part would leave them
    // without one. Not when the window sends them between frames.
    if (targets_[0] && targets_[1] && !parts_between_frames_ && send_next_part()) return;
    width = std::max(width, 1);
    height = std::max(height, 1);
    const bool moving = !same_camera(camera, last_camera_);
    const bool all = moving || !same_style(style, last_style_);
    const auto has_picture = [&](std::size_t i) {
        return targets_[i] && targets_[i]->width() == width && targets_[i]->height() == height;
    };
    // The views' first pictures (fresh memory for their samples, 15 ms of llvmpipe's at
    // 640 x 700 each) are made one a render, the window's first frames: a view waits for its
    // own, drawn once it is there. A new size makes both at once.
    bool made_first = false;
    for (std::size_t i = 0; i < kViews; ++i) {
        if (has_picture(i) || (!targets_[i] && std::exchange(made_first, true))) continue;
        targets_[i] = std::make_unique<render::RenderTarget>(width, height, kSamples);
        parts_[i].reset();
        drawing_parts_[i] = false;
        dirty_[i] = true;
    }
    bool drew = false;
    const auto now = std::chrono::steady_clock::now();
    const render::Viewport viewport{0, 0, width, height};
    for (std::size_t i = 0; i < kViews; ++i) {
        if (!targets_[i]) continue;               // its first picture comes with the next render
        if (next_part_[i] != kNoUpload) continue; // its buffers are being sent: drawn after
        // Too many triangles for one frame: the preview now, the whole mesh in parts after.
        const bool large = views_[i].has_preview() && views_[i].triangle_count() > part_triangles_;
        if (all || dirty_[i]) {
            if (dirty_[i] && drawing_parts_[i]) quiet_[i] = std::min(2 * quiet_[i], kLongestQuiet);
            const bool rapid = now - last_change_[i] < quiet_[i];
            last_change_[i] = now;
            drawing_parts_[i] = false; // what it held shows what changed
            const bool preview = views_[i].has_preview() && (moving || rapid || large);
            draw_whole(i, viewport, camera, style, preview);
            parts_due_[i] = preview && large && !moving && !rapid;
            drew = true;
        } else if (refine_[i] && !drawing_parts_[i] &&
                   (parts_due_[i] || now - last_change_[i] >= quiet_[i])) {
            // Starting the parts clears the second target (made anew the first time): no part
            // is drawn in the same render.
            if (large)
                start_parts(i, viewport, style);
            else
                draw_whole(i, viewport, camera, style, false);
            parts_due_[i] = false;
            drew = true;
        }
    }
    // At most one part a frame, and none in a frame that drew anything else: the UI thread's
    // share of software GL stays within a frame.
    for (std::size_t i = 0; i < kViews && !drew; ++i)
        if (drawing_parts_[i] && next_part_[i] == kNoUpload) {
            draw_next_part(i, viewport, camera, style);
            drew = true;
        }
    if (!drew) return;
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    last_camera_ = camera;
    last_style_ = style;
    ++render_count_;
}

bool ViewRenderer::draw_part_between_frames() {
    // A mesh's buffers first: the views wait for them. Once the views have pictures, as render()
    // sends them.
    if (targets_[0] && targets_[1] && send_next_part()) return true;
    for (std::size_t i = 0; i < kViews; ++i) {
        // A view whose mesh changed is drawn anew by the next render(): its parts are moot.
        if (!drawing_parts_[i] || dirty_[i]) continue;
        const render::Viewport viewport{0, 0, parts_[i]->width(), parts_[i]->height()};
        draw_next_part(i, viewport, last_camera_, last_style_);
        glBindFramebuffer(GL_FRAMEBUFFER, 0);
        if (!drawing_parts_[i]) picture_waiting_ = true;
        return true;
    }
    return false;
}

void ViewRenderer::draw_whole(std::size_t i, const render::Viewport& viewport,
                              const render::OrbitCamera& camera, const render::DrawStyle& style,
                              bool preview) {
    const render::RenderTarget& target = *targets_[i];
    target.bind();
    renderer_.draw_background(viewport, style);
    if (meshes_[i] && !views_[i].empty())
        renderer_.draw(views_[i], camera, viewport, style, preview);
    target.resolve();
    dirty_[i] = false;
    refine_[i] = preview;
    ++(preview ? preview_draws_ : view_draws_)[i];
}

// The whole mesh goes into a second target, shown once complete; the first keeps the preview.
void ViewRenderer::start_parts(std::size_t i, const render::Viewport& viewport,
                               const render::DrawStyle& style) {
    auto& parts = parts_[i];
    if (!parts)
        parts = std::make_unique<render::RenderTarget>(viewport.width, viewport.height, kSamples);
    parts->bind();
    renderer_.draw_background(viewport, style);
    parts_drawn_[i] = 0;
    drawing_parts_[i] = true;
}

void ViewRenderer::draw_next_part(std::size_t i, const render::Viewport& viewport,
                                  const render::OrbitCamera& camera,
                                  const render::DrawStyle& style) {
    parts_[i]->bind();
    const auto start = std::chrono::steady_clock::now();
    renderer_.draw_part(views_[i], camera, viewport, style, parts_drawn_[i], part_triangles_);
    // Waited for, so the next part's size follows what this one cost (software GL draws on
    // this thread; a GPU soon takes whole meshes in one part).
    glFinish();
    const double ms =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    // Parts run while parts_drawn_ is short of the mesh: the last one draws what is left.
    const std::size_t drawn =
        std::min(part_triangles_, views_[i].triangle_count() - parts_drawn_[i]);
    parts_drawn_[i] += part_triangles_;
    ++part_draws_;
    part_ms_ += ms;
    largest_part_ms_ = std::max(largest_part_ms_, ms);
    part_triangles_ = next_part_triangles(part_triangles_, drawn, ms);
    if (parts_drawn_[i] < views_[i].triangle_count()) return;
    parts_[i]->resolve();
    std::swap(targets_[i], parts_[i]);
    drawing_parts_[i] = false;
    quiet_[i] = kQuiet;
    refine_[i] = false;
    ++view_draws_[i];
}

std::size_t ViewRenderer::next_part_triangles(std::size_t size, std::size_t drawn, double ms) {
    // A mesh's last part is what is left of it: its time says little of a whole part's (taken as
    // a whole part's, a quick remainder doubled the next mesh's first part).
    if (2 * drawn < size) return size;
    const double scale =
        std::clamp(kPartBudgetMs / std::max(ms, 0.01) * double(drawn) / double(size), 0.5, 2.0);
    return std::clamp(std::size_t(double(size) * scale), kMinPartTriangles, kMaxPartTriangles);
}

unsigned ViewRenderer::texture(int view) const {
    const auto& target = targets_[std::size_t(view)];
    return target ? target->texture() : 0u;
}

} // namespace snert::app
