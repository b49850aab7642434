// Tools and brush: what the left mouse does, on which map, and how.
#include "app/panels.h"

#include "document/command.h"

#include <imgui.h>

namespace plimsoll::editor {

void drawBrushPanel(EditorState& s, const Rect& area) {
    ImGui::SetNextWindowPos(ImVec2(area.x, area.y));
    ImGui::SetNextWindowSize(ImVec2(area.w, area.h));
    ImGui::Begin("Tools", nullptr,
                 ImGuiWindowFlags_NoMove | ImGuiWindowFlags_NoResize | ImGuiWindowFlags_NoCollapse);
    int tool = static_cast<int>(s.tool);
    ImGui::RadioButton("Navigate", &tool, static_cast<int>(Tool::Navigate));
    ImGui::SameLine();
    ImGui::RadioButton("Brush", &tool, static_cast<int>(Tool::Brush));
    ImGui::SameLine();
    ImGui::RadioButton("Fill island", &tool, static_cast<int>(Tool::FillIsland));
    ImGui::SameLine();
    ImGui::RadioButton("Pick", &tool, static_cast<int>(Tool::Pick));
    s.tool = static_cast<Tool>(tool);

    int channel = static_cast<int>(s.channel);
    if (ImGui::Combo("Map", &channel, "permeability\0density\0thickness\0")) {
        s.channel = static_cast<MapChannel>(channel);
        s.overlay = s.channel == MapChannel::Permeability ? Overlay::Permeability
                    : s.channel == MapChannel::Density    ? Overlay::Density
                                                          : Overlay::Thickness;
        s.overlaysDirty = true;
    }
    int mode = static_cast<int>(s.brush.mode);
    if (ImGui::Combo("Mode", &mode, "paint\0erase\0smooth\0")) s.brush.mode = static_cast<BrushMode>(mode);
    float radius = static_cast<float>(s.brush.radius);
    if (ImGui::SliderFloat("Radius (m)", &radius, 0.001f, 5.0f, "%.3f", ImGuiSliderFlags_Logarithmic)) {
        s.brush.radius = radius;
    }
    float strength = static_cast<float>(s.brush.strength);
    if (ImGui::SliderFloat("Strength", &strength, 0.0f, 1.0f)) s.brush.strength = strength;
    float value = static_cast<float>(s.brush.value);
    if (ImGui::SliderFloat("Value", &value, 0.0f, 1.0f)) s.brush.value = value;
    int falloff = static_cast<int>(s.brush.falloff);
    if (ImGui::Combo("Falloff", &falloff, "smooth\0linear\0constant\0")) {
        s.brush.falloff = static_cast<Falloff>(falloff);
    }
    ImGui::Checkbox("X mirror", &s.brush.mirrorX);
    ImGui::SameLine();
    const bool hasBody = s.selectedBody >= 0 &&
                         static_cast<std::size_t>(s.selectedBody) < s.document->bodyCount();
    if (ImGui::Button("Fill all") && hasBody) {
        s.execute(makeFillAllCommand(*s.document, s.selectedBody, s.channel, s.brush.value));
    }
    ImGui::SameLine();
    static int newSize = 1024;
    if (ImGui::Button("New map") && hasBody) {
        s.execute(makeNewMapCommand(*s.document, s.selectedBody, s.channel, newSize, newSize, 0.0,
                                    ""));
    }
    ImGui::SameLine();
    ImGui::SetNextItemWidth(80);
    ImGui::InputInt("px", &newSize, 0);
    newSize = std::clamp(newSize, 16, 8192);

    int overlay = static_cast<int>(s.overlay);
    if (ImGui::Combo("Overlay", &overlay,
                     "none\0permeability\0density\0thickness\0coverage\0position (PT)\0area (AVT)\0")) {
        s.overlay = static_cast<Overlay>(overlay);
        s.overlaysDirty = true;
    }
    ImGui::Checkbox("Water", &s.showWater);
    ImGui::SameLine();
    ImGui::Checkbox("Waves move", &s.animateWater);
    ImGui::SameLine();
    ImGui::Checkbox("Grid", &s.showGrid);
    ImGui::End();
}

}  // namespace plimsoll::editor
