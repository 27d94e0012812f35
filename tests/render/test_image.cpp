// Images: PNG round trip, errors naming the file, and the snapshot comparison.
#include <filesystem>

#include <gtest/gtest.h>

#include "render/image.h"
#include "support/expect_error.h"
#include "support/temp_folder.h"

using namespace snert::render;
using namespace snert::test;

namespace {

Image gradient(int width, int height) {
    Image image{width, height, std::vector<std::uint8_t>(std::size_t(width) * height * 4)};
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x) {
            std::uint8_t* p = image.pixel(x, y);
            p[0] = std::uint8_t(x * 7), p[1] = std::uint8_t(y * 11), p[2] = 90, p[3] = 255;
        }
    return image;
}

} // namespace

TEST(Image, PngRoundTripIsExact) {
    const Image image = gradient(13, 7);
    const TempFolder temp("snert-image");
    const std::string path = temp.file("round.png");
    write_png(path, image);
    const Image back = read_png(path);
    EXPECT_EQ(back.width, 13);
    EXPECT_EQ(back.height, 7);
    EXPECT_EQ(back.rgba, image.rgba);
}

TEST(Image, ReadErrorsNameTheFile) {
    const TempFolder temp("snert-image");
    const std::string path = temp.file("not_a.png");
    write_text(path, "this is no PNG");
    expect_error<std::runtime_error>([&] { read_png(path); }, {path});
    EXPECT_THROW(read_png(temp.file("missing.png")), std::runtime_error);
}

TEST(Image, WriteToAMissingFolderFailsAndLeavesNothing) {
    const TempFolder temp("snert-image");
    const auto folder = temp.path() / "no_such_folder";
    EXPECT_THROW(write_png((folder / "x.png").string(), gradient(4, 4)), std::runtime_error);
    EXPECT_FALSE(std::filesystem::exists(folder));
    EXPECT_THROW(write_png(temp.file("bad.png"), Image{4, 4, {}}), std::invalid_argument);
    EXPECT_TRUE(std::filesystem::is_empty(temp.path()));
}

TEST(ImageComparison, CountsPixelsBeyondTheTolerance) {
    const Image a = gradient(10, 10);
    Image b = a;
    b.pixel(0, 0)[0] = std::uint8_t(a.pixel(0, 0)[0] + 5);   // within 8
    b.pixel(3, 4)[1] = std::uint8_t(a.pixel(3, 4)[1] + 9);   // beyond 8
    b.pixel(9, 9)[2] = std::uint8_t(a.pixel(9, 9)[2] + 100); // far beyond
    const ImageComparison c = compare_images(a, b, 8);
    EXPECT_EQ(c.pixels, 100u);
    EXPECT_EQ(c.differing, 2u);
    EXPECT_EQ(c.largest_difference, 100);
    EXPECT_DOUBLE_EQ(c.share(), 0.02);
    EXPECT_EQ(compare_images(a, b, 0).differing, 3u);
    EXPECT_EQ(compare_images(a, a, 0).differing, 0u);
}

TEST(ImageComparison, DiffImageMarksExactlyTheDifferingPixels) {
    const Image a = gradient(6, 5);
    Image b = a;
    b.pixel(2, 3)[0] = std::uint8_t(a.pixel(2, 3)[0] ^ 0x80);
    const Image diff = difference_image(a, b, 8);
    for (int y = 0; y < 5; ++y)
        for (int x = 0; x < 6; ++x) {
            const std::uint8_t* p = diff.pixel(x, y);
            const bool magenta = p[1] == 0 && p[0] > 127 && p[0] == p[2];
            EXPECT_EQ(magenta, x == 2 && y == 3) << x << "," << y;
        }
}

TEST(ImageComparison, DifferentSizesAreAnError) {
    EXPECT_THROW(compare_images(gradient(4, 4), gradient(4, 5), 0), std::invalid_argument);
    EXPECT_THROW(difference_image(gradient(4, 4), gradient(5, 4), 0), std::invalid_argument);
}
