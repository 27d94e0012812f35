// The one OpenGL function loader of snert: glad (GL 3.3 core), loaded through the current
// context's own GetProcAddress. The same loader serves a GLFW window, OSMesa and EGL in one
// process; call load_gl again whenever a context of another kind becomes current.
//
// Include this header before any other GL header (GLFW: define GLFW_INCLUDE_NONE, or include
// this first); glad refuses to follow another gl.h.
#pragma once

#include <glad/gl.h>

#include <string>

namespace snert::render {

// A GL entry point as every GetProcAddress returns it (glfwGetProcAddress, eglGetProcAddress,
// OSMesaGetProcAddress all have this signature, so the app passes glfwGetProcAddress as is).
using GlProc = void (*)();
using GlProcLoader = GlProc (*)(const char* name);

// Loads the GL 3.3 core functions of the context that is current on this thread. Throws
// std::runtime_error when the context lacks GL 3.3 (or no context is current).
void load_gl(GlProcLoader loader);

// "4.5 (Core Profile) Mesa 22.3.6 / llvmpipe (LLVM 15.0.6, 256 bits)" of the current context.
std::string gl_description();

// Throws std::runtime_error "GL error 0x0502 (GL_INVALID_OPERATION) in <where>" when the GL
// error flag is set; clears all pending errors.
void check_gl(const char* where);

} // namespace snert::render
