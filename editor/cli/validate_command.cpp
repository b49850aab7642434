// plimsoll validate MESH: lists every problem; exits 0 when the mesh can be baked as it is.
#include "cli/commands.h"

#include "plimsoll/io/mesh_io.h"
#include "plimsoll/geometry/validate.h"

#include <nlohmann/json.hpp>

#include <iostream>
#include <memory>

namespace plimsoll::cli {

namespace {
struct ValidateOptions {
    std::string mesh;
    bool json = false;
};

nlohmann::json toJson(const TriangleMesh& mesh, const ValidationReport& report) {
    nlohmann::json problems = nlohmann::json::array();
    for (const Problem& p : report.problems) {
        problems.push_back({{"code", problemCode(p.kind)},
                            {"severity", p.severity == Severity::Error ? "error" : "warning"},
                            {"count", p.count},
                            {"surface_fraction", p.surfaceFraction},
                            {"message", p.message}});
    }
    return {{"mesh", report.source},
            {"triangles", mesh.triangleCount()},
            {"vertices", mesh.vertexCount()},
            {"has_uvs", mesh.hasUvs()},
            {"usable", report.usableForTexture()},
            {"closed_solid", report.closedSolid()},
            {"uv_area_spread", report.uvAreaSpread},
            {"mirrored_surface_fraction", report.mirroredSurfaceFraction},
            {"problems", problems}};
}

int runValidate(const ValidateOptions& options) {
    Result<TriangleMesh> mesh = loadMesh(options.mesh);
    if (!mesh) {
        std::cerr << "error: " << mesh.error().message << "\n";
        return kExitFailure;
    }
    const ValidationReport report = validateMesh(*mesh);
    if (options.json) {
        std::cout << toJson(*mesh, report).dump(2) << "\n";
    } else {
        std::cout << report.format();
        std::cout << options.mesh << ": " << mesh->triangleCount() << " triangles, "
                  << mesh->vertexCount() << " vertices: "
                  << (report.usableForTexture() ? "usable" : "NOT usable") << "\n";
        if (mesh->hasUvs()) {
            std::cout << "  uv area spread " << report.uvAreaSpread
                      << " (world area per UV area, 99th over 1st percentile), mirrored "
                      << 100.0 * report.mirroredSurfaceFraction << "% of the surface\n";
        }
        if (!report.usableForTexture() && report.closedSolid()) {
            std::cout << "  baking it generates a physics atlas (--atlas auto, the default)\n";
        }
    }
    return report.usableForTexture() ? kExitOk : kExitFailure;
}
}  // namespace

void addValidateCommand(CLI::App& root, CommandRunner& selected) {
    auto options = std::make_shared<ValidateOptions>();
    CLI::App* cmd = root.add_subcommand(
        "validate", "Check a mesh: closed, manifold, oriented, finite, bijective UVs");
    cmd->add_option("MESH", options->mesh, "Mesh file (OBJ, glTF/GLB, PLY, FBX, STL, ...)")
        ->required();
    cmd->add_flag("--json", options->json, "Print the report as one JSON object");
    cmd->callback([options, &selected] { selected = [options] { return runValidate(*options); }; });
}

}  // namespace plimsoll::cli
