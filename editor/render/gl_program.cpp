// Shader programs for the editor's OpenGL 4.5 drawing (gl_program.h).
#include "render/gl_program.h"

#include <epoxy/gl.h>

#include <string>

namespace plimsoll::editor {

namespace {

Result<unsigned> compileStage(GLenum type, const char* source) {
    const GLuint shader = glCreateShader(type);
    glShaderSource(shader, 1, &source, nullptr);
    glCompileShader(shader);
    GLint ok = 0;
    glGetShaderiv(shader, GL_COMPILE_STATUS, &ok);
    if (!ok) {
        char log[2048];
        glGetShaderInfoLog(shader, sizeof log, nullptr, log);
        glDeleteShader(shader);
        return makeError(ErrorKind::kernelBuild, std::string("shader compile: ") + log);
    }
    return shader;
}

}  // namespace

Result<unsigned> linkGlProgram(const char* vertex, const char* fragment) {
    Result<unsigned> vs = compileStage(GL_VERTEX_SHADER, vertex);
    if (!vs) return vs.error();
    Result<unsigned> fs = compileStage(GL_FRAGMENT_SHADER, fragment);
    if (!fs) {
        glDeleteShader(*vs);
        return fs.error();
    }
    const GLuint program = glCreateProgram();
    glAttachShader(program, *vs);
    glAttachShader(program, *fs);
    glLinkProgram(program);
    glDeleteShader(*vs);
    glDeleteShader(*fs);
    GLint ok = 0;
    glGetProgramiv(program, GL_LINK_STATUS, &ok);
    if (!ok) {
        char log[2048];
        glGetProgramInfoLog(program, sizeof log, nullptr, log);
        glDeleteProgram(program);
        return makeError(ErrorKind::kernelBuild, std::string("shader link: ") + log);
    }
    return program;
}

}  // namespace plimsoll::editor
