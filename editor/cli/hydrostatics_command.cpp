// plimsoll hydrostatics PROJECT [--body NAME] [--json] [--svg FILE] [--exact] [--step DEG]:
// equilibrium, waterplane, metacentric heights and the righting-arm curve of one body of a
// project (physics/hydrostatics.h), from the textures and from the exact clip side by side,
// and the stability report: TPC, MCT1cm, KN cross curves, the largest GZ, the downflooding
// angle and the IMO 2008 IS Code's general criteria.
#include "cli/commands.h"

#include "cli/common.h"
#include "cli/jobs.h"
#include "cli/svg_plot.h"
#include "plimsoll/io/file_util.h"
#include "plimsoll/physics/hydrostatics.h"
#include "plimsoll/project/project.h"
#include "plimsoll/scene/scene_hydrostatics.h"
#include "plimsoll/project/scene_loader.h"

#include <nlohmann/json.hpp>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <memory>
#include <optional>
#include <string>

namespace plimsoll::cli {

namespace {

struct HydrostaticsOptions {
    HydrostaticsJob job;
    bool json = false;
    std::string svg;
};

using Measured = MeasuredHydrostatics;

nlohmann::json optionalJson(const std::optional<double>& value) {
    return value ? nlohmann::json(*value) : nlohmann::json(nullptr);
}

nlohmann::json criteriaJson(const StabilityCriteria& c) {
    nlohmann::json criteria = nlohmann::json::array();
    for (const StabilityCriterion& k : c.criteria) {
        criteria.push_back({{"name", k.name},
                            {"value", k.value},
                            {"required", k.required},
                            {"unit", k.unit},
                            {"pass", k.pass}});
    }
    return {{"pass", c.pass}, {"criteria", criteria}};
}

nlohmann::json crossCurvesJson(const HydrostaticsResult& r, double density) {
    nlohmann::json curves = nlohmann::json::array();
    for (const CrossCurve& c : r.crossCurves) {
        nlohmann::json kn = nlohmann::json::array();
        for (std::size_t i = 0; i < c.kn.size(); ++i) kn.push_back({c.heelsDegrees[i], c.kn[i]});
        curves.push_back({{"displacement", c.displacement},
                          {"displacement_t", density * c.displacement / 1000},
                          {"kn", kn}});
    }
    return curves;
}

nlohmann::json resultJson(const Measured& m, double density) {
    const HydrostaticsResult& r = m.result;
    nlohmann::json gz = nlohmann::json::array();
    for (const RightingArm& p : r.gz) gz.push_back({p.heelDegrees, p.arm});
    return {{"method", hydrostaticsMethodName(r.method)},
            {"draft", r.draft},
            {"trim_deg", r.trimDegrees},
            {"heel_deg", r.heelDegrees},
            {"displacement", r.displacement},
            {"waterplane_area", r.waterplaneArea},
            {"center_of_flotation", vectorJson(r.centerOfFlotation)},
            {"kb", r.kb},
            {"kg", r.kg},
            {"bm_transverse", r.bmTransverse},
            {"bm_longitudinal", r.bmLongitudinal},
            {"gm_transverse", r.gmTransverse},
            {"gm_longitudinal", r.gmLongitudinal},
            {"free_surface_loss_transverse", r.freeSurfaceLossTransverse},
            {"free_surface_loss_longitudinal", r.freeSurfaceLossLongitudinal},
            {"gm_transverse_effective", r.gmTransverse - r.freeSurfaceLossTransverse},
            {"gm_longitudinal_effective", r.gmLongitudinal - r.freeSurfaceLossLongitudinal},
            {"gz", gz},
            {"vanishing_stability_deg", r.vanishingStabilityDegrees},
            {"waterline_length", r.waterlineLength},
            {"tpc", r.tonnesPerCentimetre},
            {"mct1cm", r.momentToChangeTrim},
            {"gz_max", r.gzMax},
            {"gz_max_angle_deg", r.gzMaxDegrees},
            {"downflooding_angle_deg", optionalJson(r.downfloodingDegrees)},
            {"openings", r.openingCount},
            {"kn_cross_curves", crossCurvesJson(r, density)},
            {"is_code_2008", criteriaJson(r.isCode2008)},
            {"seconds", m.seconds}};
}

/// The figures the table shows, by name, unit and how to read them off a result.
struct HydrostaticsRow {
    const char* name;
    double (*value)(const HydrostaticsResult&);
};
const HydrostaticsRow kRows[] = {
    {"draft (m)", [](const HydrostaticsResult& r) { return r.draft; }},
    {"trim (deg)", [](const HydrostaticsResult& r) { return r.trimDegrees; }},
    {"heel (deg)", [](const HydrostaticsResult& r) { return r.heelDegrees; }},
    {"displacement (m^3)", [](const HydrostaticsResult& r) { return r.displacement; }},
    {"waterplane area (m^2)", [](const HydrostaticsResult& r) { return r.waterplaneArea; }},
    {"flotation centre x (m)", [](const HydrostaticsResult& r) { return r.centerOfFlotation.x(); }},
    {"flotation centre z (m)", [](const HydrostaticsResult& r) { return r.centerOfFlotation.z(); }},
    {"KB (m)", [](const HydrostaticsResult& r) { return r.kb; }},
    {"KG (m)", [](const HydrostaticsResult& r) { return r.kg; }},
    {"BM transverse (m)", [](const HydrostaticsResult& r) { return r.bmTransverse; }},
    {"BM longitudinal (m)", [](const HydrostaticsResult& r) { return r.bmLongitudinal; }},
    {"GM transverse (m)", [](const HydrostaticsResult& r) { return r.gmTransverse; }},
    {"GM longitudinal (m)", [](const HydrostaticsResult& r) { return r.gmLongitudinal; }},
    {"free-surface loss T (m)",
     [](const HydrostaticsResult& r) { return r.freeSurfaceLossTransverse; }},
    {"free-surface loss L (m)",
     [](const HydrostaticsResult& r) { return r.freeSurfaceLossLongitudinal; }},
    {"effective GM T (m)",
     [](const HydrostaticsResult& r) { return r.gmTransverse - r.freeSurfaceLossTransverse; }},
    {"vanishing stability (deg)",
     [](const HydrostaticsResult& r) { return r.vanishingStabilityDegrees; }},
    {"waterline length (m)", [](const HydrostaticsResult& r) { return r.waterlineLength; }},
    {"TPC (t/cm)", [](const HydrostaticsResult& r) { return r.tonnesPerCentimetre; }},
    {"MCT1cm (t m/cm)", [](const HydrostaticsResult& r) { return r.momentToChangeTrim; }},
    {"GZ max (m)", [](const HydrostaticsResult& r) { return r.gzMax; }},
    {"angle of GZ max (deg)", [](const HydrostaticsResult& r) { return r.gzMaxDegrees; }},
    {"downflooding angle (deg)",
     [](const HydrostaticsResult& r) { return r.downfloodingDegrees.value_or(NAN); }},
};

void printRow(const std::string& name, const std::vector<double>& values) {
    std::printf("  %-27s", name.c_str());
    for (double v : values) {
        if (std::isnan(v)) {
            std::printf(" %14s", "none");
        } else {
            std::printf(" %14.7g", v);
        }
    }
    std::printf("\n");
}

/// The IS Code's criteria, each method's value and verdict beside the required value.
void printCriteria(const std::vector<Measured>& methods) {
    std::printf("\n  %-27s %14s", "IMO 2008 IS Code, A 2.2", "required");
    for (const Measured& m : methods) std::printf(" %14s", hydrostaticsMethodName(m.result.method));
    std::printf("\n");
    std::printf(
        "  on GZ less the free-surface loss times sin(heel); the areas to 40 degrees end at\n"
        "  the downflooding angle where that is less\n");
    const std::vector<StabilityCriterion>& first = methods[0].result.isCode2008.criteria;
    for (std::size_t i = 0; i < first.size(); ++i) {
        const std::string name = first[i].name + " (" + first[i].unit + ")";
        std::printf("  %-27s %14.4g", name.c_str(), first[i].required);
        for (const Measured& m : methods) {
            const StabilityCriterion& k = m.result.isCode2008.criteria[i];
            std::printf(" %9.4g %4s", k.value, k.pass ? "pass" : "FAIL");
        }
        std::printf("\n");
    }
    std::printf("  %-27s %14s", "verdict", "");
    for (const Measured& m : methods)
        std::printf(" %14s", m.result.isCode2008.pass ? "pass" : "FAIL");
    std::printf("\n");
}

/// KN against heel, one column per displacement, for each method.
void printCrossCurves(const std::vector<Measured>& methods) {
    for (const Measured& m : methods) {
        const std::vector<CrossCurve>& curves = m.result.crossCurves;
        if (curves.empty()) continue;
        const std::string title = std::string("KN (m), ") + hydrostaticsMethodName(m.result.method);
        std::printf("\n  %-27s", title.c_str());
        for (const CrossCurve& c : curves) {
            char volume[32];
            std::snprintf(volume, sizeof volume, "%.5g m^3", c.displacement);
            std::printf(" %14s", volume);
        }
        std::printf("\n");
        for (std::size_t i = 0; i < curves[0].heelsDegrees.size(); ++i) {
            char heel[32];
            std::snprintf(heel, sizeof heel, "%g deg", curves[0].heelsDegrees[i]);
            std::vector<double> values;
            for (const CrossCurve& c : curves) values.push_back(c.kn[i]);
            printRow(heel, values);
        }
    }
}

void printTable(const std::vector<Measured>& methods) {
    const bool both = methods.size() == 2;
    std::printf("  %-27s", "");
    for (const Measured& m : methods) std::printf(" %14s", hydrostaticsMethodName(m.result.method));
    if (both) std::printf(" %14s", "difference");
    std::printf("\n");
    auto values = [&](auto&& of) {
        std::vector<double> v;
        for (const Measured& m : methods) v.push_back(of(m.result));
        if (both) v.push_back(v[0] - v[1]);
        return v;
    };
    for (const HydrostaticsRow& row : kRows) printRow(row.name, values(row.value));
    printRow("seconds", [&] {
        std::vector<double> v;
        for (const Measured& m : methods) v.push_back(m.seconds);
        return v;
    }());
    std::printf("\n  %-27s\n", "GZ (m) at heel (deg)");
    const std::vector<RightingArm>& first = methods[0].result.gz;
    for (std::size_t i = 0; i < first.size(); ++i) {
        char heel[32];
        std::snprintf(heel, sizeof heel, "%g", first[i].heelDegrees);
        printRow(heel, values([&](const HydrostaticsResult& r) { return r.gz[i].arm; }));
    }
    printCriteria(methods);
    printCrossCurves(methods);
}

bool writeGzSvg(const std::string& path, const std::string& label,
                const std::vector<Measured>& methods) {
    LinearPlot plot;
    plot.title = "Righting arm GZ of " + label;
    plot.xLabel = "heel (degrees)";
    plot.yLabel = "GZ (m)";
    for (const Measured& m : methods) {
        PlotSeries s;
        s.name = hydrostaticsMethodName(m.result.method);
        for (const RightingArm& p : m.result.gz) s.points.push_back({p.heelDegrees, p.arm, ""});
        plot.series.push_back(std::move(s));
    }
    char text[64];
    std::snprintf(text, sizeof text, "vanishing stability %.1f deg",
                  methods[0].result.vanishingStabilityDegrees);
    plot.markers.push_back({methods[0].result.vanishingStabilityDegrees, text});
    const Status written =
        writeFileAtomically(path, [&](std::ostream& out) { return writeSvg(plot, out); });
    if (!written) {
        std::cerr << "error: " << written.error().message << "\n";
        return false;
    }
    return true;
}

int runHydrostatics(const HydrostaticsOptions& o) {
    Result<HydrostaticsStudy> study = hydrostaticsJob(o.job, stderrReporter());
    if (!study) {
        std::cerr << "error: " << study.error().message << "\n";
        return kExitFailure;
    }
    const std::vector<Measured>& methods = study->methods;
    if (!o.svg.empty() && !writeGzSvg(o.svg, study->label, methods)) return kExitFailure;
    if (o.json) {
        std::cout << reportJson(study->json()) << "\n";
        return kExitOk;
    }
    const FloatingBody& floating = study->floating;
    std::printf(
        "%s: calm water of %g kg/m^3 at the mean level, mass %g kg (%g m^3 of it graph "
        "water), centre of mass %g %g %g m; heel about x, trim about z, y up\n",
        study->label.c_str(), study->density, floating.body.mass, floating.graphWater,
        floating.body.centerOfMass.x(), floating.body.centerOfMass.y(),
        floating.body.centerOfMass.z());
    if (!study->exactOnly) std::printf("textures at %d^2\n", study->textureSize);
    printTable(methods);
    return kExitOk;
}

}  // namespace

Result<HydrostaticsStudy> hydrostaticsJob(const HydrostaticsJob& o, const Reporter& reporter) {
    Result<Project> project = loadProject(o.project);
    if (!project) return project.error();
    Result<std::size_t> index = bodyIndexOf(*project, o.body, o.project);
    if (!index) return index.error();
    Result<HydrostaticsSettings> settings =
        hydrostaticsSettingsOf(project->medium, project->simulation.gravity);
    if (!settings) return withContext(o.project + ": ", settings.error());
    settings->gzStepDegrees = o.stepDegrees;
    Result<SceneBody> body = loadSceneBody(
        *project, *index, [&](const std::string& line) { reporter.note("note: " + line + "\n"); });
    if (!body) return body.error();
    Result<FloatingBody> floating = floatingBodyOf(*body, project->medium);
    if (!floating) return floating.error();

    HydrostaticsStudy study;
    study.label = body->label;
    study.bodyName = body->desc.name;
    study.textureSize = body->desc.textureSize;
    study.exactOnly = o.exact;
    study.density = settings->density;
    study.floating = *floating;
    auto measure = [&](auto&& compute) -> Status {
        const auto start = std::chrono::steady_clock::now();
        Result<HydrostaticsResult> r = compute();
        if (!r) return withContext(body->label + ": ", r.error());
        study.methods.push_back(
            {std::move(*r),
             std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count()});
        return Ok{};
    };
    if (!o.exact) {
        if (Status s = measure([&] {
                return hydrostaticsFromTextures(*body->textures, floating->body, *settings);
            });
            !s)
            return s.error();
    }
    if (Status s = measure(
            [&] { return hydrostaticsExact(*body->parts.mesh, floating->body, *settings); });
        !s)
        return s.error();
    return study;
}

nlohmann::json HydrostaticsStudy::json() const {
    nlohmann::json out = resultJson(methods[0], density);
    out["body"] = bodyName;
    out["texture_size"] = exactOnly ? nlohmann::json(nullptr) : nlohmann::json(textureSize);
    out["mass"] = floating.body.mass;
    out["center_of_mass"] = vectorJson(floating.body.centerOfMass);
    out["graph_water"] = floating.graphWater;
    out["water_density"] = density;
    if (methods.size() == 2) out["exact"] = resultJson(methods[1], density);
    return out;
}

void addHydrostaticsCommand(CLI::App& root, CommandRunner& selected) {
    auto o = std::make_shared<HydrostaticsOptions>();
    CLI::App* cmd = root.add_subcommand(
        "hydrostatics",
        "Equilibrium draft, trim and heel, KB, BM, GM and the righting-arm curve of a body, "
        "from the textures and the exact clip");
    cmd->add_option("PROJECT", o->job.project, "Project file (.plim.json)")->required();
    cmd->add_option("--body", o->job.body, "Body name (default: the first body)");
    cmd->add_flag("--json", o->json,
                  "Print one JSON object (with --exact: the exact clip only; "
                  "otherwise the textures', the exact one under \"exact\")");
    cmd->add_flag("--exact", o->job.exact, "The exact clip of the mesh only");
    cmd->add_option("--svg", o->svg, "Write the GZ curve as an SVG plot")->check(kNonEmptyPath);
    cmd->add_option("--step", o->job.stepDegrees, "Heel step of the GZ curve, degrees (default 5)")
        ->check(kFinitePositive)
        ->check(CLI::Range(0.01, 90.0));
    cmd->callback([o, &selected] { selected = [o] { return runHydrostatics(*o); }; });
}

}  // namespace plimsoll::cli
