// GL contexts the renderer draws in: offscreen OSMesa or EGL (surfaceless Mesa) for headless
// rendering, or a window's context made by the app (GLFW), all behind one small interface.
//
// Every context is OpenGL 3.3 core (Mesa answers with 4.5 core, which is a superset). Offscreen
// contexts have no usable default framebuffer: draw into a RenderTarget (target.h).
// A context is used from the thread that created it.
#pragma once

#include <functional>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "gl.h"

namespace snert::render {

class GlContext {
  public:
    virtual ~GlContext() = default;
    GlContext(const GlContext&) = delete;
    GlContext& operator=(const GlContext&) = delete;

    // Makes the context current on this thread and (re)loads the GL functions through its own
    // GetProcAddress. Throws std::runtime_error on failure.
    virtual void make_current() = 0;

    // "osmesa", "egl" or "window".
    virtual std::string_view backend() const = 0;

  protected:
    GlContext() = default;
};

struct GlVersion {
    int major = 3;
    int minor = 3;
};

// The offscreen back ends, in the order "auto" tries them.
std::vector<std::string> offscreen_backends(); // {"osmesa", "egl"}

// Creates an offscreen core-profile context and makes it current. `backend` is "osmesa",
// "egl" or "auto" (the first of offscreen_backends() that works).
// Throws std::invalid_argument for an unknown backend name, and std::runtime_error with a
// one-line reason when the context cannot be created ("auto": the reasons of both).
std::unique_ptr<GlContext> create_offscreen_context(std::string_view backend,
                                                    GlVersion version = {});

// Wraps a context somebody else made, such as a GLFW window's: `make_current` makes it
// current (e.g. [w] { glfwMakeContextCurrent(w); }) and `loader` is its GetProcAddress
// (glfwGetProcAddress). The wrapper does not own the context. Makes it current now.
std::unique_ptr<GlContext> adopt_context(std::function<void()> make_current, GlProcLoader loader);

} // namespace snert::render
