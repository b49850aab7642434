// Cummins' radiation memory, one filter at a time: the engine's World (physics/cummins.h, which
// derives it and fits the filters) and the runtime library step the same code. C++17, no
// Eigen, no I/O.
//
// Each filter of a mode is the damped oscillator x'' + 2 zeta w x' + w^2 x = v driven by the
// body's velocity in that mode; its force on the body is -c x'. It is passive (it can store
// energy, c/2 (x'^2 + w^2 x^2), and give it back, never make any), and backward Euler keeps it
// so at any step.
#pragma once

#include <algorithm>
#include <cstddef>

namespace plimsoll_eval {

/// The most filters one mode's fit can have (fitMemory's basis: 12 frequencies by 3 damping
/// ratios); a bundle listing more is refused.
inline constexpr std::size_t kMaxMemoryTerms = 36;

/// One filter of the memory fit of a mode.
struct MemoryTerm {
    double gain = 0;          ///< c >= 0 (kg/s^2 for translations)
    double frequency = 0;     ///< w > 0, rad/s
    double dampingRatio = 0;  ///< zeta > 0
};

/// A filter's state: x and x'.
struct MemoryFilter {
    double x = 0;
    double rate = 0;
};

/// Advances the filter by dt with the mode's velocity over the step (backward Euler on (x, x'):
/// unconditionally stable and dissipative, so the stored energy never grows either).
inline void advanceFilter(const MemoryTerm& t, MemoryFilter& f, double velocity, double dt) {
    const double w2 = t.frequency * t.frequency;
    const double rate = (f.rate + dt * (velocity - w2 * f.x)) /
                        (1.0 + 2.0 * t.dampingRatio * t.frequency * dt + w2 * dt * dt);
    f = {f.x + dt * rate, rate};
}

/// The filter's generalised force on the body in its mode.
inline double filterForce(const MemoryTerm& t, const MemoryFilter& f) { return -t.gain * f.rate; }

/// The energy the filter holds, J.
inline double filterEnergy(const MemoryTerm& t, const MemoryFilter& f) {
    return 0.5 * t.gain * (f.rate * f.rate + t.frequency * t.frequency * f.x * f.x);
}

/// The share of its equilibrium added mass and memory a body keeps with `submergedVolume`
/// under water (physics/cummins.h: entrainedShare): clamp(2 V / V_rest, 0, 1).
inline double entrainedShare(double submergedVolume, double restVolume) {
    return restVolume > 0 ? std::clamp(2.0 * submergedVolume / restVolume, 0.0, 1.0) : 0.0;
}

}  // namespace plimsoll_eval
