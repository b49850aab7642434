// Free heave decays against the frequency-domain coefficients: the prediction from A and B and
// the measurement of a record are the engine's (scene/radiation_decay.h, the editor's decay
// test); this adds the prediction from a panel solution itself. Shared by the Cummins tests on
// the bare rigid body and through the World.
#pragma once

#include "plimsoll/physics/radiation.h"
#include "plimsoll/scene/radiation_decay.h"

#include <utility>

namespace plimsoll::test {

using plimsoll::DecayFigures;
using plimsoll::HeaveCoefficients;
using plimsoll::measuredDecay;
using plimsoll::predictedHeaveDecay;

/// The same from the panel solution itself.
inline DecayFigures predictedHeaveDecay(const RadiationSolver& solver, double mass,
                                        double stiffness, double* naturalFrequency = nullptr) {
    const HeaveCoefficients panels = [&](double omega) {
        const RadiationCoefficients c = solver.at(omega);
        return std::pair{c.addedMass(kHeaveY, kHeaveY), c.damping(kHeaveY, kHeaveY)};
    };
    return predictedHeaveDecay(panels, mass, stiffness, naturalFrequency);
}

}  // namespace plimsoll::test
