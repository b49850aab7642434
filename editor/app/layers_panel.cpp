// The Layers panel: the selected body's map of the current channel as a stack, top layer first
// as painting tools list them. Every change is a command of command.h (one undo step each; a
// slider is one step when it is let go). The active layer (or its mask) is what strokes and
// fills change.
#include "app/panels.h"

#include "document/command.h"

#include <imgui.h>

#include <cstdio>
#include <functional>
#include <optional>
#include <string>

namespace plimsoll::editor {

namespace {

void startRename(EditorState& s, std::size_t body, int layer, const std::string& name) {
    s.layerRename = {layer, body, s.channel, name, true};
}

/// The name field over layer `i`'s row while it is renamed: Enter keeps the name, Esc puts the
/// old one back, and a click elsewhere keeps a name that can be kept. True: rename it now (the
/// caller runs the command once it no longer holds references into the stack).
bool renameField(EditorState& s, int i, const LayerStack& stack) {
    LayerRename& r = s.layerRename;
    const std::string& old = stack.layers[static_cast<std::size_t>(i)].name;
    char buffer[256];
    std::snprintf(buffer, sizeof buffer, "%s", r.text.c_str());
    if (r.focus) {
        ImGui::SetKeyboardFocusHere();
        r.focus = false;
    }
    ImGui::SetNextItemWidth(-1);
    const bool enter =
        ImGui::InputText("##rename", buffer, sizeof buffer,
                         ImGuiInputTextFlags_EnterReturnsTrue | ImGuiInputTextFlags_AutoSelectAll);
    tooltip("The layer's new name: Enter keeps it, Esc keeps the old one.");
    r.text = buffer;
    const bool escape = ImGui::IsKeyPressed(ImGui::GetKeyIndex(ImGuiKey_Escape), false);
    const bool left = ImGui::IsItemDeactivated() && !enter;
    const bool unchanged = trimmedLayerName(r.text) == old;
    const Status valid = checkLayerName(stack, i, r.text);
    if (escape || (left && (unchanged || !valid)) || (enter && unchanged)) {
        // Esc in ImGui's field has put the old text back; a click away from a name that
        // cannot be kept gives it up, saying why.
        if (left && !escape && !valid) s.status = "Layer not renamed: " + valid.error().message;
        r = {};
        return false;
    }
    if (enter || left) return true;
    if (!unchanged && !valid) {
        ImGui::PushStyleColor(ImGuiCol_Text, ImVec4(1, 0.45f, 0.4f, 1));
        ImGui::TextWrapped("%s", valid.error().message.c_str());
        ImGui::PopStyleColor();
    }
    return false;
}

/// The index of the layer named `name` (names are unique within a map), or -1.
int layerNamed(const EditorState& s, std::size_t body, const std::string& name) {
    const LayerStack* stack = s.document->layers(body, s.channel);
    if (!stack) return -1;
    for (std::size_t i = 0; i < stack->layers.size(); ++i) {
        if (stack->layers[i].name == name) return static_cast<int>(i);
    }
    return -1;
}

/// Runs a layer command that keeps the active layer's name, and follows that layer to where
/// the command put it (a move, a folder's change).
void executeFollowing(EditorState& s, std::size_t body, const std::string& active,
                      Result<std::unique_ptr<Command>> command) {
    if (!s.execute(std::move(command))) return;
    if (const int i = layerNamed(s, body, active); i >= 0) s.activeLayer = i;
}

/// Adds a paint / fill layer above the active one, or a folder above the active item (the
/// active layer's folder, where it is in one: folders do not nest).
void drawAddButtons(EditorState& s, std::size_t body, const LayerStack* stack) {
    const int active = s.activeLayer;
    if (ImGui::Button("+ Paint")) {
        if (s.execute(makeAddLayerCommand(*s.document, body, s.channel, LayerKind::Paint, "", 1.0,
                                          active + 1))) {
            s.activeLayer = active + 1;
            s.paintMask = false;
        }
    }
    tooltip("A new paint layer above the active one: clear until painted.");
    ImGui::SameLine();
    if (ImGui::Button("+ Fill")) {
        if (s.execute(makeAddLayerCommand(*s.document, body, s.channel, LayerKind::Fill, "",
                                          s.brush.value, active + 1))) {
            s.activeLayer = active + 1;
        }
    }
    tooltip("A layer of one value (the brush value); give it a mask to place it.");
    ImGui::SameLine();
    if (ImGui::Button("+ Folder")) {
        const int folder = stack ? folderOf(*stack, active) : -1;
        const int at = (folder >= 0 ? folder : active) + 1;
        if (s.execute(
                makeAddLayerCommand(*s.document, body, s.channel, LayerKind::Folder, "", 1.0, at)))
            s.activeLayer = at;
    }
    tooltip(
        "A new folder above the active layer: right-click a layer > Move into folder to fill it.\n"
        "Its layers are composited together, then shown with the folder's opacity and blend.");
}

/// Deletes the active layer (or folder with its layers) and moves it up or down among the
/// items of its folder; each one command.
void drawStackButtons(EditorState& s, std::size_t body, const LayerStack* stack, int count) {
    // Read before any button runs: a command replaces the stack.
    const int active = s.activeLayer;
    const int start = stack ? blockStart(*stack, active) : active;
    const std::string name = stack ? stack->layers[std::size_t(active)].name : std::string();
    const int above = stack ? siblingAbove(*stack, active) : -1;
    const int below = stack ? siblingBelow(*stack, active) : -1;
    ImGui::SameLine();
    ImGui::BeginDisabled(count - (active - start + 1) < 1);
    if (ImGui::Button("Delete")) {
        if (s.execute(makeRemoveLayerCommand(*s.document, body, s.channel, active))) {
            s.activeLayer = std::max(0, start - 1);
        }
    }
    tooltip(
        "Removes the active layer, or the active folder with its layers (a map keeps one "
        "layer).");
    ImGui::EndDisabled();
    for (const bool up : {true, false}) {
        const int to = up ? above : below;
        ImGui::SameLine();
        ImGui::BeginDisabled(to < 0);
        if (ImGui::ArrowButton(up ? "##up" : "##down", up ? ImGuiDir_Up : ImGuiDir_Down))
            executeFollowing(s, body, name,
                             makeMoveLayerCommand(*s.document, body, s.channel, active, to));
        tooltip(up ? "Moves the active layer (or folder) up, over the one above it in its folder."
                   : "Moves the active layer (or folder) down, under the one below it in its "
                     "folder.");
        ImGui::EndDisabled();
    }
}

/// The panel's key of a folder shown closed.
std::string collapseKey(const EditorState& s, std::size_t body, const std::string& name) {
    return std::to_string(body) + "/" + channelName(s.channel) + "/" + name;
}

/// Layer `i`'s right-click menu: rename, into or out of a folder. The move is returned, to run
/// once nothing reads the stack.
std::function<void()> layerMenu(EditorState& s, std::size_t body, const LayerStack& stack, int i) {
    std::function<void()> action;
    const MapLayer& layer = stack.layers[std::size_t(i)];
    if (ImGui::MenuItem("Rename")) startRename(s, body, i, layer.name);
    if (layer.isFolder()) return action;
    const int holder = folderOf(stack, i);
    if (ImGui::BeginMenu("Move into folder", stack.hasFolders())) {
        for (int f = 0; f < static_cast<int>(stack.layers.size()); ++f) {
            const MapLayer& folder = stack.layers[std::size_t(f)];
            if (!folder.isFolder() || f == holder || !ImGui::MenuItem(folder.name.c_str()))
                continue;
            action = [&s, body, i, f, name = layer.name] {
                executeFollowing(s, body, name,
                                 makeMoveIntoFolderCommand(*s.document, body, s.channel, i, f));
            };
        }
        ImGui::EndMenu();
    }
    if (ImGui::MenuItem("Move out of folder", nullptr, false, holder >= 0)) {
        action = [&s, body, i, name = layer.name] {
            executeFollowing(s, body, name,
                             makeMoveOutOfFolderCommand(*s.document, body, s.channel, i));
        };
    }
    return action;
}

/// A folder's open / closed arrow before its row.
void folderArrow(EditorState& s, std::size_t body, const MapLayer& folder) {
    const std::string key = collapseKey(s, body, folder.name);
    const bool closed = s.collapsedFolders.count(key) > 0;
    if (ImGui::ArrowButton("##open", closed ? ImGuiDir_Right : ImGuiDir_Down)) {
        if (closed)
            s.collapsedFolders.erase(key);
        else
            s.collapsedFolders.insert(key);
    }
    tooltip(closed ? "Shows the folder's layers." : "Hides the folder's layers in this list.");
    ImGui::SameLine();
}

std::string layerLabel(const LayerStack& stack, int i) {
    const MapLayer& layer = stack.layers[std::size_t(i)];
    const std::string held =
        layer.isFolder() ? ", " + std::to_string(i - blockStart(stack, i)) + " layers" : "";
    return layer.name + "  (" + layerKindName(layer.kind) + ", " + blendModeName(layer.blend) +
           ", " + std::to_string(static_cast<int>(layer.opacity * 100 + 0.5f)) + "%" +
           (layer.mask ? ", mask" : "") + held + ")";
}

/// Layer `i`'s row: visibility, the active layer, rename in place, its menu. True when a
/// rename was confirmed; a change to make is left in `action`.
bool drawLayerRow(EditorState& s, std::size_t body, const LayerStack& stack, int i, int active,
                  std::function<void()>& action) {
    const MapLayer& layer = stack.layers[static_cast<std::size_t>(i)];
    if (layer.isFolder()) folderArrow(s, body, layer);
    bool visible = layer.visible;
    if (ImGui::Checkbox("##visible", &visible)) {
        action = [&s, body, i, visible] {
            LayerEdit e;
            e.visible = visible;
            s.execute(makeSetLayerCommand(*s.document, body, s.channel, i, e));
        };
    }
    tooltip(layer.isFolder() ? "Show or hide the folder with its layers."
                             : "Show or hide the layer.");
    ImGui::SameLine();
    if (s.layerRename.layer == i) return renameField(s, i, stack);
    if (ImGui::Selectable(layerLabel(stack, i).c_str(), i == active,
                          ImGuiSelectableFlags_AllowDoubleClick)) {
        s.activeLayer = i;
        if (!layer.mask) s.paintMask = false;
        if (ImGui::IsMouseDoubleClicked(ImGuiMouseButton_Left)) startRename(s, body, i, layer.name);
    }
    tooltip(
        "Click to make it the active layer: strokes, fills and the settings below act on it.\n"
        "Double-click (or right-click > Rename) to rename it; right-click to move it into or\n"
        "out of a folder.");
    if (ImGui::BeginPopupContextItem("##layer_menu")) {
        if (std::function<void()> moved = layerMenu(s, body, stack, i)) action = std::move(moved);
        ImGui::EndPopup();
    }
    return false;
}

/// The list, top first, a folder's layers indented under it (hidden while it is closed). True
/// when a rename was confirmed this frame; a change asked for is left in `action` (both are
/// carried out by the caller, after everything that reads the stack).
bool drawLayerList(EditorState& s, std::size_t body, const LayerStack& stack, int count, int active,
                   std::function<void()>& action) {
    // A rename ends with its map (another body or channel) or its layer (an undo took it).
    LayerRename& rename = s.layerRename;
    if (rename.layer >= count || rename.body != body || rename.channel != s.channel) rename = {};
    bool renameNow = false;
    for (int i = count - 1; i >= 0; --i) {
        const int holder = folderOf(stack, i);
        if (holder >= 0 &&
            s.collapsedFolders.count(collapseKey(s, body, stack.layers[std::size_t(holder)].name)))
            continue;
        ImGui::PushID(i);
        if (holder >= 0) ImGui::Indent();
        if (drawLayerRow(s, body, stack, i, active, action)) renameNow = true;
        if (holder >= 0) ImGui::Unindent();
        ImGui::PopID();
    }
    return renameNow;
}

/// "Smart mask": a mask for the active layer worked out from the physics and the shape (one
/// undo step), the body where the view shows it (as the live preview left it, or its start)
/// against the still water.
void drawSmartMaskMenu(EditorState& s, std::size_t body, int active) {
    if (ImGui::Button("Smart mask...")) ImGui::OpenPopup("##smart_mask");
    tooltip(
        "A mask from the physics and the shape: below the waterline, by depth, by the\n"
        "way the surface faces (for the body where the view shows it), or by the shape's\n"
        "curvature: its convex edges or its hollows.");
    if (!ImGui::BeginPopup("##smart_mask")) return;
    SmartMask mask;
    mask.pose = s.shownPose(body);
    mask.waterLevel = s.document->project().water.level;
    std::optional<SmartMask::Kind> chosen;
    if (ImGui::MenuItem("Below the waterline")) chosen = SmartMask::Kind::BelowWaterline;
    if (ImGui::MenuItem("By depth")) chosen = SmartMask::Kind::Depth;
    ImGui::SetNextItemWidth(120);
    ImGui::DragFloat("full at depth", &s.smartMaskDepth, 0.05f, 0.05f, 100.0f, "%.2f m",
                     ImGuiSliderFlags_AlwaysClamp);
    if (ImGui::MenuItem("Facing up (decks)")) {
        chosen = SmartMask::Kind::Facing;
    }
    if (ImGui::MenuItem("Facing down (bottom)")) {
        chosen = SmartMask::Kind::Facing;
        mask.direction = -Eigen::Vector3d::UnitY();
    }
    ImGui::Separator();
    if (ImGui::MenuItem("Curvature (convex edges)")) chosen = SmartMask::Kind::Curvature;
    if (ImGui::MenuItem("Cavity (hollows)")) chosen = SmartMask::Kind::Cavity;
    ImGui::SetNextItemWidth(120);
    ImGui::DragFloat("over radius", &s.smartMaskRadius, 0.005f, 0.005f, 10.0f, "%.3f m",
                     ImGuiSliderFlags_AlwaysClamp);
    tooltip("The ball the mean curvature is measured over: a crease marks a band this wide.");
    ImGui::SetNextItemWidth(120);
    ImGui::DragFloat("full at", &s.smartMaskFullCurvature, 0.1f, 0.01f, 1000.0f, "%.2f 1/m",
                     ImGuiSliderFlags_AlwaysClamp);
    tooltip("The mean curvature that masks fully (a sphere of radius R has 1/R).");
    if (chosen) {
        mask.kind = *chosen;
        mask.depth = s.smartMaskDepth;
        mask.radius = s.smartMaskRadius;
        mask.fullCurvature = s.smartMaskFullCurvature;
        if (s.execute(makeSmartMaskCommand(*s.document, body, s.channel, active, mask)))
            s.paintMask = true;
        ImGui::CloseCurrentPopup();
    }
    ImGui::EndPopup();
}

/// The active layer's settings: blend mode, opacity, a fill's value and its mask.
void drawActiveLayerSettings(EditorState& s, std::size_t body, const MapLayer& layer, int active,
                             float width) {
    static_assert(kBlendModeCount == 7);
    int blend = static_cast<int>(layer.blend);
    ImGui::SetNextItemWidth(width * 0.3f);
    // Picking the mode the layer already has changes nothing: no step in the history.
    if (ImGui::Combo("Blend", &blend,
                     "normal\0multiply\0add\0subtract\0screen\0lighten\0darken\0") &&
        blend != static_cast<int>(layer.blend)) {
        LayerEdit e;
        e.blend = static_cast<BlendMode>(blend);
        s.execute(makeSetLayerCommand(*s.document, body, s.channel, active, e));
    }
    tooltip(
        "How the layer meets what is below it: normal replaces, multiply scales, add and\n"
        "subtract offset, screen brightens, lighten and darken keep the larger or smaller.");
    ImGui::SameLine();
    LayerSliders& held = s.layerSliders;
    // A 0..1 slider that shows the value while held and edits the layer once let go.
    auto slider = [&](const char* label, const char* help, const char* format, float current,
                      bool& isHeld, float& heldValue, std::optional<double> LayerEdit::*field) {
        float value = isHeld ? heldValue : current;
        ImGui::SetNextItemWidth(width * 0.3f);
        ImGui::SliderFloat(label, &value, 0.0f, 1.0f, format);
        tooltip(help);
        isHeld = ImGui::IsItemActive();
        heldValue = value;
        if (ImGui::IsItemDeactivatedAfterEdit()) {
            LayerEdit e;
            e.*field = value;
            s.execute(makeSetLayerCommand(*s.document, body, s.channel, active, e));
        }
    };
    slider("Opacity", "How much of the layer shows over what is below it (Ctrl+click to type).",
           "%.2f", layer.opacity, held.opacityHeld, held.opacity, &LayerEdit::opacity);
    if (layer.kind == LayerKind::Fill) {
        slider("Fill value", "The one value the fill layer holds, 0 to 1 (Ctrl+click to type).",
               "%.3f", layer.fillValue, held.fillHeld, held.fill, &LayerEdit::fillValue);
    }
    if (!layer.mask) {
        if (ImGui::Button("Add mask")) {
            // A fill layer's mask starts empty (nothing shows until painted), a paint layer's
            // full (it hides nothing until painted out).
            const double start = layer.kind == LayerKind::Fill ? 0.0 : 1.0;
            if (s.execute(makeAddMaskCommand(*s.document, body, s.channel, active, start))) {
                s.paintMask = true;
            }
        }
        tooltip(
            "A mask for the layer: paint it to show (white) or hide (black) the layer in places.");
    } else {
        ImGui::Checkbox("Paint the mask", &s.paintMask);
        tooltip("Strokes and fills change the mask (1 shows the layer, 0 hides it).");
        ImGui::SameLine();
        if (ImGui::Button("Remove mask")) {
            if (s.execute(makeRemoveMaskCommand(*s.document, body, s.channel, active)))
                s.paintMask = false;
        }
        tooltip("Removes the mask: the whole layer shows again.");
    }
    ImGui::SameLine();
    drawSmartMaskMenu(s, body, active);
}

}  // namespace

void drawLayersPanel(EditorState& s, const Rect& area) {
    beginColumnPanel("Layers", area);
    const bool hasBody =
        s.selectedBody >= 0 && static_cast<std::size_t>(s.selectedBody) < s.document->bodyCount();
    const std::size_t body = hasBody ? static_cast<std::size_t>(s.selectedBody) : 0;
    if (!hasBody || !s.document->map(body, s.channel)) {
        ImGui::TextWrapped("No %s map on this body yet: paint on it, or use \"New map\".",
                           channelName(s.channel));
        ImGui::End();
        return;
    }
    const LayerStack* stack = s.document->layers(body, s.channel);
    const int count = stack ? static_cast<int>(stack->layers.size()) : 1;
    if (s.activeLayer >= count || s.activeLayer < 0) s.activeLayer = count - 1;
    const int active = s.activeLayer;
    drawAddButtons(s, body, stack);
    drawStackButtons(s, body, stack, count);
    if (!stack) {
        ImGui::TextDisabled("Base (the map; add a layer to stack more)");
        ImGui::End();
        return;
    }
    const MapLayer& activeLayer = stack->layers[static_cast<std::size_t>(active)];
    const float settingRows = activeLayer.kind == LayerKind::Fill ? 3.0f : 2.0f;
    const float listHeight = std::max(
        40.0f, ImGui::GetContentRegionAvail().y - settingRows * ImGui::GetFrameHeightWithSpacing());
    ImGui::BeginChild("##layers", ImVec2(0, listHeight), true);
    std::function<void()> action;
    const bool renameNow = drawLayerList(s, body, *stack, count, active, action);
    ImGui::EndChild();
    drawActiveLayerSettings(s, body, activeLayer, active, area.w);
    // Then: a change asked for in the list replaces the stack the list and the settings read.
    if (action) action();
    // Last: the rename replaces the stack that `activeLayer` and the list read.
    LayerRename& rename = s.layerRename;
    if (renameNow) {
        // A refused name leaves the field open (the status line says why) to be corrected.
        if (s.execute(
                makeRenameLayerCommand(*s.document, body, s.channel, rename.layer, rename.text))) {
            rename = {};
        } else {
            rename.focus = true;
        }
    }
    ImGui::End();
}

}  // namespace plimsoll::editor
