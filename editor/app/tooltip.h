// One way to give a control its tooltip, for the panels and the dialogs.
#pragma once

#include <imgui.h>

namespace plimsoll::editor {

/// The last item's tooltip while it is hovered, also while it is disabled (where the text says
/// what would enable it).
inline void tooltip(const char* text) {
    if (ImGui::IsItemHovered(ImGuiHoveredFlags_AllowWhenDisabled)) ImGui::SetTooltip("%s", text);
}

}  // namespace plimsoll::editor
