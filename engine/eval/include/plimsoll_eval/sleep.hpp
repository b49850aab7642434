// Sleeping bodies: a body at rest on calm water stops being evaluated and integrated until the
// water, a force or its own water graph wakes it (docs/design.md, "Sleeping bodies"). The
// engine's World and the runtime's Simulation and step use this one rule, so that the editor's
// run and the game's fall asleep on the same frame. C++17, no Eigen, no I/O.
//
// A body falls asleep after it has stayed below the speed and acceleration thresholds for
// `restTime` without a break, on water that is calm where it floats (the surface's own speed under
// the linear threshold), with no outside force on it and no water moving through its graph. Asleep
// it holds its pose with zero velocity. It wakes when the surface above it moves faster than the
// linear threshold or its height there changes by more than `wakeHeight`, when an outside
// force acts on it, or when the caller wakes it (a new water model, a state set by hand).
#pragma once

#include <cmath>

namespace plimsoll_eval {

struct SleepSettings {
    bool enabled = true;
    double linearSpeed = 0.005;   ///< m/s: of the centre of mass, and of the water's surface
    double angularSpeed = 0.005;  ///< rad/s
    /// m/s^2 and rad/s^2, the velocities' mean change over the frame: a body at the turning
    /// point of a slow roll is still for an instant but not at rest. Held within these, a body
    /// heaving at w rad/s sleeps at most a_lin / w^2 from its equilibrium (0.1 mm at 10 rad/s).
    double linearAcceleration = 0.01;
    double angularAcceleration = 0.01;
    double restTime = 2.0;      ///< s below every threshold before the body sleeps
    double wakeHeight = 0.001;  ///< m: a change of the water's height above the body
};

inline bool operator==(const SleepSettings& a, const SleepSettings& b) {
    return a.enabled == b.enabled && a.linearSpeed == b.linearSpeed &&
           a.angularSpeed == b.angularSpeed && a.linearAcceleration == b.linearAcceleration &&
           a.angularAcceleration == b.angularAcceleration && a.restTime == b.restTime &&
           a.wakeHeight == b.wakeHeight;
}

/// One body's sleep bookkeeping; part of its state (saved with it for a bit-exact restore).
struct SleepState {
    bool asleep = false;
    double restedFor = 0;    ///< s below the thresholds so far
    double waterHeight = 0;  ///< the surface's height above the body when it fell asleep
};

/// What the caller measured for an awake body at the end of a frame of `dt` seconds.
struct RestSample {
    double speed = 0;                ///< |v| of the centre of mass, m/s
    double spin = 0;                 ///< |w|, rad/s
    double acceleration = 0;         ///< |v_end - v_start| / frame time, m/s^2
    double angularAcceleration = 0;  ///< |w_end - w_start| / frame time, rad/s^2
    double waterSpeed = 0;           ///< |u| of the surface above the body, m/s
    double waterHeight = 0;          ///< that surface's height, m
    bool pushed = false;             ///< an outside force acts on the body
    bool changing = false;           ///< its water graph moved water or its mesh deforms
};

/// The body's own motion is still enough to count as rest (sleeping on), whatever the water:
/// a caller asks for the water above the body (a height query on waves) only when this holds.
inline bool bodyStill(const SleepSettings& settings, const RestSample& sample) {
    return settings.enabled && sample.speed <= settings.linearSpeed &&
           sample.spin <= settings.angularSpeed &&
           sample.acceleration <= settings.linearAcceleration &&
           sample.angularAcceleration <= settings.angularAcceleration;
}

/// Fills the sample's water (the height and speed of the surface above the body) with
/// ask(height, speed), only where they can matter: when the body's own motion is still. A
/// moving body is not at rest whatever the water does, and asking is a height query on waves.
template <class Ask>
void sampleWaterIfStill(const SleepSettings& settings, RestSample& sample, Ask&& ask) {
    if (bodyStill(settings, sample)) ask(sample.waterHeight, sample.waterSpeed);
}

/// The body and the water above it are still enough to count as rest (sleeping on): what
/// needs no outside force to be asked (a caller asks for that, which may cost a game's
/// callback, only when this holds).
inline bool stillOnCalmWater(const SleepSettings& settings, const RestSample& sample) {
    return bodyStill(settings, sample) && sample.waterSpeed <= settings.linearSpeed;
}

/// Counts an awake body's rest; true when it falls asleep now (the caller then zeroes its
/// velocities and, with radiation, its memory: a body that has rested this long holds almost
/// none).
inline bool countRest(SleepState& state, const SleepSettings& settings, const RestSample& sample,
                      double dt) {
    const bool resting = stillOnCalmWater(settings, sample) && !sample.pushed && !sample.changing;
    if (!resting) {
        state.restedFor = 0;
        return false;
    }
    state.restedFor += dt;
    if (state.restedFor < settings.restTime) return false;
    state.asleep = true;
    state.waterHeight = sample.waterHeight;
    return true;
}

/// Whether a sleeping body must wake, from what the water and the forces do now.
inline bool mustWake(const SleepState& state, const SleepSettings& settings, double waterSpeed,
                     double waterHeight, bool pushed) {
    return !settings.enabled || pushed || waterSpeed > settings.linearSpeed ||
           std::abs(waterHeight - state.waterHeight) > settings.wakeHeight;
}

inline void wake(SleepState& state) {
    state.asleep = false;
    state.restedFor = 0;
}

}  // namespace plimsoll_eval
