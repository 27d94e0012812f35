// A slice's pixels as an OpenGL texture that ImGui draws (nearest-neighbour, so each sample
// stays a sharp square when zoomed in). Needs a current GL context while it lives.
#pragma once

#include <cstdint>
#include <span>

#include <imgui.h>

namespace snert::render {

class SliceTexture {
  public:
    SliceTexture() = default;
    ~SliceTexture();
    SliceTexture(const SliceTexture&) = delete;
    SliceTexture& operator=(const SliceTexture&) = delete;

    // Uploads width x height RGBA8 pixels (row 0 first), replacing what was there.
    void upload(std::span<const std::uint8_t> rgba, int width, int height);
    ImTextureID id() const;
    bool empty() const { return texture_ == 0; }

  private:
    unsigned texture_ = 0;
};

} // namespace snert::render
