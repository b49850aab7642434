// The live preview in the editor window under Xvfb: the buoy project, dropped from above its
// floating height, runs for 5 s (300 frames of 1/60 s); screenshots at 0.5 s and 5 s differ
// where the buoy moved, and show the weight (red) and buoyancy (green) arrows where the camera
// puts the centres of mass and buoyancy. Skipped where xvfb-run is missing or the build has no
// window.
#include "cli_runner.h"
#include "test_support.h"
#include "editor/xvfb_support.h"

#include "view/camera.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <stb_image.h>

#include <cstdlib>
#include <fstream>
#include <optional>
#include <unistd.h>

namespace plimsoll::editor {
namespace test_editor_preview_window {
namespace {

namespace fs = std::filesystem;

struct Image {
    int width = 0, height = 0;
    std::vector<unsigned char> rgb;
    Eigen::Vector3i at(int x, int y) const {
        x = std::clamp(x, 0, width - 1);
        y = std::clamp(y, 0, height - 1);
        const std::size_t i = 3 * (static_cast<std::size_t>(y) * width + x);
        return {rgb[i], rgb[i + 1], rgb[i + 2]};
    }
};

Image load(const std::string& path) {
    Image image;
    int channels = 0;
    unsigned char* data = stbi_load(path.c_str(), &image.width, &image.height, &channels, 3);
    EXPECT_TRUE(data) << path << ": " << stbi_failure_reason();
    if (data) {
        image.rgb.assign(data, data + 3 * image.width * image.height);
        stbi_image_free(data);
    }
    return image;
}

Eigen::Vector3d vec(const nlohmann::json& j) {
    return Eigen::Vector3d(j[0].get<double>(), j[1].get<double>(), j[2].get<double>());
}

/// The sample buoy project in a fresh folder `name`, its files made absolute, dropped from
/// 0.3 m above where the project starts it.
fs::path buoyProject(const std::string& name) {
    const fs::path dir =
        fs::temp_directory_path() / "plimsoll_tests" / (name + "_" + std::to_string(::getpid()));
    fs::remove_all(dir);
    fs::create_directories(dir);
    const fs::path source = fs::path(PLIMSOLL_SOURCE_DIR) / "projects";
    nlohmann::json project = nlohmann::json::parse(std::ifstream(source / "buoy.plim.json"));
    nlohmann::json& body = project["bodies"][0];
    body["mesh"] = (source / body["mesh"].get<std::string>()).lexically_normal().string();
    body["material"]["map"] = (source / body["material"]["map"].get<std::string>()).string();
    body["position"] = {0.0, 0.45, 0.0};
    const fs::path file = dir / "buoy.plim.json";
    std::ofstream(file) << project.dump(2);
    return file;
}

/// The new size: 1024, or 512 in the sanitized build, where a 1024^2 bake and the preview's
/// physics at that size took most of a minute and a half (the buoy's own size is 128).
constexpr int kNewSize = test::kSanitizedBuild ? 512 : 1024;

/// The most frames a rebake run may draw before the test gives up on the new size. The run ends
/// as soon as the size is in, so this only bounds a failure; frames are not paced under Xvfb and
/// cost 3-7 ms, and on CI's 2 busy cores 5000 frames (32 s) once ran out before the 1024^2 bake
/// finished, so the bound is several times that.
constexpr int kMaxRebakeFrames = 30000;

/// The buoy's preview with `option` kNewSize given (a new texture size asked for at the second
/// frame); the run ends once it is in. Its report, or nothing with `skip` saying why the window
/// could not run. Frames must keep coming while it bakes: a loop that waited for the bake would
/// draw none while it ran.
std::optional<nlohmann::json> rebakeRun(const std::string& name, const std::string& option,
                                        std::string& skip) {
    if (std::system("command -v xvfb-run >/dev/null 2>&1") != 0) {
        skip = "xvfb-run is not installed";
        return std::nullopt;
    }
    const fs::path file = buoyProject(name);
    const test::CommandOutput run = test::runPlimsoll(
        "edit '" + file.string() + "' --frames " + std::to_string(kMaxRebakeFrames) +
            " --preview " + option + " " + std::to_string(kNewSize) +
            " "
            "--window-size 1024x640 --view front --overlay coverage",
        test::xvfbRun(file.parent_path()));
    if (run.exitCode != 0 && run.err.find("built without the editor window") != std::string::npos) {
        skip = run.err;
        return std::nullopt;
    }
    EXPECT_EQ(run.exitCode, 0) << run.err << run.out;
    if (run.exitCode != 0) return std::nullopt;
    nlohmann::json report = nlohmann::json::parse(run.out);
    const nlohmann::json& rebake = report["rebake"];
    std::cout << option << " " << kNewSize << ": " << rebake["frames_while_baking"]
              << " frames drawn while it baked, "
              << "the longest " << rebake["frame_ms_max_while_baking"] << " ms ("
              << report["gl_renderer"] << ")\n";
    EXPECT_EQ(rebake["error"], "");
    EXPECT_EQ(rebake["texture_size"], kNewSize) << "the preview never swapped the new size in";
    EXPECT_GE(rebake["frames_while_baking"].get<int>(), 3);
    EXPECT_LT(report["frames"].get<int>(), kMaxRebakeFrames);
    return report;
}

TEST(EditorPreviewWindow, NewTextureSizeBakesWhileTheWindowKeepsDrawing) {
    // Choosing 1024^2 in "Speed and accuracy" froze the window.
    std::string skip;
    if (!rebakeRun("preview_rebake", "--texture-size", skip) && !skip.empty()) GTEST_SKIP() << skip;
}

TEST(EditorPreviewWindow, InspectorTextureSizeBakesOnAWorkerWhileFramesKeepComing) {
    // The inspector's Texture size baked on the UI thread. Set through the
    // inspector's own path with the preview running, the document's textures bake on a worker
    // and the preview rebakes the body in the background, the old size running meanwhile.
    std::string skip;
    const std::optional<nlohmann::json> report =
        rebakeRun("inspector_rebake", "--inspector-texture-size", skip);
    if (!report && !skip.empty()) GTEST_SKIP() << skip;
    ASSERT_TRUE(report);
    const nlohmann::json& rebake = (*report)["rebake"];
    EXPECT_EQ(rebake["document_error"], "");
    EXPECT_EQ(rebake["document_texture_size"], kNewSize);
    EXPECT_EQ(rebake["document_baked_size"], kNewSize) << "the document's bake never arrived";
    EXPECT_TRUE(rebake["baked_on_worker"].get<bool>());
    EXPECT_EQ((*report)["title"], "*buoy.plim.json - Plimsoll");  // one edit: the size
}

TEST(EditorPreviewWindow, BuoyMovesAndForceArrowsShowUnderXvfb) {
    if (std::system("command -v xvfb-run >/dev/null 2>&1") != 0) {
        GTEST_SKIP() << "xvfb-run is not installed";
    }
    const fs::path file = buoyProject("preview_window");
    const fs::path dir = file.parent_path();
    const std::string environment = test::xvfbRun(dir);
    const std::string early = (dir / "early.png").string(), late = (dir / "late.png").string();
    const test::CommandOutput run = test::runPlimsoll(
        "edit '" + file.string() + "' --frames 300 --preview --snapshot 30:'" + early +
            "' --snapshot 300:'" + late + "' --window-size 1024x640 --view front --overlay none",
        environment);
    if (run.exitCode != 0 && run.err.find("built without the editor window") != std::string::npos) {
        GTEST_SKIP() << run.err;
    }
    ASSERT_EQ(run.exitCode, 0) << run.err << run.out;
    const nlohmann::json report = nlohmann::json::parse(run.out);
    std::cout << "live preview frame time under Xvfb (buoy): " << report["frame_ms_median"]
              << " ms (median), " << report["gl_renderer"] << ", physics on "
              << report["preview"]["device"] << "\n";
    ASSERT_EQ(report["snapshots"].size(), 2u);
    const nlohmann::json& first = report["snapshots"][0];
    const nlohmann::json& second = report["snapshots"][1];
    // One simulated frame per drawn frame.
    EXPECT_NEAR(first["time"].get<double>(), 30.0 / 60.0, 1e-9);
    EXPECT_NEAR(second["time"].get<double>(), 300.0 / 60.0, 1e-9);

    const auto& vp = report["viewport"];
    const double vx = vp[0], vy = vp[1], vw = vp[2], vh = vp[3];
    const auto& c = first["camera"];
    Camera camera;
    camera.target = vec(c["target"]);
    camera.yaw = c["yaw"];
    camera.pitch = c["pitch"];
    camera.distance = c["distance"];
    camera.fovY = c["fov_y"];
    camera.orthographic = c["orthographic"];
    auto pixelOf = [&](const Eigen::Vector3d& world) {
        const auto p = camera.toPixel(world, static_cast<int>(vw), static_cast<int>(vh));
        EXPECT_TRUE(p);
        return p ? Eigen::Vector2d(vx + p->x(), vy + p->y()) : Eigen::Vector2d(-1, -1);
    };

    const Image a = load(early), b = load(late);
    ASSERT_EQ(a.width, 1024);
    ASSERT_EQ(b.height, 640);

    // The buoy moved (it fell and bobbed): its centre of mass is elsewhere, and the pictures
    // differ around the buoy, more than elsewhere in the view.
    const Eigen::Vector3d comEarly = vec(first["bodies"][0]["center_of_mass"]);
    const Eigen::Vector3d comLate = vec(second["bodies"][0]["center_of_mass"]);
    EXPECT_GT((comEarly - comLate).norm(), 0.02)
        << comEarly.transpose() << " / " << comLate.transpose();
    auto differing = [&](const Eigen::Vector2d& centre, double half) {
        int n = 0;
        for (int y = int(centre.y() - half); y < int(centre.y() + half); ++y) {
            for (int x = int(centre.x() - half); x < int(centre.x() + half); ++x) {
                if (x < vx || y < vy || x >= vx + vw || y >= vy + vh) continue;
                n += (a.at(x, y) - b.at(x, y)).cwiseAbs().sum() > 60;
            }
        }
        return n;
    };
    const double halfBuoy =
        (pixelOf(comEarly + Eigen::Vector3d(0.5, 0, 0)) - pixelOf(comEarly)).norm();
    const int nearBuoy = differing(pixelOf(0.5 * (comEarly + comLate)), halfBuoy);
    EXPECT_GT(nearBuoy, 300) << "the screenshots should differ where the buoy moved";

    // The arrows, in their colours, along their projected segments (drawn over everything).
    // The arrows' own colours (255, 31, 31) and (31, 255, 31), told apart from the view's
    // x and y axis lines (217, 64, 64) and (89, 204, 89).
    auto isRed = [](const Eigen::Vector3i& p) { return p.x() > 235 && p.y() < 50 && p.z() < 50; };
    auto isGreen = [](const Eigen::Vector3i& p) { return p.y() > 235 && p.x() < 50 && p.z() < 50; };
    auto checkArrows = [&](const nlohmann::json& shot, const Image& image) {
        int red = 0, green = 0;
        for (const auto& arrow : shot["arrows"]) {
            const Eigen::Vector3d from = vec(arrow["from"]), to = vec(arrow["to"]);
            const bool weight = arrow["colour"][0].get<double>() > 0.9;
            const bool buoyancy = arrow["colour"][1].get<double>() > 0.9;
            if (!weight && !buoyancy) continue;
            if (weight) EXPECT_LT(to.y(), from.y()) << "the weight points down";
            if (buoyancy) EXPECT_GT(to.y(), from.y()) << "buoyancy points up";
            const Eigen::Vector2d p = pixelOf(from), q = pixelOf(to);
            int found = 0, samples = 0;
            for (double t = 0.15; t <= 0.75; t += 0.05) {
                const Eigen::Vector2d m = p + t * (q - p);
                // Drawn over the panels too, but clipped to the view.
                if (m.x() < vx + 6 || m.y() < vy + 6 || m.x() > vx + vw - 6 || m.y() > vy + vh - 6)
                    continue;
                ++samples;
                bool hit = false;
                // The weight drawn 3 px wide on top, buoyancy 9 px wide below it.
                const int reach = weight ? 2 : 5;
                for (int dy = -reach; dy <= reach && !hit; ++dy) {
                    for (int dx = -reach; dx <= reach && !hit; ++dx) {
                        const Eigen::Vector3i colour = image.at(int(m.x()) + dx, int(m.y()) + dy);
                        hit = weight ? isRed(colour) : isGreen(colour);
                    }
                }
                found += hit;
            }
            EXPECT_GE(samples, 5) << "the arrow should be in the view";
            EXPECT_GE(found, samples - 1) << (weight ? "weight" : "buoyancy") << " arrow from "
                                          << p.transpose() << " to " << q.transpose();
            (weight ? red : green) += 1;
        }
        EXPECT_EQ(red, 1);
        EXPECT_EQ(green, 1);
    };
    checkArrows(first, a);
    checkArrows(second, b);
    // The centres: the weight at the centre of mass, buoyancy at the centre of buoyancy.
    EXPECT_LT((vec(second["arrows"][0]["from"]) - comLate).norm(), 1e-9);
}

}  // namespace
}  // namespace test_editor_preview_window
}  // namespace plimsoll::editor
