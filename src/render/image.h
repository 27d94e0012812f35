// RGBA8 images and PNG files (stb_image / stb_image_write from libstb).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace snert::render {

// 8-bit RGBA, rows top to bottom (the order of PNG files, not of glReadPixels).
struct Image {
    int width = 0;
    int height = 0;
    std::vector<std::uint8_t> rgba; // width * height * 4

    std::uint8_t* pixel(int x, int y) { return &rgba[(std::size_t(y) * width + x) * 4]; }
    const std::uint8_t* pixel(int x, int y) const {
        return &rgba[(std::size_t(y) * width + x) * 4];
    }
};

// Writes a PNG atomically (write_path_atomically): on failure the target is untouched and the
// std::runtime_error names the file.
void write_png(const std::string& path, const Image& image);

// Reads any PNG as RGBA8. Throws std::runtime_error naming the file and stb's reason.
Image read_png(const std::string& path);

// How far two images of the same size differ: a pixel differs when any of its channels
// differs by more than `tolerance` (0..255).
struct ImageComparison {
    std::size_t differing = 0;  // pixels beyond the tolerance
    std::size_t pixels = 0;     // width * height
    int largest_difference = 0; // over all channels and pixels
    double share() const { return pixels ? double(differing) / double(pixels) : 0.0; }
};
// Throws std::invalid_argument when the sizes differ (the message gives both).
ImageComparison compare_images(const Image& expected, const Image& actual, int tolerance);

// A picture of the differences for a person: the expected image faded to light grey, and every
// pixel beyond the tolerance in magenta (brighter the larger the difference).
Image difference_image(const Image& expected, const Image& actual, int tolerance);

} // namespace snert::render
