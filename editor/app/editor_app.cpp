// The editor's window and frame loop: GLFW + OpenGL 4.5 core (libepoxy) + Dear ImGui, as in
// ImGui's example_glfw_opengl3. Index:
//   [SECTION] window callbacks (drop, close)
//   [SECTION] menus and shortcuts
//   [SECTION] dialogs (file browser, unsaved changes, recovery, help)
//   [SECTION] frame loop (layout, panels, stroke preview, 3D view, autosave, screenshot)
#include "app/editor_app.h"

#include "app/editor_state.h"
#include "app/export_dialog.h"
#include "app/panels.h"
#include "app/preview_panel.h"
#include "document/command.h"

#include "plimsoll/bake_io.h"
#include "plimsoll/file_util.h"

#include <epoxy/gl.h>
#include <GLFW/glfw3.h>
#include <imgui.h>
#include <imgui_impl_glfw.h>
#include <imgui_impl_opengl3.h>
#include <nlohmann/json.hpp>
#include <stb_image_write.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <iostream>

namespace plimsoll::editor {

namespace fs = std::filesystem;

namespace {

// [SECTION] window callbacks -------------------------------------------------------------------

std::vector<std::string> droppedPaths;
EditorState* callbackState = nullptr;

void onDrop(GLFWwindow*, int count, const char** paths) {
    for (int i = 0; i < count; ++i) droppedPaths.emplace_back(paths[i]);
}

void onClose(GLFWwindow* window) {
    if (callbackState && callbackState->document->dirty()) {
        glfwSetWindowShouldClose(window, GLFW_FALSE);
        callbackState->requestQuit = true;
        callbackState->confirmDiscardOpen = true;
    }
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
    for (const std::string& path : droppedPaths) {
        if (isProjectFile(path)) {
            requestOpen(s, path, false);
        } else {
            s.execute(makeImportMeshCommand(*s.document, path, std::nullopt));
            s.frameAll();
        }
    }
    droppedPaths.clear();
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

void drawMenus(EditorState& s) {
    if (!ImGui::BeginMainMenuBar()) return;
    const fs::path folder = s.document->project().folder;
    if (ImGui::BeginMenu("File")) {
        if (ImGui::MenuItem("New", "Ctrl+N")) requestOpen(s, "", true);
        if (ImGui::MenuItem("Open...", "Ctrl+O")) s.browser.open(FileBrowser::Purpose::OpenProject, folder);
        if (ImGui::BeginMenu("Open Recent", !s.settings.recentFiles.empty())) {
            for (const std::string& recent : s.settings.recentFiles) {
                if (ImGui::MenuItem(recent.c_str())) {
                    requestOpen(s, recent, false);
                    break;
                }
            }
            ImGui::EndMenu();
        }
        if (ImGui::MenuItem("Import Mesh...")) s.browser.open(FileBrowser::Purpose::ImportMesh, folder);
        ImGui::Separator();
        if (ImGui::MenuItem("Save", "Ctrl+S")) s.save();
        if (ImGui::MenuItem("Save As...", "Ctrl+Shift+S")) {
            s.browser.open(FileBrowser::Purpose::SaveProjectAs, folder);
        }
        if (ImGui::MenuItem("Export bundle...")) s.browser.open(FileBrowser::Purpose::Export, folder);
        ImGui::Separator();
        if (ImGui::MenuItem("Quit", "Ctrl+Q")) s.requestQuit = true;
        ImGui::EndMenu();
    }
    if (ImGui::BeginMenu("Edit")) {
        const std::string undo = "Undo " + s.document->undoName();
        const std::string redo = "Redo " + s.document->redoName();
        if (ImGui::MenuItem(undo.c_str(), "Ctrl+Z", false, s.document->canUndo())) s.undo();
        if (ImGui::MenuItem(redo.c_str(), "Ctrl+Shift+Z", false, s.document->canRedo())) s.redo();
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
        ImGui::EndMenu();
    }
    if (ImGui::BeginMenu("Simulate")) {
        const bool running = s.preview && s.preview->session;
        if (ImGui::MenuItem(running ? "Restart live preview" : "Live preview", "P")) startPreview(s, true);
        if (ImGui::MenuItem("Stop live preview", nullptr, false, running)) stopPreview(s);
        ImGui::EndMenu();
    }
    if (ImGui::BeginMenu("Help")) {
        if (ImGui::MenuItem("Keyboard shortcuts", "F1")) s.showShortcuts = true;
        if (ImGui::MenuItem("About Plimsoll")) s.showAbout = true;
        ImGui::EndMenu();
    }
    ImGui::EndMainMenuBar();
}

void handleShortcuts(EditorState& s) {
    const ImGuiIO& io = ImGui::GetIO();
    if (io.WantTextInput) return;
    const bool ctrl = io.KeyCtrl, shift = io.KeyShift;
    auto pressed = [](int key) { return ImGui::IsKeyPressed(key, false); };
    if (ctrl && pressed(GLFW_KEY_Z)) shift ? s.redo() : s.undo();
    if (ctrl && pressed(GLFW_KEY_Y)) s.redo();
    if (ctrl && pressed(GLFW_KEY_S)) {
        if (shift) s.browser.open(FileBrowser::Purpose::SaveProjectAs, s.document->project().folder);
        else s.save();
    }
    if (ctrl && pressed(GLFW_KEY_O)) s.browser.open(FileBrowser::Purpose::OpenProject, s.document->project().folder);
    if (ctrl && pressed(GLFW_KEY_N)) requestOpen(s, "", true);
    if (ctrl && pressed(GLFW_KEY_Q)) s.requestQuit = true;
    if (ctrl) return;
    if (pressed(GLFW_KEY_1) || pressed(GLFW_KEY_KP_1)) s.setView(ViewPreset::Front);
    if (pressed(GLFW_KEY_3) || pressed(GLFW_KEY_KP_3)) s.setView(ViewPreset::Side);
    if (pressed(GLFW_KEY_7) || pressed(GLFW_KEY_KP_7)) s.setView(ViewPreset::Top);
    if (pressed(GLFW_KEY_0) || pressed(GLFW_KEY_KP_0)) s.setView(ViewPreset::Persp);
    if (pressed(GLFW_KEY_5) || pressed(GLFW_KEY_KP_5)) s.camera.orthographic = !s.camera.orthographic;
    if (pressed(GLFW_KEY_HOME)) s.frameAll();
    if (pressed(GLFW_KEY_F)) frameSelected(s);
    if (pressed(GLFW_KEY_V)) s.tool = Tool::Navigate;
    if (pressed(GLFW_KEY_B)) s.tool = Tool::Brush;
    if (pressed(GLFW_KEY_G)) s.tool = Tool::FillIsland;
    if (pressed(GLFW_KEY_I)) s.tool = Tool::Pick;
    if (pressed(GLFW_KEY_E)) {
        s.brush.mode = s.brush.mode == BrushMode::Erase ? BrushMode::Paint : BrushMode::Erase;
    }
    if (pressed(GLFW_KEY_S)) {
        s.brush.mode = s.brush.mode == BrushMode::Smooth ? BrushMode::Paint : BrushMode::Smooth;
    }
    if (pressed(GLFW_KEY_X)) s.brush.mirrorX = !s.brush.mirrorX;
    if (pressed(GLFW_KEY_LEFT_BRACKET)) s.brush.radius /= 1.25;
    if (pressed(GLFW_KEY_RIGHT_BRACKET)) s.brush.radius *= 1.25;
    if (pressed(GLFW_KEY_F1)) s.showShortcuts = true;
    if (pressed(GLFW_KEY_P)) startPreview(s, true);
}

// [SECTION] dialogs ----------------------------------------------------------------------------

void drawDialogs(EditorState& s, GLFWwindow* window) {
    drawBundleExport();
    if (auto chosen = s.browser.draw()) {
        switch (s.browser.purpose()) {
            case FileBrowser::Purpose::OpenProject: requestOpen(s, chosen->string(), false); break;
            case FileBrowser::Purpose::SaveProjectAs: s.saveAs(*chosen); break;
            case FileBrowser::Purpose::ImportMesh:
                s.execute(makeImportMeshCommand(*s.document, *chosen, std::nullopt));
                s.frameAll();
                break;
            case FileBrowser::Purpose::Export:
                startBundleExport(s.document->project(), *chosen, s.document->dirty());
                break;
        }
    }
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
        ImGui::SameLine();
        if (ImGui::Button("Discard")) {
            s.document->discardAutosave();
            proceed();
        }
        ImGui::SameLine();
        if (ImGui::Button("Cancel")) {
            s.requestQuit = false;
            s.pendingOpen.clear();
            s.pendingNew = false;
            ImGui::CloseCurrentPopup();
        }
        ImGui::EndPopup();
    }
    if (s.recoveryOffer) {
        ImGui::OpenPopup("Recover autosave");
    }
    if (ImGui::BeginPopupModal("Recover autosave", nullptr, ImGuiWindowFlags_AlwaysAutoResize)) {
        ImGui::TextUnformatted("Plimsoll did not close cleanly last time.");
        ImGui::Text("An autosave with unsaved changes exists:\n%s", s.recoveryOffer->string().c_str());
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
        ImGui::SameLine();
        if (ImGui::Button("Discard it")) {
            std::error_code ec;
            fs::remove(*s.recoveryOffer, ec);
            s.recoveryOffer.reset();
            ImGui::CloseCurrentPopup();
        }
        ImGui::EndPopup();
    }
    if (s.showShortcuts) {
        ImGui::Begin("Keyboard shortcuts", &s.showShortcuts, ImGuiWindowFlags_AlwaysAutoResize);
        ImGui::TextUnformatted(
            "Middle mouse: orbit   Shift+middle: pan   Ctrl+middle / wheel: zoom\n"
            "Alt+left mouse: orbit   Right mouse: pan\n"
            "1 / 3 / 7: front / side / top   0: perspective   5: orthographic on/off\n"
            "Home: frame all   F: frame selected\n"
            "V: navigate   B: brush   G: fill island   I: pick value\n"
            "E: erase on/off   S: smooth on/off   X: X-mirror   [ ]: brush radius\n"
            "Ctrl+Z: undo   Ctrl+Shift+Z / Ctrl+Y: redo\n"
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

// [SECTION] frame loop -------------------------------------------------------------------------

void updateStroke(EditorState& s) {
    if (!s.stroke.active) return;
    if (!ImGui::IsMouseDown(0)) {
        // Release: the whole stroke becomes one command (one undo step).
        if (!s.stroke.points.empty()) {
            s.execute(makeStrokeCommand(*s.document, s.stroke.body, s.channel, s.brush,
                                        s.stroke.points));
        }
        s.stroke = {};
        s.overlaysDirty = true;
        return;
    }
    if (!s.stroke.previewDirty) return;
    s.stroke.previewDirty = false;
    const PaintedMap* map = s.document->map(s.stroke.body, s.channel);
    if (!map) return;  // the map is made when the stroke ends
    auto surface = s.document->paintSurface(s.stroke.body, s.channel);
    if (!surface) return;
    const PixelChange change = strokeChange(*map, **surface, s.brush, s.stroke.points);
    PaintedMap preview = *map;
    applyValues(preview, change.pixels, change.after);
    s.renderer->setOverlay(static_cast<int>(s.stroke.body), overlayOfMap(preview));
}

void uploadOverlays(EditorState& s) {
    if (!s.overlaysDirty) return;
    s.overlaysDirty = false;
    for (std::size_t b = 0; b < s.document->bodyCount() + 4; ++b) {
        OverlayImage none;
        if (b >= s.document->bodyCount() || s.overlay == Overlay::None || !s.document->assets(b).mesh) {
            s.renderer->setOverlay(static_cast<int>(b), none);
            continue;
        }
        Result<OverlayImage> image = buildOverlay(*s.document, b, s.overlay);
        s.renderer->setOverlay(static_cast<int>(b), image ? *image : none);
        if (!image) s.status = image.error().message;
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
    if (!stbi_write_png_to_func(append, &png, width, height, 4, pixels.data(), int(row))) return false;
    return writeFileAtomically(path, [&](std::ostream& out) {
               out.write(png.data(), static_cast<std::streamsize>(png.size()));
               return static_cast<bool>(out);
           }).ok();
}

}  // namespace

int runEditorWindow(const EditorLaunch& launch) {
    glfwSetErrorCallback([](int code, const char* message) {
        std::cerr << "glfw error " << code << ": " << message << "\n";
    });
    if (!glfwInit()) {
        std::cerr << "error: cannot open the editor window (no display?). The headless "
                     "sub-commands work without one: plimsoll --help\n";
        return 1;
    }
    EditorState s;
    s.settings = Settings::load();
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
        return 1;
    }
    glfwMakeContextCurrent(window);
    glfwSwapInterval(launch.frames > 0 ? 0 : 1);
    callbackState = &s;
    glfwSetDropCallback(window, onDrop);
    glfwSetWindowCloseCallback(window, onClose);

    IMGUI_CHECKVERSION();
    ImGui::CreateContext();
    ImGuiIO& io = ImGui::GetIO();
    io.IniFilename = nullptr;  // the layout is fixed; settings.json holds what persists
    ImGui::StyleColorsDark();
    ImGui_ImplGlfw_InitForOpenGL(window, true);
    ImGui_ImplOpenGL3_Init("#version 450 core");

    Result<std::unique_ptr<Renderer>> renderer = Renderer::create();
    if (!renderer) {
        std::cerr << "error: " << renderer.error().message << "\n";
        return 1;
    }
    s.renderer = std::move(renderer).value();
    if (!s.open(launch.project)) {
        std::cerr << "error: " << s.status << "\n";
        if (!launch.project.empty()) return 1;
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
    s.lastAutosave = glfwGetTime();
    s.preview = std::make_shared<PreviewUi>();
    s.preview->fixedStep = launch.frames > 0;
    std::vector<std::pair<int, std::string>> snapshots;
    for (const std::string& spec : launch.snapshots) {
        const auto colon = spec.find(':');
        const int at = colon == std::string::npos ? 0 : std::atoi(spec.substr(0, colon).c_str());
        if (at <= 0) {
            std::cerr << "error: --snapshot " << spec << ": expected FRAME:PATH, FRAME > 0\n";
            return 1;
        }
        snapshots.emplace_back(at, spec.substr(colon + 1));
    }
    if (launch.preview && !startPreview(s, true)) {
        std::cerr << "error: " << s.status << "\n";
        return 1;
    }
    nlohmann::json snapshotReports = nlohmann::json::array();

    std::vector<double> frameMs;
    std::string title;
    int frame = 0;
    bool screenshotOk = true;
    while (!glfwWindowShouldClose(window)) {
        const auto frameStart = std::chrono::steady_clock::now();
        glfwPollEvents();
        handleDrops(s);
        ImGui_ImplOpenGL3_NewFrame();
        ImGui_ImplGlfw_NewFrame();
        ImGui::NewFrame();

        // Layout: menu bar, 3D view on the left, tools / inspector / UV view on the right,
        // status line at the bottom.
        drawMenus(s);
        const ImVec2 display = io.DisplaySize;
        const float menu = ImGui::GetFrameHeight();
        const float status = ImGui::GetFrameHeight() + 4;
        const float column = std::min(400.0f, display.x * 0.4f);
        const float below = display.y - menu - status;
        const float uvSide = std::min(column, below * 0.36f);
        const float tools = std::min(250.0f, below * 0.3f);
        s.viewport = Rect{0, menu, display.x - column, below};
        drawBrushPanel(s, Rect{display.x - column, menu, column, tools});
        drawInspectorPanel(s, Rect{display.x - column, menu + tools, column,
                                   below - tools - uvSide});
        drawUvPanel(s, Rect{display.x - column, display.y - status - uvSide, column, uvSide});
        drawPreviewPanel(s);
        drawPlotPanels(s);
        drawGraphPanel(s);
        ImGui::SetNextWindowPos(ImVec2(0, display.y - status));
        ImGui::SetNextWindowSize(ImVec2(display.x, status));
        ImGui::Begin("##status", nullptr,
                     ImGuiWindowFlags_NoDecoration | ImGuiWindowFlags_NoMove |
                         ImGuiWindowFlags_NoSavedSettings);
        ImGui::Text("%s   |   %s", s.document->title().c_str(), s.status.c_str());
        ImGui::End();
        handleShortcuts(s);
        if (graphEditsInView(s) || !previewInput(s)) viewportInput(s);
        drawViewportOverlay(s);
        updatePreview(s, io.DeltaTime);
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
        int fbWidth = 0, fbHeight = 0;
        glfwGetFramebufferSize(window, &fbWidth, &fbHeight);
        const float scale = display.x > 0 ? fbWidth / display.x : 1.0f;
        glViewport(0, 0, fbWidth, fbHeight);
        glClearColor(0.1f, 0.1f, 0.1f, 1.0f);
        glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
        const int vw = static_cast<int>(s.viewport.w * scale), vh = static_cast<int>(s.viewport.h * scale);
        if (vw > 0 && vh > 0) {
            RenderScene scene = sceneOf(s);
            applyPreviewToScene(s, scene);
            s.renderer->draw(scene, s.camera, vw, vh, static_cast<int>(s.viewport.x * scale),
                             fbHeight - static_cast<int>((s.viewport.y + s.viewport.h) * scale));
        }
        glViewport(0, 0, fbWidth, fbHeight);
        ImGui_ImplOpenGL3_RenderDrawData(ImGui::GetDrawData());
        ++frame;
        const bool last = launch.frames > 0 && frame >= launch.frames;
        for (const auto& [at, path] : snapshots) {
            if (at != frame) continue;
            glFinish();
            screenshotOk = writeScreenshot(path, fbWidth, fbHeight) && screenshotOk;
            nlohmann::json shot = previewReport(s);
            shot["frame"] = frame;
            shot["path"] = path;
            snapshotReports.push_back(shot);
        }
        if (last && !launch.screenshot.empty()) {
            glFinish();
            screenshotOk = writeScreenshot(launch.screenshot, fbWidth, fbHeight);
        }
        glfwSwapBuffers(window);

        const std::string wanted = s.document->title() + " - Plimsoll";
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
        frameMs.push_back(std::chrono::duration<double, std::milli>(
                              std::chrono::steady_clock::now() - frameStart)
                              .count());
        s.preview->uiFrameMs = frameMs.back();
        if (last) break;
    }

    if (launch.frames > 0) {
        // Frame times after the first few (shader compiles, first uploads).
        std::vector<double> steady(frameMs.begin() + std::min<std::size_t>(frameMs.size() / 4, 10),
                                   frameMs.end());
        std::sort(steady.begin(), steady.end());
        double sum = 0;
        for (double ms : steady) sum += ms;
        nlohmann::json report;
        report["frames"] = frame;
        report["frame_ms_mean"] = steady.empty() ? 0.0 : sum / steady.size();
        report["frame_ms_median"] = steady.empty() ? 0.0 : steady[steady.size() / 2];
        report["first_frame_ms"] = frameMs.empty() ? 0.0 : frameMs.front();
        report["window"] = {io.DisplaySize.x, io.DisplaySize.y};
        report["viewport"] = {s.viewport.x, s.viewport.y, s.viewport.w, s.viewport.h};
        report["gl_renderer"] = reinterpret_cast<const char*>(glGetString(GL_RENDERER));
        report["title"] = title;
        if (!launch.screenshot.empty()) report["screenshot"] = launch.screenshot;
        if (!snapshotReports.empty()) report["snapshots"] = snapshotReports;
        if (s.preview->session) report["preview"] = previewReport(s);
        std::cout << report.dump(2) << std::endl;
    } else {
        // A clean close retires the autosave (unsaved changes were saved or discarded).
        if (!s.document->dirty()) s.document->discardAutosave();
        int w = 0, h = 0;
        glfwGetWindowSize(window, &w, &h);
        s.settings.windowWidth = w;
        s.settings.windowHeight = h;
        (void)s.settings.save();
    }
    callbackState = nullptr;
    s.preview.reset();
    releaseGraphPanel();
    s.renderer.reset();
    ImGui_ImplOpenGL3_Shutdown();
    ImGui_ImplGlfw_Shutdown();
    ImGui::DestroyContext();
    glfwDestroyWindow(window);
    glfwTerminate();
    return screenshotOk ? 0 : 1;
}

}  // namespace plimsoll::editor
