// plimsoll hydro PROJECT [--body NAME] [--json] [--svg FILE] [--no-convergence]: the added
// mass A(omega) and radiation damping B(omega) of one body (scene_radiation.h) per mode, its
// infinite-frequency added mass and memory fit, and how the figures move with the panel count
// (the body's panel edge, and twice and 1.4 times it). The coefficients come through the
// project's radiation cache (radiation_cache.h); a body without "radiation" gets the defaults.
#include "cli/commands.h"

#include "cli/common.h"
#include "cli/svg_plot.h"
#include "plimsoll/io/file_util.h"
#include "plimsoll/project/project.h"
#include "plimsoll/project/radiation_cache.h"
#include "plimsoll/project/scene_loader.h"
#include "plimsoll/scene/scene_radiation.h"

#include <nlohmann/json.hpp>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <memory>
#include <string>

namespace plimsoll::cli {

namespace {

struct HydroOptions {
    std::string project;
    std::string body;
    bool json = false;
    std::string svg;
    bool convergence = true;
};

const char* const kModeNames[6] = {"surge x", "heave y", "sway z", "roll x", "yaw y", "pitch z"};

/// A and B of mode j made nondimensional: over rho V (translations) or rho V L^2 (rotations,
/// L = cbrt(V)), B also over omega.
struct Scales {
    double translation = 1, rotation = 1;
    double of(int mode) const { return mode < 3 ? translation : rotation; }
};

Scales scalesOf(const BodyRadiation& r, double density) {
    const double length = std::cbrt(r.restVolume);
    return {density * r.restVolume, density * r.restVolume * length * length};
}

/// One row of the convergence study: the solution at one panel edge.
struct ConvergencePoint {
    double panelEdge = 0;
    std::size_t panels = 0;
    Matrix6d addedMassInfinity = Matrix6d::Zero();
    RadiationCoefficients at;  ///< at the study's frequency
};

Result<std::vector<ConvergencePoint>> convergence(const SceneBody& body, const RadiationDesc& desc,
                                                  const Project& project, double omega) {
    std::vector<ConvergencePoint> points;
    for (const double factor : {2.0, std::sqrt(2.0), 1.0}) {
        RadiationDesc coarser = desc;
        coarser.panelEdge = desc.panelEdge * factor;
        Result<RestRadiationSurface> surface =
            restRadiationSurface(body, coarser, project.medium, project.simulation.gravity);
        if (!surface) return surface.error();
        points.push_back({coarser.panelEdge, surface->solver->panelCount(),
                          surface->solver->infiniteFrequencyAddedMass(),
                          surface->solver->at(omega)});
    }
    return points;
}

nlohmann::json diagonal(const Matrix6d& m) {
    nlohmann::json d = nlohmann::json::array();
    for (int j = 0; j < 6; ++j) d.push_back(m(j, j));
    return d;
}

nlohmann::json matrixRows(const Matrix6d& m) {
    nlohmann::json rows = nlohmann::json::array();
    for (int i = 0; i < 6; ++i) {
        nlohmann::json row = nlohmann::json::array();
        for (int j = 0; j < 6; ++j) row.push_back(m(i, j));
        rows.push_back(row);
    }
    return rows;
}

bool writeCoefficientSvg(const std::string& path, const std::string& label, const BodyRadiation& r,
                         double density) {
    const Scales scales = scalesOf(r, density);
    LinearPlot plot;
    plot.title = "Added mass A and radiation damping B of " + label;
    plot.xLabel = "omega (rad/s)";
    plot.yLabel = "A / (rho V), B / (rho V omega); rotations also / L^2";
    for (int mode = 0; mode < 6; ++mode) {
        // A mode the body does not radiate in (a sphere's yaw) has nothing to show.
        if (r.model.memory[mode].empty()) continue;
        PlotSeries a, b;
        a.name = std::string(kModeNames[mode]) + " A";
        b.name = std::string(kModeNames[mode]) + " B";
        for (const RadiationCoefficients& c : r.coefficients) {
            a.points.push_back({c.omega, c.addedMass(mode, mode) / scales.of(mode), ""});
            b.points.push_back({c.omega, c.damping(mode, mode) / (scales.of(mode) * c.omega), ""});
        }
        plot.series.push_back(std::move(a));
        plot.series.push_back(std::move(b));
    }
    const Status written =
        writeFileAtomically(path, [&](std::ostream& out) { return writeSvg(plot, out); });
    if (!written) {
        std::cerr << "error: " << written.error().message << "\n";
        return false;
    }
    return true;
}

int runHydro(const HydroOptions& o) {
    Result<Project> project = loadProject(o.project);
    if (!project) {
        std::cerr << "error: " << project.error().message << "\n";
        return kExitFailure;
    }
    const std::optional<std::size_t> index = bodyIndexByName(*project, o.body, o.project);
    if (!index) return kExitFailure;
    const LogFunction note = [](const std::string& line) { std::cerr << "note: " << line << "\n"; };
    // The body is loaded without its radiation (computed below, once, whether it is on or off).
    Project bare = *project;
    bare.bodies[*index].radiation = RadiationDesc{.enabled = false};
    Result<SceneBody> body = loadSceneBody(bare, *index, note);
    if (!body) {
        std::cerr << "error: " << body.error().message << "\n";
        return kExitFailure;
    }
    const RadiationDesc desc = project->bodies[*index].radiation.value_or(RadiationDesc{});
    const auto start = std::chrono::steady_clock::now();
    Result<std::shared_ptr<const BodyRadiation>> computed = cachedBodyRadiation(
        *body, desc, project->medium, project->simulation.gravity,
        project->radiationCacheFile(*index), note, stderrProgress(body->label + ": radiation"));
    if (!computed) {
        std::cerr << "error: " << projectFileName(*project) << ": bodies[" << *index
                  << "].radiation: " << computed.error().message << "\n";
        return kExitFailure;
    }
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    const BodyRadiation& r = **computed;
    const double density = project->medium.density;
    const Scales scales = scalesOf(r, density);
    // The convergence study's frequency: the middle of the grid (geometric mean).
    const double omega = std::sqrt(r.coefficients.front().omega * r.coefficients.back().omega);
    std::vector<ConvergencePoint> study;
    if (o.convergence) {
        RadiationDesc resolved = desc;
        resolved.panelEdge = r.panelEdge;
        Result<std::vector<ConvergencePoint>> points =
            convergence(*body, resolved, *project, omega);
        if (!points) {
            std::cerr << "error: " << points.error().message << "\n";
            return kExitFailure;
        }
        study = std::move(*points);
    }
    if (!o.svg.empty() && !writeCoefficientSvg(o.svg, body->label, r, density)) return kExitFailure;

    if (o.json) {
        nlohmann::json frequencies = nlohmann::json::array();
        for (const RadiationCoefficients& c : r.coefficients) {
            frequencies.push_back({{"omega", c.omega},
                                   {"added_mass", diagonal(c.addedMass)},
                                   {"damping", diagonal(c.damping)}});
        }
        nlohmann::json memory = nlohmann::json::array();
        for (int mode = 0; mode < 6; ++mode) {
            nlohmann::json terms = nlohmann::json::array();
            for (const MemoryTerm& t : r.model.memory[mode])
                terms.push_back({{"gain", t.gain},
                                 {"frequency", t.frequency},
                                 {"damping_ratio", t.dampingRatio}});
            memory.push_back(terms);
        }
        nlohmann::json points = nlohmann::json::array();
        for (const ConvergencePoint& p : study) {
            points.push_back({{"panel_edge", p.panelEdge},
                              {"panels", p.panels},
                              {"added_mass_infinity", diagonal(p.addedMassInfinity)},
                              {"omega", omega},
                              {"added_mass", diagonal(p.at.addedMass)},
                              {"damping", diagonal(p.at.damping)}});
        }
        const nlohmann::json out = {
            {"body", body->desc.name},
            {"modes", {"surge_x", "heave_y", "sway_z", "roll_x", "yaw_y", "pitch_z"}},
            {"water_density", density},
            {"rest_volume", r.restVolume},
            {"rest_height", r.restHeight},
            {"panel_edge", r.panelEdge},
            {"panels", r.panelCount},
            {"added_mass_infinity", matrixRows(r.addedMassInfinity)},
            {"frequencies", frequencies},
            {"memory", memory},
            {"convergence", points},
            {"seconds", seconds}};
        std::cout << reportJson(out) << "\n";
        return kExitOk;
    }
    std::printf(
        "%s: %zu panels (edge %g m) below the waterline at rest, displacement %g m^3, deep water "
        "of "
        "%g kg/m^3; object axes, about the centre of mass; %.3g s\n",
        body->label.c_str(), r.panelCount, r.panelEdge, r.restVolume, density, seconds);
    std::printf(
        "nondimensional: A / (rho V), B / (rho V omega), rotations also / L^2 with L = cbrt(V) = "
        "%g m\n\n",
        std::cbrt(r.restVolume));
    std::printf("  %10s", "omega");
    for (const char* name : kModeNames) std::printf(" %9s A %9s B", name, "");
    std::printf("\n");
    for (const RadiationCoefficients& c : r.coefficients) {
        std::printf("  %10.4g", c.omega);
        for (int j = 0; j < 6; ++j)
            std::printf(" %11.4g %11.4g", c.addedMass(j, j) / scales.of(j),
                        c.damping(j, j) / (scales.of(j) * c.omega));
        std::printf("\n");
    }
    std::printf("  %10s", "infinity");
    for (int j = 0; j < 6; ++j)
        std::printf(" %11.4g %11s", r.addedMassInfinity(j, j) / scales.of(j), "");
    std::printf("\n\n  memory fit (per mode, second-order terms): ");
    for (int j = 0; j < 6; ++j)
        std::printf("%s %zu%s", kModeNames[j], r.model.memory[j].size(), j < 5 ? ", " : "\n");
    if (!study.empty()) {
        std::printf(
            "\n  convergence with panel count (A at infinite frequency; A and B at omega %.4g "
            "rad/s):\n",
            omega);
        std::printf("  %10s %7s %12s %12s %12s %12s %12s %12s\n", "panel edge", "panels",
                    "surge A inf", "heave A inf", "surge A", "surge B", "heave A", "heave B");
        for (const ConvergencePoint& p : study) {
            std::printf("  %10.4g %7zu %12.5g %12.5g %12.5g %12.5g %12.5g %12.5g\n", p.panelEdge,
                        p.panels, p.addedMassInfinity(0, 0) / scales.translation,
                        p.addedMassInfinity(1, 1) / scales.translation,
                        p.at.addedMass(0, 0) / scales.translation,
                        p.at.damping(0, 0) / (scales.translation * omega),
                        p.at.addedMass(1, 1) / scales.translation,
                        p.at.damping(1, 1) / (scales.translation * omega));
        }
    }
    return kExitOk;
}

}  // namespace

void addHydroCommand(CLI::App& root, CommandRunner& selected) {
    auto o = std::make_shared<HydroOptions>();
    CLI::App* cmd =
        root.add_subcommand("hydro",
                            "Added mass A(omega) and radiation damping B(omega) of a body per "
                            "mode, and their convergence "
                            "with the panel count (through the project's radiation cache)");
    cmd->add_option("PROJECT", o->project, "Project file (.plim.json)")->required();
    cmd->add_option("--body", o->body, "Body name (default: the first body)");
    cmd->add_flag("--json", o->json, "Print one JSON object");
    cmd->add_option("--svg", o->svg, "Write A(omega) and B(omega) as an SVG plot")
        ->check(kNonEmptyPath);
    cmd->add_flag("--no-convergence{false}", o->convergence,
                  "Skip the convergence study (two coarser solutions)");
    cmd->callback([o, &selected] { selected = [o] { return runHydro(*o); }; });
}

}  // namespace plimsoll::cli
