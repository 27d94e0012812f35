// Drawing meshes for real on OSMesa: what lands in which pixel for each shading, the
// wireframe, the image orientation, and the upload checks.
#include <cmath>
#include <cstdint>
#include <initializer_list>
#include <span>
#include <stdexcept>
#include <vector>

#include <gtest/gtest.h>

#include "core/mesh.h"
#include "gl_test.h"
#include "render/mesh_view.h"
#include "render/target.h"
#include "support/test_meshes.h"

using namespace snert;
using namespace snert::render;

namespace {

// test::square(): in the z = 0 plane facing +z, two right triangles (quality 0.5 each).
using test::square;

// A camera in front of the square (on +z), framing it.
OrbitCamera camera_on_z(const Mesh& mesh) {
    OrbitCamera c = frame_bounds(mesh_bounds(mesh), ViewPreset::Top, 1.0f, 0.2f);
    return c;
}

glm::ivec3 rgb(const Image& image, int x, int y) {
    const std::uint8_t* p = image.pixel(x, y);
    return {p[0], p[1], p[2]};
}

} // namespace

class MeshViewTest : public GlTest {};

TEST_F(MeshViewTest, ShadingNamesRoundTrip) {
    for (Shading s : {Shading::Flat, Shading::Smooth, Shading::Quality})
        EXPECT_EQ(parse_shading(shading_name(s)), s);
    EXPECT_FALSE(parse_shading("phong").has_value());
}

TEST_F(MeshViewTest, VertexNormalsPointOutOfACounterClockwiseSquare) {
    const std::vector<glm::vec3> normals = vertex_normals(square());
    ASSERT_EQ(normals.size(), 4u);
    for (const glm::vec3& n : normals) EXPECT_NEAR(n.z, 1.0f, 1e-6f);
    Mesh lonely = square();
    lonely.positions.push_back({5, 5, 5}); // used by no triangle
    EXPECT_EQ(vertex_normals(lonely).back(), glm::vec3(0, 0, 1));
}

TEST_F(MeshViewTest, UploadRejectsBadIndicesAndQualityCounts) {
    MeshView view;
    Mesh bad = square();
    bad.indices.back() = 4;
    EXPECT_THROW(view.upload(bad), std::invalid_argument);
    const std::vector<float> one = {0.5f};
    EXPECT_THROW(view.upload(square(), one), std::invalid_argument);
    view.upload(square());
    EXPECT_EQ(view.triangle_count(), 2u);
    EXPECT_EQ(view.bounds().max, glm::vec3(1, 1, 0));
}

// Sent one part at a time (a part a frame in the app), the mesh draws nothing until the last
// part, then the picture of upload() in one call; a bad part throws.
TEST_F(MeshViewTest, UploadInPartsDrawsNothingUntilCompleteThenAsOneUpload) {
    RenderTarget target(32, 32, 1);
    MeshRenderer renderer;
    const Mesh mesh = square();
    const std::vector<float> quality = {0.0f, 1.0f};
    DrawStyle style;
    style.shading = Shading::Quality;
    const Viewport all{0, 0, 32, 32};
    const auto picture = [&](const MeshView& view) {
        renderer.draw_background(all, style);
        renderer.draw(view, camera_on_z(mesh), all, style);
        return target.read();
    };
    MeshView whole;
    whole.upload(mesh, quality);
    const Image expected = picture(whole);
    MeshView empty;
    const Image backdrop = picture(empty);
    ASSERT_NE(expected.rgba, backdrop.rgba);

    MeshView parts;
    parts.upload(test::square(2.0f)); // another mesh first: the parts replace it
    const int count = MeshView::upload_parts(mesh);
    ASSERT_EQ(count, 4); // positions, normals, one block of indices, quality
    for (int part = 0; part < count; ++part) {
        EXPECT_EQ(parts.counters().uploads, 1) << part;
        parts.upload_part(part, mesh, quality);
        if (part + 1 < count) {
            EXPECT_TRUE(parts.empty()) << part;
            EXPECT_EQ(picture(parts).rgba, backdrop.rgba) << "drawn after part " << part;
        }
    }
    EXPECT_EQ(parts.triangle_count(), 2u);
    EXPECT_EQ(parts.counters().uploads, 2);
    EXPECT_EQ(picture(parts).rgba, expected.rgba);

    const std::vector<float> one = {0.5f};
    EXPECT_THROW(parts.upload_part(3, mesh, one), std::invalid_argument);
    Mesh bad = mesh;
    bad.indices.back() = 4;
    EXPECT_THROW(parts.upload_part(2, bad), std::invalid_argument);
    EXPECT_THROW(parts.upload_part(count, mesh), std::invalid_argument);
}

namespace {

// Squares [first, end) of a strip of `squares` unit-wide squares along x (x from 0 to 1), each
// `height` tall and split into two triangles; squares [flip_first, flip_end) along their other
// diagonal.
Mesh strip_of_squares(std::uint32_t squares, std::uint32_t first, std::uint32_t end, float height,
                      std::uint32_t flip_first = 0, std::uint32_t flip_end = 0) {
    Mesh mesh;
    for (std::uint32_t i = first; i <= end; ++i) {
        const float x = float(i) / float(squares);
        mesh.positions.push_back({x, 0.0f, 0.0f});
        mesh.positions.push_back({x, height, 0.0f});
    }
    for (std::uint32_t i = 0; i < end - first; ++i) {
        const std::uint32_t a = 2 * i, b = a + 2, c = a + 3, d = a + 1;
        if (first + i >= flip_first && first + i < flip_end)
            mesh.indices.insert(mesh.indices.end(), {a, b, d, b, c, d});
        else
            mesh.indices.insert(mesh.indices.end(), {a, b, c, a, c, d});
    }
    return mesh;
}

// Pictures of a strip of squares seen from above, in quality shading (a triangle read with
// another's quality shows), 256 x 16 pixels.
struct StripPictures {
    explicit StripPictures(const Mesh& strip)
        : camera(frame_bounds(mesh_bounds(strip), ViewPreset::Top, 16.0f, 0.0f)) {
        style.shading = Shading::Quality;
    }
    std::vector<std::uint8_t> operator()(std::initializer_list<const MeshView*> views) {
        renderer.draw_background(all, style);
        for (const MeshView* view : views) renderer.draw(*view, camera, all, style);
        return target.read().rgba;
    }
    RenderTarget target{256, 16, 1};
    MeshRenderer renderer;
    DrawStyle style;
    Viewport all{0, 0, 256, 16};
    OrbitCamera camera;
};

} // namespace

// A mesh of two blocks of indices (kIndexBlockTriangles, a buffer each) is drawn a block a
// call: the picture of its two halves drawn as meshes of their own, each triangle in its own
// quality; a step that flips quads' diagonals across the blocks' border updates both blocks, as
// new buffers would.
TEST_F(MeshViewTest, IndicesInTwoBlocksDrawAsOneMesh) {
    // A strip of squares along x, the second block's triangles on its right half.
    const std::uint32_t squares = MeshView::kIndexBlockTriangles;
    const auto strip = [&](std::uint32_t first, std::uint32_t end, std::uint32_t flip_first = 0,
                           std::uint32_t flip_end = 0) {
        return strip_of_squares(squares, first, end, 0.05f, flip_first, flip_end);
    };
    const Mesh mesh = strip(0, squares);
    ASSERT_EQ(mesh.triangle_count(), 2 * MeshView::kIndexBlockTriangles);
    // Positions and normals in three pieces each (2^19 + 2 vertices), two blocks, the quality.
    EXPECT_EQ(MeshView::upload_parts(mesh), 3 + 3 + 2 + 1);
    // Qualities across the colour map, so that a block's triangle read with another's quality
    // shows.
    std::vector<float> quality(mesh.triangle_count());
    for (std::size_t t = 0; t < quality.size(); ++t) quality[t] = float(t % 97) / 96.0f;
    const std::span<const float> all_quality = quality;
    StripPictures picture(mesh);
    MeshView view;
    view.upload(mesh, quality);
    const std::vector<std::uint8_t> blocks = picture({&view});
    MeshView left, right;
    const std::size_t half = MeshView::kIndexBlockTriangles;
    left.upload(strip(0, squares / 2), all_quality.first(half));
    right.upload(strip(squares / 2, squares), all_quality.subspan(half));
    EXPECT_EQ(blocks, picture({&left, &right}));

    // From the middle of the first block to the middle of the second: one run of changed
    // indices, written into each block at its own offset.
    const Mesh flipped = strip(0, squares, squares / 4, 3 * squares / 4);
    const std::vector<IndexRun> runs = changed_index_runs(flipped.indices, mesh.indices);
    ASSERT_EQ(runs.size(), 1u);
    ASSERT_TRUE(view.update(flipped, runs, quality));
    MeshView fresh;
    fresh.upload(flipped, quality);
    const std::vector<std::uint8_t> updated = picture({&view});
    EXPECT_NE(updated, blocks) << "the flips change which quality a pixel shows";
    EXPECT_EQ(updated, picture({&fresh}));
}

// A mesh larger than a part in every array (positions, normals, indices, quality) goes in
// pieces of at most kPartBytes, uploaded and updated: the pictures and the bytes sent are those
// of upload() and update() in one call.
TEST_F(MeshViewTest, LargeMeshGoesInPiecesAsInOneCall) {
    const std::uint32_t squares = 400000;
    const auto strip = [&](float height, std::uint32_t flip_end) {
        return strip_of_squares(squares, 0, squares, height, 0, flip_end);
    };
    const Mesh mesh = strip(0.05f, 0);
    ASSERT_GT(mesh.positions.size(), 3 * MeshView::kPartVertices);
    ASSERT_GT(mesh.triangle_count(), MeshView::kPartValues);
    // 4 pieces of positions and of normals, 4 blocks of indices, 2 pieces of quality.
    EXPECT_EQ(MeshView::upload_parts(mesh), 4 + 4 + 4 + 2);
    EXPECT_EQ(MeshView::update_parts(mesh), 4 + 4 + 2);
    EXPECT_EQ(MeshView::quality_parts(mesh), 2);
    std::vector<float> quality(mesh.triangle_count());
    for (std::size_t t = 0; t < quality.size(); ++t) quality[t] = float(t % 89) / 88.0f;
    StripPictures pictures(mesh);
    const auto picture = [&](const MeshView& view) { return pictures({&view}); };
    MeshView whole, parts;
    whole.upload(mesh, quality);
    for (int part = 0; part < MeshView::upload_parts(mesh); ++part)
        parts.upload_part(part, mesh, quality);
    EXPECT_EQ(parts.counters().vertex_bytes, whole.counters().vertex_bytes);
    EXPECT_EQ(parts.counters().index_bytes, whole.counters().index_bytes);
    EXPECT_EQ(parts.counters().quality_bytes, whole.counters().quality_bytes);
    EXPECT_EQ(whole.counters().vertex_bytes, 2 * mesh.positions.size() * sizeof(glm::vec3));
    EXPECT_EQ(whole.counters().quality_bytes, quality.size() * sizeof(float));
    EXPECT_EQ(picture(parts), picture(whole));

    // Taller, and the first quarter's diagonals flipped.
    const Mesh moved = strip(0.08f, squares / 4);
    const std::vector<IndexRun> runs = changed_index_runs(moved.indices, mesh.indices);
    ASSERT_TRUE(whole.update(moved, runs, quality));
    ASSERT_TRUE(parts.begin_update(moved, runs));
    for (int part = 0; part < MeshView::update_parts(moved); ++part)
        parts.update_part(part, moved, quality);
    EXPECT_EQ(parts.counters().updates, 1);
    EXPECT_EQ(parts.counters().vertex_bytes, whole.counters().vertex_bytes);
    EXPECT_EQ(parts.counters().index_bytes, whole.counters().index_bytes);
    MeshView fresh;
    fresh.upload(moved, quality);
    const std::vector<std::uint8_t> updated = picture(parts);
    EXPECT_EQ(updated, picture(fresh));
    EXPECT_EQ(updated, picture(whole));
    EXPECT_THROW(parts.update_part(MeshView::update_parts(moved), moved), std::invalid_argument);
    EXPECT_FALSE(parts.begin_update(square(), {})) << "another topology";
}

// Blocks of 128 triangles (384 indices) compared; neighbouring changed blocks join into one run.
TEST(IndexRuns, AreTheChangedBlocksJoinedWhereTheyTouch) {
    std::vector<std::uint32_t> before(384 * 5 + 30);
    for (std::size_t i = 0; i < before.size(); ++i) before[i] = std::uint32_t(i % 1000);
    EXPECT_TRUE(changed_index_runs(before, before).empty());
    std::vector<std::uint32_t> now = before;
    now[10] += 1;          // block 0
    now[384 * 2 + 1] += 1; // blocks 2 and 3
    now[384 * 3 + 383] += 1;
    now.back() += 1; // the short last block
    const std::vector<IndexRun> runs = changed_index_runs(now, before);
    const std::vector<IndexRun> expected = {{0, 384}, {384 * 2, 384 * 4}, {384 * 5, now.size()}};
    EXPECT_EQ(runs, expected);
    now.pop_back();
    EXPECT_THROW(changed_index_runs(now, before), std::invalid_argument);
}

TEST_F(MeshViewTest, UpdateRefusesRunsOutsideTheMesh) {
    const Mesh mesh = square();
    MeshView view;
    view.upload(mesh);
    const IndexRun beyond[] = {{0, mesh.indices.size() + 3}};
    EXPECT_THROW(view.update(mesh, beyond), std::invalid_argument);
    const IndexRun reversed[] = {{3, 0}};
    EXPECT_THROW(view.update(mesh, reversed), std::invalid_argument);
    const IndexRun all[] = {{0, mesh.indices.size()}};
    EXPECT_TRUE(view.update(mesh, all));
    EXPECT_EQ(view.counters().index_bytes, 2 * mesh.indices.size() * sizeof(std::uint32_t));
}

TEST_F(MeshViewTest, FlatShadingLightsTheMeshOverTheBackdrop) {
    RenderTarget target(64, 64, 1);
    MeshRenderer renderer;
    MeshView view;
    const Mesh mesh = square();
    view.upload(mesh);
    DrawStyle style;
    style.shading = Shading::Flat;
    const Viewport all{0, 0, 64, 64};
    renderer.draw_background(all, style);
    renderer.draw(view, camera_on_z(mesh), all, style);
    const Image image = target.read();
    // The corner shows the backdrop's top colour (image row 0 is the top).
    const glm::ivec3 corner = rgb(image, 0, 0);
    EXPECT_NEAR(corner.r, std::lround(style.background_top.r * 255), 3);
    // The centre shows the surface: lit clay, warmer (red > blue) than the cool backdrop.
    const glm::ivec3 centre = rgb(image, 32, 32);
    EXPECT_GT(centre.r, centre.b + 10);
    EXPECT_GT(centre.r, 120);
    EXPECT_EQ(image.pixel(32, 32)[3], 255);
}

TEST_F(MeshViewTest, QualityShadingUsesTheColormapAndTheThreshold) {
    RenderTarget target(32, 32, 1);
    MeshRenderer renderer;
    MeshView view;
    const Mesh mesh = square();
    const std::vector<float> best = {1.0f, 1.0f};
    view.upload(mesh, best);
    DrawStyle style;
    style.shading = Shading::Quality;
    style.quality_threshold = 0.25f;
    const Viewport all{0, 0, 32, 32};
    renderer.draw_background(all, style);
    renderer.draw(view, camera_on_z(mesh), all, style);
    // q = 1: viridis' yellow end (lit, so only the hue is checked): much red and green, little
    // blue.
    glm::ivec3 c = rgb(target.read(), 16, 16);
    EXPECT_GT(c.r, 150);
    EXPECT_GT(c.g, 150);
    EXPECT_LT(c.b, 90);

    const std::vector<float> poor = {0.1f, 0.1f};
    view.upload(mesh, poor);
    renderer.draw_background(all, style);
    renderer.draw(view, camera_on_z(mesh), all, style);
    // Under the threshold: the highlight red.
    c = rgb(target.read(), 16, 16);
    EXPECT_GT(c.r, 150);
    EXPECT_LT(c.g, 80);
    EXPECT_LT(c.b, 80);
}

TEST_F(MeshViewTest, QualityIsLookedUpPerTriangle) {
    RenderTarget target(64, 64, 1);
    MeshRenderer renderer;
    MeshView view;
    const Mesh mesh = square();
    // Triangle 0 (below the diagonal from (-1,-1) to (1,1): the lower right) poor, triangle 1 best.
    const std::vector<float> quality = {0.0f, 1.0f};
    view.upload(mesh, quality);
    DrawStyle style;
    style.shading = Shading::Quality;
    const Viewport all{0, 0, 64, 64};
    renderer.draw_background(all, style);
    renderer.draw(view, camera_on_z(mesh), all, style);
    const Image image = target.read();
    // Top view: +x right, +y up in the image. Lower right is triangle 0, upper left triangle 1.
    const glm::ivec3 lower_right = rgb(image, 44, 44), upper_left = rgb(image, 20, 20);
    EXPECT_GT(lower_right.r, lower_right.g + 60); // red
    EXPECT_GT(upper_left.g, upper_left.b + 60);   // yellow
}

TEST_F(MeshViewTest, WireframeDarkensTheEdges) {
    RenderTarget target(64, 64, 1);
    MeshRenderer renderer;
    MeshView view;
    const Mesh mesh = square();
    view.upload(mesh);
    DrawStyle style;
    style.shading = Shading::Flat;
    const Viewport all{0, 0, 64, 64};
    renderer.draw_background(all, style);
    renderer.draw(view, camera_on_z(mesh), all, style);
    const Image plain = target.read();
    style.wireframe = true;
    renderer.draw_background(all, style);
    renderer.draw(view, camera_on_z(mesh), all, style);
    const Image wired = target.read();
    // The diagonal edge runs through the centre; a point inside a triangle stays unchanged.
    EXPECT_LT(rgb(wired, 32, 32).g, rgb(plain, 32, 32).g - 60);
    EXPECT_EQ(rgb(wired, 45, 45), rgb(plain, 45, 45));
}

TEST_F(MeshViewTest, ImagesReadBackTopRowFirst) {
    RenderTarget target(16, 16, 1);
    MeshRenderer renderer;
    DrawStyle style;
    style.background_top = style.background_bottom = glm::vec3(0.0f, 0.0f, 1.0f);
    glClearColor(1, 0, 0, 1);
    glClear(GL_COLOR_BUFFER_BIT);
    // GL's viewport origin is the bottom-left: this fills the upper half of the picture.
    renderer.draw_background(Viewport{0, 8, 16, 8}, style);
    const Image image = target.read();
    EXPECT_EQ(rgb(image, 3, 2), glm::ivec3(0, 0, 255));
    EXPECT_EQ(rgb(image, 3, 13), glm::ivec3(255, 0, 0));
}

TEST_F(MeshViewTest, TargetsRejectImpossibleSizes) {
    EXPECT_THROW(RenderTarget(0, 10), std::invalid_argument);
    EXPECT_THROW(RenderTarget(10, 1 << 20), std::invalid_argument);
    RenderTarget target(10, 12, 64); // samples clamp to what the driver offers
    EXPECT_GE(target.samples(), 1);
    EXPECT_EQ(target.read().rgba.size(), 10u * 12u * 4u);
}
