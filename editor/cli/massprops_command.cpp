// plimsoll massprops MESH [--size N | --exact] [--density RHO] [--shell-density SIGMA
//                    [--shell-density-map PNG]] --json
#include "cli/commands.h"

#include "cli/common.h"
#include "plimsoll/physics/massprops.h"
#include "plimsoll/io/painted_map_io.h"
#include "plimsoll/surface/painted_map.h"

#include <nlohmann/json.hpp>

#include <cmath>
#include <iostream>
#include <memory>

namespace plimsoll::cli {

namespace {
struct MassPropsOptions {
    std::string mesh;
    BakeOptions bake;
    bool exact = false;
    double density = 1000.0;
    double shellDensity = 0.0;
    std::string shellDensityMap;
    bool densityGiven = false;
    bool json = false;
};

int runMassProps(const MassPropsOptions& o) {
    std::optional<TriangleMesh> mesh;
    bool generatedAtlas = false;
    MeshReport report;
    if (o.exact) {
        mesh = loadClosedMesh(o.mesh, o.bake.unitScale, &report);
    } else if (std::optional<BakeableMesh> bakeable = loadMeshForBake(o.mesh, o.bake)) {
        mesh = std::move(bakeable->mesh);
        generatedAtlas = bakeable->generatedAtlas;
        report = std::move(bakeable->report);
    }
    if (!mesh) return kExitFailure;
    // A shell alone unless a solid density was asked for too.
    const double solidDensity = (o.shellDensity > 0 && !o.densityGiven) ? 0.0 : o.density;

    nlohmann::json out;
    MassProperties props;
    if (o.exact) {
        props = withoutHollow(exactSolidMassProperties(*mesh, solidDensity), report.hollow, solidDensity);
        if (o.shellDensity > 0) props = props + exactShellMassProperties(*mesh, o.shellDensity);
        out = {{"method", "exact"}, {"texture_size", nullptr}, {"covered_texels", nullptr}};
    } else {
        std::optional<SurfaceTextures> textures = bakeWithProgress(*mesh, o.bake);
        if (!textures) return kExitFailure;
        props = withoutHollow(textureSolidMassProperties(*textures, solidDensity), report.hollow, solidDensity);
        std::vector<double> painted;
        if (!o.shellDensityMap.empty()) {
            Result<PaintedMap> map = loadPaintedMap(o.shellDensityMap);
            if (!map) {
                std::cerr << "error: " << map.error().message << "\n";
                return kExitFailure;
            }
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
    out["volume"] = props.volume;
    out["mass"] = props.mass;
    out["center_of_mass"] = vectorJson(props.centerOfMass);
    out["inertia"] = {vectorJson(props.inertia.row(0)), vectorJson(props.inertia.row(1)),
                      vectorJson(props.inertia.row(2))};
    if (o.json) {
        std::cout << reportJson(out) << "\n";
    } else {
        std::cout << o.mesh << " (" << out["method"].get<std::string>() << ", "
                  << lengthUnitName(report.facts.unitScale) << ": " << report.facts.unitSource << ")\n"
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

void addMassPropsCommand(CLI::App& root, CommandRunner& selected) {
    auto o = std::make_shared<MassPropsOptions>();
    CLI::App* cmd = root.add_subcommand(
        "massprops", "Volume, mass, centre of mass and inertia, from textures or exactly");
    cmd->add_option("MESH", o->mesh, "Mesh file (a surface that is not one closed solid gives its physics solid)")->required();
    CLI::Option* size = addBakeOptions(*cmd, o->bake);
    addUnitOption(*cmd, o->bake.unitScale);
    CLI::Option* exact =
        cmd->add_flag("--exact", o->exact, "Exact polyhedral integrals of the mesh (no textures)")
            ->excludes(size);
    cmd->add_option("--density", o->density, "Solid density, kg/m^3 (default 1000)")
        ->check(kFiniteNonNegative)
        ->each([o](const std::string&) { o->densityGiven = true; });
    cmd->add_option("--shell-density", o->shellDensity,
                    "Thin-shell surface density, kg/m^2 (thickness x material density); "
                    "alone it gives a hollow shell, with --density both are added")
        ->check(kFiniteNonNegative);
    cmd->add_option("--shell-density-map", o->shellDensityMap,
                    "Painted surface-density map (8/16-bit PNG over the mesh's UVs): white is "
                    "--shell-density, black 0")
        ->check(CLI::ExistingFile)
        ->needs("--shell-density")
        ->excludes(exact);
    cmd->add_flag("--json", o->json, "Print one JSON object");
    cmd->callback([o, &selected] { selected = [o] { return runMassProps(*o); }; });
}

}  // namespace plimsoll::cli
