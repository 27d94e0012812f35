// The coarse preview drawn while the camera moves (app/preview_mesh.h).
#include <gtest/gtest.h>

#include "app/preview_mesh.h"
#include "core/marching_cubes.h"
#include "core/phantom.h"

using namespace snert;
using namespace snert::app;

TEST(PreviewMesh, HasAboutTheTargetCountOverTheMeshsOwnVertices) {
    const Phantom p = make_phantom("two-spheres", 48);
    const Mesh mesh = marching_cubes(p.volume, {p.iso, InsideIs::Above});
    const std::size_t target = mesh.triangle_count() / 8;
    const PreviewMesh preview = make_preview(mesh, target);
    const std::size_t triangles = preview.indices.size() / 3;
    EXPECT_EQ(preview.indices.size() % 3, 0u);
    EXPECT_EQ(preview.source.size(), triangles);
    EXPECT_GT(triangles, target / 3);
    EXPECT_LT(triangles, target * 3);
    for (std::uint32_t i : preview.indices) ASSERT_LT(i, mesh.vertex_count());
    for (std::uint32_t t : preview.source) ASSERT_LT(t, mesh.triangle_count());
    for (std::size_t t = 0; t < triangles; ++t) { // no collapsed triangle
        EXPECT_NE(preview.indices[3 * t], preview.indices[3 * t + 1]);
        EXPECT_NE(preview.indices[3 * t + 1], preview.indices[3 * t + 2]);
        EXPECT_NE(preview.indices[3 * t], preview.indices[3 * t + 2]);
    }
}

TEST(PreviewMesh, SmallMeshesHaveNone) {
    const Phantom p = make_phantom("sphere", 24);
    const Mesh mesh = marching_cubes(p.volume, {p.iso, InsideIs::Above});
    EXPECT_TRUE(make_preview(mesh, mesh.triangle_count()).indices.empty());
    EXPECT_TRUE(make_preview(Mesh{}).indices.empty());
}
