// The one text form of raw options, read by the command line and the settings file.
#include <gtest/gtest.h>

#include <string>

#include "io/raw_options_text.h"

namespace snert {
namespace {

TEST(RawOptionsText, DimsAndSpacingRoundTrip) {
    glm::ivec3 dims{0};
    EXPECT_EQ(parse_raw_dims("64,64,93", dims), "");
    EXPECT_EQ(dims, glm::ivec3(64, 64, 93));
    EXPECT_EQ(raw_dims_text(dims), "64,64,93");
    glm::vec3 spacing{0.0f};
    EXPECT_EQ(parse_raw_spacing("3.2,3.2,1.5", spacing), "");
    EXPECT_EQ(spacing, glm::vec3(3.2f, 3.2f, 1.5f));
    EXPECT_EQ(raw_spacing_text(spacing), "3.2,3.2,1.5");
    const glm::vec3 odd{0.1f, 1.0f / 3.0f, 1e-7f};
    glm::vec3 back{0.0f};
    EXPECT_EQ(parse_raw_spacing(raw_spacing_text(odd), back), "");
    EXPECT_EQ(back, odd); // the shortest text that reads back exactly
}

TEST(RawOptionsText, BadTextSaysWhatIsWrongAndLeavesTheTarget) {
    glm::ivec3 dims{7, 8, 9};
    EXPECT_EQ(parse_raw_dims("4,4", dims), "takes three comma-separated values X,Y,Z, got '4,4'");
    EXPECT_EQ(parse_raw_dims("4,4,4,4", dims),
              "takes three comma-separated values X,Y,Z, got '4,4,4,4'");
    EXPECT_EQ(parse_raw_dims("4,x,4", dims), "'x' is not a number (in '4,x,4')");
    EXPECT_EQ(parse_raw_dims("4,,4", dims), "'' is not a number (in '4,,4')");
    EXPECT_EQ(parse_raw_dims("4,4,4.5", dims), "'4.5' is not a number (in '4,4,4.5')");
    EXPECT_EQ(parse_raw_dims(" 4,4,4", dims), "' 4' is not a number (in ' 4,4,4')");
    EXPECT_EQ(parse_raw_dims("4,0,4", dims), "every dimension must be at least 1, got '4,0,4'");
    EXPECT_EQ(dims, glm::ivec3(7, 8, 9));
    glm::vec3 spacing{1.0f};
    EXPECT_EQ(parse_raw_spacing("1,1,-2", spacing),
              "every spacing must be a positive number, got '1,1,-2'");
    EXPECT_EQ(parse_raw_spacing("1,inf,1", spacing),
              "every spacing must be a positive number, got '1,inf,1'");
    EXPECT_EQ(spacing, glm::vec3(1.0f));
}

} // namespace
} // namespace snert
