// The renderer's ways of drawing less, each against the image drawn without it. The kept scene
// (Renderer::draw): a scene that stands still is drawn once more into a texture, upside down,
// and copied from it with its rows reversed, so that llvmpipe copies rows instead of drawing a
// textured quad; what reaches the target must be the scene as drawn directly. Opaque closed
// solids lose their back faces, and the water is a tint, not a drawn surface (water_view.h).
// Built only with the GUI (plimsoll_render); skipped where no headless OpenGL 4.5 context can
// be made.
#include "test_support.h"

#include "view/camera.h"
#include "headless_gl_test.h"
#include "render/renderer.h"
#include "view/water_view.h"

#include "plimsoll/geometry/validate.h"
#include "plimsoll/io/mesh_io.h"

#include <epoxy/gl.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>

namespace plimsoll::editor {
namespace test_editor_renderer_cache {
namespace {

struct Difference {
    std::size_t pixels = 0;  ///< pixels with any channel off by more than `tolerance`
    int largest = 0;         ///< the largest channel difference anywhere
};

Difference compare(const std::vector<std::uint8_t>& a, const std::vector<std::uint8_t>& b,
                   int tolerance) {
    Difference d;
    for (std::size_t p = 0; p + 3 < a.size(); p += 4) {
        int worst = 0;
        for (int c = 0; c < 3; ++c)
            worst = std::max(worst, std::abs(int(a[p + c]) - int(b[p + c])));
        d.largest = std::max(d.largest, worst);
        if (worst > tolerance) ++d.pixels;
    }
    return d;
}

/// A renderer in a headless OpenGL 4.5 context; the test is skipped where there is none.
class EditorRenderer : public test::HeadlessRendererTest {
protected:
    std::unique_ptr<OffscreenTarget> makeTarget(int width, int height) {
        Result<std::unique_ptr<OffscreenTarget>> t = OffscreenTarget::create(width, height);
        EXPECT_TRUE(t.ok()) << t.error().message;
        return t ? std::move(t).value() : nullptr;
    }
    /// The sample sphere, radius 0.5 about the origin (nullptr, with a failure, if unreadable).
    static std::shared_ptr<const TriangleMesh> sphere() {
        Result<TriangleMesh> mesh = loadMesh(test::assetPath("sphere.obj"));
        EXPECT_TRUE(mesh.ok()) << mesh.error().message;
        return mesh ? std::make_shared<const TriangleMesh>(std::move(mesh).value()) : nullptr;
    }
};

TEST_F(EditorRenderer, KeptSceneCopiesTheSamePixelsTheRightWayUp) {
    // Not a multiple of the rasteriser's 64-pixel tiles, and taller than wide.
    const int width = 200, height = 250;
    const std::unique_ptr<OffscreenTarget> target = makeTarget(width, height);
    ASSERT_TRUE(target);

    RenderScene scene;
    RenderBody body;
    body.mesh = sphere();
    ASSERT_TRUE(body.mesh);
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
        target->bind();
        glClearColor(0.0f, 0.0f, 0.0f, 1.0f);  // not the scene's background
        glClear(GL_COLOR_BUFFER_BIT);
        renderer->draw(scene, camera, width, height);
        return target->readRgba();
    };
    const std::vector<std::uint8_t> direct = drawOnce();  // a new scene: drawn
    const std::vector<std::uint8_t> kept = drawOnce();    // the same again: kept and copied
    const std::vector<std::uint8_t> copied = drawOnce();  // and again: copied only
    EXPECT_EQ(renderer->framesDrawn(), 2u);
    EXPECT_EQ(renderer->framesCopied(), 1u);

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
TEST_F(EditorRenderer, OpaqueClosedSolidsLoseOnlyTheBackFacesNoOneSees) {
    const int width = 160, height = 120;
    const std::unique_ptr<OffscreenTarget> target = makeTarget(width, height);
    ASSERT_TRUE(target);

    const std::shared_ptr<const TriangleMesh> ball = sphere();
    ASSERT_TRUE(ball);
    Camera camera;
    camera.distance = 3.0;
    camera.pitch = 0.35;
    camera.yaw = 0.4;
    // The open copy: the triangle farthest from the eye gone (behind the sphere's front).
    TriangleMesh open = *ball;
    const Eigen::Vector3d eye = camera.eye();
    auto centroidDistance = [&](const Triangle& t) {
        return ((open.positions[t[0]] + open.positions[t[1]] + open.positions[t[2]]) / 3.0 - eye)
            .norm();
    };
    open.triangles.erase(std::max_element(open.triangles.begin(), open.triangles.end(),
                                          [&](const Triangle& a, const Triangle& b) {
                                              return centroidDistance(a) < centroidDistance(b);
                                          }));
    ASSERT_TRUE(validateSurface(*ball).closedSolid());
    ASSERT_FALSE(validateSurface(open).closedSolid());

    auto draw = [&](const TriangleMesh& mesh, bool upsideDownToo) {
        RenderScene scene;  // no water, no grid: the body on its background
        scene.grid = scene.axes = false;
        RenderBody body;
        body.mesh = std::make_shared<const TriangleMesh>(mesh);
        scene.bodies.push_back(body);
        target->bind();
        renderer->draw(scene, camera, width, height);
        std::vector<std::uint8_t> image = target->readRgba();
        if (upsideDownToo) {
            // The same scene again is kept: drawn upside down, where the winding turns.
            target->bind();
            renderer->draw(scene, camera, width, height);
            EXPECT_LT(compare(target->readRgba(), image, 8).pixels,
                      std::size_t(width * height / 200));
        }
        return image;
    };
    auto drawBackground = [&] {
        RenderScene scene;
        scene.grid = scene.axes = false;
        target->bind();
        renderer->draw(scene, camera, width, height);
        return target->readRgba();
    };
    const std::vector<std::uint8_t> closedOutside = draw(*ball, true);
    const std::vector<std::uint8_t> openOutside = draw(open, true);
    const std::vector<std::uint8_t> background = drawBackground();
    EXPECT_GT(compare(closedOutside, background, 30).pixels, std::size_t(width * height / 20));
    EXPECT_EQ(compare(closedOutside, openOutside, 0).pixels, 0u);

    camera.distance = 0.2;  // the eye inside the sphere, 0.2 from its centre
    const std::vector<std::uint8_t> closedInside = draw(*ball, false);
    const std::vector<std::uint8_t> openInside = draw(open, false);
    const std::vector<std::uint8_t> backgroundInside = drawBackground();
    EXPECT_EQ(compare(closedInside, backgroundInside, 0).pixels, 0u);
    EXPECT_GT(compare(openInside, backgroundInside, 30).pixels, std::size_t(width * height / 2));
}

// The water is not drawn as a surface: the background is split at the horizon and whatever is
// seen through the water tints itself (water_view.h). Each pixel, cast as a ray at the exact
// sphere and the sky, must be what the C++ twin (WaterView) says: the image without water
// tinted as a sheet of water would tint it, or left as it is. Pixels next to a change of
// answer (the sphere's outline, its waterline, the horizon) are left out: the drawn sphere is
// a polyhedron.
TEST_F(EditorRenderer, WaterTintsExactlyWhatTheCppTwinSeesThroughIt) {
    const int width = 240, height = 160;
    const std::unique_ptr<OffscreenTarget> target = makeTarget(width, height);
    ASSERT_TRUE(target);
    const Eigen::Vector3d centre(0.2, -0.05, 0.1);
    RenderBody body;
    body.mesh = sphere();
    ASSERT_TRUE(body.mesh);
    body.pose.translation = centre;

    WaterModel flat = WaterModel::flat(0.1);
    WaterModel waves;
    waves.kind = WaterModel::Kind::Gerstner;
    waves.waves = {GerstnerWave{0.12, 2.5, {1.0, 0.3}, 0.5, 0.0}};
    struct Case {
        const char* name;
        const WaterModel* water;
        double pitch, targetY;
    };
    for (const Case& c :
         {Case{"flat, from above", &flat, 0.2, 0.0}, Case{"waves, from above", &waves, 0.25, 0.0},
          Case{"waves, from below", &waves, -0.2, -0.6}}) {
        SCOPED_TRACE(c.name);
        Camera camera;
        camera.distance = 3.0;
        camera.pitch = c.pitch;
        camera.yaw = 0.4;
        camera.target = Eigen::Vector3d(0.2, c.targetY, 0.1);
        RenderScene scene;
        scene.grid = scene.axes = false;
        scene.bodies.push_back(body);
        scene.time = 0.8;
        auto draw = [&](const WaterModel* water) {
            scene.water = water;
            target->bind();
            renderer->draw(scene, camera, width, height);
            return target->readRgba();
        };
        const std::vector<std::uint8_t> dry = draw(nullptr), wet = draw(c.water);

        const WaterView view = WaterView::of(*c.water, scene.time, camera);
        enum Answer { SkyPlain, SkyThrough, BodyPlain, BodyThrough };
        std::vector<Answer> answer(std::size_t(width) * height);
        for (int y = 0; y < height; ++y) {
            for (int x = 0; x < width; ++x) {
                Eigen::Vector3d origin, direction;
                camera.rayThrough(x + 0.5, y + 0.5, width, height, origin, direction);
                const Eigen::Vector3d o = origin - centre;
                const double b = o.dot(direction), disc = b * b - (o.squaredNorm() - 0.25);
                Answer& a = answer[std::size_t(y) * width + x];
                if (disc >= 0 && -b - std::sqrt(disc) > 0) {
                    a = view.seenThrough(origin + direction * (-b - std::sqrt(disc))) ? BodyThrough
                                                                                      : BodyPlain;
                } else {
                    a = view.backgroundSeenThrough(origin, direction) ? SkyThrough : SkyPlain;
                }
            }
        }
        std::size_t counted[4] = {}, wrong = 0;
        for (int y = 1; y + 1 < height; ++y) {
            for (int x = 1; x + 1 < width; ++x) {
                const Answer a = answer[std::size_t(y) * width + x];
                bool settled = true;
                for (int dy = -1; dy <= 1; ++dy) {
                    for (int dx = -1; dx <= 1; ++dx) {
                        settled = settled && answer[std::size_t(y + dy) * width + x + dx] == a;
                    }
                }
                if (!settled) continue;
                ++counted[a];
                const std::size_t p = (std::size_t(y) * width + x) * 4;
                const Eigen::Vector3f plain(dry[p] / 255.0f, dry[p + 1] / 255.0f,
                                            dry[p + 2] / 255.0f);
                const Eigen::Vector3f expected =
                    (a == SkyThrough || a == BodyThrough)
                        ? throughWater(plain, Renderer::kWaterColour, Renderer::kWaterOpacity)
                        : plain;
                for (int ch = 0; ch < 3; ++ch) {
                    if (std::abs(int(wet[p + ch]) - int(std::lround(expected[ch] * 255.0f))) > 2) {
                        ++wrong;
                        break;
                    }
                }
            }
        }
        EXPECT_EQ(wrong, 0u);
        // Each answer is in the picture: the sphere on both sides of its waterline, the
        // background on both sides of the horizon.
        for (std::size_t n : counted) EXPECT_GT(n, std::size_t(200));
    }
    // Drawn after a scene with water, the UV view's wireframe (the same line program, in UV
    // space, half of it below the water's height) is still plain white.
    const unsigned wireframe = renderer->uvWireframeTexture(body.mesh, 64);
    ASSERT_NE(wireframe, 0u);
    std::vector<std::uint8_t> texels(64 * 64 * 4);
    glBindTexture(GL_TEXTURE_2D, wireframe);
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    glGetTexImage(GL_TEXTURE_2D, 0, GL_RGBA, GL_UNSIGNED_BYTE, texels.data());
    std::size_t drawn = 0, tinted = 0;
    for (std::size_t p = 0; p < texels.size(); p += 4) {
        if (texels[p + 3] == 0) continue;
        ++drawn;
        if (texels[p] != texels[p + 2]) ++tinted;
    }
    EXPECT_GT(drawn, std::size_t(100));
    EXPECT_EQ(tinted, 0u);
}

}  // namespace
}  // namespace test_editor_renderer_cache
}  // namespace plimsoll::editor
