// plimsoll validate MESH: lists every problem and says how the mesh can be used: as it is,
// through a generated atlas or a physics solid (exit 0, with the reasons), or not at all
// (exit 1, with what to fix in the modelling tool).
#include "cli/commands.h"
#include "cli/common.h"
#include "cli/jobs.h"

#include "plimsoll/geometry/validate.h"
#include "plimsoll/io/mesh_io.h"
#include "plimsoll/repair/physics_solid.h"

#include <nlohmann/json.hpp>

#include <iostream>
#include <memory>

namespace plimsoll::cli {

namespace {
struct ValidateOptions {
    std::string mesh;
    double unitScale = 0;
    bool json = false;
};

Verdict judge(const TriangleMesh& mesh, const ValidationReport& report) {
    Verdict verdict;
    for (const Problem& p : report.problems)
        if (p.severity == Severity::Error)
            verdict.reasons.push_back(std::string(problemCode(p.kind)) + ": " + p.message);
    ValidationReport surface = report;
    std::erase_if(surface.problems, [](const Problem& p) { return isUvProblem(p.kind); });
    Result<PhysicsSolid> solid = physicsSolidFor(mesh, surface);
    if (!solid) {
        verdict.code = "unusable";
        verdict.reasons.push_back(solid.error().message);
        return verdict;
    }
    if (!solid->repairs.empty())
        verdict.code = "physics-solid";
    else if (!report.usableForTexture())
        verdict.code = "generated-atlas";
    verdict.solid = std::move(*solid);
    return verdict;
}

const char* verdictLine(const Verdict& v) {
    const std::string code = v.code;
    if (code == "as-is") return "usable as is";
    if (code == "generated-atlas") return "usable through a generated physics atlas";
    if (code == "physics-solid")
        return "usable through a physics solid (repaired, baked on a generated atlas)";
    return "cannot be used";
}

nlohmann::json toJson(const TriangleMesh& mesh, const ValidationReport& report,
                      const MeshFileFacts& facts, const Verdict& verdict) {
    nlohmann::json problems = nlohmann::json::array();
    for (const Problem& p : report.problems) {
        problems.push_back({{"code", problemCode(p.kind)},
                            {"severity", p.severity == Severity::Error ? "error" : "warning"},
                            {"count", p.count},
                            {"surface_fraction", p.surfaceFraction},
                            {"message", p.message}});
    }
    nlohmann::json parts = nlohmann::json::array();
    for (const MeshPart& part : facts.parts)
        parts.push_back(
            {{"name", part.name}, {"triangles", part.triangleCount}, {"has_uvs", part.hasUvs}});
    const Bounds3 bounds = computeBounds(mesh);
    const bool usable = verdict.solid.has_value();
    return {{"mesh", report.source},
            {"triangles", mesh.triangleCount()},
            {"vertices", mesh.vertexCount()},
            {"has_uvs", mesh.hasUvs()},
            {"unit_scale", facts.unitScale},
            {"unit_source", facts.unitSource},
            {"bounds", {{"min", vectorJson(bounds.min)}, {"max", vectorJson(bounds.max)}}},
            {"parts", parts},
            {"usable", usable},
            {"usable_as_is", report.usableForTexture()},
            {"verdict", verdict.code},
            {"reasons", verdict.reasons},
            {"closed_solid", report.closedSolid()},
            {"repairs", usable ? repairsJson(verdict.solid->repairs) : nlohmann::json::array()},
            {"material_volume",
             usable ? nlohmann::json(verdict.solid->materialVolume) : nlohmann::json()},
            {"displacement_volume",
             usable ? nlohmann::json(verdict.solid->displacementVolume) : nlohmann::json()},
            {"uv_area_spread", report.uvAreaSpread},
            {"mirrored_surface_fraction", report.mirroredSurfaceFraction},
            {"problems", problems}};
}

void printHuman(const ValidateOptions& options, const TriangleMesh& mesh,
                const ValidationReport& report, const MeshFileFacts& facts,
                const Verdict& verdict) {
    std::cout << report.format();
    const Bounds3 bounds = computeBounds(mesh);
    const Eigen::Vector3d size = bounds.max - bounds.min;
    std::cout << options.mesh << ": " << mesh.triangleCount() << " triangles, "
              << mesh.vertexCount() << " vertices, " << facts.parts.size()
              << " parts: " << verdictLine(verdict) << "\n"
              << "  unit: " << lengthUnitName(facts.unitScale) << " (" << facts.unitSource
              << "); size " << size.x() << " x " << size.y() << " x " << size.z()
              << " m (x, y up, z)\n";
    if (facts.someUvsMissing()) {
        std::cout << "  some parts have no UVs (";
        bool first = true;
        for (const MeshPart& part : facts.parts)
            if (!part.hasUvs) {
                std::cout << (first ? "" : ", ") << (part.name.empty() ? "unnamed" : part.name);
                first = false;
            }
        std::cout << "): their UVs are (0, 0), the other parts keep theirs\n";
    }
    if (mesh.hasUvs()) {
        std::cout << "  uv area spread " << report.uvAreaSpread
                  << " (world area per UV area, 99th over 1st percentile), mirrored "
                  << 100.0 * report.mirroredSurfaceFraction << "% of the surface\n";
    }
    const std::string code = verdict.code;
    if (code == "unusable") {
        for (const std::string& reason : verdict.reasons) std::cout << "  " << reason << "\n";
        std::cout << "  to fix in the modelling tool: give the model at least one closed part with "
                     "volume "
                     "(close holes, remove stray points and lines, keep faces with area)\n";
        return;
    }
    if (code == "generated-atlas")
        std::cout
            << "  its own UVs cannot be baked (the errors above); baking generates a physics atlas "
               "(--atlas auto, the default)\n";
    if (code == "physics-solid") {
        std::cout << (verdict.solid->openings.empty()
                          ? "  the surface is not one closed, consistently oriented solid; the "
                            "physics solid is "
                            "baked instead, the mesh stays for painting:\n"
                          : "  an open hull or container: its physics solid, with its openings "
                            "capped, is baked "
                            "instead, the mesh stays for painting:\n");
        for (const Repair& r : verdict.solid->repairs)
            std::cout << "    " << r.kind << " " << r.count << ": " << r.detail
                      << (r.volumeChange != 0
                              ? " (volume " + std::to_string(r.volumeChange) + " m^3)"
                              : "")
                      << "\n";
    }
    std::cout << "  material volume " << verdict.solid->materialVolume
              << " m^3, displacement volume " << verdict.solid->displacementVolume << " m^3\n";
}

int runValidate(const ValidateOptions& options) {
    Result<Validation> v = validateJob(options.mesh, options.unitScale);
    if (!v) {
        std::cerr << "error: " << v.error().message << "\n";
        return kExitFailure;
    }
    if (options.json)
        std::cout << reportJson(v->json) << "\n";
    else
        printHuman(options, v->mesh, v->report, v->facts, v->verdict);
    return v->verdict.solid ? kExitOk : kExitFailure;
}
}  // namespace

Result<Validation> validateJob(const std::string& path, double unitScale) {
    Validation v;
    MeshLoadOptions options;
    options.unitScale = unitScale;
    Result<TriangleMesh> mesh = loadMesh(path, options, &v.facts);
    if (!mesh) return mesh.error();
    v.mesh = std::move(*mesh);
    v.report = validateMesh(v.mesh);
    v.verdict = judge(v.mesh, v.report);
    v.json = toJson(v.mesh, v.report, v.facts, v.verdict);
    return v;
}

void addValidateCommand(CLI::App& root, CommandRunner& selected) {
    auto options = std::make_shared<ValidateOptions>();
    CLI::App* cmd = root.add_subcommand(
        "validate",
        "Check a mesh and say how it can be used: as is, through a generated atlas or "
        "a physics solid, or not at all");
    cmd->add_option("MESH", options->mesh, "Mesh file (OBJ, glTF/GLB, PLY, FBX, STL, ...)")
        ->required();
    addUnitOption(*cmd, options->unitScale);
    cmd->add_flag("--json", options->json, "Print the report as one JSON object");
    cmd->callback([options, &selected] { selected = [options] { return runValidate(*options); }; });
}

}  // namespace plimsoll::cli
