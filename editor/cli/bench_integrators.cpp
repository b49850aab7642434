// plimsoll bench --integrators [--quick] [--out DIR]: the integrators' speed against accuracy
// trade: the energy drift of a floating box without dissipation and the time per step, for each
// integrator and time step. A table on stdout and DIR/bench_integrators.csv.
#include "cli/bench.h"

#include "cli/commands.h"
#include "cli/common.h"
#include "plimsoll/io/file_util.h"
#include "plimsoll/samples/primitives.h"
#include "plimsoll/scene/scene.h"
#include "plimsoll/scene/world.h"

#include <chrono>
#include <cmath>
#include <filesystem>
#include <iostream>
#include <limits>
#include <memory>
#include <string>
#include <vector>

namespace plimsoll::cli {

namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

// --- Integrators: energy drift against time step -------------------------------------------
//
// A flat box (1 x 0.25 x 0.8 m, density 500) floating on flat water (1000), let go 0.05 m above
// its equilibrium (the centre at the water line: it floats at half draft) and rolled 5 degrees
// about x, so it both heaves and rolls. No drag, friction or damping: the exact dynamics keep
// World::mechanicalEnergy constant, and whatever an integrator adds or loses is its error,
// measured against the energy the start has above the box at rest at equilibrium. One step a
// frame: World's stability sub-stepping (max_phase_step) is turned off, or it would shrink the
// long steps until every integrator looked alike.

constexpr double kIntegratorLift = 0.05;        ///< m above equilibrium at the start
constexpr double kIntegratorRollDegrees = 5.0;  ///< about x at the start
constexpr int kIntegratorTextureSize = 64;
constexpr double kIntegratorSeconds = 30.0;
constexpr double kIntegratorQuickSeconds = 5.0;
constexpr Integrator kIntegrators[] = {Integrator::ExplicitEuler, Integrator::SemiImplicitEuler,
                                       Integrator::RK4};
/// Frame rates: one integration step per frame (sub_steps 1), dt = 1 / rate.
constexpr int kIntegratorRates[] = {240, 60, 15};

/// The box, baked once: every run floats the same body (shared, not baked again).
Result<SceneBody> integratorBox() {
    BodyDesc body;
    body.name = "box";
    body.mesh = "box 1 x 0.25 x 0.8 m (generated)";
    body.textureSize = kIntegratorTextureSize;
    body.material.density = 500.0;
    // Nothing that dissipates: energy is the integrator's to keep.
    body.dragCoefficient = 0.0;
    body.frictionCoefficient = 0.0;
    body.linearDamping = 0.0;
    body.angularDamping = 0.0;
    BodyParts parts;
    parts.mesh = std::make_shared<const TriangleMesh>(makeBox({1.0, 0.25, 0.8}));
    return bakeSceneBody(body, std::move(parts));
}

Result<std::unique_ptr<World>> createIntegratorWorld(const SceneBody& box, Integrator integrator,
                                                     int rate, bool displaced) {
    Scene scene;
    scene.name = "bench --integrators";
    SceneBody& body = scene.bodies.emplace_back(box);
    if (displaced) {
        body.desc.position = {0.0, kIntegratorLift, 0.0};
        body.desc.rotationDegrees = {kIntegratorRollDegrees, 0.0, 0.0};
    }
    scene.medium.density = 1000.0;
    scene.water = WaterModel::flat(0.0);
    scene.simulation.timeStep = 1.0 / rate;
    scene.simulation.subSteps = 1;
    // World's own stability sub-stepping off: the integrator is measured at the asked step.
    scene.simulation.maxPhaseStep = std::numeric_limits<double>::infinity();
    scene.simulation.integrator = integrator;
    return World::create(std::move(scene), createReferenceBackend());
}

struct IntegratorRow {
    Integrator integrator = Integrator::SemiImplicitEuler;
    int rate = 0;     ///< dt = 1 / rate s, the project's frame time step
    long frames = 0;  ///< taken: fewer than planned when the state stopped being finite
    /// Integration steps World took (WorldStatistics::steps): one a frame, as the scene turns
    /// World's stability sub-stepping off; checked, since it would hide the integrator's step.
    std::size_t steps = 0;
    double finalDrift = 0;      ///< (E_end - E_0) / (E_0 - E_eq)
    double maxDrift = 0;        ///< largest |E(t) - E_0| / (E_0 - E_eq) over the run
    double usPerStep = 0;       ///< wall clock of advanceFrame, microseconds per integration step
    double finalVelocityY = 0;  ///< vertical velocity of the centre of mass at the end, m/s

    double dt() const { return 1.0 / rate; }
    /// The step actually integrated (s): dt unless World sub-stepped.
    double integratedStep() const {
        return steps > 0 ? static_cast<double>(frames) * dt() / static_cast<double>(steps) : dt();
    }
    bool diverged() const {
        return !std::isfinite(finalDrift) || !std::isfinite(maxDrift) ||
               !std::isfinite(finalVelocityY);
    }
};

bool finiteState(const RigidBodyState& s) {
    return s.position.allFinite() && s.orientation.coeffs().allFinite() &&
           s.linearMomentum.allFinite() && s.angularMomentum.allFinite();
}

/// Runs one integrator at one frame time step for `seconds` of simulated time. Only
/// advanceFrame is timed; the energy is read after every frame (one reference evaluation).
Result<IntegratorRow> measureIntegrator(const SceneBody& box, Integrator integrator, int rate,
                                        double seconds, double restEnergy) {
    Result<std::unique_ptr<World>> created = createIntegratorWorld(box, integrator, rate, true);
    if (!created) return created.error();
    World& world = **created;
    const double start = world.mechanicalEnergy(0);
    const double excess = start - restEnergy;
    if (!(excess > 0)) {
        return makeError(ErrorKind::invalidArgument,
                         "bench: the displaced box has no energy above equilibrium (" +
                             format("%.6g", excess) + " J)");
    }
    IntegratorRow row;
    row.integrator = integrator;
    row.rate = rate;
    const long planned = std::lround(seconds * rate);
    double energy = start;
    double elapsedUs = 0;
    while (row.frames < planned) {
        const Clock::time_point t0 = Clock::now();
        if (Status s = world.advanceFrame(); !s.ok()) return s.error();
        elapsedUs += std::chrono::duration<double, std::micro>(Clock::now() - t0).count();
        ++row.frames;
        const RigidBodyState& state = world.bodies()[0].state;
        // A state that is no longer finite stays so: stop and report the run as diverged.
        energy = finiteState(state) ? world.mechanicalEnergy(0)
                                    : std::numeric_limits<double>::quiet_NaN();
        const double drift = std::abs(energy - start) / excess;
        row.maxDrift = std::isfinite(drift) ? std::max(row.maxDrift, drift) : drift;
        if (!std::isfinite(energy)) break;
    }
    const SimulatedBody& body = world.bodies()[0];
    row.steps = world.statistics().steps;
    row.finalDrift = (energy - start) / excess;
    row.finalVelocityY = linearVelocity(body.state, body.mass).y();
    row.usPerStep = row.steps > 0 ? elapsedUs / static_cast<double>(row.steps) : 0.0;
    return row;
}

std::string rateCell(int rate) { return "1/" + std::to_string(rate); }

/// A number of a run, or "diverged" where the run produced NaN or infinity.
std::string finiteCell(const char* spec, double value) {
    return std::isfinite(value) ? format(spec, value) : "diverged";
}

std::vector<std::string> integratorCells(const IntegratorRow& r) {
    return {integratorName(r.integrator),      rateCell(r.rate),
            std::to_string(r.steps),           format("%.3e", r.integratedStep()),
            finiteCell("%+.3e", r.finalDrift), finiteCell("%.3e", r.maxDrift),
            format("%.2f", r.usPerStep),       finiteCell("%+.4f", r.finalVelocityY)};
}

void printIntegratorTable(const std::vector<IntegratorRow>& rows) {
    std::vector<std::vector<std::string>> lines = {{"integrator", "dt (s)", "steps", "step (s)",
                                                    "final drift", "max |drift|", "us/step",
                                                    "final vy (m/s)"}};
    for (const IntegratorRow& r : rows) lines.push_back(integratorCells(r));
    printAligned(lines, 2);
}

/// Non-finite numbers are left empty, with diverged = 1.
bool writeIntegratorCsv(const std::vector<IntegratorRow>& rows, std::ostream& out) {
    const auto number = [](const char* spec, double value) {
        return std::isfinite(value) ? format(spec, value) : std::string();
    };
    out << "integrator,dt_s,frames,steps,step_s,final_drift,max_drift,wall_us_per_step,"
           "final_vy_m_s,diverged\n";
    for (const IntegratorRow& r : rows) {
        out << integratorName(r.integrator) << ',' << format("%.17g", r.dt()) << ',' << r.frames
            << ',' << r.steps << ',' << format("%.9e", r.integratedStep()) << ','
            << number("%.9e", r.finalDrift) << ',' << number("%.9e", r.maxDrift) << ','
            << format("%.6g", r.usPerStep) << ',' << number("%.9e", r.finalVelocityY) << ','
            << (r.diverged() ? 1 : 0) << '\n';
    }
    return static_cast<bool>(out);
}

}  // namespace

int runIntegratorBench(const BenchOptions& o) {
    const double seconds = o.quick ? kIntegratorQuickSeconds : kIntegratorSeconds;
    auto fail = [](const Error& error) {
        std::cerr << "error: " << error.message << "\n";
        return kExitFailure;
    };

    Result<SceneBody> box = integratorBox();
    if (!box) return fail(box.error());
    Result<std::unique_ptr<World>> rest =
        createIntegratorWorld(*box, Integrator::SemiImplicitEuler, kIntegratorRates[0], false);
    if (!rest) return fail(rest.error());
    const double restEnergy = (*rest)->mechanicalEnergy(0);
    Result<std::unique_ptr<World>> displaced =
        createIntegratorWorld(*box, Integrator::SemiImplicitEuler, kIntegratorRates[0], true);
    if (!displaced) return fail(displaced.error());
    const double startEnergy = (*displaced)->mechanicalEnergy(0);
    const SimulatedBody& floating = (*displaced)->bodies()[0];

    std::vector<IntegratorRow> rows;
    for (Integrator integrator : kIntegrators) {
        for (int rate : kIntegratorRates) {
            Result<IntegratorRow> row =
                measureIntegrator(*box, integrator, rate, seconds, restEnergy);
            if (!row) return fail(row.error());
            const std::vector<std::string> c = integratorCells(*row);
            std::cerr << "bench: " << c[0] << " dt " << c[1] << " s: " << c[2]
                      << " steps, final drift " << c[4] << ", " << c[6] << " us/step\n";
            rows.push_back(std::move(*row));
        }
    }

    std::cout << "integrators: box 1 x 0.25 x 0.8 m, density 500, on flat water of 1000, "
              << kIntegratorTextureSize << "^2 textures, mass "
              << format("%.6g", floating.mass.mass) << " kg, volume "
              << format("%.6g", floating.volume) << " m^3\n"
              << "started " << kIntegratorLift << " m above equilibrium and rolled "
              << kIntegratorRollDegrees << " degrees about x; no drag, friction or damping; "
              << format("%g", seconds)
              << " s simulated, sub_steps 1 (max_phase_step off), reference backend\n"
              << "energy above equilibrium at the start: E_0 - E_eq = "
              << format("%.6g", startEnergy - restEnergy)
              << " J; drift = (E - E_0) / (E_0 - E_eq)\n\n";
    printIntegratorTable(rows);
    if (std::any_of(rows.begin(), rows.end(), [](const IntegratorRow& r) {
            return r.steps != static_cast<std::size_t>(r.frames);
        })) {
        std::cout << "\nnote: World took more integration steps than the 1 a frame asked for "
                     "(its own stability sub-stepping): 'step' is the step integrated\n";
    }

    if (!createOutputFolder(o.out)) return kExitFailure;
    const fs::path csv = fs::path(o.out) / "bench_integrators.csv";
    if (Status s = writeFileAtomically(
            csv, [&](std::ostream& out) { return writeIntegratorCsv(rows, out); });
        !s.ok())
        return fail(s.error());
    std::cout << "\nwritten: " << csv.string() << "\n";
    return kExitOk;
}

}  // namespace plimsoll::cli
