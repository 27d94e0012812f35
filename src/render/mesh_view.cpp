#include "mesh_view.h"

#include <algorithm>
#include <cstdint>
#include <limits>
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
        position_buffer_ = std::exchange(other.position_buffer_, 0);
        normal_buffer_ = std::exchange(other.normal_buffer_, 0);
        index_buffers_ = std::exchange(other.index_buffers_, {});
        quality_buffer_ = std::exchange(other.quality_buffer_, 0);
        quality_texture_ = std::exchange(other.quality_texture_, 0);
        preview_index_buffer_ = std::exchange(other.preview_index_buffer_, 0);
        preview_quality_buffer_ = std::exchange(other.preview_quality_buffer_, 0);
        preview_quality_texture_ = std::exchange(other.preview_quality_texture_, 0);
        triangles_ = std::exchange(other.triangles_, 0);
        vertices_ = std::exchange(other.vertices_, 0);
        preview_triangles_ = std::exchange(other.preview_triangles_, 0);
        bounds_ = other.bounds_;
        counters_ = other.counters_;
    }
    return *this;
}

void MeshView::release() {
    if (vertex_array_ == 0) return;
    glDeleteTextures(1, &preview_quality_texture_);
    glDeleteBuffers(1, &preview_quality_buffer_);
    glDeleteBuffers(1, &preview_index_buffer_);
    preview_index_buffer_ = preview_quality_buffer_ = preview_quality_texture_ = 0;
    preview_triangles_ = 0;
    glDeleteTextures(1, &quality_texture_);
    glDeleteBuffers(1, &quality_buffer_);
    glDeleteBuffers(GLsizei(index_buffers_.size()), index_buffers_.data());
    index_buffers_.clear();
    glDeleteBuffers(1, &normal_buffer_);
    glDeleteBuffers(1, &position_buffer_);
    glDeleteVertexArrays(1, &vertex_array_);
    vertex_array_ = position_buffer_ = normal_buffer_ = 0;
    quality_buffer_ = quality_texture_ = 0;
    triangles_ = vertices_ = 0;
}

namespace {

void check_indices(std::span<const std::uint32_t> indices, std::size_t vertex_count) {
    for (std::uint32_t i : indices)
        if (i >= vertex_count)
            throw std::invalid_argument("mesh index " + std::to_string(i) + " out of range (" +
                                        std::to_string(vertex_count) + " vertices)");
}

// The quality given, or computed; throws when its size does not match.
std::span<const float> quality_of(const Mesh& mesh, std::span<const float> quality,
                                  std::vector<float>& computed) {
    if (quality.empty() && mesh.triangle_count() > 0) {
        computed = triangle_quality(mesh);
        quality = computed;
    }
    if (quality.size() != mesh.triangle_count())
        throw std::invalid_argument("quality has " + std::to_string(quality.size()) +
                                    " values for " + std::to_string(mesh.triangle_count()) +
                                    " triangles");
    return quality;
}

std::span<const glm::vec3> normals_of(const Mesh& mesh, std::span<const glm::vec3> normals,
                                      std::vector<glm::vec3>& computed) {
    if (normals.empty()) {
        computed = vertex_normals(mesh);
        normals = computed;
    }
    if (normals.size() != mesh.positions.size())
        throw std::invalid_argument("normals have " + std::to_string(normals.size()) +
                                    " values for " + std::to_string(mesh.positions.size()) +
                                    " vertices");
    return normals;
}

template <typename T> GLsizeiptr bytes(std::span<const T> data) {
    return GLsizeiptr(data.size() * sizeof(T));
}

// Piece `piece` of `values`, `per_piece` items a piece, into `buffer` bound at `target`: the
// first piece makes the buffer's storage for all of them (nothing written: the pieces write it).
// Returns the bytes written.
template <typename T>
std::size_t send_piece(GLenum target, GLuint buffer, std::span<const T> values, std::size_t piece,
                       std::size_t per_piece, bool make_storage) {
    glBindBuffer(target, buffer);
    if (make_storage)
        glBufferData(target, GLsizeiptr(std::max<std::size_t>(values.size(), 1) * sizeof(T)),
                     nullptr, GL_DYNAMIC_DRAW);
    const std::size_t first = std::min(piece * per_piece, values.size());
    const std::span<const T> part =
        values.subspan(first, std::min(per_piece, values.size() - first));
    if (!part.empty())
        glBufferSubData(target, GLintptr(first * sizeof(T)), bytes(part), part.data());
    glBindBuffer(target, 0);
    return std::size_t(bytes(part));
}

// The quality's buffer as the buffer texture the shaders fetch a triangle's value from
// (gl_PrimitiveID).
void attach_quality_texture(GLuint texture, GLuint buffer) {
    glBindTexture(GL_TEXTURE_BUFFER, texture);
    glTexBuffer(GL_TEXTURE_BUFFER, GL_R32F, buffer);
    glBindTexture(GL_TEXTURE_BUFFER, 0);
}

// Per-triangle quality into a buffer texture, in one piece. A buffer texture needs storage, so an
// empty mesh gets one unused value.
void upload_quality(GLuint buffer, GLuint texture, std::span<const float> quality) {
    send_piece(GL_TEXTURE_BUFFER, buffer, quality, 0, std::max<std::size_t>(quality.size(), 1),
               true);
    attach_quality_texture(texture, buffer);
}

} // namespace

void MeshView::upload(const Mesh& mesh, std::span<const float> quality,
                      std::span<const glm::vec3> normals) {
    // Everything checked before anything is sent: a mesh that throws leaves the view as it was.
    if (mesh.indices.size() % 3 != 0)
        throw std::invalid_argument("mesh index count is not a multiple of 3");
    check_indices(mesh.indices, mesh.positions.size());
    std::vector<float> computed_quality;
    quality = quality_of(mesh, quality, computed_quality);
    std::vector<glm::vec3> computed_normals;
    normals = normals_of(mesh, normals, computed_normals);
    for (int part = 0, parts = upload_parts(mesh); part < parts; ++part)
        upload_part(part, mesh, quality, normals);
}

namespace {

// Pieces of at most `per_piece` items for `count` items; one for none (a buffer still gets its
// storage).
std::size_t pieces(std::size_t count, std::size_t per_piece) {
    return std::max<std::size_t>(1, (count + per_piece - 1) / per_piece);
}

std::size_t vertex_pieces(const Mesh& mesh) {
    return pieces(mesh.positions.size(), MeshView::kPartVertices);
}

std::size_t index_blocks(const Mesh& mesh) {
    return pieces(mesh.triangle_count(), MeshView::kIndexBlockTriangles);
}

std::size_t quality_pieces(const Mesh& mesh) {
    return pieces(mesh.triangle_count(), MeshView::kPartValues);
}

} // namespace

int MeshView::upload_parts(const Mesh& mesh) {
    return int(2 * vertex_pieces(mesh) + index_blocks(mesh) + quality_pieces(mesh));
}

int MeshView::update_parts(const Mesh& mesh) {
    return int(2 * vertex_pieces(mesh) + quality_pieces(mesh));
}

int MeshView::quality_parts(const Mesh& mesh) {
    return int(quality_pieces(mesh));
}

// Part `part` of the positions, the normals and the quality, which upload_part and update_part
// send alike: the positions' pieces, the normals', then (after the indices, when uploading) the
// quality's. `storage`: the first piece of each makes its buffer's storage.
void MeshView::send_vertex_or_quality_part(int part, const Mesh& mesh,
                                           std::span<const float> quality,
                                           std::span<const glm::vec3> normals, bool storage) {
    const int vertex = int(vertex_pieces(mesh));
    if (part < vertex) {
        counters_.vertex_bytes += send_piece(
            GL_ARRAY_BUFFER, position_buffer_, std::span<const glm::vec3>(mesh.positions),
            std::size_t(part), kPartVertices, storage && part == 0);
    } else if (part < 2 * vertex) {
        std::vector<glm::vec3> computed;
        normals = normals_of(mesh, normals, computed);
        const auto piece = std::size_t(part - vertex);
        counters_.vertex_bytes += send_piece(GL_ARRAY_BUFFER, normal_buffer_, normals, piece,
                                             kPartVertices, storage && piece == 0);
    } else {
        std::vector<float> computed;
        quality = quality_of(mesh, quality, computed);
        const auto piece = std::size_t(part - 2 * vertex);
        const bool first = storage && piece == 0;
        // An empty mesh's storage holds one unused value: a buffer texture needs storage.
        counters_.quality_bytes +=
            send_piece(GL_TEXTURE_BUFFER, quality_buffer_, quality, piece, kPartValues, first);
        if (first) attach_quality_texture(quality_texture_, quality_buffer_);
    }
}

void MeshView::upload_part(int part, const Mesh& mesh, std::span<const float> quality,
                           std::span<const glm::vec3> normals) {
    if (vertex_array_ == 0) {
        glGenVertexArrays(1, &vertex_array_);
        glGenBuffers(1, &position_buffer_);
        glGenBuffers(1, &normal_buffer_);
        glGenBuffers(1, &quality_buffer_);
        glGenTextures(1, &quality_texture_);
    }
    const int vertex = int(vertex_pieces(mesh)), blocks = int(index_blocks(mesh));
    const int parts = upload_parts(mesh);
    if (part < 0 || part >= parts)
        throw std::invalid_argument("MeshView::upload_part: no part " + std::to_string(part));
    if (part == 0) {
        if (mesh.indices.size() % 3 != 0)
            throw std::invalid_argument("mesh index count is not a multiple of 3");
        triangles_ = vertices_ = preview_triangles_ = 0; // nothing to draw until complete
    }
    if (part < 2 * vertex) {
        send_vertex_or_quality_part(part, mesh, {}, normals, true);
        // Positions and normals in buffers of their own: a relaxation step replaces both straight
        // from the mesh's arrays.
        if (part == 0 || part == vertex) {
            const GLuint attribute = part == 0 ? 0 : 1;
            glBindVertexArray(vertex_array_);
            glBindBuffer(GL_ARRAY_BUFFER, part == 0 ? position_buffer_ : normal_buffer_);
            glEnableVertexAttribArray(attribute);
            glVertexAttribPointer(attribute, 3, GL_FLOAT, GL_FALSE, sizeof(glm::vec3), nullptr);
            glBindVertexArray(0);
            glBindBuffer(GL_ARRAY_BUFFER, 0);
        }
    } else if (part < 2 * vertex + blocks) {
        const std::size_t block = std::size_t(part - 2 * vertex), size = 3 * kIndexBlockTriangles;
        const std::size_t first = std::min(block * size, mesh.indices.size());
        const std::span<const std::uint32_t> indices =
            std::span<const std::uint32_t>(mesh.indices)
                .subspan(first, std::min(size, mesh.indices.size() - first));
        check_indices(indices, mesh.positions.size());
        if (index_buffers_.size() != std::size_t(blocks)) {
            glDeleteBuffers(GLsizei(index_buffers_.size()), index_buffers_.data());
            index_buffers_.assign(std::size_t(blocks), 0);
            glGenBuffers(GLsizei(blocks), index_buffers_.data());
        }
        // Through a neutral target: the element binding belongs to the vertex array, and the
        // draws bind each block there.
        glBindBuffer(GL_COPY_WRITE_BUFFER, index_buffers_[block]);
        glBufferData(GL_COPY_WRITE_BUFFER, bytes(indices), indices.data(), GL_DYNAMIC_DRAW);
        glBindBuffer(GL_COPY_WRITE_BUFFER, 0);
        counters_.index_bytes += std::size_t(bytes(indices));
    } else {
        send_vertex_or_quality_part(part - blocks, mesh, quality, {}, true);
        if (part == parts - 1) {
            triangles_ = mesh.triangle_count();
            vertices_ = mesh.positions.size();
            bounds_ = mesh_bounds(mesh);
            ++counters_.uploads;
        }
    }
    check_gl("MeshView::upload");
}

bool MeshView::can_update(const Mesh& mesh) const {
    return vertex_array_ != 0 && mesh.positions.size() == vertices_ &&
           mesh.indices.size() == triangles_ * 3;
}

bool MeshView::begin_update(const Mesh& mesh, std::span<const IndexRun> changed) {
    if (!can_update(mesh)) return false;
    const std::span<const std::uint32_t> indices = mesh.indices;
    for (const IndexRun& run : changed) {
        if (run.first > run.end || run.end > indices.size())
            throw std::invalid_argument("MeshView::update: index run [" +
                                        std::to_string(run.first) + ", " + std::to_string(run.end) +
                                        ") outside the mesh's " + std::to_string(indices.size()) +
                                        " indices");
        check_indices(indices.subspan(run.first, run.end - run.first), vertices_);
    }
    constexpr std::size_t kBlockIndices = 3 * kIndexBlockTriangles;
    for (const IndexRun& changed_run : changed) {
        // A run may cross from one block's buffer into the next.
        for (std::size_t b = changed_run.first, e = changed_run.end; b < e;) {
            const std::size_t block = b / kBlockIndices;
            const std::size_t end = std::min(e, (block + 1) * kBlockIndices);
            const std::span<const std::uint32_t> run = indices.subspan(b, end - b);
            glBindBuffer(GL_COPY_WRITE_BUFFER, index_buffers_[block]);
            glBufferSubData(GL_COPY_WRITE_BUFFER,
                            GLintptr((b - block * kBlockIndices) * sizeof(std::uint32_t)),
                            bytes(run), run.data());
            counters_.index_bytes += std::size_t(bytes(run));
            b = end;
        }
    }
    glBindBuffer(GL_COPY_WRITE_BUFFER, 0);
    check_gl("MeshView::update");
    return true;
}

void MeshView::update_part(int part, const Mesh& mesh, std::span<const float> quality,
                           std::span<const glm::vec3> normals) {
    const int parts = update_parts(mesh);
    if (part < 0 || part >= parts || !can_update(mesh))
        throw std::invalid_argument("MeshView::update_part: no part " + std::to_string(part) +
                                    " of this mesh");
    send_vertex_or_quality_part(part, mesh, quality, normals, false);
    if (part == parts - 1) {
        bounds_ = mesh_bounds(mesh);
        ++counters_.updates;
    }
    check_gl("MeshView::update");
}

bool MeshView::update(const Mesh& mesh, std::span<const IndexRun> changed,
                      std::span<const float> quality, std::span<const glm::vec3> normals) {
    if (!can_update(mesh)) return false;
    // Everything checked before anything is sent, as upload() does.
    std::vector<float> computed_quality;
    quality = quality_of(mesh, quality, computed_quality);
    std::vector<glm::vec3> computed_normals;
    normals = normals_of(mesh, normals, computed_normals);
    begin_update(mesh, changed);
    for (int part = 0, parts = update_parts(mesh); part < parts; ++part)
        update_part(part, mesh, quality, normals);
    return true;
}

void MeshView::set_preview(std::span<const std::uint32_t> indices, std::span<const float> quality) {
    if (vertex_array_ == 0) return;
    if (indices.empty()) {
        preview_triangles_ = 0;
        return;
    }
    if (indices.size() % 3 != 0 || quality.size() != indices.size() / 3)
        throw std::invalid_argument("preview: 3 indices and one quality per triangle");
    check_indices(indices, vertices_);
    if (preview_index_buffer_ == 0) {
        glGenBuffers(1, &preview_index_buffer_);
        glGenBuffers(1, &preview_quality_buffer_);
        glGenTextures(1, &preview_quality_texture_);
    }
    // Filled through a neutral target (the element binding belongs to the vertex array);
    // draw() binds it as the index buffer when drawing the preview.
    glBindBuffer(GL_COPY_WRITE_BUFFER, preview_index_buffer_);
    glBufferData(GL_COPY_WRITE_BUFFER, bytes(indices), indices.data(), GL_STATIC_DRAW);
    glBindBuffer(GL_COPY_WRITE_BUFFER, 0);
    preview_triangles_ = indices.size() / 3;
    counters_.index_bytes += std::size_t(bytes(indices));
    upload_quality(preview_quality_buffer_, preview_quality_texture_, quality);
    counters_.quality_bytes += std::size_t(bytes(quality));
    check_gl("MeshView::set_preview");
}

void MeshView::set_preview_quality(std::span<const float> quality) {
    if (preview_triangles_ == 0 || quality.size() != preview_triangles_) return;
    glBindBuffer(GL_TEXTURE_BUFFER, preview_quality_buffer_);
    glBufferSubData(GL_TEXTURE_BUFFER, 0, bytes(quality), quality.data());
    glBindBuffer(GL_TEXTURE_BUFFER, 0);
    counters_.quality_bytes += std::size_t(bytes(quality));
}

DrawStyle measure_style(DrawStyle style, ShapeMeasure measure, const MeasureScale& scale) {
    style.value_low = scale.low;
    style.value_high = scale.high;
    style.diverging = scale.diverging;
    if (is_distance(measure)) style.quality_threshold = -std::numeric_limits<float>::infinity();
    return style;
}

// ---------------------------------------------------------------------------------------------
// MeshRenderer

namespace {
// `source` with `#define SNERT_DIRECT` after its #version line.
std::string direct(const char* source) {
    std::string text = source;
    const std::size_t line_end = text.find('\n');
    text.insert(line_end == std::string::npos ? text.size() : line_end + 1,
                "#define SNERT_DIRECT 1\n");
    return text;
}
} // namespace

// Two mesh programs: with the geometry shader for the wireframe (it needs each triangle's
// barycentrics), without it for everything else.
struct MeshRenderer::Programs {
    Program wire{"mesh", shaders::kMeshVert, shaders::kMeshGeom, shaders::kMeshFrag};
    Program mesh{"mesh (direct)", direct(shaders::kMeshVert).c_str(), nullptr,
                 direct(shaders::kMeshFrag).c_str()};
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

namespace {
GLuint colormap_texture(const std::vector<std::uint8_t>& rgba) {
    GLuint texture = 0;
    glGenTextures(1, &texture);
    glBindTexture(GL_TEXTURE_1D, texture);
    glTexImage1D(GL_TEXTURE_1D, 0, GL_RGBA8, GLsizei(rgba.size() / 4), 0, GL_RGBA, GL_UNSIGNED_BYTE,
                 rgba.data());
    glTexParameteri(GL_TEXTURE_1D, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
    glTexParameteri(GL_TEXTURE_1D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    glTexParameteri(GL_TEXTURE_1D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    glBindTexture(GL_TEXTURE_1D, 0);
    return texture;
}
} // namespace

MeshRenderer::MeshRenderer() : programs_(std::make_unique<Programs>()) {
    colormap_texture_ = colormap_texture(viridis_rgba8(kColormapSize));
    diverging_texture_ = colormap_texture(cool_warm_rgba8(kColormapSize));
    glGenVertexArrays(1, &empty_vertex_array_);
    check_gl("MeshRenderer");
}

MeshRenderer::~MeshRenderer() {
    glDeleteVertexArrays(1, &empty_vertex_array_);
    glDeleteTextures(1, &colormap_texture_);
    glDeleteTextures(1, &diverging_texture_);
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
                        const DrawStyle& style, bool preview) const {
    draw_triangles(mesh, camera, viewport, style, preview && mesh.has_preview(), 0,
                   mesh.triangle_count());
}

void MeshRenderer::draw_part(const MeshView& mesh, const OrbitCamera& camera,
                             const Viewport& viewport, const DrawStyle& style, std::size_t first,
                             std::size_t count) const {
    first = std::min(first, mesh.triangle_count());
    count = std::min(count, mesh.triangle_count() - first);
    if (count > 0) draw_triangles(mesh, camera, viewport, style, false, first, count);
}

void MeshRenderer::draw_triangles(const MeshView& mesh, const OrbitCamera& camera,
                                  const Viewport& viewport, const DrawStyle& style, bool preview,
                                  std::size_t first, std::size_t count) const {
    if (mesh.empty() || viewport.width <= 0 || viewport.height <= 0) return;
    set_viewport(viewport);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_LESS);
    glDepthMask(GL_TRUE);
    glDisable(GL_BLEND);
    glDisable(GL_CULL_FACE);

    const Program& p = style.wireframe ? programs_->wire : programs_->mesh;
    p.use();
    const glm::mat4 view = camera.view();
    const glm::mat4 projection = camera.projection(viewport.aspect());
    glUniformMatrix4fv(p.uniform("view"), 1, GL_FALSE, glm::value_ptr(view));
    glUniformMatrix4fv(p.uniform("projection"), 1, GL_FALSE, glm::value_ptr(projection));
    glUniform1i(p.uniform("shading"), int(style.shading));
    glUniform3fv(p.uniform("surface_color"), 1, glm::value_ptr(style.surface_color));
    glUniform1f(p.uniform("quality_threshold"), style.quality_threshold);
    glUniform1f(p.uniform("value_low"), style.value_low);
    glUniform1f(p.uniform("value_high"), style.value_high);
    glUniform3fv(p.uniform("poor_color"), 1, glm::value_ptr(kPoorQualityColor));
    glUniform1i(p.uniform("wireframe"), style.wireframe ? 1 : 0);
    glUniform1f(p.uniform("line_half_width"), 0.5f * style.line_width);
    glUniform3fv(p.uniform("line_color"), 1, glm::value_ptr(style.line_color));
    glUniform1i(p.uniform("quality"), kQualityUnit);
    glUniform1i(p.uniform("colormap"), kColormapUnit);
    glActiveTexture(GL_TEXTURE0 + kQualityUnit);
    glBindTexture(GL_TEXTURE_BUFFER,
                  preview ? mesh.preview_quality_texture_ : mesh.quality_texture_);
    glActiveTexture(GL_TEXTURE0 + kColormapUnit);
    glBindTexture(GL_TEXTURE_1D, style.diverging ? diverging_texture_ : colormap_texture_);

    glBindVertexArray(mesh.vertex_array_);
    if (preview) {
        glUniform1i(p.uniform("first_triangle"), 0);
        glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, mesh.preview_index_buffer_);
        glDrawElements(GL_TRIANGLES, GLsizei(mesh.preview_triangles_ * 3), GL_UNSIGNED_INT,
                       nullptr);
    } else {
        // A call a block of indices; gl_PrimitiveID starts at 0 in each, the quality's index at
        // first_triangle.
        const std::size_t end = first + count, size = MeshView::kIndexBlockTriangles;
        for (std::size_t block = first / size; block * size < end; ++block) {
            const std::size_t from = std::max(first, block * size);
            const std::size_t to = std::min(end, (block + 1) * size);
            glUniform1i(p.uniform("first_triangle"), GLint(from));
            glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, mesh.index_buffers_[block]);
            // GL takes the offset into the bound index buffer as a pointer.
            const void* offset = reinterpret_cast<const void*>( // NOLINT(performance-no-int-to-ptr)
                static_cast<std::uintptr_t>((from - block * size) * 3 * sizeof(GLuint)));
            glDrawElements(GL_TRIANGLES, GLsizei((to - from) * 3), GL_UNSIGNED_INT, offset);
        }
    }
    glBindVertexArray(0);

    glBindTexture(GL_TEXTURE_1D, 0);
    glActiveTexture(GL_TEXTURE0 + kQualityUnit);
    glBindTexture(GL_TEXTURE_BUFFER, 0);
    glDisable(GL_SCISSOR_TEST);
    check_gl("MeshRenderer::draw");
}

} // namespace snert::render
