// The editor window under Xvfb: it starts, opens a sample project, and its screenshot shows the
// UI and the mesh where the camera puts it (pixel positions computed from the camera, not a
// stored image). Skipped where xvfb-run is missing or the build has no window.
#include "cli_runner.h"
#include "test_support.h"

#include "render/camera.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <stb_image.h>

#include <cstdlib>
#include <fstream>
#include <unistd.h>

namespace plimsoll::editor {
namespace {

namespace fs = std::filesystem;

TEST(EditorWindow, ScreenshotUnderXvfbShowsUiAndMeshWhereTheCameraPutsIt) {
    if (std::system("command -v xvfb-run >/dev/null 2>&1") != 0) {
        GTEST_SKIP() << "xvfb-run is not installed";
    }
    const fs::path dir = fs::temp_directory_path() / "plimsoll_tests" /
                         ("window_" + std::to_string(::getpid()));
    fs::remove_all(dir);
    fs::create_directories(dir);
    const fs::path project = dir / "window.plim.json";
    // The water far below, so that the front view sees it edge-on outside the picture.
    std::ofstream(project) << R"({"schema_version": 1, "name": "window",
        "water": {"model": "flat", "level": -5},
        "bodies": [{"name": "ball", "mesh": ")" << test::assetPath("sphere.obj").string()
                           << R"(", "material": {"density": 500}, "position": [0.3, 1.0, 0]}]})";
    const fs::path shot = dir / "window.png";
    // Its own config folder: no recent files or autosaves of the user's.
    const std::string environment = "XDG_CONFIG_HOME='" + (dir / "config").string() + "' xvfb-run -a -s '-screen 0 1280x800x24'";
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
        const std::size_t i = 3 * (static_cast<std::size_t>(y) * width + static_cast<std::size_t>(x));
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
         {Eigen::Vector3d(0, 0, 0.5), Eigen::Vector3d(0.35, 0.2, 0.3), Eigen::Vector3d(-0.3, -0.25, 0.3),
          Eigen::Vector3d(0.1, 0.4, 0.25), Eigen::Vector3d(-0.4, 0.0, 0.3)}) {
        const Eigen::Vector2d p = pixelOf(centre + offset);
        const Eigen::Vector3i c = at(p.x(), p.y());
        EXPECT_GT(c.x(), 85) << "mesh expected at " << p.transpose() << ", colour " << c.transpose();
        EXPECT_NEAR(c.y(), c.x() * 0.78 / 0.80, 4);
        EXPECT_NEAR(c.z(), c.x() * 0.72 / 0.80, 4);
    }
    // Just outside its outline (0.6 m from the centre, off the grid line and the y axis): the
    // view's background.
    for (const Eigen::Vector3d& offset : {Eigen::Vector3d(0.62, 0.0, 0), Eigen::Vector3d(-0.62, 0.1, 0),
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

}  // namespace
}  // namespace plimsoll::editor
