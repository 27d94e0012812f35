// The two 3D views, redrawn on change only.
#include "view_renderer.h"

#include "render/gl.h"

#include <algorithm>

namespace snert::app {

namespace {

bool same_camera(const render::OrbitCamera& a, const render::OrbitCamera& b) {
    return a.target == b.target && a.distance == b.distance && a.yaw == b.yaw &&
           a.pitch == b.pitch && a.fov_y == b.fov_y && a.near_plane == b.near_plane &&
           a.far_plane == b.far_plane;
}

bool same_style(const render::DrawStyle& a, const render::DrawStyle& b) {
    return a.shading == b.shading && a.wireframe == b.wireframe &&
           a.quality_threshold == b.quality_threshold && a.surface_color == b.surface_color &&
           a.line_color == b.line_color && a.line_width == b.line_width &&
           a.background_top == b.background_top && a.background_bottom == b.background_bottom;
}

} // namespace

ViewRenderer::ViewRenderer() = default;
ViewRenderer::~ViewRenderer() = default;

void ViewRenderer::set_mesh(int view, std::shared_ptr<const DisplayMesh> mesh) {
    auto& slot = meshes_[std::size_t(view)];
    if (slot == mesh) return;
    slot = std::move(mesh);
    if (slot)
        views_[std::size_t(view)].upload(slot->mesh, slot->quality);
    else
        views_[std::size_t(view)] = render::MeshView();
    dirty_ = true;
}

std::optional<Bounds> ViewRenderer::bounds() const {
    std::optional<Bounds> all;
    for (const auto& m : meshes_) {
        if (!m || m->mesh.positions.empty()) continue;
        const Bounds b = mesh_bounds(m->mesh);
        if (!all)
            all = b;
        else
            all = Bounds{glm::min(all->min, b.min), glm::max(all->max, b.max)};
    }
    return all;
}

void ViewRenderer::render(int width, int height, const render::OrbitCamera& camera,
                          const render::DrawStyle& style) {
    width = std::max(width, 1);
    height = std::max(height, 1);
    for (auto& target : targets_) {
        if (!target || target->width() != width || target->height() != height) {
            target = std::make_unique<render::RenderTarget>(width, height, 4);
            dirty_ = true;
        }
    }
    if (!dirty_ && same_camera(camera, last_camera_) && same_style(style, last_style_)) return;
    for (int i = 0; i < kViews; ++i) {
        const render::RenderTarget& target = *targets_[std::size_t(i)];
        target.bind();
        const render::Viewport viewport{0, 0, width, height};
        renderer_.draw_background(viewport, style);
        if (meshes_[std::size_t(i)] && !views_[std::size_t(i)].empty())
            renderer_.draw(views_[std::size_t(i)], camera, viewport, style);
        target.resolve();
    }
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    last_camera_ = camera;
    last_style_ = style;
    dirty_ = false;
    ++render_count_;
}

unsigned ViewRenderer::texture(int view) const {
    const auto& target = targets_[std::size_t(view)];
    return target ? target->texture() : 0u;
}

} // namespace snert::app
