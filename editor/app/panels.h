// The editor's panels, one per file: each draws itself from the shared state.
#pragma once

#include "app/editor_state.h"
#include "app/tooltip.h"

#include <imgui.h>

namespace plimsoll::editor {

/// Begins one of the column's panels (tools, layers, inspector, UV view) over `area`: placed and
/// sized by the layout, so it neither moves, resizes nor collapses. End it with ImGui::End.
inline void beginColumnPanel(const char* title, const Rect& area, ImGuiWindowFlags extra = 0) {
    ImGui::SetNextWindowPos(ImVec2(area.x, area.y));
    ImGui::SetNextWindowSize(ImVec2(area.w, area.h));
    ImGui::Begin(
        title, nullptr,
        ImGuiWindowFlags_NoMove | ImGuiWindowFlags_NoResize | ImGuiWindowFlags_NoCollapse | extra);
}

/// 3D view input (navigation, painting) over state.viewport; the scene itself is drawn by the
/// frame loop before ImGui, into that rectangle.
void viewportInput(EditorState& state);
/// F / Shift+F's radial control (EditorState::RadialControl): starts it at the mouse, and its
/// keys (Enter keeps, Escape cancels). True when the key was the control's.
bool radialControlKey(EditorState& state, int key, bool shift);
void drawViewportOverlay(EditorState& state);  ///< view name, brush circle, hints
void drawBrushPanel(EditorState& state, const Rect& area);
/// The selected map's layers: add, remove, reorder, hide, opacity, blend mode, masks.
void drawLayersPanel(EditorState& state, const Rect& area);
void drawInspectorPanel(EditorState& state, const Rect& area);
void drawUvPanel(EditorState& state, const Rect& area);

// The water graph (graph_panel.cpp): its floating panel; its mouse tools in the 3D view (true:
// the graph took the mouse this frame); the box-select rectangle and drag readout over the
// view; the graph inside the see-through hull and the feed / segment colours in the scene;
// freeing its GL objects and waiting for its worker before the context goes.
void drawGraphPanel(EditorState& state);
bool graphViewportInput(EditorState& state);
/// Whether the graph panel edits in the view (its tools then have the left mouse before the
/// live preview's grab).
bool graphEditsInView(EditorState& state);
void drawGraphOverlay(EditorState& state);
void addGraphToScene(EditorState& state, RenderScene& scene);
void releaseGraphPanel(EditorState& state);
/// Whether the graph panel waits for a worker (automatic graph) or drags: the frame loop keeps
/// drawing.
bool graphPanelBusy(const EditorState& state);

/// The hydrostatics window for the selected body (hydrostatics_panel.cpp): beside a running
/// preview, for its scene; from Simulate > Hydrostatics at any time, for the document's.
void drawHydrostaticsPanel(EditorState& state);
/// Whether its figures are being computed on a worker (the frame loop keeps drawing).
bool hydrostaticsComputing();

/// Closes the open menus and popups above the topmost modal window (Esc, or the view taking
/// the wheel or the middle mouse while a menu is open); whether there were any (editor_app.cpp).
bool closeMenus();

/// Called right after Begin of a window that starts folded: a click on its title bar opens it
/// (ImGui opens it only from the arrow or a double-click).
void openWhenTitleClicked();

/// Whether the mouse is over the 3D view or another area with no ImGui window on top, a menu
/// being open or not: the wheel and the middle mouse reach the views under an open menu, which
/// ImGui's want-capture (true while any popup is open) would hold back.
bool mouseOverNoWindow();

/// Edit > Undo history: every step by name, the current one marked; a click undoes or redoes
/// to just after that step (history_panel.cpp).
void drawHistoryPanel(EditorState& state);

}  // namespace plimsoll::editor
