// Shader programs for the editor's OpenGL 4.5 drawing (the renderer, the water graph).
#pragma once

#include "plimsoll/core/result.h"

#include <initializer_list>

namespace plimsoll::editor {

/// Compiles the vertex and the fragment shaders (of each stage the main one, then the
/// functions it declares and others define, such as water_view.vert's and .frag's) and links
/// them; needs a current context. The error carries the driver's log ("shader compile: ..." /
/// "shader link: ...").
Result<unsigned> linkGlProgram(std::initializer_list<const char*> vertexSources,
                               std::initializer_list<const char*> fragmentSources);

}  // namespace plimsoll::editor
