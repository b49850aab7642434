// Edit > Undo history: the document's steps as a list, like Blender's and Painter's history
// panels. A click undoes or redoes one step at a time to just after the step clicked (the
// command layer's own undo and redo, byte for byte); "Original" is the state as opened.
#include "app/panels.h"

#include <string>

namespace plimsoll::editor {

void drawHistoryPanel(EditorState& s) {
    if (!s.showHistory) return;
    ImGui::SetNextWindowSize(ImVec2(280, 320), ImGuiCond_FirstUseEver);
    if (!ImGui::Begin("Undo history", &s.showHistory)) {
        ImGui::End();
        return;
    }
    const std::vector<std::string> names = s.document->historyNames();
    const std::size_t position = s.document->historyPosition();
    std::optional<std::size_t> jump;
    // Row i is the state after i steps; the current one selected, the undone ones greyed.
    auto row = [&](std::size_t i, const std::string& name) {
        const bool undone = i > position;
        if (undone)
            ImGui::PushStyleColor(ImGuiCol_Text, ImGui::GetStyleColorVec4(ImGuiCol_TextDisabled));
        const std::string label = name + "##step" + std::to_string(i);
        if (ImGui::Selectable(label.c_str(), i == position)) jump = i;
        if (undone) ImGui::PopStyleColor();
        if (i == position && s.historyScrollPending) {
            ImGui::SetScrollHereY(1.0f);
            s.historyScrollPending = false;
        }
    };
    row(0, "Original");
    tooltip("The project as it was opened");
    for (std::size_t i = 0; i < names.size(); ++i) row(i + 1, names[i]);
    ImGui::End();
    if (jump && *jump != position) s.jumpToHistory(*jump);
}

}  // namespace plimsoll::editor
