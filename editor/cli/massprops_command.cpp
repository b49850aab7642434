// plimsoll massprops MESH [--size N | --exact] [--density RHO] [--shell-density SIGMA
//                    [--shell-density-map PNG]] --json
// plimsoll massprops PROJECT [--body NAME] --json
#include "cli/commands.h"

#include "cli/common.h"
#include "cli/jobs.h"
#include "plimsoll/physics/massprops.h"
#include "plimsoll/io/painted_map_io.h"
#include "plimsoll/project/scene_loader.h"
#include "plimsoll/surface/painted_map.h"

#include <nlohmann/json.hpp>

#include <cmath>
#include <iostream>
#include <memory>

namespace plimsoll::cli {

namespace {
struct MassPropsOptions {
    MassPropsJob job;
    bool json = false;
};

int runMassProps(const MassPropsOptions& options) {
    Result<MassPropsOutcome> outcome = massPropsJob(options.job, stderrReporter());
    if (!outcome) {
        std::cerr << "error: " << outcome.error().message << "\n";
        return kExitFailure;
    }
    const nlohmann::json& out = outcome->json;
    const MassProperties& props = outcome->props;
    const MeshReport& report = outcome->report;
    if (options.json) {
        std::cout << reportJson(out) << "\n";
    } else if (out.contains("project")) {
        std::cout << options.job.mesh << ", body '" << out["body"].get<std::string>()
                  << "' (texture " << out["texture_size"].get<int>() << "^2)\n"
                  << "  volume          " << props.volume << " m^3\n"
                  << "  mass            " << props.mass << " kg\n"
                  << "  centre of mass  " << props.centerOfMass.transpose() << " m\n"
                  << "  inertia (kg m^2, about the centre of mass)\n"
                  << props.inertia << "\n";
    } else {
        std::cout << options.job.mesh << " (" << out["method"].get<std::string>() << ", "
                  << lengthUnitName(report.facts.unitScale) << ": " << report.facts.unitSource
                  << ")\n"
                  << "  repairs         " << describeRepairs(report.repairs) << "\n"
                  << "  volume          " << props.volume << " m^3\n"
                  << "  mass            " << props.mass << " kg\n"
                  << "  centre of mass  " << props.centerOfMass.transpose() << " m\n"
                  << "  inertia (kg m^2, about the centre of mass)\n"
                  << props.inertia << "\n";
    }
    return kExitOk;
}
}  // namespace

namespace {

bool isProjectPath(const std::string& path) { return path.ends_with(".plim.json"); }

/// The mass properties of a project's body as the World has them: the body loaded and baked by
/// loadSceneBody, whose bake weighs it (bodyMassProperties: the solid, the shell scaled by the
/// painted density and thickness maps, the caps and the space behind them). Its radiation is
/// not computed: it does not change the mass.
Result<MassPropsOutcome> projectMassPropsJob(const MassPropsJob& o, const Reporter& reporter) {
    if (o.exact || o.densityGiven || o.shellDensity > 0 || !o.shellDensityMap.empty())
        return makeError(ErrorKind::invalidArgument,
                         o.mesh +
                             ": a project's body has its own material and texture size "
                             "(--exact, --density, --shell-density and their maps are for "
                             "meshes)");
    Result<Project> project = loadProject(o.mesh);
    if (!project) return project.error();
    Result<std::size_t> index = bodyIndexOf(*project, o.body, o.mesh);
    if (!index) return index.error();
    project->bodies[*index].radiation = RadiationDesc{.enabled = false};
    Result<SceneBody> body = loadSceneBody(
        *project, *index, [&](const std::string& line) { reporter.note("note: " + line + "\n"); });
    if (!body) return body.error();
    MassPropsOutcome outcome;
    outcome.props = *body->mass;
    const MaterialDesc& material = body->desc.material;
    nlohmann::json& out = outcome.json;
    out = {{"method", "texture"},
           {"project", o.mesh},
           {"body", body->desc.name},
           {"mesh", body->desc.mesh},
           {"texture_size", body->desc.textureSize},
           {"covered_texels", body->textures->distinctTexelCount()},
           {"density", material.density.value_or(0.0)},
           {"shell_density", material.shellSurfaceDensity.value_or(0.0)},
           {"shell_density_map", material.shellDensityMap},
           {"shell_thickness_map", material.shellThicknessMap}};
    return outcome;
}

void putMassProperties(nlohmann::json& out, const MassProperties& props) {
    out["volume"] = props.volume;
    out["mass"] = props.mass;
    out["center_of_mass"] = vectorJson(props.centerOfMass);
    out["inertia"] = {vectorJson(props.inertia.row(0)), vectorJson(props.inertia.row(1)),
                      vectorJson(props.inertia.row(2))};
}

}  // namespace

Result<MassPropsOutcome> massPropsJob(const MassPropsJob& o, const Reporter& reporter) {
    if (isProjectPath(o.mesh)) {
        Result<MassPropsOutcome> outcome = projectMassPropsJob(o, reporter);
        if (outcome) putMassProperties(outcome->json, outcome->props);
        return outcome;
    }
    if (!o.body.empty())
        return makeError(ErrorKind::invalidArgument,
                         "--body names a body of a project (*.plim.json), not of a mesh");
    MassPropsOutcome outcome;
    MeshReport& report = outcome.report;
    std::optional<TriangleMesh> mesh;
    bool generatedAtlas = false;
    if (o.exact) {
        Result<TriangleMesh> closed = closedMeshOf(o.mesh, o.bake.unitScale, &report, reporter);
        if (!closed) return closed.error();
        mesh = std::move(*closed);
    } else {
        Result<BakeableMesh> bakeable = bakeableMeshOf(o.mesh, o.bake, reporter);
        if (!bakeable) return bakeable.error();
        mesh = std::move(bakeable->mesh);
        generatedAtlas = bakeable->generatedAtlas;
        report = std::move(bakeable->report);
    }
    // A shell alone unless a solid density was asked for too.
    const double solidDensity = (o.shellDensity > 0 && !o.densityGiven) ? 0.0 : o.density;

    nlohmann::json& out = outcome.json;
    MassProperties& props = outcome.props;
    if (o.exact) {
        props = withoutHollow(exactSolidMassProperties(*mesh, solidDensity), report.hollow,
                              solidDensity);
        if (o.shellDensity > 0) props = props + exactShellMassProperties(*mesh, o.shellDensity);
        out = {{"method", "exact"}, {"texture_size", nullptr}, {"covered_texels", nullptr}};
    } else {
        Result<SurfaceTextures> textures = bakeTextures(*mesh, o.bake, reporter);
        if (!textures) return textures.error();
        props = withoutHollow(textureSolidMassProperties(*textures, solidDensity), report.hollow,
                              solidDensity);
        std::vector<double> painted;
        if (!o.shellDensityMap.empty()) {
            Result<PaintedMap> map = loadPaintedMap(o.shellDensityMap);
            if (!map) return map.error();
            painted = sampleAtTexels(*map, *textures, o.shellDensity);
        }
        if (o.shellDensity > 0)
            props = props + textureShellMassProperties(*textures, o.shellDensity, painted);
        out = {{"method", "texture"},
               {"texture_size", o.bake.size},
               {"max_texel_stretch", o.bake.maxTexelStretch},
               {"atlas", generatedAtlas ? "generated" : "mesh"},
               {"texel_area_spread", textures->texelAreaSpread()},
               {"uv_coverage", textures->uvCoverage()},
               {"covered_texels", textures->distinctTexelCount()},
               {"texel_samples", textures->coveredCount()},
               {"closure_error", textures->closureError()}};
    }
    out["mesh"] = o.mesh;
    out["unit_scale"] = report.facts.unitScale;
    out["repairs"] = repairsJson(report.repairs);
    // The exact volumes of the solid used (the texture method's "volume" estimates the same).
    out["material_volume"] = report.materialVolume;
    out["displacement_volume"] = report.displacementVolume;
    out["density"] = solidDensity;
    out["shell_density"] = o.shellDensity;
    putMassProperties(out, props);
    return outcome;
}

void addMassPropsCommand(CLI::App& root, CommandRunner& selected) {
    auto o = std::make_shared<MassPropsOptions>();
    CLI::App* cmd = root.add_subcommand(
        "massprops", "Volume, mass, centre of mass and inertia, from textures or exactly");
    cmd->add_option("MESH", o->job.mesh,
                    "Mesh file (a surface that is not one closed solid gives its physics "
                    "solid), or a project (*.plim.json): its body as the World weighs it, with "
                    "its material and painted density and thickness maps")
        ->required();
    cmd->add_option("--body", o->job.body, "A project's body by name (default: the first)");
    CLI::Option* size = addBakeOptions(*cmd, o->job.bake);
    addUnitOption(*cmd, o->job.bake.unitScale);
    CLI::Option* exact = cmd->add_flag("--exact", o->job.exact,
                                       "Exact polyhedral integrals of the mesh (no textures)")
                             ->excludes(size);
    cmd->add_option("--density", o->job.density, "Solid density, kg/m^3 (default 1000)")
        ->check(kFiniteNonNegative)
        ->each([o](const std::string&) { o->job.densityGiven = true; });
    cmd->add_option("--shell-density", o->job.shellDensity,
                    "Thin-shell surface density, kg/m^2 (thickness x material density); "
                    "alone it gives a hollow shell, with --density both are added")
        ->check(kFiniteNonNegative);
    cmd->add_option("--shell-density-map", o->job.shellDensityMap,
                    "Painted surface-density map (8/16-bit PNG over the mesh's UVs): white is "
                    "--shell-density, black 0")
        ->check(CLI::ExistingFile)
        ->needs("--shell-density")
        ->excludes(exact);
    cmd->add_flag("--json", o->json, "Print one JSON object");
    cmd->callback([o, &selected] { selected = [o] { return runMassProps(*o); }; });
}

}  // namespace plimsoll::cli
