// Water-graph editing through the command layer (graph_edit.h): a three-node graph built by
// commands on the damaged boat floods and sinks it in World the way the physics says, and
// undoing every edit gives back the original graph byte for byte; each command's undo / redo
// round trip; the script verbs; the picking and drag math of the 3D view, without a window.
#include "cli_runner.h"
#include "test_support.h"
#include "world_support.h"
#include "editor/document_test_support.h"

#include "document/command.h"
#include "document/graph_edit.h"
#include "document/graph_view.h"
#include "document/script.h"
#include "view/graph_pick.h"

#include "plimsoll/compute/compute.h"
#include "plimsoll/graph_auto/graph_auto.h"
#include "plimsoll/io/graph_json.h"
#include "plimsoll/scene/world.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <stb_image.h>

#include <numbers>

namespace plimsoll::editor {
namespace test_editor_graph {
namespace {

namespace fs = std::filesystem;
using test::executeOrFail;
using test::openOrFail;
using Json = nlohmann::json;

/// The damaged-boat project and the files it names, copied into a scratch folder.
fs::path copyDamagedBoat(const std::string& test) {
    const fs::path root = test::scratchFolder("editor_graph_" + test);
    fs::remove_all(root);
    fs::create_directories(root / "projects");
    const fs::path source = PLIMSOLL_SOURCE_DIR;
    fs::create_directories(root / "assets");
    for (const char* file : {"hull.obj", "hull_stern_damage.png"})
        fs::copy_file(source / "assets" / file, root / "assets" / file);
    for (const char* file : {"damaged_boat.plim.json", "boat.graph.json"})
        fs::copy_file(source / "projects" / file, root / "projects" / file);
    return root / "projects" / "damaged_boat.plim.json";
}

GraphNode node(const std::string& id, const Eigen::Vector3d& position, double capacity) {
    GraphNode n;
    n.id = id;
    n.position = position;
    n.capacity = capacity;
    return n;
}

GraphPipe pipe(const std::string& a, const std::string& b, double radius) {
    GraphPipe p;
    p.a = a;
    p.b = b;
    p.radius = radius;
    return p;
}

// The issue's scripted check: build a three-node graph by commands, run 10 s of the damaged
// boat, check the water and the sinking, undo back to the original graph.
TEST(EditorGraphSchematic, BoxesKeepTheProfilesOrderAndNeverOverlap) {
    // A hull's profile: bow tank forward (+x), engine room aft, two wing tanks side by side
    // (same x and y, z apart), a deck locker above the engine room.
    WaterGraph g;
    auto node = [&](const std::string& id, double x, double y, double z) {
        GraphNode n;
        n.id = id;
        n.position = Eigen::Vector3d(x, y, z);
        n.capacity = 1;
        g.nodes.push_back(n);
    };
    node("bow", 4.0, 0.0, 0.0);
    node("engine", -3.0, 0.0, 0.0);
    node("wing_port", 0.5, 0.2, -1.0);
    node("wing_starboard", 0.5, 0.2, 1.0);
    node("locker", -3.0, 1.5, 0.0);
    const Eigen::Vector2f box(64, 26);
    const SchematicLayout layout = schematicLayout(g, 400, 200, box);
    ASSERT_EQ(layout.centre.size(), 5u);
    const auto& c = layout.centre;
    // Forward is right, up is up (canvas y down); the ends of the profile at the canvas's.
    EXPECT_GT(c[0].x(), c[2].x());
    EXPECT_GT(c[2].x(), c[1].x());
    EXPECT_LT(c[4].y(), c[1].y());
    EXPECT_NEAR(c[0].x(), 400 - 32, 1e-3);
    EXPECT_NEAR(c[1].x(), 32, 1e-3);
    EXPECT_NEAR(c[4].y(), 13, 1e-3);
    // No two boxes overlap: the wing tanks, one place in profile, are pulled apart.
    for (std::size_t i = 0; i < c.size(); ++i) {
        for (std::size_t j = i + 1; j < c.size(); ++j) {
            const Eigen::Vector2f d = (c[i] - c[j]).cwiseAbs();
            EXPECT_TRUE(d.x() >= box.x() || d.y() >= box.y())
                << g.nodes[i].id << " overlaps " << g.nodes[j].id;
        }
    }
    // Clicks find the box under them; empty canvas finds none.
    for (std::size_t i = 0; i < c.size(); ++i) {
        EXPECT_EQ(schematicNodeAt(layout, c[i] + Eigen::Vector2f(30, -12)), int(i))
            << g.nodes[i].id;
    }
    EXPECT_EQ(schematicNodeAt(layout, Eigen::Vector2f(200, 190)), -1);
    // A hull modelled along z (the sample damaged boat's four tanks, stern at -z): the side
    // view runs along z, stern to bow left to right, all on one level.
    WaterGraph boat;
    for (const auto& [id, z] :
         {std::pair{"stern", -2.25}, {"aft", -0.75}, {"fore", 0.75}, {"bow", 2.25}}) {
        GraphNode n;
        n.id = id;
        n.position = Eigen::Vector3d(0.0, 0.0, z);
        n.capacity = 1;
        boat.nodes.push_back(n);
    }
    const SchematicLayout along = schematicLayout(boat, 400, 200, box);
    ASSERT_EQ(along.centre.size(), 4u);
    EXPECT_NEAR(along.centre[0].x(), 32, 1e-3);
    EXPECT_NEAR(along.centre[3].x(), 400 - 32, 1e-3);
    for (std::size_t i = 1; i < 4; ++i) {
        EXPECT_GT(along.centre[i].x(), along.centre[i - 1].x() + box.x()) << boat.nodes[i].id;
        EXPECT_NEAR(along.centre[i].y(), 100, 1e-3);
    }
    // One node: the canvas's centre.
    g.nodes.resize(1);
    const SchematicLayout one = schematicLayout(g, 400, 200, box);
    EXPECT_NEAR(one.centre[0].x(), 200, 1e-3);
    EXPECT_NEAR(one.centre[0].y(), 100, 1e-3);
}

TEST(EditorGraphSchematic, BoxesHoldWholeNamesAndDragsMoveAndConnectNodesAsCommands) {
    const fs::path projectPath = copyDamagedBoat("schematic_edit");
    auto doc = openOrFail(projectPath);
    ASSERT_TRUE(doc);
    ASSERT_NE(doc->graph(0), nullptr) << doc->assets(0).graph.error;
    const WaterGraph before = *doc->graph(0);
    // Whole names: a label of 7 px a character, wrapped at 15 characters a line, fits its box
    // ("stern compartment (engine room)" is 31 characters: three lines).
    auto textSize = [](const std::string& label) {
        const float chars = float(label.size());
        return Eigen::Vector2f(7.0f * std::min(chars, 15.0f), 14.0f * std::ceil(chars / 15.0f));
    };
    const Eigen::Vector2f box = schematicBoxFor(before, textSize, Eigen::Vector2f(64, 26));
    for (const GraphNode& n : before.nodes) {
        EXPECT_GE(box.x(), textSize(schematicLabel(n)).x() + 2 * kSchematicMargin.x()) << n.id;
        EXPECT_GE(box.y(), textSize(schematicLabel(n)).y() + 2 * kSchematicMargin.y()) << n.id;
    }
    EXPECT_EQ(schematicLabel(before.nodes[0]), "stern compartment (engine room)");
    EXPECT_FLOAT_EQ(box.y(), 3 * 14.0f + 2 * kSchematicMargin.y());

    // The scale: boxes far enough apart to keep their mapped places are as many pixels apart
    // as their nodes are metres apart, over metresPerPixel.
    const SchematicLayout layout = schematicLayout(before, 1200, 200, box);
    ASSERT_EQ(layout.along, 2);  // the boat is modelled along z
    const float pixels = layout.centre[3].x() - layout.centre[0].x();
    EXPECT_NEAR(pixels * layout.metresPerPixel.x(),
                before.nodes[3].position.z() - before.nodes[0].position.z(), 1e-4);

    // A drag of the aft hold 40 px right and 20 px up moves it along z and up by that many
    // pixels at the layout's scale, as one undoable command.
    const Eigen::Vector3d offset = schematicDragOffset(layout, Eigen::Vector2f(40, -20));
    EXPECT_NEAR(offset.z(), 40 * layout.metresPerPixel.x(), 1e-6);
    EXPECT_NEAR(offset.y(), 20 * layout.metresPerPixel.y(), 1e-6);
    EXPECT_EQ(offset.x(), 0.0);
    executeOrFail(*doc, makeMoveNodesCommand(*doc, 0, {"aft"}, offset));
    EXPECT_LT((doc->graph(0)->nodes[1].position - before.nodes[1].position - offset).norm(), 1e-12);
    // A drop from the stern's port onto the fore hold: a pipe between them.
    EXPECT_EQ(schematicPortAt(layout, layout.centre[0] + Eigen::Vector2f(0.5f * box.x(), 3), 6), 0);
    EXPECT_EQ(schematicPortAt(layout, layout.centre[0], 6), -1);
    GraphPipe joined;
    joined.a = "stern";
    joined.b = "fore";
    executeOrFail(*doc, makeAddPipeCommand(*doc, 0, joined));
    EXPECT_GE(findPipe(*doc->graph(0), "stern", "fore"), 0);
    // Both undo back to the graph as it was.
    ASSERT_TRUE(doc->undo());
    ASSERT_TRUE(doc->undo());
    EXPECT_EQ(graphToJson(*doc->graph(0)), graphToJson(before));
}

TEST(EditorGraphSchematic, AVerticalDragMovesOnlyTheDraggedBoxInTheKeptFrame) {
    // The boat's four compartments all lie at y = 0: framed to fit, the up axis takes the
    // across scale. The aft hold dragged 30 px up and dropped, in the frame the schematic
    // keeps: the aft box is 30 px higher and every other box stays on its pixel.
    const fs::path projectPath = copyDamagedBoat("schematic_frame");
    auto doc = openOrFail(projectPath);
    ASSERT_TRUE(doc);
    ASSERT_NE(doc->graph(0), nullptr) << doc->assets(0).graph.error;
    const WaterGraph before = *doc->graph(0);
    const Eigen::Vector2f box(80, 40);
    const SchematicFrame frame = schematicFrame(before, 1200, 200, box);
    const SchematicLayout shown = schematicLayout(before, frame, box);
    // The kept frame places the graph it was made for as the fitted layout does.
    const SchematicLayout fitted = schematicLayout(before, 1200, 200, box);
    for (std::size_t i = 0; i < before.nodes.size(); ++i)
        EXPECT_LT((shown.centre[i] - fitted.centre[i]).norm(), 1e-3f) << i;
    const Eigen::Vector2f drag(0, -30);
    executeOrFail(*doc, makeMoveNodesCommand(*doc, 0, {"aft"}, schematicDragOffset(shown, drag)));
    const WaterGraph& after = *doc->graph(0);
    ASSERT_GT(after.nodes[1].position.y(), 0.0);
    const SchematicLayout kept = schematicLayout(after, frame, box);
    for (std::size_t i = 0; i < after.nodes.size(); ++i) {
        const Eigen::Vector2f expected =
            shown.centre[i] + (i == 1 ? drag : Eigen::Vector2f::Zero());
        EXPECT_LT((kept.centre[i] - expected).norm(), 1e-3f) << after.nodes[i].id;
    }
    // Fitted again ("Frame"), the one raised node stretches the height over the canvas: the
    // others move, which is why a drop does not refit.
    const SchematicLayout refitted = schematicLayout(after, 1200, 200, box);
    EXPECT_GT(std::abs(refitted.centre[0].y() - shown.centre[0].y()), 20.0f);
}

TEST(EditorGraph, ThreeNodeGraphBuiltByCommandsFloodsAndSinksTheBoatAndUndoesExactly) {
    const fs::path projectPath = copyDamagedBoat("scripted");
    auto doc = openOrFail(projectPath);
    ASSERT_TRUE(doc);
    ASSERT_NE(doc->graph(0), nullptr) << doc->assets(0).graph.error;
    const std::string original = graphToJson(*doc->graph(0));
    const std::string originalFile = test::readFile(projectPath.parent_path() / "boat.graph.json");

    // Clear the four compartments, then three nodes along the keel: stern (where the hull is
    // holed), midships, bow; two pipes; capacities set after adding.
    std::vector<std::string> old;
    for (const GraphNode& n : doc->graph(0)->nodes) old.push_back(n.id);
    std::size_t edits = 0;
    executeOrFail(*doc, makeDeleteNodesCommand(*doc, 0, old)), ++edits;
    executeOrFail(*doc, makeAddNodeCommand(*doc, 0, node("stern", {0, 0, -2.0}, 1.0))), ++edits;
    executeOrFail(*doc, makeAddNodeCommand(*doc, 0, node("mid", {0, 0, 0.0}, 1.0))), ++edits;
    executeOrFail(*doc, makeAddNodeCommand(*doc, 0, node("bow", {0, 0, 2.0}, 1.0))), ++edits;
    executeOrFail(*doc, makeAddPipeCommand(*doc, 0, pipe("stern", "mid", 0.03))), ++edits;
    executeOrFail(*doc, makeAddPipeCommand(*doc, 0, pipe("mid", "bow", 0.03))), ++edits;
    const double capacity[3] = {3.0, 3.0, 2.0};
    const char* ids[3] = {"stern", "mid", "bow"};
    for (int i = 0; i < 3; ++i) {
        NodeEdit e;
        e.capacity = capacity[i];
        executeOrFail(*doc, makeSetNodeCommand(*doc, 0, ids[i], e)), ++edits;
    }
    // The project floods over two minutes; a hole twenty times the size sinks it within the
    // 10 s of the check (a project edit, undone with the rest).
    executeOrFail(*doc, makeSetPropertyCommand(*doc, "/bodies/0/water_graph/inflow_rate", 6.0)),
        ++edits;
    ASSERT_EQ(doc->graph(0)->nodes.size(), 3u);
    ASSERT_EQ(doc->graph(0)->pipes.size(), 2u);
    const GraphReport report = validateGraph(*doc->graph(0), doc->assets(0).mesh.get());
    EXPECT_FALSE(report.hasErrors()) << report.format();
    EXPECT_FALSE(report.has(GraphProblemKind::NodeOutsideMesh)) << report.format();

    // The document's unsaved state goes to World in memory, as the live preview runs it; the
    // project's own files stay as they were.
    Result<Scene> scene = doc->simulationScene();
    ASSERT_TRUE(scene.ok()) << scene.error().message;
    ASSERT_TRUE(scene->bodies[0].desc.waterGraph);
    ASSERT_TRUE(scene->bodies[0].parts.waterGraph);
    EXPECT_EQ(*scene->bodies[0].parts.waterGraph, *doc->graph(0));
    EXPECT_DOUBLE_EQ(scene->bodies[0].desc.waterGraph->settings.inflowRate, 6.0);
    EXPECT_EQ(test::readFile(projectPath.parent_path() / "boat.graph.json"), originalFile);

    // On the fast CPU path, as the preview runs it by default (10 s of flooding).
    std::unique_ptr<World> made = test::fastWorldOrFail(std::move(*scene));
    ASSERT_TRUE(made);
    World& world = *made;
    const double startHeight = world.bodies()[0].state.position.y();
    const double volume = world.bodies()[0].volume;
    const WaterGraphSimulation* sim = world.waterGraph(0);
    ASSERT_NE(sim, nullptr);
    // Every permeable texel lies at the stern: it feeds the stern node (nearestNode).
    ASSERT_FALSE(sim->samples().empty());
    std::size_t sternSamples = 0;
    for (const ExchangeSample& s : sim->samples()) sternSamples += s.node == 0;
    EXPECT_EQ(sternSamples, sim->samples().size());

    const int frames = static_cast<int>(std::lround(10.0 / doc->project().simulation.timeStep));
    // When each node first holds 99% of its capacity, and when the hull first went under.
    std::vector<double> filledAt(3, -1.0);
    double underAt = -1;
    for (int f = 0; f < frames; ++f) {
        ASSERT_TRUE(world.advanceFrame().ok());
        for (std::size_t i = 0; i < 3; ++i) {
            const GraphNode& n = sim->graph().nodes[i];
            if (filledAt[i] < 0 && n.water >= 0.99 * n.capacity) filledAt[i] = world.time();
        }
        if (underAt < 0 && world.bodies()[0].buoyancy.submergedVolume > 0.999 * volume) {
            underAt = world.time();
        }
    }
    EXPECT_NEAR(world.time(), 10.0, 1e-9);
    const WaterGraph& g = sim->graph();
    double stored = 0;
    for (std::size_t i = 0; i < g.nodes.size(); ++i) {
        EXPECT_GE(g.nodes[i].water, 0.0) << g.nodes[i].id;
        EXPECT_LE(g.nodes[i].water, g.nodes[i].capacity * (1 + 1e-12)) << g.nodes[i].id;
        stored += g.nodes[i].water;
    }
    const GraphTotals& totals = sim->totals();
    EXPECT_GT(totals.entered, 0.5);  // m^3: the hole lets real water in
    EXPECT_NEAR(stored, totals.initial + totals.entered - totals.left, 1e-9 * totals.entered);
    EXPECT_LT(sim->conservationError(), 1e-12);
    // Water enters at the stern and runs forward only downhill, from a full node: the stern
    // fills first, then midships, then the bow.
    std::printf("[ figures ] full at: stern %.2f s, mid %.2f s, bow %.2f s; hull under at %.2f s\n",
                filledAt[0], filledAt[1], filledAt[2], underAt);
    ASSERT_GT(filledAt[0], 0.0);
    EXPECT_GT(filledAt[1], filledAt[0]);
    EXPECT_GT(filledAt[2], filledAt[1]);
    // The boat sank: well below where it started, and (nearly) all of it under water.
    const SimulatedBody& boat = world.bodies()[0];
    std::printf(
        "[ figures ] after 10 s: water stern %.4f mid %.4f bow %.4f m^3 (entered %.4f, "
        "left %.4f), height %.4f -> %.4f m, submerged %.4f of %.4f m^3\n",
        g.nodes[0].water, g.nodes[1].water, g.nodes[2].water, totals.entered, totals.left,
        startHeight, boat.state.position.y(), boat.buoyancy.submergedVolume, volume);
    EXPECT_LT(boat.state.position.y(), startHeight - 0.5);
    EXPECT_GT(boat.buoyancy.submergedVolume, 0.99 * volume);
    EXPECT_GT(underAt, 0.0);

    // Undo every graph edit: the original graph, byte for byte, and on disk once saved.
    for (std::size_t i = 0; i < edits; ++i) ASSERT_TRUE(doc->undo());
    ASSERT_NE(doc->graph(0), nullptr);
    EXPECT_EQ(graphToJson(*doc->graph(0)), original);
    ASSERT_TRUE(doc->save().ok());
    EXPECT_EQ(test::readFile(projectPath.parent_path() / "boat.graph.json"), original);
}

/// Runs a command, checks that undo gives the graph before and redo the graph after, byte for
/// byte, and leaves it done.
void roundTrip(Document& d, Result<std::unique_ptr<Command>> command) {
    ASSERT_TRUE(command.ok()) << command.error().message;
    const std::string before = d.graph(0) ? graphToJson(*d.graph(0)) : "none";
    ASSERT_TRUE(d.execute(std::move(command).value()).ok());
    ASSERT_NE(d.graph(0), nullptr);
    const std::string after = graphToJson(*d.graph(0));
    EXPECT_NE(after, before) << d.undoName();
    ASSERT_TRUE(d.undo());
    EXPECT_EQ(d.graph(0) ? graphToJson(*d.graph(0)) : "none", before) << d.redoName();
    ASSERT_TRUE(d.redo());
    EXPECT_EQ(graphToJson(*d.graph(0)), after) << d.undoName();
}

TEST(EditorGraph, EveryCommandUndoesAndRedoesExactly) {
    const fs::path projectPath = copyDamagedBoat("roundtrip");
    auto doc = openOrFail(projectPath);
    ASSERT_TRUE(doc);
    roundTrip(*doc, makeAddNodeCommand(*doc, 0, node("", {0.1, -0.2, 0.3}, 0.5)));
    const std::string added = doc->graph(0)->nodes.back().id;
    EXPECT_EQ(added, "n5");
    EXPECT_DOUBLE_EQ(doc->graph(0)->nodes.back().capacity, 0.5);
    roundTrip(*doc, makeDuplicateNodesCommand(*doc, 0, {"stern", "aft"}, {0, 0.25, 0}));
    {
        const WaterGraph& g = *doc->graph(0);
        ASSERT_EQ(g.nodes.size(), 7u);
        EXPECT_EQ(g.nodes[5].position, g.nodes[0].position + Eigen::Vector3d(0, 0.25, 0));
        EXPECT_EQ(g.nodes[5].boxSize, g.nodes[0].boxSize);
        // The pipe between the duplicated pair came along, joining the copies.
        ASSERT_EQ(g.pipes.size(), 4u);
        EXPECT_EQ(g.pipes[3].a, g.nodes[5].id);
        EXPECT_EQ(g.pipes[3].b, g.nodes[6].id);
    }
    roundTrip(*doc, makeMoveNodesCommand(*doc, 0, {"fore", "bow"}, {0, -0.1, 0.05}));
    EXPECT_EQ(doc->graph(0)->nodes[3].position, Eigen::Vector3d(0, -0.1, 2.3));
    NodeEdit e;
    e.name = "renamed";
    e.water = 0.25;
    e.sealed = true;
    e.boxSize = Eigen::Vector3d::Zero();
    e.position = Eigen::Vector3d(0.1, 0.2, 0.3);
    roundTrip(*doc, makeSetNodeCommand(*doc, 0, "aft", e));
    EXPECT_EQ(doc->graph(0)->nodes[1].name, "renamed");
    EXPECT_TRUE(doc->graph(0)->nodes[1].sealed);
    EXPECT_FALSE(doc->graph(0)->nodes[1].isBox());
    // Several nodes at once: one step sets the shared fields on each, leaving the rest.
    {
        NodeEdit shared;
        shared.capacity = 0.75;
        shared.sealed = false;
        const GraphNode sternBefore = doc->graph(0)->nodes[doc->graph(0)->indexOf("stern")];
        roundTrip(*doc, makeSetNodesCommand(*doc, 0, {"stern", "aft", added}, shared));
        EXPECT_EQ(doc->undoName(), "Edit 3 nodes");
        for (const std::string id : {"stern", "aft", added.c_str()}) {
            const GraphNode& n = doc->graph(0)->nodes[doc->graph(0)->indexOf(id)];
            EXPECT_DOUBLE_EQ(n.capacity, 0.75) << id;
            EXPECT_FALSE(n.sealed) << id;
        }
        const GraphNode& stern = doc->graph(0)->nodes[doc->graph(0)->indexOf("stern")];
        EXPECT_EQ(stern.position, sternBefore.position);
        EXPECT_EQ(stern.boxSize, sternBefore.boxSize);
        EXPECT_EQ(stern.name, sternBefore.name);
        // A name or a position is one node's; one bad node refuses the whole edit.
        NodeEdit named;
        named.name = "same";
        EXPECT_FALSE(makeSetNodesCommand(*doc, 0, {"stern", "aft"}, named).ok());
        NodeEdit overfull;
        overfull.water = 0.8;
        const auto refused = makeSetNodesCommand(*doc, 0, {"stern", "aft"}, overfull);
        ASSERT_FALSE(refused.ok());
        EXPECT_NE(refused.error().message.find("water must be within"), std::string::npos)
            << refused.error().message;
        EXPECT_FALSE(makeSetNodesCommand(*doc, 0, {"stern", "ghost"}, shared).ok());
    }
    roundTrip(*doc, makeAddPipeCommand(*doc, 0, pipe("stern", added, 0.04)));
    PipeEdit close;
    close.open = false;
    roundTrip(*doc, makeSetPipeCommand(*doc, 0, added, "stern", close));  // either order
    EXPECT_FALSE(doc->graph(0)->pipes.back().open);
    EXPECT_EQ(doc->undoName(), "Close pipe " + added + "-stern");
    PipeEdit size;
    size.radius = 0.05;
    size.length = 2.5;
    roundTrip(*doc, makeSetPipeCommand(*doc, 0, "stern", added, size));
    EXPECT_DOUBLE_EQ(doc->graph(0)->pipeLength(doc->graph(0)->pipes.back()), 2.5);
    roundTrip(*doc, makeRemovePipeCommand(*doc, 0, "stern", added));
    const std::size_t pipesBefore = doc->graph(0)->pipes.size();
    roundTrip(*doc, makeDeleteNodesCommand(*doc, 0, {"fore"}));
    // fore had two pipes (aft-fore, fore-bow): both went with it.
    EXPECT_EQ(doc->graph(0)->pipes.size(), pipesBefore - 2);
    EXPECT_LT(doc->graph(0)->indexOf("fore"), 0);
    WaterGraph replacement;
    replacement.nodes.push_back(node("only", {0, 0, 0}, 1.0));
    roundTrip(*doc, makeReplaceGraphCommand(*doc, 0, replacement));
    EXPECT_EQ(*doc->graph(0), replacement);

    // Bad requests are refused with a reason, and change nothing.
    const std::string now = graphToJson(*doc->graph(0));
    EXPECT_FALSE(makeAddNodeCommand(*doc, 0, node("only", {0, 0, 0}, 1.0)).ok());  // taken id
    EXPECT_FALSE(makeAddNodeCommand(*doc, 0, node("x", {0, 0, 0}, 0.0)).ok());     // capacity
    EXPECT_FALSE(makeAddPipeCommand(*doc, 0, pipe("only", "only", 0.01)).ok());    // self loop
    EXPECT_FALSE(makeAddPipeCommand(*doc, 0, pipe("only", "ghost", 0.01)).ok());   // dangling
    EXPECT_FALSE(makeMoveNodesCommand(*doc, 0, {"ghost"}, {1, 0, 0}).ok());
    NodeEdit tooMuch;
    tooMuch.water = 2.0;
    const auto refused = makeSetNodeCommand(*doc, 0, "only", tooMuch);
    ASSERT_FALSE(refused.ok());
    EXPECT_NE(refused.error().message.find("water"), std::string::npos) << refused.error().message;
    EXPECT_FALSE(makeCreateGraphCommand(*doc, 0).ok());  // already has one
    EXPECT_EQ(graphToJson(*doc->graph(0)), now);
}

TEST(EditorGraph, NewGraphOnABodyWithoutOneIsSavedAtomicallyAndUndoesAway) {
    const fs::path projectPath = copyDamagedBoat("create");
    // A body without a graph: the buoy-like sealed boat (drop the graph entry).
    std::string text = test::readFile(projectPath);
    const std::size_t at = text.find(",\n     \"water_graph\"");
    ASSERT_NE(at, std::string::npos);
    text = text.substr(0, at) + "}\n  ]\n}\n";
    std::ofstream(projectPath) << text;
    auto doc = openOrFail(projectPath);
    ASSERT_TRUE(doc);
    ASSERT_FALSE(doc->project().bodies[0].waterGraph);
    EXPECT_FALSE(makeAddNodeCommand(*doc, 0, node("a", {0, 0, 0}, 1)).ok());  // no graph yet
    executeOrFail(*doc, makeCreateGraphCommand(*doc, 0));
    ASSERT_TRUE(doc->project().bodies[0].waterGraph);
    EXPECT_EQ(doc->project().bodies[0].waterGraph->graph, "damaged_boat_boat.graph.json");
    executeOrFail(*doc, makeAddNodeCommand(*doc, 0, node("a", {0, 0, 0}, 1)));
    ASSERT_TRUE(doc->save().ok());
    const fs::path file = projectPath.parent_path() / "damaged_boat_boat.graph.json";
    Result<WaterGraph> loaded = loadGraph(file);
    ASSERT_TRUE(loaded.ok()) << loaded.error().message;
    EXPECT_EQ(loaded->nodes.size(), 1u);
    Result<Project> reread = loadProject(projectPath);
    ASSERT_TRUE(reread.ok()) << reread.error().message;
    ASSERT_TRUE(reread->bodies[0].waterGraph);
    // Undo both: no graph entry in the project, none in the document.
    ASSERT_TRUE(doc->undo());
    ASSERT_TRUE(doc->undo());
    EXPECT_FALSE(doc->project().bodies[0].waterGraph);
    EXPECT_EQ(doc->graph(0), nullptr);
    ASSERT_TRUE(doc->redo());
    ASSERT_TRUE(doc->redo());
    ASSERT_NE(doc->graph(0), nullptr);
    EXPECT_EQ(doc->graph(0)->nodes.size(), 1u);
}

TEST(EditorGraph, EditedGraphSurvivesAutosaveRecoveryAndTravelsWithSaveAs) {
    const fs::path projectPath = copyDamagedBoat("autosave");
    auto doc = openOrFail(projectPath);
    ASSERT_TRUE(doc);
    const std::string original = test::readFile(projectPath.parent_path() / "boat.graph.json");
    executeOrFail(*doc, makeAddNodeCommand(*doc, 0, node("extra", {0, -0.3, 0}, 0.2)));
    const std::string edited = graphToJson(*doc->graph(0));
    ASSERT_TRUE(doc->autosave().ok());
    // Not saved: the file on disk is untouched until the project is.
    EXPECT_EQ(test::readFile(projectPath.parent_path() / "boat.graph.json"), original);
    Result<std::unique_ptr<Document>> recovered = Document::recover(doc->autosavePath());
    ASSERT_TRUE(recovered.ok()) << recovered.error().message;
    ASSERT_NE((*recovered)->graph(0), nullptr);
    EXPECT_EQ(graphToJson(*(*recovered)->graph(0)), edited);
    EXPECT_TRUE((*recovered)->dirty());
    // Save As into another folder: the graph is written there, the original stays.
    const fs::path elsewhere = projectPath.parent_path().parent_path() / "copy" / "boat.plim.json";
    fs::create_directories(elsewhere.parent_path());
    ASSERT_TRUE(doc->saveAs(elsewhere).ok());
    EXPECT_EQ(test::readFile(elsewhere.parent_path() / "boat.graph.json"), edited);
    EXPECT_EQ(test::readFile(projectPath.parent_path() / "boat.graph.json"), original);
    Result<Project> reread = loadProject(elsewhere);
    ASSERT_TRUE(reread.ok()) << reread.error().message;
    EXPECT_EQ(reread->bodies[0].waterGraph->graph, "boat.graph.json");
}

TEST(EditorGraph, ScriptVerbsEditTheGraph) {
    const fs::path projectPath = copyDamagedBoat("script");
    auto doc = openOrFail(projectPath);
    ASSERT_TRUE(doc);
    const std::string original = graphToJson(*doc->graph(0));
    const Json script = Json::parse(R"([
      {"op": "graph_add_node", "name": "keel", "position": [0, -0.2, 0], "capacity": 0.4, "water": 0.1},
      {"op": "graph_connect", "a": "aft", "b": "n5", "radius": 0.015},
      {"op": "graph_close", "a": "aft", "b": "n5"},
      {"op": "graph_set_pipe", "a": "n5", "b": "aft", "length": 0.9},
      {"op": "graph_set_node", "node": "n5", "capacity": 0.5, "sealed": true, "box": [0.5, 0.2, 0.5]},
      {"op": "graph_move", "nodes": ["n5", "bow"], "offset": [0, 0.1, 0]},
      {"op": "graph_duplicate", "nodes": ["n5"], "offset": [0.3, 0, 0]},
      {"op": "graph_delete", "nodes": ["stern"]},
      {"op": "graph_disconnect", "a": "fore", "b": "bow"},
      {"op": "graph_open", "a": "aft", "b": "n5"}
    ])");
    Result<Json> results = runEditScript(*doc, script);
    ASSERT_TRUE(results.ok()) << results.error().message;
    EXPECT_EQ((*results)[0]["id"], "n5");
    const WaterGraph& g = *doc->graph(0);
    const int keel = g.indexOf("n5");
    ASSERT_GE(keel, 0);
    EXPECT_EQ(g.nodes[keel].name, "keel");
    EXPECT_DOUBLE_EQ(g.nodes[keel].capacity, 0.5);
    EXPECT_DOUBLE_EQ(g.nodes[keel].water, 0.1);
    EXPECT_TRUE(g.nodes[keel].sealed);
    EXPECT_TRUE(g.nodes[keel].isBox());
    EXPECT_NEAR(g.nodes[keel].position.y(), -0.1, 1e-15);
    EXPECT_EQ(g.nodes.size(), 5u);  // 4 + keel + copy - stern
    const int p = findPipe(g, "aft", "n5");
    ASSERT_GE(p, 0);
    EXPECT_TRUE(g.pipes[p].open);
    EXPECT_DOUBLE_EQ(g.pipes[p].length, 0.9);
    EXPECT_DOUBLE_EQ(g.pipes[p].radius, 0.015);
    EXPECT_LT(findPipe(g, "fore", "bow"), 0);
    EXPECT_LT(findPipe(g, "stern", "aft"), 0);

    // Every step undoes: ten undos give back the file's graph.
    for (int i = 0; i < 10; ++i) ASSERT_TRUE(doc->undo());
    EXPECT_EQ(graphToJson(*doc->graph(0)), original);

    // A failing verb names its index and what is wrong.
    Result<Json> bad =
        runEditScript(*doc, Json::parse(R"([{"op": "graph_connect", "a": "aft", "b": "aft"}])"));
    ASSERT_FALSE(bad.ok());
    EXPECT_NE(bad.error().message.find("command 0"), std::string::npos) << bad.error().message;
    // graph_replace takes a graph in graph.json's format.
    Result<Json> replaced = runEditScript(*doc, Json::parse(R"([{"op": "graph_replace", "graph":
        {"schema_version": 1, "nodes": [{"id": "a", "position": [0, 0, 0], "capacity": 1}], "pipes": []}}])"));
    ASSERT_TRUE(replaced.ok()) << replaced.error().message;
    EXPECT_EQ(doc->graph(0)->nodes.size(), 1u);
}

TEST(EditorGraph, AutoGenerateVerbReplacesTheGraphInOneUndoStep) {
    PLIMSOLL_SKIP_WITHOUT_CGAL();
    const fs::path projectPath = copyDamagedBoat("auto");
    auto doc = openOrFail(projectPath);
    ASSERT_TRUE(doc);
    const std::string original = graphToJson(*doc->graph(0));
    Result<Json> done =
        runEditScript(*doc, Json::parse(R"([{"op": "graph_auto", "segments": 3}])"));
    ASSERT_TRUE(done.ok()) << done.error().message;
    const WaterGraph& g = *doc->graph(0);
    EXPECT_EQ(g.nodes.size(), 3u);
    // The same graph `plimsoll graph --auto` builds (buildAutomaticGraph on the body's mesh):
    // its capacities share out the hull's enclosed volume.
    const MassProperties exact = exactSolidMassProperties(*doc->assets(0).mesh, 1.0);
    EXPECT_NEAR(g.totalCapacity(), exact.volume, 1e-6 * exact.volume);
    EXPECT_FALSE(validateGraph(g, doc->assets(0).mesh.get()).hasErrors());
    ASSERT_TRUE(doc->undo());
    EXPECT_EQ(graphToJson(*doc->graph(0)), original);
}

// --- the 3D view's math, headless -----------------------------------------------------------

TEST(EditorGraphPick, SphereRadiusAndCapHeightMatchTheVolumes) {
    const double r = sphereRadiusOfVolume(4.0 / 3.0 * std::numbers::pi * 8.0);
    EXPECT_NEAR(r, 2.0, 1e-12);
    EXPECT_DOUBLE_EQ(sphereCapHeight(2.0, 0.0), 0.0);
    EXPECT_NEAR(sphereCapHeight(2.0, 2.0 / 3.0 * std::numbers::pi * 8.0), 2.0, 1e-9);  // half
    const double h = sphereCapHeight(1.0, 0.5);
    EXPECT_NEAR(std::numbers::pi * h * h * (3 - h) / 3, 0.5, 1e-9);
}

TEST(EditorGraphPick, CameraRayPicksTheNodeUnderThePixel) {
    WaterGraph g;
    g.nodes.push_back(node("a", {0, 0, 0}, 4.0 / 3.0 * std::numbers::pi * 0.125));  // r = 0.5
    g.nodes.push_back(node("b", {2, 0, 0}, 4.0 / 3.0 * std::numbers::pi * 0.001));  // r = 0.1
    GraphNode box = node("c", {-3, 0, 0}, 1.0);
    box.boxSize = {1, 1, 1};
    g.nodes.push_back(box);
    g.pipes.push_back(pipe("a", "b", 0.02));
    // The body moved 1 m up and turned 90 degrees about z: object x points along world y.
    const Pose pose = Pose::fromEulerDegrees({0, 1, 0}, {0, 0, 90});
    ASSERT_TRUE(pose.apply(g.nodes[1].position).isApprox(Eigen::Vector3d(0, 3, 0)));
    Camera camera;
    camera.target = {0, 1, 0};
    camera.distance = 10;
    const int w = 640, h = 480;
    Eigen::Vector3d o, d;
    for (std::size_t i = 0; i < g.nodes.size(); ++i) {
        const auto px = camera.toPixel(pose.apply(g.nodes[i].position), w, h);
        ASSERT_TRUE(px);
        camera.rayThrough(px->x(), px->y(), w, h, o, d);
        const auto hit = pickNode(g, pose, o, d);
        ASSERT_TRUE(hit) << i;
        EXPECT_EQ(hit->index, i);
    }
    // Node a seen from the front: the ray enters its sphere 0.5 m before its centre.
    const auto centre = camera.toPixel(pose.apply(g.nodes[0].position), w, h);
    camera.rayThrough(centre->x(), centre->y(), w, h, o, d);
    EXPECT_NEAR(pickNode(g, pose, o, d)->distance,
                (pose.apply(g.nodes[0].position) - o).norm() - 0.5, 1e-9);
    // Just outside node b's projected radius: nothing; just inside: b.
    const Eigen::Vector3d bWorld = pose.apply(g.nodes[1].position);
    for (double k : {0.9, 1.2}) {
        const auto edge = camera.toPixel(bWorld + camera.up() * 0.1 * k, w, h);
        camera.rayThrough(edge->x(), edge->y(), w, h, o, d);
        const auto hit = pickNode(g, pose, o, d);
        if (k < 1) {
            ASSERT_TRUE(hit);
            EXPECT_EQ(hit->index, 1u);
        } else {
            EXPECT_FALSE(hit && hit->index == 1u);
        }
    }
    // The pipe's midpoint picks the pipe; a point 0.3 m beside it does not.
    const Eigen::Vector3d mid = pose.apply(Eigen::Vector3d(1, 0, 0));
    auto px = camera.toPixel(mid, w, h);
    camera.rayThrough(px->x(), px->y(), w, h, o, d);
    ASSERT_TRUE(pickPipe(g, pose, o, d, 0.01));
    px = camera.toPixel(mid + Eigen::Vector3d(0.3, 0, 0), w, h);
    camera.rayThrough(px->x(), px->y(), w, h, o, d);
    EXPECT_FALSE(pickPipe(g, pose, o, d, 0.01));
}

TEST(EditorGraphPick, BoxSelectTakesTheNodesProjectedInsideTheRectangle) {
    WaterGraph g;
    for (int i = 0; i < 5; ++i)
        g.nodes.push_back(node("n" + std::to_string(i), {i - 2.0, 0, 0}, 0.01));
    Camera camera;  // looking down -z from +z: world x is screen right
    camera.distance = 10;
    const int w = 800, h = 600;
    const auto left = camera.toPixel({-1.5, 0, 0}, w, h), right = camera.toPixel({0.5, 0, 0}, w, h);
    // Dragged right to left, bottom to top: the same rectangle.
    const auto inside = nodesInRect(g, Pose{}, camera, w, h, right->x(), 400, left->x(), 200);
    EXPECT_EQ(inside, (std::vector<std::size_t>{1, 2}));
    EXPECT_TRUE(nodesInRect(g, Pose{}, camera, w, h, 0, 0, 10, 10).empty());
    EXPECT_EQ(nodesInRect(g, Pose{}, camera, w, h, 0, 0, w, h).size(), 5u);
}

TEST(EditorGraphPick, AxisAndPlaneDragFollowTheMouseRay) {
    // A ray through (3, 5, 7) along -z: the nearest point on the x axis through the origin is
    // (3, 0, 0); on the y axis (0, 5, 0); along z the ray is parallel: the anchor stays.
    const Eigen::Vector3d o(3, 5, 7), d(0, 0, -1);
    EXPECT_TRUE(closestOnAxis({0, 0, 0}, {1, 0, 0}, o, d).isApprox(Eigen::Vector3d(3, 0, 0)));
    EXPECT_TRUE(closestOnAxis({0, 0, 0}, {0, 1, 0}, o, d).isApprox(Eigen::Vector3d(0, 5, 0)));
    EXPECT_EQ(closestOnAxis({1, 2, 3}, {0, 0, 1}, o, d), Eigen::Vector3d(1, 2, 3));
    // A slanted ray: at the axis point the gap to the ray is perpendicular to the axis too,
    // and no other axis point comes closer to the ray.
    const Eigen::Vector3d slanted = Eigen::Vector3d(1, -1, -2).normalized();
    const Eigen::Vector3d p = closestOnAxis({0, 0, 0}, {1, 0, 0}, o, slanted);
    auto gapToRay = [&](const Eigen::Vector3d& q) {
        return (q - (o + (q - o).dot(slanted) * slanted)).norm();
    };
    const Eigen::Vector3d onRay = o + (p - o).dot(slanted) * slanted;
    EXPECT_NEAR((p - onRay).x(), 0.0, 1e-12);
    for (double ds : {-0.01, 0.01}) EXPECT_LT(gapToRay(p), gapToRay(p + Eigen::Vector3d(ds, 0, 0)));
    // The plane y = 1 under a ray going down.
    const auto hit =
        rayPlane({0, 3, 0}, Eigen::Vector3d(1, -1, 0).normalized(), {0, 1, 0}, {0, 1, 0});
    ASSERT_TRUE(hit);
    EXPECT_TRUE(hit->isApprox(Eigen::Vector3d(2, 1, 0)));
    EXPECT_FALSE(rayPlane({0, 3, 0}, {1, 0, 0}, {0, 1, 0}, {0, 1, 0}));  // parallel
    EXPECT_FALSE(rayPlane({0, 3, 0}, {0, 1, 0}, {0, 1, 0}, {0, 1, 0}));  // behind
}

// --- drawing --------------------------------------------------------------------------------

TEST(EditorGraphView, FeedOverlayColoursEachTexelByItsNearestNode) {
    const fs::path projectPath = copyDamagedBoat("feeds");
    auto doc = openOrFail(projectPath);
    ASSERT_TRUE(doc);
    auto textures = doc->physicsTextures(0);
    ASSERT_TRUE(textures.ok()) << textures.error().message;
    const SurfaceTextures& t = **textures;
    const OverlayImage image = feedOverlay(*doc->graph(0), t);
    ASSERT_EQ(image.width, t.size);
    std::size_t checked = 0;
    for (std::size_t i = 0; i < t.coveredCount(); i += 37) {
        if (i + 1 < t.coveredCount() && t.texelIndex[i + 1] == t.texelIndex[i]) continue;  // shared
        if (i > 0 && t.texelIndex[i - 1] == t.texelIndex[i]) continue;
        const int n = nearestNode(*doc->graph(0), t.position[i]);
        const Eigen::Vector3f c = nodeColour(static_cast<std::size_t>(n)) * 255.0f;
        const std::uint8_t* px = &image.rgba[std::size_t(t.texelIndex[i]) * 4];
        for (int k = 0; k < 3; ++k) EXPECT_NEAR(px[k], c[k], 1.0) << "texel entry " << i;
        EXPECT_EQ(px[3], 255);
        ++checked;
    }
    EXPECT_GT(checked, 100u);
}

TEST(EditorGraphView, SegmentPreviewTakesTheNearestTrianglesSegment) {
    // Two triangles far apart in segments 0 and 1; texel points near each.
    TriangleMesh mesh;
    mesh.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {10, 0, 0}, {11, 0, 0}, {10, 1, 0}};
    mesh.triangles = {{0, 1, 2}, {3, 4, 5}};
    MeshSegmentation seg;
    seg.triangleSegment = {0, 1};
    seg.segmentCount = 2;
    SurfaceTextures t;
    t.size = 2;
    t.texelIndex = {0, 1, 2};
    t.position = {{0.3, 0.3, 0.1}, {10.2, 0.4, -0.1}, {6, 0, 0}};
    const std::vector<int> s = texelSegments(mesh, seg, t);
    EXPECT_EQ(s, (std::vector<int>{0, 1, 1}));
}

// The issue's drawing: `plimsoll render --graph` draws the nodes in their colours where they
// project, through the see-through hull, filled to their water level.
TEST(EditorGraphView, RenderedGraphShowsNodeColoursWhereNodesProject) {
    const fs::path projectPath = copyDamagedBoat("render");
    const fs::path dir = projectPath.parent_path();
    // Half fill the stern compartment (through the CLI's edit script, which saves).
    std::ofstream(dir / "fill.json")
        << R"([{"op": "graph_set_node", "node": "stern", "water": 1.36}])";
    const test::CommandOutput edit = test::runPlimsoll(
        "edit '" + projectPath.string() + "' --script '" + (dir / "fill.json").string() + "'");
    ASSERT_EQ(edit.exitCode, 0) << edit.err;
    const int w = 480, h = 240;
    const fs::path shot = dir / "graph.png", plain = dir / "plain.png";
    const std::string common = " --view side --size 480x240 --no-water --no-grid";
    const test::CommandOutput r = test::runPlimsoll(
        "render '" + projectPath.string() + "' --out '" + shot.string() + "' --graph" + common);
    if (test::cannotRender(r)) GTEST_SKIP() << "no EGL OpenGL 4.5 here: " << r.err;
    ASSERT_EQ(r.exitCode, 0) << r.err;
    ASSERT_EQ(test::runPlimsoll("render '" + projectPath.string() + "' --out '" + plain.string() +
                                "'" + common)
                  .exitCode,
              0);
    auto load = [&](const fs::path& p) {
        int iw = 0, ih = 0, ch = 0;
        unsigned char* data = stbi_load(p.c_str(), &iw, &ih, &ch, 3);
        EXPECT_TRUE(data && iw == w && ih == h);
        std::vector<unsigned char> rgb(data, data + (data ? 3 * iw * ih : 0));
        stbi_image_free(data);
        return rgb;
    };
    const std::vector<unsigned char> a = load(shot), b = load(plain);
    ASSERT_EQ(a.size(), std::size_t(3 * w * h));
    auto doc = openOrFail(projectPath);
    ASSERT_TRUE(doc);
    const Camera camera = Camera::preset(ViewPreset::Side, doc->worldBounds());
    const Pose pose = doc->bodyPose(0);
    auto colourAt = [&](const std::vector<unsigned char>& img, const Eigen::Vector3d& object) {
        const auto p = camera.toPixel(pose.apply(object), w, h);
        EXPECT_TRUE(p);
        const std::size_t i = 3 * (std::size_t(p->y()) * w + std::size_t(p->x()));
        return Eigen::Vector3i(img[i], img[i + 1], img[i + 2]);
    };
    const WaterGraph& g = *doc->graph(0);
    ASSERT_DOUBLE_EQ(g.nodes[0].water, 1.36);
    for (std::size_t n = 0; n < g.nodes.size(); ++n) {
        // 0.25 m above the centre: dry, the node's colour (its strongest channel strongest).
        const Eigen::Vector3d above = g.nodes[n].position + Eigen::Vector3d(0, 0.25, 0);
        const Eigen::Vector3i c = colourAt(a, above), bare = colourAt(b, above);
        Eigen::Index expected = 0, got = 0;
        nodeColour(n).maxCoeff(&expected);
        c.maxCoeff(&got);
        EXPECT_EQ(got, expected) << "node " << n << " colour " << c.transpose();
        EXPECT_GT((c - bare).cwiseAbs().maxCoeff(), 40) << "node " << n;
    }
    // The half-filled stern: 0.25 m below its centre the water's colour (blue over red), above
    // it the node's orange (red over blue).
    const Eigen::Vector3i wet = colourAt(a, g.nodes[0].position - Eigen::Vector3d(0, 0.25, 0));
    const Eigen::Vector3i dry = colourAt(a, g.nodes[0].position + Eigen::Vector3d(0, 0.25, 0));
    EXPECT_GT(wet.z(), wet.x()) << wet.transpose();
    EXPECT_GT(dry.x(), dry.z()) << dry.transpose();
    // The aft hold is empty: below its centre it keeps its own colour.
    const Eigen::Vector3i empty = colourAt(a, g.nodes[1].position - Eigen::Vector3d(0, 0.25, 0));
    Eigen::Index expected = 0, got = 0;
    nodeColour(1).maxCoeff(&expected);
    empty.maxCoeff(&got);
    EXPECT_EQ(got, expected) << empty.transpose();
}

// The compartment boxes z-fought with the deck, their tops (in the deck's
// plane) a speckle of box and see-through hull. Drawn in perspective over the deck, each top is
// now one even colour: the hull over it everywhere.
TEST(EditorGraphView, BoxTopsInTheDecksPlaneShowNoZFighting) {
    const fs::path projectPath = copyDamagedBoat("zfight");
    const fs::path shot = projectPath.parent_path() / "persp.png";
    const int w = 640, h = 400;
    const test::CommandOutput r = test::runPlimsoll(
        "render '" + projectPath.string() + "' --out '" + shot.string() +
        "' --graph --view persp --size 640x400 --no-water --no-grid --overlay none");
    if (test::cannotRender(r)) GTEST_SKIP() << "no EGL OpenGL 4.5 here: " << r.err;
    ASSERT_EQ(r.exitCode, 0) << r.err;
    int iw = 0, ih = 0, ch = 0;
    unsigned char* data = stbi_load(shot.c_str(), &iw, &ih, &ch, 3);
    ASSERT_TRUE(data && iw == w && ih == h);
    const std::vector<unsigned char> img(data, data + 3 * iw * ih);
    stbi_image_free(data);
    auto doc = openOrFail(projectPath);
    ASSERT_TRUE(doc);
    const Camera camera = Camera::preset(ViewPreset::Persp, doc->worldBounds());
    const Pose pose = doc->bodyPose(0);
    const WaterGraph& g = *doc->graph(0);
    for (std::size_t n = 0; n < g.nodes.size(); ++n) {
        const GraphNode& node = g.nodes[n];
        ASSERT_TRUE(node.isBox()) << node.id;
        const Eigen::Vector3d half = 0.5 * node.boxSize;
        // The top's inner 60 % (clear of its edges' lines), sampled on a 9 x 9 grid.
        Eigen::Vector3i lo = Eigen::Vector3i::Constant(255), hi = Eigen::Vector3i::Zero();
        int samples = 0;
        for (int i = 0; i < 9; ++i) {
            for (int j = 0; j < 9; ++j) {
                const Eigen::Vector3d object =
                    node.position + Eigen::Vector3d((-0.6 + 0.15 * i) * half.x(), half.y(),
                                                    (-0.6 + 0.15 * j) * half.z());
                const auto p = camera.toPixel(pose.apply(object), w, h);
                if (!p || p->x() < 0 || p->y() < 0 || p->x() >= w || p->y() >= h) continue;
                const std::size_t k = 3 * (std::size_t(p->y()) * w + std::size_t(p->x()));
                const Eigen::Vector3i c(img[k], img[k + 1], img[k + 2]);
                lo = lo.cwiseMin(c);
                hi = hi.cwiseMax(c);
                ++samples;
            }
        }
        ASSERT_GT(samples, 40) << node.id << ": its top should be in the picture";
        EXPECT_LE((hi - lo).maxCoeff(), 12)
            << node.id << ": top from " << lo.transpose() << " to " << hi.transpose();
    }
}

}  // namespace
}  // namespace test_editor_graph
}  // namespace plimsoll::editor
