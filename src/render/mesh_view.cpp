#include "mesh_view.h"

#include <algorithm>
#include <stdexcept>
#include <string>
#include <utility>

#include <glm/gtc/type_ptr.hpp>

#include "core/metrics.h"
#include "program.h"
#include "shader_sources.h"

namespace snert::render {

std::optional<Shading> parse_shading(std::string_view name) {
    if (name == "flat") return Shading::Flat;
    if (name == "smooth") return Shading::Smooth;
    if (name == "quality") return Shading::Quality;
    return std::nullopt;
}

namespace {
constexpr Named<Shading> kShadings[] = {
    {Shading::Flat, "flat", "flat"},
    {Shading::Smooth, "smooth", "smooth"},
    {Shading::Quality, "quality", "quality"},
};
} // namespace

std::span<const Named<Shading>> name_table(Shading) {
    return kShadings;
}

const char* shading_name(Shading shading) {
    switch (shading) {
    case Shading::Flat:
        return "flat";
    case Shading::Smooth:
        return "smooth";
    case Shading::Quality:
        return "quality";
    }
    return "?";
}

std::vector<glm::vec3> vertex_normals(const Mesh& mesh) {
    std::vector<glm::vec3> normals(mesh.positions.size(), glm::vec3(0.0f));
    for (std::size_t t = 0; t + 2 < mesh.indices.size(); t += 3) {
        const std::uint32_t a = mesh.indices[t], b = mesh.indices[t + 1], c = mesh.indices[t + 2];
        // The cross product's length is twice the area: summing it weights by area.
        const glm::vec3 n = glm::cross(mesh.positions[b] - mesh.positions[a],
                                       mesh.positions[c] - mesh.positions[a]);
        normals[a] += n;
        normals[b] += n;
        normals[c] += n;
    }
    for (glm::vec3& n : normals) {
        const float length = glm::length(n);
        n = length > 0.0f ? n / length : glm::vec3(0.0f, 0.0f, 1.0f);
    }
    return normals;
}

// ---------------------------------------------------------------------------------------------
// MeshView

MeshView::MeshView() = default;
MeshView::~MeshView() {
    release();
}

MeshView::MeshView(MeshView&& other) noexcept {
    *this = std::move(other);
}

MeshView& MeshView::operator=(MeshView&& other) noexcept {
    if (this != &other) {
        release();
        vertex_array_ = std::exchange(other.vertex_array_, 0);
        vertex_buffer_ = std::exchange(other.vertex_buffer_, 0);
        index_buffer_ = std::exchange(other.index_buffer_, 0);
        quality_buffer_ = std::exchange(other.quality_buffer_, 0);
        quality_texture_ = std::exchange(other.quality_texture_, 0);
        triangles_ = std::exchange(other.triangles_, 0);
        bounds_ = other.bounds_;
    }
    return *this;
}

void MeshView::release() {
    if (vertex_array_ == 0) return;
    glDeleteTextures(1, &quality_texture_);
    glDeleteBuffers(1, &quality_buffer_);
    glDeleteBuffers(1, &index_buffer_);
    glDeleteBuffers(1, &vertex_buffer_);
    glDeleteVertexArrays(1, &vertex_array_);
    vertex_array_ = vertex_buffer_ = index_buffer_ = quality_buffer_ = quality_texture_ = 0;
    triangles_ = 0;
}

void MeshView::upload(const Mesh& mesh, std::span<const float> quality) {
    const std::size_t triangles = mesh.triangle_count();
    if (mesh.indices.size() % 3 != 0)
        throw std::invalid_argument("mesh index count is not a multiple of 3");
    for (std::uint32_t i : mesh.indices)
        if (i >= mesh.positions.size())
            throw std::invalid_argument("mesh index " + std::to_string(i) + " out of range (" +
                                        std::to_string(mesh.positions.size()) + " vertices)");
    std::vector<float> computed;
    if (quality.empty() && triangles > 0) {
        computed = triangle_quality(mesh);
        quality = computed;
    }
    if (quality.size() != triangles)
        throw std::invalid_argument("quality has " + std::to_string(quality.size()) +
                                    " values for " + std::to_string(triangles) + " triangles");

    if (vertex_array_ == 0) {
        glGenVertexArrays(1, &vertex_array_);
        glGenBuffers(1, &vertex_buffer_);
        glGenBuffers(1, &index_buffer_);
        glGenBuffers(1, &quality_buffer_);
        glGenTextures(1, &quality_texture_);
    }
    // Interleaved position and normal, 6 floats per vertex.
    const std::vector<glm::vec3> normals = vertex_normals(mesh);
    std::vector<glm::vec3> vertices;
    vertices.reserve(mesh.positions.size() * 2);
    for (std::size_t i = 0; i < mesh.positions.size(); ++i) {
        vertices.push_back(mesh.positions[i]);
        vertices.push_back(normals[i]);
    }
    glBindVertexArray(vertex_array_);
    glBindBuffer(GL_ARRAY_BUFFER, vertex_buffer_);
    glBufferData(GL_ARRAY_BUFFER, GLsizeiptr(vertices.size() * sizeof(glm::vec3)), vertices.data(),
                 GL_STATIC_DRAW);
    glEnableVertexAttribArray(0);
    glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, 2 * sizeof(glm::vec3), nullptr);
    glEnableVertexAttribArray(1);
    glVertexAttribPointer(1, 3, GL_FLOAT, GL_FALSE, 2 * sizeof(glm::vec3),
                          reinterpret_cast<const void*>(
                              sizeof(glm::vec3))); // NOLINT(performance-no-int-to-ptr): GL offset
    glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, index_buffer_);
    glBufferData(GL_ELEMENT_ARRAY_BUFFER, GLsizeiptr(mesh.indices.size() * sizeof(std::uint32_t)),
                 mesh.indices.data(), GL_STATIC_DRAW);
    glBindVertexArray(0);

    // Per-triangle quality in a buffer texture, fetched by gl_PrimitiveID. A buffer texture
    // needs storage, so an empty mesh gets one unused value.
    const float unused_value = 0.0f;
    glBindBuffer(GL_TEXTURE_BUFFER, quality_buffer_);
    glBufferData(GL_TEXTURE_BUFFER, GLsizeiptr(std::max<std::size_t>(quality.size(), 1) * 4),
                 quality.empty() ? &unused_value : quality.data(), GL_STATIC_DRAW);
    glBindTexture(GL_TEXTURE_BUFFER, quality_texture_);
    glTexBuffer(GL_TEXTURE_BUFFER, GL_R32F, quality_buffer_);
    glBindTexture(GL_TEXTURE_BUFFER, 0);
    glBindBuffer(GL_TEXTURE_BUFFER, 0);
    check_gl("MeshView::upload");

    triangles_ = triangles;
    bounds_ = mesh_bounds(mesh);
}

// ---------------------------------------------------------------------------------------------
// MeshRenderer

struct MeshRenderer::Programs {
    Program mesh{"mesh", shaders::kMeshVert, shaders::kMeshGeom, shaders::kMeshFrag};
    Program background{"background", shaders::kBackgroundVert, nullptr, shaders::kBackgroundFrag};
};

namespace {
constexpr int kColormapSize = 256;
constexpr GLint kQualityUnit = 0;
constexpr GLint kColormapUnit = 1;

void set_viewport(const Viewport& viewport) {
    glViewport(viewport.x, viewport.y, viewport.width, viewport.height);
    glScissor(viewport.x, viewport.y, viewport.width, viewport.height);
    glEnable(GL_SCISSOR_TEST);
}
} // namespace

MeshRenderer::MeshRenderer() : programs_(std::make_unique<Programs>()) {
    const std::vector<std::uint8_t> colormap = viridis_rgba8(kColormapSize);
    glGenTextures(1, &colormap_texture_);
    glBindTexture(GL_TEXTURE_1D, colormap_texture_);
    glTexImage1D(GL_TEXTURE_1D, 0, GL_RGBA8, kColormapSize, 0, GL_RGBA, GL_UNSIGNED_BYTE,
                 colormap.data());
    glTexParameteri(GL_TEXTURE_1D, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
    glTexParameteri(GL_TEXTURE_1D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    glTexParameteri(GL_TEXTURE_1D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    glBindTexture(GL_TEXTURE_1D, 0);
    glGenVertexArrays(1, &empty_vertex_array_);
    check_gl("MeshRenderer");
}

MeshRenderer::~MeshRenderer() {
    glDeleteVertexArrays(1, &empty_vertex_array_);
    glDeleteTextures(1, &colormap_texture_);
}

void MeshRenderer::draw_background(const Viewport& viewport, const DrawStyle& style) const {
    set_viewport(viewport);
    glDisable(GL_DEPTH_TEST);
    glDisable(GL_BLEND);
    glDisable(GL_CULL_FACE);
    glDepthMask(GL_TRUE);
    glClear(GL_DEPTH_BUFFER_BIT);
    const Program& p = programs_->background;
    p.use();
    glUniform3fv(p.uniform("top_color"), 1, glm::value_ptr(style.background_top));
    glUniform3fv(p.uniform("bottom_color"), 1, glm::value_ptr(style.background_bottom));
    glBindVertexArray(empty_vertex_array_);
    glDrawArrays(GL_TRIANGLES, 0, 3);
    glBindVertexArray(0);
    glDisable(GL_SCISSOR_TEST);
    check_gl("MeshRenderer::draw_background");
}

void MeshRenderer::draw(const MeshView& mesh, const OrbitCamera& camera, const Viewport& viewport,
                        const DrawStyle& style) const {
    if (mesh.empty() || viewport.width <= 0 || viewport.height <= 0) return;
    set_viewport(viewport);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_LESS);
    glDepthMask(GL_TRUE);
    glDisable(GL_BLEND);
    glDisable(GL_CULL_FACE);

    const Program& p = programs_->mesh;
    p.use();
    const glm::mat4 view = camera.view();
    const glm::mat4 projection = camera.projection(viewport.aspect());
    glUniformMatrix4fv(p.uniform("view"), 1, GL_FALSE, glm::value_ptr(view));
    glUniformMatrix4fv(p.uniform("projection"), 1, GL_FALSE, glm::value_ptr(projection));
    glUniform1i(p.uniform("shading"), int(style.shading));
    glUniform3fv(p.uniform("surface_color"), 1, glm::value_ptr(style.surface_color));
    glUniform1f(p.uniform("quality_threshold"), style.quality_threshold);
    glUniform3fv(p.uniform("poor_color"), 1, glm::value_ptr(kPoorQualityColor));
    glUniform1i(p.uniform("wireframe"), style.wireframe ? 1 : 0);
    glUniform1f(p.uniform("line_half_width"), 0.5f * style.line_width);
    glUniform3fv(p.uniform("line_color"), 1, glm::value_ptr(style.line_color));
    glUniform1i(p.uniform("quality"), kQualityUnit);
    glUniform1i(p.uniform("colormap"), kColormapUnit);
    glActiveTexture(GL_TEXTURE0 + kQualityUnit);
    glBindTexture(GL_TEXTURE_BUFFER, mesh.quality_texture_);
    glActiveTexture(GL_TEXTURE0 + kColormapUnit);
    glBindTexture(GL_TEXTURE_1D, colormap_texture_);

    glBindVertexArray(mesh.vertex_array_);
    glDrawElements(GL_TRIANGLES, GLsizei(mesh.triangles_ * 3), GL_UNSIGNED_INT, nullptr);
    glBindVertexArray(0);

    glBindTexture(GL_TEXTURE_1D, 0);
    glActiveTexture(GL_TEXTURE0 + kQualityUnit);
    glBindTexture(GL_TEXTURE_BUFFER, 0);
    glDisable(GL_SCISSOR_TEST);
    check_gl("MeshRenderer::draw");
}

} // namespace snert::render
