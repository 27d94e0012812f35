// The slice view as a headless figure (snert render --slice): a title line, the view on the
// left and its legend (with the node inspection's values) on the right.
//
//   +-------------------------------+-----------------+
//   | title                                           |
//   +-------------------------------+-----------------+
//   |                               | Legend          |
//   |       slice view              | ...             |
//   |                               | Node ..., values|
//   +-------------------------------+-----------------+
//   caption (optional)
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "image.h"
#include "slice_view.h"

namespace snert::render {

struct SliceFigure {
    SliceScene scene;                 // scene.image is set from `pixels`
    std::vector<std::uint8_t> pixels; // the slice's RGBA (slice_pixels)
    SliceWindow window;
    std::string title;
    std::string caption; // empty: none
    int width = 1100;
    int height = 760;
    int samples = 4;
};

// Renders with the GL context current on this thread. Throws std::invalid_argument for a size
// below 320 x 240 or pixels that do not match the slice.
Image render_slice_figure(const SliceFigure& figure);

} // namespace snert::render
