#include "fonts.h"

#include <imgui.h>

// The font files are assembled into read-only data by the assembler's .incbin, which is much
// faster to build than a generated array of a million bytes. SNERT_FONT_REGULAR and
// SNERT_FONT_BOLD are the files' paths, given by the build.
#define SNERT_EMBED_FILE(symbol, path)                                                             \
    __asm__(".section .rodata\n"                                                                   \
            ".balign 16\n"                                                                         \
            ".global " #symbol "\n" #symbol ":\n"                                                  \
            ".incbin \"" path "\"\n"                                                               \
            ".global " #symbol "_end\n" #symbol "_end:\n"                                          \
            ".previous\n")

SNERT_EMBED_FILE(snert_font_regular, SNERT_FONT_REGULAR);
SNERT_EMBED_FILE(snert_font_bold, SNERT_FONT_BOLD);

extern "C" {
extern const unsigned char snert_font_regular[], snert_font_regular_end[];
extern const unsigned char snert_font_bold[], snert_font_bold_end[];
}

namespace snert::render {

namespace {
ImFont* add_font(ImFontAtlas& atlas, const unsigned char* begin, const unsigned char* end,
                 float size_px) {
    ImFontConfig config;
    // The data lives in the executable: the atlas must neither free nor modify it.
    config.FontDataOwnedByAtlas = false;
    // Sharper small text than the default 3x horizontal oversampling blur.
    config.OversampleH = 2;
    config.OversampleV = 2;
    config.PixelSnapH = false;
    return atlas.AddFontFromMemoryTTF(const_cast<unsigned char*>(begin), int(end - begin), size_px,
                                      &config);
}
} // namespace

FigureFonts add_figure_fonts(ImFontAtlas& atlas, float size_px) {
    FigureFonts fonts;
    fonts.size = size_px;
    fonts.regular = add_font(atlas, snert_font_regular, snert_font_regular_end, size_px);
    fonts.bold = add_font(atlas, snert_font_bold, snert_font_bold_end, size_px);
    fonts.small =
        add_font(atlas, snert_font_regular, snert_font_regular_end, small_font_size(size_px));
    return fonts;
}

} // namespace snert::render
