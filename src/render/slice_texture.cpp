#include "slice_texture.h"

#include <cstdint>
#include <stdexcept>

#include "gl.h"

namespace snert::render {

SliceTexture::~SliceTexture() {
    if (texture_ != 0) glDeleteTextures(1, &texture_);
}

void SliceTexture::upload(std::span<const std::uint8_t> rgba, int width, int height) {
    if (width < 1 || height < 1 || rgba.size() != std::size_t(width) * std::size_t(height) * 4)
        throw std::invalid_argument("SliceTexture: pixels do not match the size");
    if (texture_ == 0) glGenTextures(1, &texture_);
    glBindTexture(GL_TEXTURE_2D, texture_);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
    glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA8, width, height, 0, GL_RGBA, GL_UNSIGNED_BYTE,
                 rgba.data());
    glBindTexture(GL_TEXTURE_2D, 0);
    check_gl("SliceTexture::upload");
}

ImTextureID SliceTexture::id() const {
    return reinterpret_cast<ImTextureID>(static_cast<std::uintptr_t>(texture_));
}

} // namespace snert::render
