// The water models, one C++ reference for each formula: a flat plane, a sum of Gerstner waves
// (deep-water dispersion) and a regular grid of heights (bilinear), in double precision, one
// point per call, with the standard library only. The engine's scalar models
// (plimsoll::WaterModel::height / velocity, engine/src/physics/water.cpp) and the runtime's
// (plimsoll_runtime::WaterModel, the manifest's "world.water", docs/bundle.md) both call the
// functions below, so the two give the same bits. The engine's vectorised batch
// (gerstner_batch.h, single-precision phases) is held to these within a stated bound
// (tests/physics/test_water.cpp), and kernels/buoyancy.cl mirrors them line for line.
#pragma once

#include "plimsoll_eval/portable_math.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <vector>

namespace plimsoll_eval {

struct GerstnerWaveDesc {
    double amplitude = 0.1;                     ///< m
    double wavelength = 10.0;                   ///< m
    double directionX = 1.0, directionZ = 0.0;  ///< normalised on use
    double steepness = 0.5;                     ///< Q in 0..1
    double phase = 0.0;                         ///< rad
};

struct HeightGridDesc {
    int countX = 0, countZ = 0;
    double spacing = 1.0;  ///< m
    double originX = 0.0, originZ = 0.0;
    std::vector<float> heights;  ///< countX * countZ, row j = fixed z, relative to level
};

struct WaterModelDesc {
    enum class Kind { Flat, Gerstner, HeightGrid };
    Kind kind = Kind::Flat;
    double level = 0.0;
    std::vector<GerstnerWaveDesc> waves;
    HeightGridDesc grid;
    double gravity = 9.81;  ///< for the dispersion relation, m/s^2
};

namespace water_detail {

/// One wave as the formulas use it: wavenumber k (rad/m), angular frequency omega (rad/s;
/// deep water, omega^2 = g k), the horizontal displacement factor q = steepness / (k A n) that
/// keeps the summed surface free of loops for steepness <= 1 (GPU Gems 1, ch. 1), the unit
/// direction (dx, dz), the amplitude (m) and the phase (rad).
struct WaveTerms {
    double k, omega, q, dx, dz;
    double amplitude, phase;
};

/// A wave's terms, one of `count` waves.
inline WaveTerms termsOf(double amplitude, double wavelength, double directionX, double directionZ,
                         double steepness, double phase, double gravity, std::size_t count) {
    constexpr double kPi = 3.14159265358979323846;
    WaveTerms t;
    t.k = 2.0 * kPi / wavelength;
    t.omega = std::sqrt(gravity * t.k);
    t.q = amplitude > 0 ? steepness / (t.k * amplitude * static_cast<double>(count)) : 0.0;
    const double n = std::sqrt(directionX * directionX + directionZ * directionZ);
    t.dx = n > 0 ? directionX / n : 1.0;
    t.dz = n > 0 ? directionZ / n : 0.0;
    t.amplitude = amplitude;
    t.phase = phase;
    return t;
}

inline WaveTerms termsOf(const GerstnerWaveDesc& w, double gravity, std::size_t count) {
    return termsOf(w.amplitude, w.wavelength, w.directionX, w.directionZ, w.steepness, w.phase,
                   gravity, count);
}

/// The phase theta = k (D . x0) - omega t + phase of wave t at the undisplaced point (x0, z0).
inline double phaseAt(const WaveTerms& t, double x0, double z0, double time) {
    return t.k * (t.dx * x0 + t.dz * z0) - t.omega * time + t.phase;
}

/// Three fixed-point steps x0 <- x + sum Q A D sin(theta(x0)) (contracting for steepness < 1):
/// the undisplaced point whose surface point lies above (x, z).
inline void undisplaced(const WaveTerms* terms, std::size_t count, double x, double z, double time,
                        double& x0, double& z0) {
    x0 = x;
    z0 = z;
    for (int iteration = 0; iteration < 3; ++iteration) {
        double sx = 0, sz = 0;
        for (std::size_t i = 0; i < count; ++i) {
            const WaveTerms& t = terms[i];
            const double s = t.q * t.amplitude * math::sin(phaseAt(t, x0, z0, time));
            sx += s * t.dx;
            sz += s * t.dz;
        }
        x0 = x + sx;
        z0 = z + sz;
    }
}

/// Gerstner surface height above (x, z) at time t: level + sum A cos(theta(x0)).
inline double gerstnerHeight(const WaveTerms* terms, std::size_t count, double level, double x,
                             double z, double time) {
    double x0 = x, z0 = z;
    undisplaced(terms, count, x, z, time, x0, z0);
    double y = level;
    for (std::size_t i = 0; i < count; ++i)
        y += terms[i].amplitude * math::cos(phaseAt(terms[i], x0, z0, time));
    return y;
}

/// Gerstner orbital velocity at a point (m/s into out[0..2]), decaying as e^(k d) with the
/// depth d below the mean level.
inline void gerstnerVelocity(const WaveTerms* terms, std::size_t count, double level, double px,
                             double py, double pz, double time, double out[3]) {
    out[0] = out[1] = out[2] = 0.0;
    double x0 = px, z0 = pz;
    undisplaced(terms, count, px, pz, time, x0, z0);
    for (std::size_t i = 0; i < count; ++i) {
        const WaveTerms& t = terms[i];
        const double theta = phaseAt(t, x0, z0, time);
        const double decay = math::exp(t.k * std::min(0.0, py - level));
        const double horizontal = t.q * t.amplitude * t.omega * math::cos(theta) * decay;
        out[0] += horizontal * t.dx;
        out[1] += t.amplitude * t.omega * math::sin(theta) * decay;
        out[2] += horizontal * t.dz;
    }
}

/// Bilinear height of a grid (heights[j * countX + i] at (originX + i spacing, originZ + j
/// spacing)), clamped at the edges; 0 for an empty grid.
inline double gridHeight(const float* heights, int countX, int countZ, double spacing,
                         double originX, double originZ, double x, double z) {
    if (countX == 0 || countZ == 0) return 0.0;
    const double gx = (x - originX) / spacing;
    const double gz = (z - originZ) / spacing;
    const double fx = gx - std::floor(gx), fz = gz - std::floor(gz);
    auto at = [&](double i, double j) {
        const int ci = std::clamp(static_cast<int>(i), 0, countX - 1);
        const int cj = std::clamp(static_cast<int>(j), 0, countZ - 1);
        return static_cast<double>(heights[static_cast<std::size_t>(cj) * countX + ci]);
    };
    // Clamp the cell index in floating point first: far outside the grid the edge value holds.
    const double i0 = std::clamp(std::floor(gx), -1.0, static_cast<double>(countX));
    const double j0 = std::clamp(std::floor(gz), -1.0, static_cast<double>(countZ));
    return (1 - fz) * ((1 - fx) * at(i0, j0) + fx * at(i0 + 1, j0)) +
           fz * ((1 - fx) * at(i0, j0 + 1) + fx * at(i0 + 1, j0 + 1));
}

inline double gridHeight(const HeightGridDesc& grid, double x, double z) {
    return gridHeight(grid.heights.data(), grid.countX, grid.countZ, grid.spacing, grid.originX,
                      grid.originZ, x, z);
}

/// The highest surface of waves of these amplitudes above the level: sum |A|.
template <class Waves>
double amplitudeSum(const Waves& waves) {
    double sum = 0;
    for (const auto& w : waves) sum += std::abs(w.amplitude);
    return sum;
}

}  // namespace water_detail

/// Every wave's terms, on the stack for up to kInline waves (no allocation per query).
class WaveTable {
public:
    static constexpr std::size_t kInline = 16;

    /// `waves`: anything with amplitude, wavelength, steepness and phase per wave;
    /// direction(w, x, z) gives a wave's direction.
    template <class Waves, class Direction>
    WaveTable(const Waves& waves, double gravity, Direction&& direction) : count_(waves.size()) {
        if (count_ > kInline) spill_.resize(count_);
        water_detail::WaveTerms* out = count_ > kInline ? spill_.data() : inline_;
        std::size_t i = 0;
        for (const auto& w : waves) {
            double x = 1.0, z = 0.0;
            direction(w, x, z);
            out[i++] = water_detail::termsOf(w.amplitude, w.wavelength, x, z, w.steepness, w.phase,
                                             gravity, count_);
        }
    }
    const water_detail::WaveTerms* data() const {
        return count_ > kInline ? spill_.data() : inline_;
    }
    std::size_t size() const { return count_; }
    const water_detail::WaveTerms& operator[](std::size_t i) const { return data()[i]; }

private:
    std::size_t count_;
    water_detail::WaveTerms inline_[kInline];
    std::vector<water_detail::WaveTerms> spill_;
};

/// The wave constants of a model, worked out once (they depend on nothing else).
inline std::vector<water_detail::WaveTerms> waveTerms(const WaterModelDesc& water) {
    std::vector<water_detail::WaveTerms> terms;
    terms.reserve(water.waves.size());
    for (const GerstnerWaveDesc& w : water.waves)
        terms.push_back(water_detail::termsOf(w, water.gravity, water.waves.size()));
    return terms;
}

/// Surface height at (x, z) and time t; `terms` from waveTerms(water).
inline double waterHeight(const WaterModelDesc& water,
                          const std::vector<water_detail::WaveTerms>& terms, double x, double z,
                          double time) {
    switch (water.kind) {
        case WaterModelDesc::Kind::Flat:
            return water.level;
        case WaterModelDesc::Kind::HeightGrid:
            return water.level + water_detail::gridHeight(water.grid, x, z);
        case WaterModelDesc::Kind::Gerstner:
            return water_detail::gerstnerHeight(terms.data(), terms.size(), water.level, x, z,
                                                time);
    }
    return water.level;
}

/// The water's velocity at a point: Gerstner orbital velocity decaying as e^(k d) below the
/// mean level; zero for the plane and the grid.
inline void waterVelocity(const WaterModelDesc& water,
                          const std::vector<water_detail::WaveTerms>& terms, double px, double py,
                          double pz, double time, double out[3]) {
    out[0] = out[1] = out[2] = 0.0;
    if (water.kind != WaterModelDesc::Kind::Gerstner) return;
    water_detail::gerstnerVelocity(terms.data(), terms.size(), water.level, px, py, pz, time, out);
}

/// Highest and lowest surface height.
inline double waterMaxHeight(const WaterModelDesc& water) {
    switch (water.kind) {
        case WaterModelDesc::Kind::Flat:
            return water.level;
        case WaterModelDesc::Kind::Gerstner:
            return water.level + water_detail::amplitudeSum(water.waves);
        case WaterModelDesc::Kind::HeightGrid:
            return water.grid.heights.empty()
                       ? water.level
                       : water.level + *std::max_element(water.grid.heights.begin(),
                                                         water.grid.heights.end());
    }
    return water.level;
}

inline double waterMinHeight(const WaterModelDesc& water) {
    switch (water.kind) {
        case WaterModelDesc::Kind::Flat:
            return water.level;
        case WaterModelDesc::Kind::Gerstner:
            return 2.0 * water.level - waterMaxHeight(water);
        case WaterModelDesc::Kind::HeightGrid:
            return water.grid.heights.empty()
                       ? water.level
                       : water.level + *std::min_element(water.grid.heights.begin(),
                                                         water.grid.heights.end());
    }
    return water.level;
}

}  // namespace plimsoll_eval
