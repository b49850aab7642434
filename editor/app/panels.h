// The editor's panels, one per file: each draws itself from the shared state.
#pragma once

#include "app/editor_state.h"

namespace plimsoll::editor {

/// 3D view input (navigation, painting) over state.viewport; the scene itself is drawn by the
/// frame loop before ImGui, into that rectangle.
void viewportInput(EditorState& state);
void drawViewportOverlay(EditorState& state);  ///< view name, brush circle, hints
void drawBrushPanel(EditorState& state, const Rect& area);
void drawInspectorPanel(EditorState& state, const Rect& area);
void drawUvPanel(EditorState& state, const Rect& area);

}  // namespace plimsoll::editor
