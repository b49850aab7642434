// The free heave decay test (radiation_decay.h).
#include "plimsoll/scene/radiation_decay.h"

#include "plimsoll/compute/compute.h"
#include "plimsoll/compute/fast_backend.h"
#include "plimsoll/physics/radiation.h"
#include "plimsoll/scene/scene_radiation.h"
#include "plimsoll/scene/world.h"

#include <algorithm>
#include <cmath>
#include <complex>
#include <numbers>

namespace plimsoll {

DecayFigures predictedHeaveDecay(const HeaveCoefficients& coefficients, double mass,
                                 double stiffness, double* naturalFrequency) {
    double omega = std::sqrt(stiffness / mass);
    std::pair<double, double> at;
    for (int iteration = 0; iteration < 6; ++iteration) {
        at = coefficients(omega);
        omega = std::sqrt(stiffness / (mass + at.first));
    }
    if (naturalFrequency) *naturalFrequency = omega;
    const double h = 0.03 * omega;
    const std::pair<double, double> below = coefficients(omega - h),
                                    above = coefficients(omega + h);
    const double a0 = at.first, b0 = at.second;
    const double a1 = (above.first - below.first) / (2 * h);
    const double b1 = (above.second - below.second) / (2 * h);
    using Complex = std::complex<double>;
    auto residual = [&](Complex w) {
        return stiffness - w * w * (mass + a0 + a1 * (w - omega)) +
               Complex(0, 1) * w * (b0 + b1 * (w - omega));
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

DecayFigures measuredDecay(const std::vector<double>& offset, double dt) {
    std::vector<double> upCrossings, extremes;
    for (std::size_t n = 1; n < offset.size(); ++n) {
        const double a = offset[n - 1], b = offset[n];
        if (a < 0 && b >= 0) upCrossings.push_back(dt * (n - 1 + (-a) / (b - a)));
        if (n + 1 < offset.size() && std::abs(b) >= std::abs(a) &&
            std::abs(b) > std::abs(offset[n + 1]) && (b - a) * (offset[n + 1] - b) <= 0) {
            extremes.push_back(std::abs(b));
        }
    }
    DecayFigures out;
    if (upCrossings.size() >= 3) out.period = (upCrossings[2] - upCrossings[0]) / 2;
    if (extremes.size() >= 4) {
        out.logDecrement =
            0.5 * (std::log(extremes[0] / extremes[2]) + std::log(extremes[1] / extremes[3]));
    }
    return out;
}

namespace {

/// A and B in heave at omega, linear in omega between the body's samples (held at the ends).
std::pair<double, double> interpolatedHeave(const std::vector<RadiationCoefficients>& samples,
                                            double omega) {
    auto heave = [](const RadiationCoefficients& c) {
        return std::pair{c.addedMass(kHeaveY, kHeaveY), c.damping(kHeaveY, kHeaveY)};
    };
    if (omega <= samples.front().omega) return heave(samples.front());
    if (omega >= samples.back().omega) return heave(samples.back());
    const auto upper =
        std::upper_bound(samples.begin(), samples.end(), omega,
                         [](double w, const RadiationCoefficients& c) { return w < c.omega; });
    const RadiationCoefficients& a = *(upper - 1);
    const RadiationCoefficients& b = *upper;
    const double t = (omega - a.omega) / (b.omega - a.omega);
    const auto [a0, b0] = heave(a);
    const auto [a1, b1] = heave(b);
    return {a0 + t * (a1 - a0), b0 + t * (b1 - b0)};
}

}  // namespace

Result<HeaveDecayTest> runHeaveDecayTest(const Scene& scene, std::size_t index, double release,
                                         double periods) {
    if (index >= scene.bodies.size())
        return makeError(ErrorKind::invalidArgument,
                         "decay test: no body " + std::to_string(index));
    const SceneBody& source = scene.bodies[index];
    if (!source.radiation || source.radiation->coefficients.size() < 2 || !source.mass ||
        !source.parts.mesh)
        return makeError(
            ErrorKind::invalidArgument,
            source.label + ": decay test: the body has no radiation computed (turn it on)");
    if (!(release > 0) || !std::isfinite(release) || !(periods >= 2) || !std::isfinite(periods))
        return makeError(ErrorKind::invalidArgument,
                         "decay test: release must be > 0 and periods at least 2");
    const BodyRadiation& radiation = *source.radiation;
    const double density = scene.medium.density, gravity = scene.simulation.gravity.norm();
    const double level = scene.water.level;

    Scene tank;
    tank.name = scene.name + " (decay test)";
    tank.medium = scene.medium;
    tank.water = WaterModel::flat(level);
    tank.simulation = scene.simulation;
    tank.simulation.timeStep = 1.0 / 250;
    tank.simulation.subSteps = 4;  // 1 ms steps
    SceneBody body = source;
    body.desc.position = {0, level + radiation.restHeight - release, 0};
    body.desc.rotationDegrees = Eigen::Vector3d::Zero();
    body.desc.velocity = body.desc.angularVelocity = Eigen::Vector3d::Zero();
    body.desc.dragCoefficient = 0;
    body.desc.linearDamping = body.desc.angularDamping = 0;
    if (!body.desc.radiation) body.desc.radiation = RadiationDesc{};
    body.desc.radiation->enabled = true;
    tank.bodies = {body};

    HeaveDecayTest out;
    out.dt = tank.simulation.timeStep;
    // The mesh's own waterplane at rest: rho g dV/dh.
    const TriangleMesh& mesh = *source.parts.mesh;
    auto displaced = [&](double h) {
        return wettedVolume(wettedPanels(
            mesh, Eigen::Affine3d(Eigen::Translation3d(0, radiation.restHeight + h, 0))));
    };
    out.stiffness = density * gravity * (displaced(-1e-4) - displaced(1e-4)) / 2e-4;
    // What floats at rest: the body with its water graph's water, as the radiation's rest.
    const double mass = radiation.restVolume * density;
    out.predicted = predictedHeaveDecay(
        [&](double omega) { return interpolatedHeave(radiation.coefficients, omega); }, mass,
        out.stiffness, &out.naturalFrequency);
    if (!(out.predicted.period > 0) || !std::isfinite(out.predicted.period))
        return makeError(ErrorKind::invalidArgument,
                         source.label + ": decay test: no heave oscillation to test");

    // The fast CPU path, the default simulate and the editor use (within 1e-5 of the reference
    // on flat water): the same period and decrement as the reference's, in less time.
    Result<std::unique_ptr<World>> world = World::create(std::move(tank), createFastBackend());
    if (!world) return world.error();
    const double rest = level + radiation.restHeight + source.mass->centerOfMass.y();
    const int frames = static_cast<int>(std::ceil(periods * out.predicted.period / out.dt));
    out.offset.reserve(static_cast<std::size_t>(frames));
    for (int f = 0; f < frames; ++f) {
        if (Status s = (*world)->advanceFrame(); !s) return s.error();
        out.offset.push_back((*world)->bodies()[0].state.position.y() - rest);
    }
    out.measured = measuredDecay(out.offset, out.dt);
    return out;
}

}  // namespace plimsoll
