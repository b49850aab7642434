// Time-domain radiation (Cummins 1962, "The impulse response function and ship motions"):
//
//   (M + A_inf) v' + int_0^t K(t - s) v(s) ds + C x = F,   K(t) = (2/pi) int_0^inf B(w) cos(w t)
//   dw.
//
// A_inf goes into the rigid body's mass matrix (MassDistribution::addedMass), never into a
// force: an added-mass force computed from the acceleration is unstable for light bodies. The
// memory integral is replaced, per mode (the diagonal of B), by a sum of second-order filters
//
//   K_j(s) = sum_m c_m s / (s^2 + 2 zeta_m w_m s + w_m^2),   c_m >= 0,
//
// fitted to B_jj(w). Each filter is a damped oscillator driven by the velocity, so the fit is
// passive by construction (Re K(i w) >= 0: it can store the body's energy and give some back,
// never make any) and stable; its added mass w -> 0 limit sum c_m / w_m^2 is what the memory
// adds to A_inf at low frequency.
#pragma once

#include "plimsoll/physics/radiation.h"
#include "plimsoll_eval/cummins.hpp"
#include "plimsoll/physics/rigid_body.h"

#include <array>
#include <vector>

namespace plimsoll {

using Vector6d = Eigen::Matrix<double, 6, 1>;

/// One filter of the memory fit (c_m, w_m, zeta_m), the evaluation core's type.
using MemoryTerm = plimsoll_eval::MemoryTerm;

/// B(w) of a fit (the real part of K(i w)).
double fittedDamping(const std::vector<MemoryTerm>& terms, double omega);
/// A(w) - A_inf of a fit (Im K(i w) / w: a filter's slow limit adds c / w_m^2, as a body that
/// drags water along; the sign the panel method's A(w) - A_inf has).
double fittedAddedMass(const std::vector<MemoryTerm>& terms, double omega);

/// Non-negative least-squares fit of the damping samples (omega rad/s, B > 0 expected) on a
/// fixed basis of filters: frequencies log-spaced over the samples' range, damping ratios
/// 0.25, 0.5 and 1; terms with no weight are dropped (typically 2-4 remain).
std::vector<MemoryTerm> fitMemory(const std::vector<double>& omega,
                                  const std::vector<double>& damping);

/// What the simulation needs of a body's radiation: body axes, about the centre of mass.
struct CumminsModel {
    Matrix6d addedMassInfinity = Matrix6d::Zero();
    std::array<std::vector<MemoryTerm>, 6> memory;  ///< per mode, kRadiationMode order
};

/// From baked coefficients (any frequency order) and A_inf.
CumminsModel cumminsModel(const std::vector<RadiationCoefficients>& coefficients,
                          const Matrix6d& addedMassInfinity);

/// The filters' states: (x, x') of each term of each mode.
struct MemoryState {
    std::array<std::vector<plimsoll_eval::MemoryFilter>, 6> filters;
};
MemoryState memoryStateFor(const CumminsModel& model);

/// The memory's generalised force on the body (forces then moments, body axes): -sum c x'.
Vector6d memoryForce(const CumminsModel& model, const MemoryState& state);
/// Advance every filter by dt with the body's generalised velocity over the step (body axes),
/// backward Euler: unconditionally stable and dissipative, so the storage never grows either.
void advanceMemory(const CumminsModel& model, MemoryState& state, const Vector6d& velocity,
                   double dt);
/// Energy held in the filters (J): sum c/2 (x'^2 + w^2 x^2). Body energy plus this never grows.
double memoryEnergy(const CumminsModel& model, const MemoryState& state);

/// Off its equilibrium waterline a body entrains less water. The approximation: the added mass
/// and the memory keep their equilibrium values while at least half the resting displacement
/// is submerged (deeper than at rest too: the linear theory's values), then fall linearly to
/// zero as the body leaves the water: share = clamp(2 V / V_rest, 0, 1). (A share that
/// followed every small heave would let the energy-safe update below drain energy on every
/// oscillation.)
double entrainedShare(double submergedVolume, double restVolume);

/// Sets mass.addedMass/addedInertia to share * A_inf (the diagonal blocks; the coupling blocks
/// are left out) and adjusts the momenta so that the change makes no energy: when the added
/// mass shrinks the velocity is kept (the water's share of the momentum is let go), when it
/// grows the momentum is kept (the body drags the water along); the kinetic energy can only
/// fall. The caller scales the memory's input and output by the same share, which keeps it
/// passive.
void applyAddedMass(const CumminsModel& model, double share, MassDistribution& mass,
                    RigidBodyState& state);

}  // namespace plimsoll
