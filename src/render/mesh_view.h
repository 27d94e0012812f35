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
#include "index_runs.h" // IndexRun
#include "normals.h"    // vertex_normals

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
    float quality_threshold = 0.25f; // Quality: triangles with q below are red
    // Quality shading of another measure (core/metrics.h's MeasureScale): the values' range
    // across the map, and the diverging map instead of viridis. NaN values (not measured) are
    // drawn in surface_color.
    float value_low = 0.0f, value_high = 1.0f;
    bool diverging = false;
    glm::vec3 surface_color = kSurfaceColor;             // Flat and Smooth (sRGB)
    glm::vec3 line_color{0.09f, 0.10f, 0.12f};           // wireframe (sRGB)
    float line_width = 1.2f;                             // wireframe line width in pixels
    glm::vec3 background_top{0.985f, 0.988f, 0.992f};    // sRGB
    glm::vec3 background_bottom{0.855f, 0.875f, 0.900f}; // sRGB
};

// `style` set to colour by `measure` over `scale` (its range and map), and no poor-quality red
// for a distance.
DrawStyle measure_style(DrawStyle style, ShapeMeasure measure, const MeasureScale& scale);

// A rectangle of the framebuffer in pixels, origin at the bottom-left (GL's convention).
struct Viewport {
    int x = 0, y = 0, width = 0, height = 0;
    float aspect() const { return height > 0 ? float(width) / float(height) : 1.0f; }
};

// What MeshView sent to the GPU so far (tests check that an update sends what changed only).
struct UploadCounters {
    int uploads = 0;              // whole meshes (new buffers)
    int updates = 0;              // positions, normals and quality of the same topology
    std::size_t vertex_bytes = 0; // positions and normals
    std::size_t index_bytes = 0;
    std::size_t quality_bytes = 0;
};

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
    // `normals` (one per vertex, as vertex_normals makes them) are computed here when empty.
    void upload(const Mesh& mesh, std::span<const float> quality = {},
                std::span<const glm::vec3> normals = {});
    // upload() in parts, for a software GL whose new storage is slow to make (the pages of
    // llvmpipe's copy are the kernel's fresh ones: about 2.5 ms a MB on a small VM, 60-80 ms for
    // a clinical mesh's positions at once), so that each step of the window sends one: the
    // positions, the normals, the indices and the quality, in that order, each in pieces of at
    // most kPartBytes (kPartVertices vertices, kIndexBlockTriangles triangles' indices,
    // kPartValues values); upload_parts(mesh) parts in all, each call with the same mesh. From
    // part 0 the view is empty (draws nothing, no preview) until the last part completes it.
    // Each part checks what it sends and throws std::invalid_argument as upload() does. The
    // normals and the quality are computed for each of their parts when not given: give them
    // for a large mesh.
    static constexpr std::size_t kPartBytes = std::size_t(3) << 20;
    static constexpr std::size_t kPartVertices = kPartBytes / sizeof(glm::vec3);
    static constexpr std::size_t kIndexBlockTriangles = kPartBytes / (3 * sizeof(std::uint32_t));
    static constexpr std::size_t kPartValues = kPartBytes / sizeof(float);
    static int upload_parts(const Mesh& mesh);
    void upload_part(int part, const Mesh& mesh, std::span<const float> quality = {},
                     std::span<const glm::vec3> normals = {});
    // The last quality_parts(mesh) parts of an upload or an update are the quality's: the
    // values shown go with those.
    static int quality_parts(const Mesh& mesh);
    // The same topology with new positions (a relaxation step): `mesh` has the vertex and
    // triangle counts of the mesh uploaded last, and `changed` holds the runs of its indices that
    // differ from that mesh's (changed_index_runs; none when the triangulation stayed). Sends the
    // positions, normals and quality, and of the indices only those runs. Returns false, changing
    // nothing, when the counts differ; throws std::invalid_argument for a run outside the mesh.
    bool update(const Mesh& mesh, std::span<const IndexRun> changed,
                std::span<const float> quality = {}, std::span<const glm::vec3> normals = {});
    // update() in parts: begin_update sends the changed runs at once (a few quads' diagonals a
    // step) and returns false, sending nothing, when the counts differ (then upload); then
    // update_parts(mesh) parts, the positions, the normals and the quality in pieces as
    // upload_part sends them. Until the last, the GPU holds a mix of two meshes: not to be drawn.
    bool begin_update(const Mesh& mesh, std::span<const IndexRun> changed);
    // Whether `mesh` has the counts of the mesh uploaded last (what update() needs).
    bool can_update(const Mesh& mesh) const;
    static int update_parts(const Mesh& mesh);
    void update_part(int part, const Mesh& mesh, std::span<const float> quality = {},
                     std::span<const glm::vec3> normals = {});
    const UploadCounters& counters() const { return counters_; }
    // A coarse stand-in over the same vertices, drawn instead of the mesh when asked (while
    // the camera moves): its triangles (3 indices each) and their quality. Empty: none.
    void set_preview(std::span<const std::uint32_t> indices, std::span<const float> quality);
    // Replaces the preview's quality only (the mesh was updated).
    void set_preview_quality(std::span<const float> quality);
    bool has_preview() const { return preview_triangles_ > 0; }

    std::size_t triangle_count() const { return triangles_; }
    const Bounds& bounds() const { return bounds_; }
    bool empty() const { return triangles_ == 0; }

  private:
    friend class MeshRenderer;
    void release();
    // Part `part` of the positions' pieces, then the normals', then the quality's (`storage`:
    // each buffer's first piece makes its storage, as an upload needs).
    void send_vertex_or_quality_part(int part, const Mesh& mesh, std::span<const float> quality,
                                     std::span<const glm::vec3> normals, bool storage);

    GLuint vertex_array_ = 0, position_buffer_ = 0, normal_buffer_ = 0;
    // The indices in blocks of kIndexBlockTriangles, a buffer each (drawn a block a call): no
    // one buffer's making takes a whole frame.
    std::vector<GLuint> index_buffers_;
    GLuint quality_buffer_ = 0, quality_texture_ = 0;
    GLuint preview_index_buffer_ = 0, preview_quality_buffer_ = 0, preview_quality_texture_ = 0;
    std::size_t triangles_ = 0, vertices_ = 0, preview_triangles_ = 0;
    Bounds bounds_;
    UploadCounters counters_;
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
    // Draws the mesh (or its preview, when it has one) into the viewport, depth-tested
    // against what the viewport holds.
    void draw(const MeshView& mesh, const OrbitCamera& camera, const Viewport& viewport,
              const DrawStyle& style, bool preview = false) const;
    // Draws `count` of the whole mesh's triangles from `first` (clamped to the mesh): a large
    // mesh drawn in parts over several frames into the same target gives the picture of one
    // draw, since the parts keep the triangles' order.
    void draw_part(const MeshView& mesh, const OrbitCamera& camera, const Viewport& viewport,
                   const DrawStyle& style, std::size_t first, std::size_t count) const;

  private:
    void draw_triangles(const MeshView& mesh, const OrbitCamera& camera, const Viewport& viewport,
                        const DrawStyle& style, bool preview, std::size_t first,
                        std::size_t count) const;
    struct Programs;
    std::unique_ptr<Programs> programs_;
    GLuint colormap_texture_ = 0, diverging_texture_ = 0;
    GLuint empty_vertex_array_ = 0; // the backdrop needs no vertex data, but core GL a VAO
};

} // namespace snert::render
