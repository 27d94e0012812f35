// The typefaces of the figures: DejaVu Sans regular and bold (Debian's fonts-dejavu-core),
// embedded in the executable at build time so text renders the same everywhere.
#pragma once

struct ImFont;
struct ImFontAtlas;

namespace snert::render {

struct FigureFonts {
    ImFont* regular = nullptr; // body text, table, axes
    ImFont* bold = nullptr;    // titles, table header
    ImFont* small = nullptr;   // tick labels, captions (0.85 of the regular size)
    float size = 0.0f;         // regular size in pixels
};

// The small face's size for a regular size, known before any atlas is built (for layouts).
inline float small_font_size(float size_px) {
    return 0.85f * size_px;
}

// Adds the three faces at `size_px` (regular) to `atlas`; the first becomes ImGui's default.
// The atlas must be (re)built afterwards (the OpenGL 3 backend does so on its next frame).
FigureFonts add_figure_fonts(ImFontAtlas& atlas, float size_px);

} // namespace snert::render
