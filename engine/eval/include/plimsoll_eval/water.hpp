// The water models a bundle carries (manifest "world.water", docs/bundle.md): a flat plane, a
// sum of Gerstner waves (deep-water dispersion) and a regular grid of heights (bilinear), in
// double precision, one point per call. The formulas are the engine's reference ones
// (engine/src/physics/water.cpp: the same fixed-point search of the undisplaced point, the same
// wave constants), written with the standard library only so that the runtime compiles them.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <vector>

namespace plimsoll_eval {

struct GerstnerWaveDesc {
    double amplitude = 0.1;    ///< m
    double wavelength = 10.0;  ///< m
    double directionX = 1.0, directionZ = 0.0;  ///< normalised on use
    double steepness = 0.5;    ///< Q in 0..1
    double phase = 0.0;        ///< rad
};

struct HeightGridDesc {
    int countX = 0, countZ = 0;
    double spacing = 1.0;               ///< m
    double originX = 0.0, originZ = 0.0;
    std::vector<float> heights;         ///< countX * countZ, row j = fixed z, relative to level
};

struct WaterModelDesc {
    enum class Kind { Flat, Gerstner, HeightGrid };
    Kind kind = Kind::Flat;
    double level = 0.0;
    std::vector<GerstnerWaveDesc> waves;
    HeightGridDesc grid;
    double gravity = 9.81;              ///< for the dispersion relation, m/s^2
};

namespace water_detail {

struct WaveTerms {
    double k, omega, q, dx, dz;
};

inline WaveTerms termsOf(const GerstnerWaveDesc& w, double gravity, std::size_t count) {
    constexpr double kPi = 3.14159265358979323846;
    WaveTerms t;
    t.k = 2.0 * kPi / w.wavelength;
    t.omega = std::sqrt(gravity * t.k);
    t.q = w.amplitude > 0 ? w.steepness / (t.k * w.amplitude * static_cast<double>(count)) : 0.0;
    const double n = std::sqrt(w.directionX * w.directionX + w.directionZ * w.directionZ);
    t.dx = n > 0 ? w.directionX / n : 1.0;
    t.dz = n > 0 ? w.directionZ / n : 0.0;
    return t;
}

/// Three fixed-point steps x0 <- x + sum Q A D sin(theta(x0)): the undisplaced point whose
/// surface point lies above (x, z).
inline void undisplaced(const WaterModelDesc& water, const std::vector<WaveTerms>& terms, double x,
                        double z, double time, double& x0, double& z0) {
    x0 = x;
    z0 = z;
    for (int iteration = 0; iteration < 3; ++iteration) {
        double sx = 0, sz = 0;
        for (std::size_t i = 0; i < water.waves.size(); ++i) {
            const GerstnerWaveDesc& w = water.waves[i];
            const WaveTerms& t = terms[i];
            const double theta = t.k * (t.dx * x0 + t.dz * z0) - t.omega * time + w.phase;
            const double s = t.q * w.amplitude * std::sin(theta);
            sx += s * t.dx;
            sz += s * t.dz;
        }
        x0 = x + sx;
        z0 = z + sz;
    }
}

inline double gridHeight(const HeightGridDesc& grid, double x, double z) {
    if (grid.countX == 0 || grid.countZ == 0) return 0.0;
    const double gx = (x - grid.originX) / grid.spacing;
    const double gz = (z - grid.originZ) / grid.spacing;
    const double fx = gx - std::floor(gx), fz = gz - std::floor(gz);
    auto at = [&](double i, double j) {
        const int ci = std::clamp(static_cast<int>(i), 0, grid.countX - 1);
        const int cj = std::clamp(static_cast<int>(j), 0, grid.countZ - 1);
        return static_cast<double>(grid.heights[static_cast<std::size_t>(cj) * grid.countX + ci]);
    };
    const double i0 = std::clamp(std::floor(gx), -1.0, static_cast<double>(grid.countX));
    const double j0 = std::clamp(std::floor(gz), -1.0, static_cast<double>(grid.countZ));
    return (1 - fz) * ((1 - fx) * at(i0, j0) + fx * at(i0 + 1, j0)) +
           fz * ((1 - fx) * at(i0, j0 + 1) + fx * at(i0 + 1, j0 + 1));
}

}  // namespace water_detail

/// The wave constants of a model, worked out once (they depend on nothing else).
inline std::vector<water_detail::WaveTerms> waveTerms(const WaterModelDesc& water) {
    std::vector<water_detail::WaveTerms> terms;
    terms.reserve(water.waves.size());
    for (const GerstnerWaveDesc& w : water.waves)
        terms.push_back(water_detail::termsOf(w, water.gravity, water.waves.size()));
    return terms;
}

/// Surface height at (x, z) and time t; `terms` from waveTerms(water).
inline double waterHeight(const WaterModelDesc& water, const std::vector<water_detail::WaveTerms>& terms,
                          double x, double z, double time) {
    switch (water.kind) {
        case WaterModelDesc::Kind::Flat:
            return water.level;
        case WaterModelDesc::Kind::HeightGrid:
            return water.level + water_detail::gridHeight(water.grid, x, z);
        case WaterModelDesc::Kind::Gerstner: {
            double x0 = x, z0 = z;
            water_detail::undisplaced(water, terms, x, z, time, x0, z0);
            double y = water.level;
            for (std::size_t i = 0; i < water.waves.size(); ++i) {
                const GerstnerWaveDesc& w = water.waves[i];
                const water_detail::WaveTerms& t = terms[i];
                y += w.amplitude * std::cos(t.k * (t.dx * x0 + t.dz * z0) - t.omega * time + w.phase);
            }
            return y;
        }
    }
    return water.level;
}

/// The water's velocity at a point: Gerstner orbital velocity decaying as e^(k d) below the
/// mean level; zero for the plane and the grid.
inline void waterVelocity(const WaterModelDesc& water, const std::vector<water_detail::WaveTerms>& terms,
                          double px, double py, double pz, double time, double out[3]) {
    out[0] = out[1] = out[2] = 0.0;
    if (water.kind != WaterModelDesc::Kind::Gerstner) return;
    double x0 = px, z0 = pz;
    water_detail::undisplaced(water, terms, px, pz, time, x0, z0);
    for (std::size_t i = 0; i < water.waves.size(); ++i) {
        const GerstnerWaveDesc& w = water.waves[i];
        const water_detail::WaveTerms& t = terms[i];
        const double theta = t.k * (t.dx * x0 + t.dz * z0) - t.omega * time + w.phase;
        const double decay = std::exp(t.k * std::min(0.0, py - water.level));
        const double horizontal = t.q * w.amplitude * t.omega * std::cos(theta) * decay;
        out[0] += horizontal * t.dx;
        out[1] += w.amplitude * t.omega * std::sin(theta) * decay;
        out[2] += horizontal * t.dz;
    }
}

/// Highest and lowest surface height.
inline double waterMaxHeight(const WaterModelDesc& water) {
    switch (water.kind) {
        case WaterModelDesc::Kind::Flat:
            return water.level;
        case WaterModelDesc::Kind::Gerstner: {
            double sum = 0;
            for (const GerstnerWaveDesc& w : water.waves) sum += std::abs(w.amplitude);
            return water.level + sum;
        }
        case WaterModelDesc::Kind::HeightGrid:
            return water.grid.heights.empty()
                       ? water.level
                       : water.level + *std::max_element(water.grid.heights.begin(), water.grid.heights.end());
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
                       : water.level + *std::min_element(water.grid.heights.begin(), water.grid.heights.end());
    }
    return water.level;
}

}  // namespace plimsoll_eval
