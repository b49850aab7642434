// WaterView: the water as the 3D view shows it (the C++ twin of water_view.frag). Its heights
// against the water model, its horizon against the camera's geometry, and which points the eye
// sees through the water, from above, from below and in orthographic views.
#include "view/water_view.h"

#include <gtest/gtest.h>

#include <cmath>

namespace plimsoll::editor {
namespace test_editor_water_view {
namespace {

WaterModel waves() {
    WaterModel w;
    w.kind = WaterModel::Kind::Gerstner;
    w.level = 0.2;
    w.waves = {GerstnerWave{0.3, 7.0, {1.0, 0.4}, 0.5, 0.3},
               GerstnerWave{0.1, 3.0, {-0.2, 1.0}, 0.3, 1.0}};
    return w;
}

Camera lookingDown(double pitch) {
    Camera c;
    c.target = Eigen::Vector3d(1.0, 0.0, -2.0);
    c.distance = 5.0;
    c.yaw = 0.7;
    c.pitch = pitch;
    return c;
}

TEST(WaterView, SurfaceNetJoinsTheSamplesAtTheModelsHeights) {
    // The net the renderer draws on waves: each sample joined to its neighbours along x and
    // z, every point at the wave function's height there (plus the lift asked for).
    const WaterModel water = waves();
    const double time = 0.6;
    const WaterView view = WaterView::of(water, time, lookingDown(0.4));
    const float lift = 0.25f;
    const std::vector<Eigen::Vector3f> net = view.surfaceSegments(lift);
    constexpr int n = WaterView::kCells + 1;
    ASSERT_EQ(net.size(), std::size_t(4) * WaterView::kCells * n);
    for (std::size_t k = 0; k < net.size(); ++k) {
        const Eigen::Vector3f& p = net[k];
        EXPECT_NEAR(p.y() - lift, water.height(p.x(), p.z(), time), 4e-6) << k;
        // On the sample grid.
        const double i = (p.x() - view.x0) / view.step, j = (p.z() - view.z0) / view.step;
        EXPECT_NEAR(i, std::round(i), 1e-4);
        EXPECT_NEAR(j, std::round(j), 1e-4);
    }
    for (std::size_t k = 0; k + 1 < net.size(); k += 2) {
        // Neighbours: one step apart along x or z.
        EXPECT_NEAR((net[k + 1] - net[k]).head<1>().norm() + std::abs(net[k + 1].z() - net[k].z()),
                    view.step, 1e-4);
    }
}

TEST(WaterView, HeightsAreTheModelsAtTheSamplesAndLinearBetween) {
    const WaterModel water = waves();
    const double time = 1.3;
    const WaterView view = WaterView::of(water, time, lookingDown(0.4));
    // The square: 3 distances (15 m) each side of the target, in 32 cells.
    EXPECT_DOUBLE_EQ(view.step, 30.0 / WaterView::kCells);
    EXPECT_DOUBLE_EQ(view.x0, 1.0 - 15.0);
    EXPECT_DOUBLE_EQ(view.z0, -2.0 - 15.0);
    for (int j = 0; j <= WaterView::kCells; j += 5) {
        for (int i = 0; i <= WaterView::kCells; i += 3) {
            const double x = view.x0 + i * view.step, z = view.z0 + j * view.step;
            // Single precision samples, and heights() sines in single precision.
            EXPECT_NEAR(view.heightAt(x, z), water.height(x, z, time), 2e-6) << i << ", " << j;
        }
    }
    // Inside a cell: on the plane of its triangle, whichever side of the diagonal.
    const double x = view.x0 + 7 * view.step, z = view.z0 + 11 * view.step;
    auto h = [&](int di, int dj) { return view.heightAt(x + di * view.step, z + dj * view.step); };
    EXPECT_NEAR(view.heightAt(x + 0.75 * view.step, z + 0.25 * view.step),
                h(0, 0) + 0.75 * (h(1, 0) - h(0, 0)) + 0.25 * (h(1, 1) - h(1, 0)), 1e-12);
    EXPECT_NEAR(view.heightAt(x + 0.25 * view.step, z + 0.75 * view.step),
                h(0, 0) + 0.75 * (h(0, 1) - h(0, 0)) + 0.25 * (h(1, 1) - h(0, 1)), 1e-12);
    // Beyond the square the edge's heights go on.
    EXPECT_DOUBLE_EQ(view.heightAt(view.x0 - 100.0, z), view.heightAt(view.x0, z));
    // Flat water: its level everywhere.
    const WaterView flat = WaterView::of(WaterModel::flat(-0.4), 0.0, lookingDown(0.4));
    EXPECT_NEAR(flat.heightAt(3.3, -1.7), -0.4, 1e-7);
}

TEST(WaterView, TheBackdropSplitsAtTheHorizon) {
    const int width = 300, height = 200;
    for (double pitch : {0.05, 0.2, 0.35}) {
        const Camera camera = lookingDown(pitch);
        const WaterView view = WaterView::of(waves(), 0.0, camera);
        ASSERT_FALSE(view.below(camera.eye()));
        // Seen from above the water, the horizon is tan(pitch) / tan(fov / 2) of the half
        // height above the centre: the sky above it, the water below.
        const double horizonRow =
            0.5 * height * (1.0 - std::tan(pitch) / std::tan(camera.fovY / 2));
        const WaterView::Backdrop b = view.backdrop(width, height);
        EXPECT_FALSE(b.topSeenThrough);
        EXPECT_NEAR(b.split, horizonRow, 1.0) << "pitch " << pitch;
    }
    // Looking down more steeply than half the field of view: water everywhere.
    const WaterView steep = WaterView::of(waves(), 0.0, lookingDown(0.6));
    const WaterView::Backdrop all = steep.backdrop(width, height);
    EXPECT_EQ(all.split, height);
    EXPECT_TRUE(all.topSeenThrough);

    // From below the surface, looking up a little: the surface above the horizon, seen from
    // under it; below the horizon, water on the eye's side (nothing seen through).
    Camera under = lookingDown(-0.2);
    under.target.y() = -3.0;
    const WaterView fromBelow = WaterView::of(waves(), 0.0, under);
    ASSERT_TRUE(fromBelow.below(under.eye()));
    const WaterView::Backdrop b = fromBelow.backdrop(width, height);
    EXPECT_TRUE(b.topSeenThrough);
    EXPECT_NEAR(b.split, 0.5 * height * (1.0 - std::tan(-0.2) / std::tan(under.fovY / 2)), 1.0);
}

TEST(WaterView, PointsAreSeenThroughTheWaterFromTheOtherSide) {
    const WaterModel flat = WaterModel::flat(0.0);
    const Camera above = lookingDown(0.4);
    const WaterView view = WaterView::of(flat, 0.0, above);
    EXPECT_TRUE(view.seenThrough({0.5, -0.1, 0.3}));
    EXPECT_FALSE(view.seenThrough({0.5, 0.1, 0.3}));

    Camera below = above;
    below.target.y() = -10.0;  // the eye 10 - 5 sin(0.4) m under water
    const WaterView fromBelow = WaterView::of(flat, 0.0, below);
    EXPECT_FALSE(fromBelow.seenThrough({0.5, -0.1, 0.3}));
    EXPECT_TRUE(fromBelow.seenThrough({0.5, 0.1, 0.3}));

    // Orthographic, looking level (the front view): lines of sight run along the water and
    // cross no surface, whatever the height.
    Camera front = lookingDown(0.0);
    front.orthographic = true;
    const WaterView level = WaterView::of(flat, 0.0, front);
    EXPECT_FALSE(level.seenThrough({0.5, -0.1, 0.3}));
    EXPECT_FALSE(level.seenThrough({0.5, 0.1, 0.3}));
    const WaterView::Backdrop side = level.backdrop(300, 200);
    EXPECT_EQ(side.split, 200);
    EXPECT_FALSE(side.topSeenThrough);
    // Orthographic from the top: everything under the water is seen through it.
    Camera top = lookingDown(1.5707963267948966);
    top.orthographic = true;
    const WaterView fromTop = WaterView::of(flat, 0.0, top);
    EXPECT_TRUE(fromTop.seenThrough({4.0, -0.1, 2.0}));
    EXPECT_FALSE(fromTop.seenThrough({4.0, 0.1, 2.0}));
    EXPECT_TRUE(fromTop.backdrop(300, 200).topSeenThrough);
    EXPECT_EQ(fromTop.backdrop(300, 200).split, 200);

    // On waves: a point just under a crest is seen through it, one just over a trough is not,
    // though the first is higher than the second.
    const WaterModel w = waves();
    const WaterView wavy = WaterView::of(w, 0.0, above);
    double crestX = 0, troughX = 0;
    for (double x = -3; x <= 3; x += 0.01) {
        if (wavy.heightAt(x, 0.0) > wavy.heightAt(crestX, 0.0)) crestX = x;
        if (wavy.heightAt(x, 0.0) < wavy.heightAt(troughX, 0.0)) troughX = x;
    }
    const Eigen::Vector3d underCrest(crestX, wavy.heightAt(crestX, 0.0) - 0.01, 0.0);
    const Eigen::Vector3d overTrough(troughX, wavy.heightAt(troughX, 0.0) + 0.01, 0.0);
    ASSERT_GT(underCrest.y(), overTrough.y());
    EXPECT_TRUE(wavy.seenThrough(underCrest));
    EXPECT_FALSE(wavy.seenThrough(overTrough));
}

}  // namespace
}  // namespace test_editor_water_view
}  // namespace plimsoll::editor
