// The editor's window and frame loop: GLFW + OpenGL 4.5 core (libepoxy) + Dear ImGui, as in
// ImGui's example_glfw_opengl3. Index:
//   [SECTION] window callbacks (drop, close)
//   [SECTION] menus and shortcuts
//   [SECTION] dialogs (file browser, unsaved changes, recovery, help)
//   [SECTION] frame loop (layout, panels, stroke preview, 3D view, autosave, screenshot)
#include "app/editor_app.h"

#include "app/editor_state.h"
#include "app/panel_cache.h"
#include "app/export_dialog.h"
#include "app/panels.h"
#include "app/preview_panel.h"
#include "document/command.h"

#include "plimsoll/io/bake_io.h"
#include "plimsoll/io/file_util.h"

#include <epoxy/gl.h>
#include <GLFW/glfw3.h>
#include <imgui.h>
#include <imgui_internal.h>  // BringWindowToDisplayFront: the splitters stay over the panels
#include <imgui_impl_glfw.h>
#include <imgui_impl_opengl3.h>
#include <nlohmann/json.hpp>
#include <stb_image_write.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <iostream>
#include <sys/resource.h>
#include <thread>

namespace plimsoll::editor {

namespace fs = std::filesystem;

namespace {

// [SECTION] window callbacks -------------------------------------------------------------------

// The window's user pointer is the EditorState: callbacks reach it without globals.
EditorState& stateOf(GLFWwindow* window) {
    return *static_cast<EditorState*>(glfwGetWindowUserPointer(window));
}

void onDrop(GLFWwindow* window, int count, const char** paths) {
    EditorState& s = stateOf(window);
    for (int i = 0; i < count; ++i) s.droppedPaths.emplace_back(paths[i]);
    ++s.inputEvents;
}

void onClose(GLFWwindow* window) {
    EditorState& s = stateOf(window);
    if (s.document->dirty()) {
        glfwSetWindowShouldClose(window, GLFW_FALSE);
        s.requestQuit = true;
        s.confirmDiscardOpen = true;
    }
}

// Installed before ImGui's backend, which calls them first and then does its own work.
void onKey(GLFWwindow* window, int key, int, int action, int mods) {
    EditorState& s = stateOf(window);
    ++s.inputEvents;
    if (action == GLFW_PRESS || (action == GLFW_REPEAT &&
                                 (key == GLFW_KEY_LEFT_BRACKET || key == GLFW_KEY_RIGHT_BRACKET))) {
        s.keyPresses.emplace_back(key, mods);
    }
    if (action == GLFW_PRESS) s.keysPressedSinceFrame.push_back(key);
    if (action == GLFW_RELEASE &&
        std::find(s.keysPressedSinceFrame.begin(), s.keysPressedSinceFrame.end(), key) !=
            s.keysPressedSinceFrame.end()) {
        s.tappedKeys.push_back(key);
    }
}

/// Before a frame: the keys tapped since the last one (pressed and released in between) are
/// down for this frame, so that ImGui's widgets see them (Enter in a number field, typed
/// quickly after the digits, was lost about one time in two). Returns them for releaseTappedKeys.
std::vector<int> holdTappedKeys(EditorState& s) {
    std::vector<int> held;
    held.swap(s.tappedKeys);
    s.keysPressedSinceFrame.clear();
    ImGuiIO& io = ImGui::GetIO();
    for (int key : held) {
        if (key >= 0 && key < static_cast<int>(IM_ARRAYSIZE(io.KeysDown))) io.KeysDown[key] = true;
    }
    return held;
}

/// After the frame: the held taps go up again (unless pressed anew meanwhile).
void releaseTappedKeys(EditorState& s, const std::vector<int>& held) {
    ImGuiIO& io = ImGui::GetIO();
    for (int key : held) {
        const bool pressedAgain =
            std::find(s.keysPressedSinceFrame.begin(), s.keysPressedSinceFrame.end(), key) !=
            s.keysPressedSinceFrame.end();
        if (!pressedAgain && key >= 0 && key < static_cast<int>(IM_ARRAYSIZE(io.KeysDown)))
            io.KeysDown[key] = false;
    }
}
void onChar(GLFWwindow* window, unsigned int) { ++stateOf(window).inputEvents; }
void onMouseButton(GLFWwindow* window, int, int, int) { ++stateOf(window).inputEvents; }
void onScroll(GLFWwindow* window, double, double) { ++stateOf(window).inputEvents; }
void onCursor(GLFWwindow* window, double, double) { ++stateOf(window).inputEvents; }
void onResize(GLFWwindow* window, int, int) { ++stateOf(window).inputEvents; }
void onRefresh(GLFWwindow* window) { ++stateOf(window).inputEvents; }
void onFocus(GLFWwindow* window, int) { ++stateOf(window).inputEvents; }
void onEnter(GLFWwindow* window, int) { ++stateOf(window).inputEvents; }

/// How long an idle editor sleeps between looks (autosave, background results), and how many
/// frames it draws after an event.
constexpr double kIdleWakeSeconds = 0.5;
constexpr int kFramesAfterEvent = 3;
constexpr double kBakeProgressSeconds = 0.25;

/// Whether something moves on screen without input: the frame loop then draws continuously.
bool animating(const EditorState& s) {
    const bool previewMoving = s.preview && s.preview->session &&
                               (s.preview->session->playing() || s.preview->session->rebuilding());
    return previewMoving || s.animateWater || s.stroke.active || s.navigating ||
           graphPanelBusy(s) || bundleExportNeedsFrames(*s.exportDialog) || hydrostaticsComputing();
}

/// The splitters: thin windows over the borders between the view and the column and between
/// the column's panels, kept in front, dragged with the left mouse (ImGui 1.86 has no docking).
void drawSplitters(EditorState& s, const WindowLayout& layout) {
    constexpr float kGrip = 6.0f;
    const ImGuiWindowFlags flags = ImGuiWindowFlags_NoDecoration | ImGuiWindowFlags_NoMove |
                                   ImGuiWindowFlags_NoSavedSettings |
                                   ImGuiWindowFlags_NoBackground |
                                   ImGuiWindowFlags_NoFocusOnAppearing | ImGuiWindowFlags_NoNav;
    auto splitter = [&](const char* id, ImVec2 at, ImVec2 size, ImGuiMouseCursor cursor,
                        const auto& drag) {
        ImGui::SetNextWindowPos(at);
        ImGui::SetNextWindowSize(size);
        ImGui::PushStyleVar(ImGuiStyleVar_WindowPadding, ImVec2(0, 0));
        ImGui::PushStyleVar(ImGuiStyleVar_WindowMinSize, ImVec2(1, 1));
        ImGui::PushStyleVar(ImGuiStyleVar_WindowBorderSize, 0.0f);
        ImGui::Begin(id, nullptr, flags);
        ImGui::BringWindowToDisplayFront(ImGui::GetCurrentWindow());
        ImGui::InvisibleButton("##grip", size);
        const bool active = ImGui::IsItemActive();
        if (active || ImGui::IsItemHovered()) {
            ImGui::SetMouseCursor(cursor);
            ImGui::GetWindowDrawList()->AddRectFilled(
                at, ImVec2(at.x + size.x, at.y + size.y),
                active ? IM_COL32(120, 160, 230, 200) : IM_COL32(120, 160, 230, 110));
        }
        if (active) drag(ImGui::GetIO().MouseDelta);
        ImGui::End();
        ImGui::PopStyleVar(3);
    };
    const PanelRect& view = layout.view;
    const ImVec2 display = ImGui::GetIO().DisplaySize;
    splitter("##split_column", ImVec2(layout.column.x - kGrip / 2, view.y), ImVec2(kGrip, view.h),
             ImGuiMouseCursor_ResizeEW,
             [&](ImVec2 delta) { dragColumnSplitter(s.settings.layout, delta.x, display.x); });
    for (int i = 0; i < layout.columnPanels - 1; ++i) {
        const PanelRect& p = layout.panels[i];
        const std::string id = "##split_row" + std::to_string(i);
        splitter(id.c_str(), ImVec2(p.x, p.y + p.h - kGrip / 2), ImVec2(p.w, kGrip),
                 ImGuiMouseCursor_ResizeNS, [&](ImVec2 delta) {
                     // The shares are of the four panels' column: three of them fill it when
                     // the UV view lies beside the 3D view.
                     const float uvShare =
                         layout.columnPanels == 4 ? 0.0f : sanitised(s.settings.layout).shares[3];
                     dragRowSplitter(s.settings.layout, i, delta.y, view.h / (1.0f - uvShare));
                 });
    }
}

/// --frame-stats: where a frame's time goes. Each mark waits for the GL work queued so far
/// (glFinish), so the GPU's (llvmpipe's) share is booked to the phase that queued it: the UI
/// (events, panels, overlays; CPU), the preview's physics, the 3D scene, the panels' drawing
/// and the present (swap). The waits cost a little: the frame times of such a run are a bit
/// longer than a plain --frames run's.
class FramePhases {
public:
    enum Phase { Ui, Preview, Scene, Panels, Present, Count };
    explicit FramePhases(bool on) : on_(on) {}
    void start(std::chrono::steady_clock::time_point at) {
        if (!on_) return;
        last_ = at;
        for (auto& p : phases_) p.push_back(0.0);
    }
    void mark(Phase phase) {
        if (!on_) return;
        glFinish();
        const auto now = std::chrono::steady_clock::now();
        phases_[phase].back() += std::chrono::duration<double, std::milli>(now - last_).count();
        last_ = now;
    }
    /// Each phase's time in frame `i` (counted from 0), ms: where one long frame's time went.
    nlohmann::json frame(std::size_t i) const {
        nlohmann::json out;
        for (int p = 0; p < Count; ++p) {
            out[kNames[p]] = i < phases_[p].size() ? phases_[p][i] : 0.0;
        }
        return out;
    }
    /// Each phase's median over the frames after the first `skip`, ms.
    nlohmann::json report(std::size_t skip) const {
        nlohmann::json out;
        for (int p = 0; p < Count; ++p) {
            std::vector<double> v(phases_[p].begin() + std::min(skip, phases_[p].size()),
                                  phases_[p].end());
            std::sort(v.begin(), v.end());
            out[kNames[p]] = v.empty() ? 0.0 : v[v.size() / 2];
        }
        return out;
    }

private:
    static constexpr const char* kNames[Count] = {"ui_ms", "preview_ms", "scene_ms", "panels_ms",
                                                  "present_ms"};
    bool on_;
    std::chrono::steady_clock::time_point last_;
    std::vector<double> phases_[Count];
};

/// CPU time this process has used (user + system), s.
double processCpuSeconds() {
    rusage usage{};
    getrusage(RUSAGE_SELF, &usage);
    auto seconds = [](const timeval& t) { return t.tv_sec + t.tv_usec * 1e-6; };
    return seconds(usage.ru_utime) + seconds(usage.ru_stime);
}

/// The window's title: the document's (with its unsaved mark) and the program's name.
std::string windowTitle(const EditorState& s) { return s.document->title() + " - Plimsoll"; }

/// --state-file and --run-seconds' report: the window as the frame just drawn left it, for
/// window tests to wait on and check (integer pixels, so that a test can look for an exact
/// position in the text).
nlohmann::json windowState(const EditorState& s, int frame) {
    const ImGuiIO& io = ImGui::GetIO();
    const ImGuiContext& g = *ImGui::GetCurrentContext();
    nlohmann::json j;
    j["frame"] = frame;
    j["window"] = {static_cast<int>(io.DisplaySize.x), static_cast<int>(io.DisplaySize.y)};
    j["viewport"] = {static_cast<int>(s.viewport.x), static_cast<int>(s.viewport.y),
                     static_cast<int>(s.viewport.w), static_cast<int>(s.viewport.h)};
    // ImGui's mouse is -FLT_MAX while the pointer is outside the window.
    j["mouse"] =
        ImGui::IsMousePosValid(&io.MousePos)
            ? nlohmann::json{static_cast<int>(io.MousePos.x), static_cast<int>(io.MousePos.y)}
            : nlohmann::json{-1, -1};
    j["mouse_down"] = io.MouseDown[0];
    j["shift"] = io.KeyShift;  // a test waits for a held Shift to have been seen
    // The window of the control the mouse holds (a splitter's "##split_column"; "" when none).
    j["held"] = g.ActiveId != 0 && g.ActiveIdWindow ? g.ActiveIdWindow->Name : "";
    j["tooltip"] = tooltipShownThisFrame();
    j["undo"] = s.document->undoName();
    j["dirty"] = s.document->dirty();
    j["tool"] = static_cast<int>(s.tool);  // a test waits for B or G to have been seen
    j["view"] = viewName(s.camera);
    j["mirror_x"] = s.brush.mirrorX;
    j["preview_running"] = static_cast<bool>(s.preview->session);
    j["preview_playing"] = s.preview->session && s.preview->session->playing();
    j["title"] = windowTitle(s);
    j["status"] = s.status;
    j["export"] = bundleExportStatus(*s.exportDialog);
    j["bodies"] = s.document->bodyCount();
    j["radial_control"] = !s.radialControl ? "" : s.radialControl->strength ? "strength" : "radius";
    j["brush_radius"] = s.brush.radius;
    j["brush_strength"] = s.brush.strength;
    j["selected_body"] = s.selectedBody;
    j["camera_target"] = {s.camera.target.x(), s.camera.target.y(), s.camera.target.z()};
    j["uv_zoom"] = s.uvZoom;
    if (s.uvUnderMouse) j["uv_under_mouse"] = {s.uvUnderMouse->x(), s.uvUnderMouse->y()};
    // Where the tooltip was drawn, only when it was: ImGui hides a tooltip in the first frame
    // it appears (it measures itself), so the text alone does not mean it is on screen.
    if (const ImGuiWindow* tip = ImGui::FindWindowByName("##Tooltip_00");
        tip && tip->Active && !tip->Hidden) {
        j["tooltip_rect"] = {static_cast<int>(tip->Pos.x), static_cast<int>(tip->Pos.y),
                             static_cast<int>(tip->Size.x), static_cast<int>(tip->Size.y)};
    }
    // The windows on screen and open (not collapsed), by title, where they are: a test opens a
    // plot window and waits for it, then looks there in the picture.
    nlohmann::json windows = nlohmann::json::array();
    for (const ImGuiWindow* w : g.Windows) {
        constexpr ImGuiWindowFlags kNotPanels =
            ImGuiWindowFlags_ChildWindow | ImGuiWindowFlags_Tooltip | ImGuiWindowFlags_Popup;
        if (!w->Active || w->Hidden || w->Collapsed || (w->Flags & kNotPanels) || w->Name[0] == '#')
            continue;
        windows.push_back({{"name", w->Name},
                           {"rect",
                            {static_cast<int>(w->Pos.x), static_cast<int>(w->Pos.y),
                             static_cast<int>(w->Size.x), static_cast<int>(w->Size.y)}}});
    }
    j["windows"] = windows;
    // The modal or popup on top ("" when none) and where it is: a test waits for a question
    // ("Replace map?", "Export unsaved changes?") before it answers it.
    j["popup"] = "";
    if (!g.OpenPopupStack.empty()) {
        if (const ImGuiWindow* popup = g.OpenPopupStack.back().Window; popup && popup->Active) {
            j["popup"] = popup->Name;
            j["popup_rect"] = {static_cast<int>(popup->Pos.x), static_cast<int>(popup->Pos.y),
                               static_cast<int>(popup->Size.x), static_cast<int>(popup->Size.y)};
        }
    }
    return j;
}

bool isProjectFile(const std::string& path) {
    return path.size() > 10 && path.compare(path.size() - 10, 10, ".plim.json") == 0;
}

/// Open (or new) after the unsaved-changes question when there are unsaved changes.
void requestOpen(EditorState& s, const std::string& path, bool isNew) {
    if (s.document->dirty()) {
        s.pendingOpen = path;
        s.pendingNew = isNew;
        s.confirmDiscardOpen = true;
        return;
    }
    s.document->discardAutosave();
    s.open(isNew ? std::string() : path);
}

void handleDrops(EditorState& s) {
    for (const std::string& path : s.droppedPaths) {
        if (isProjectFile(path)) {
            requestOpen(s, path, false);
        } else {
            s.execute(makeImportMeshCommand(*s.document, path, std::nullopt));
            s.frameAll();
        }
    }
    s.droppedPaths.clear();
}

// [SECTION] menus and shortcuts ----------------------------------------------------------------

void frameSelected(EditorState& s) {
    if (s.selectedBody < 0 || static_cast<std::size_t>(s.selectedBody) >= s.document->bodyCount()) {
        s.frameAll();
        return;
    }
    const auto& mesh = s.document->assets(s.selectedBody).mesh;
    if (!mesh) return;
    Bounds3 bounds;
    const Pose pose = s.document->bodyPose(s.selectedBody);
    for (const Eigen::Vector3d& p : mesh->positions) {
        bounds.min = bounds.min.cwiseMin(pose.apply(p));
        bounds.max = bounds.max.cwiseMax(pose.apply(p));
    }
    s.camera.frame(bounds);
}

void togglePreview(EditorState& s) {
    if (s.preview && s.preview->session)
        stopPreview(s);
    else
        startPreview(s, true);
}

void playPause(EditorState& s) {
    if (!s.preview || !s.preview->session) return;
    PreviewSession& session = *s.preview->session;
    session.playing() ? session.pause() : session.play();
}

void handleKey(EditorState& s, int key, bool ctrl, bool shift) {
    if (ctrl) {
        if (key == GLFW_KEY_Z) shift ? s.redo() : s.undo();
        if (key == GLFW_KEY_Y) s.redo();
        if (key == GLFW_KEY_H) {
            s.showHistory = !s.showHistory;
            s.historyScrollPending = true;
        }
        if (key == GLFW_KEY_S) {
            if (shift)
                s.openSaveAs();
            else
                s.save();
        }
        if (key == GLFW_KEY_O)
            s.browser.open(FileBrowser::Purpose::OpenProject, s.document->project().folder);
        if (key == GLFW_KEY_N) requestOpen(s, "", true);
        if (key == GLFW_KEY_Q) s.requestQuit = true;
        return;
    }
    if (radialControlKey(s, key, shift)) return;  // F / Shift+F with the Brush, and its keys
    switch (key) {
        case GLFW_KEY_1:
        case GLFW_KEY_KP_1:
            s.setView(ViewPreset::Front);
            break;
        case GLFW_KEY_3:
        case GLFW_KEY_KP_3:
            s.setView(ViewPreset::Side);
            break;
        case GLFW_KEY_7:
        case GLFW_KEY_KP_7:
            s.setView(ViewPreset::Top);
            break;
        case GLFW_KEY_0:
        case GLFW_KEY_KP_0:
            s.setView(ViewPreset::Persp);
            break;
        case GLFW_KEY_5:
        case GLFW_KEY_KP_5:
            s.camera.orthographic = !s.camera.orthographic;
            break;
        case GLFW_KEY_HOME:
            s.frameAll();
            break;
        case GLFW_KEY_F:
            frameSelected(s);
            break;
        case GLFW_KEY_V:
            s.tool = Tool::Navigate;
            break;
        case GLFW_KEY_B:
            s.tool = Tool::Brush;
            break;
        case GLFW_KEY_G:
            s.tool = Tool::FillIsland;
            break;
        case GLFW_KEY_I:
            s.tool = Tool::Pick;
            break;
        case GLFW_KEY_E:
            s.brush.mode = s.brush.mode == BrushMode::Erase ? BrushMode::Paint : BrushMode::Erase;
            break;
        case GLFW_KEY_S:
            s.brush.mode = s.brush.mode == BrushMode::Smooth ? BrushMode::Paint : BrushMode::Smooth;
            break;
        case GLFW_KEY_X:
            // While the graph edits in the view, X (like Y and Z) holds a node drag on that
            // axis: it does not also flip the brush's mirror.
            if (!graphEditsInView(s)) s.brush.mirrorX = !s.brush.mirrorX;
            break;
        case GLFW_KEY_LEFT_BRACKET:
            s.brush.radius /= 1.25;
            break;
        case GLFW_KEY_RIGHT_BRACKET:
            s.brush.radius *= 1.25;
            break;
        case GLFW_KEY_F1:
            s.showShortcuts = true;
            break;
        case GLFW_KEY_P:
            togglePreview(s);
            break;
        case GLFW_KEY_SPACE:
            playPause(s);
            break;
        case GLFW_KEY_C:
            if (s.preview) s.preview->followBody = !s.preview->followBody;
            break;
        default:
            break;
    }
}

void drawMenus(EditorState& s) {
    if (!ImGui::BeginMainMenuBar()) return;
    const fs::path folder = s.document->project().folder;
    if (ImGui::BeginMenu("File")) {
        if (ImGui::MenuItem("New", "Ctrl+N")) requestOpen(s, "", true);
        if (ImGui::MenuItem("Open...", "Ctrl+O"))
            s.browser.open(FileBrowser::Purpose::OpenProject, folder);
        if (ImGui::BeginMenu("Open Recent", !s.settings.recentFiles.empty())) {
            for (const std::string& recent : s.settings.recentFiles) {
                if (ImGui::MenuItem(recent.c_str())) {
                    requestOpen(s, recent, false);
                    break;
                }
            }
            ImGui::EndMenu();
        }
        if (ImGui::MenuItem("Import Mesh..."))
            s.browser.open(FileBrowser::Purpose::ImportMesh, folder);
        ImGui::Separator();
        if (ImGui::MenuItem("Save", "Ctrl+S")) s.save();
        if (ImGui::MenuItem("Save As...", "Ctrl+Shift+S")) s.openSaveAs();
        if (ImGui::MenuItem("Export bundle..."))
            s.browser.open(FileBrowser::Purpose::Export, folder);
        ImGui::Separator();
        if (ImGui::MenuItem("Quit", "Ctrl+Q")) s.requestQuit = true;
        ImGui::EndMenu();
    }
    if (ImGui::BeginMenu("Edit")) {
        const std::string undo = "Undo " + s.document->undoName();
        const std::string redo = "Redo " + s.document->redoName();
        if (ImGui::MenuItem(undo.c_str(), "Ctrl+Z", false, s.document->canUndo())) s.undo();
        if (ImGui::MenuItem(redo.c_str(), "Ctrl+Shift+Z", false, s.document->canRedo())) s.redo();
        ImGui::Separator();
        if (ImGui::MenuItem("Undo history", "Ctrl+H", s.showHistory)) {
            s.showHistory = !s.showHistory;
            s.historyScrollPending = true;
        }
        ImGui::EndMenu();
    }
    if (ImGui::BeginMenu("View")) {
        if (ImGui::MenuItem("Front", "1")) s.setView(ViewPreset::Front);
        if (ImGui::MenuItem("Side", "3")) s.setView(ViewPreset::Side);
        if (ImGui::MenuItem("Top", "7")) s.setView(ViewPreset::Top);
        if (ImGui::MenuItem("Perspective", "0")) s.setView(ViewPreset::Persp);
        if (ImGui::MenuItem("Orthographic", "5", s.camera.orthographic)) {
            s.camera.orthographic = !s.camera.orthographic;
        }
        if (ImGui::MenuItem("Frame all", "Home")) s.frameAll();
        if (ImGui::MenuItem("Frame selected", "F")) frameSelected(s);
        ImGui::Separator();
        ImGui::MenuItem("Water", nullptr, &s.showWater);
        ImGui::MenuItem("Grid and axes", nullptr, &s.showGrid);
        ImGui::MenuItem("Show physics solid / caps", nullptr, &s.showPhysicsSolid);
        ImGui::Separator();
        // Kept in the settings with the rest of the layout.
        if (ImGui::MenuItem("UV view beside the 3D view", nullptr,
                            s.settings.layout.uvBesideView)) {
            s.settings.layout.uvBesideView = !s.settings.layout.uvBesideView;
            (void)s.settings.save();
        }
        ImGui::EndMenu();
    }
    if (ImGui::BeginMenu("Simulate")) {
        const bool running = s.preview && s.preview->session;
        if (ImGui::MenuItem("Live preview", "P", running)) togglePreview(s);
        if (ImGui::MenuItem("Restart live preview", nullptr, false, running)) startPreview(s, true);
        if (ImGui::MenuItem("Play / pause", "Space", false, running)) playPause(s);
        ImGui::Separator();
        if (ImGui::MenuItem("Hydrostatics...")) {
            s.showHydrostatics = true;
            s.hydrostaticsOpenRequest = true;
        }
        ImGui::EndMenu();
    }
    if (ImGui::BeginMenu("Help")) {
        if (ImGui::MenuItem("Keyboard shortcuts", "F1")) s.showShortcuts = true;
        if (ImGui::MenuItem("About Plimsoll")) s.showAbout = true;
        ImGui::EndMenu();
    }
    ImGui::EndMainMenuBar();
}

}  // namespace

void openWhenTitleClicked() {
    ImGuiWindow* w = ImGui::GetCurrentWindow();
    const ImGuiIO& io = ImGui::GetIO();
    if (!w || !w->Collapsed || w->WantCollapseToggle) return;  // open, or ImGui toggles it already
    // A click (not a drag: that moves the window) released over the title bar.
    if (ImGui::IsMouseReleased(0) && ImGui::IsWindowHovered() &&
        io.MouseDragMaxDistanceSqr[0] < 16.0f) {
        ImGui::SetWindowCollapsed(false);
    }
}

bool mouseOverNoWindow() {
    return !ImGui::IsWindowHovered(ImGuiHoveredFlags_AnyWindow |
                                   ImGuiHoveredFlags_AllowWhenBlockedByPopup);
}

bool closeMenus() {
    ImGuiContext& g = *ImGui::GetCurrentContext();
    int keep = 0;
    for (int i = 0; i < g.OpenPopupStack.Size; ++i) {
        const ImGuiWindow* w = g.OpenPopupStack[i].Window;
        if (w && (w->Flags & ImGuiWindowFlags_Modal)) keep = i + 1;
    }
    if (keep >= g.OpenPopupStack.Size) return false;
    ImGui::ClosePopupToLevel(keep, true);
    return true;
}

namespace {

void handleShortcuts(EditorState& s) {
    // From the key callback's queue, not ImGui's key state: a tap shorter than a frame is
    // pressed and released before the frame looks (ImGui 1.86 would miss it).
    std::vector<std::pair<int, int>> presses;
    presses.swap(s.keyPresses);
    const ImGuiIO& io = ImGui::GetIO();
    // Esc closes an open menu (and any popup over it), as in every desktop program; ImGui 1.86
    // does so only with keyboard navigation on. A modal question keeps its own buttons.
    const auto escape = std::find_if(presses.begin(), presses.end(), [](const auto& press) {
        return press.first == GLFW_KEY_ESCAPE;
    });
    if (escape != presses.end() && closeMenus()) presses.erase(escape);
    if (io.WantTextInput) return;
    for (const auto& [key, mods] : presses)
        handleKey(s, key, (mods & GLFW_MOD_CONTROL) != 0, (mods & GLFW_MOD_SHIFT) != 0);
}

// [SECTION] dialogs ----------------------------------------------------------------------------

/// What the file browser chose: open, save as, import or export it.
void fileChosen(EditorState& s) {
    if (auto chosen = s.browser.draw()) {
        switch (s.browser.purpose()) {
            case FileBrowser::Purpose::OpenProject:
                requestOpen(s, chosen->string(), false);
                break;
            case FileBrowser::Purpose::SaveProjectAs:
                s.saveAs(*chosen);
                break;
            case FileBrowser::Purpose::ImportMesh:
                // The new body is the last: selected, so that the inspector shows it.
                if (s.execute(makeImportMeshCommand(*s.document, *chosen, std::nullopt))) {
                    s.selectedBody = static_cast<int>(s.document->bodyCount()) - 1;
                }
                s.frameAll();
                break;
            case FileBrowser::Purpose::Export:
                // Bundles are made from the files on disk: with unsaved edits, ask first
                // rather than export what is not on screen.
                if (s.document->dirty()) {
                    s.pendingExport = *chosen;
                    ImGui::OpenPopup("Export unsaved changes?");
                } else {
                    startBundleExport(*s.exportDialog, s.document->project(), *chosen, false);
                }
                break;
        }
    }
}

/// Save As over existing files: replace them or save nothing.
void replaceFilesQuestion(EditorState& s) {
    if (s.pendingSaveAs && !ImGui::IsPopupOpen("Replace existing files?"))
        ImGui::OpenPopup("Replace existing files?");
    if (ImGui::BeginPopupModal("Replace existing files?", nullptr,
                               ImGuiWindowFlags_AlwaysAutoResize)) {
        ImGui::Text("Saving as %s replaces:",
                    s.pendingSaveAs ? s.pendingSaveAs->filename().c_str() : "");
        for (const std::filesystem::path& file : s.pendingSaveAsReplaces)
            ImGui::BulletText("%s", file.c_str());
        if (ImGui::Button("Replace")) {
            if (s.pendingSaveAs) s.saveAs(*s.pendingSaveAs, /*replace=*/true);
            ImGui::CloseCurrentPopup();
        }
        tooltip("Saves over the files listed (each replaced whole, never half-written).");
        ImGui::SameLine();
        if (ImGui::Button("Cancel")) {
            s.pendingSaveAs.reset();
            s.status = "Not saved: nothing was replaced";
            ImGui::CloseCurrentPopup();
        }
        tooltip("Saves nothing; the files stay as they are.");
        ImGui::EndPopup();
    }
}

/// Export with unsaved edits: save first, export the last save, or nothing.
void exportUnsavedQuestion(EditorState& s) {
    if (ImGui::BeginPopupModal("Export unsaved changes?", nullptr,
                               ImGuiWindowFlags_AlwaysAutoResize)) {
        ImGui::Text("%s has unsaved changes; a bundle is made from the saved files.",
                    s.document->title().c_str());
        if (ImGui::Button("Save and export")) {
            s.save();
            if (!s.document->dirty() && s.pendingExport) {
                startBundleExport(*s.exportDialog, s.document->project(), *s.pendingExport, false);
            }
            s.pendingExport.reset();
            ImGui::CloseCurrentPopup();
        }
        tooltip("Saves the project, then exports what is on screen.");
        ImGui::SameLine();
        if (ImGui::Button("Export the last save")) {
            if (s.pendingExport) {
                startBundleExport(*s.exportDialog, s.document->project(), *s.pendingExport, true);
            }
            s.pendingExport.reset();
            ImGui::CloseCurrentPopup();
        }
        tooltip("Exports the files as last saved; the unsaved changes stay in the editor only.");
        ImGui::SameLine();
        if (ImGui::Button("Cancel")) {
            s.pendingExport.reset();
            ImGui::CloseCurrentPopup();
        }
        tooltip("Exports nothing.");
        ImGui::EndPopup();
    }
}

/// Open, new or quit with unsaved changes: save, discard or stay.
void unsavedChangesQuestion(EditorState& s, GLFWwindow* window) {
    if (s.confirmDiscardOpen) {
        ImGui::OpenPopup("Unsaved changes");
        s.confirmDiscardOpen = false;
    }
    if (ImGui::BeginPopupModal("Unsaved changes", nullptr, ImGuiWindowFlags_AlwaysAutoResize)) {
        ImGui::Text("%s has unsaved changes.", s.document->title().c_str());
        auto proceed = [&] {
            if (s.requestQuit) {
                glfwSetWindowShouldClose(window, GLFW_TRUE);
            } else if (s.pendingNew || !s.pendingOpen.empty()) {
                s.open(s.pendingNew ? std::string() : s.pendingOpen);
            }
            s.pendingOpen.clear();
            s.pendingNew = false;
            ImGui::CloseCurrentPopup();
        };
        if (ImGui::Button("Save")) {
            s.save();
            if (!s.document->dirty()) proceed();
        }
        tooltip("Saves the changes first, then goes on.");
        ImGui::SameLine();
        if (ImGui::Button("Discard")) {
            s.document->discardAutosave();
            proceed();
        }
        tooltip("Goes on without saving: the changes since the last save are lost.");
        ImGui::SameLine();
        if (ImGui::Button("Cancel")) {
            s.requestQuit = false;
            s.pendingOpen.clear();
            s.pendingNew = false;
            ImGui::CloseCurrentPopup();
        }
        tooltip("Stays with this project, changes kept.");
        ImGui::EndPopup();
    }
}

/// An autosave left by a crash: recover it or delete it.
void recoveryQuestion(EditorState& s) {
    if (s.recoveryOffer) {
        ImGui::OpenPopup("Recover autosave");
    }
    if (ImGui::BeginPopupModal("Recover autosave", nullptr, ImGuiWindowFlags_AlwaysAutoResize)) {
        ImGui::TextUnformatted("Plimsoll did not close cleanly last time.");
        ImGui::Text("An autosave with unsaved changes exists:\n%s",
                    s.recoveryOffer->string().c_str());
        if (ImGui::Button("Recover")) {
            auto recovered = Document::recover(*s.recoveryOffer);
            if (recovered) {
                s.document = std::move(recovered).value();
                s.overlaysDirty = true;
                ++s.documentRevision;
                s.status = "Recovered the autosave (not saved yet)";
            } else {
                s.status = recovered.error().message;
            }
            s.recoveryOffer.reset();
            ImGui::CloseCurrentPopup();
        }
        tooltip("Opens the autosaved edits (unsaved until you save them).");
        ImGui::SameLine();
        if (ImGui::Button("Discard it")) {
            std::error_code ec;
            fs::remove(*s.recoveryOffer, ec);
            s.recoveryOffer.reset();
            ImGui::CloseCurrentPopup();
        }
        tooltip("Deletes the autosave; the saved project is untouched.");
        ImGui::EndPopup();
    }
}

/// Help > Keyboard shortcuts and About.
void helpWindows(EditorState& s) {
    if (s.showShortcuts) {
        ImGui::Begin("Keyboard shortcuts", &s.showShortcuts, ImGuiWindowFlags_AlwaysAutoResize);
        ImGui::TextUnformatted(
            "Middle mouse: orbit   Shift+middle: pan   Ctrl+middle / wheel: zoom\n"
            "Alt+left mouse: orbit   Right mouse: pan\n"
            "1 / 3 / 7: front / side / top   0: perspective   5: orthographic on/off\n"
            "Home: frame all   F: frame selected (with the Brush: F drags its radius,\n"
            "  Shift+F its strength; click or Enter keeps, Esc or right mouse cancels)\n"
            "UV view: wheel zooms at the cursor, middle mouse pans, middle double-click: all\n"
            "V: navigate   B: brush   G: fill island   I: pick value\n"
            "E: erase on/off   S: smooth on/off   X: X-mirror   [ ]: brush radius\n"
            "P: live preview on/off   Space: play / pause the preview   C: camera follows the "
            "body\n"
            "Ctrl+Z: undo   Ctrl+Shift+Z / Ctrl+Y: redo   Ctrl+H: undo history\n"
            "Ctrl+N / Ctrl+O / Ctrl+S / Ctrl+Shift+S: new / open / save / save as   Ctrl+Q: quit\n"
            "Drop a .plim.json to open it, a mesh to import it.");
        ImGui::End();
    }
    if (s.showAbout) {
        ImGui::Begin("About Plimsoll", &s.showAbout, ImGuiWindowFlags_AlwaysAutoResize);
        ImGui::Text("Plimsoll %s: real-time buoyancy from surface textures.", PLIMSOLL_VERSION);
        ImGui::TextUnformatted("After Bajo, Patow, Delrieux, Computer Graphics Forum 39(6), 2020.");
        ImGui::End();
    }
}

void drawDialogs(EditorState& s, GLFWwindow* window) {
    drawBundleExport(*s.exportDialog);
    fileChosen(s);
    replaceFilesQuestion(s);
    exportUnsavedQuestion(s);
    unsavedChangesQuestion(s, window);
    recoveryQuestion(s);
    helpWindows(s);
}

// [SECTION] frame loop -------------------------------------------------------------------------

void updateStroke(EditorState& s) {
    if (!s.stroke.active) return;
    if (!ImGui::IsMouseDown(0)) {
        // Release: the whole stroke becomes one command (one undo step).
        if (!s.stroke.points.empty() &&
            s.execute(makeStrokeCommand(*s.document, s.stroke.body, s.channel, s.brush,
                                        s.stroke.points, s.paintTarget()))) {
            s.lastStrokeEnd = {s.stroke.body, s.stroke.points.back()};
            s.lastStrokePoints = s.stroke.points.size();
        }
        s.stroke = {};
        s.overlaysDirty = true;
        return;
    }
    if (!s.stroke.previewDirty || s.stroke.points.empty()) return;
    s.stroke.previewDirty = false;
    if (!s.document->map(s.stroke.body, s.channel)) return;  // the map is made when the stroke ends
    auto command = makeStrokeCommand(*s.document, s.stroke.body, s.channel, s.brush,
                                     s.stroke.points, s.paintTarget());
    auto* paint = command ? dynamic_cast<PaintCommand*>(command->get()) : nullptr;
    if (!paint) return;
    s.renderer->setOverlay(static_cast<int>(s.stroke.body),
                           overlayOfMap(paint->preview(*s.document)));
}

void uploadOverlays(EditorState& s) {
    if (!s.overlaysDirty) return;
    s.overlaysDirty = false;
    for (std::size_t b = 0; b < s.document->bodyCount() + 4; ++b) {
        OverlayImage none;
        if (b >= s.document->bodyCount() || s.overlay == Overlay::None ||
            !s.document->assets(b).mesh) {
            s.renderer->setOverlay(static_cast<int>(b), none);
            continue;
        }
        if (overlayChannel(s.overlay)) {
            s.renderer->setOverlay(static_cast<int>(b), buildMapOverlay(*s.document, b, s.overlay));
            continue;
        }
        // The physics overlays from the textures baked in the background (none until the
        // first bake arrives; its poll marks the overlays for refresh).
        const auto textures = s.physicsFor(b);
        s.renderer->setOverlay(static_cast<int>(b),
                               textures ? overlayOfTextures(*textures, s.overlay) : none);
        if (const std::string error = s.physicsBakes->error(b); !error.empty()) s.status = error;
    }
}

RenderScene sceneOf(EditorState& s) {
    RenderScene scene;
    scene.water = s.showWater ? &s.document->project().water : nullptr;
    scene.time = s.waterTime;
    scene.grid = scene.axes = s.showGrid;
    for (std::size_t b = 0; b < s.document->bodyCount(); ++b) {
        RenderBody body;
        body.mesh = s.document->assets(b).mesh;
        body.pose = s.document->bodyPose(b);
        body.selected = static_cast<int>(b) == s.selectedBody;
        body.overlay = s.renderer->overlayTexture(static_cast<int>(b)) ? static_cast<int>(b) : -1;
        scene.bodies.push_back(std::move(body));
    }
    addGraphToScene(s, scene);
    return scene;
}

/// View > Show physics solid / caps: see-through over each body where it is drawn (its starting
/// pose, or the preview's), the solid it is simulated as (when that is not its mesh) and its
/// caps, more opaque. After the bodies' poses are final, appended after them.
void addPhysicsSolidsToScene(EditorState& s, RenderScene& scene) {
    if (!s.showPhysicsSolid) return;
    const std::size_t bodies = std::min(scene.bodies.size(), s.document->bodyCount());
    for (std::size_t b = 0; b < bodies; ++b) {
        const PhysicsSolids::Solid solid = s.physicsSolids->solidFor(*s.document, b);
        for (const auto& [mesh, alpha] :
             {std::pair{solid.solid, 0.25f}, std::pair{solid.caps, 0.6f}}) {
            if (!mesh) continue;
            RenderBody overlay;
            overlay.mesh = mesh;
            overlay.pose = scene.bodies[b].pose;
            overlay.alpha = alpha;
            scene.bodies.push_back(std::move(overlay));
        }
    }
}

bool writeScreenshot(const std::string& path, int width, int height) {
    std::vector<unsigned char> pixels(static_cast<std::size_t>(width) * height * 4);
    glReadBuffer(GL_BACK);
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    glReadPixels(0, 0, width, height, GL_RGBA, GL_UNSIGNED_BYTE, pixels.data());
    const std::size_t row = static_cast<std::size_t>(width) * 4;
    for (int y = 0; y < height / 2; ++y) {
        std::swap_ranges(pixels.begin() + y * row, pixels.begin() + (y + 1) * row,
                         pixels.begin() + (height - 1 - y) * row);
    }
    std::string png;
    const auto append = [](void* context, void* data, int size) {
        static_cast<std::string*>(context)->append(static_cast<const char*>(data), size);
    };
    if (!stbi_write_png_to_func(append, &png, width, height, 4, pixels.data(), int(row)))
        return false;
    return writeFileAtomically(path,
                               [&](std::ostream& out) {
                                   out.write(png.data(), static_cast<std::streamsize>(png.size()));
                                   return static_cast<bool>(out);
                               })
        .ok();
}

/// One refresh of the fastest display (so that a window on a 144 Hz display is not held to 60),
/// or of 60 Hz where no display gives its rate.
std::chrono::steady_clock::duration displayFramePeriod() {
    int refreshRate = 0, monitorCount = 0;
    if (GLFWmonitor** monitors = glfwGetMonitors(&monitorCount)) {
        for (int m = 0; m < monitorCount; ++m)
            if (const GLFWvidmode* mode = glfwGetVideoMode(monitors[m]))
                refreshRate = std::max(refreshRate, mode->refreshRate);
    }
    return std::chrono::duration_cast<std::chrono::steady_clock::duration>(
        std::chrono::duration<double>(1.0 / (refreshRate > 0 ? refreshRate : 60)));
}

/// The scripted and measured runs' side of the window (--frames, --run-seconds, --snapshot,
/// --screenshot, --state-file, --frame-stats, --texture-size): what is recorded each frame and
/// reported at the end, kept apart from the frame loop, which an interactive session runs
/// without any of it.
class FrameHarness {
public:
    explicit FrameHarness(const EditorLaunch& launch)
        : phases(launch.frameStats), launch_(launch) {}

    FramePhases phases;

    /// --snapshot FRAME:PATH, each FRAME > 0; false (with the message printed) otherwise.
    bool readSnapshots() {
        for (const std::string& spec : launch_.snapshots) {
            const auto colon = spec.find(':');
            const int at =
                colon == std::string::npos ? 0 : std::atoi(spec.substr(0, colon).c_str());
            if (at <= 0) {
                std::cerr << "error: --snapshot " << spec << ": expected FRAME:PATH, FRAME > 0\n";
                return false;
            }
            snapshots_.emplace_back(at, spec.substr(colon + 1));
        }
        return true;
    }

    /// The run's clock starts as the frame loop does (after start-up).
    void startClock() { runStart_ = std::chrono::steady_clock::now(); }
    double elapsed() const {
        return std::chrono::duration<double>(std::chrono::steady_clock::now() - runStart_).count();
    }
    /// --run-seconds, before each frame: true when the run ends now. With --screenshot one more
    /// frame is drawn (an idle loop may have drawn none lately) and written: finalFrame().
    bool timeIsUp() {
        if (launch_.runSeconds <= 0) return false;
        if (!cpuAtOneSecond_ && elapsed() >= 1.0) cpuAtOneSecond_ = processCpuSeconds();
        if (elapsed() < launch_.runSeconds) return false;
        if (launch_.screenshot.empty()) return true;
        finalFrame_ = true;
        return false;
    }
    bool finalFrame() const { return finalFrame_; }
    /// An idle wait, cut short where --run-seconds ends first.
    double idleWait(double wait) const {
        return launch_.runSeconds > 0 ? std::clamp(launch_.runSeconds - elapsed(), 0.01, wait)
                                      : wait;
    }
    void frameDrawn() {
        if (cpuAtOneSecond_) ++framesAfterOneSecond_;
    }
    bool lastFrame(int frame) const { return launch_.frames > 0 && frame >= launch_.frames; }

    /// After a frame is drawn, before it is shown: the snapshots due and the screenshot of the
    /// last frame (of --frames, of the time of --run-seconds, or as the window closes).
    void capture(EditorState& s, int frame, int fbWidth, int fbHeight, bool windowClosing) {
        if (frame == kSteadyFrom) cpuAtSteady_ = processCpuSeconds();
        for (const auto& [at, path] : snapshots_) {
            if (at != frame) continue;
            glFinish();
            screenshotOk_ = writeScreenshot(path, fbWidth, fbHeight) && screenshotOk_;
            nlohmann::json shot = previewReport(s);
            shot["frame"] = frame;
            shot["path"] = path;
            snapshotReports_.push_back(shot);
        }
        const bool lastInteractive = launch_.runSeconds > 0 && (finalFrame_ || windowClosing);
        if ((lastFrame(frame) || lastInteractive) && !launch_.screenshot.empty()) {
            glFinish();
            screenshotOk_ = writeScreenshot(launch_.screenshot, fbWidth, fbHeight);
        }
    }
    /// --state-file: the window's state after each frame, for tests that drive it.
    void writeState(EditorState& s, int frame) const {
        if (launch_.stateFile.empty()) return;
        const std::string line = windowState(s, frame).dump() + "\n";
        (void)writeFileAtomically(launch_.stateFile, [&](std::ostream& out) {
            out << line;
            return static_cast<bool>(out);
        });
    }

    /// The frame's time; with --texture-size (or the inspector's), the new size is asked for in
    /// frame 2 and the frames are timed while it bakes. True when that measurement is over.
    bool recordFrame(EditorState& s, double ms, int frame) {
        frameMs_.push_back(ms);
        if (!rebakeRequested(s)) return false;
        if (!textureSizeRequested_ && frame == 2) {
            if (launch_.inspectorTextureSize > 0)
                (void)s.setTextureSize(0, launch_.inspectorTextureSize);
            else
                s.preview->session->requestTextureSize(launch_.textureSize);
            textureSizeRequested_ = true;
        } else if (textureSizeRequested_) {
            // While it bakes, and the frame it was swapped in (or failed) in: that frame's cost
            // (the new textures taken in) counts too. The frame after shows the new size.
            ++bakingFrames_;
            if (ms > bakingFrameMsMax_) {
                bakingFrameMsMax_ = ms;
                bakingFrameLongest_ = frameMs_.size() - 1;
            }
            if (!rebaking(s)) {
                arrivalFrameMs_ = ms;
                return true;
            }
        }
        return false;
    }

    /// What --run-seconds prints: the interactive loop's cost after its first second and the
    /// state it ended in.
    void reportRunSeconds(EditorState& s, const ImGuiIO& io, const std::string& title,
                          int frame) const {
        nlohmann::json report;
        report["seconds"] = elapsed();
        report["frames_after_first_second"] = framesAfterOneSecond_;
        report["cpu_seconds_after_first_second"] =
            cpuAtOneSecond_ ? processCpuSeconds() - *cpuAtOneSecond_ : 0.0;
        report["view"] = viewName(s.camera);
        report["tool"] = static_cast<int>(s.tool);
        report["mirror_x"] = s.brush.mirrorX;
        report["preview_running"] = static_cast<bool>(s.preview->session);
        report["preview_playing"] = s.preview->session && s.preview->session->playing();
        report["title"] = title;
        report["window"] = {io.DisplaySize.x, io.DisplaySize.y};
        report["viewport"] = {s.viewport.x, s.viewport.y, s.viewport.w, s.viewport.h};
        report["undo"] = s.document->undoName();
        report["status"] = s.status;
        report["last_stroke_points"] = s.lastStrokePoints;
        report["last_frame"] = windowState(s, frame);
        if (s.preview->session) report["preview"] = previewReport(s);
        int steps = 0;  // the history's length (the run is over: undoing costs nothing now)
        while (s.document->undo()) ++steps;
        report["undo_steps"] = steps;
        std::cout << report.dump(2) << std::endl;
    }

    /// What --frames prints: frame times after the first few (shader compiles, first uploads),
    /// the snapshots, the phases and the rebake's frames.
    void reportFrames(EditorState& s, const ImGuiIO& io, const std::string& title, int frame,
                      const PanelCache& panelCache) {
        const std::size_t warmUp = std::min<std::size_t>(frameMs_.size() / 4, 10);
        std::vector<double> steady(frameMs_.begin() + warmUp, frameMs_.end());
        std::sort(steady.begin(), steady.end());
        double sum = 0;
        for (double ms : steady) sum += ms;
        nlohmann::json report;
        report["frames"] = frame;
        report["frame_ms_mean"] = steady.empty() ? 0.0 : sum / steady.size();
        report["frame_ms_median"] = steady.empty() ? 0.0 : steady[steady.size() / 2];
        report["first_frame_ms"] = frameMs_.empty() ? 0.0 : frameMs_.front();
        report["window"] = {io.DisplaySize.x, io.DisplaySize.y};
        report["viewport"] = {s.viewport.x, s.viewport.y, s.viewport.w, s.viewport.h};
        report["gl_renderer"] = reinterpret_cast<const char*>(glGetString(GL_RENDERER));
        report["title"] = title;
        if (!launch_.screenshot.empty()) report["screenshot"] = launch_.screenshot;
        if (!snapshotReports_.empty()) report["snapshots"] = snapshotReports_;
        if (s.preview->session) report["preview"] = previewReport(s);
        if (launch_.frameStats) {
            nlohmann::json stats = phases.report(warmUp);
            if (frame > kSteadyFrom) {
                stats["cpu_ms_per_frame"] =
                    1000.0 * (processCpuSeconds() - cpuAtSteady_) / (frame - kSteadyFrom);
            }
            stats["scene_frames_drawn"] = s.renderer->framesDrawn();
            stats["scene_frames_copied"] = s.renderer->framesCopied();
            stats["panel_frames_kept"] = panelCache.framesKept();
            stats["panel_frames_copied"] = panelCache.framesCopied();
            report["frame_stats"] = stats;
        }
        if (rebakeRequested(s)) report["rebake"] = rebakeReport(s);
        std::cout << report.dump(2) << std::endl;
    }

    bool screenshotOk() const { return screenshotOk_; }

private:
    /// CPU of every thread (UI, llvmpipe's rasteriser threads, workers) is counted over the
    /// steady frames, from this one: a figure that a busy machine inflates far less than
    /// wall-clock frame times.
    static constexpr int kSteadyFrom = 10;

    /// The preview panel's request needs a running preview; the inspector's works either way.
    bool rebakeRequested(const EditorState& s) const {
        return (launch_.textureSize > 0 && s.preview->session) ||
               (launch_.inspectorTextureSize > 0 && s.document->bodyCount() > 0);
    }
    bool rebaking(const EditorState& s) const {
        return (s.preview->session && s.preview->session->rebuilding()) ||
               (launch_.inspectorTextureSize > 0 && s.physicsBakes->busy());
    }

    nlohmann::json rebakeReport(EditorState& s) {
        nlohmann::json rebake = {
            {"requested", std::max(launch_.textureSize, launch_.inspectorTextureSize)},
            {"frames_while_baking", bakingFrames_},
            {"frame_ms_max_while_baking", bakingFrameMsMax_},
            {"frame_ms_arrival", arrivalFrameMs_},
            {"longest_frame", static_cast<int>(bakingFrameLongest_) + 1}};
        // Where the longest frame's time went (the frame-stats phases of that one frame).
        if (launch_.frameStats) rebake["longest_frame_phases"] = phases.frame(bakingFrameLongest_);
        if (s.preview->session) {
            rebake["texture_size"] = s.preview->session->textureSize();
            rebake["error"] = s.preview->session->rebuildError();
        }
        if (launch_.inspectorTextureSize > 0) {
            // What the inspector shows: the document's size and the textures baked for it, by
            // a thread that is not this (the frame loop's) one.
            const auto baked = s.document->bakedPhysics(0);
            rebake["document_texture_size"] = s.document->project().bodies[0].textureSize;
            rebake["document_baked_size"] = baked ? baked->size : 0;
            rebake["document_error"] = s.physicsBakes->error(0);
            rebake["baked_on_worker"] = s.physicsBakes->lastWorker(0) != std::thread::id() &&
                                        s.physicsBakes->lastWorker(0) != std::this_thread::get_id();
        }
        return rebake;
    }

    const EditorLaunch& launch_;
    std::chrono::steady_clock::time_point runStart_ = std::chrono::steady_clock::now();
    std::vector<std::pair<int, std::string>> snapshots_;
    nlohmann::json snapshotReports_ = nlohmann::json::array();
    bool screenshotOk_ = true;
    std::vector<double> frameMs_;
    double cpuAtSteady_ = 0;
    // --run-seconds: the interactive loop, timed (CPU from one second in, after start-up).
    std::optional<double> cpuAtOneSecond_;
    int framesAfterOneSecond_ = 0;
    bool finalFrame_ = false;
    // --texture-size: the frames drawn while the new size baked, and the longest of them.
    bool textureSizeRequested_ = false;
    int bakingFrames_ = 0;
    double bakingFrameMsMax_ = 0;
    std::size_t bakingFrameLongest_ = 0;  ///< its index in frameMs_ (--frame-stats: its phases)
    double arrivalFrameMs_ = 0;           ///< the frame in which the new size was taken in
};

/// The window with an OpenGL 4.5 core context and the editor's input callbacks, or null (with
/// the message printed and GLFW shut down).
GLFWwindow* openEditorWindow(const EditorLaunch& launch, EditorState& s) {
    glfwSetErrorCallback([](int code, const char* message) {
        std::cerr << "glfw error " << code << ": " << message << "\n";
    });
    if (!glfwInit()) {
        std::cerr << "error: cannot open the editor window (no display?). The headless "
                     "sub-commands work without one: plimsoll --help\n";
        return nullptr;
    }
    const int width = launch.width > 0 ? launch.width : s.settings.windowWidth;
    const int height = launch.height > 0 ? launch.height : s.settings.windowHeight;
    glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 4);
    glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 5);
    glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
    glfwWindowHint(GLFW_OPENGL_FORWARD_COMPAT, GLFW_TRUE);
    GLFWwindow* window = glfwCreateWindow(width, height, "Plimsoll", nullptr, nullptr);
    if (!window) {
        std::cerr << "error: cannot create an OpenGL 4.5 core window\n";
        glfwTerminate();
        return nullptr;
    }
    glfwMakeContextCurrent(window);
    glfwSwapInterval(launch.frames > 0 ? 0 : 1);
    glfwSetWindowUserPointer(window, &s);
    glfwSetDropCallback(window, onDrop);
    glfwSetWindowCloseCallback(window, onClose);
    glfwSetKeyCallback(window, onKey);
    glfwSetCharCallback(window, onChar);
    glfwSetMouseButtonCallback(window, onMouseButton);
    glfwSetScrollCallback(window, onScroll);
    glfwSetCursorPosCallback(window, onCursor);
    glfwSetWindowSizeCallback(window, onResize);
    glfwSetWindowRefreshCallback(window, onRefresh);
    glfwSetWindowFocusCallback(window, onFocus);
    glfwSetCursorEnterCallback(window, onEnter);

    IMGUI_CHECKVERSION();
    ImGui::CreateContext();
    ImGui::GetIO().IniFilename = nullptr;  // the layout is fixed; settings.json holds what persists
    ImGui::StyleColorsDark();
    ImGui_ImplGlfw_InitForOpenGL(window, true);
    ImGui_ImplOpenGL3_Init("#version 450 core");
    return window;
}

/// The settings, the brush as it was last used, the renderer, the project (or the offer to
/// recover an unsaved session), the launch's view and overlay, and the preview when asked for.
/// False with the message printed where the run cannot go on.
bool startSession(const EditorLaunch& launch, EditorState& s) {
    Result<std::unique_ptr<Renderer>> renderer = Renderer::create();
    if (!renderer) {
        std::cerr << "error: " << renderer.error().message << "\n";
        return false;
    }
    s.renderer = std::move(renderer).value();
    s.renderer->warmUpOnFirstDraw();  // the first frame pays the kept scene's start-up cost
    if (!s.open(launch.project)) {
        std::cerr << "error: " << s.status << "\n";
        if (!launch.project.empty()) return false;
    }
    if (launch.project.empty()) {
        // Started with nothing to open: an autosave of the untitled document, or of the most
        // recent project, means the last session did not end cleanly.
        s.recoveryOffer = Document::findAutosave("");
        if (!s.recoveryOffer && !s.settings.recentFiles.empty()) {
            s.recoveryOffer = Document::findAutosave(s.settings.recentFiles.front());
        }
    }
    if (launch.frames > 0) s.recoveryOffer.reset();  // measurements answer no questions
    if (const auto view = parseViewPreset(launch.view.empty() ? "persp" : launch.view)) {
        s.setView(*view);
    }
    if (!launch.overlay.empty()) {
        if (const auto overlay = parseOverlay(launch.overlay)) s.overlay = *overlay;
    }
    s.showPhysicsSolid = launch.showPhysicsSolid;
    s.lastAutosave = glfwGetTime();
    s.preview = std::make_shared<PreviewUi>();
    s.preview->fixedStep = launch.frames > 0;
    return true;
}

/// One frame's interface, up to ImGui::Render: the menu bar, the 3D view on the left, tools /
/// layers / inspector / UV view in the column on the right, the floating panels and the status
/// line at the bottom; then input, the preview's step, dialogs, the stroke and the overlays.
WindowLayout buildFrameUi(EditorState& s, GLFWwindow* window, FramePhases& phases) {
    ImGuiIO& io = ImGui::GetIO();
    tooltipShownThisFrame().clear();
    handleDrops(s);
    s.pollPhysicsBakes();
    ImGui_ImplOpenGL3_NewFrame();
    ImGui_ImplGlfw_NewFrame();
    const std::vector<int> tapped = holdTappedKeys(s);
    ImGui::NewFrame();

    drawMenus(s);
    const ImVec2 display = io.DisplaySize;
    const float menu = ImGui::GetFrameHeight();
    const float status = ImGui::GetFrameHeight() + 4;
    // Shares of the column, not pixels: a window that shrinks and grows gets its panels back.
    const WindowLayout layout = windowLayout(s.settings.layout, display.x, display.y, menu, status);
    auto rect = [](const PanelRect& r) { return Rect{r.x, r.y, r.w, r.h}; };
    s.viewport = rect(layout.view);
    // No border on the column's panels (their title bars and the splitters part them): a
    // border's anti-aliased edge reaches a pixel past the panel, into the 3D view, which the
    // kept panels (PanelCache) cannot hold.
    ImGui::PushStyleVar(ImGuiStyleVar_WindowBorderSize, 0.0f);
    drawBrushPanel(s, rect(layout.panels[0]));
    drawLayersPanel(s, rect(layout.panels[1]));
    drawInspectorPanel(s, rect(layout.panels[2]));
    drawUvPanel(s, rect(layout.panels[3]));
    ImGui::PopStyleVar();
    drawSplitters(s, layout);
    drawPreviewPanel(s);
    drawPlotPanels(s);
    drawGraphPanel(s);
    drawHydrostaticsPanel(s);
    drawHistoryPanel(s);
    ImGui::SetNextWindowPos(ImVec2(0, display.y - status));
    ImGui::SetNextWindowSize(ImVec2(display.x, status));
    ImGui::Begin(
        "##status", nullptr,
        ImGuiWindowFlags_NoDecoration | ImGuiWindowFlags_NoMove | ImGuiWindowFlags_NoSavedSettings);
    ImGui::Text("%s   |   %s", s.document->title().c_str(), s.status.c_str());
    ImGui::End();
    handleShortcuts(s);
    if (graphEditsInView(s) || !previewInput(s)) viewportInput(s);
    drawViewportOverlay(s);
    phases.mark(FramePhases::Ui);
    updatePreview(s, io.DeltaTime);
    phases.mark(FramePhases::Preview);
    drawPreviewOverlay(s);
    drawDialogs(s, window);
    if (s.requestQuit && !s.document->dirty()) glfwSetWindowShouldClose(window, GLFW_TRUE);
    if (s.requestQuit && s.document->dirty() && !ImGui::IsPopupOpen("Unsaved changes")) {
        s.confirmDiscardOpen = true;
    }
    updateStroke(s);
    uploadOverlays(s);
    if (s.animateWater) s.waterTime += io.DeltaTime;

    ImGui::Render();
    releaseTappedKeys(s, tapped);
    phases.mark(FramePhases::Ui);
    return layout;
}

/// Draws the 3D view and then the column's panels into the framebuffer, whose size it returns.
std::pair<int, int> renderFrame(EditorState& s, GLFWwindow* window, const WindowLayout& layout,
                                PanelCache& panelCache, FramePhases& phases) {
    ImGuiIO& io = ImGui::GetIO();
    int fbWidth = 0, fbHeight = 0;
    glfwGetFramebufferSize(window, &fbWidth, &fbHeight);
    const float scale = io.DisplaySize.x > 0 ? fbWidth / io.DisplaySize.x : 1.0f;
    glViewport(0, 0, fbWidth, fbHeight);
    // The whole window in the 3D view's background (the panels cover the rest): the renderer
    // then need not clear its rectangle again, and clears depth only in a frame in which it
    // draws the scene (a copied scene needs none).
    RenderScene scene = sceneOf(s);
    const int vw = static_cast<int>(s.viewport.w * scale),
              vh = static_cast<int>(s.viewport.h * scale);
    applyPreviewToScene(s, scene);
    addPhysicsSolidsToScene(s, scene);
    const Eigen::Vector3f clear =
        s.renderer->clearColour(scene, s.camera, std::max(vw, 1), std::max(vh, 1));
    glClearColor(clear.x(), clear.y(), clear.z(), 1.0f);
    glClear(GL_COLOR_BUFFER_BIT);
    if (vw > 0 && vh > 0) {
        s.renderer->draw(scene, s.camera, vw, vh, static_cast<int>(s.viewport.x * scale),
                         fbHeight - static_cast<int>((s.viewport.y + s.viewport.h) * scale),
                         /*cleared=*/true);
    }
    phases.mark(FramePhases::Scene);
    glViewport(0, 0, fbWidth, fbHeight);
    // The column's panels from their kept image while they stay the same. The 3D view is drawn
    // over the whole pixels of its width (vw above), so no pixel the column touches is the
    // view's.
    const PanelRect& c = layout.column;
    const ImTextureID fontAtlas = io.Fonts->TexID;
    panelCache.render(*ImGui::GetDrawData(), ImVec4(c.x, c.y, c.x + c.w, c.y + c.h),
                      ImVec4(clear.x(), clear.y(), clear.z(), 1.0f),
                      [&](ImTextureID texture) -> std::optional<std::uint64_t> {
                          if (texture == fontAtlas) return 0;  // made once
                          return s.renderer->textureVersion(
                              static_cast<unsigned>(reinterpret_cast<std::uintptr_t>(texture)));
                      });
    phases.mark(FramePhases::Panels);
    return {fbWidth, fbHeight};
}

/// After a frame: the window's title, and the autosave when it is due.
void afterFrame(EditorState& s, GLFWwindow* window, std::string& title) {
    const std::string wanted = windowTitle(s);
    if (wanted != title) {
        title = wanted;
        glfwSetWindowTitle(window, title.c_str());
    }
    if (s.document->dirty() && glfwGetTime() - s.lastAutosave > s.settings.autosaveSeconds) {
        Status saved = s.document->autosave();
        s.status = saved ? "Autosaved to " + s.document->autosavePath().string()
                         : "Autosave failed: " + saved.error().message;
        s.lastAutosave = glfwGetTime();
    }
}

/// Idle, the editor sleeps until an event (or the autosave's next look): nothing moves, so
/// nothing needs drawing. A few frames follow each event, for ImGui to settle (hover, popups
/// opening the frame after a click). False: woken with nothing to draw.
bool waitForFrame(EditorState& s, const EditorLaunch& launch, const FrameHarness& harness,
                  int awakeFrames, std::uint64_t eventsSeen) {
    const bool idle =
        launch.frames == 0 && awakeFrames == 0 && !animating(s) && !harness.finalFrame();
    if (!idle) {
        glfwPollEvents();
        return true;
    }
    // A new texture size baking: its progress bar moves four times a second.
    glfwWaitEventsTimeout(
        harness.idleWait(s.physicsBakes->resizing() ? kBakeProgressSeconds : kIdleWakeSeconds));
    // Woken by the timeout alone: nothing to draw unless the autosave is due, a bake has
    // finished or one shows its progress.
    const bool autosaveDue =
        s.document->dirty() && glfwGetTime() - s.lastAutosave > s.settings.autosaveSeconds;
    const bool bakeNews = s.physicsBakes->finishedWaiting() || s.physicsBakes->resizing();
    return s.inputEvents != eventsSeen || autosaveDue || bakeNews || animating(s);
}

/// A clean close of an interactive session: the autosave retired (unsaved changes were saved or
/// discarded), the window's size and the brush kept for the next.
void saveSessionSettings(EditorState& s, GLFWwindow* window) {
    if (!s.document->dirty()) s.document->discardAutosave();
    int w = 0, h = 0;
    glfwGetWindowSize(window, &w, &h);
    s.settings.windowWidth = w;
    s.settings.windowHeight = h;
    s.settings.brush = s.brush;
    (void)s.settings.save();
}

/// Releases the GL objects while the context is current, then ImGui, the window and GLFW.
void closeEditorWindow(EditorState& s, GLFWwindow* window,
                       std::unique_ptr<PanelCache>& panelCache) {
    glfwSetWindowUserPointer(window, nullptr);
    s.preview.reset();
    releaseGraphPanel(s);
    s.renderer.reset();
    panelCache.reset();
    ImGui_ImplOpenGL3_Shutdown();
    ImGui_ImplGlfw_Shutdown();
    ImGui::DestroyContext();
    glfwDestroyWindow(window);
    glfwTerminate();
}

}  // namespace

int runEditorWindow(const EditorLaunch& launch) {
    EditorState s;
    s.settings = Settings::load();
    s.brush = s.settings.brush;  // the brush as it was last used
    if (!s.brush.alphaPath.empty()) {
        const std::string alpha = s.brush.alphaPath;
        s.brush.alphaPath.clear();
        if (Status loaded = loadBrushAlpha(s.brush, alpha); !loaded)
            s.status = loaded.error().message;
    }
    GLFWwindow* window = openEditorWindow(launch, s);
    if (!window) return 1;
    // Interactive frames are paced to the displays (displayFramePeriod). Where the swap does not
    // wait for the display (a virtual or remote display, llvmpipe under Xvfb, vsync turned off
    // in the driver) an animating view redrew as fast as the processor allowed: the ball's live
    // preview under Xvfb drew 217 frames a second on 1.4 cores, taken from the bakes and the
    // physics for frames no display shows. With vsync the swap has already waited and the
    // pacing sleeps nothing. Scripted runs (--frames) are not paced.
    const std::chrono::steady_clock::duration framePeriod = displayFramePeriod();
    auto panelCache = std::make_unique<PanelCache>();
    FrameHarness harness(launch);
    if (!startSession(launch, s) || !harness.readSnapshots()) return 1;
    if (launch.preview && !startPreview(s, true)) {
        std::cerr << "error: " << s.status << "\n";
        return 1;
    }

    std::string title;
    int frame = 0;
    std::uint64_t eventsSeen = 0;
    int awakeFrames = 0;
    harness.startClock();
    while (!glfwWindowShouldClose(window)) {
        if (harness.timeIsUp()) break;
        if (!waitForFrame(s, launch, harness, awakeFrames, eventsSeen)) continue;
        harness.frameDrawn();
        if (s.inputEvents != eventsSeen) {
            eventsSeen = s.inputEvents;
            awakeFrames = kFramesAfterEvent;
        } else if (awakeFrames > 0) {
            --awakeFrames;
        }
        const auto frameStart = std::chrono::steady_clock::now();
        harness.phases.start(frameStart);
        const WindowLayout layout = buildFrameUi(s, window, harness.phases);
        const auto [fbWidth, fbHeight] =
            renderFrame(s, window, layout, *panelCache, harness.phases);
        ++frame;
        harness.capture(s, frame, fbWidth, fbHeight, glfwWindowShouldClose(window));
        glfwSwapBuffers(window);
        harness.phases.mark(FramePhases::Present);
        harness.writeState(s, frame);
        afterFrame(s, window, title);
        const double ms =
            std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - frameStart)
                .count();
        s.preview->uiFrameMs = ms;
        if (harness.recordFrame(s, ms, frame)) break;
        if (harness.lastFrame(frame) || harness.finalFrame()) break;
        // After the frame's own time is taken: the pacing is no frame's cost.
        if (launch.frames == 0) std::this_thread::sleep_until(frameStart + framePeriod);
    }

    if (launch.runSeconds > 0) {
        harness.reportRunSeconds(s, ImGui::GetIO(), title, frame);
    } else if (launch.frames > 0) {
        harness.reportFrames(s, ImGui::GetIO(), title, frame, *panelCache);
    } else {
        saveSessionSettings(s, window);
    }
    closeEditorWindow(s, window, panelCache);
    return harness.screenshotOk() ? 0 : 1;
}

}  // namespace plimsoll::editor
