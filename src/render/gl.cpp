#include "gl.h"

#include <cstdio>
#include <stdexcept>

namespace snert::render {

void load_gl(GlProcLoader loader) {
    if (loader == nullptr) throw std::runtime_error("no GL function loader given");
    // glad's loader type differs from GlProcLoader only in the name of the returned pointer.
    const int version = gladLoadGL(reinterpret_cast<GLADloadfunc>(loader));
    if (version == 0)
        throw std::runtime_error("cannot load OpenGL functions: no current context, or the "
                                 "driver does not provide OpenGL 3.3");
    if (GLAD_VERSION_MAJOR(version) < 3 ||
        (GLAD_VERSION_MAJOR(version) == 3 && GLAD_VERSION_MINOR(version) < 3))
        throw std::runtime_error("OpenGL 3.3 is needed, the context offers " +
                                 std::to_string(GLAD_VERSION_MAJOR(version)) + "." +
                                 std::to_string(GLAD_VERSION_MINOR(version)));
}

std::string gl_description() {
    auto text = [](GLenum name) {
        const auto* s = reinterpret_cast<const char*>(glGetString(name));
        return std::string(s ? s : "?");
    };
    return text(GL_VERSION) + " / " + text(GL_RENDERER);
}

namespace {
const char* gl_error_name(GLenum error) {
    switch (error) {
    case GL_INVALID_ENUM:
        return "GL_INVALID_ENUM";
    case GL_INVALID_VALUE:
        return "GL_INVALID_VALUE";
    case GL_INVALID_OPERATION:
        return "GL_INVALID_OPERATION";
    case GL_INVALID_FRAMEBUFFER_OPERATION:
        return "GL_INVALID_FRAMEBUFFER_OPERATION";
    case GL_OUT_OF_MEMORY:
        return "GL_OUT_OF_MEMORY";
    default:
        return "unknown";
    }
}
} // namespace

void check_gl(const char* where) {
    const GLenum first = glGetError();
    if (first == GL_NO_ERROR) return;
    // The flags are sticky per kind: drain them so the next check starts clean.
    for (int i = 0; i < 16 && glGetError() != GL_NO_ERROR; ++i) {
    }
    char code[16];
    std::snprintf(code, sizeof code, "0x%04x", first);
    throw std::runtime_error(std::string("GL error ") + code + " (" + gl_error_name(first) +
                             ") in " + where);
}

} // namespace snert::render
