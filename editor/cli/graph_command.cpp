// plimsoll graph auto MESH [--segments K] [--thickness T] [--volume-samples N] --out GRAPH.json
// plimsoll graph validate GRAPH.json [--mesh MESH]
// Water graphs (graph.h): automatic construction from the SDF segmentation (paper 4.1) and the
// checks of a hand-built or edited graph.
#include "cli/commands.h"

#include "cli/common.h"
#include "plimsoll/graph/graph.h"
#include "plimsoll/graph_auto/graph_auto.h"
#include "plimsoll/io/graph_json.h"
#include "plimsoll/physics/massprops.h"
#include "plimsoll/io/mesh_io.h"
#include "plimsoll/geometry/validate.h"

#include <cstdio>
#include <iostream>
#include <memory>

namespace plimsoll::cli {

namespace {

struct GraphOptions {
    std::string mesh;
    std::string graph;
    std::string out;
    int segments = 0;
    double thickness = 0;
    int volumeSamples = AutoGraphSettings{}.volumeSamples;
};

int runAuto(const GraphOptions& o) {
    std::optional<TriangleMesh> mesh = loadClosedMesh(o.mesh);
    if (!mesh) return kExitFailure;
    AutoGraphSettings settings;
    settings.segments = o.segments;
    settings.shellThickness = o.thickness;
    settings.volumeSamples = o.volumeSamples;
    settings.progress = stderrProgress("segmenting");
    AutoGraphReport report;
    Result<WaterGraph> graph = buildAutomaticGraph(*mesh, settings, &report);
    if (!graph) {
        std::cerr << "error: " << graph.error().message << "\n";
        return kExitFailure;
    }
    const GraphReport check = validateGraph(*graph, &*mesh, o.out);
    if (!check.problems.empty()) std::cerr << check.format() << "\n";
    if (check.hasErrors()) return kExitFailure;
    if (Status s = saveGraph(*graph, o.out); !s.ok()) {
        std::cerr << "error: " << s.error().message << "\n";
        return kExitFailure;
    }
    std::printf("%s: %zu nodes, %zu pipes from %s (k = %d%s)\n", o.out.c_str(), graph->nodes.size(),
                graph->pipes.size(), o.mesh.c_str(), static_cast<int>(graph->nodes.size()),
                o.segments > 0 ? "" : ", chosen from the mesh");
    std::printf("  enclosed volume %.9g m^3, capacities sum to %.9g m^3%s\n", report.enclosedVolume,
                graph->totalCapacity(),
                o.thickness > 0 ? " (the enclosed volume less the shell's area x thickness)" : "");
    std::printf("  interior grid %.9g m^3 (%.2e relative to the enclosed volume)\n",
                report.sampledVolume,
                std::abs(report.sampledVolume - report.enclosedVolume) / report.enclosedVolume);
    std::printf("  SDF segmentation %.2f s, total %.2f s\n", report.segmentation.sdfSeconds,
                report.totalSeconds);
    for (const GraphNode& n : graph->nodes) {
        std::printf("  %-4s at (%.4f, %.4f, %.4f), capacity %.6g m^3\n", n.id.c_str(),
                    n.position.x(), n.position.y(), n.position.z(), n.capacity);
    }
    return kExitOk;
}

int runValidate(const GraphOptions& o) {
    std::optional<TriangleMesh> mesh;
    if (!o.mesh.empty()) {
        mesh = loadClosedMesh(o.mesh);
        if (!mesh) return kExitFailure;
    }
    std::string warnings;
    Result<WaterGraph> graph = loadGraph(o.graph, mesh ? &*mesh : nullptr, &warnings);
    if (!graph) {
        std::cerr << graph.error().message << "\n";
        return kExitFailure;
    }
    if (!warnings.empty()) std::cerr << warnings << "\n";
    std::printf("%s: %zu nodes, %zu pipes, capacity %.6g m^3, water %.6g m^3: valid\n",
                o.graph.c_str(), graph->nodes.size(), graph->pipes.size(), graph->totalCapacity(),
                graph->totalWater());
    return kExitOk;
}

}  // namespace

void addGraphCommand(CLI::App& root, CommandRunner& selected) {
    CLI::App* sub =
        root.add_subcommand("graph", "Water graphs: build one automatically, or check one");
    sub->require_subcommand(1);
    auto o = std::make_shared<GraphOptions>();

    CLI::App* autoCmd = sub->add_subcommand(
        "auto", "Segment a closed mesh (Shape Diameter Function) and write its water graph");
    autoCmd->add_option("mesh", o->mesh, "Closed mesh (any format assimp reads)")->required();
    autoCmd
        ->add_option("--segments,-k", o->segments,
                     "Number of nodes (segments); 0 or absent: chosen from the mesh")
        ->check(CLI::Range(0, 64));
    autoCmd
        ->add_option("--thickness", o->thickness,
                     "Shell thickness (m): capacities leave out the shell's own volume")
        ->check(kFiniteNonNegative);
    autoCmd
        ->add_option("--volume-samples", o->volumeSamples,
                     "Grid cells along the longest side for the volume shares")
        ->check(CLI::Range(8, 256));
    autoCmd->add_option("--out,-o", o->out, "graph.json to write")
        ->required()
        ->check(kNonEmptyPath);
    autoCmd->callback([&selected, o] { selected = [o] { return runAuto(*o); }; });

    CLI::App* validate =
        sub->add_subcommand("validate", "Check a graph.json (and its nodes against a mesh)");
    validate->add_option("graph", o->graph, "graph.json")->required();
    validate->add_option("--mesh", o->mesh, "The body's mesh: warn about nodes outside it");
    validate->callback([&selected, o] { selected = [o] { return runValidate(*o); }; });
}

}  // namespace plimsoll::cli
