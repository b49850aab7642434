// Water models: flat, Gerstner (dispersion, the fixed-point surface search, orbital velocity),
// and the sampled grid.
#include "plimsoll/physics/water.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

namespace plimsoll {
namespace {

WaterModel twoWaves() {
    WaterModel water;
    water.kind = WaterModel::Kind::Gerstner;
    water.level = 0.3;
    water.waves = {{0.4, 12.0, {1.0, 0.2}, 0.7, 0.5}, {0.15, 5.0, {-0.3, 1.0}, 0.6, 2.0}};
    return water;
}

TEST(Water, FlatIsFlatAndStill) {
    const WaterModel water = WaterModel::flat(-1.5);
    EXPECT_EQ(water.height(1e5, -3.0, 7.0), -1.5);
    EXPECT_EQ(water.velocity({1, -4, 2}, 3.0), Eigen::Vector3d::Zero());
    EXPECT_EQ(water.maxHeight(), -1.5);
}

// The height found above (x, z) must be the height of the Gerstner particle that sits there:
// displace the undisplaced point the search found and compare.
TEST(Water, GerstnerHeightIsTheSurfaceAboveThePoint) {
    const WaterModel water = twoWaves();
    for (double x : {-7.0, 0.0, 3.3, 100.0}) {
        for (double t : {0.0, 1.7}) {
            const double f = water.height(x, 2.0, t);
            EXPECT_LE(f, water.maxHeight());
            EXPECT_GE(f, water.minHeight());
            // Brute force: scan undisplaced positions for the one displaced onto (x, 2).
            double best = 1e9, bestHeight = 0;
            for (double x0 = x - 1.0; x0 <= x + 1.0; x0 += 1e-3) {
                for (double z0 = 1.0; z0 <= 3.0; z0 += 1e-2) {
                    double px = x0, pz = z0, py = water.level;
                    for (const GerstnerWave& w : water.waves) {
                        const double k = 2 * std::numbers::pi / w.wavelength;
                        const Eigen::Vector2d d = w.direction.normalized();
                        const double theta = k * (d.x() * x0 + d.y() * z0) -
                                             std::sqrt(water.gravity * k) * t + w.phase;
                        const double q = w.steepness / (k * w.amplitude * water.waves.size());
                        px -= q * w.amplitude * d.x() * std::sin(theta);
                        pz -= q * w.amplitude * d.y() * std::sin(theta);
                        py += w.amplitude * std::cos(theta);
                    }
                    const double miss = std::hypot(px - x, pz - 2.0);
                    if (miss < best) {
                        best = miss;
                        bestHeight = py;
                    }
                }
            }
            EXPECT_NEAR(f, bestHeight, 2e-2) << "x " << x << " t " << t;
        }
    }
}

TEST(Water, GerstnerDispersionAndOrbitalVelocity) {
    WaterModel water;
    water.kind = WaterModel::Kind::Gerstner;
    water.waves = {{0.5, 20.0, {1.0, 0.0}, 0.0, 0.0}};  // steepness 0: a plain sine wave
    const double k = 2 * std::numbers::pi / 20.0;
    const double omega = std::sqrt(9.81 * k);
    // The crest moves at the deep-water phase speed omega / k.
    const double t = 1.3;
    EXPECT_NEAR(water.height(omega / k * t, 0.0, t), 0.5, 1e-12);
    // The vertical surface velocity is the time derivative of the height.
    const double x = 3.0, dt = 1e-6;
    const double dhdt = (water.height(x, 0, t + dt) - water.height(x, 0, t - dt)) / (2 * dt);
    EXPECT_NEAR(water.velocity({x, 0.0, 0.0}, t).y(), dhdt, 1e-6);
    // Decays as e^(k d) with depth d below the mean level.
    const double deep = water.velocity({x, -5.0, 0.0}, t).y() / water.velocity({x, 0.0, 0.0}, t).y();
    EXPECT_NEAR(deep, std::exp(-k * 5.0), 1e-9);
}

TEST(Water, HeightGridIsBilinearAndClampedAtItsEdges) {
    WaterModel water;
    water.kind = WaterModel::Kind::HeightField;
    water.level = 1.0;
    water.grid.countX = 4;
    water.grid.countZ = 3;
    water.grid.spacing = 2.0;
    water.grid.origin = {-1.0, 5.0};
    // A plane h = 0.1 i + 0.2 j: bilinear interpolation reproduces it exactly.
    for (int j = 0; j < 3; ++j)
        for (int i = 0; i < 4; ++i) water.grid.heights.push_back(0.1f * i + 0.2f * j);
    const double x = -1.0 + 2.0 * 1.3, z = 5.0 + 2.0 * 0.6;
    EXPECT_NEAR(water.height(x, z, 0), 1.0 + 0.1 * 1.3 + 0.2 * 0.6, 1e-6);
    EXPECT_NEAR(water.height(-1e6, -1e6, 0), 1.0, 1e-6);          // corner (0, 0)
    EXPECT_NEAR(water.height(1e6, 1e6, 0), 1.0 + 0.3 + 0.4, 1e-6);  // corner (3, 2)
    EXPECT_NEAR(water.maxHeight(), 1.7, 1e-6);
    EXPECT_NEAR(water.minHeight(), 1.0, 1e-6);
}

}  // namespace
}  // namespace plimsoll
