// The editor window (GLFW + OpenGL 4.5 core + Dear ImGui). Built only with
// PLIMSOLL_BUILD_EDITOR_GUI; otherwise a stub says so.
#pragma once

#include <string>
#include <vector>

namespace plimsoll::editor {

struct EditorLaunch {
    std::string project;  ///< project to open (empty: a new one)
    /// Run this many frames, then quit and print the frame times and the layout as JSON on
    /// stdout (0: run until the user quits). For tests and measurements.
    int frames = 0;
    /// With frames or runSeconds: the window's last frame as PNG (with runSeconds, the frame
    /// drawn when the time is up or the window closes).
    std::string screenshot;
    std::string view;               ///< front, side, top or persp (default persp)
    std::string overlay;            ///< initial overlay (default permeability)
    bool showPhysicsSolid = false;  ///< View > Show physics solid / caps, on from the start
    /// Start the live preview playing (with frames: one simulated frame per drawn frame).
    bool preview = false;
    /// With frames and preview: "FRAME:PATH" screenshots taken at those frames; the report
    /// then lists the preview's bodies and force arrows at each.
    std::vector<std::string> snapshots;
    /// Run the interactive loop (idle waits included) for this long, then quit and print the
    /// frames drawn, the CPU time used after the first second and the view as JSON (0: off).
    /// For measuring the idle editor and for tests that send it input.
    double runSeconds = 0;
    /// With frames and preview: ask for this physics texture size at the second frame, as the
    /// preview panel does; the run ends once it is in (or after `frames`) and the report says
    /// how many frames were drawn while it baked and the longest of them (0: off).
    int textureSize = 0;
    /// With frames: set body 0's texture size at the second frame through the inspector's
    /// field (the document's bake and, with preview, the session's); reported like textureSize.
    int inspectorTextureSize = 0;
    /// With frames: also time each phase of a frame (UI, preview physics, 3D scene, panels,
    /// present; glFinish after each) and report their medians as "frame_stats".
    bool frameStats = false;
    /// After every drawn frame, this file (replaced whole, never half-written) holds the
    /// window's state as one line of JSON: frame, window and view size, the mouse, the ImGui
    /// window whose item is held, the tooltip shown. Window tests wait on it ("until the drag
    /// has begun") instead of sleeping a fixed time ("" : off).
    std::string stateFile;
    int width = 0;  ///< window size (0: the saved one)
    int height = 0;
};

/// Opens the window. Returns the process exit code.
int runEditorWindow(const EditorLaunch& launch);

}  // namespace plimsoll::editor
