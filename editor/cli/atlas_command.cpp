// plimsoll atlas generate MESH --out atlas.obj: a physics atlas for a mesh without bijective UVs.
// plimsoll atlas transfer-map MAP --from A --to B --out MAP2: a painted map moved between UV
// layouts (a mesh and its atlas, or two versions of a mesh) through the surface.
#include "cli/commands.h"

#include "cli/common.h"
#include "plimsoll/surface/atlas.h"
#include "plimsoll/io/painted_map_io.h"
#include "plimsoll/surface/map_transfer.h"
#include "plimsoll/io/mesh_io.h"
#include "plimsoll/surface/painted_map.h"

#include <chrono>
#include <iostream>
#include <memory>

namespace plimsoll::cli {

namespace {

struct GenerateOptions {
    std::string mesh, out;
    AtlasSettings settings;
    bool json = false;
};

int runGenerate(const GenerateOptions& o) {
    Result<TriangleMesh> mesh = loadMesh(o.mesh);
    if (!mesh) {
        std::cerr << "error: " << mesh.error().message << "\n";
        return kExitFailure;
    }
    AtlasSettings settings = o.settings;
    settings.progress = stderrProgress("generating a physics atlas");
    const auto start = std::chrono::steady_clock::now();
    Result<PhysicsAtlas> atlas = generatePhysicsAtlas(*mesh, settings);
    if (!atlas) {
        std::cerr << "error: " << atlas.error().message << "\n";
        return kExitFailure;
    }
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    if (Status s = writeObj(atlas->mesh, o.out); !s.ok()) {
        std::cerr << "error: " << s.error().message << "\n";
        return kExitFailure;
    }
    const ValidationReport report = validateMesh(atlas->mesh);
    const nlohmann::json out = {{"mesh", o.mesh},
                                {"out", o.out},
                                {"texture_size", o.settings.textureSize},
                                {"charts", atlas->chartCount},
                                {"uv_coverage", atlas->uvCoverage},
                                {"uv_area_spread", report.uvAreaSpread},
                                {"seconds", seconds}};
    if (o.json) {
        std::cout << reportJson(out) << "\n";
    } else {
        std::cout << o.mesh << ": " << atlas->chartCount << " charts, " << 100.0 * atlas->uvCoverage
                  << "% of a " << o.settings.textureSize << "^2 texture, "
                  << "uv area spread " << report.uvAreaSpread << ", " << seconds
                  << " s; written to " << o.out << "\n";
    }
    return kExitOk;
}

struct TransferOptions {
    std::string map, from, to, out;
    int width = 0, height = 0;
};

int runTransfer(const TransferOptions& o) {
    Result<PaintedMap> map = loadPaintedMap(o.map);
    Result<TriangleMesh> from = loadMesh(o.from);
    Result<TriangleMesh> to = loadMesh(o.to);
    for (const Error* e : {map ? nullptr : &map.error(), from ? nullptr : &from.error(),
                           to ? nullptr : &to.error()}) {
        if (e) {
            std::cerr << "error: " << e->message << "\n";
            return kExitFailure;
        }
    }
    const int width = o.width > 0 ? o.width : map->width;
    const int height = o.height > 0 ? o.height : map->height;
    Result<PaintedMap> moved = transferPaintedMap(*map, *from, *to, width, height);
    if (!moved) {
        std::cerr << "error: " << o.map << ": " << moved.error().message << "\n";
        return kExitFailure;
    }
    if (Status s = savePaintedMap(*moved, o.out); !s.ok()) {
        std::cerr << "error: " << s.error().message << "\n";
        return kExitFailure;
    }
    std::cout << o.map << " -> " << o.out << " (" << width << " x " << height << ", over " << o.to
              << "'s UVs)\n";
    return kExitOk;
}

}  // namespace

void addAtlasCommand(CLI::App& root, CommandRunner& selected) {
    CLI::App* atlas = root.add_subcommand(
        "atlas", "Physics atlases: generate one, or move a painted map between UV layouts");
    atlas->require_subcommand(1);

    auto generate = std::make_shared<GenerateOptions>();
    CLI::App* g = atlas->add_subcommand(
        "generate", "Generate a physics atlas (charts without folds, packed with gutters)");
    g->add_option("MESH", generate->mesh, "Mesh file (its own UVs are ignored)")->required();
    g->add_option("--out", generate->out, "The mesh with the atlas as its UVs (OBJ)")
        ->required()
        ->check(kNonEmptyPath);
    g->add_option("--size", generate->settings.textureSize,
                  "Texels per side the atlas is packed for")
        ->check(CLI::Range(kMinTextureSize, kMaxTextureSize))
        ->capture_default_str();
    g->add_option("--gutter", generate->settings.gutterTexels, "Empty texels between charts")
        ->check(CLI::Range(0, 64))
        ->capture_default_str();
    g->add_option("--max-chart-angle", generate->settings.maxChartAngleDegrees,
                  "Largest angle (degrees) between a chart's normals and its projection axis")
        ->check(CLI::Range(1.0, 89.0))
        ->capture_default_str();
    g->add_flag("--json", generate->json, "Print the result as one JSON object");
    g->callback(
        [generate, &selected] { selected = [generate] { return runGenerate(*generate); }; });

    auto transfer = std::make_shared<TransferOptions>();
    CLI::App* t = atlas->add_subcommand(
        "transfer-map",
        "Resample a painted map from one UV layout onto another through the surface");
    t->add_option("MAP", transfer->map, "Painted map (8/16-bit PNG) over --from's UVs")->required();
    t->add_option("--from", transfer->from, "Mesh whose UVs the map is painted over")->required();
    t->add_option("--to", transfer->to, "Mesh (the same surface, other UVs) to move it onto")
        ->required();
    t->add_option("--out", transfer->out, "The moved map (16-bit PNG)")
        ->required()
        ->check(kNonEmptyPath);
    t->add_option("--width", transfer->width, "Width of the result (default: the map's)")
        ->check(CLI::Range(1, 16384));
    t->add_option("--height", transfer->height, "Height of the result (default: the map's)")
        ->check(CLI::Range(1, 16384));
    t->callback(
        [transfer, &selected] { selected = [transfer] { return runTransfer(*transfer); }; });
}

}  // namespace plimsoll::cli
