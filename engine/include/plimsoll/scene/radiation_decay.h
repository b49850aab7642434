// A free heave decay test of a radiating body, as a model basin runs one: released below its
// rest waterline in calm water and left to oscillate, its damped period and logarithmic
// decrement measured from the record and set beside what its A(omega) and B(omega) predict.
// The editor's decay-test button runs it; the tests compare the World with it. No file I/O.
#pragma once

#include "plimsoll/core/result.h"
#include "plimsoll/scene/scene.h"

#include <cstddef>
#include <functional>
#include <utility>
#include <vector>

namespace plimsoll {

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
/// real axis, and for a hemisphere that adds 13% to the damping that B(w_n) alone would give.
/// `naturalFrequency`, if given, receives w_n (rad/s).
DecayFigures predictedHeaveDecay(const HeaveCoefficients& coefficients, double mass,
                                 double stiffness, double* naturalFrequency = nullptr);

/// Period and decrement of a heave record (offsets from rest at equal steps dt): the period
/// from the first three up-crossings (interpolated), the decrement from the extremes after the
/// release, peaks one period apart (same sign), averaged over two pairs. Zero where the record
/// is too short for them.
DecayFigures measuredDecay(const std::vector<double>& offset, double dt);

struct HeaveDecayTest {
    double dt = 0;                ///< s between samples
    std::vector<double> offset;   ///< the centre of mass's heave from rest, m
    double stiffness = 0;         ///< N/m: rho g dV/dh of the mesh at rest
    double naturalFrequency = 0;  ///< rad/s, with A at that frequency
    DecayFigures predicted;       ///< from A and B (interpolated in the body's coefficients)
    DecayFigures measured;        ///< from the record
};

/// Body `body` of `scene` alone in calm water (flat at the scene's water level), upright at
/// its rest waterline, released `release` m below it at rest, with its radiation on
/// (body.radiation must be computed) and drag and the damping stand-ins off so that radiation
/// alone damps it; `periods` predicted periods at 1 ms steps on the fast CPU path.
Result<HeaveDecayTest> runHeaveDecayTest(const Scene& scene, std::size_t body,
                                         double release = 0.02, double periods = 6);

}  // namespace plimsoll
