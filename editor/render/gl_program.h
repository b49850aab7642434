// Shader programs for the editor's OpenGL 4.5 drawing (the renderer, the water graph).
#pragma once

#include "plimsoll/core/result.h"

namespace plimsoll::editor {

/// Compiles a vertex and a fragment shader and links them; needs a current context. The
/// error carries the driver's log ("shader compile: ..." / "shader link: ...").
Result<unsigned> linkGlProgram(const char* vertexSource, const char* fragmentSource);

}  // namespace plimsoll::editor
