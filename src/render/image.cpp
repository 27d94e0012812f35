#include "image.h"

#include <algorithm>
#include <cstdlib>
#include <stdexcept>

#include <stb_image.h>
#include <stb_image_write.h>

#include "io/atomic_file.h"

namespace snert::render {

void write_png(const std::string& path, const Image& image) {
    if (image.width <= 0 || image.height <= 0 ||
        image.rgba.size() != std::size_t(image.width) * std::size_t(image.height) * 4)
        throw std::invalid_argument("write_png: inconsistent image for " + path);
    write_path_atomically(path, [&](const std::string& temporary) {
        if (!stbi_write_png(temporary.c_str(), image.width, image.height, 4, image.rgba.data(),
                            image.width * 4))
            throw std::runtime_error(path + ": cannot write the PNG file");
    });
}

Image read_png(const std::string& path) {
    int width = 0, height = 0, channels = 0;
    stbi_uc* data = stbi_load(path.c_str(), &width, &height, &channels, 4);
    if (data == nullptr)
        throw std::runtime_error(path + ": cannot read the image (" + stbi_failure_reason() + ")");
    Image image;
    image.width = width;
    image.height = height;
    image.rgba.assign(data, data + std::size_t(width) * std::size_t(height) * 4);
    stbi_image_free(data);
    return image;
}

namespace {
void require_same_size(const Image& expected, const Image& actual) {
    if (expected.width != actual.width || expected.height != actual.height)
        throw std::invalid_argument(
            "image sizes differ: expected " + std::to_string(expected.width) + "x" +
            std::to_string(expected.height) + ", got " + std::to_string(actual.width) + "x" +
            std::to_string(actual.height));
}

int pixel_difference(const std::uint8_t* a, const std::uint8_t* b) {
    int largest = 0;
    for (int c = 0; c < 4; ++c) largest = std::max(largest, std::abs(int(a[c]) - int(b[c])));
    return largest;
}
} // namespace

ImageComparison compare_images(const Image& expected, const Image& actual, int tolerance) {
    require_same_size(expected, actual);
    ImageComparison result;
    result.pixels = std::size_t(expected.width) * std::size_t(expected.height);
    for (std::size_t i = 0; i < result.pixels; ++i) {
        const int d = pixel_difference(&expected.rgba[i * 4], &actual.rgba[i * 4]);
        result.largest_difference = std::max(result.largest_difference, d);
        if (d > tolerance) ++result.differing;
    }
    return result;
}

Image difference_image(const Image& expected, const Image& actual, int tolerance) {
    require_same_size(expected, actual);
    Image diff = expected;
    for (std::size_t i = 0; i < diff.rgba.size() / 4; ++i) {
        std::uint8_t* out = &diff.rgba[i * 4];
        const int d = pixel_difference(&expected.rgba[i * 4], &actual.rgba[i * 4]);
        if (d > tolerance) {
            const int level = 128 + std::min(127, d); // magenta, brighter when further off
            out[0] = std::uint8_t(level), out[1] = 0, out[2] = std::uint8_t(level);
        } else {
            // Faded: a quarter of the original grey level over white.
            const int grey = (int(out[0]) * 3 + int(out[1]) * 6 + int(out[2])) / 10;
            out[0] = out[1] = out[2] = std::uint8_t(255 - (255 - grey) / 4);
        }
        out[3] = 255;
    }
    return diff;
}

} // namespace snert::render
