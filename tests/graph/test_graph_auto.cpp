// Automatic water graphs (paper 4.1): SDF segmentation into k segments, nodes inside the mesh,
// a connected graph, capacities that sum to the enclosed volume; and the `plimsoll graph`
// commands end to end.
#include "plimsoll/graph/graph.h"
#include "plimsoll/graph_auto/graph_auto.h"
#include "plimsoll/io/graph_json.h"
#include "plimsoll/physics/massprops.h"
#include "plimsoll/io/mesh_io.h"
#include "plimsoll/samples/primitives.h"

#include "cli_runner.h"
#include "test_support.h"

#include <cmath>

namespace plimsoll {
namespace test_graph_auto {
namespace {

namespace fs = std::filesystem;

/// The checks of the issue on one mesh: k nodes, connected, every node inside, capacities
/// summing to the enclosed volume (exact, divergence theorem) within 1%.
void expectGoodGraph(const TriangleMesh& mesh, int k) {
    SCOPED_TRACE(mesh.source);
    AutoGraphSettings settings;
    settings.segments = k;
    AutoGraphReport report;
    Result<WaterGraph> graph = buildAutomaticGraph(mesh, settings, &report);
    ASSERT_TRUE(graph.ok()) << graph.error().message;
    EXPECT_EQ(static_cast<int>(graph->nodes.size()), k);
    const GraphReport check = validateGraph(*graph, &mesh);
    EXPECT_FALSE(check.hasErrors()) << check.format();
    EXPECT_FALSE(check.has(GraphProblemKind::Disconnected)) << check.format();
    EXPECT_FALSE(check.has(GraphProblemKind::NodeOutsideMesh)) << check.format();
    const double exact = exactSolidMassProperties(mesh, 1.0).volume;
    const double error = std::abs(graph->totalCapacity() - exact) / exact;
    EXPECT_LT(error, 0.01);
    for (const GraphNode& n : graph->nodes) EXPECT_GT(n.capacity, 0.0) << n.id;
    // The grid that shares the volume out covers it (independent of the exact sum).
    const double grid = std::abs(report.sampledVolume - exact) / exact;
    EXPECT_LT(grid, 0.05);
    std::printf(
        "  %-26s k=%d: %zu pipes, capacity sum error %.2e, interior grid %.2e, SDF "
        "%.2f s, total %.2f s\n",
        fs::path(mesh.source).filename().c_str(), k, graph->pipes.size(), error, grid,
        report.segmentation.sdfSeconds, report.totalSeconds);
}

TEST(AutoGraph, SharedMeshes) {
    PLIMSOLL_SKIP_WITHOUT_CGAL();
    int found = 0;
    for (const auto& [name, k] : {std::pair{"bunny.obj", 5}, std::pair{"spot.obj", 4}}) {
        const std::optional<fs::path> path = test::sharedMesh(name);
        if (!path) continue;
        Result<TriangleMesh> mesh = loadMesh(*path);
        ASSERT_TRUE(mesh.ok()) << mesh.error().message;
        expectGoodGraph(*mesh, k);
        ++found;
    }
    if (found == 0) GTEST_SKIP() << "../shared/meshes not present";
}

TEST(AutoGraph, DumbbellSplitsIntoItsTwoLobes) {
    PLIMSOLL_SKIP_WITHOUT_CGAL();
    // Two balls of radius 0.5 joined by a thin neck, along y: two segments, one node in each
    // ball, capacities equal by symmetry, one pipe through the neck.
    std::vector<ProfilePoint> profile;
    const int n = 24;
    for (int i = 0; i <= n; ++i) {  // lower ball, centre y = -0.6
        const double a = -std::numbers::pi / 2 + std::numbers::pi * i / n;
        const double r = 0.5 * std::cos(a), y = -0.6 + 0.5 * std::sin(a);
        if (y > -0.15) break;
        profile.push_back({std::abs(r) < 1e-12 ? 0.0 : r, y});
    }
    profile.push_back({0.12, -0.12});
    profile.push_back({0.12, 0.12});
    for (int i = 0; i <= n; ++i) {  // upper ball, centre y = +0.6
        const double a = -std::numbers::pi / 2 + std::numbers::pi * i / n;
        const double r = 0.5 * std::cos(a), y = 0.6 + 0.5 * std::sin(a);
        if (y < 0.15) continue;
        profile.push_back({i == n ? 0.0 : r, y});
    }
    const TriangleMesh mesh = makeLathe(profile, 32);
    expectGoodGraph(mesh, 2);
    Result<WaterGraph> graph = buildAutomaticGraph(mesh, AutoGraphSettings{2, 0.0, 48, {}});
    ASSERT_TRUE(graph.ok());
    ASSERT_EQ(graph->pipes.size(), 1u);
    const GraphNode& a = graph->nodes[0];
    const GraphNode& b = graph->nodes[1];
    EXPECT_LT(a.position.y() * b.position.y(), 0.0) << "one node in each ball";
    EXPECT_NEAR(std::abs(a.position.y()), 0.6, 0.15);
    EXPECT_NEAR(a.capacity / b.capacity, 1.0, 0.1);
    // The border is a ring about the neck (radius 0.12 to 0.22): the pipe's radius.
    EXPECT_GT(graph->pipes[0].radius, 0.08);
    EXPECT_LT(graph->pipes[0].radius, 0.3);

    // A shell of 1 cm leaves the enclosed volume minus area x thickness.
    AutoGraphSettings shell{2, 0.01, 48, {}};
    Result<WaterGraph> thin = buildAutomaticGraph(mesh, shell);
    ASSERT_TRUE(thin.ok());
    double area = 0;
    for (const Triangle& t : mesh.triangles) area += triangleAreaVector(mesh, t).norm();
    const double exact = exactSolidMassProperties(mesh, 1.0).volume;
    EXPECT_NEAR(thin->totalCapacity(), exact - 0.01 * area, 1e-12 * exact);
}

TEST(AutoGraph, DefaultSegmentCountGrowsWithTheMesh) {
    TriangleMesh small = makeBox({1, 1, 1});
    EXPECT_EQ(defaultSegmentCount(small), 2);
    const TriangleMesh fine = makeUvSphere(1.0, 128, 64);  // 16k triangles
    EXPECT_EQ(defaultSegmentCount(fine), 6);
}

TEST(AutoGraph, RefusesAnOpenMesh) {
    TriangleMesh open = makeBox({1, 1, 1});
    open.triangles.pop_back();
    EXPECT_FALSE(buildAutomaticGraph(open, AutoGraphSettings{2, 0, 24, {}}).ok());
}

// A build without CGAL says that it lacks automatic graphs, in the engine and the CLI.
TEST(AutoGraph, WithoutCgalItSaysSo) {
    if (meshSegmentationAvailable()) GTEST_SKIP() << "this build has CGAL";
    const Result<WaterGraph> graph = buildAutomaticGraph(makeBox({1, 1, 1}), AutoGraphSettings{});
    ASSERT_FALSE(graph.ok());
    EXPECT_EQ(graph.error().kind, ErrorKind::unsupported);
    EXPECT_NE(graph.error().message.find("CGAL"), std::string::npos) << graph.error().message;
    const fs::path out = test::scratchFolder("plimsoll_test_graph_nocgal") / "box.graph.json";
    const test::CommandOutput r = test::runPlimsoll(
        "graph auto '" + test::assetPath("box.obj").string() + "' --out '" + out.string() + "'");
    EXPECT_EQ(r.exitCode, 1);
    EXPECT_NE(r.err.find("this build has none"), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(out));
}

TEST(GraphCli, HelpOnEverySubcommand) {
    for (const char* sub : {"graph", "graph auto", "graph validate"}) {
        const test::CommandOutput r = test::runPlimsoll(std::string(sub) + " --help");
        EXPECT_EQ(r.exitCode, 0) << sub;
        EXPECT_NE(r.out.find("Usage"), std::string::npos) << sub;
    }
    // A missing mesh: a failure naming it, no graph written.
    const test::CommandOutput r =
        test::runPlimsoll("graph auto /no/such/mesh.obj --out /tmp/x.json");
    EXPECT_EQ(r.exitCode, 1);
    EXPECT_NE(r.err.find("/no/such/mesh.obj"), std::string::npos) << r.err;
}

TEST(GraphCli, AutoWritesAValidGraphAndValidateReadsIt) {
    PLIMSOLL_SKIP_WITHOUT_CGAL();
    const fs::path out = test::scratchFolder("plimsoll_test_graph_cli") / "sphere.graph.json";
    const std::string sphere = test::assetPath("sphere.obj").string();
    const test::CommandOutput r =
        test::runPlimsoll("graph auto '" + sphere + "' --segments 3 --out '" + out.string() + "'");
    ASSERT_EQ(r.exitCode, 0) << r.err;
    EXPECT_NE(r.out.find("3 nodes"), std::string::npos) << r.out;
    Result<WaterGraph> graph = loadGraph(out);
    ASSERT_TRUE(graph.ok()) << graph.error().message;
    EXPECT_EQ(graph->nodes.size(), 3u);
    Result<TriangleMesh> mesh = loadMesh(sphere);
    ASSERT_TRUE(mesh.ok());
    EXPECT_NEAR(graph->totalCapacity(), exactSolidMassProperties(*mesh, 1.0).volume, 1e-9);

    const test::CommandOutput v =
        test::runPlimsoll("graph validate '" + out.string() + "' --mesh '" + sphere + "'");
    EXPECT_EQ(v.exitCode, 0) << v.err;
    EXPECT_NE(v.out.find("valid"), std::string::npos);

    // A broken graph: refused, the class named.
    WaterGraph bad = *graph;
    bad.pipes.push_back({bad.nodes[0].id, bad.nodes[0].id, 0.1, 0, true});
    const fs::path badFile = out.parent_path() / "loop.graph.json";
    ASSERT_TRUE(saveGraph(bad, badFile).ok());
    const test::CommandOutput b = test::runPlimsoll("graph validate '" + badFile.string() + "'");
    EXPECT_EQ(b.exitCode, 1);
    EXPECT_NE(b.err.find("[self-loop]"), std::string::npos) << b.err;
}

}  // namespace
}  // namespace test_graph_auto
}  // namespace plimsoll
