// Shader programs for the editor's OpenGL 4.5 drawing (gl_program.h).
#include "render/gl_program.h"

#include <epoxy/gl.h>

#include <string>
#include <utility>
#include <vector>

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

Result<unsigned> linkGlProgram(std::initializer_list<const char*> vertices,
                               std::initializer_list<const char*> fragments) {
    std::vector<GLuint> stages;
    auto deleteStages = [&] {
        for (GLuint s : stages) glDeleteShader(s);
    };
    for (auto [type, sources] :
         {std::pair{GL_VERTEX_SHADER, vertices}, std::pair{GL_FRAGMENT_SHADER, fragments}}) {
        for (const char* source : sources) {
            Result<unsigned> stage = compileStage(type, source);
            if (!stage) {
                deleteStages();
                return stage.error();
            }
            stages.push_back(*stage);
        }
    }
    const GLuint program = glCreateProgram();
    for (GLuint s : stages) glAttachShader(program, s);
    glLinkProgram(program);
    deleteStages();
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
