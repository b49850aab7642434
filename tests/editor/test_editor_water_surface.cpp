// The water's surface as the 3D view draws it on waves: a net of the view's height samples
// (WaterView::surfaceSegments), drawn where the flat grid was. Read back from a headless
// OpenGL 4.5 image: in a front view the net's top edge in a sample's column lies at the wave
// function's height there. Skipped where no headless context can be made.
#include "headless_gl_test.h"
#include "render/renderer.h"
#include "view/camera.h"
#include "view/water_view.h"

#include <gtest/gtest.h>

#include <cmath>
#include <optional>

namespace plimsoll::editor {
namespace test_editor_water_surface {
namespace {

using EditorWaterSurface = test::HeadlessRendererTest;

/// A wave along x alone: every line of the net along x has the same profile, so a front view
/// shows that profile.
WaterModel waveAlongX() {
    WaterModel w;
    w.kind = WaterModel::Kind::Gerstner;
    w.waves = {GerstnerWave{0.4, 6.0, {1.0, 0.0}, 0.3, 0.7}};
    return w;
}

/// The net's colours (trough to crest blues): far bluer than the background, seen through the
/// water or not, and than the grey grid.
bool isNet(const std::uint8_t* p) { return p[2] > 130 && p[2] > p[0] + 50; }

TEST_F(EditorWaterSurface, FrontViewShowsTheWaveFunctionsHeightAtTheSamples) {
    const int width = 400, height = 300;
    Result<std::unique_ptr<OffscreenTarget>> target = OffscreenTarget::create(width, height);
    ASSERT_TRUE(target.ok()) << target.error().message;
    (*target)->bind();

    const WaterModel water = waveAlongX();
    const double time = 1.1;
    RenderScene scene;
    scene.water = &water;
    scene.time = time;
    scene.axes = false;
    Camera camera;  // front, orthographic: looking along -z
    camera.orthographic = true;
    camera.distance = 4.0;
    renderer->draw(scene, camera, width, height);
    const std::vector<std::uint8_t> rgba = (*target)->readRgba();

    const WaterView view = WaterView::of(water, time, camera);
    const double metresPerPixel = 2 * camera.distance * std::tan(camera.fovY / 2) / height;
    int columns = 0;
    double lowest = 1e9, highest = -1e9;
    for (int i = 0; i <= WaterView::kCells; ++i) {
        const double x = view.x0 + i * view.step;
        const double h = water.height(x, 0.0, time);
        const std::optional<Eigen::Vector2d> at = camera.toPixel({x, h, 0.0}, width, height);
        ASSERT_TRUE(at);
        const int column = static_cast<int>(at->x());
        if (column < 2 || column >= width - 2) continue;
        std::optional<int> top;
        for (int row = 0; row < height && !top; ++row) {
            if (isNet(&rgba[(std::size_t(row) * width + column) * 4])) top = row;
        }
        ASSERT_TRUE(top) << "no water surface drawn in column " << column << " (x = " << x << ")";
        // The topmost pixel of a one-pixel line through the sample: within its slope's reach.
        const double drawnHeight = h + (at->y() - (*top + 0.5)) * metresPerPixel;
        EXPECT_NEAR(drawnHeight, h, 2.5 * metresPerPixel) << "x = " << x;
        lowest = std::min(lowest, h);
        highest = std::max(highest, h);
        ++columns;
    }
    EXPECT_GE(columns, 4);
    // The columns cover crests and troughs, tens of pixels apart: not a flat line.
    EXPECT_GT(highest - lowest, 30 * metresPerPixel);
}

}  // namespace
}  // namespace test_editor_water_surface
}  // namespace plimsoll::editor
