// Cummins' equation pieces (cummins.h).
#include "plimsoll/physics/cummins.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <complex>
#include <iterator>

namespace plimsoll {

namespace {

// K(i w) of one filter: c i w / (w_m^2 - w^2 + 2 i zeta w_m w).
std::complex<double> response(const MemoryTerm& t, double omega) {
    const std::complex<double> iw(0.0, omega);
    return t.gain * iw /
           (t.frequency * t.frequency - omega * omega + 2.0 * t.dampingRatio * t.frequency * iw);
}

}  // namespace

double fittedDamping(const std::vector<MemoryTerm>& terms, double omega) {
    double b = 0;
    for (const MemoryTerm& t : terms) b += response(t, omega).real();
    return b;
}

double fittedAddedMass(const std::vector<MemoryTerm>& terms, double omega) {
    double a = 0;
    for (const MemoryTerm& t : terms) a += response(t, omega).imag() / omega;
    return a;
}

namespace {

// Non-negative least squares ||columns c - target|| by projected Gauss-Seidel on the normal
// equations (Lawson & Hanson's NNLS problem; the bases here are small).
Eigen::VectorXd nonNegativeFit(const Eigen::MatrixXd& columns, const Eigen::VectorXd& target) {
    const Eigen::MatrixXd normal = columns.transpose() * columns;
    const Eigen::VectorXd rhs = columns.transpose() * target;
    Eigen::VectorXd c = Eigen::VectorXd::Zero(columns.cols());
    for (int sweep = 0; sweep < 5000; ++sweep) {
        double change = 0;
        for (Eigen::Index j = 0; j < c.size(); ++j) {
            if (normal(j, j) <= 0) continue;
            const double next =
                std::max(0.0, c(j) + (rhs(j) - normal.row(j).dot(c)) / normal(j, j));
            change = std::max(change, std::abs(next - c(j)) * std::sqrt(normal(j, j)));
            c(j) = next;
        }
        if (change <= 1e-12 * std::max(target.cwiseAbs().maxCoeff(), 1e-300)) break;
    }
    return c;
}

}  // namespace

std::vector<MemoryTerm> fitMemory(const std::vector<double>& omega,
                                  const std::vector<double>& damping) {
    assert(omega.size() == damping.size());
    std::vector<MemoryTerm> basis;
    if (omega.size() < 2) return basis;
    const auto [lowIt, highIt] = std::minmax_element(omega.begin(), omega.end());
    const double low = *lowIt, high = *highIt;
    constexpr int kFrequencies = 12;
    constexpr double kDampingRatios[] = {0.25, 0.5, 1.0};
    static_assert(kFrequencies * std::size(kDampingRatios) == plimsoll_eval::kMaxMemoryTerms);
    for (int k = 0; k < kFrequencies; ++k) {
        const double w = low * std::pow(high / low, k / double(kFrequencies - 1));
        for (const double zeta : kDampingRatios) basis.push_back({1.0, w, zeta});
    }
    const auto samples = static_cast<Eigen::Index>(omega.size());
    const Eigen::VectorXd target = Eigen::Map<const Eigen::VectorXd>(damping.data(), samples);
    const double peak = target.cwiseAbs().maxCoeff();
    auto fitOn = [&](const std::vector<MemoryTerm>& terms) {
        Eigen::MatrixXd columns(samples, static_cast<Eigen::Index>(terms.size()));
        for (Eigen::Index s = 0; s < samples; ++s)
            for (std::size_t j = 0; j < terms.size(); ++j)
                columns(s, j) = fittedDamping({terms[j]}, omega[s]);
        const Eigen::VectorXd c = nonNegativeFit(columns, target);
        // Keep the terms that carry at least 2% of the peak damping somewhere: the fit stays
        // low-order (each term is two states per mode).
        std::vector<MemoryTerm> kept;
        for (std::size_t j = 0; j < terms.size(); ++j) {
            if (c(j) * columns.col(j).cwiseAbs().maxCoeff() >= 0.02 * peak)
                kept.push_back({c(j), terms[j].frequency, terms[j].dampingRatio});
        }
        return kept;
    };
    std::vector<MemoryTerm> terms = fitOn(basis);
    // Refit the gains of the kept terms alone (pruning moved what the dropped ones carried).
    for (MemoryTerm& t : terms) t.gain = 1.0;
    return fitOn(terms);
}

CumminsModel cumminsModel(const std::vector<RadiationCoefficients>& coefficients,
                          const Matrix6d& addedMassInfinity) {
    CumminsModel model;
    model.addedMassInfinity = 0.5 * (addedMassInfinity + addedMassInfinity.transpose());
    for (int mode = 0; mode < 6; ++mode) {
        std::vector<double> omega, damping;
        for (const RadiationCoefficients& c : coefficients) {
            omega.push_back(c.omega);
            damping.push_back(std::max(0.0, c.damping(mode, mode)));
        }
        // A mode the body cannot radiate in (a sphere's yaw) keeps no filter.
        const double peak =
            damping.empty() ? 0.0 : *std::max_element(damping.begin(), damping.end());
        const double scale =
            std::max(1.0, model.addedMassInfinity.diagonal().cwiseAbs().maxCoeff());
        if (peak > 1e-9 * scale) model.memory[mode] = fitMemory(omega, damping);
    }
    return model;
}

MemoryState memoryStateFor(const CumminsModel& model) {
    MemoryState state;
    for (int mode = 0; mode < 6; ++mode) state.filters[mode].assign(model.memory[mode].size(), {});
    return state;
}

Vector6d memoryForce(const CumminsModel& model, const MemoryState& state) {
    Vector6d force = Vector6d::Zero();
    for (int mode = 0; mode < 6; ++mode)
        for (std::size_t m = 0; m < model.memory[mode].size(); ++m)
            force(mode) +=
                plimsoll_eval::filterForce(model.memory[mode][m], state.filters[mode][m]);
    return force;
}

void advanceMemory(const CumminsModel& model, MemoryState& state, const Vector6d& velocity,
                   double dt) {
    for (int mode = 0; mode < 6; ++mode)
        for (std::size_t m = 0; m < model.memory[mode].size(); ++m)
            plimsoll_eval::advanceFilter(model.memory[mode][m], state.filters[mode][m],
                                         velocity(mode), dt);
}

double memoryEnergy(const CumminsModel& model, const MemoryState& state) {
    double e = 0;
    for (int mode = 0; mode < 6; ++mode)
        for (std::size_t m = 0; m < model.memory[mode].size(); ++m)
            e += plimsoll_eval::filterEnergy(model.memory[mode][m], state.filters[mode][m]);
    return e;
}

double entrainedShare(double submergedVolume, double restVolume) {
    return plimsoll_eval::entrainedShare(submergedVolume, restVolume);
}

void applyAddedMass(const CumminsModel& model, double share, MassDistribution& mass,
                    RigidBodyState& state) {
    share = std::clamp(share, 0.0, 1.0);
    const Eigen::Matrix3d translational = share * model.addedMassInfinity.topLeftCorner<3, 3>();
    const Eigen::Matrix3d rotational = share * model.addedMassInfinity.bottomRightCorner<3, 3>();
    if (translational == mass.addedMass && rotational == mass.addedInertia) return;
    const Eigen::Vector3d v = linearVelocity(state, mass);
    const Eigen::Vector3d w = angularVelocity(state, mass);
    const bool shrinks = translational.trace() + rotational.trace() <
                         mass.addedMass.trace() + mass.addedInertia.trace();
    mass.addedMass = translational;
    mass.addedInertia = rotational;
    if (shrinks) {
        const Eigen::Matrix3d r = state.orientation.toRotationMatrix();
        state.linearMomentum =
            r * (mass.mass * Eigen::Matrix3d::Identity() + translational) * r.transpose() * v;
        state.angularMomentum = r * (mass.inertia + rotational) * r.transpose() * w;
    }
}

}  // namespace plimsoll
