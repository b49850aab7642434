// What the editor's panels share: the document, the view, the tool and brush, and requests
// between panels. The frame loop (editor_app.cpp) owns it; each panel is a function of it.
#pragma once

#include "app/file_browser.h"
#include "document/document.h"
#include "document/overlay.h"
#include "document/paint.h"
#include "document/physics_bakes.h"
#include "document/physics_solids.h"
#include "document/settings.h"
#include "view/camera.h"
#include "render/renderer.h"

#include <memory>
#include <optional>
#include <set>
#include <string>
#include <vector>

namespace plimsoll::editor {

struct PreviewUi;  // app/preview_panel.h
struct GraphUi;    // app/graph_panel.cpp
std::shared_ptr<GraphUi> makeGraphUi();
class ExportDialog;  // app/export_dialog.h
std::shared_ptr<ExportDialog> makeExportDialog();
struct InspectorCache;  // app/inspector_panel.cpp
std::shared_ptr<InspectorCache> makeInspectorCache();

enum class Tool { Navigate, Brush, FillIsland, FillAll, Pick };

struct ActiveStroke {
    bool active = false;
    /// Whether the stroke has reached a body yet: one that starts off the mesh paints the body
    /// it first crosses.
    bool onBody = false;
    std::size_t body = 0;
    std::vector<Eigen::Vector3d> points;  ///< object space
    bool previewDirty = false;
    LazyMouse lazy;  ///< where the brush trails the cursor (window px)
};

/// A rectangle of the window, in window pixels (top-left origin).
struct Rect {
    float x = 0, y = 0, w = 0, h = 0;
    bool contains(float px, float py) const {
        return px >= x && py >= y && px < x + w && py < y + h;
    }
    Eigen::AlignedBox2f box() const {
        return {Eigen::Vector2f(x, y), Eigen::Vector2f(x + w, y + h)};
    }
};

/// The Layers panel's sliders while held (the value shown; the command comes on release).
struct LayerSliders {
    bool opacityHeld = false, fillHeld = false;
    float opacity = 0, fill = 0;
};

/// A layer name being typed in the Layers panel (double-click or "Rename"): Enter keeps it, Esc
/// puts the old name back.
struct LayerRename {
    int layer = -1;        ///< index from the bottom; -1: no rename open
    std::size_t body = 0;  ///< the map the layer is on (a rename ends when it changes)
    MapChannel channel = MapChannel::Permeability;
    std::string text;    ///< as typed
    bool focus = false;  ///< give the field the keyboard on its next frame
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
    /// View > Show physics solid / caps: the solid each body is simulated as, and its caps,
    /// see-through over the artist's mesh.
    bool showPhysicsSolid = false;
    double waterTime = 0.0;
    bool animateWater = false;

    ActiveStroke stroke;
    /// F / Shift+F with the Brush, as Blender's radial control: while it is up, the mouse's
    /// distance from `centre` (px) sets the brush radius or strength; a left click or Enter
    /// keeps the value, Esc or the right button puts `start` back.
    struct RadialControl {
        bool strength = false;         ///< Shift+F: strength; F: radius
        double start = 0.0;            ///< the value before, for a cancel
        Eigen::Vector2d centre{0, 0};  ///< screen px
    };
    std::optional<RadialControl> radialControl;
    /// Where the last stroke ended (body, object space): Shift-click draws a line from there.
    std::optional<std::pair<std::size_t, Eigen::Vector3d>> lastStrokeEnd;
    std::size_t lastStrokePoints = 0;  ///< surface points of the last stroke (reports)
    /// The layer strokes and fills change on a map with layers (index from the bottom; -1: the
    /// top paint layer), and whether they paint its mask.
    int activeLayer = -1;
    bool paintMask = false;
    LayerSliders layerSliders;
    LayerRename layerRename;
    /// The Layers panel's folders shown closed, as "body/channel/name" (a view setting, not
    /// an edit: no undo step, not saved).
    std::set<std::string> collapsedFolders;
    int newMapSize = 1024;       ///< the Tools panel's "New map" size, px
    bool confirmNewMap = false;  ///< "replace the map?" question to open
    /// Key presses since the last frame, in order, from the key callback: a tap shorter than a
    /// frame is still seen (ImGui 1.86 only keeps whether a key is down at the frame start).
    std::vector<std::pair<int, int>> keyPresses;  ///< (GLFW key, modifier bits)
    /// Keys pressed since the last frame began, and those of them already released again: a
    /// tap shorter than a frame, which ImGui 1.86 (key state, no event queue) would never see
    /// down. The frame loop holds each such key down for one frame (holdTappedKeys).
    std::vector<int> keysPressedSinceFrame;
    std::vector<int> tappedKeys;
    std::uint64_t inputEvents = 0;          ///< counts window events (the idle loop wakes on them)
    std::vector<std::string> droppedPaths;  ///< files dropped on the window, to open or import
    bool overlaysDirty = true;              ///< re-upload overlay textures
    std::uint64_t documentRevision = 0;     ///< bumps on every edit (panels cache against it)

    /// The UV view's zoom (1: the whole 0..1 square fits) and the uv at its centre.
    float uvZoom = 1.0f;
    Eigen::Vector2f uvCentre{0.5f, 0.5f};
    bool uvPanning = false;  ///< a middle drag that started in the UV view is on
    /// The uv under the mouse in the UV view this frame (reports; none when not over it).
    std::optional<Eigen::Vector2f> uvUnderMouse;
    Rect viewport;  ///< where the 3D view is drawn this frame
    /// The Live preview window's rectangle this frame (empty: closed) and the view's legend's
    /// (empty: none), which the labels drawn over the view keep clear of (overlayPlace).
    Eigen::AlignedBox2f previewWindow, legendBox;
    bool navigating = false;  ///< a mouse drag is moving the camera
    std::string status;       ///< status bar line
    FileBrowser browser;
    double lastAutosave = 0.0;  ///< glfwGetTime of the last autosave

    // Requests handled by the frame loop (dialogs that need the window).
    bool requestQuit = false;
    bool confirmDiscardOpen = false;  ///< "unsaved changes" dialog visible
    std::string pendingOpen;          ///< project to open once unsaved changes are settled
    bool pendingNew = false;
    std::optional<std::filesystem::path> pendingExport;  ///< export folder awaiting "save first?"
    /// Save As target that would replace existing files, awaiting "replace them?" (its files).
    std::optional<std::filesystem::path> pendingSaveAs;
    std::vector<std::filesystem::path> pendingSaveAsReplaces;
    bool showShortcuts = false;
    bool showHistory = false;              ///< Edit > Undo history
    bool showHydrostatics = false;         ///< Simulate > Hydrostatics (without a preview too)
    bool hydrostaticsOpenRequest = false;  ///< unfold the window on its next frame
    bool historyScrollPending = false;     ///< the history list scrolls to the current step
    bool showAbout = false;
    std::optional<std::filesystem::path> recoveryOffer;  ///< autosave found at start

    /// The live preview (app/preview_panel.h); made by the frame loop.
    std::shared_ptr<PreviewUi> preview;
    /// The water graph panel's state (app/graph_panel.cpp).
    std::shared_ptr<GraphUi> graphUi = makeGraphUi();
    /// The inspector's per-body facts and fields being typed into (app/inspector_panel.cpp).
    std::shared_ptr<InspectorCache> inspector = makeInspectorCache();
    /// File > Export bundle's worker and window (app/export_dialog.h).
    std::shared_ptr<ExportDialog> exportDialog = makeExportDialog();
    /// The bodies' physics textures baked on workers for the panels (physics_bakes.h).
    std::shared_ptr<PhysicsBakes> physicsBakes = std::make_shared<PhysicsBakes>();
    /// The bodies' physics solids and caps worked out on workers (physics_solids.h).
    std::shared_ptr<PhysicsSolids> physicsSolids = std::make_shared<PhysicsSolids>();

    /// The selected body's physics textures for this frame, never baked on this thread (null
    /// while a first bake runs; during a new size's bake, the previous size's).
    std::shared_ptr<const SurfaceTextures> physicsFor(std::size_t body);
    /// Sets a body's texture size (one undo step) and bakes it in the background: the running
    /// preview is asked for it too, and keeps the old size running until it is ready.
    bool setTextureSize(std::size_t body, int size);
    /// Stops the body's texture bake and sets its size back to the one still shown.
    void cancelTextureBake(std::size_t body);
    /// Each frame: moves finished bakes into the document (views refresh).
    void pollPhysicsBakes();

    /// What strokes and fills on the selected map change (paint.h, layers.h).
    PaintTarget paintTarget() const;
    /// Executes an edit, reports failures in the status line, marks views for refresh.
    bool execute(Result<std::unique_ptr<Command>> command);
    void undo();
    void redo();
    /// Undo or redo to `position` steps done (the history panel's click).
    void jumpToHistory(std::size_t position);
    /// Opens a project (or a new document with an empty path), resetting the view.
    bool open(const std::string& path);
    void save();
    /// File > Save As: the browser in the project's folder, with the document's name.
    void openSaveAs();
    /// Saves under `path` (".plim.json" added). Files the project reads are never replaced;
    /// other existing files only with `replace`: without it, pendingSaveAs is set for the
    /// dialog to ask.
    void saveAs(const std::filesystem::path& path, bool replace = false);
    void frameAll();
    void setView(ViewPreset view);
    /// The body and object-space point under window position (x, y) of the viewport.
    std::optional<std::pair<std::size_t, Eigen::Vector3d>> pick(float x, float y) const;
    /// pick's hit with the hit triangle's outward unit normal, both in world space (the brush
    /// cursor lies in the surface's tangent plane).
    struct SurfacePick {
        std::size_t body = 0;
        Eigen::Vector3d point;   ///< world
        Eigen::Vector3d normal;  ///< world, unit
    };
    std::optional<SurfacePick> pickSurface(float x, float y) const;
    /// The bodies' poses as the view showed them last: the simulated ones while the live
    /// preview runs (set as its scene is drawn), none otherwise.
    std::vector<Pose> previewPoses;
    /// The depth at which a "by depth" smart mask reaches 1, m (the Layers panel's menu).
    float smartMaskDepth = 1.0f;
    float smartMaskRadius = 0.05f;        ///< m: the curvature's ball
    float smartMaskFullCurvature = 5.0f;  ///< 1/m: where a curvature or cavity mask is 1
    /// Body b's pose as the view shows it (the preview's, else its starting pose): what the
    /// picks, the brush and its cursor work with, so that one paints on a floating body.
    Pose shownPose(std::size_t body) const;

private:
    /// The body and the ray's hit (object space, with its triangle) under (x, y).
    std::optional<std::pair<std::size_t, SurfaceHit>> pickHit(float x, float y) const;

public:
};

}  // namespace plimsoll::editor
