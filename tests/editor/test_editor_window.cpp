// The editor window under Xvfb: it starts, opens a sample project, and its screenshot shows the
// UI and the mesh where the camera puts it (pixel positions computed from the camera, not a
// stored image). Skipped where xvfb-run is missing or the build has no window.
#include "cli_runner.h"
#include "test_support.h"
#include "editor/xvfb_support.h"

#include "view/camera.h"

#include "plimsoll/surface/painted_map.h"
#include "plimsoll/io/painted_map_io.h"
#include "plimsoll/project/project.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <stb_image.h>

#include <algorithm>
#include <cstdlib>
#include <fstream>
#include <initializer_list>
#include <optional>
#include <unistd.h>
#include <utility>
#include <vector>

namespace plimsoll::editor {
namespace test_editor_window {
namespace {

namespace fs = std::filesystem;

TEST(EditorWindow, ScreenshotUnderXvfbShowsUiAndMeshWhereTheCameraPutsIt) {
    if (std::system("command -v xvfb-run >/dev/null 2>&1") != 0) {
        GTEST_SKIP() << "xvfb-run is not installed";
    }
    const fs::path dir =
        fs::temp_directory_path() / "plimsoll_tests" / ("window_" + std::to_string(::getpid()));
    fs::remove_all(dir);
    fs::create_directories(dir);
    const fs::path project = dir / "window.plim.json";
    // The water far below, so that the front view sees it edge-on outside the picture.
    std::ofstream(project) << R"({"schema_version": 1, "name": "window",
        "water": {"model": "flat", "level": -5},
        "bodies": [{"name": "ball", "mesh": ")"
                           << test::assetPath("sphere.obj").string()
                           << R"(", "material": {"density": 500}, "position": [0.3, 1.0, 0]}]})";
    const fs::path shot = dir / "window.png";
    const std::string environment = test::xvfbRun(dir);
    const test::CommandOutput run = test::runPlimsoll(
        "edit '" + project.string() + "' --frames 20 --screenshot '" + shot.string() +
            "' --window-size 1024x640 --view front --overlay none",
        environment);
    if (run.exitCode != 0 && run.err.find("built without the editor window") != std::string::npos) {
        GTEST_SKIP() << run.err;
    }
    ASSERT_EQ(run.exitCode, 0) << run.err << run.out;
    const nlohmann::json report = nlohmann::json::parse(run.out);
    EXPECT_EQ(report["title"], "window.plim.json - Plimsoll");  // not dirty: no '*'
    std::cout << "editor frame time under Xvfb: " << report["frame_ms_median"] << " ms (median), "
              << report["gl_renderer"] << "\n";

    int width = 0, height = 0, channels = 0;
    unsigned char* data = stbi_load(shot.c_str(), &width, &height, &channels, 3);
    ASSERT_TRUE(data) << stbi_failure_reason();
    std::vector<unsigned char> rgb(data, data + 3 * width * height);
    stbi_image_free(data);
    ASSERT_EQ(width, 1024);
    ASSERT_EQ(height, 640);
    auto at = [&](double x, double y) {
        const std::size_t i =
            3 * (static_cast<std::size_t>(y) * width + static_cast<std::size_t>(x));
        return Eigen::Vector3i(rgb[i], rgb[i + 1], rgb[i + 2]);
    };

    // Where the 3D view is, and its camera: the front preset framing the body.
    const auto& vp = report["viewport"];
    const double vx = vp[0], vy = vp[1], vw = vp[2], vh = vp[3];
    ASSERT_GT(vw, 100);
    ASSERT_GT(vh, 100);
    Bounds3 bounds;
    bounds.min = Eigen::Vector3d(0.3 - 0.5, 1.0 - 0.5, -0.5);
    bounds.max = Eigen::Vector3d(0.3 + 0.5, 1.0 + 0.5, 0.5);
    const Camera camera = Camera::preset(ViewPreset::Front, bounds);
    auto pixelOf = [&](const Eigen::Vector3d& world) {
        const auto p = camera.toPixel(world, static_cast<int>(vw), static_cast<int>(vh));
        EXPECT_TRUE(p);
        return Eigen::Vector2d(vx + p->x(), vy + p->y());
    };
    const Eigen::Vector3d centre(0.3, 1.0, 0.0);
    // On the ball (inside its outline, 0.4 m from the centre at most): the selected body's
    // colour (0.80, 0.78, 0.72) times its lighting.
    for (const Eigen::Vector3d& offset :
         {Eigen::Vector3d(0, 0, 0.5), Eigen::Vector3d(0.35, 0.2, 0.3),
          Eigen::Vector3d(-0.3, -0.25, 0.3), Eigen::Vector3d(0.1, 0.4, 0.25),
          Eigen::Vector3d(-0.4, 0.0, 0.3)}) {
        const Eigen::Vector2d p = pixelOf(centre + offset);
        const Eigen::Vector3i c = at(p.x(), p.y());
        EXPECT_GT(c.x(), 85) << "mesh expected at " << p.transpose() << ", colour "
                             << c.transpose();
        EXPECT_NEAR(c.y(), c.x() * 0.78 / 0.80, 4);
        EXPECT_NEAR(c.z(), c.x() * 0.72 / 0.80, 4);
    }
    // Just outside its outline (0.6 m from the centre, off the grid line and the y axis): the
    // view's background.
    for (const Eigen::Vector3d& offset :
         {Eigen::Vector3d(0.62, 0.0, 0), Eigen::Vector3d(-0.62, 0.1, 0),
          Eigen::Vector3d(0.0, 0.62, 0), Eigen::Vector3d(0.45, -0.45, 0)}) {
        const Eigen::Vector2d p = pixelOf(centre + offset);
        const Eigen::Vector3i c = at(p.x(), p.y());
        EXPECT_NEAR(c.x(), 51, 3) << "background expected at " << p.transpose();
        EXPECT_NEAR(c.y(), 54, 3);
        EXPECT_NEAR(c.z(), 59, 3);
    }
    // The UI: the menu bar's text above the view, and panels to its right.
    int bright = 0;
    for (int y = 0; y < static_cast<int>(vy); ++y) {
        for (int x = 0; x < 200; ++x) bright += at(x, y).x() > 180;
    }
    EXPECT_GT(bright, 20) << "no menu text";
    int panelPixels = 0, samples = 0;
    for (int y = static_cast<int>(vy) + 10; y < static_cast<int>(vy + vh); y += 7) {
        for (int x = static_cast<int>(vx + vw) + 5; x < width; x += 7) {
            const Eigen::Vector3i c = at(x, y);
            ++samples;
            panelPixels += !(std::abs(c.x() - 51) <= 3 && std::abs(c.y() - 54) <= 3 &&
                             std::abs(c.z() - 59) <= 3);
        }
    }
    EXPECT_GT(panelPixels, samples * 9 / 10) << "the panels beside the view are missing";
}

/// A project of one ball in a fresh folder, for the interactive runs below; `height` above its
/// floating place (it falls and bobs in a preview).
fs::path ballProject(const std::string& name, double height = 0.0) {
    const fs::path dir =
        fs::temp_directory_path() / "plimsoll_tests" / (name + "_" + std::to_string(::getpid()));
    fs::remove_all(dir);
    fs::create_directories(dir);
    const fs::path project = dir / "ball.plim.json";
    std::ofstream(project) << R"({"schema_version": 1, "name": "ball",
        "bodies": [{"name": "ball", "mesh": ")"
                           << test::assetPath("sphere.obj").string()
                           << R"(", "material": {"density": 500}, "position": [0, )" << height
                           << R"(, 0]}]})";
    return project;
}

/// Runs `script` (sh) under its own Xvfb with $PLIMSOLL set; its stdout.
std::string runUnderXvfb(const fs::path& dir, const std::string& script) {
    const std::string command = "cd '" + dir.string() + "' && PLIMSOLL='" +
                                test::plimsollExecutable().string() + "' " + test::xvfbRun(dir) +
                                " sh -c '" + script + "' 2>/dev/null";
    std::string out;
    if (FILE* pipe = ::popen(command.c_str(), "r")) {
        char buffer[4096];
        while (std::size_t n = std::fread(buffer, 1, sizeof buffer, pipe)) out.append(buffer, n);
        ::pclose(pipe);
    }
    return out;
}

/// Whether this build's plimsoll has the editor window. The minimal build (no GUI) says at once
/// that it has none; without this check each window test's script would wait out all its
/// timeouts (over two minutes for the state-file tests) before skipping.
bool haveEditorWindow() {
    static const bool have = [] {
        const std::string probe = "'" + test::plimsollExecutable().string() +
                                  "' edit /nonexistent.plim.json --run-seconds 0 2>&1 | "
                                  "grep -q 'built without the editor window'";
        return std::system(probe.c_str()) != 0;
    }();
    return have;
}

/// Whether a window test can run here: xvfb-run (and xdotool for input) and a build with the
/// editor window (the skip messages name the tools; a build without the window is the other case).
bool haveWindowTools(bool needInput) {
    if (!haveEditorWindow()) return false;
    if (std::system("command -v xvfb-run >/dev/null 2>&1") != 0) return false;
    return !needInput || std::system("command -v xdotool >/dev/null 2>&1") == 0;
}

TEST(EditorWindow, IdleEditorSleepsInsteadOfRedrawing) {
    // 97-165% of a core with nothing happening. Idle, the loop now waits for
    // events: over 2 s after start-up it draws no frame and uses next to no CPU.
    if (!haveWindowTools(false)) GTEST_SKIP() << "xvfb-run is not installed";
    const fs::path project = ballProject("window_idle");
    const std::string out =
        runUnderXvfb(project.parent_path(),
                     "$PLIMSOLL edit ball.plim.json --run-seconds 3 --window-size 800x500");
    if (out.empty()) GTEST_SKIP() << "no editor window in this build or no X server";
    const nlohmann::json report = nlohmann::json::parse(out);
    EXPECT_LE(report["frames_after_first_second"].get<int>(), 2);
    // Below 5% of one core (the issue's bound) over the 2 s.
    EXPECT_LT(report["cpu_seconds_after_first_second"].get<double>(), 0.05 * 2.0);
}

TEST(EditorWindow, AnimatingEditorIsPacedToTheDisplayWithoutVsync) {
    // Xvfb's swap does not wait for a display: the ball's live preview drew 435 frames in 2 s
    // on 1.4 cores. Paced to the display's rate (Xvfb gives none: 60 Hz), it draws at most
    // about 120 in 2 s (a loaded machine draws fewer, never more), and still animates.
    if (!haveWindowTools(false)) GTEST_SKIP() << "xvfb-run is not installed";
    const fs::path project = ballProject("window_paced", 0.3);
    const std::string out = runUnderXvfb(
        project.parent_path(),
        "$PLIMSOLL edit ball.plim.json --preview --run-seconds 3 --window-size 800x500");
    if (out.empty()) GTEST_SKIP() << "no editor window in this build or no X server";
    const nlohmann::json report = nlohmann::json::parse(out);
    ASSERT_TRUE(report["preview_running"].get<bool>());
    const int frames = report["frames_after_first_second"].get<int>();
    std::printf("  animating 2 s: %d frames, %.2f s of CPU\n", frames,
                report["cpu_seconds_after_first_second"].get<double>());
    EXPECT_LE(frames, 2 * 60 + 10);
    EXPECT_GE(frames, 10);
}

/// Shell lines that start a script driving the editor run with `--state-file state.json`: `w`
/// is its window once it has drawn a frame, and `waitfor TEXT` waits until the state the
/// editor wrote after its latest frame holds TEXT (up to 30 s, then goes on and the test's
/// checks fail). Each step waits for the editor to have seen the last one, not a fixed time: a
/// slow X server or a loaded machine makes the run slower, not different.
const std::string kWaitForState =
    "waitfor() { i=0; until grep -qF \"$1\" state.json 2>/dev/null; do i=$((i+1)); "
    "[ $i -gt 600 ] && echo \"timed out waiting for $1\" >&2 && break; sleep 0.05; done; }; "
    "for i in $(seq 600); do [ -s state.json ] && break; sleep 0.05; done; "
    "w=$(xdotool search --name Plimsoll | head -1); ";

/// `waitfor` of a piece of the state's JSON (its quotes escaped for the shell's double quotes).
std::string waitFor(const std::string& json) {
    std::string escaped;
    for (char c : json) {
        if (c == '"') escaped += '\\';
        escaped += c;
    }
    return "waitfor \"" + escaped + "\"; ";
}

/// Moves the pointer to (x, y) of the window and waits until a frame has seen it there.
std::string moveTo(int x, int y) {
    const std::string at = std::to_string(x) + " " + std::to_string(y);
    return "xdotool mousemove --window $w " + at + "; " +
           waitFor("\"mouse\":[" + std::to_string(x) + "," + std::to_string(y) + "]");
}

/// Moves to (x, y) and presses the left button, each step seen by a frame.
std::string pressAt(int x, int y) {
    return moveTo(x, y) + "xdotool mousedown 1; " + waitFor("\"mouse_down\":true");
}

/// Moves to (x, y), then presses and releases the left button, each step seen by a frame.
std::string clickAt(int x, int y) {
    return pressAt(x, y) + "xdotool mouseup 1; " + waitFor("\"mouse_down\":false");
}

/// A left-button drag along the row y through the columns xs (pressed at the first, each move
/// seen by a frame), released at the last; the caller waits for what the release does.
std::string dragAlong(int y, std::initializer_list<int> xs) {
    std::string drag = pressAt(*xs.begin(), y);
    for (auto x = xs.begin() + 1; x != xs.end(); ++x) drag += moveTo(*x, y);
    return drag + "xdotool mouseup 1; ";
}

/// A left-button drag through the points (pressed at the first, each move seen by a frame),
/// released at the last; the caller waits for what the release does.
std::string dragThrough(const std::vector<std::pair<int, int>>& points) {
    std::string drag = pressAt(points.front().first, points.front().second);
    for (std::size_t i = 1; i < points.size(); ++i)
        drag += moveTo(points[i].first, points[i].second);
    return drag + "xdotool mouseup 1; ";
}

/// A fresh copy of the damaged boat sample (its mesh and map in assets/, the project and its
/// graph in projects/) under a folder of the temporary directory; the project file.
fs::path damagedBoatCopy(const std::string& name) {
    const fs::path root =
        fs::temp_directory_path() / "plimsoll_tests" / (name + "_" + std::to_string(::getpid()));
    fs::remove_all(root);
    const fs::path source = PLIMSOLL_SOURCE_DIR;
    fs::create_directories(root / "assets");
    fs::create_directories(root / "projects");
    for (const char* file : {"hull.obj", "hull_stern_damage.png"})
        fs::copy_file(source / "assets" / file, root / "assets" / file);
    for (const char* file : {"damaged_boat.plim.json", "boat.graph.json"})
        fs::copy_file(source / "projects" / file, root / "projects" / file);
    return root / "projects" / "damaged_boat.plim.json";
}

/// Pieces of the set of pixels (8-neighbours joined).
int connectedPieces(const std::vector<char>& set, int width, int height) {
    std::vector<char> seen(set.size(), 0);
    int pieces = 0;
    for (std::size_t start = 0; start < set.size(); ++start) {
        if (!set[start] || seen[start]) continue;
        ++pieces;
        std::vector<std::size_t> stack{start};
        seen[start] = 1;
        while (!stack.empty()) {
            const std::size_t p = stack.back();
            stack.pop_back();
            const int x = static_cast<int>(p % width), y = static_cast<int>(p / width);
            for (int dy = -1; dy <= 1; ++dy) {
                for (int dx = -1; dx <= 1; ++dx) {
                    const int nx = x + dx, ny = y + dy;
                    if (nx < 0 || ny < 0 || nx >= width || ny >= height) continue;
                    const std::size_t q = static_cast<std::size_t>(ny) * width + nx;
                    if (set[q] && !seen[q]) {
                        seen[q] = 1;
                        stack.push_back(q);
                    }
                }
            }
        }
    }
    return pieces;
}

TEST(EditorWindow, XWithTheWaterGraphOpenLeavesTheBrushMirrorAlone) {
    // Holding X to constrain a node drag also toggled the brush's X mirror.
    // X toggles the mirror only while the paint tools have the view (KeyTapsShorterThanAFrame-
    // AllCount: the graph panel closed); here the damaged boat's Water graph panel is opened
    // by a click on its title bar's arrow, and X then B are tapped: B is seen (so X was), the
    // mirror stays off.
    if (!haveWindowTools(true)) GTEST_SKIP() << "xvfb-run or xdotool is not installed";
    const fs::path root = fs::temp_directory_path() / "plimsoll_tests" /
                          ("window_graph_x_" + std::to_string(::getpid()));
    fs::remove_all(root);
    const fs::path source = PLIMSOLL_SOURCE_DIR;
    fs::create_directories(root / "assets");
    fs::create_directories(root / "projects");
    for (const char* file : {"hull.obj", "hull_stern_damage.png"})
        fs::copy_file(source / "assets" / file, root / "assets" / file);
    for (const char* file : {"damaged_boat.plim.json", "boat.graph.json"})
        fs::copy_file(source / "projects" / file, root / "projects" / file);
    // 800 x 500: the Water graph panel's title bar, collapsed, spans (17..475, 41..57).
    const std::string out =
        runUnderXvfb(root / "projects",
                     "$PLIMSOLL edit damaged_boat.plim.json --run-seconds 60 --window-size 800x500 "
                     "--state-file state.json & " +
                         kWaitForState + clickAt(28, 49) + waitFor("\"name\":\"Water graph\"") +
                         "xdotool key --window $w --delay 0 x b; " + waitFor("\"tool\":1") +
                         "xdotool key --window $w ctrl+q; wait");
    if (out.empty()) GTEST_SKIP() << "no editor window in this build or no X server";
    const nlohmann::json report = nlohmann::json::parse(out);
    EXPECT_LT(report["seconds"].get<double>(), 59.0) << "Ctrl+Q was not seen";
    EXPECT_EQ(report["tool"], 1);          // b: Brush, after x
    EXPECT_EQ(report["mirror_x"], false);  // x went to the graph
}

TEST(EditorWindow, KeyTapsShorterThanAFrameAllCount) {
    // Taps sent back to back (xdotool: press and release with no
    // delay, all within one frame) were lost about half the time; P restarted a running
    // preview and Space did nothing. Each tap below must take effect, in order.
    if (!haveWindowTools(true)) GTEST_SKIP() << "xvfb-run or xdotool is not installed";
    const fs::path project = ballProject("window_keys");
    const std::string out = runUnderXvfb(
        project.parent_path(),
        "$PLIMSOLL edit ball.plim.json --run-seconds 30 --window-size 800x500 --view front "
        "--state-file state.json & " +
            kWaitForState + "xdotool key --window $w --delay 0 3 b x p space; " +
            waitFor("\"preview_playing\":false,\"preview_running\":true") +
            waitFor("\"view\":\"Side (orthographic)\"") + "xdotool key --window $w ctrl+q; wait");
    if (out.empty()) GTEST_SKIP() << "no editor window in this build or no X server";
    const nlohmann::json report = nlohmann::json::parse(out);
    EXPECT_LT(report["seconds"].get<double>(), 29.0) << "Ctrl+Q was not seen";
    EXPECT_EQ(report["view"], "Side (orthographic)");  // 3
    EXPECT_EQ(report["tool"], 1);                      // b: Brush
    EXPECT_EQ(report["mirror_x"], true);               // x (the graph panel is closed)
    EXPECT_EQ(report["preview_running"], true);        // p: started
    EXPECT_EQ(report["preview_playing"], false);       // space: paused
}

TEST(EditorWindow, StrokeFromOffTheMeshPaintsDuringThePreviewAndAfterIt) {
    // A stroke that started off the mesh and crossed it painted nothing. With the Brush a drag
    // paints on the body where the preview has floated it (the preview takes the stroke at
    // once); after the preview stops, the same drag from empty space paints again: two steps.
    if (!haveWindowTools(true)) GTEST_SKIP() << "xvfb-run or xdotool is not installed";
    const fs::path project = ballProject("window_stroke");
    // 800 x 500: the 3D view is the left 480 px; the ball (front view, framed) at its centre.
    // Each step waits for a frame to have seen it (the state file), not a fixed time.
    const std::string drag =
        dragAlong(250, {15, 60, 120, 180, 240, 280}) + waitFor("\"mouse_down\":false");
    const std::string out = runUnderXvfb(
        project.parent_path(),
        "$PLIMSOLL edit ball.plim.json --run-seconds 60 --window-size 800x500 --view front "
        "--state-file state.json & " +
            kWaitForState + "xdotool key --window $w b p; " + waitFor("\"preview_running\":true") +
            waitFor("\"tool\":1") + drag + waitFor("\"undo\":\"Paint permeability\"") +
            waitFor("\"status\":\"Live preview: the new paint is simulated\"") +
            // Saved, so that the second stroke shows as the document turning dirty again.
            "cp state.json floating.json; xdotool key --window $w ctrl+s; " +
            waitFor("\"dirty\":false") + "xdotool key --window $w p; " +
            waitFor("\"preview_running\":false") + drag + waitFor("\"dirty\":true") +
            // Saved before Ctrl+Q, which would otherwise ask about the unsaved paint.
            "cp state.json painted.json; xdotool key --window $w ctrl+s; " +
            waitFor("\"dirty\":false") + "xdotool key --window $w ctrl+q; wait");
    if (out.empty()) GTEST_SKIP() << "no editor window in this build or no X server";
    const nlohmann::json report = nlohmann::json::parse(out);
    EXPECT_LT(report["seconds"].get<double>(), 59.0) << "Ctrl+Q was not seen";
    EXPECT_EQ(report["tool"], 1);
    EXPECT_EQ(report["preview_running"], false);
    EXPECT_EQ(report["undo"], "Paint permeability");
    EXPECT_EQ(report["undo_steps"], 2) << "one stroke during the preview, one after it";
    const nlohmann::json floating =
        nlohmann::json::parse(test::readFile(project.parent_path() / "floating.json"));
    EXPECT_EQ(floating["preview_running"], true);
    EXPECT_EQ(floating["status"], "Live preview: the new paint is simulated");
    const nlohmann::json painted =
        nlohmann::json::parse(test::readFile(project.parent_path() / "painted.json"));
    EXPECT_EQ(painted["title"], "*ball.plim.json - Plimsoll");
}

TEST(EditorWindow, FillDragDuringThePreviewSaysWhyItPullsAndStopClearsThePreviewsStatus) {
    // With a paint tool up during the preview a left drag pulled the body and painted nothing,
    // without a word; after Stop the status bar still said "Live preview on fast CPU". Now
    // a fill's drag says why it pulls (the Brush paints), and Stop says the preview stopped.
    if (!haveWindowTools(true)) GTEST_SKIP() << "xvfb-run or xdotool is not installed";
    const fs::path project = ballProject("window_brush_preview");
    const fs::path dir = project.parent_path();
    const std::string out = runUnderXvfb(
        dir,
        "$PLIMSOLL edit ball.plim.json --run-seconds 60 --window-size 800x500 --view front "
        "--state-file state.json & " +
            kWaitForState + "xdotool key --window $w g p; " + waitFor("\"preview_running\":true") +
            waitFor("\"tool\":2") + "cp state.json started.json; " +
            dragAlong(250, {200, 230, 260, 290}) + waitFor("\"mouse_down\":false") +
            "cp state.json pulled.json; xdotool key --window $w p; " +
            waitFor("\"preview_running\":false") + "xdotool key --window $w ctrl+q; wait");
    if (out.empty()) GTEST_SKIP() << "no editor window in this build or no X server";
    const nlohmann::json started = nlohmann::json::parse(test::readFile(dir / "started.json"));
    EXPECT_EQ(started["status"].get<std::string>().rfind("Live preview on ", 0), 0u)
        << started["status"];
    const nlohmann::json pulled = nlohmann::json::parse(test::readFile(dir / "pulled.json"));
    EXPECT_NE(pulled["status"].get<std::string>().find("The Brush (B) paints on it"),
              std::string::npos)
        << pulled["status"];
    EXPECT_EQ(pulled["undo"], "") << "the drag painted during the preview";
    const nlohmann::json report = nlohmann::json::parse(out);
    EXPECT_EQ(report["status"], "Live preview stopped");
}

TEST(EditorWindow, AClickOnTheWaterGraphsTitleOpensIt) {
    // The folded Water graph panel opened only from its arrow (or a double-click); a click on
    // its title, as on any folded header, did nothing. At 800 x 500 its title bar spans
    // (17..475, 41..57): a click at (200, 49), clear of the arrow, opens it.
    if (!haveWindowTools(true)) GTEST_SKIP() << "xvfb-run or xdotool is not installed";
    const fs::path project = damagedBoatCopy("window_graph_title");
    const fs::path dir = project.parent_path();
    const std::string out =
        runUnderXvfb(dir,
                     "$PLIMSOLL edit damaged_boat.plim.json --run-seconds 60 --window-size 800x500 "
                     "--state-file state.json & " +
                         kWaitForState + clickAt(200, 49) + waitFor("\"name\":\"Water graph\"") +
                         "cp state.json opened.json; xdotool key --window $w ctrl+q; wait");
    if (out.empty()) GTEST_SKIP() << "no editor window in this build or no X server";
    const nlohmann::json opened = nlohmann::json::parse(test::readFile(dir / "opened.json"));
    bool open = false;
    for (const auto& w : opened["windows"]) open = open || w["name"] == "Water graph";
    EXPECT_TRUE(open) << "the click on the title left the panel folded";
}

TEST(EditorWindow, SchematicDragsConnectAndMoveNodesAsUndoSteps) {
    // The schematic only selected. At 1280 x 720, with the Water graph panel opened, its
    // schematic shows the damaged boat's four boxes in a row at y = 491, the stern's port
    // (the dot on its right edge) at x = 121 and the fore hold's box around x = 305: a drag
    // from the port onto that box connects them; a drag of the aft hold's box (x = 190) up
    // moves it. Each is one undo step, undone by Ctrl+Z.
    if (!haveWindowTools(true)) GTEST_SKIP() << "xvfb-run or xdotool is not installed";
    const fs::path project = damagedBoatCopy("window_schematic");
    const fs::path dir = project.parent_path();
    const std::string out = runUnderXvfb(
        dir,
        "$PLIMSOLL edit damaged_boat.plim.json --run-seconds 60 --window-size 1280x720 "
        "--state-file state.json & " +
            kWaitForState + clickAt(70, 66) + waitFor("\"name\":\"Water graph\"") +
            dragAlong(491, {121, 200, 300}) + waitFor("\"undo\":\"Connect stern-fore\"") +
            "cp state.json connected.json; " + dragThrough({{190, 480}, {190, 440}, {192, 430}}) +
            waitFor("\"undo\":\"Move 1 node\"") + "cp state.json moved.json; " +
            "xdotool key --window $w ctrl+z ctrl+z; " + waitFor("\"undo\":\"\"") +
            "xdotool key --window $w ctrl+q; wait");
    if (out.empty()) GTEST_SKIP() << "no editor window in this build or no X server";
    const nlohmann::json connected = nlohmann::json::parse(test::readFile(dir / "connected.json"));
    EXPECT_EQ(connected["undo"], "Connect stern-fore");
    const nlohmann::json moved = nlohmann::json::parse(test::readFile(dir / "moved.json"));
    EXPECT_EQ(moved["undo"], "Move 1 node");
    const nlohmann::json report = nlohmann::json::parse(out);
    EXPECT_LT(report["seconds"].get<double>(), 59.0) << "Ctrl+Q was not seen";
    EXPECT_EQ(report["undo"], "");  // both undone
}

TEST(EditorWindow, ASchematicDropMovesNoOtherBox) {
    // The damaged boat's compartments all lie at one height. The aft hold's box (x = 190, in
    // the row at y = 491 as above) dragged 20 px up (0.26 m, still inside the hull: no warning
    // line above the schematic) and dropped: the other boxes stay on their pixels, so a drag from
    // the stern's port (121, 491) onto the fore hold's box (300, 491) still connects them. The
    // schematic used to refit its view to the raised node on the drop, which sent the rest of the
    // row to the canvas's bottom edge.
    if (!haveWindowTools(true)) GTEST_SKIP() << "xvfb-run or xdotool is not installed";
    const fs::path project = damagedBoatCopy("window_schematic_frame");
    const fs::path dir = project.parent_path();
    const std::string out = runUnderXvfb(
        dir,
        "$PLIMSOLL edit damaged_boat.plim.json --run-seconds 60 --window-size 1280x720 "
        "--state-file state.json & " +
            kWaitForState + clickAt(70, 66) + waitFor("\"name\":\"Water graph\"") +
            dragThrough({{190, 480}, {190, 470}, {190, 460}}) +
            waitFor("\"undo\":\"Move 1 node\"") + dragAlong(491, {121, 200, 300}) +
            waitFor("\"undo\":\"Connect stern-fore\"") + "cp state.json connected.json; " +
            "xdotool key --window $w ctrl+z ctrl+z; " + waitFor("\"undo\":\"\"") +
            "xdotool key --window $w ctrl+q; wait");
    if (out.empty()) GTEST_SKIP() << "no editor window in this build or no X server";
    const nlohmann::json connected = nlohmann::json::parse(test::readFile(dir / "connected.json"));
    EXPECT_EQ(connected["undo"], "Connect stern-fore") << "the stern's port moved";
    const nlohmann::json report = nlohmann::json::parse(out);
    EXPECT_LT(report["seconds"].get<double>(), 59.0) << "Ctrl+Q was not seen";
    EXPECT_EQ(report["undo"], "");  // both undone
}

TEST(EditorWindow, EscClosesAMenuAndTheUvViewZoomsUnderAnOpenMenu) {
    // Esc did not close an open menu, and while one was open the UV view ignored the wheel.
    // At 800 x 500 the File menu's title is at (25, 9) and the UV view's square spans
    // (488..590, 366..468): File, Esc (closed); File again, the wheel over the UV view (it
    // zooms, the menu closes).
    if (!haveWindowTools(true)) GTEST_SKIP() << "xvfb-run or xdotool is not installed";
    const fs::path project = ballProject("window_menu_esc");
    const fs::path dir = project.parent_path();
    const std::string out = runUnderXvfb(
        dir,
        "$PLIMSOLL edit ball.plim.json --run-seconds 60 --window-size 800x500 --view front "
        "--state-file state.json & " +
            kWaitForState + clickAt(25, 9) + waitFor("\"popup\":\"##Menu_00\"") +
            "cp state.json opened.json; xdotool key --window $w Escape; " +
            waitFor("\"popup\":\"\"") + "cp state.json closed.json; " + clickAt(25, 9) +
            waitFor("\"popup\":\"##Menu_00\"") + moveTo(539, 417) + "xdotool click 4; " +
            waitFor("\"uv_zoom\":1.25") +
            "cp state.json zoomed.json; xdotool key --window $w ctrl+q; wait");
    if (out.empty()) GTEST_SKIP() << "no editor window in this build or no X server";
    const nlohmann::json opened = nlohmann::json::parse(test::readFile(dir / "opened.json"));
    EXPECT_EQ(opened["popup"], "##Menu_00");
    const nlohmann::json closed = nlohmann::json::parse(test::readFile(dir / "closed.json"));
    EXPECT_EQ(closed["popup"], "") << "Esc left the menu open";
    const nlohmann::json report = nlohmann::json::parse(out);
    EXPECT_LT(report["seconds"].get<double>(), 59.0) << "Ctrl+Q was not seen";
    const nlohmann::json zoomed = nlohmann::json::parse(test::readFile(dir / "zoomed.json"));
    EXPECT_EQ(zoomed["uv_zoom"], 1.25) << "the wheel under the open menu did not reach the UV view";
    EXPECT_EQ(zoomed["popup"], "") << "the menu stayed open over the zoomed view";
}

TEST(EditorWindow, EnterTappedRightAfterTypingANumberCommitsIt) {
    // After typing in a number field the first Enter was ignored about one time in two: a tap
    // shorter than a frame (pressed and released between two frames) never showed as down to
    // ImGui 1.86. Here the inspector's x position gets "0.25" and an Enter sent back to back
    // (xdotool, no delay), three times over: each Enter moves the ball, one undo step each.
    if (!haveWindowTools(true)) GTEST_SKIP() << "xvfb-run or xdotool is not installed";
    const fs::path project = ballProject("window_enter");
    const fs::path dir = project.parent_path();
    // The inspector given most of the column: at 800 x 500 its x position field is at (520, 263).
    fs::create_directories(dir / "config" / "plimsoll");
    std::ofstream(dir / "config" / "plimsoll" / "settings.json")
        << R"({"layout": {"column_width": 400, "shares": [0.1, 0.1, 0.7, 0.1]}})";
    std::string typing;
    for (const char* value : {"0.25", "0.5", "0.75"}) {
        typing += clickAt(520, 263) +
                  "xdotool key --window $w ctrl+a; xdotool type --window $w --delay 0 " + value +
                  "; xdotool key --window $w --delay 0 Return; " +
                  waitFor(std::string("\"undo\":\"Move ball\"")) + "sleep 0.3; ";
    }
    const std::string out = runUnderXvfb(
        dir,
        "$PLIMSOLL edit ball.plim.json --run-seconds 60 --window-size 800x500 --view front "
        "--state-file state.json & " +
            kWaitForState + typing + "xdotool key --window $w ctrl+s; " +
            waitFor("\"dirty\":false") + "xdotool key --window $w ctrl+q; wait");
    if (out.empty()) GTEST_SKIP() << "no editor window in this build or no X server";
    const nlohmann::json report = nlohmann::json::parse(out);
    EXPECT_LT(report["seconds"].get<double>(), 59.0) << "Ctrl+Q was not seen (unsaved?)";
    EXPECT_EQ(report["undo"], "Move ball");
    EXPECT_EQ(report["undo_steps"], 3) << "an Enter was lost";
    Result<Project> saved = loadProject(project);
    ASSERT_TRUE(saved.ok()) << saved.error().message;
    EXPECT_EQ(saved->bodies[0].position.x(), 0.75);
}

/// The rectangle of the window named `name` in a state or report (empty when it is not open).
std::vector<int> windowRect(const nlohmann::json& state, const std::string& name) {
    for (const auto& w : state["windows"]) {
        if (w["name"] == name) return w["rect"].get<std::vector<int>>();
    }
    return {};
}

TEST(EditorWindow, LivePreviewPanelStaysInTheViewCornerWhenTheWindowShrinksAndGrows) {
    // At 1000 x 650 the Live preview panel was pushed off the bottom over the status bar, and
    // after the window grew back it sat mid-left over the view. Now it keeps to the view's
    // lower-left corner: inside the view at 1000 x 650, opened sections and all, and in the
    // corner again at 1200 x 780.
    if (!haveWindowTools(true)) GTEST_SKIP() << "xvfb-run or xdotool is not installed";
    const fs::path project = ballProject("window_preview_corner", 0.3);
    const fs::path dir = project.parent_path();
    const std::string out = runUnderXvfb(
        dir,
        "$PLIMSOLL edit ball.plim.json --preview --run-seconds 60 --window-size 1000x650 "
        "--state-file state.json & " +
            kWaitForState + waitFor("\"name\":\"Live preview\"") +
            "sleep 0.5; cp state.json small.json; "
            "xdotool windowsize $w 1200 780; " +
            waitFor("\"window\":[1200,780]") +
            "sleep 0.5; "
            "cp state.json large.json; xdotool key --window $w ctrl+q; wait");
    if (out.empty()) GTEST_SKIP() << "no editor window in this build or no X server";
    for (const char* file : {"small.json", "large.json"}) {
        SCOPED_TRACE(file);
        const nlohmann::json state = nlohmann::json::parse(test::readFile(dir / file));
        const std::vector<int> view = state["viewport"].get<std::vector<int>>();
        const std::vector<int> panel = windowRect(state, "Live preview");
        ASSERT_EQ(panel.size(), 4u) << state.dump();
        EXPECT_GE(panel[1], view[1]);
        EXPECT_LE(panel[1] + panel[3], view[1] + view[3]) << "below the view, over the status bar";
        EXPECT_NEAR(panel[0], view[0] + 8, 1) << "not at the view's left edge";
        EXPECT_NEAR(panel[1] + panel[3], view[1] + view[3] - 8, 1) << "not at the view's bottom";
    }
}

TEST(EditorWindow, HydrostaticsFromTheMenuWithoutAPreviewPlotsBothCurvesAgainstDegrees) {
    // Hydrostatics existed only while a preview ran, and its GZ plots had no axes, separate
    // curves and a sample index under the mouse ("14: 0.6075"). Simulate > Hydrostatics opens
    // it with no preview; Compute fills it on a worker; under the mouse the plot gives the heel
    // in degrees and both methods' arms there. 1200 x 780, damaged boat: the menu's item at
    // (190, 95), Compute at (57, 227), the plot's 58th degree or so at (200, 575).
    if (!haveWindowTools(true)) GTEST_SKIP() << "xvfb-run or xdotool is not installed";
    const fs::path project = damagedBoatCopy("window_hydrostatics");
    const fs::path dir = project.parent_path();
    const std::string out = runUnderXvfb(
        dir,
        "$PLIMSOLL edit damaged_boat.plim.json --run-seconds 90 --window-size 1200x780 "
        "--state-file state.json & " +
            kWaitForState + clickAt(170, 9) + waitFor("\"popup\":\"##Menu_00\"") +
            clickAt(190, 95) + waitFor("\"name\":\"Hydrostatics\"") + clickAt(57, 227) +
            "i=0; until grep -q \"textures: GZ\" state.json || [ $i -gt 600 ]; do i=$((i+1)); "
            "xdotool mousemove --window $w 200 575; sleep 0.1; xdotool mousemove --window $w 201 "
            "575; done; "
            "cp state.json hovered.json; xdotool key --window $w ctrl+q; wait");
    if (out.empty()) GTEST_SKIP() << "no editor window in this build or no X server";
    const nlohmann::json report = nlohmann::json::parse(out);
    EXPECT_EQ(report["preview_running"], false);
    const nlohmann::json hovered = nlohmann::json::parse(test::readFile(dir / "hovered.json"));
    const std::string tip = hovered["tooltip"].get<std::string>();
    ASSERT_NE(tip.find("textures: GZ "), std::string::npos) << tip;
    ASSERT_NE(tip.find("exact: GZ "), std::string::npos) << tip;
    const std::size_t at = tip.find(" m at ");
    ASSERT_NE(at, std::string::npos) << tip;
    const double heel = std::stod(tip.substr(at + 6));
    EXPECT_GT(heel, 40.0) << tip;
    EXPECT_LT(heel, 80.0) << tip;
    EXPECT_NE(tip.find(" deg"), std::string::npos) << tip;
}

TEST(EditorWindow, ShiftClickDrawsALineStrokeFromTheLastStrokesEnd) {
    // A short stroke on the ball, then Shift-click elsewhere on it draws a
    // straight line from the stroke's end there (Blender and Painter): a second undo step made
    // of many surface points, not one dab. Each step waits until a frame has seen the last
    // one (fixed sleeps lost the Shift under a slow sanitizer build).
    if (!haveWindowTools(true)) GTEST_SKIP() << "xvfb-run or xdotool is not installed";
    const fs::path project = ballProject("window_line");
    const std::string stroke = "xdotool key --window $w b; " + waitFor("\"tool\":1") +
                               dragAlong(250, {220, 230, 240, 250, 260}) +
                               waitFor("\"undo\":\"Paint permeability\"");
    const std::string line =
        moveTo(240, 190) + "xdotool keydown shift; " + waitFor("\"shift\":true") +
        "xdotool mousedown 1; " + waitFor("\"mouse_down\":true") + "xdotool mouseup 1; " +
        waitFor("\"mouse_down\":false") + "xdotool keyup shift; " + waitFor("\"shift\":false");
    const std::string out = runUnderXvfb(
        project.parent_path(),
        "$PLIMSOLL edit ball.plim.json --run-seconds 90 --window-size 800x500 --view front "
        "--state-file state.json & " +
            kWaitForState + stroke + line + "xdotool key --window $w ctrl+s; " +
            waitFor("\"dirty\":false") + "xdotool key --window $w ctrl+q; wait");
    if (out.empty()) GTEST_SKIP() << "no editor window in this build or no X server";
    const nlohmann::json report = nlohmann::json::parse(out);
    EXPECT_LT(report["seconds"].get<double>(), 89.0) << "Ctrl+Q was not seen";
    EXPECT_EQ(report["undo"], "Paint permeability");
    EXPECT_EQ(report["undo_steps"], 2) << "the stroke and the line";
    // 60 px from (260, 250) to (240, 190), picked every 3 px: about 20 points.
    EXPECT_GE(report["last_stroke_points"].get<int>(), 12);
}

TEST(EditorWindow, ColumnSplitterDragsAndPanelsComeBackAfterShrinkAndGrow) {
    // The border between the 3D view and the
    // panels (x = 480 at 800 x 500: the column is 0.4 of the width), dragged 100 px right,
    // narrows the column to 220 px; the window shrunk to 300 x 200 and grown back to 800 x 500
    // gets that same layout back. Each step waits until the editor has drawn a frame after it
    // (the drag held, each move seen, the new size): under load, fixed sleeps let the release
    // come in the same frame as the last move, or the run end before the window grew back.
    if (!haveWindowTools(true)) GTEST_SKIP() << "xvfb-run or xdotool is not installed";
    const fs::path project = ballProject("window_splitter");
    std::string drag =
        moveTo(480, 300) + "xdotool mousedown 1; " + waitFor("\"held\":\"##split_column\"");
    for (int x : {500, 530, 560, 580}) drag += moveTo(x, 300);
    drag += "xdotool mouseup 1; " + waitFor("\"held\":\"\"");
    const std::string out =
        runUnderXvfb(project.parent_path(),
                     "$PLIMSOLL edit ball.plim.json --run-seconds 90 --window-size 800x500 "
                     "--state-file state.json & " +
                         kWaitForState + drag + "xdotool windowsize $w 300 200; " +
                         waitFor("\"window\":[300,200]") + "xdotool windowsize $w 800 500; " +
                         waitFor("\"window\":[800,500]") + "xdotool key --window $w ctrl+q; wait");
    if (out.empty()) GTEST_SKIP() << "no editor window in this build or no X server";
    const nlohmann::json report = nlohmann::json::parse(out);
    EXPECT_LT(report["seconds"].get<double>(), 89.0) << "Ctrl+Q was not seen";
    ASSERT_EQ(report["window"][0].get<double>(), 800);
    ASSERT_EQ(report["window"][1].get<double>(), 500);
    EXPECT_NEAR(report["viewport"][2].get<double>(), 580, 2) << "the splitter did not move";
    EXPECT_EQ(report["undo_steps"], 0);  // the drag edited nothing
}

TEST(EditorWindow, HoveringAControlShowsItsTooltip) {
    // Tooltips on every control. The pointer rests on the Tools panel's
    // "Navigate" button through the real window; the frame then shows that button's tooltip:
    // its text (reported by the tooltip helper) and its window in the last frame's picture,
    // an outlined box at the place ImGui reports, with text in it. In the 3D view before, none.
    if (!haveWindowTools(true)) GTEST_SKIP() << "xvfb-run or xdotool is not installed";
    const fs::path project = ballProject("window_tooltip");
    const fs::path dir = project.parent_path();
    const std::string out = runUnderXvfb(
        dir,
        "$PLIMSOLL edit ball.plim.json --run-seconds 90 --window-size 800x500 "
        "--state-file state.json --screenshot shot.png & " +
            kWaitForState + moveTo(200, 250) + "cp state.json before.json; " + moveTo(504, 52) +
            waitFor("\"tooltip_rect\"") + "xdotool key --window $w ctrl+q; wait");
    if (out.empty()) GTEST_SKIP() << "no editor window in this build or no X server";
    const nlohmann::json report = nlohmann::json::parse(out);
    const nlohmann::json before = nlohmann::json::parse(test::readFile(dir / "before.json"));
    EXPECT_EQ(before["tooltip"], "") << before.dump();
    EXPECT_FALSE(before.contains("tooltip_rect"));
    const nlohmann::json& last = report["last_frame"];
    EXPECT_EQ(last["tooltip"], "Left mouse orbits the view (V)") << last.dump();
    ASSERT_TRUE(last.contains("tooltip_rect")) << last.dump();

    int width = 0, height = 0, channels = 0;
    unsigned char* data = stbi_load((dir / "shot.png").c_str(), &width, &height, &channels, 3);
    ASSERT_TRUE(data) << stbi_failure_reason();
    std::vector<unsigned char> rgb(data, data + 3 * width * height);
    stbi_image_free(data);
    ASSERT_EQ(width, 800);
    auto at = [&](int x, int y) {
        x = std::clamp(x, 0, width - 1);
        y = std::clamp(y, 0, height - 1);
        const std::size_t i = 3 * (static_cast<std::size_t>(y) * width + x);
        return Eigen::Vector3i(rgb[i], rgb[i + 1], rgb[i + 2]);
    };
    const int x0 = last["tooltip_rect"][0], y0 = last["tooltip_rect"][1];
    const int w = last["tooltip_rect"][2], h = last["tooltip_rect"][3];
    EXPECT_GT(w, 150) << "the tooltip holds one line of about 30 characters";
    EXPECT_GT(h, 10);
    // Beside the pointer (ImGui puts it below and right of the cursor), on screen.
    EXPECT_NEAR(x0, 504, 40);
    EXPECT_NEAR(y0, 52, 40);
    // The outline: ImGui's window border (a grey-blue) along the box's top and bottom edges.
    auto border = [&](const Eigen::Vector3i& c) {
        return c.z() >= c.x() && c.x() > 40 && c.x() < 120 && std::abs(c.x() - c.y()) <= 3;
    };
    int outline = 0, outlineSamples = 0;
    for (int x = x0 + 4; x < x0 + w - 4; ++x) {
        for (int y : {y0, y0 + h - 1}) {
            ++outlineSamples;
            outline += border(at(x, y));
        }
    }
    EXPECT_GT(outline, outlineSamples * 9 / 10) << "no tooltip box where ImGui put it";
    // Its text: white pixels inside the box.
    int bright = 0;
    for (int y = y0 + 2; y < y0 + h - 2; ++y) {
        for (int x = x0 + 2; x < x0 + w - 2; ++x) bright += at(x, y).minCoeff() > 200;
    }
    EXPECT_GT(bright, 100) << "no text in the tooltip";
}

TEST(EditorWindow, AnOpenedPlotWindowDrawsItsCurveAcrossItsWidth) {
    // The plot windows drew no curve, only a 1-pixel line above "Export CSV"
    // (a plot of width -1, which Debian's ImGui 1.86 sizes to nothing here). The ball, dropped
    // from 0.3 m, bobs in the live preview; its "Submerged volume" window, opened by a click on
    // its title bar's arrow, shows the curve in ImGui's plot-line grey over most of its width,
    // rising and falling by more than a few pixels.
    if (!haveWindowTools(true)) GTEST_SKIP() << "xvfb-run or xdotool is not installed";
    const fs::path project = ballProject("window_plot", 0.3);
    const fs::path dir = project.parent_path();
    // 800 x 500: the plot windows stack, collapsed, from (150, 49) down the view's right edge.
    const std::string frameNow = "$(sed \"s/.*\\\"frame\\\":\\([0-9]*\\).*/\\1/\" state.json)";
    const std::string out = runUnderXvfb(
        dir,
        "$PLIMSOLL edit ball.plim.json --preview --run-seconds 90 --window-size 800x500 "
        "--state-file state.json --screenshot shot.png & " +
            kWaitForState + waitFor("\"name\":\"Live preview\"") + clickAt(162, 58) +
            waitFor("\"name\":\"Submerged volume: ball\"") + moveTo(700, 480) +
            // 90 more frames (one simulated frame each, at most): rows for the curve.
            "f0=" + frameNow + "; i=0; until [ " + frameNow +
            " -ge $((f0 + 90)) ] || [ $i -gt 600 ]; "
            "do i=$((i+1)); sleep 0.05; done; xdotool key --window $w ctrl+q; wait");
    if (out.empty()) GTEST_SKIP() << "no editor window in this build or no X server";
    const nlohmann::json report = nlohmann::json::parse(out);
    EXPECT_TRUE(report["preview_running"].get<bool>());
    std::optional<nlohmann::json> rect;
    for (const nlohmann::json& w : report["last_frame"]["windows"]) {
        if (w["name"] == "Submerged volume: ball") rect = w["rect"];
    }
    ASSERT_TRUE(rect) << "the plot window is not open: " << report["last_frame"].dump();
    int width = 0, height = 0, channels = 0;
    unsigned char* data = stbi_load((dir / "shot.png").c_str(), &width, &height, &channels, 3);
    ASSERT_TRUE(data) << stbi_failure_reason();
    std::vector<unsigned char> rgb(data, data + 3 * width * height);
    stbi_image_free(data);
    const int x0 = (*rect)[0], y0 = (*rect)[1], w = (*rect)[2], h = (*rect)[3];
    ASSERT_GT(w, 200);
    // The plot (60 px high, below the 19 px title bar and 8 px of padding) is dark blue; its
    // curve, a light grey 1-pixel line, brightens every column it crosses. Looked for below
    // the value's white text at the plot's top (18 px), where a peak may pass out of sight.
    const int bandTop = y0 + 19 + 8 + 18, bandBottom = y0 + 19 + 8 + 60;
    int columns = 0, top = height, bottom = 0;
    for (int x = std::max(0, x0 + 8); x < std::min(width, x0 + w - 8); ++x) {
        bool line = false;
        for (int y = std::max(0, bandTop); y < std::min(height, bandBottom); ++y) {
            const std::size_t i = 3 * (static_cast<std::size_t>(y) * width + x);
            if (rgb[i] + rgb[i + 1] + rgb[i + 2] > 250) {  // the plot's own blue: about 150
                line = true;
                top = std::min(top, y);
                bottom = std::max(bottom, y);
            }
        }
        columns += line;
    }
    // 187 of 304 columns when written (the peaks above the band); a 1-pixel plot: 1 or 2.
    EXPECT_GT(columns, w / 3) << "the curve should run across the window";
    EXPECT_GT(bottom - top, 5) << "a bobbing ball's submerged volume rises and falls";
}

TEST(EditorWindow, UvViewZoomsAtTheCursorAndPans) {
    // A UV view that zooms and pans. At 800 x 500 the UV view's square starts
    // at (488, 366), 102 px a side. Two wheel steps up over a point a quarter in from its top
    // left zoom by 1.25^2 with the uv under the cursor staying put; a middle-mouse drag 40 px
    // left then moves the layout with the mouse: the uv at that point grows by 40 / (102 zoom).
    if (!haveWindowTools(true)) GTEST_SKIP() << "xvfb-run or xdotool is not installed";
    const fs::path project = ballProject("window_uv");
    const fs::path dir = project.parent_path();
    const std::string out = runUnderXvfb(
        dir,
        "$PLIMSOLL edit ball.plim.json --run-seconds 90 --window-size 800x500 --state-file "
        "state.json & " +
            kWaitForState + moveTo(513, 391) + waitFor("\"tooltip_rect\"") +
            "cp state.json before.json; " + "xdotool click 4; " + waitFor("\"uv_zoom\":1.25") +
            "xdotool click 4; " + waitFor("\"uv_zoom\":1.5625") + "cp state.json zoomed.json; " +
            "xdotool mousedown 2; " + moveTo(493, 391) + moveTo(473, 391) + "xdotool mouseup 2; " +
            moveTo(513, 391) + "cp state.json panned.json; xdotool key --window $w ctrl+q; wait");
    if (out.empty()) GTEST_SKIP() << "no editor window in this build or no X server";
    const nlohmann::json report = nlohmann::json::parse(out);
    EXPECT_LT(report["seconds"].get<double>(), 89.0) << "Ctrl+Q was not seen";
    const nlohmann::json before = nlohmann::json::parse(test::readFile(dir / "before.json"));
    const nlohmann::json zoomed = nlohmann::json::parse(test::readFile(dir / "zoomed.json"));
    const nlohmann::json panned = nlohmann::json::parse(test::readFile(dir / "panned.json"));
    ASSERT_TRUE(before.contains("uv_under_mouse"))
        << "the point is not over the UV view: " << before.dump();
    EXPECT_EQ(before["uv_zoom"].get<double>(), 1.0);
    // The view's long tooltip is up, wrapped inside the window (one line of it was 1109 px).
    ASSERT_TRUE(before.contains("tooltip_rect")) << before.dump();
    EXPECT_GE(before["tooltip_rect"][0].get<int>(), 0);
    EXPECT_LE(before["tooltip_rect"][0].get<int>() + before["tooltip_rect"][2].get<int>(), 800);
    EXPECT_NEAR(before["uv_under_mouse"][0].get<double>(), 25.0 / 102, 0.02);
    EXPECT_NEAR(before["uv_under_mouse"][1].get<double>(), 1 - 25.0 / 102, 0.02);
    EXPECT_EQ(zoomed["uv_zoom"].get<double>(), 1.5625);
    EXPECT_NEAR(zoomed["uv_under_mouse"][0].get<double>(),
                before["uv_under_mouse"][0].get<double>(), 1e-4);
    EXPECT_NEAR(zoomed["uv_under_mouse"][1].get<double>(),
                before["uv_under_mouse"][1].get<double>(), 1e-4);
    EXPECT_NEAR(panned["uv_under_mouse"][0].get<double>(),
                before["uv_under_mouse"][0].get<double>() + 40.0 / (102 * 1.5625), 0.01);
    EXPECT_NEAR(panned["uv_under_mouse"][1].get<double>(),
                before["uv_under_mouse"][1].get<double>(), 1e-4);
    EXPECT_EQ(report["undo_steps"], 0);  // navigation edits nothing
}

TEST(EditorWindow, CameraFollowsTheBodyInThePreview) {
    // The camera can follow a body. The ball, dropped from 0.3 m, bobs;
    // with C pressed the view's centre is the ball's centre of mass in every frame after, the
    // last one included (the report's camera and body are that frame's).
    if (!haveWindowTools(true)) GTEST_SKIP() << "xvfb-run or xdotool is not installed";
    const fs::path project = ballProject("window_follow", 0.3);
    const fs::path dir = project.parent_path();
    const std::string frameNow = "$(sed \"s/.*\\\"frame\\\":\\([0-9]*\\).*/\\1/\" state.json)";
    const std::string out = runUnderXvfb(
        dir,
        "$PLIMSOLL edit ball.plim.json --preview --run-seconds 90 --window-size 800x500 "
        "--state-file state.json & " +
            kWaitForState + waitFor("\"name\":\"Live preview\"") + "cp state.json before.json; " +
            "xdotool key --window $w c; f0=" + frameNow + "; i=0; until [ " + frameNow +
            " -ge $((f0 + 30)) ] || [ $i -gt 600 ]; do i=$((i+1)); sleep 0.05; done; "
            "xdotool key --window $w ctrl+q; wait");
    if (out.empty()) GTEST_SKIP() << "no editor window in this build or no X server";
    const nlohmann::json report = nlohmann::json::parse(out);
    EXPECT_LT(report["seconds"].get<double>(), 89.0) << "Ctrl+Q was not seen";
    ASSERT_TRUE(report.contains("preview")) << report.dump();
    const nlohmann::json before = nlohmann::json::parse(test::readFile(dir / "before.json"));
    const nlohmann::json& target = report["preview"]["camera"]["target"];
    const nlohmann::json& com = report["preview"]["bodies"][0]["center_of_mass"];
    for (int k = 0; k < 3; ++k)
        EXPECT_DOUBLE_EQ(target[k].get<double>(), com[k].get<double>()) << k;
    // Framed before (the ball's place in the project, 0.3 m up), on the moving ball after.
    EXPECT_NEAR(before["camera_target"][1].get<double>(), 0.3, 1e-6);
    EXPECT_GT(std::abs(com[1].get<double>() - 0.3), 1e-3) << "the ball should have moved";
}

TEST(EditorWindow, WaterChangedInThePreviewIsKeptInTheProject) {
    // Water and wave edits made in the preview could not be kept. At 800 x 500
    // the Live preview window's Water section opens at (60, 365); its "level (m)" field, dragged
    // 20 px right (0.01 m a pixel), raises the preview's water 0.2 m; "Keep in project" makes
    // that one undoable project edit, and Ctrl+S saves it. (The script's text has no
    // apostrophe: it runs inside sh -c '...'.)
    if (!haveWindowTools(true)) GTEST_SKIP() << "xvfb-run or xdotool is not installed";
    const fs::path project = ballProject("window_keep_water", 0.3);
    const fs::path dir = project.parent_path();
    const std::string out = runUnderXvfb(
        dir,
        "$PLIMSOLL edit ball.plim.json --preview --run-seconds 90 --window-size 800x500 "
        "--state-file state.json & " +
            kWaitForState + waitFor("\"name\":\"Live preview\"") + clickAt(60, 365) +
            moveTo(125, 411) + waitFor("\"tooltip\":\"The still-water height") +
            "xdotool mousedown 1; " + waitFor("\"held\":\"Live preview\"") + moveTo(135, 411) +
            moveTo(145, 411) + "xdotool mouseup 1; " + waitFor("\"held\":\"\"") + moveTo(72, 434) +
            waitFor("\"tooltip\":\"Write these water") + clickAt(72, 434) +
            waitFor("\"undo\":\"Keep the preview") + "xdotool key --window $w ctrl+s; " +
            waitFor("\"dirty\":false") + "xdotool key --window $w ctrl+q; wait");
    if (out.empty()) GTEST_SKIP() << "no editor window in this build or no X server";
    const nlohmann::json report = nlohmann::json::parse(out);
    EXPECT_LT(report["seconds"].get<double>(), 89.0) << "Ctrl+Q was not seen (unsaved?)";
    EXPECT_EQ(report["undo"], "Keep the preview's water");
    EXPECT_EQ(report["undo_steps"], 1);
    Result<Project> saved = loadProject(project);
    ASSERT_TRUE(saved.ok()) << saved.error().message;
    EXPECT_NEAR(saved->water.level, 0.2, 1e-6);
}

TEST(EditorWindow, SaveAsTakesATypedNameAndLeavesTheOriginalAsItWas) {
    // Ctrl+Shift+S opens Save As with
    // the name field holding the keys and the project's own name in it, selected (not
    // "untitled"); typing replaces it and Enter saves there. The title follows the new file;
    // the original is untouched.
    if (!haveWindowTools(true)) GTEST_SKIP() << "xvfb-run or xdotool is not installed";
    const fs::path project = ballProject("window_save_as");
    const std::string original = test::readFile(project);
    const std::string out = runUnderXvfb(
        project.parent_path(),
        "$PLIMSOLL edit ball.plim.json --run-seconds 60 --window-size 800x500 --state-file "
        "state.json & " +
            kWaitForState + "xdotool key --window $w ctrl+shift+s; " +
            waitFor("\"popup\":\"Save project as\"") +
            // ImGui 1.86 has no input queue (a frame sees all its keys and characters at once):
            // a pause lets the last letters reach the field in a frame before Enter's.
            "xdotool type --window $w --delay 40 copy.plim.json; sleep 0.3; "
            "xdotool key --window $w Return; " +
            waitFor("\"title\":\"copy.plim.json - Plimsoll\"") +
            "xdotool key --window $w ctrl+q; wait");
    if (out.empty()) GTEST_SKIP() << "no editor window in this build or no X server";
    const nlohmann::json report = nlohmann::json::parse(out);
    const fs::path copy = project.parent_path() / "copy.plim.json";
    EXPECT_EQ(report["title"], "copy.plim.json - Plimsoll") << report.dump();
    EXPECT_NE(report["status"].get<std::string>().find("Saved"), std::string::npos)
        << report["status"];
    ASSERT_TRUE(fs::exists(copy)) << report.dump();
    Result<Project> saved = loadProject(copy);
    ASSERT_TRUE(saved.ok()) << saved.error().message;
    ASSERT_EQ(saved->bodies.size(), 1u);
    EXPECT_EQ(saved->bodies[0].name, "ball");
    EXPECT_EQ(test::readFile(project), original);
}

TEST(EditorWindow, SaveAsOfANewProjectNamesItAfterTheFile) {
    // Save As kept a new project's name "untitled". Started with no project, Ctrl+Shift+S and
    // "harbour.plim.json": the saved project is called harbour.
    if (!haveWindowTools(true)) GTEST_SKIP() << "xvfb-run or xdotool is not installed";
    const fs::path dir = ballProject("window_save_as_new").parent_path();
    const std::string out = runUnderXvfb(
        dir, "$PLIMSOLL edit --run-seconds 60 --window-size 800x500 --state-file state.json & " +
                 kWaitForState + "xdotool key --window $w ctrl+shift+s; " +
                 waitFor("\"popup\":\"Save project as\"") +
                 "xdotool type --window $w --delay 40 harbour.plim.json; sleep 0.3; xdotool key "
                 "--window $w Return; " +
                 waitFor("\"title\":\"harbour.plim.json - Plimsoll\"") +
                 "xdotool key --window $w ctrl+q; wait");
    if (out.empty()) GTEST_SKIP() << "no editor window in this build or no X server";
    // A project of no bodies, which loadProject refuses to simulate: its JSON read as it is.
    ASSERT_TRUE(fs::exists(dir / "harbour.plim.json")) << out;
    const nlohmann::json saved = nlohmann::json::parse(test::readFile(dir / "harbour.plim.json"));
    EXPECT_EQ(saved["name"], "harbour");
}

/// The ball's project with a saved permeability map of `value` everywhere (64 x 64, written by
/// a headless edit script, as a user's earlier session would have), and a settings file whose
/// Tools panel takes most of the column: at 1200 x 780 Fill all and New map are then on screen
/// at (839, 377) and (907, 377), Strength at (937, 170) (below the brush preset row).
fs::path ballWithSavedPaint(const std::string& name, double value) {
    const fs::path project = ballProject(name);
    const fs::path script = project.parent_path() / "paint.json";
    std::ofstream(script)
        << R"([{"op": "new_map", "channel": "permeability", "size": 64, "value": )" << value
        << "}]";
    const test::CommandOutput run =
        test::runPlimsoll("edit '" + project.string() + "' --script '" + script.string() + "'");
    EXPECT_EQ(run.exitCode, 0) << run.err;
    fs::create_directories(project.parent_path() / "config" / "plimsoll");
    std::ofstream(project.parent_path() / "config" / "plimsoll" / "settings.json")
        << R"({"layout": {"column_width": 400, "shares": [0.7, 0.1, 0.1, 0.1]}})";
    return project;
}

/// The body's saved permeability map.
PaintedMap savedPermeability(const fs::path& project) {
    Result<Project> saved = loadProject(project);
    EXPECT_TRUE(saved.ok()) << saved.error().message;
    if (!saved.ok() || saved->bodies.empty()) return {};
    Result<PaintedMap> map = loadPaintedMap(saved->resolvePath(saved->bodies[0].permeabilityMap));
    EXPECT_TRUE(map.ok()) << map.error().message;
    return map.ok() ? *map : PaintedMap{};
}

/// How many of the map's values are within `tolerance` of `value`.
std::size_t countNear(const PaintedMap& map, double value, double tolerance) {
    return static_cast<std::size_t>(
        std::count_if(map.values.begin(), map.values.end(),
                      [&](float v) { return std::abs(v - value) <= tolerance; }));
}

TEST(EditorWindow, StrokeSmallerThanAPixelPaintsAContinuousLine) {
    // A drag along the damaged boat's side with the default 0.05 m brush painted a few blobs:
    // the 128 x 128 map's pixels there are 5 to 7 cm of hull, and a pixel got paint only where
    // the stroke passed within the brush's radius of its centre. A brush paints every pixel
    // whose surface it reaches: the stroke's pixels in the saved map are one unbroken line.
    if (!haveWindowTools(true)) GTEST_SKIP() << "xvfb-run or xdotool is not installed";
    const fs::path project = damagedBoatCopy("window_thin_stroke");
    const fs::path dir = project.parent_path();
    Result<PaintedMap> original =
        loadPaintedMap(dir.parent_path() / "assets" / "hull_stern_damage.png");
    ASSERT_TRUE(original.ok()) << original.error().message;
    // 1200 x 780, the default perspective view: the hull's near side runs from the bow at
    // about (200, 505) up to the stern at (560, 370); the drag follows its middle.
    std::vector<std::pair<int, int>> path;
    for (int i = 0; i <= 10; ++i) path.emplace_back(220 + 20 * i, 500 - 15 * i / 2);
    const std::string out = runUnderXvfb(
        dir,
        "$PLIMSOLL edit damaged_boat.plim.json --run-seconds 60 --window-size 1200x780 "
        "--state-file state.json & " +
            kWaitForState + "xdotool key --window $w b; " + waitFor("\"tool\":1") +
            dragThrough(path) + waitFor("\"undo\":\"Paint permeability\"") +
            "xdotool key --window $w ctrl+s; " + waitFor("\"dirty\":false") +
            "xdotool key --window $w ctrl+q; wait");
    if (out.empty()) GTEST_SKIP() << "no editor window in this build or no X server";
    const nlohmann::json report = nlohmann::json::parse(out);
    EXPECT_LT(report["seconds"].get<double>(), 59.0) << "Ctrl+Q was not seen (unsaved?)";
    EXPECT_EQ(report["undo_steps"], 1);
    const PaintedMap map = savedPermeability(project);
    ASSERT_EQ(map.width, original->width);
    ASSERT_EQ(map.values.size(), original->values.size());
    std::vector<char> painted(map.values.size(), 0);
    std::size_t count = 0;
    for (std::size_t p = 0; p < map.values.size(); ++p) {
        painted[p] = map.values[p] > original->values[p] + 0.5f;
        count += painted[p];
    }
    // 220 px of drag over about 2 m of hull: some 30 pixels along, at least one across.
    EXPECT_GT(count, 25u);
    EXPECT_EQ(connectedPieces(painted, map.width, map.height), 1) << count << " pixels painted";
}

TEST(EditorWindow, NewMapOverSavedPaintAsksAndUndoBringsTheSavedPaintBack) {
    // On a project with saved paint, New map wiped the map without
    // asking; Undo named the step but the map stayed gone, and one stroke and Ctrl+S then
    // wrote a blank map plus that stroke over the saved PNG. Here New map asks first
    // ("Replace map?"); Replace, then Ctrl+Z, gives the saved map back (the project is clean
    // again); a stroke across the ball and Ctrl+S save the 64 x 64 map of 0.6 with that stroke
    // on it, not a blank 1024 x 1024 one.
    if (!haveWindowTools(true)) GTEST_SKIP() << "xvfb-run or xdotool is not installed";
    const fs::path project = ballWithSavedPaint("window_new_map", 0.6);
    const fs::path dir = project.parent_path();
    ASSERT_EQ(countNear(savedPermeability(project), 0.6, 0.003), 64u * 64u);
    // The ball's centre is at (400, 388) of the 1200 x 780 window in the front view, 178 px
    // across its radius: the stroke runs over its middle.
    const std::string stroke = "xdotool key --window $w b; " + waitFor("\"tool\":1") +
                               dragAlong(388, {340, 370, 400, 430, 460}) +
                               waitFor("\"undo\":\"Paint permeability\"");
    const std::string out = runUnderXvfb(
        dir,
        "$PLIMSOLL edit ball.plim.json --run-seconds 90 --window-size 1200x780 --view front "
        "--state-file state.json & " +
            kWaitForState + clickAt(907, 377) + waitFor("\"popup\":\"Replace map?\"") +
            "cp state.json asked.json; " + moveTo(340, 416) +
            waitFor("\"tooltip\":\"Replaces the map with a blank one") + clickAt(340, 416) +
            waitFor("\"undo\":\"New permeability map\"") + "cp state.json replaced.json; " +
            "xdotool key --window $w ctrl+z; " + waitFor("\"dirty\":false") + stroke +
            "xdotool key --window $w ctrl+s; " + waitFor("\"dirty\":false") +
            "xdotool key --window $w ctrl+q; wait");
    if (out.empty()) GTEST_SKIP() << "no editor window in this build or no X server";
    const nlohmann::json report = nlohmann::json::parse(out);
    EXPECT_LT(report["seconds"].get<double>(), 89.0) << "Ctrl+Q was not seen (unsaved?)";
    const nlohmann::json asked = nlohmann::json::parse(test::readFile(dir / "asked.json"));
    EXPECT_EQ(asked["popup"], "Replace map?");
    EXPECT_EQ(asked["dirty"], false) << "the question changed nothing yet";
    const nlohmann::json replaced = nlohmann::json::parse(test::readFile(dir / "replaced.json"));
    EXPECT_EQ(replaced["dirty"], true);
    EXPECT_EQ(replaced["popup"], "");
    EXPECT_EQ(report["undo"], "Paint permeability");
    EXPECT_EQ(report["undo_steps"], 1) << "the undone New map is off the stack";
    const PaintedMap map = savedPermeability(project);
    ASSERT_EQ(map.width, 64) << "the blank 1024 x 1024 map was saved";
    ASSERT_EQ(map.height, 64);
    // The stroke covers a band of the ball; the rest keeps the saved 0.6 (0 when it was lost).
    const std::size_t kept = countNear(map, 0.6, 0.003);
    EXPECT_GT(kept, 64u * 64u * 3 / 4) << "the saved paint is gone";
    EXPECT_LT(kept, 64u * 64u) << "the stroke is not in the saved map";
    // The stroke's texels moved toward 1 (a 64 x 64 map's texel centres lie up to 0.012 m off
    // the stroke's line: 0.95 there under the smooth falloff).
    EXPECT_GT(countNear(map, 0.85, 0.15), 0u) << "the stroke is not in the saved map";
}

TEST(EditorWindow, FillMovesByStrengthAndFillIslandSaysTheMeshIsOneIsland) {
    // Fill ignored Strength; on a single-island map Fill island flooded the
    // whole mesh without saying why. Strength typed as 0.5 (Ctrl-click on its slider), Fill
    // all moves every texel of the saved 0.6 half way to Value 1: 0.8, not 1. Fill island (G,
    // a click on the ball) names the step after the reason it covers everything: the sphere's
    // UVs are one island.
    if (!haveWindowTools(true)) GTEST_SKIP() << "xvfb-run or xdotool is not installed";
    const fs::path project = ballWithSavedPaint("window_fill", 0.6);
    const fs::path dir = project.parent_path();
    const std::string out = runUnderXvfb(
        dir,
        "$PLIMSOLL edit ball.plim.json --run-seconds 90 --window-size 1200x780 --view front "
        "--state-file state.json & " +
            kWaitForState + moveTo(937, 170) + waitFor("\"tooltip\":\"How far one stroke") +
            "xdotool keydown ctrl; xdotool mousedown 1; " + waitFor("\"mouse_down\":true") +
            "xdotool mouseup 1; xdotool keyup ctrl; " + waitFor("\"held\":\"Tools\"") +
            // The field's text is selected: typing replaces it. Enter is held until a
            // frame has taken it (ImGui 1.86 misses a tap shorter than a frame).
            "xdotool type --window $w 0.5; xdotool keydown --window $w Return; " +
            waitFor("\"held\":\"\"") + "xdotool keyup --window $w Return; " +
            waitFor("\"brush_strength\":0.5") + moveTo(839, 377) +
            waitFor("\"tooltip\":\"Moves every pixel") + clickAt(839, 377) +
            waitFor("\"undo\":\"Fill permeability\"") + "xdotool key --window $w g; " +
            waitFor("\"tool\":2") + clickAt(400, 388) + waitFor("one UV island") +
            "cp state.json island.json; xdotool key --window $w ctrl+z; " +
            waitFor("\"undo\":\"Fill permeability\"") + "xdotool key --window $w ctrl+s; " +
            waitFor("\"dirty\":false") + "xdotool key --window $w ctrl+q; wait");
    if (out.empty()) GTEST_SKIP() << "no editor window in this build or no X server";
    const nlohmann::json report = nlohmann::json::parse(out);
    EXPECT_LT(report["seconds"].get<double>(), 89.0) << "Ctrl+Q was not seen (unsaved?)";
    const nlohmann::json island = nlohmann::json::parse(test::readFile(dir / "island.json"));
    EXPECT_EQ(island["undo"], "Fill island permeability (the mesh is one UV island: all of it)");
    EXPECT_EQ(report["undo"], "Fill permeability");
    EXPECT_EQ(report["undo_steps"], 1);
    const PaintedMap map = savedPermeability(project);
    ASSERT_EQ(map.values.size(), 64u * 64u);
    // 0.6 + 0.5 (1 - 0.6), within the PNG's rounding.
    EXPECT_EQ(countNear(map, 0.8, 0.003), 64u * 64u)
        << "first texel " << map.values[0] << " (1 when Strength was ignored)";
}

TEST(EditorWindow, ExportWithUnsavedPaintAsksAndSaveAndExportWritesWhatIsOnScreen) {
    // Export wrote the last save, not what was on screen, and only a log line
    // said so. A stroke on the saved 0.6 map, then File > Export bundle... > Export here: the
    // editor asks ("Export unsaved changes?"); Save and export saves, then the bundle's
    // permeability image holds the stroke (the last save had none of it). At 800 x 500 the
    // menu item is at (60, 140), Export here at (130, 425), Save and export at (193, 267).
    if (!haveWindowTools(true)) GTEST_SKIP() << "xvfb-run or xdotool is not installed";
    const fs::path project = ballWithSavedPaint("window_export", 0.6);
    const fs::path dir = project.parent_path();
    fs::remove(dir / "config" / "plimsoll" / "settings.json");  // the default layout
    // The ball at (240, 248) of the 800 x 500 front view, about 110 px across its radius.
    const std::string stroke = "xdotool key --window $w b; " + waitFor("\"tool\":1") +
                               dragAlong(248, {200, 220, 240, 260, 280}) +
                               waitFor("\"undo\":\"Paint permeability\"");
    const std::string out = runUnderXvfb(
        dir,
        "$PLIMSOLL edit ball.plim.json --run-seconds 90 --window-size 800x500 --view front "
        "--state-file state.json & " +
            kWaitForState + stroke + clickAt(25, 9) + clickAt(60, 140) +
            waitFor("\"popup\":\"Export to folder\"") + clickAt(130, 425) +
            waitFor("\"popup\":\"Export unsaved changes?\"") + "cp state.json asked.json; " +
            moveTo(193, 267) + waitFor("\"tooltip\":\"Saves the project, then exports") +
            clickAt(193, 267) + waitFor("\"dirty\":false") +
            "i=0; until [ -s ball/ball/manifest.json ] || [ $i -gt 600 ]; do i=$((i+1)); sleep "
            "0.05; done; "
            "xdotool key --window $w ctrl+q; wait");
    if (out.empty()) GTEST_SKIP() << "no editor window in this build or no X server";
    const nlohmann::json report = nlohmann::json::parse(out);
    EXPECT_LT(report["seconds"].get<double>(), 89.0) << "Ctrl+Q was not seen (unsaved?)";
    const nlohmann::json asked = nlohmann::json::parse(test::readFile(dir / "asked.json"));
    EXPECT_EQ(asked["popup"], "Export unsaved changes?");
    EXPECT_EQ(asked["dirty"], true);
    ASSERT_TRUE(fs::exists(dir / "ball" / "ball" / "manifest.json")) << report.dump();
    // The saved map and the bundle's image both hold the stroke: texels near 1 beside the 0.6.
    EXPECT_GT(countNear(savedPermeability(project), 0.85, 0.15), 0u);
    int width = 0, height = 0, channels = 0;
    unsigned char* data = stbi_load((dir / "ball" / "ball" / "permeability.png").c_str(), &width,
                                    &height, &channels, 1);
    ASSERT_TRUE(data) << stbi_failure_reason();
    std::vector<unsigned char> grey(data, data + static_cast<std::size_t>(width) * height);
    stbi_image_free(data);
    const auto painted =
        std::count_if(grey.begin(), grey.end(), [](unsigned char v) { return v >= 0.7 * 255; });
    const auto base = std::count_if(grey.begin(), grey.end(),
                                    [](unsigned char v) { return std::abs(v - 153) <= 1; });
    EXPECT_GT(painted, 0) << "the bundle was made from the last save, without the stroke";
    EXPECT_GT(base, static_cast<long>(grey.size()) / 10) << "the saved 0.6 is not in the bundle";
}

TEST(EditorWindow, ExportWindowShowsTheResultWithoutInputAndTheExportsOwnDuration) {
    // The export window stayed on "Exporting..." with Close greyed out until the mouse moved
    // (the idle frame loop slept through the worker's end), then gave the time until that
    // frame as the export's ("Done: 1 bundles in 64.8 s" for 0.16 s of work). Here nothing is
    // touched after Export here: the result appears by itself, timed by the worker.
    if (!haveWindowTools(true)) GTEST_SKIP() << "xvfb-run or xdotool is not installed";
    const fs::path project = ballProject("window_export_done");
    const fs::path dir = project.parent_path();
    const std::string out = runUnderXvfb(
        dir,
        "$PLIMSOLL edit ball.plim.json --run-seconds 60 --window-size 800x500 --view front "
        "--state-file state.json & " +
            kWaitForState + clickAt(25, 9) + clickAt(60, 140) +
            waitFor("\"popup\":\"Export to folder\"") + clickAt(130, 425) + "sleep 2; " +
            waitFor("\"export\":\"Done: 1 bundle in") +
            "cp state.json done.json; xdotool key --window $w ctrl+q; wait");
    if (out.empty()) GTEST_SKIP() << "no editor window in this build or no X server";
    ASSERT_TRUE(fs::exists(dir / "ball" / "ball" / "manifest.json"));
    const nlohmann::json done = nlohmann::json::parse(test::readFile(dir / "done.json"));
    const std::string status = done["export"].get<std::string>();
    ASSERT_EQ(status.rfind("Done: 1 bundle in ", 0), 0u) << status;
    // The worker's time: the 2 s the test waited before looking are not in it. The export
    // includes the ball's radiation panel solve (on by default: 0.2 to 0.3 s of CPU, 1.9 s of
    // wall time measured on a loaded two-core machine), so the bound is the wait itself.
    EXPECT_LT(std::stod(status.substr(std::string("Done: 1 bundle in ").size())), 2.0) << status;
}

TEST(EditorWindow, OpenedPlotWindowsPushTheOnesBelowDownInsteadOfHidingUnderThem) {
    // Expanding "Submerged volume" drew the folded Heel / Forces / Water headers over its plot
    // and its Export CSV (the windows sat 30 px apart whatever their size). Now the stack
    // reflows: at 800 x 500 the folded titles are at y 49 and 72 (arrows at x 162); the second
    // is opened, then the first, and the second lies wholly below the first.
    if (!haveWindowTools(true)) GTEST_SKIP() << "xvfb-run or xdotool is not installed";
    const fs::path project = ballProject("window_plot_stack", 0.3);
    const fs::path dir = project.parent_path();
    const std::string out = runUnderXvfb(
        dir,
        "$PLIMSOLL edit ball.plim.json --preview --run-seconds 60 --window-size 800x500 "
        "--state-file state.json & " +
            kWaitForState + waitFor("\"name\":\"Live preview\"") + "sleep 0.5; " +
            clickAt(162, 81) + waitFor("\"name\":\"Heel and trim: ball\"") + clickAt(162, 58) +
            waitFor("\"name\":\"Submerged volume: ball\"") +
            "sleep 0.3; cp state.json both.json; "
            "xdotool key --window $w ctrl+q; wait");
    if (out.empty()) GTEST_SKIP() << "no editor window in this build or no X server";
    const nlohmann::json both = nlohmann::json::parse(test::readFile(dir / "both.json"));
    const std::vector<int> volume = windowRect(both, "Submerged volume: ball");
    const std::vector<int> heel = windowRect(both, "Heel and trim: ball");
    ASSERT_EQ(volume.size(), 4u) << both.dump();
    ASSERT_EQ(heel.size(), 4u) << both.dump();
    EXPECT_GE(heel[1], volume[1] + volume[3]) << "the second plot window lies over the first";
}

TEST(EditorWindow, PlotCsvExportedFromTheWindowStartsWithTheFirstFramesVolume) {
    // The exported plot CSV started with a wrong row (submerged volume 0 at
    // t = 0). The ball (r = 0.5 m) dropped from 0.3 m in the live preview; its Submerged
    // volume window opened (a click on its arrow at (162, 58) at 800 x 500) and its Export CSV
    // (196, 149) clicked: the file's first row is the first simulated frame, one time step in,
    // with the cap's volume pi h^2 (3 r - h) / 3 for h = 0.2 m, and times rise row by row.
    if (!haveWindowTools(true)) GTEST_SKIP() << "xvfb-run or xdotool is not installed";
    const fs::path project = ballProject("window_plot_csv", 0.3);
    const fs::path dir = project.parent_path();
    const fs::path csv = dir / "Submerged_volume__ball.csv";
    const std::string out = runUnderXvfb(
        dir,
        "$PLIMSOLL edit ball.plim.json --preview --run-seconds 90 --window-size 800x500 "
        "--state-file state.json & " +
            kWaitForState + waitFor("\"name\":\"Live preview\"") + clickAt(162, 58) +
            waitFor("\"name\":\"Submerged volume: ball\"") + moveTo(196, 149) +
            waitFor("\"tooltip\":\"Writes these series") + clickAt(196, 149) +
            "i=0; until [ -s Submerged_volume__ball.csv ] || [ $i -gt 600 ]; do i=$((i+1)); sleep "
            "0.05; done; "
            "xdotool key --window $w ctrl+q; wait");
    if (out.empty()) GTEST_SKIP() << "no editor window in this build or no X server";
    const nlohmann::json report = nlohmann::json::parse(out);
    EXPECT_LT(report["seconds"].get<double>(), 89.0) << "Ctrl+Q was not seen";
    ASSERT_TRUE(fs::exists(csv)) << report.dump();
    std::ifstream in(csv);
    std::string header, line;
    std::getline(in, header);
    EXPECT_EQ(header, "time (s),\"ball submerged volume (m^3)\"");
    Result<Project> loaded = loadProject(project);
    ASSERT_TRUE(loaded.ok()) << loaded.error().message;
    const double cap = 3.14159265358979 * 0.04 * (1.5 - 0.2) / 3.0;
    std::size_t rows = 0;
    double lastTime = 0;
    while (std::getline(in, line)) {
        double t = -1, v = -1;
        ASSERT_EQ(std::sscanf(line.c_str(), "%lf,%lf", &t, &v), 2) << line;
        if (rows == 0) {
            EXPECT_NEAR(t, loaded->simulation.timeStep, 1e-9) << "first row: " << line;
            // Within a frame the ball sinks ~1 mm; the faceted sphere and the bake a few %.
            EXPECT_NEAR(v, cap, 0.06 * cap) << "first row: " << line;
        } else {
            EXPECT_GT(t, lastTime) << line;
        }
        lastTime = t;
        ++rows;
    }
    EXPECT_GE(rows, 2u);
}

TEST(EditorWindow, FAndShiftFDragTheBrushRadiusAndStrengthAsInBlender) {
    // Drag-to-resize radius and strength (Blender's F and Shift+F). With the
    // Brush, F puts the control's centre 100 px left of the mouse (the radius in use); moving
    // the mouse to 150 px from it makes the radius 1.5 times as large, and the click that keeps
    // it paints nothing. Shift+F: strength is the distance over 200 px; Esc puts it back,
    // Enter keeps it. With Navigate, F still frames the selection (no control comes up).
    if (!haveWindowTools(true)) GTEST_SKIP() << "xvfb-run or xdotool is not installed";
    const fs::path project = ballProject("window_radial");
    const fs::path dir = project.parent_path();
    const std::string out = runUnderXvfb(
        dir,
        "$PLIMSOLL edit ball.plim.json --run-seconds 90 --window-size 800x500 --view front "
        "--state-file state.json & " +
            kWaitForState + moveTo(200, 250) + "xdotool key --window $w f b; " +
            waitFor("\"tool\":1") + "cp state.json before.json; xdotool key --window $w f; " +
            waitFor("\"radial_control\":\"radius\"") + moveTo(250, 250) +
            "cp state.json radius_live.json; " + "xdotool click 1; " +
            waitFor("\"radial_control\":\"\"") + "cp state.json radius.json; " +
            "xdotool key --window $w shift+f; " + waitFor("\"radial_control\":\"strength\"") +
            moveTo(150, 250) +
            "cp state.json strength_live.json; xdotool key --window $w Escape; " +
            waitFor("\"radial_control\":\"\"") + "cp state.json cancelled.json; " +
            "xdotool key --window $w shift+f; " + waitFor("\"radial_control\":\"strength\"") +
            moveTo(50, 250) + "xdotool key --window $w Return; " +
            waitFor("\"radial_control\":\"\"") + "xdotool key --window $w ctrl+q; wait");
    if (out.empty()) GTEST_SKIP() << "no editor window in this build or no X server";
    const nlohmann::json report = nlohmann::json::parse(out);
    EXPECT_LT(report["seconds"].get<double>(), 89.0) << "Ctrl+Q was not seen";
    auto state = [&](const char* name) {
        return nlohmann::json::parse(test::readFile(dir / name));
    };
    const nlohmann::json before = state("before.json");
    EXPECT_EQ(before["radial_control"], "") << "F with Navigate opened the brush control";
    const double radius = before["brush_radius"].get<double>();
    ASSERT_GT(radius, 0.0);
    EXPECT_EQ(state("radius_live.json")["radial_control"], "radius");
    EXPECT_NEAR(state("radius_live.json")["brush_radius"].get<double>(), 1.5 * radius, 1e-9);
    EXPECT_NEAR(state("radius.json")["brush_radius"].get<double>(), 1.5 * radius, 1e-9);
    EXPECT_NEAR(state("strength_live.json")["brush_strength"].get<double>(), 0.5, 1e-9);
    EXPECT_EQ(state("cancelled.json")["brush_strength"].get<double>(), 1.0) << "Esc did not cancel";
    // After the cancel the control started at strength 1 again: its centre 200 px left of
    // (150, 250); at (50, 250) the distance is 100 px.
    EXPECT_NEAR(report["last_frame"]["brush_strength"].get<double>(), 0.5, 1e-9);
    EXPECT_NEAR(report["last_frame"]["brush_radius"].get<double>(), 1.5 * radius, 1e-9);
    EXPECT_EQ(report["undo_steps"], 0) << "the click that kept the radius painted";
}

/// The Inspector's "Add body..." button at 1200 x 780 (the default layout).
constexpr int kAddBodyX = 840, kAddBodyY = 497;

TEST(EditorWindow, AddBodyFromTheInspectorIsOneUndoStep) {
    // Add bodies. The Inspector's "Add body..." opens the mesh browser; a
    // typed path and Enter add the box as a second body (selected); Ctrl+Z takes it out again,
    // back to the saved project (clean), and Ctrl+Shift+Z puts it back.
    if (!haveWindowTools(true)) GTEST_SKIP() << "xvfb-run or xdotool is not installed";
    const fs::path project = ballProject("window_add_body");
    const fs::path dir = project.parent_path();
    const std::string box = test::assetPath("box.obj").string();
    const std::string out = runUnderXvfb(
        dir,
        "$PLIMSOLL edit ball.plim.json --run-seconds 90 --window-size 1200x780 "
        "--state-file state.json & " +
            kWaitForState + moveTo(kAddBodyX, kAddBodyY) + waitFor("\"tooltip\":\"Adds a body") +
            clickAt(kAddBodyX, kAddBodyY) + waitFor("\"popup\":\"Import mesh\"") +
            waitFor("\"held\":\"Import mesh\"") +  // the name field has the keys
            "xdotool type --window $w --delay 20 " + box + "; " +
            // Enter held until a frame has taken it: ImGui 1.86 misses a shorter tap.
            "xdotool keydown --window $w Return; " + waitFor("\"bodies\":2") +
            "xdotool keyup --window $w Return; " + waitFor("\"popup\":\"\"") +
            "cp state.json added.json; xdotool key --window $w ctrl+z; " + waitFor("\"bodies\":1") +
            "cp state.json undone.json; xdotool key --window $w ctrl+shift+z; " +
            waitFor("\"bodies\":2") +
            "cp state.json redone.json; xdotool key --window $w ctrl+z; " +
            waitFor("\"bodies\":1") + "xdotool key --window $w ctrl+q; wait");
    if (out.empty()) GTEST_SKIP() << "no editor window in this build or no X server";
    const nlohmann::json report = nlohmann::json::parse(out);
    EXPECT_LT(report["seconds"].get<double>(), 89.0) << "Ctrl+Q was not seen (unsaved?)";
    auto state = [&](const char* name) {
        return nlohmann::json::parse(test::readFile(dir / name));
    };
    const nlohmann::json added = state("added.json");
    EXPECT_EQ(added["undo"], "Import box.obj");
    EXPECT_EQ(added["selected_body"], 1);
    EXPECT_EQ(added["dirty"], true);
    EXPECT_EQ(state("undone.json")["dirty"], false);
    EXPECT_EQ(state("redone.json")["bodies"], 2);
    EXPECT_EQ(report["last_frame"]["bodies"], 1);
    EXPECT_EQ(report["last_frame"]["dirty"], false);
    // Nothing was saved: the project on disk still has the ball alone.
    Result<Project> saved = loadProject(project);
    ASSERT_TRUE(saved.ok()) << saved.error().message;
    EXPECT_EQ(saved->bodies.size(), 1u);
}

TEST(EditorWindow, InspectorPositionFieldMovesTheBodyAsOneUndoStep) {
    // Body transforms editable in the inspector. At 1200 x 780 the
    // Inspector's Position x field is at (812..892, 521); a click past its "0" puts the cursor
    // at the end, "5" and Enter make x = 5 m: one step, "Move ball", that undoes to the saved
    // project (clean) and redoes; Ctrl+S saves the new place.
    if (!haveWindowTools(true)) GTEST_SKIP() << "xvfb-run or xdotool is not installed";
    const fs::path project = ballProject("window_move_body");
    const fs::path dir = project.parent_path();
    const std::string out = runUnderXvfb(
        dir,
        "$PLIMSOLL edit ball.plim.json --run-seconds 90 --window-size 1200x780 "
        "--state-file state.json & " +
            kWaitForState + moveTo(870, 521) + waitFor("\"tooltip\":\"Where the body starts") +
            clickAt(870, 521) + waitFor("\"held\":\"Inspector\"") +
            // Enter held until a frame has taken it: ImGui 1.86 misses a shorter tap.
            "xdotool type --window $w 5; xdotool keydown --window $w Return; " +
            waitFor("\"undo\":\"Move ball\"") + "xdotool keyup --window $w Return; " +
            "cp state.json moved.json; xdotool key --window $w ctrl+z; " +
            waitFor("\"dirty\":false") +
            "cp state.json undone.json; xdotool key --window $w ctrl+shift+z; " +
            waitFor("\"undo\":\"Move ball\"") + "xdotool key --window $w ctrl+s; " +
            waitFor("\"dirty\":false") + "xdotool key --window $w ctrl+q; wait");
    if (out.empty()) GTEST_SKIP() << "no editor window in this build or no X server";
    const nlohmann::json report = nlohmann::json::parse(out);
    EXPECT_LT(report["seconds"].get<double>(), 89.0) << "Ctrl+Q was not seen (unsaved?)";
    const nlohmann::json moved = nlohmann::json::parse(test::readFile(dir / "moved.json"));
    EXPECT_EQ(moved["dirty"], true);
    const nlohmann::json undone = nlohmann::json::parse(test::readFile(dir / "undone.json"));
    EXPECT_EQ(undone["undo"], "");
    EXPECT_EQ(report["undo"], "Move ball");
    EXPECT_EQ(report["undo_steps"], 1);
    Result<Project> saved = loadProject(project);
    ASSERT_TRUE(saved.ok()) << saved.error().message;
    ASSERT_EQ(saved->bodies.size(), 1u);
    EXPECT_EQ(saved->bodies[0].position, Eigen::Vector3d(5, 0, 0));
}

TEST(EditorWindow, LayerRenameFromTheContextMenuKeepsEnterAndDropsEsc) {
    // The ball's map with layers Base, "Layer 1" and "Fill 2" (a headless script), the Layers
    // panel given most of the column: at 800 x 500 the rows "Fill 2" and "Layer 1" are at
    // y = 134 and 157, and a right-click's menu has "Rename" 14 px below the click. "Layer 1"
    // becomes "Rust" with Enter (one step, saved in the layers file); "Fill 2" typed over as
    // "Zed" and left with Esc keeps its name. Keys are held until a frame has taken them.
    if (!haveWindowTools(true)) GTEST_SKIP() << "xvfb-run or xdotool is not installed";
    const fs::path project = ballProject("window_layer_rename");
    const fs::path dir = project.parent_path();
    std::ofstream(dir / "layers.json") << R"([{"op": "new_map", "size": 64, "value": 0.3},
        {"op": "layer_add", "kind": "paint"}, {"op": "layer_add", "kind": "fill", "value": 0.5}])";
    const test::CommandOutput made = test::runPlimsoll(
        "edit '" + project.string() + "' --script '" + (dir / "layers.json").string() + "'");
    ASSERT_EQ(made.exitCode, 0) << made.err;
    fs::create_directories(dir / "config" / "plimsoll");
    std::ofstream(dir / "config" / "plimsoll" / "settings.json")
        << R"({"layout": {"column_width": 400, "shares": [0.1, 0.7, 0.1, 0.1]}})";
    auto renameAt = [](int y) {
        return moveTo(600, y) + "xdotool click 3; " + waitFor("\"popup\":\"##Popup_") +
               clickAt(620, y + 14) + waitFor("\"held\":\"Layers/");
    };
    // Enter: the step's name has quotes of its own, and the script is in single quotes.
    const std::string enter =
        "xdotool type --window $w Rust; xdotool keydown --window $w Return; " +
        waitFor("\"undo\":\"Rename layer ") + "xdotool keyup --window $w Return; ";
    const std::string escape =
        "xdotool type --window $w Zed; xdotool keydown --window $w Escape; " +
        waitFor("\"held\":\"\"") + "xdotool keyup --window $w Escape; ";
    const std::string out = runUnderXvfb(
        dir,
        "$PLIMSOLL edit ball.plim.json --run-seconds 90 --window-size 800x500 --view front "
        "--state-file state.json & " +
            kWaitForState + renameAt(157) + enter + renameAt(134) + escape +
            "cp state.json escaped.json; xdotool key --window $w ctrl+s; " +
            waitFor("\"dirty\":false") + "xdotool key --window $w ctrl+q; wait");
    if (out.empty()) GTEST_SKIP() << "no editor window in this build or no X server";
    const nlohmann::json report = nlohmann::json::parse(out);
    EXPECT_LT(report["seconds"].get<double>(), 89.0) << "Ctrl+Q was not seen (unsaved?)";
    EXPECT_EQ(report["undo"], "Rename layer 'Layer 1' to 'Rust'");
    EXPECT_EQ(report["undo_steps"], 1) << "Esc made a step";
    const nlohmann::json escaped = nlohmann::json::parse(test::readFile(dir / "escaped.json"));
    EXPECT_EQ(escaped["held"], "") << "the field stayed open after Esc";
    const nlohmann::json layers =
        nlohmann::json::parse(test::readFile(dir / "maps" / "ball_ball_permeability.layers.json"));
    ASSERT_EQ(layers["layers"].size(), 3u);
    EXPECT_EQ(layers["layers"][0]["name"], "Base");
    EXPECT_EQ(layers["layers"][1]["name"], "Rust");
    EXPECT_EQ(layers["layers"][2]["name"], "Fill 2");
}

}  // namespace
}  // namespace test_editor_window
}  // namespace plimsoll::editor

namespace plimsoll::editor {
namespace test_editor_window {
namespace {

/// The window's last frame after `seconds` of `project` (the perspective view, from above the
/// water, no paint overlay), with or
/// without View > Show physics solid / caps; empty when the window cannot run here.
std::vector<unsigned char> frameOf(const fs::path& project, bool showSolid, double seconds) {
    const fs::path shot = project.parent_path() / (showSolid ? "solid.png" : "plain.png");
    const test::CommandOutput run =
        test::runPlimsoll("edit '" + project.string() + "' --run-seconds " +
                              std::to_string(seconds) + " --screenshot '" + shot.string() +
                              "' --window-size 800x500 --view persp --overlay none" +
                              (showSolid ? " --show-physics-solid" : ""),
                          test::xvfbRun(project.parent_path()));
    EXPECT_EQ(run.exitCode, 0) << run.err;
    int width = 0, height = 0, channels = 0;
    unsigned char* data = stbi_load(shot.c_str(), &width, &height, &channels, 3);
    if (!data) return {};
    std::vector<unsigned char> rgb(data, data + 3 * width * height);
    stbi_image_free(data);
    return rgb;
}

std::size_t differingPixels(const std::vector<unsigned char>& a,
                            const std::vector<unsigned char>& b) {
    std::size_t count = 0;
    for (std::size_t i = 0; i + 2 < std::min(a.size(), b.size()); i += 3)
        count += a[i] != b[i] || a[i + 1] != b[i + 1] || a[i + 2] != b[i + 2];
    return count;
}

TEST(EditorWindow, ShowPhysicsSolidDrawsAnOpenHullsCapAndNothingOverAClosedMesh) {
    if (!haveWindowTools(false)) GTEST_SKIP() << "xvfb-run is not installed, or no editor window";
    const fs::path boatFile = test::realAssetsDir() / "quaternius" / "Boat.fbx";
    if (!fs::exists(boatFile)) GTEST_SKIP() << "../shared/real-assets is absent";
    // A closed ball: its physics solid is its mesh and it has no cap, so nothing is drawn over it.
    const fs::path ball = ballProject("window_solid_ball");
    const std::vector<unsigned char> ballPlain = frameOf(ball, false, 3.0);
    const std::vector<unsigned char> ballSolid = frameOf(ball, true, 3.0);
    ASSERT_FALSE(ballPlain.empty());
    ASSERT_EQ(ballPlain.size(), ballSolid.size());
    const std::size_t ballChanged = differingPixels(ballPlain, ballSolid);

    // The open dinghy: its cap across the gunwale, worked out in the background, is drawn over it.
    const fs::path dir = ball.parent_path();
    const fs::path boat = dir / "boat.plim.json";
    std::ofstream(boat) << R"({"schema_version": 1, "name": "boat",
        "water": {"model": "flat", "level": -5},
        "bodies": [{"name": "boat", "mesh": ")"
                        << boatFile.string() << R"(", "material": {"density": 500}}]})";
    const std::vector<unsigned char> boatPlain = frameOf(boat, false, 6.0);
    const std::vector<unsigned char> boatSolid = frameOf(boat, true, 6.0);
    ASSERT_EQ(boatPlain.size(), boatSolid.size());
    const std::size_t boatChanged = differingPixels(boatPlain, boatSolid);
    // The cap across the hull seen from above, and the solid's see-through walls over the hull:
    // some thousands of pixels of the 400,000; the ball's frames differ by at most a few pixels
    // of text that changes with time.
    EXPECT_GT(boatChanged, 2000u);
    EXPECT_LT(ballChanged, boatChanged / 20);
}

}  // namespace
}  // namespace test_editor_window
}  // namespace plimsoll::editor
