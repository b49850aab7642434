// Headless rendering through EGL: `plimsoll render` writes a PNG of the requested size, with the
// overlay's colours where the camera puts the painted region (no stored reference image).
#include "cli_runner.h"
#include "test_support.h"

#include "document/document.h"
#include "document/overlay.h"
#include "view/camera.h"

#include <gtest/gtest.h>
#include <stb_image.h>

#include <fstream>
#include <unistd.h>

namespace plimsoll::editor {
namespace test_editor_render {
namespace {

namespace fs = std::filesystem;

struct Image {
    int width = 0, height = 0;
    std::vector<unsigned char> rgb;
    Eigen::Vector3i at(const Eigen::Vector2d& p) const {
        const int x = static_cast<int>(p.x()), y = static_cast<int>(p.y());
        const std::size_t i = 3 * (static_cast<std::size_t>(y) * width + x);
        return {rgb[i], rgb[i + 1], rgb[i + 2]};
    }
};

Image loadRgb(const fs::path& path) {
    Image image;
    int channels = 0;
    unsigned char* data = stbi_load(path.c_str(), &image.width, &image.height, &channels, 3);
    if (data) {
        image.rgb.assign(data, data + 3 * image.width * image.height);
        stbi_image_free(data);
    }
    return image;
}

TEST(EditorRender, OverlayColoursWhereThePaintedRegionProjects) {
    const fs::path dir =
        fs::temp_directory_path() / "plimsoll_tests" / ("render_" + std::to_string(::getpid()));
    fs::remove_all(dir);
    fs::create_directories(dir);
    const fs::path project = dir / "ball.plim.json";
    std::ofstream(project)
        << R"({"schema_version": 1, "name": "ball", "bodies": [{"name": "ball", "mesh": ")"
        << test::assetPath("sphere.obj").string()
        << R"(", "material": {"density": 500}, "position": [0.2, 0.1, 0]}]})";
    // Paint a spot of radius 0.2 m around the point of the sphere nearest the front camera.
    const fs::path script = dir / "paint.json";
    std::ofstream(script) << R"([
      {"op": "paint", "channel": "permeability", "radius": 0.2, "falloff": "constant",
       "value": 1, "points": [[0, 0, 0.5]]}])";
    const test::CommandOutput edit =
        test::runPlimsoll("edit '" + project.string() + "' --script '" + script.string() + "'");
    ASSERT_EQ(edit.exitCode, 0) << edit.err;

    const fs::path shot = dir / "shot.png";
    const test::CommandOutput render = test::runPlimsoll(
        "render '" + project.string() + "' --out '" + shot.string() +
        "' --view front --overlay permeability --size 320x240 --no-water --no-grid");
    if (test::cannotRender(render)) {
        GTEST_SKIP() << "no EGL OpenGL 4.5 here: " << render.err;
    }
    ASSERT_EQ(render.exitCode, 0) << render.err;
    const Image image = loadRgb(shot);
    ASSERT_EQ(image.width, 320);
    ASSERT_EQ(image.height, 240);

    // Where the camera of `--view front` puts points of the body (its pose: +0.2, +0.1, 0).
    auto document = Document::open(project);
    ASSERT_TRUE(document.ok()) << document.error().message;
    const Camera camera = Camera::preset(ViewPreset::Front, (*document)->worldBounds());
    const Eigen::Vector3d offset(0.2, 0.1, 0);
    auto pixelOf = [&](const Eigen::Vector3d& objectPoint) {
        const std::optional<Eigen::Vector2d> p = camera.toPixel(objectPoint + offset, 320, 240);
        EXPECT_TRUE(p);
        return p.value_or(Eigen::Vector2d(0, 0));
    };
    auto onSphere = [](double x, double y) {
        return Eigen::Vector3d(x, y, std::sqrt(0.25 - x * x - y * y));
    };
    const Eigen::Vector3f painted = rampColour(1.0) * 255.0f, bare = rampColour(0.0) * 255.0f;
    // Inside the spot (less than 0.2 m from its centre, with a pixel's margin): the overlay's
    // colour for 1 (orange: red well above blue); the shading scales it by 0.35..1.
    int checked = 0;
    for (double x = -0.12; x <= 0.12; x += 0.04) {
        for (double y = -0.12; y <= 0.12; y += 0.04) {
            const Eigen::Vector3d p = onSphere(x, y);
            if ((p - Eigen::Vector3d(0, 0, 0.5)).norm() > 0.17) continue;
            const Eigen::Vector3i c = image.at(pixelOf(p));
            EXPECT_GT(c.x(), c.z() + 60) << "painted point " << p.transpose() << " pixel "
                                         << pixelOf(p).transpose() << " colour " << c.transpose();
            // Hue of the ramp's orange: green between blue and red.
            EXPECT_GT(c.y(), c.z());
            ++checked;
        }
    }
    EXPECT_GT(checked, 10);
    // Outside it (more than 0.25 m away, still facing the camera): the colour for 0 (blue).
    for (const Eigen::Vector3d& p :
         {onSphere(0.35, 0.2), onSphere(-0.35, -0.2), onSphere(0.0, 0.4), onSphere(-0.4, 0.1)}) {
        ASSERT_GT((p - Eigen::Vector3d(0, 0, 0.5)).norm(), 0.25);
        const Eigen::Vector3i c = image.at(pixelOf(p));
        EXPECT_GT(c.z(), c.x() + 60)
            << "bare point " << p.transpose() << " colour " << c.transpose();
    }
    // Beyond the silhouette (0.55 m from the centre on screen): the background.
    for (const Eigen::Vector3d& p : {Eigen::Vector3d(0.55, 0, 0), Eigen::Vector3d(-0.4, 0.4, 0),
                                     Eigen::Vector3d(0, -0.56, 0)}) {
        const Eigen::Vector3i c = image.at(pixelOf(p));
        EXPECT_NEAR(c.x(), 51, 2);
        EXPECT_NEAR(c.y(), 54, 2);
        EXPECT_NEAR(c.z(), 59, 2);
    }
    (void)painted;
    (void)bare;
}

TEST(EditorRender, WritesTheRequestedSizeForEveryViewAndOverlay) {
    const fs::path dir = fs::temp_directory_path() / "plimsoll_tests" /
                         ("render_views_" + std::to_string(::getpid()));
    fs::create_directories(dir);
    const std::string project = std::string(PLIMSOLL_SOURCE_DIR) + "/projects/buoy.plim.json";
    for (const char* view : {"side", "top", "persp"}) {
        const fs::path shot = dir / (std::string(view) + ".png");
        const test::CommandOutput r =
            test::runPlimsoll("render '" + project + "' --out '" + shot.string() + "' --view " +
                              view + " --overlay area --size 64x48");
        if (test::cannotRender(r)) {
            GTEST_SKIP() << r.err;
        }
        ASSERT_EQ(r.exitCode, 0) << r.err;
        const Image image = loadRgb(shot);
        EXPECT_EQ(image.width, 64);
        EXPECT_EQ(image.height, 48);
    }
    const test::CommandOutput bad = test::runPlimsoll("render '" + project + "' --out '" +
                                                      (dir / "x.png").string() + "' --size 12by3");
    EXPECT_EQ(bad.exitCode, 2);
}

}  // namespace
}  // namespace test_editor_render
}  // namespace plimsoll::editor
