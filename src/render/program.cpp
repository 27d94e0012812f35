#include "program.h"

#include <algorithm>
#include <stdexcept>
#include <vector>

namespace snert::render {

namespace {

std::string info_log(GLuint object, bool is_program) {
    GLint length = 0;
    if (is_program)
        glGetProgramiv(object, GL_INFO_LOG_LENGTH, &length);
    else
        glGetShaderiv(object, GL_INFO_LOG_LENGTH, &length);
    std::vector<char> log(std::size_t(std::max(length, 1)), '\0');
    if (is_program)
        glGetProgramInfoLog(object, length, nullptr, log.data());
    else
        glGetShaderInfoLog(object, length, nullptr, log.data());
    std::string text(log.data());
    while (!text.empty() && (text.back() == '\n' || text.back() == ' ')) text.pop_back();
    return text.empty() ? "(no log)" : text;
}

GLuint compile(const char* program, const char* stage, GLenum type, const char* source) {
    const GLuint shader = glCreateShader(type);
    glShaderSource(shader, 1, &source, nullptr);
    glCompileShader(shader);
    GLint ok = GL_FALSE;
    glGetShaderiv(shader, GL_COMPILE_STATUS, &ok);
    if (ok != GL_TRUE) {
        const std::string log = info_log(shader, false);
        glDeleteShader(shader);
        throw std::runtime_error(std::string("cannot compile the ") + program + " " + stage +
                                 " shader: " + log);
    }
    return shader;
}

} // namespace

Program::Program(const char* name, const char* vertex, const char* geometry, const char* fragment) {
    std::vector<GLuint> shaders;
    try {
        shaders.push_back(compile(name, "vertex", GL_VERTEX_SHADER, vertex));
        if (geometry) shaders.push_back(compile(name, "geometry", GL_GEOMETRY_SHADER, geometry));
        shaders.push_back(compile(name, "fragment", GL_FRAGMENT_SHADER, fragment));
    } catch (...) {
        for (GLuint s : shaders) glDeleteShader(s);
        throw;
    }
    id_ = glCreateProgram();
    for (GLuint s : shaders) glAttachShader(id_, s);
    glLinkProgram(id_);
    for (GLuint s : shaders) {
        glDetachShader(id_, s);
        glDeleteShader(s);
    }
    GLint ok = GL_FALSE;
    glGetProgramiv(id_, GL_LINK_STATUS, &ok);
    if (ok != GL_TRUE) {
        const std::string log = info_log(id_, true);
        glDeleteProgram(id_);
        throw std::runtime_error(std::string("cannot link the ") + name + " shaders: " + log);
    }
}

Program::~Program() {
    glDeleteProgram(id_);
}

} // namespace snert::render
