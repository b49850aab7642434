// Water surface models: a height field y = f(x, z, t) with the water's own velocity below it.
// One description serves the C++ reference and the OpenCL kernels (which receive it relative
// to each body, see compute.h). Flat plane, a sum of Gerstner waves (deep-water dispersion), or
// a sampled grid (bilinear).
#pragma once

#include <Eigen/Core>

#include <vector>

namespace plimsoll {

inline constexpr int kMaxGerstnerWaves = 16;
inline constexpr double kStandardGravity = 9.81;  ///< m/s^2

/// One Gerstner wave. Phase speed from deep-water dispersion: omega^2 = g k.
struct GerstnerWave {
    double amplitude = 0.1;               ///< m
    double wavelength = 10.0;             ///< m (k = 2 pi / wavelength)
    Eigen::Vector2d direction{1.0, 0.0};  ///< (x, z), normalised on use
    double steepness = 0.5;               ///< Q in 0..1: 0 = sine wave, 1 = sharp crests
    double phase = 0.0;                   ///< rad

    bool operator==(const GerstnerWave&) const = default;
};

/// A regular grid of heights: height(i, j) at (origin.x + i spacing, origin.y + j spacing),
/// i along x, j along z; clamped at the edges. The water does not move horizontally.
struct HeightGrid {
    int countX = 0, countZ = 0;
    double spacing = 1.0;                              ///< m
    Eigen::Vector2d origin = Eigen::Vector2d::Zero();  ///< (x, z) of sample (0, 0), m
    std::vector<float> heights;                        ///< countX * countZ, row j = fixed z, m

    bool operator==(const HeightGrid&) const = default;
};

struct WaterModel {
    enum class Kind { Flat, Gerstner, HeightField };
    Kind kind = Kind::Flat;
    double level = 0.0;                 ///< mean surface height, m (all kinds)
    std::vector<GerstnerWave> waves;    ///< Gerstner: up to kMaxGerstnerWaves
    HeightGrid grid;                    ///< HeightField: heights relative to `level`
    double gravity = kStandardGravity;  ///< for the dispersion relation, m/s^2

    static WaterModel flat(double level) { return WaterModel{Kind::Flat, level, {}, {}}; }
    bool operator==(const WaterModel&) const = default;

    /// Surface height f(x, z, t) (m). For Gerstner waves the surface point above (x, z) is
    /// found by a fixed-point search of the undisplaced position (the waves move water
    /// sideways), the same three iterations as the kernels.
    double height(double x, double z, double time) const;

    /// Velocity of the water at a point (m/s): Gerstner orbital velocity, decaying as e^(k d)
    /// with depth d below the mean level; zero for the flat plane and the grid.
    Eigen::Vector3d velocity(const Eigen::Vector3d& point, double time) const;
    /// height() at n points in one call (out[i]); for Gerstner waves vectorised, with the
    /// phases' sines and cosines in single precision (a few 1e-7 of the amplitudes from
    /// height(); src/physics/gerstner_batch.h). What the fast CPU path samples.
    void heights(std::size_t n, const double* x, const double* z, double time, double* out) const;
    /// velocity() at n points in one call (out[3 i + 0..2]), vectorised as heights().
    void velocities(std::size_t n, const double* x, const double* y, const double* z, double time,
                    double* out) const;

    /// Highest and lowest possible surface height (bounds for culling whole tiles).
    double maxHeight() const;
    double minHeight() const;
};

}  // namespace plimsoll
