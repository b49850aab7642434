// The editor window (GLFW + OpenGL 4.5 core + Dear ImGui). Built only with
// PLIMSOLL_BUILD_EDITOR_GUI; otherwise a stub says so.
#pragma once

#include <string>

namespace plimsoll::editor {

/// Opens the window on `project` (empty: a new project, or the autosave to recover). Returns the
/// process exit code.
int runEditorWindow(const std::string& project);

}  // namespace plimsoll::editor
