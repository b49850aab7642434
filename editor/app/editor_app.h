// The editor window (GLFW + OpenGL 4.5 core + Dear ImGui). Built only with
// PLIMSOLL_BUILD_EDITOR_GUI; otherwise a stub says so.
#pragma once

#include <string>
#include <vector>

namespace plimsoll::editor {

struct EditorLaunch {
    std::string project;     ///< project to open (empty: a new one)
    /// Run this many frames, then quit and print the frame times and the layout as JSON on
    /// stdout (0: run until the user quits). For tests and measurements.
    int frames = 0;
    std::string screenshot;  ///< with frames: the window's last frame as PNG
    std::string view;        ///< front, side, top or persp (default persp)
    std::string overlay;     ///< initial overlay (default permeability)
    /// Start the live preview playing (with frames: one simulated frame per drawn frame).
    bool preview = false;
    /// With frames and preview: "FRAME:PATH" screenshots taken at those frames; the report
    /// then lists the preview's bodies and force arrows at each.
    std::vector<std::string> snapshots;
    int width = 0;           ///< window size (0: the saved one)
    int height = 0;
};

/// Opens the window. Returns the process exit code.
int runEditorWindow(const EditorLaunch& launch);

}  // namespace plimsoll::editor
