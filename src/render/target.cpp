#include "target.h"

#include <algorithm>
#include <cstring>
#include <stdexcept>
#include <string>

namespace snert::render {

namespace {
void require_complete(const char* which) {
    const GLenum status = glCheckFramebufferStatus(GL_FRAMEBUFFER);
    if (status != GL_FRAMEBUFFER_COMPLETE)
        throw std::runtime_error(std::string("the ") + which +
                                 " framebuffer is incomplete (status " + std::to_string(status) +
                                 ")");
}
} // namespace

RenderTarget::RenderTarget(int width, int height, int samples) : width_(width), height_(height) {
    GLint max_size = 0, max_samples = 1;
    glGetIntegerv(GL_MAX_RENDERBUFFER_SIZE, &max_size);
    glGetIntegerv(GL_MAX_SAMPLES, &max_samples);
    if (width < 1 || height < 1 || width > max_size || height > max_size)
        throw std::invalid_argument("image size " + std::to_string(width) + "x" +
                                    std::to_string(height) + " is outside 1.." +
                                    std::to_string(max_size));
    samples_ = std::clamp(samples, 1, std::max(1, int(max_samples)));

    glGenRenderbuffers(1, &color_renderbuffer_);
    glBindRenderbuffer(GL_RENDERBUFFER, color_renderbuffer_);
    glRenderbufferStorageMultisample(GL_RENDERBUFFER, samples_, GL_RGBA8, width, height);
    glGenRenderbuffers(1, &depth_renderbuffer_);
    glBindRenderbuffer(GL_RENDERBUFFER, depth_renderbuffer_);
    glRenderbufferStorageMultisample(GL_RENDERBUFFER, samples_, GL_DEPTH24_STENCIL8, width, height);
    glGenFramebuffers(1, &draw_framebuffer_);
    glBindFramebuffer(GL_FRAMEBUFFER, draw_framebuffer_);
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER,
                              color_renderbuffer_);
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_STENCIL_ATTACHMENT, GL_RENDERBUFFER,
                              depth_renderbuffer_);

    glGenTextures(1, &resolved_texture_);
    glBindTexture(GL_TEXTURE_2D, resolved_texture_);
    glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA8, width, height, 0, GL_RGBA, GL_UNSIGNED_BYTE, nullptr);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    glGenFramebuffers(1, &resolved_framebuffer_);
    try {
        require_complete("drawing");
        glBindFramebuffer(GL_FRAMEBUFFER, resolved_framebuffer_);
        glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D,
                               resolved_texture_, 0);
        require_complete("resolve");
        check_gl("RenderTarget");
    } catch (...) {
        release();
        throw;
    }
    bind();
}

RenderTarget::~RenderTarget() {
    release();
}

void RenderTarget::release() {
    glDeleteFramebuffers(1, &resolved_framebuffer_);
    glDeleteTextures(1, &resolved_texture_);
    glDeleteFramebuffers(1, &draw_framebuffer_);
    glDeleteRenderbuffers(1, &depth_renderbuffer_);
    glDeleteRenderbuffers(1, &color_renderbuffer_);
    resolved_framebuffer_ = resolved_texture_ = draw_framebuffer_ = 0;
    depth_renderbuffer_ = color_renderbuffer_ = 0;
}

void RenderTarget::bind() const {
    glBindFramebuffer(GL_FRAMEBUFFER, draw_framebuffer_);
    glViewport(0, 0, width_, height_);
}

void RenderTarget::resolve() const {
    glBindFramebuffer(GL_READ_FRAMEBUFFER, draw_framebuffer_);
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, resolved_framebuffer_);
    glBlitFramebuffer(0, 0, width_, height_, 0, 0, width_, height_, GL_COLOR_BUFFER_BIT,
                      GL_NEAREST);
    glBindFramebuffer(GL_FRAMEBUFFER, draw_framebuffer_);
}

Image RenderTarget::read() const {
    resolve();
    Image image;
    image.width = width_;
    image.height = height_;
    image.rgba.resize(std::size_t(width_) * std::size_t(height_) * 4);
    glBindFramebuffer(GL_READ_FRAMEBUFFER, resolved_framebuffer_);
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    glReadPixels(0, 0, width_, height_, GL_RGBA, GL_UNSIGNED_BYTE, image.rgba.data());
    glBindFramebuffer(GL_FRAMEBUFFER, draw_framebuffer_);
    check_gl("RenderTarget::read");
    // GL rows run bottom-up; PNG rows top-down.
    const std::size_t row = std::size_t(width_) * 4;
    for (int y = 0; y < height_ / 2; ++y)
        std::swap_ranges(image.rgba.begin() + std::ptrdiff_t(y * row),
                         image.rgba.begin() + std::ptrdiff_t((y + 1) * row),
                         image.rgba.begin() + std::ptrdiff_t((height_ - 1 - y) * row));
    // Surfaces are opaque; make the picture so regardless of what blending left in alpha.
    for (std::size_t i = 3; i < image.rgba.size(); i += 4) image.rgba[i] = 255;
    return image;
}

} // namespace snert::render
