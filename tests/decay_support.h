// Free heave decays against the frequency-domain coefficients: what A(omega) and B(omega) of a
// panel solution predict for the damped period and the logarithmic decrement, and both measured
// from a sampled record of the heave. Shared by the Cummins tests on the bare rigid body and
// through the World.
#pragma once

#include "plimsoll/physics/radiation.h"

#include <cmath>
#include <complex>
#include <functional>
#include <utility>
#include <numbers>
#include <vector>

namespace plimsoll::test {

struct DecayFigures {
    double period = 0;        ///< s
    double logDecrement = 0;  ///< ln of the ratio of peaks one period apart
};

/// Heave added mass and damping at a frequency (rad/s): {A, B}.
using HeaveCoefficients = std::function<std::pair<double, double>(double omega)>;

/// The damped period and log decrement that A and B predict for a body of `mass` (kg) on a
/// heave stiffness `stiffness` (N/m): the root of
///   C - w^2 (m + A(w)) + i w B(w) = 0
/// near the natural frequency, A and B continued into complex w by their slopes there (central
/// differences). The slope matters: the decaying oscillation samples A and B a little off the
/// real axis, and for the hemisphere that adds 13% to the damping that B(w_n) alone would give.
/// `naturalFrequency`, if given, receives w_n (rad/s).
inline DecayFigures predictedHeaveDecay(const HeaveCoefficients& coefficients, double mass, double stiffness,
                                        double* naturalFrequency = nullptr) {
    double omega = std::sqrt(stiffness / mass);
    std::pair<double, double> at;
    for (int iteration = 0; iteration < 6; ++iteration) {
        at = coefficients(omega);
        omega = std::sqrt(stiffness / (mass + at.first));
    }
    if (naturalFrequency) *naturalFrequency = omega;
    const double h = 0.03 * omega;
    const std::pair<double, double> below = coefficients(omega - h), above = coefficients(omega + h);
    const double a0 = at.first, b0 = at.second;
    const double a1 = (above.first - below.first) / (2 * h);
    const double b1 = (above.second - below.second) / (2 * h);
    using Complex = std::complex<double>;
    auto residual = [&](Complex w) {
        return stiffness - w * w * (mass + a0 + a1 * (w - omega)) + Complex(0, 1) * w * (b0 + b1 * (w - omega));
    };
    Complex root(omega, 0.5 * b0 / (mass + a0));
    for (int iteration = 0; iteration < 50; ++iteration) {
        const Complex dz = 1e-7 * omega;
        const Complex step = residual(root) * dz / (residual(root + dz) - residual(root));
        root -= step;
        if (std::abs(step) < 1e-12 * omega) break;
    }
    constexpr double kTwoPi = 2 * std::numbers::pi;
    return {kTwoPi / root.real(), kTwoPi * root.imag() / root.real()};
}

/// The same from the panel solution itself.
inline DecayFigures predictedHeaveDecay(const RadiationSolver& solver, double mass, double stiffness,
                                        double* naturalFrequency = nullptr) {
    const HeaveCoefficients panels = [&](double omega) {
        const RadiationCoefficients c = solver.at(omega);
        return std::pair{c.addedMass(kHeaveY, kHeaveY), c.damping(kHeaveY, kHeaveY)};
    };
    return predictedHeaveDecay(panels, mass, stiffness, naturalFrequency);
}

/// Period and decrement of a sampled heave record (offsets from rest at equal steps dt): the
/// period from the first three up-crossings (interpolated), the decrement from the extremes
/// after the release, peaks one period apart (same sign), averaged over two pairs.
inline DecayFigures measuredDecay(const std::vector<double>& offset, double dt) {
    std::vector<double> upCrossings, extremes;
    for (std::size_t n = 1; n < offset.size(); ++n) {
        const double a = offset[n - 1], b = offset[n];
        if (a < 0 && b >= 0) upCrossings.push_back(dt * (n - 1 + (-a) / (b - a)));
        if (n + 1 < offset.size() && std::abs(b) >= std::abs(a) && std::abs(b) > std::abs(offset[n + 1]) &&
            (b - a) * (offset[n + 1] - b) <= 0) {
            extremes.push_back(std::abs(b));
        }
    }
    DecayFigures out;
    if (upCrossings.size() >= 3) out.period = (upCrossings[2] - upCrossings[0]) / 2;
    if (extremes.size() >= 4) {
        out.logDecrement = 0.5 * (std::log(extremes[0] / extremes[2]) + std::log(extremes[1] / extremes[3]));
    }
    return out;
}

}  // namespace plimsoll::test
