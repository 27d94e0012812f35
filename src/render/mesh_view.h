// Drawing a snert::Mesh: MeshView holds one mesh on the GPU, MeshRenderer draws mesh views
// into a viewport with a camera and a style.
//
// Shadings: Flat (one normal per triangle: facets and stair steps stay visible), Smooth
// (area-weighted vertex normals) and Quality (each triangle in the viridis colour of its
// quality, smallest / largest angle; triangles under a threshold in a highlight red). Any of
// them can carry a wireframe overlay drawn in the same pass. Both sides of a surface are lit.
// Everything here needs a current GL context (context.h) and must be used on its thread.
#pragma once

#include <cstddef>
#include <memory>
#include <optional>
#include <span>
#include <string_view>
#include <vector>

#include <glm/glm.hpp>

#include "camera.h"
#include "colormap.h"
#include "core/mesh.h"
#include "gl.h"

namespace snert::render {

enum class Shading { Flat, Smooth, Quality };

// "flat", "smooth", "quality"; std::nullopt for anything else.
std::optional<Shading> parse_shading(std::string_view name);
const char* shading_name(Shading shading);
// The same names in the table of core/names.h (parse_name, name_of, name_choices).
std::span<const Named<Shading>> name_table(Shading);

struct DrawStyle {
    Shading shading = Shading::Smooth;
    bool wireframe = false;
    float quality_threshold = 0.25f;                     // Quality: triangles with q below are red
    glm::vec3 surface_color = kSurfaceColor;             // Flat and Smooth (sRGB)
    glm::vec3 line_color{0.09f, 0.10f, 0.12f};           // wireframe (sRGB)
    float line_width = 1.2f;                             // wireframe line width in pixels
    glm::vec3 background_top{0.985f, 0.988f, 0.992f};    // sRGB
    glm::vec3 background_bottom{0.855f, 0.875f, 0.900f}; // sRGB
};

// A rectangle of the framebuffer in pixels, origin at the bottom-left (GL's convention).
struct Viewport {
    int x = 0, y = 0, width = 0, height = 0;
    float aspect() const { return height > 0 ? float(width) / float(height) : 1.0f; }
};

// Area-weighted vertex normals (unit length; +z for a vertex with no area around it), the
// normals of smooth shading. Winding gives the direction: counter-clockwise seen from outside.
std::vector<glm::vec3> vertex_normals(const Mesh& mesh);

// One mesh on the GPU: positions, smooth normals, indices and per-triangle quality.
class MeshView {
  public:
    MeshView();
    ~MeshView();
    MeshView(MeshView&& other) noexcept;
    MeshView& operator=(MeshView&& other) noexcept;
    MeshView(const MeshView&) = delete;
    MeshView& operator=(const MeshView&) = delete;

    // Replaces the GPU copy with `mesh`. `quality` has one value per triangle, in triangle
    // order (as triangle_quality returns it); when empty it is computed here. Throws
    // std::invalid_argument when its size does not match or an index is out of range.
    void upload(const Mesh& mesh, std::span<const float> quality = {});

    std::size_t triangle_count() const { return triangles_; }
    const Bounds& bounds() const { return bounds_; }
    bool empty() const { return triangles_ == 0; }

  private:
    friend class MeshRenderer;
    void release();

    GLuint vertex_array_ = 0, vertex_buffer_ = 0, index_buffer_ = 0;
    GLuint quality_buffer_ = 0, quality_texture_ = 0;
    std::size_t triangles_ = 0;
    Bounds bounds_;
};

// The shader programs and the colormap texture; one per GL context.
class MeshRenderer {
  public:
    MeshRenderer(); // compiles the embedded shaders; throws std::runtime_error on failure
    ~MeshRenderer();
    MeshRenderer(const MeshRenderer&) = delete;
    MeshRenderer& operator=(const MeshRenderer&) = delete;

    // Fills the viewport with the style's backdrop gradient and clears its depth.
    void draw_background(const Viewport& viewport, const DrawStyle& style) const;
    // Draws the mesh into the viewport (depth-tested against what the viewport holds).
    void draw(const MeshView& mesh, const OrbitCamera& camera, const Viewport& viewport,
              const DrawStyle& style) const;

  private:
    struct Programs;
    std::unique_ptr<Programs> programs_;
    GLuint colormap_texture_ = 0;
    GLuint empty_vertex_array_ = 0; // the backdrop needs no vertex data, but core GL a VAO
};

} // namespace snert::render
