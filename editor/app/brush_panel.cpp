// Tools and brush: what the left mouse does, on which map, and how.
#include "app/panels.h"

#include "document/brush_presets.h"
#include "document/command.h"

#include <imgui.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

namespace plimsoll::editor {

namespace {

/// Blender's custom falloff curve: the weight (up) against the distance from the dab's centre
/// over the radius (across, centre at the left). Drag a point to move it (the end points
/// move up and down only), click empty space to add one, right-click a point to remove it;
/// the buttons below start from a preset's shape.
void falloffCurveEditor(FalloffCurve& curve) {
    static int dragged = -1;  // the point being dragged (one Tools panel)
    const float side = std::clamp(ImGui::GetContentRegionAvail().x, 120.0f, 320.0f);
    const ImVec2 size(side, side * 0.55f);
    const ImVec2 origin = ImGui::GetCursorScreenPos();
    ImGui::InvisibleButton("##falloff_curve", size,
                           ImGuiButtonFlags_MouseButtonLeft | ImGuiButtonFlags_MouseButtonRight);
    tooltip(
        "The custom falloff: weight up, distance from the centre across (rim at the right).\n"
        "Drag a point, click to add one, right-click to remove one.");
    const float pad = 6.0f;
    auto toScreen = [&](const Eigen::Vector2d& p) {
        return ImVec2(origin.x + pad + float(p.x()) * (size.x - 2 * pad),
                      origin.y + pad + float(1.0 - p.y()) * (size.y - 2 * pad));
    };
    auto toCurve = [&](const ImVec2& m) {
        return Eigen::Vector2d(
            std::clamp((m.x - origin.x - pad) / (size.x - 2 * pad), 0.0f, 1.0f),
            std::clamp(1.0f - (m.y - origin.y - pad) / (size.y - 2 * pad), 0.0f, 1.0f));
    };
    const ImVec2 mouse = ImGui::GetIO().MousePos;
    int hovered = -1;
    for (std::size_t i = 0; i < curve.points.size(); ++i) {
        const ImVec2 p = toScreen(curve.points[i]);
        if (std::hypot(p.x - mouse.x, p.y - mouse.y) < 7.0f) hovered = static_cast<int>(i);
    }
    if (ImGui::IsItemActivated() && ImGui::IsMouseClicked(ImGuiMouseButton_Left)) {
        dragged = hovered;
        if (dragged < 0 && curve.points.size() < static_cast<std::size_t>(kMaxFalloffPoints)) {
            const Eigen::Vector2d at = toCurve(mouse);
            const auto it =
                std::upper_bound(curve.points.begin(), curve.points.end(), at.x(),
                                 [](double x, const Eigen::Vector2d& p) { return x < p.x(); });
            dragged = static_cast<int>(curve.points.insert(it, at) - curve.points.begin());
        }
    }
    if (dragged >= 0 && ImGui::IsItemActive() && ImGui::IsMouseDown(ImGuiMouseButton_Left)) {
        const std::size_t i = static_cast<std::size_t>(dragged);
        Eigen::Vector2d at = toCurve(mouse);
        // Points keep their order; the ends stay at the centre and the rim.
        if (i == 0)
            at.x() = 0;
        else if (i + 1 == curve.points.size())
            at.x() = 1;
        else
            at.x() =
                std::clamp(at.x(), curve.points[i - 1].x() + 0.01, curve.points[i + 1].x() - 0.01);
        curve.points[i] = at;
    }
    if (!ImGui::IsMouseDown(ImGuiMouseButton_Left)) dragged = -1;
    if (ImGui::IsItemHovered() && ImGui::IsMouseClicked(ImGuiMouseButton_Right) && hovered > 0 &&
        hovered + 1 < static_cast<int>(curve.points.size())) {
        curve.points.erase(curve.points.begin() + hovered);
    }
    ImDrawList* draw = ImGui::GetWindowDrawList();
    draw->AddRectFilled(origin, ImVec2(origin.x + size.x, origin.y + size.y),
                        IM_COL32(30, 32, 36, 255));
    for (int g = 1; g < 4; ++g) {
        const float f = g / 4.0f;
        draw->AddLine(toScreen({f, 0}), toScreen({f, 1}), IM_COL32(60, 62, 68, 255));
        draw->AddLine(toScreen({0, f}), toScreen({1, f}), IM_COL32(60, 62, 68, 255));
    }
    ImVec2 previous = toScreen({0, curve(0)});
    for (int k = 1; k <= 64; ++k) {
        const double x = k / 64.0;
        const ImVec2 next = toScreen({x, curve(x)});
        draw->AddLine(previous, next, IM_COL32(235, 200, 90, 255), 2.0f);
        previous = next;
    }
    for (std::size_t i = 0; i < curve.points.size(); ++i) {
        const bool hot = static_cast<int>(i) == hovered || static_cast<int>(i) == dragged;
        draw->AddCircleFilled(toScreen(curve.points[i]), hot ? 5.0f : 4.0f,
                              hot ? IM_COL32(255, 255, 255, 255) : IM_COL32(200, 200, 200, 255));
    }
    // Blender's presets as starting shapes.
    for (int i = 0; i < kFalloffPresetCount; ++i) {
        const Falloff f = static_cast<Falloff>(i);
        if (i % 4 != 0) ImGui::SameLine();
        if (ImGui::SmallButton(falloffName(f))) curve = FalloffCurve::preset(f);
        tooltip("Start the curve from this preset's shape");
    }
}

/// The brush's alpha / stencil image: a grey PNG whose values scale each dab's weight.
void alphaControls(EditorState& s) {
    static std::string typed;  // the path being typed (one Tools panel)
    if (typed.empty() && !s.brush.alphaPath.empty()) typed = s.brush.alphaPath;
    char buffer[512];
    std::snprintf(buffer, sizeof buffer, "%s", typed.c_str());
    ImGui::SetNextItemWidth(-110);
    if (ImGui::InputText("##alpha", buffer, sizeof buffer)) typed = buffer;
    tooltip(
        "A grey PNG laid over each dab, upright on screen: white paints, black does not "
        "(Painter's alpha, Blender's stencil)");
    ImGui::SameLine();
    if (ImGui::Button("Alpha")) {
        if (Status loaded = loadBrushAlpha(s.brush, typed); loaded) {
            s.status = "Brush alpha: " + typed;
        } else {
            s.status = loaded.error().message;
        }
    }
    tooltip("Load the image named on the left as the brush's alpha");
    ImGui::SameLine();
    ImGui::BeginDisabled(!s.brush.alpha);
    if (ImGui::Button("None")) {
        s.brush.alpha.reset();
        s.brush.alphaPath.clear();
        typed.clear();
    }
    ImGui::EndDisabled();
    tooltip("Paint without an alpha image");
}

/// The brush presets: the built-in ones and the painter's own (kept in the settings file), a
/// Save... that keeps the current tip under a name, and Delete for one of the painter's. The
/// combo shows the preset the brush matches, or "custom".
void brushPresetControls(EditorState& s) {
    static char typed[64];       // the name of the preset being saved (one Tools panel)
    static std::string refusal;  // why the last Save was refused, shown in its popup
    const BrushPreset* current = nullptr;
    bool currentIsUsers = false;
    for (const BrushPreset& p : builtinBrushPresets()) {
        if (!current && brushHasPreset(s.brush, p)) current = &p;
    }
    for (const BrushPreset& p : s.settings.brushPresets) {
        if (!current && brushHasPreset(s.brush, p)) {
            current = &p;
            currentIsUsers = true;
        }
    }
    const std::string shown = current ? current->name : "custom";
    std::string chosen;
    ImGui::SetNextItemWidth(ImGui::GetContentRegionAvail().x * 0.45f);
    if (ImGui::BeginCombo("Preset", shown.c_str())) {
        for (const BrushPreset& p : builtinBrushPresets()) {
            if (ImGui::Selectable(p.name.c_str(), &p == current)) {
                applyBrushPreset(p, s.brush);
                chosen = p.name;
            }
        }
        if (!s.settings.brushPresets.empty()) ImGui::Separator();
        for (const BrushPreset& p : s.settings.brushPresets) {
            ImGui::PushID(&p);
            if (ImGui::Selectable(p.name.c_str(), &p == current)) {
                applyBrushPreset(p, s.brush);
                chosen = p.name;
            }
            ImGui::PopID();
        }
        ImGui::EndCombo();
    }
    tooltip(
        "Brush presets: Hole (small and hard: opens the map fully), Seep (soft and weak: lets a\n"
        "little more in per stroke), Seal (paints 0), and your own. A preset sets mode, radius,\n"
        "strength, value, falloff and spacing; symmetry and the rest stay.");
    if (!chosen.empty()) s.status = "Brush preset " + chosen;
    ImGui::SameLine();
    if (ImGui::Button("Save...")) {
        std::snprintf(typed, sizeof typed, "%s", currentIsUsers ? current->name.c_str() : "");
        refusal.clear();
        ImGui::OpenPopup("Save brush preset");
    }
    tooltip("Keep the brush as a preset of your own (kept between sessions).");
    ImGui::SameLine();
    ImGui::BeginDisabled(!currentIsUsers);
    if (ImGui::Button("Delete##brush_preset") && currentIsUsers) {
        const std::string name = current->name;
        s.settings.removeBrushPreset(name);
        (void)s.settings.save();
        s.status = "Removed brush preset " + name;
    }
    ImGui::EndDisabled();
    tooltip("Remove the preset of yours the brush is set to (the built-in ones stay).");
    if (ImGui::BeginPopup("Save brush preset")) {
        ImGui::TextUnformatted("Keep the brush as:");
        if (ImGui::IsWindowAppearing()) ImGui::SetKeyboardFocusHere();
        const bool enter = ImGui::InputText("##preset_name", typed, sizeof typed,
                                            ImGuiInputTextFlags_EnterReturnsTrue);
        tooltip("A name of your own (a preset of that name is replaced).");
        const bool save = ImGui::Button("Save");
        ImGui::SameLine();
        if (ImGui::Button("Cancel")) ImGui::CloseCurrentPopup();
        if (enter || save) {
            if (Status saved = s.settings.saveBrushPreset(typed, s.brush); saved) {
                (void)s.settings.save();
                s.status = "Saved brush preset " + std::string(typed);
                ImGui::CloseCurrentPopup();
            } else {
                refusal = saved.error().message;
            }
        }
        if (!refusal.empty()) ImGui::TextColored(ImVec4(1, 0.45f, 0.4f, 1), "%s", refusal.c_str());
        ImGui::EndPopup();
    }
}

/// The tool and the map it changes.
void drawToolAndChannel(EditorState& s) {
    int tool = static_cast<int>(s.tool);
    ImGui::RadioButton("Navigate", &tool, static_cast<int>(Tool::Navigate));
    tooltip("Left mouse orbits the view (V)");
    ImGui::SameLine();
    ImGui::RadioButton("Brush", &tool, static_cast<int>(Tool::Brush));
    tooltip("Left mouse paints the map; Shift-click draws a line from the last stroke (B)");
    ImGui::SameLine();
    ImGui::RadioButton("Fill island", &tool, static_cast<int>(Tool::FillIsland));
    tooltip("Click fills the UV island under the cursor with Value (G)");
    ImGui::SameLine();
    ImGui::RadioButton("Pick", &tool, static_cast<int>(Tool::Pick));
    tooltip("Click reads the map's value under the cursor into Value (I)");
    s.tool = static_cast<Tool>(tool);

    int channel = static_cast<int>(s.channel);
    if (ImGui::Combo("Map", &channel, "permeability\0density\0thickness\0")) {
        s.channel = static_cast<MapChannel>(channel);
        s.overlay = s.channel == MapChannel::Permeability ? Overlay::Permeability
                    : s.channel == MapChannel::Density    ? Overlay::Density
                                                          : Overlay::Thickness;
        s.overlaysDirty = true;
    }
    tooltip(
        "The map the tools change: permeability (water flow in), or the shell's density and "
        "thickness scales");
}

/// The brush's settings: mode, size, strength, value, falloff, spacing, symmetry, lazy mouse
/// and which texels it reaches.
void drawBrushSettings(EditorState& s) {
    int mode = static_cast<int>(s.brush.mode);
    if (ImGui::Combo("Mode", &mode, "paint\0erase\0smooth\0"))
        s.brush.mode = static_cast<BrushMode>(mode);
    tooltip(
        "Paint toward Value, erase toward 0 (E), or smooth toward the mean under the brush (S)");
    float radius = static_cast<float>(s.brush.radius);
    if (ImGui::SliderFloat("Radius (m)", &radius, 0.001f, 5.0f, "%.3f",
                           ImGuiSliderFlags_Logarithmic)) {
        s.brush.radius = radius;
    }
    tooltip("Brush radius on the surface, in metres ([ and ] change it)");
    float strength = static_cast<float>(s.brush.strength);
    if (ImGui::SliderFloat("Strength", &strength, 0.0f, 1.0f)) s.brush.strength = strength;
    tooltip("How far one stroke or fill moves a pixel toward Value (1: all the way)");
    float value = static_cast<float>(s.brush.value);
    if (ImGui::SliderFloat("Value", &value, 0.0f, 1.0f)) s.brush.value = value;
    tooltip("The value painted (0..1; what 1 means depends on the map)");
    int falloff = static_cast<int>(s.brush.falloff);
    if (ImGui::Combo(
            "Falloff", &falloff,
            [](void*, int i, const char** out) {
                *out = falloffName(static_cast<Falloff>(i));
                return true;
            },
            nullptr, kFalloffCount)) {
        s.brush.falloff = static_cast<Falloff>(falloff);
    }
    tooltip(
        "How the brush's weight falls from its centre to its rim (Blender's presets: sphere, "
        "root, sharp, inverse-square; custom: a curve you draw)");
    if (s.brush.falloff == Falloff::Custom) falloffCurveEditor(s.brush.curve);
    float spacing = static_cast<float>(s.brush.spacing);
    if (ImGui::SliderFloat("Spacing", &spacing, 0.05f, 4.0f, "%.2f radii",
                           ImGuiSliderFlags_Logarithmic)) {
        s.brush.spacing = spacing;
    }
    tooltip(
        "Dabs along a stroke at most this many radii apart (0.25: a solid line; above 2: dots)");
    ImGui::Checkbox("X mirror", &s.brush.mirrorX);
    tooltip("Also paint at (-x, y, z) (X)");
    ImGui::SameLine();
    ImGui::Checkbox("Y", &s.brush.mirrorY);
    tooltip("Also paint at (x, -y, z)");
    ImGui::SameLine();
    ImGui::Checkbox("Z", &s.brush.mirrorZ);
    tooltip("Also paint at (x, y, -z)");
    ImGui::SameLine();
    ImGui::SetNextItemWidth(70);
    ImGui::InputInt("radial", &s.brush.radial, 1);
    s.brush.radial = std::clamp(s.brush.radial, 1, kMaxRadialCopies);
    tooltip("Radial symmetry about the body's y axis: copies of every dab, evenly turned (1: off)");
    float lazy = static_cast<float>(s.brush.lazyRadius);
    if (ImGui::SliderFloat("Lazy mouse", &lazy, 0.0f, static_cast<float>(kMaxLazyRadius),
                           "%.0f px")) {
        s.brush.lazyRadius = lazy;
    }
    tooltip(
        "The brush trails the cursor on a string this long (0: off), for smooth lines. "
        "Shift-click draws a straight line from the last stroke's end.");
    float normalAngle = static_cast<float>(s.brush.normalAngle);
    if (ImGui::SliderFloat("Normal falloff", &normalAngle, 1.0f, 180.0f, "%.0f deg")) {
        s.brush.normalAngle = normalAngle;
    }
    tooltip(
        "Texels turned more than this from the view get no paint, fading from half the angle "
        "(Blender's normal falloff; 180: off)");
    ImGui::Checkbox("Front faces only", &s.brush.frontFacesOnly);
    tooltip(
        "Backface culling: texels facing away from the view get no paint (the far side of a thin "
        "hull under the brush stays as it is)");
    ImGui::SameLine();
    ImGui::Checkbox("Occlusion", &s.brush.occlusion);
    tooltip(
        "Texels hidden from the view behind other parts of the body get no paint (a deck "
        "under a superstructure, the inside of a hull seen through an opening)");
}

/// Whole-map commands: fill all, a new blank map (asking before replacing one), resize.
void drawMapCommands(EditorState& s) {
    const bool hasBody =
        s.selectedBody >= 0 && static_cast<std::size_t>(s.selectedBody) < s.document->bodyCount();
    if (ImGui::Button("Fill all") && hasBody) {
        s.execute(makeFillAllCommand(*s.document, s.selectedBody, s.channel, s.brush.value,
                                     s.brush.strength, s.paintTarget()));
    }
    tooltip("Moves every pixel toward Value by Strength");
    ImGui::SameLine();
    auto newMap = [&] {
        s.execute(makeNewMapCommand(*s.document, s.selectedBody, s.channel, s.newMapSize,
                                    s.newMapSize, 0.0, ""));
    };
    const bool newMapClicked = ImGui::Button("New map");
    tooltip("A blank map of this size for the channel (asks before replacing one)");
    if (newMapClicked && hasBody) {
        // Replacing a map (saved paint, layers) asks first; the undo brings it back either way.
        if (s.document->map(s.selectedBody, s.channel))
            s.confirmNewMap = true;
        else
            newMap();
    }
    ImGui::SameLine();
    ImGui::SetNextItemWidth(80);
    ImGui::InputInt("px", &s.newMapSize, 0);
    tooltip("The new map's texels per side, 16 to 8192.");
    s.newMapSize = std::clamp(s.newMapSize, 16, 8192);
    ImGui::SameLine();
    const PaintedMap* current = hasBody ? s.document->map(s.selectedBody, s.channel) : nullptr;
    ImGui::BeginDisabled(!current ||
                         (current->width == s.newMapSize && current->height == s.newMapSize));
    if (ImGui::Button("Resize") && current) {
        s.execute(makeResizeMapCommand(*s.document, s.selectedBody, s.channel, s.newMapSize,
                                       s.newMapSize));
    }
    ImGui::EndDisabled();
    tooltip(
        "The map at this size, its paint kept (filtered down or up, every layer too; one undo "
        "step).");
    if (s.confirmNewMap) {
        ImGui::OpenPopup("Replace map?");
        s.confirmNewMap = false;
    }
    if (ImGui::BeginPopupModal("Replace map?", nullptr, ImGuiWindowFlags_AlwaysAutoResize)) {
        ImGui::Text("Replace the body's %s map (and its layers) with a blank %d x %d map?",
                    channelName(s.channel), s.newMapSize, s.newMapSize);
        ImGui::TextDisabled("Undo gives the current map back.");
        if (ImGui::Button("Replace")) {
            newMap();
            ImGui::CloseCurrentPopup();
        }
        tooltip("Replaces the map with a blank one (one undo step).");
        ImGui::SameLine();
        if (ImGui::Button("Cancel")) ImGui::CloseCurrentPopup();
        tooltip("Keeps the map as it is.");
        ImGui::EndPopup();
    }
}

/// What the view shows: the hull's overlay, the water, the grid.
void drawDisplayOptions(EditorState& s) {
    int overlay = static_cast<int>(s.overlay);
    if (ImGui::Combo(
            "Overlay", &overlay,
            "none\0permeability\0density\0thickness\0coverage\0position (PT)\0area (AVT)\0")) {
        s.overlay = static_cast<Overlay>(overlay);
        s.overlaysDirty = true;
    }
    tooltip(
        "What the hull shows: a painted map, the physics coverage, or the baked position\n"
        "and area textures; the legend in the view gives its units.");
    ImGui::Checkbox("Water", &s.showWater);
    tooltip("Draw the water surface.");
    ImGui::SameLine();
    ImGui::Checkbox("Waves move", &s.animateWater);
    tooltip("Animate the project's waves in edit mode (off: the surface at t = 0).");
    ImGui::SameLine();
    ImGui::Checkbox("Grid", &s.showGrid);
    tooltip("Draw the ground grid and the axes.");
}

}  // namespace

void drawBrushPanel(EditorState& s, const Rect& area) {
    beginColumnPanel("Tools", area);
    drawToolAndChannel(s);
    brushPresetControls(s);
    drawBrushSettings(s);
    alphaControls(s);
    drawMapCommands(s);
    drawDisplayOptions(s);
    ImGui::End();
}

}  // namespace plimsoll::editor
