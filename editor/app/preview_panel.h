// The live preview in the window: the session's controls (preview_panel.cpp), the plots
// (plot_panel.cpp), the force arrows / waterline / wet texels over the 3D view and the
// performance overlay. The frame loop calls these hooks; the simulation itself is the GL-free
// PreviewSession (document/preview.h).
#pragma once

#include "app/editor_state.h"
#include "document/preview.h"
#include "view/force_overlay.h"

#include <nlohmann/json.hpp>

#include <future>
#include <memory>
#include <set>
#include <string>
#include <vector>

namespace plimsoll::editor {

/// A body held with the left mouse during the preview.
struct GrabDrag {
    bool active = false;
    Eigen::Vector3d planePoint = Eigen::Vector3d::Zero();  ///< world, the drag plane's point
};

struct PreviewUi {
    std::unique_ptr<PreviewSession> session;
    bool open = false;   ///< the preview window is shown
    std::string device;  ///< createBuoyancyBackend spec ("": the default device)
    std::string error;   ///< why the session could not start or stopped
    /// Scripted runs (--frames): one simulated frame per drawn frame, whatever the wall clock,
    /// so that a screenshot at frame N shows simulated time N * timeStep.
    bool fixedStep = false;
    /// Per body, which texels the wet-texel image tests; for new textures (a new size swapped
    /// in) found on a worker while the last image stays up (the walk over every covered texel
    /// took 15 ms at 1024^2, in the very frame the size arrived).
    struct WetSamples {
        WetTexelSamples ready;
        std::future<WetTexelSamples> finding;
        std::uint64_t findingKey = 0;
    };
    std::vector<WetSamples> wetSamples;
    bool showForces = true, showWaterline = true, showWetTexels = true;
    bool showPerformance = true, showPlots = true;
    /// The camera's target stays on the selected body's centre of mass (C toggles it).
    bool followBody = false;
    int integrator = 1;         ///< index into the panel's integrator list
    std::string lastCheck;      ///< the volume-error line shown
    double lastCheckTime = -1;  ///< simulated time it was computed at
    double uiFrameMs = 0;       ///< the window's last frame, wall clock
    std::vector<char> plotted;  ///< per history series: shown in the plot windows
    std::string plotStatus;     ///< last CSV export result
    unsigned overlayGeneration = 0;
    GrabDrag grabDrag;
    /// The document's state the session last took its paint from (followDocument).
    std::uint64_t followedState = 0;
    /// The window sits in the view's lower-left corner, growing upward, until the user drags
    /// it elsewhere; wherever it is, it stays inside the view when the window shrinks.
    bool anchored = true;
    /// The plot windows the user has dragged: the others stack down the view's right edge,
    /// each just below the one above as it is now (opened or folded), never over another.
    std::set<std::string> plotsMoved;
};

/// Starts (or restarts) the session from the document's project; playing when `play`.
bool startPreview(EditorState& s, bool play);
void stopPreview(EditorState& s);

/// Steps the session by the frame's wall time (or one frame in fixedStep mode).
void updatePreview(EditorState& s, double wallSeconds);
/// The control window (play, pause, step, reset, time scale, water, integrator, texture size,
/// device, kernel time, volume error).
void drawPreviewPanel(EditorState& s);
/// The plot windows (movable, collapsible: Debian's ImGui 1.86 has no docking), "Export CSV".
void drawPlotPanels(EditorState& s);
/// Grabbing a body with the left mouse while the preview runs. True when it used the mouse
/// this frame (the view's own navigation then leaves it alone).
bool previewInput(EditorState& s);
/// Arrows, waterline, grab spring and the performance overlay over the 3D view.
void drawPreviewOverlay(EditorState& s);
/// The simulated poses, wet-texel overlays and water time in the scene the renderer draws.
void applyPreviewToScene(EditorState& s, RenderScene& scene);
/// Facts for a scripted run's JSON report (bodies' centres of mass and buoyancy, world).
nlohmann::json previewReport(const EditorState& s);

}  // namespace plimsoll::editor
