// GL error checks and shader program building.
#include "gl.hpp"
#include "polycut/common/error.hpp"

#include <cstdio>
#include <string>

namespace polycut::render::gl {

void check(const char* what) {
    const GLenum error = glGetError();
    if (error != GL_NO_ERROR) {
        char hex[16];
        std::snprintf(hex, sizeof hex, "0x%04x", error);
        throw Error("GL", std::string(what) + ": GL error " + hex);
    }
}

namespace {

GLuint compile(GLenum type, const char* source) {
    const GLuint shader = glCreateShader(type);
    glShaderSource(shader, 1, &source, nullptr);
    glCompileShader(shader);
    GLint ok = 0;
    glGetShaderiv(shader, GL_COMPILE_STATUS, &ok);
    if (!ok) {
        char log[2048] = {};
        glGetShaderInfoLog(shader, sizeof log, nullptr, log);
        glDeleteShader(shader);
        throw Error("GL", std::string("shader compilation failed: ") + log);
    }
    return shader;
}

} // namespace

GLuint link_program(const char* vertex_source, const char* fragment_source) {
    const GLuint vs = compile(GL_VERTEX_SHADER, vertex_source);
    const GLuint fs = compile(GL_FRAGMENT_SHADER, fragment_source);
    const GLuint program = glCreateProgram();
    glAttachShader(program, vs);
    glAttachShader(program, fs);
    glLinkProgram(program);
    glDeleteShader(vs);
    glDeleteShader(fs);
    GLint ok = 0;
    glGetProgramiv(program, GL_LINK_STATUS, &ok);
    if (!ok) {
        char log[2048] = {};
        glGetProgramInfoLog(program, sizeof log, nullptr, log);
        glDeleteProgram(program);
        throw Error("GL", std::string("program link failed: ") + log);
    }
    return program;
}

} // namespace polycut::render::gl
