// A linked GLSL program (internal to the renderer).
#pragma once

#include <string>

#include "gl.h"

namespace snert::render {

class Program {
  public:
    // Compiles and links; `geometry` may be null. Throws std::runtime_error with the stage's
    // name and the driver's log when compiling or linking fails.
    Program(const char* name, const char* vertex, const char* geometry, const char* fragment);
    ~Program();
    Program(const Program&) = delete;
    Program& operator=(const Program&) = delete;

    void use() const { glUseProgram(id_); }
    // Location of a uniform; -1 (ignored by glUniform*) when the driver optimised it away.
    GLint uniform(const char* name) const { return glGetUniformLocation(id_, name); }
    GLuint id() const { return id_; }

  private:
    GLuint id_ = 0;
};

} // namespace snert::render
