// plimsoll bake MESH --size N | --tolerance T --out DIR: position, area-vector and coverage
// textures (EXR).
#include "cli/commands.h"

#include "cli/common.h"
#include "plimsoll/io/bake_io.h"
#include "plimsoll/io/mesh_io.h"
#include "plimsoll/scene/level_ladder.h"

#include <chrono>
#include <iostream>
#include <memory>

namespace plimsoll::cli {

namespace {
struct BakeCommandOptions {
    std::string mesh;
    BakeOptions bake;
    std::optional<double> tolerance;
    std::string out;
};

/// The bake at the smallest size that meets the tolerance (level_ladder.h), saying which.
std::optional<SurfaceTextures> bakeToTolerance(const std::string& file, const TriangleMesh& mesh,
                                               const BakeOptions& options, double tolerance,
                                               std::optional<LevelChoice>& choice) {
    BakeSettings settings;
    settings.maxTexelStretch = options.maxTexelStretch;
    std::cerr << "note: trying 16, 32, 64, ... texels until the force error is within " << tolerance
              << " of rho g V\n";
    Result<LevelChoice> chosen = chooseLevelForTolerance(mesh, tolerance, settings);
    if (!chosen) {
        std::cerr << "error: " << file << ": --tolerance: " << chosen.error().message << "\n";
        return std::nullopt;
    }
    SurfaceTextures textures = *chosen->textures;
    chosen->textures.reset();
    choice = std::move(*chosen);
    return textures;
}

int runBake(const BakeCommandOptions& options) {
    std::optional<BakeableMesh> mesh = loadMeshForBake(options.mesh, options.bake);
    if (!mesh) return kExitFailure;
    const auto start = std::chrono::steady_clock::now();
    std::optional<LevelChoice> choice;
    std::optional<SurfaceTextures> textures =
        options.tolerance
            ? bakeToTolerance(options.mesh, mesh->mesh, options.bake, *options.tolerance, choice)
            : bakeWithProgress(mesh->mesh, options.bake);
    if (!textures) return kExitFailure;
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    if (Status s = writeBakedTextures(*textures, options.out, options.mesh); !s.ok()) {
        std::cerr << "error: " << s.error().message << "\n";
        return kExitFailure;
    }
    // The textures are laid out on the generated atlas: painted maps and runtime engines need it.
    const std::filesystem::path atlasFile = std::filesystem::path(options.out) / "atlas.obj";
    if (mesh->generatedAtlas) {
        if (Status s = writeObj(mesh->mesh, atlasFile); !s.ok()) {
            std::cerr << "error: " << s.error().message << "\n";
            return kExitFailure;
        }
    }
    std::cout << options.mesh << ": baked " << textures->size << "^2 in " << seconds << " s\n";
    if (choice)
        std::cout << "  tolerance       " << choice->tolerance << ": "
                  << describeLevelChoice(*choice) << "\n";
    std::cout << "  covered texels  " << textures->distinctTexelCount() << "\n"
              << "  texel samples   " << textures->coveredCount()
              << " (texels shared by UV islands or refined where the map squeezes surface "
                 "hold several)\n"
              << "  uv coverage     " << textures->uvCoverage() << "\n"
              << "  surface area    " << textures->surfaceArea() << " m^2\n"
              << "  closure error   " << textures->closureError() << "\n"
              << "  texel area spread " << textures->texelAreaSpread()
              << " (largest over smallest surface per texel, 1% extremes ignored)\n"
              << "  atlas           "
              << (mesh->generatedAtlas ? "generated, written to " + atlasFile.string()
                                       : std::string("the mesh's own UVs"))
              << "\n"
              << "  unit            " << lengthUnitName(mesh->report.facts.unitScale) << " ("
              << mesh->report.facts.unitSource << ")\n"
              << "  repairs         " << describeRepairs(mesh->report.repairs)
              << (mesh->report.repaired() ? " (the physics solid is baked)" : "") << "\n"
              << "  material volume " << mesh->report.materialVolume << " m^3\n"
              << "  displacement volume " << mesh->report.displacementVolume << " m^3\n"
              << "  written to      " << options.out << "\n";
    return kExitOk;
}
}  // namespace

void addBakeCommand(CLI::App& root, CommandRunner& selected) {
    auto options = std::make_shared<BakeCommandOptions>();
    CLI::App* cmd = root.add_subcommand(
        "bake", "Bake position, area-vector and coverage textures (float32 EXR + manifest.json)");
    cmd->add_option("MESH", options->mesh,
                    "Mesh file (closed; its UVs, or a generated atlas: see --atlas)")
        ->required();
    CLI::Option* size = addBakeOptions(*cmd, options->bake);
    cmd->add_option(
           "--tolerance", options->tolerance,
           "Instead of --size: the largest force error allowed against the exact clip, a share "
           "of rho g V (e.g. 1e-3); the smallest of 16, 32, ... 1024 texels that meets it is baked")
        ->check(kFinitePositive & CLI::Range(0.0, 1.0))
        ->excludes(size);
    addUnitOption(*cmd, options->bake.unitScale);
    cmd->add_option("--out", options->out, "Output folder (created if missing)")
        ->required()
        ->check(kNonEmptyPath);
    cmd->callback([options, &selected] { selected = [options] { return runBake(*options); }; });
}

}  // namespace plimsoll::cli
