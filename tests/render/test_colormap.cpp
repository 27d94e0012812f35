// The quality colormap: published end colours, order in lightness, clamping.
#include <cmath>

#include <gtest/gtest.h>

#include "render/colormap.h"

using namespace snert::render;

namespace {
float luminance(glm::vec3 c) {
    return 0.2126f * c.r + 0.7152f * c.g + 0.0722f * c.b;
}
} // namespace

TEST(Colormap, EndpointsAreViridis) {
    const glm::vec3 low = viridis(0.0f), high = viridis(1.0f), middle = viridis(0.5f);
    // #440154, #fde725 and #21908d (matplotlib's viridis at 0, 1 and 0.5).
    EXPECT_NEAR(low.r * 255.0f, 0x44, 0.01f);
    EXPECT_NEAR(low.g * 255.0f, 0x01, 0.01f);
    EXPECT_NEAR(low.b * 255.0f, 0x54, 0.01f);
    EXPECT_NEAR(high.r * 255.0f, 0xfd, 0.01f);
    EXPECT_NEAR(high.g * 255.0f, 0xe7, 0.01f);
    EXPECT_NEAR(high.b * 255.0f, 0x25, 0.01f);
    EXPECT_NEAR(middle.g * 255.0f, 0x90, 0.01f);
}

TEST(Colormap, ClampsOutOfRangeAndNaN) {
    EXPECT_EQ(viridis(-3.0f), viridis(0.0f));
    EXPECT_EQ(viridis(7.0f), viridis(1.0f));
    EXPECT_EQ(viridis(std::nanf("")), viridis(0.0f));
}

TEST(Colormap, LightnessGrowsMonotonically) {
    // A perceptual map is readable in grey: lightness must rise with quality everywhere.
    float previous = luminance(viridis(0.0f));
    for (int i = 1; i <= 200; ++i) {
        const float l = luminance(viridis(float(i) / 200.0f));
        EXPECT_GT(l, previous) << "at t = " << float(i) / 200.0f;
        previous = l;
    }
}

TEST(Colormap, TextureSamplesMatchTheFunction) {
    const std::vector<std::uint8_t> rgba = viridis_rgba8(256);
    ASSERT_EQ(rgba.size(), 256u * 4u);
    EXPECT_EQ(rgba[0], 0x44);
    EXPECT_EQ(rgba[2], 0x54);
    EXPECT_EQ(rgba[255 * 4 + 0], 0xfd);
    EXPECT_EQ(rgba[255 * 4 + 1], 0xe7);
    for (int i = 0; i < 256; ++i) EXPECT_EQ(rgba[std::size_t(i) * 4 + 3], 255);
    EXPECT_THROW(viridis_rgba8(1), std::invalid_argument);
}

TEST(Colormap, HighlightAndMethodColoursStandApart) {
    // The poor-quality red is far from every colour of the map.
    for (int i = 0; i <= 100; ++i)
        EXPECT_GT(glm::length(viridis(float(i) / 100.0f) - kPoorQualityColor), 0.45f);
    EXPECT_GT(glm::length(method_color(snert::Method::MarchingCubes) -
                          method_color(snert::Method::Snert)),
              0.5f);
}

// The diverging map of signed distances: blue below, a light grey at the middle (0), red
// above, both halves darker the farther from the middle.
TEST(Colormap, CoolWarmDivergesFromALightMiddle) {
    const glm::vec3 low = cool_warm(0.0f), middle = cool_warm(0.5f), high = cool_warm(1.0f);
    EXPECT_GT(low.b, low.r);
    EXPECT_GT(high.r, high.b);
    EXPECT_NEAR(middle.r, middle.b, 0.01f);
    EXPECT_GT(luminance(middle), luminance(cool_warm(0.25f)));
    EXPECT_GT(luminance(cool_warm(0.25f)), luminance(low));
    EXPECT_GT(luminance(middle), luminance(cool_warm(0.75f)));
    EXPECT_GT(luminance(cool_warm(0.75f)), luminance(high));
    EXPECT_EQ(cool_warm(std::nanf("")), middle);
    EXPECT_EQ(cool_warm(-2.0f), low);
    EXPECT_EQ(cool_warm_rgba8(256).size(), 256u * 4u);
}

// A measure's colour over its scale: a distance on its own range, without the poor red.
TEST(Colormap, MeasureColourFollowsTheScale) {
    const snert::MeasureScale signed_scale{-0.1f, 0.1f, true, "voxels"};
    EXPECT_EQ(measure_color(snert::ShapeMeasure::DistanceIso, 0.0f, 0.25f, signed_scale),
              cool_warm(0.5f));
    EXPECT_EQ(measure_color(snert::ShapeMeasure::DistanceIso, -0.1f, 0.25f, signed_scale),
              cool_warm(0.0f));
    const snert::MeasureScale far{0.0f, 2.0f, false, "voxels"};
    EXPECT_EQ(measure_color(snert::ShapeMeasure::DistanceOther, 0.1f, 0.25f, far), viridis(0.05f));
    // The shapes keep the red under the threshold.
    EXPECT_EQ(measure_color(snert::ShapeMeasure::Quality, 0.1f, 0.25f, {}), kPoorQualityColor);
    EXPECT_EQ(measure_color(snert::ShapeMeasure::Quality, 0.5f, 0.25f, {}), viridis(0.5f));
}
