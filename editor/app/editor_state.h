// What the editor's panels share: the document, the view, the tool and brush, and requests
// between panels. The frame loop (editor_app.cpp) owns it; each panel is a function of it.
#pragma once

#include "app/file_browser.h"
#include "document/document.h"
#include "document/overlay.h"
#include "document/paint.h"
#include "document/settings.h"
#include "render/camera.h"
#include "render/renderer.h"

#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace plimsoll::editor {

struct PreviewUi;  // app/preview_panel.h

enum class Tool { Navigate, Brush, FillIsland, FillAll, Pick };

struct ActiveStroke {
    bool active = false;
    std::size_t body = 0;
    std::vector<Eigen::Vector3d> points;  ///< object space
    bool previewDirty = false;
};

/// A rectangle of the window, in window pixels (top-left origin).
struct Rect {
    float x = 0, y = 0, w = 0, h = 0;
    bool contains(float px, float py) const { return px >= x && py >= y && px < x + w && py < y + h; }
};

struct EditorState {
    std::unique_ptr<Document> document;
    Settings settings;
    std::unique_ptr<Renderer> renderer;

    Camera camera;
    Overlay overlay = Overlay::Permeability;
    MapChannel channel = MapChannel::Permeability;
    Brush brush;
    Tool tool = Tool::Navigate;
    int selectedBody = 0;
    bool showWater = true;
    bool showGrid = true;
    double waterTime = 0.0;
    bool animateWater = false;

    ActiveStroke stroke;
    bool overlaysDirty = true;          ///< re-upload overlay textures
    std::uint64_t documentRevision = 0; ///< bumps on every edit (panels cache against it)

    Rect viewport;                      ///< where the 3D view is drawn this frame
    std::string status;                 ///< status bar line
    FileBrowser browser;
    double lastAutosave = 0.0;          ///< glfwGetTime of the last autosave

    // Requests handled by the frame loop (dialogs that need the window).
    bool requestQuit = false;
    bool confirmDiscardOpen = false;    ///< "unsaved changes" dialog visible
    std::string pendingOpen;            ///< project to open once unsaved changes are settled
    bool pendingNew = false;
    bool showShortcuts = false;
    bool showAbout = false;
    std::optional<std::filesystem::path> recoveryOffer;  ///< autosave found at start

    /// The live preview (app/preview_panel.h); made by the frame loop.
    std::shared_ptr<PreviewUi> preview;

    /// Executes an edit, reports failures in the status line, marks views for refresh.
    bool execute(Result<std::unique_ptr<Command>> command);
    void undo();
    void redo();
    /// Opens a project (or a new document with an empty path), resetting the view.
    bool open(const std::string& path);
    void save();
    void saveAs(const std::filesystem::path& path);
    void frameAll();
    void setView(ViewPreset view);
    /// The body and object-space point under window position (x, y) of the viewport.
    std::optional<std::pair<std::size_t, Eigen::Vector3d>> pick(float x, float y) const;
};

}  // namespace plimsoll::editor
