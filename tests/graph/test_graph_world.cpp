// Water graphs in the World (on the sample content): the damaged boat floats
// level, floods through its stern, trims by the stern and sinks; the same boat with its
// permeability map cleared floats the whole run; a flooded hold heels the boat more with the
// free-surface model, and radiates over a bounded lid; the plush soaks up water; a sealed body
// computes no graph. Every frame:
// water in = water stored + water out, every node within its capacity, and the body's mass is
// the hull's plus the water's.
#include "plimsoll/graph/graph.h"
#include "plimsoll/io/painted_map_io.h"
#include "plimsoll/io/graph_json.h"
#include "plimsoll/surface/painted_map.h"
#include "plimsoll/project/project.h"
#include "plimsoll/scene/scene_radiation.h"
#include "plimsoll/scene/world.h"

#include "test_support.h"
#include "world_support.h"

#include <Eigen/Geometry>

#include <cmath>
#include <numbers>

namespace plimsoll {
namespace test_graph_world {
namespace {

namespace fs = std::filesystem;

Project sampleProject(const std::string& name) {
    Result<Project> p =
        loadProject(fs::path(PLIMSOLL_SOURCE_DIR) / "projects" / (name + ".plim.json"));
    EXPECT_TRUE(p.ok()) << (p.ok() ? "" : p.error().message);
    return p.ok() ? std::move(p).value() : Project{};
}

/// On the fast CPU path (the default users get): these runs are tens of seconds of simulated
/// time, and what they check (flooding, trim, sinking, soaking) is the graph's and the
/// world's, not the buoyancy backend's.
std::unique_ptr<World> makeWorld(const Project& project) {
    return test::fastWorldOrFail(test::sceneOrFail(project));
}

/// y of the body's bow direction (object +z) in the world: > 0 when trimmed by the stern.
double bowRise(const SimulatedBody& body) {
    return (body.state.orientation * Eigen::Vector3d::UnitZ()).y();
}

/// Heel: x of the body's up direction (object +y) in the world (sin of the roll angle).
double heel(const SimulatedBody& body) {
    return (body.state.orientation * Eigen::Vector3d::UnitY()).x();
}

/// The checks every frame of a flooding body: bookkeeping, bounds, mass composition.
void expectConsistent(const World& world, double hullMass) {
    const WaterGraphSimulation* g = world.waterGraph(0);
    ASSERT_NE(g, nullptr);
    EXPECT_LT(g->conservationError(), 1e-9);
    for (const GraphNode& n : g->graph().nodes) {
        ASSERT_GE(n.water, 0.0) << n.id;
        ASSERT_LE(n.water, n.capacity) << n.id;
    }
    const double expected = hullMass + g->settings().density * g->storedWater();
    EXPECT_NEAR(world.bodies()[0].mass.mass, expected, 1e-9 * expected);
}

fs::path blackMap() {
    PaintedMap black;
    black.width = black.height = 4;
    black.values.assign(16, 0.0f);
    const fs::path file = test::scratchFolder("plimsoll_test_graph_world") / "cleared.png";
    EXPECT_TRUE(savePaintedMap(black, file).ok());
    return file;
}

TEST(GraphWorld, DamagedBoatFloodsByTheSternAndSinks) {
    const Project project = sampleProject("damaged_boat");
    ASSERT_FALSE(project.bodies.empty());
    std::unique_ptr<World> world = makeWorld(project);
    ASSERT_TRUE(world);
    const SimulatedBody& boat = world->bodies()[0];
    const double hullMass = boat.mass.mass;  // no water at the start
    const double startY = boat.state.position.y();
    const double height = 1.0;  // keel to deck (HullShape)
    const double level = project.water.level;
    double sinkTime = -1, maxTrimAfloat = 0, firstWaterTime = -1;
    bool sternFirst = false;
    const int frames = static_cast<int>(std::lround(40.0 / project.simulation.timeStep));
    for (int f = 0; f < frames && sinkTime < 0; ++f) {
        ASSERT_TRUE(world->advanceFrame().ok());
        expectConsistent(*world, hullMass);
        const double t = world->time();
        const WaterGraphSimulation& g = *world->waterGraph(0);
        if (firstWaterTime < 0 && g.storedWater() > 0) {
            firstWaterTime = t;
            // The stern compartment (under the damage) takes the first water; the rest is
            // what ran on through the bulkhead in the same step.
            sternFirst = g.graph().nodes[0].water > 0.9 * g.storedWater();
            std::printf("  first water: %.3g of %.3g m^3 in the stern compartment\n",
                        g.graph().nodes[0].water, g.storedWater());
        }
        if (t <= 1.0) {
            // Level at first: no trim, no heel, close to where it started.
            EXPECT_LT(std::abs(bowRise(boat)), std::sin(1.5 * std::numbers::pi / 180)) << t;
            EXPECT_LT(std::abs(heel(boat)), 1e-3) << t;
            EXPECT_NEAR(boat.state.position.y(), startY, 0.1) << t;
        }
        if (boat.state.position.y() > level - height) {
            maxTrimAfloat = std::max(maxTrimAfloat, bowRise(boat));
        } else {
            sinkTime = t;
        }
    }
    EXPECT_TRUE(sternFirst);
    EXPECT_GT(maxTrimAfloat, std::sin(5.0 * std::numbers::pi / 180)) << "trims by the stern";
    ASSERT_GT(sinkTime, 0.0) << "still afloat after 40 s";
    const WaterGraphSimulation& g = *world->waterGraph(0);
    std::printf(
        "  first water %.2f s, largest trim by the stern afloat %.1f deg, mean y below "
        "the water by more than the hull's height at %.2f s; water %.3f m^3 (entered "
        "%.3f, left %.3f), conservation error %.1e\n",
        firstWaterTime, std::asin(maxTrimAfloat) * 180 / std::numbers::pi, sinkTime,
        g.storedWater(), g.totals().entered, g.totals().left, g.conservationError());
}

TEST(GraphWorld, BoatWithItsPermeabilityClearedFloatsTheWholeRun) {
    Project project = sampleProject("damaged_boat");
    ASSERT_FALSE(project.bodies.empty());
    project.bodies[0].permeabilityMap = blackMap().string();
    std::unique_ptr<World> world = makeWorld(project);
    ASSERT_TRUE(world);
    const SimulatedBody& boat = world->bodies()[0];
    const double mass = boat.mass.mass;
    const int frames = static_cast<int>(std::lround(40.0 / project.simulation.timeStep));
    double lowest = 1e9, maxTrim = 0;
    for (int f = 0; f < frames; ++f) {
        ASSERT_TRUE(world->advanceFrame().ok());
        lowest = std::min(lowest, boat.state.position.y());
        maxTrim = std::max(maxTrim, std::abs(bowRise(boat)));
    }
    EXPECT_EQ(world->waterGraph(0)->storedWater(), 0.0);
    EXPECT_EQ(world->waterGraph(0)->samples().size(), 0u);  // nothing permeable
    EXPECT_EQ(boat.mass.mass, mass);
    EXPECT_GT(lowest, project.water.level - 0.5);  // afloat: deck never under
    EXPECT_LT(maxTrim, std::sin(1.0 * std::numbers::pi / 180));
    EXPECT_GT(world->statistics().graphSteps, 0u);
    EXPECT_EQ(world->statistics().waterCompositions, 0u);
    std::printf("  intact boat over 40 s: lowest centre of mass y %.3f m, largest trim %.2f deg\n",
                lowest, std::asin(maxTrim) * 180 / std::numbers::pi);
}

/// The sample boat with 40% of each hold flooded (its graph saved as `graphFile` in scratch),
/// no exchange (the water it has, it keeps), nearer its flooded draft.
Project floodedBoat(const std::string& graphFile) {
    Project project = sampleProject("damaged_boat");
    BodyDesc& body = project.bodies[0];
    body.permeabilityMap.clear();
    Result<WaterGraph> graph = loadGraph(project.resolvePath(body.waterGraph->graph));
    EXPECT_TRUE(graph.ok());
    const fs::path file = test::scratchFolder("plimsoll_test_graph_world") / graphFile;
    if (graph) {
        for (GraphNode& n : graph->nodes) n.water = 0.4 * n.capacity;
        EXPECT_TRUE(saveGraph(*graph, file).ok());
    }
    body.waterGraph->graph = file.string();
    body.position.y() = -0.15;
    return project;
}

/// Largest heel (degrees) in 8 s of the flooded boat, rolled by an initial angular velocity,
/// with or without the free-surface model.
double largestHeel(bool freeSurface) {
    Project project = floodedBoat(freeSurface ? "flooded_fs.graph.json" : "flooded.graph.json");
    BodyDesc& body = project.bodies[0];
    body.waterGraph->settings.freeSurface = freeSurface;
    body.angularVelocity = {0.0, 0.0, 0.25};  // roll, rad/s
    // The free surface against water held at the nodes, without radiation's damping of the
    // roll, which would shrink both heels.
    body.radiation = RadiationDesc{};
    body.radiation->enabled = false;
    std::unique_ptr<World> world = makeWorld(project);
    if (!world) return 0;
    double largest = 0;
    const double hullMass =
        world->bodies()[0].mass.mass - 1000.0 * world->waterGraph(0)->storedWater();
    for (int f = 0; f < static_cast<int>(8.0 / project.simulation.timeStep); ++f) {
        EXPECT_TRUE(world->advanceFrame().ok());
        expectConsistent(*world, hullMass);
        largest = std::max(largest, std::abs(heel(world->bodies()[0])));
    }
    return std::asin(std::min(1.0, largest)) * 180 / std::numbers::pi;
}

// Flooded, the boat floats with its waterline near the deck, a loop of short edges that is not
// star-shaped. Its radiation lid is bounded as the rings are, half the body's panels (split to
// the waterline's edge it had 4177 panels for the body's 164, and minutes per frequency), and
// the World radiates (the default) while it rolls.
TEST(GraphWorld, AFloodedBoatRadiatesOverABoundedLid) {
    Project project = floodedBoat("flooded_radiating.graph.json");
    project.bodies[0].angularVelocity = {0.0, 0.0, 0.25};
    const Scene scene = test::sceneOrFail(project);
    ASSERT_FALSE(scene.bodies.empty());
    Result<RestRadiationSurface> surface = restRadiationSurface(
        scene.bodies[0], RadiationDesc{}, scene.medium, scene.simulation.gravity);
    ASSERT_TRUE(surface.ok()) << surface.error().message;
    const RadiationSolver& solver = *surface->solver;
    std::printf("  flooded boat: %zu panels, %zu on the lid\n", solver.panelCount(),
                solver.lidPanels().size());
    EXPECT_GT(solver.lidPanels().size(), 0u);
    EXPECT_LE(solver.lidPanels().size(), solver.panelCount() / 2);
    std::unique_ptr<World> world = test::fastWorldOrFail(scene);
    ASSERT_TRUE(world);
    ASSERT_NE(world->radiation(0), nullptr);
    const double hullMass =
        world->bodies()[0].mass.mass - 1000.0 * world->waterGraph(0)->storedWater();
    for (int f = 0; f < static_cast<int>(2.0 / project.simulation.timeStep); ++f) {
        ASSERT_TRUE(world->advanceFrame().ok());
        expectConsistent(*world, hullMass);
    }
}

TEST(GraphWorld, FreeSurfaceHeelsAFloodedBoatMore) {
    const double fixed = largestHeel(false);
    const double free = largestHeel(true);
    std::printf(
        "  largest heel in 8 s after a 0.25 rad/s roll, holds 40%% flooded: water at "
        "the nodes %.2f deg, free surface %.2f deg\n",
        fixed, free);
    EXPECT_GT(fixed, 0.5);
    EXPECT_GT(free, 1.2 * fixed);
}

TEST(GraphWorld, PlushSoaksUpWaterAndSettles) {
    const Project project = sampleProject("plush");
    ASSERT_FALSE(project.bodies.empty());
    std::unique_ptr<World> world = makeWorld(project);
    ASSERT_TRUE(world);
    const SimulatedBody& plush = world->bodies()[0];
    const double dryMass = plush.mass.mass;
    const WaterGraphSimulation& g = *world->waterGraph(0);
    EXPECT_EQ(g.settings().flow, FlowMode::Diffusion);
    double submergedEarly = 0, submergedLate = 0, waterEarly = 0;
    const int frames = static_cast<int>(std::lround(20.0 / project.simulation.timeStep));
    for (int f = 0; f < frames; ++f) {
        ASSERT_TRUE(world->advanceFrame().ok());
        expectConsistent(*world, dryMass);
        if (f == 120) {
            submergedEarly = plush.buoyancy.submergedVolume;
            waterEarly = g.storedWater();
        }
    }
    submergedLate = plush.buoyancy.submergedVolume;
    // Some runs out again as it bobs up (texels above the water, below the inside level),
    // but it soaks up far more.
    EXPECT_GT(g.totals().left, 0.0);
    EXPECT_GT(g.storedWater(), 3.0 * waterEarly);
    // The water spread to every node, the head included (diffusion, against gravity).
    for (const GraphNode& n : g.graph().nodes) EXPECT_GT(n.water, 0.0) << n.id;
    EXPECT_GT(submergedLate, 1.5 * submergedEarly);
    std::printf(
        "  plush after 20 s: %.4f m^3 of water (%.0f%% of its capacity), submerged "
        "volume %.4f -> %.4f m^3\n",
        g.storedWater(), 100 * g.storedWater() / g.graph().totalCapacity(), submergedEarly,
        submergedLate);
}

TEST(GraphWorld, SealedBodyComputesNoGraph) {
    const Project project = sampleProject("box_half_draft");
    ASSERT_FALSE(project.bodies.empty());
    ASSERT_FALSE(project.bodies[0].waterGraph);
    std::unique_ptr<World> world = makeWorld(project);
    ASSERT_TRUE(world);
    for (int f = 0; f < 30; ++f) ASSERT_TRUE(world->advanceFrame().ok());
    EXPECT_EQ(world->waterGraph(0), nullptr);
    EXPECT_EQ(world->statistics().graphSteps, 0u);
    EXPECT_EQ(world->bodies()[0].backendCenter, world->bodies()[0].mass.centerOfMass);
}

TEST(GraphWorld, ProjectRoundTripsTheWaterGraph) {
    const Project project = sampleProject("damaged_boat");
    ASSERT_TRUE(project.bodies[0].waterGraph);
    Result<Project> back = parseProject(projectToJson(project), "again", project.folder);
    ASSERT_TRUE(back.ok()) << back.error().message;
    EXPECT_TRUE(*back == project);
    // Bad values are reported with their path.
    std::string text = projectToJson(project);
    const std::string from = "\"flow\": \"poiseuille\"";
    text.replace(text.find(from), from.size(), "\"flow\": \"syrup\"");
    Result<Project> bad = parseProject(text, "bad.plim.json", project.folder);
    ASSERT_FALSE(bad.ok());
    EXPECT_NE(bad.error().message.find("bodies[0].water_graph.flow: unknown 'syrup'"),
              std::string::npos)
        << bad.error().message;
}

}  // namespace
}  // namespace test_graph_world
}  // namespace plimsoll
