// An offscreen framebuffer to draw into: multisampled colour + depth, resolved into a texture
// that can be read back as an Image or shown by ImGui::Image in the app.
#pragma once

#include "gl.h"
#include "image.h"

namespace snert::render {

class RenderTarget {
  public:
    // `samples` is the MSAA sample count (1 = none; clamped to what the driver offers).
    // Needs a current GL context; throws std::runtime_error when the framebuffer is
    // incomplete, std::invalid_argument for a size outside [1, GL_MAX_RENDERBUFFER_SIZE].
    RenderTarget(int width, int height, int samples = 4);
    ~RenderTarget();
    RenderTarget(const RenderTarget&) = delete;
    RenderTarget& operator=(const RenderTarget&) = delete;

    int width() const { return width_; }
    int height() const { return height_; }
    int samples() const { return samples_; }

    // Binds the drawing framebuffer and sets the viewport to the whole target.
    void bind() const;
    // Resolves the samples into the colour texture (call after drawing, before reading).
    void resolve() const;
    // RGBA8 texture with the resolved picture (GL convention: row 0 at the bottom).
    GLuint texture() const { return resolved_texture_; }
    // Resolves and reads the picture, rows top to bottom.
    Image read() const;

  private:
    void release();

    int width_ = 0, height_ = 0, samples_ = 1;
    GLuint draw_framebuffer_ = 0, color_renderbuffer_ = 0, depth_renderbuffer_ = 0;
    GLuint resolved_framebuffer_ = 0, resolved_texture_ = 0;
};

} // namespace snert::render
