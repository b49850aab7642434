// Water models: flat, Gerstner (dispersion, the fixed-point surface search, orbital velocity),
// and the sampled grid.
#include "plimsoll/physics/water.h"
#include "physics/gerstner_batch.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <vector>

namespace plimsoll {
namespace test_water {
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
    const double deep =
        water.velocity({x, -5.0, 0.0}, t).y() / water.velocity({x, 0.0, 0.0}, t).y();
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
    EXPECT_NEAR(water.height(-1e6, -1e6, 0), 1.0, 1e-6);            // corner (0, 0)
    EXPECT_NEAR(water.height(1e6, 1e6, 0), 1.0 + 0.3 + 0.4, 1e-6);  // corner (3, 2)
    EXPECT_NEAR(water.maxHeight(), 1.7, 1e-6);
    EXPECT_NEAR(water.minHeight(), 1.0, 1e-6);
}

}  // namespace
}  // namespace test_water
}  // namespace plimsoll

namespace plimsoll {
namespace test_water {
namespace {

/// The batched heights and velocities against the one-point reference (the test below).
void expectBatchesEqualTheReference() {
    WaterModel water = twoWaves();
    for (int waves : {2, kMaxGerstnerWaves + 1}) {
        while (static_cast<int>(water.waves.size()) < waves)
            water.waves.push_back(
                {0.02,
                 1.5 + 0.3 * static_cast<double>(water.waves.size()),
                 {std::cos(1.0 * water.waves.size()), std::sin(1.0 * water.waves.size())},
                 0.3,
                 0.1 * static_cast<double>(water.waves.size())});
        double amplitudes = 0, speeds = 0;
        for (const GerstnerWave& w : water.waves) {
            amplitudes += w.amplitude;
            speeds += w.amplitude * std::sqrt(water.gravity * 2 * std::numbers::pi / w.wavelength);
        }
        for (std::size_t n :
             {std::size_t(1), std::size_t(7), std::size_t(8), std::size_t(16), std::size_t(37)}) {
            for (double offset : {0.0, 2500.0}) {
                for (double t : {0.0, 1.3, 86400.0}) {
                    std::vector<double> x(n), y(n), z(n), h(n), v(3 * n);
                    for (std::size_t i = 0; i < n; ++i) {
                        x[i] = offset + 0.37 * static_cast<double>(i) - 3.0;
                        z[i] = -offset + 0.21 * static_cast<double>(i * i % 11);
                        y[i] = water.level + 0.8 - 0.2 * static_cast<double>(i % 9);
                    }
                    water.heights(n, x.data(), z.data(), t, h.data());
                    water.velocities(n, x.data(), y.data(), z.data(), t, v.data());
                    for (std::size_t i = 0; i < n; ++i) {
                        EXPECT_NEAR(h[i], water.height(x[i], z[i], t), 2e-6 * amplitudes)
                            << "point " << i << " of " << n << ", t " << t << ", offset " << offset;
                        const Eigen::Vector3d reference = water.velocity({x[i], y[i], z[i]}, t);
                        EXPECT_LT(
                            (Eigen::Vector3d(v[3 * i], v[3 * i + 1], v[3 * i + 2]) - reference)
                                .norm(),
                            2e-6 * speeds)
                            << "point " << i << " of " << n << ", t " << t << ", offset " << offset;
                    }
                }
            }
        }
    }
}

// The batched queries the fast path makes equal the one-point reference within the precision
// of their single-precision sines and cosines, in every build this processor runs (baseline,
// AVX2, AVX-512: blocks of 4, 8 and 16 points): far from the origin, late in time, above and
// below the mean level, for any count (whole blocks of points and a partial last one), and
// for more waves than the inline table holds. A dropped or misplaced lane, or a phase not
// reduced before the single-precision trigonometry, shows as an error of order the amplitude.
TEST(Water, BatchedHeightsAndVelocitiesEqualTheOnePointReference) {
    const detail::GerstnerIsa widest = detail::gerstnerBatchWidest();
    for (int isa = 0; isa <= static_cast<int>(widest); ++isa) {
        SCOPED_TRACE("instruction set " + std::to_string(isa) + " (0 baseline, 1 AVX2, 2 AVX-512)");
        detail::setGerstnerBatchIsa(static_cast<detail::GerstnerIsa>(isa));
        expectBatchesEqualTheReference();
    }
    detail::setGerstnerBatchIsa(widest);
    // Flat water: the plane and no motion, through the same calls.
    const WaterModel flat = WaterModel::flat(-0.4);
    double x = 3, z = 4, y = -2, h = 0, v[3] = {1, 1, 1};
    flat.heights(1, &x, &z, 0.0, &h);
    flat.velocities(1, &x, &y, &z, 0.0, v);
    EXPECT_EQ(h, -0.4);
    EXPECT_EQ(Eigen::Vector3d(v[0], v[1], v[2]), Eigen::Vector3d::Zero());
}

}  // namespace
}  // namespace test_water
}  // namespace plimsoll
