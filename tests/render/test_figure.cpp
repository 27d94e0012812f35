// The figure: its layout arithmetic, and a real headless render through ImGui's OpenGL 3
// backend (which only works when the backend is ours, loaded through glad, and not the copy
// prebuilt into libimgui.a).
#include <algorithm>
#include <cmath>

#include <gtest/gtest.h>

#include "gl_test.h"
#include "render/figure.h"
#include "render/panels.h"
#include "support/test_meshes.h"

using namespace snert;
using namespace snert::render;

namespace {

bool inside(const Rect& r, float width, float height) {
    return r.x >= 0 && r.y >= 0 && r.right() <= width + 0.5f && r.bottom() <= height + 0.5f;
}
bool overlap(const Rect& a, const Rect& b) {
    return a.x < b.right() && b.x < a.right() && a.y < b.bottom() && b.y < a.bottom();
}

MethodMetrics metrics_of(std::size_t triangles, double mean) {
    MethodMetrics m;
    m.triangles = triangles;
    m.vertices = 6;
    m.quality.mean = mean;
    m.quality.histogram[kQualityBins - 1] = triangles;
    return m;
}

} // namespace

TEST(FigureLayout, ComparisonRectanglesFitAndDoNotOverlap) {
    for (auto [w, h] : {std::pair{800, 640}, std::pair{1200, 900}, std::pair{1920, 1080}}) {
        const FigureRects r = layout_figure(w, h, 2, FigureLayout::Comparison, true, true);
        SCOPED_TRACE(std::to_string(w) + "x" + std::to_string(h));
        ASSERT_EQ(r.views.size(), 2u);
        ASSERT_EQ(r.titles.size(), 2u);
        std::vector<Rect> all = {r.views[0], r.views[1],  r.titles[0], r.titles[1],
                                 r.legend,   r.histogram, r.table,     r.caption};
        for (std::size_t i = 0; i < all.size(); ++i) {
            EXPECT_TRUE(inside(all[i], float(w), float(h))) << "rect " << i;
            EXPECT_GT(all[i].width, 0.0f) << "rect " << i;
            for (std::size_t j = i + 1; j < all.size(); ++j)
                EXPECT_FALSE(overlap(all[i], all[j])) << "rects " << i << " and " << j;
        }
        // Equal views side by side, titles above, panels below.
        EXPECT_EQ(r.views[0].width, r.views[1].width);
        EXPECT_EQ(r.views[0].height, r.views[1].height);
        EXPECT_LT(r.views[0].right(), r.views[1].x);
        EXPECT_LE(r.titles[0].bottom(), r.views[0].y);
        EXPECT_GE(r.histogram.y, r.views[0].bottom());
        const float table_font = r.table_groups > 1 ? small_font_size(r.font_px) : r.font_px;
        EXPECT_GE(r.table.height, metrics_table_height(r.table_groups, table_font) - 1.0f);
        // The views keep about half the height, whatever the table's length.
        EXPECT_GT(r.views[0].height, 0.4f * float(h));
    }
}

TEST(FigureLayout, WithoutLegendOrCaptionTheViewsGrow) {
    const FigureRects with = layout_figure(800, 600, 2, FigureLayout::Comparison, true, true);
    const FigureRects without = layout_figure(800, 600, 2, FigureLayout::Comparison, false, false);
    EXPECT_GT(without.views[0].height, with.views[0].height);
    EXPECT_EQ(without.legend.width, 0.0f);
    EXPECT_EQ(without.caption.height, 0.0f);
    const FigureRects single = layout_figure(600, 600, 1, FigureLayout::Views, false, false);
    ASSERT_EQ(single.views.size(), 1u);
    EXPECT_EQ(single.views[0].width, 600.0f);
    EXPECT_EQ(single.histogram.width, 0.0f);
}

TEST(FigureLayout, TooSmallImagesAreRejected) {
    EXPECT_THROW(layout_figure(100, 80, 2, FigureLayout::Comparison, false, false),
                 std::invalid_argument);
    EXPECT_THROW(layout_figure(800, 600, 0, FigureLayout::Views, false, false),
                 std::invalid_argument);
    EXPECT_THROW(layout_figure(64, 48, 2, FigureLayout::Views, false, false),
                 std::invalid_argument); // title bands leave no room for the views
    EXPECT_NO_THROW(layout_figure(120, 90, 2, FigureLayout::Views, false, false));
}

TEST(FigureLayout, FontSizeFollowsTheImage) {
    EXPECT_EQ(figure_font_size(840, 630), 15.0f);
    EXPECT_EQ(figure_font_size(100, 100), 10.0f);   // clamped below
    EXPECT_EQ(figure_font_size(9000, 9000), 40.0f); // clamped above
}

TEST(FigureLayout, ViewportsCountRowsFromTheBottom) {
    const Viewport v = to_viewport(Rect{10, 20, 100, 50}, 300);
    EXPECT_EQ(v.x, 10);
    EXPECT_EQ(v.y, 230);
    EXPECT_EQ(v.width, 100);
    EXPECT_EQ(v.height, 50);
}

TEST(Panels, NamesAndCounts) {
    EXPECT_EQ(label_of(Method::MarchingCubes), "Marching Cubes");
    EXPECT_EQ(label_of(Method::Snert), "SNERT");
    EXPECT_EQ(method_short_name(Method::MarchingCubes), "MC");
    EXPECT_EQ(method_short_name(Method::Gradient), "Gradient");
    EXPECT_EQ(format_count(0), "0");
    EXPECT_EQ(format_count(999), "999");
    EXPECT_EQ(format_count(1000), "1,000");
    EXPECT_EQ(format_count(1234567), "1,234,567");
}

class FigureTest : public GlTest {};

TEST_F(FigureTest, RendersViewsTitlesAndPanels) {
    const Mesh left = test::octahedron({0, 0, 0}, 10.0f),
               right = test::octahedron({0, 0, 0}, 10.0f);
    const MethodMetrics ml = metrics_of(8, 0.5), mr = metrics_of(8, 0.9);
    const FigureMethod methods[] = {{Method::MarchingCubes, "", &left, &ml},
                                    {Method::Snert, "", &right, &mr}};
    FigureOptions options;
    options.width = 400;
    options.height = 320;
    options.samples = 1;
    const Image image = render_figure(methods, options);
    ASSERT_EQ(image.width, 400);
    ASSERT_EQ(image.height, 320);
    const FigureRects r = layout_figure(400, 320, 2, FigureLayout::Comparison, false, false);

    // Dark text pixels in each title band: ImGui drew (its backend initialised under OSMesa).
    auto dark_pixels = [&](const Rect& rect) {
        int dark = 0;
        for (int y = int(rect.y); y < int(rect.bottom()); ++y)
            for (int x = int(rect.x); x < int(rect.right()); ++x)
                if (image.pixel(x, y)[0] < 100 && image.pixel(x, y)[1] < 100) ++dark;
        return dark;
    };
    EXPECT_GT(dark_pixels(r.titles[0]), 20);
    EXPECT_GT(dark_pixels(r.titles[1]), 20);
    EXPECT_GT(dark_pixels(r.table), 50);
    // The octahedron sits in the middle of each view, the backdrop in the corners.
    for (const Rect& v : r.views) {
        const std::uint8_t* centre = image.pixel(int(v.x + v.width / 2), int(v.y + v.height / 2));
        const std::uint8_t* corner = image.pixel(int(v.x + 2), int(v.y + 2));
        EXPECT_GT(int(centre[0]) - int(centre[2]), 8); // warm clay
        EXPECT_LT(int(corner[0]) - int(corner[2]), 3); // cool backdrop
    }
    // The histogram's bars: orange (MC) and blue (SNERT) are both there.
    int orange = 0, blue = 0;
    for (int y = int(r.histogram.y); y < int(r.histogram.bottom()); ++y)
        for (int x = int(r.histogram.x); x < int(r.histogram.right()); ++x) {
            const std::uint8_t* p = image.pixel(x, y);
            if (p[0] > 200 && p[1] > 130 && p[1] < 180 && p[2] < 40) ++orange;
            if (p[0] < 30 && p[1] > 95 && p[1] < 130 && p[2] > 160) ++blue;
        }
    EXPECT_GT(orange, 30);
    EXPECT_GT(blue, 30);
}

TEST_F(FigureTest, RejectsMissingMeshesAndBadZoom) {
    const Mesh mesh = test::octahedron({0, 0, 0}, 1.0f);
    FigureOptions options;
    options.width = 200;
    options.height = 160;
    EXPECT_THROW(render_figure({}, options), std::invalid_argument);
    const FigureMethod no_mesh[] = {{Method::MarchingCubes, "", nullptr, nullptr}};
    EXPECT_THROW(render_figure(no_mesh, options), std::invalid_argument);
    const FigureMethod one[] = {{Method::MarchingCubes, "", &mesh, nullptr}};
    options.zoom = 0.0f;
    EXPECT_THROW(render_figure(one, options), std::invalid_argument);
}
