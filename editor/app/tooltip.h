// One way to give a control its tooltip, for the panels and the dialogs.
#pragma once

#include <imgui.h>

#include <string>

namespace plimsoll::editor {

/// The text of the tooltip the helper below put up this frame ("" when none). The frame loop
/// clears it at each frame's start and reports it (`edit --state-file`, `--run-seconds`), so
/// that a window test can see which tooltip a hover brought up: ImGui keeps no text to read
/// back once the tooltip is drawn.
inline std::string& tooltipShownThisFrame() {
    static std::string text;  // the UI thread's only: ImGui runs on it alone
    return text;
}

/// The last item's tooltip while it is hovered, also while it is disabled (where the text says
/// what would enable it). Wrapped at 35 characters' widths: one long line ran off an 800 px
/// window.
inline void tooltip(const char* text) {
    if (ImGui::IsItemHovered(ImGuiHoveredFlags_AllowWhenDisabled)) {
        ImGui::BeginTooltip();
        ImGui::PushTextWrapPos(ImGui::GetFontSize() * 35.0f);
        ImGui::TextUnformatted(text);
        ImGui::PopTextWrapPos();
        ImGui::EndTooltip();
        tooltipShownThisFrame() = text;
    }
}

}  // namespace plimsoll::editor
