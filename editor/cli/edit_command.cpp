// `plimsoll edit [PROJECT] [--script commands.json]`: with a script, runs its commands on the
// project without a window and saves; without one, opens the editor window on the project.
#include "cli/commands.h"
#include "cli/common.h"
#include "plimsoll/io/json_depth.h"

#include "app/editor_app.h"
#include "document/document.h"
#include "document/script.h"
#include "plimsoll/core/limits.h"
#include "plimsoll/io/file_util.h"

#include <nlohmann/json.hpp>

#include <cstdio>
#include <fstream>
#include <iostream>
#include <memory>

namespace plimsoll::cli {

namespace {

struct EditOptions {
    std::string project;
    std::string script;
    std::string saveAs;
    bool force = false;
    bool noSave = false;
    editor::EditorLaunch window;
    std::string windowSize;
};

int runEdit(const EditOptions& o) {
    using namespace plimsoll::editor;
    if (o.script.empty()) {
        EditorLaunch launch = o.window;
        launch.project = o.project;
        if (!o.windowSize.empty()) {
            char x = 0;
            if (std::sscanf(o.windowSize.c_str(), "%d%c%d", &launch.width, &x, &launch.height) !=
                    3 ||
                x != 'x') {
                std::cerr << "error: --window-size: expected WxH\n";
                return kExitUsage;
            }
        }
        return runEditorWindow(launch);
    }
    std::unique_ptr<Document> document;
    if (o.project.empty()) {
        document = std::make_unique<Document>();
    } else {
        Result<std::unique_ptr<Document>> opened = Document::open(o.project);
        if (!opened) {
            std::cerr << "error: " << opened.error().message << "\n";
            return kExitFailure;
        }
        document = std::move(opened).value();
    }
    // A regular file of bounded size: a FIFO given as the script must not block.
    Result<std::string> text = readWholeFile(o.script, kMaxJsonFileBytes, "kMaxJsonFileBytes");
    if (!text) {
        std::cerr << "error: " << text.error().message << "\n";
        return kExitFailure;
    }
    // Deep values would overflow the stack of the commands that print or re-parse them.
    if (Status depth = checkJsonDepth(*text, o.script); !depth.ok()) {
        std::cerr << "error: " << depth.error().message << "\n";
        return kExitFailure;
    }
    nlohmann::json script;
    try {
        script = nlohmann::json::parse(*text);
    } catch (const nlohmann::json::exception& e) {
        std::cerr << "error: " << o.script << ": " << boundedExcerpt(e.what(), 200) << "\n";
        return kExitFailure;
    }
    Result<nlohmann::json> results = runEditScript(*document, script);
    if (!results) {
        std::cerr << "error: " << o.script << ": " << results.error().message << "\n";
        return kExitFailure;
    }
    nlohmann::json report;
    report["results"] = *results;
    if (!o.noSave) {
        Status saved = o.saveAs.empty() ? document->save() : document->saveAs(o.saveAs, o.force);
        if (!saved) {
            std::cerr << "error: " << saved.error().message << "\n";
            return kExitFailure;
        }
        report["saved"] = document->path().string();
    }
    std::cout << reportJson(report) << "\n";
    return kExitOk;
}

}  // namespace

void addEditCommand(CLI::App& root, CommandRunner& selected) {
    auto o = std::make_shared<EditOptions>();
    CLI::App* cmd = root.add_subcommand(
        "edit", "Open a project in the editor window, or with --script edit it headless");
    cmd->add_option("project", o->project, "Project file (*.plim.json)");
    cmd->add_option("--script", o->script,
                    "JSON list of edit commands to run without a window (docs/edit-scripts.md); "
                    "the project is saved afterwards")
        ->check(CLI::ExistingFile);
    cmd->add_option("--save-as", o->saveAs, "With --script: save under this name instead");
    cmd->add_flag("--force", o->force,
                  "With --save-as: replace an existing file (never one the "
                  "project reads, such as its mesh)");
    cmd->add_flag("--no-save", o->noSave, "With --script: do not save");
    cmd->add_option("--frames", o->window.frames,
                    "Window: run this many frames, print frame times and layout as JSON, quit");
    cmd->add_option("--screenshot", o->window.screenshot,
                    "Window: with --frames or --run-seconds, write the last frame to this PNG");
    cmd->add_flag("--preview", o->window.preview,
                  "Window: start the live preview playing (with --frames: one simulated frame "
                  "per drawn frame)");
    cmd->add_option("--snapshot", o->window.snapshots,
                    "Window: with --frames and --preview, FRAME:PATH writes that frame to a PNG "
                    "(repeatable); the JSON report lists the bodies and force arrows there");
    cmd->add_option("--texture-size", o->window.textureSize,
                    "Window: with --frames and --preview, ask for this physics texture size at the "
                    "second frame (baked in the background); the run ends once it is in")
        ->check(CLI::Range(kMinTextureSize, kMaxTextureSize));
    cmd->add_option("--inspector-texture-size", o->window.inspectorTextureSize,
                    "Window: with --frames, set the first body's texture size at the second "
                    "frame as the inspector does (baked in the background, the running preview "
                    "too); the run ends once it is in")
        ->check(CLI::Range(kMinTextureSize, kMaxTextureSize));
    cmd->add_flag(
        "--frame-stats", o->window.frameStats,
        "Window: with --frames, also report the median time of each phase of a frame "
        "(UI, preview physics, 3D scene, panels, present), waiting for the GL after each");
    cmd->add_option("--state-file", o->window.stateFile,
                    "Window: after each frame, replace this file with the window's state as one "
                    "line of JSON (frame, window, view, mouse, held control, tooltip); for tests");
    cmd->add_option("--view", o->window.view, "Window: front, side, top or persp")
        ->check(CLI::IsMember({"front", "side", "top", "persp"}));
    cmd->add_option("--overlay", o->window.overlay,
                    "Window: none, permeability, density, thickness, coverage, position, area")
        ->check(CLI::IsMember(
            {"none", "permeability", "density", "thickness", "coverage", "position", "area"}));
    cmd->add_flag("--show-physics-solid", o->window.showPhysicsSolid,
                  "Window: View > Show physics solid / caps on from the start (the solid a body "
                  "is simulated as and its caps, over the artist's mesh)");
    cmd->add_option("--window-size", o->windowSize, "Window: size WxH");
    cmd->add_option("--run-seconds", o->window.runSeconds,
                    "Window: run interactively this long, then print frames drawn, CPU seconds "
                    "after the first second and the view as JSON, and quit");
    cmd->callback([o, &selected] { selected = [o] { return runEdit(*o); }; });
}

}  // namespace plimsoll::cli
