// The renderer's kept scene (Renderer::draw): a scene that stands still is drawn once more into
// a texture, upside down, and copied from it with its rows reversed, so that llvmpipe copies
// rows instead of drawing a textured quad. What reaches the target must be the scene as drawn
// directly: the same way up and the same pixels. Built only with the GUI (plimsoll_render);
// skipped where no headless OpenGL 4.5 context can be made.
#include "test_support.h"

#include "render/camera.h"
#include "render/headless_context.h"
#include "render/renderer.h"

#include "plimsoll/geometry/validate.h"
#include "plimsoll/io/mesh_io.h"

#include <epoxy/gl.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>

namespace plimsoll::editor {
namespace {

struct Difference {
    std::size_t pixels = 0;     ///< pixels with any channel off by more than `tolerance`
    int largest = 0;            ///< the largest channel difference anywhere
};

Difference compare(const std::vector<std::uint8_t>& a, const std::vector<std::uint8_t>& b,
                   int tolerance) {
    Difference d;
    for (std::size_t p = 0; p + 3 < a.size(); p += 4) {
        int worst = 0;
        for (int c = 0; c < 3; ++c) worst = std::max(worst, std::abs(int(a[p + c]) - int(b[p + c])));
        d.largest = std::max(d.largest, worst);
        if (worst > tolerance) ++d.pixels;
    }
    return d;
}

TEST(EditorRenderer, KeptSceneCopiesTheSamePixelsTheRightWayUp) {
    Result<std::unique_ptr<HeadlessContext>> context = HeadlessContext::create();
    if (!context) GTEST_SKIP() << "no headless OpenGL 4.5 here: " << context.error().message;
    Result<std::unique_ptr<Renderer>> renderer = Renderer::create();
    ASSERT_TRUE(renderer.ok()) << renderer.error().message;
    // Not a multiple of the rasteriser's 64-pixel tiles, and taller than wide.
    const int width = 200, height = 250;
    Result<std::unique_ptr<OffscreenTarget>> target = OffscreenTarget::create(width, height);
    ASSERT_TRUE(target.ok()) << target.error().message;

    Result<TriangleMesh> mesh = loadMesh(test::assetPath("sphere.obj"));
    ASSERT_TRUE(mesh.ok()) << mesh.error().message;
    RenderScene scene;
    RenderBody body;
    body.mesh = std::make_shared<const TriangleMesh>(std::move(mesh).value());
    // Off centre and high: the image is nothing like itself turned over.
    body.pose.translation = Eigen::Vector3d(0.3, 0.6, 0.0);
    scene.bodies.push_back(body);
    WaterModel water;
    water.kind = WaterModel::Kind::Gerstner;
    water.waves = {GerstnerWave{0.15, 4.0, {1.0, 0.3}, 0.5, 0.0}};
    scene.water = &water;
    scene.time = 0.7;
    Camera camera;
    camera.distance = 4.0;
    camera.pitch = 0.35;
    camera.yaw = 0.4;

    auto drawOnce = [&] {
        (*target)->bind();
        glClearColor(0.0f, 0.0f, 0.0f, 1.0f);  // not the scene's background
        glClear(GL_COLOR_BUFFER_BIT);
        (*renderer)->draw(scene, camera, width, height);
        return (*target)->readRgba();
    };
    const std::vector<std::uint8_t> direct = drawOnce();   // a new scene: drawn
    const std::vector<std::uint8_t> kept = drawOnce();     // the same again: kept and copied
    const std::vector<std::uint8_t> copied = drawOnce();   // and again: copied only
    EXPECT_EQ((*renderer)->framesDrawn(), 2u);
    EXPECT_EQ((*renderer)->framesCopied(), 1u);

    // The image has content: the body and the water differ from the background.
    const Difference fromBackground =
        compare(direct, std::vector<std::uint8_t>(direct.size(), 0), 60);
    EXPECT_GT(fromBackground.pixels, std::size_t(width * height / 10));

    // Drawn upside down, a triangle's edge pixels may round the other way (the fill rule
    // follows the rows), so a few edge pixels may differ; the image may not.
    const Difference keptVsDirect = compare(kept, direct, 8);
    EXPECT_LT(keptVsDirect.pixels, std::size_t(width * height / 200))
        << "largest channel difference " << keptVsDirect.largest;
    EXPECT_EQ(compare(copied, kept, 0).pixels, 0u);

    // Turned over, the same image would differ almost everywhere the scene is.
    std::vector<std::uint8_t> flipped(direct.size());
    const std::size_t row = std::size_t(width) * 4;
    for (int y = 0; y < height; ++y) {
        std::copy_n(direct.begin() + std::ptrdiff_t(y * row), row,
                    flipped.begin() + std::ptrdiff_t((height - 1 - y) * row));
    }
    EXPECT_GT(compare(flipped, direct, 8).pixels, std::size_t(width * height / 20));
}

// An opaque closed solid is drawn with its back faces culled (they are never seen from
// outside). From outside, it looks the same as the same surface with a hidden triangle of its
// far side missing, which is open and so drawn whole; from inside, the closed one shows
// nothing of itself and the open one shows its inside.
TEST(EditorRenderer, OpaqueClosedSolidsLoseOnlyTheBackFacesNoOneSees) {
    Result<std::unique_ptr<HeadlessContext>> context = HeadlessContext::create();
    if (!context) GTEST_SKIP() << "no headless OpenGL 4.5 here: " << context.error().message;
    Result<std::unique_ptr<Renderer>> renderer = Renderer::create();
    ASSERT_TRUE(renderer.ok()) << renderer.error().message;
    const int width = 160, height = 120;
    Result<std::unique_ptr<OffscreenTarget>> target = OffscreenTarget::create(width, height);
    ASSERT_TRUE(target.ok()) << target.error().message;

    Result<TriangleMesh> sphere = loadMesh(test::assetPath("sphere.obj"));  // radius 0.5
    ASSERT_TRUE(sphere.ok()) << sphere.error().message;
    Camera camera;
    camera.distance = 3.0;
    camera.pitch = 0.35;
    camera.yaw = 0.4;
    // The open copy: the triangle farthest from the eye gone (behind the sphere's front).
    TriangleMesh open = *sphere;
    const Eigen::Vector3d eye = camera.eye();
    auto centroidDistance = [&](const Triangle& t) {
        return ((open.positions[t[0]] + open.positions[t[1]] + open.positions[t[2]]) / 3.0 - eye)
            .norm();
    };
    open.triangles.erase(std::max_element(open.triangles.begin(), open.triangles.end(),
                                          [&](const Triangle& a, const Triangle& b) {
                                              return centroidDistance(a) < centroidDistance(b);
                                          }));
    ASSERT_TRUE(validateSurface(*sphere).closedSolid());
    ASSERT_FALSE(validateSurface(open).closedSolid());

    auto draw = [&](const TriangleMesh& mesh, bool upsideDownToo) {
        RenderScene scene;  // no water, no grid: the body on its background
        scene.grid = scene.axes = false;
        RenderBody body;
        body.mesh = std::make_shared<const TriangleMesh>(mesh);
        scene.bodies.push_back(body);
        (*target)->bind();
        (*renderer)->draw(scene, camera, width, height);
        std::vector<std::uint8_t> image = (*target)->readRgba();
        if (upsideDownToo) {
            // The same scene again is kept: drawn upside down, where the winding turns.
            (*target)->bind();
            (*renderer)->draw(scene, camera, width, height);
            EXPECT_LT(compare((*target)->readRgba(), image, 8).pixels, std::size_t(width * height / 200));
        }
        return image;
    };
    const std::vector<std::uint8_t> closedOutside = draw(*sphere, true);
    const std::vector<std::uint8_t> openOutside = draw(open, true);
    const std::vector<std::uint8_t> background = [&] {
        RenderScene scene;
        scene.grid = scene.axes = false;
        (*target)->bind();
        (*renderer)->draw(scene, camera, width, height);
        return (*target)->readRgba();
    }();
    EXPECT_GT(compare(closedOutside, background, 30).pixels, std::size_t(width * height / 20));
    EXPECT_EQ(compare(closedOutside, openOutside, 0).pixels, 0u);

    camera.distance = 0.2;  // the eye inside the sphere, 0.2 from its centre
    const std::vector<std::uint8_t> closedInside = draw(*sphere, false);
    const std::vector<std::uint8_t> openInside = draw(open, false);
    const std::vector<std::uint8_t> backgroundInside = [&] {
        RenderScene scene;
        scene.grid = scene.axes = false;
        (*target)->bind();
        (*renderer)->draw(scene, camera, width, height);
        return (*target)->readRgba();
    }();
    EXPECT_EQ(compare(closedInside, backgroundInside, 0).pixels, 0u);
    EXPECT_GT(compare(openInside, backgroundInside, 30).pixels, std::size_t(width * height / 2));
}

}  // namespace
}  // namespace plimsoll::editor
