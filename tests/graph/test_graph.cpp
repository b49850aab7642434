// Water graph (graph.h): validation classes, the paper's findDischargeNode cases (figure 7),
// Poiseuille's law against its formula, no overshoot, exact bookkeeping of the water that
// enters, stays and leaves, diffusion, and the water's mass properties.
#include "plimsoll/graph/graph.h"

#include "plimsoll/bake/bake.h"
#include "plimsoll/geometry/box.h"
#include "plimsoll/physics/buoyancy.h"
#include "plimsoll/samples/primitives.h"

#include "graph_support.h"
#include "test_support.h"

#include "plimsoll_eval/nearest_node.hpp"

#include <Eigen/Geometry>

#include <cmath>
#include <numbers>
#include <random>

namespace plimsoll {
namespace test_graph {
namespace {

using test::node;
using test::pipe;
using test::threeNodes;

WaterGraphSimulation simulationOf(const WaterGraph& g, GraphSettings settings = {}) {
    Result<WaterGraphSimulation> sim =
        WaterGraphSimulation::create(g, SurfaceTextures{}, {}, settings);
    EXPECT_TRUE(sim.ok()) << (sim.ok() ? "" : sim.error().message);
    return std::move(sim).value();
}

/// Sphere of volume C: radius.
double sphereRadius(double capacity) {
    return std::cbrt(3.0 * capacity / (4.0 * std::numbers::pi));
}

// --- validation ----------------------------------------------------------------------------

TEST(GraphValidation, AValidGraphHasNoProblems) {
    const GraphReport r = validateGraph(threeNodes());
    EXPECT_TRUE(r.problems.empty()) << r.format();
}

TEST(GraphValidation, EachErrorHasItsClass) {
    struct Case {
        const char* what;
        std::function<void(WaterGraph&)> breakIt;
        GraphProblemKind kind;
    };
    const Case cases[] = {
        {"duplicate id", [](WaterGraph& g) { g.nodes[2].id = "a"; }, GraphProblemKind::DuplicateId},
        {"dangling pipe", [](WaterGraph& g) { g.pipes[1].b = "nowhere"; },
         GraphProblemKind::DanglingPipe},
        {"zero capacity",
         [](WaterGraph& g) {
             g.nodes[1].capacity = 0;
             g.nodes[1].water = 0;
         },
         GraphProblemKind::BadCapacity},
        {"negative capacity", [](WaterGraph& g) { g.nodes[0].capacity = -1; },
         GraphProblemKind::BadCapacity},
        {"self-loop", [](WaterGraph& g) { g.pipes[0].b = "a"; }, GraphProblemKind::SelfLoop},
        {"water above capacity", [](WaterGraph& g) { g.nodes[0].water = 2; },
         GraphProblemKind::WaterOutOfRange},
        {"zero radius", [](WaterGraph& g) { g.pipes[0].radius = 0; }, GraphProblemKind::BadPipe},
        {"no nodes",
         [](WaterGraph& g) {
             g.nodes.clear();
             g.pipes.clear();
         },
         GraphProblemKind::Empty},
    };
    for (const Case& c : cases) {
        WaterGraph g = threeNodes();
        c.breakIt(g);
        const GraphReport r = validateGraph(g, nullptr, "test.graph.json");
        EXPECT_TRUE(r.hasErrors()) << c.what;
        EXPECT_TRUE(r.has(c.kind)) << c.what << ":\n" << r.format();
        // The message names the file and the class.
        EXPECT_NE(r.format().find("test.graph.json: error [" +
                                  std::string(graphProblemCode(c.kind)) + "]"),
                  std::string::npos)
            << r.format();
        // And the simulation refuses it.
        const auto refused = WaterGraphSimulation::create(g, SurfaceTextures{}, {}, {});
        ASSERT_FALSE(refused.ok()) << c.what;
        EXPECT_EQ(refused.error().kind, ErrorKind::schema) << c.what;
    }
}

TEST(GraphValidation, NodeOutsideTheMeshIsAWarning) {
    const TriangleMesh box = makeBox({2, 2, 2});
    EXPECT_NEAR(windingNumber(box, {0.2, 0.3, -0.1}), 1.0, 1e-9);
    EXPECT_NEAR(windingNumber(box, {3, 0, 0}), 0.0, 1e-9);
    WaterGraph g;
    g.nodes = {node("in", {0.5, 0, 0}, 1), node("out", {0, 5, 0}, 1)};
    g.pipes = {pipe("in", "out", 0.1)};
    const GraphReport r = validateGraph(g, &box);
    EXPECT_FALSE(r.hasErrors()) << r.format();
    ASSERT_TRUE(r.has(GraphProblemKind::NodeOutsideMesh)) << r.format();
    EXPECT_NE(r.format().find("'out'"), std::string::npos) << r.format();
    EXPECT_EQ(r.format().find("'in' at"), std::string::npos) << r.format();
}

// The inside test went through every triangle per node (1e11 solid angles for kMaxGraphNodes
// against a 1M-triangle hull); the tree of triangle clusters that replaces it must flag the
// same nodes as the exact winding number: nodes spread through and around a buoy (3264
// triangles), many close to its surface on either side.
TEST(GraphValidation, NodesOutsideTheMeshAreTheExactWindingNumbersOnes) {
    const TriangleMesh buoy = makeBuoy();
    Eigen::Vector3d lo = buoy.positions.front(), hi = lo;
    for (const Eigen::Vector3d& p : buoy.positions) {
        lo = lo.cwiseMin(p);
        hi = hi.cwiseMax(p);
    }
    WaterGraph g;
    std::uint64_t state = 99;
    auto uniform = [&] {
        state = state * 6364136223846793005ull + 1442695040888963407ull;
        return static_cast<double>(state >> 11) / 9007199254740992.0;
    };
    std::size_t outside = 0;
    for (int i = 0; i < 600; ++i) {
        const Eigen::Vector3d t(uniform(), uniform(), uniform());
        // Within the box around the buoy, 10% beyond each side.
        const Eigen::Vector3d p = lo - 0.1 * (hi - lo) + 1.2 * t.cwiseProduct(hi - lo);
        g.nodes.push_back(node("n" + std::to_string(i), p, 1e-3));
        if (i > 0)
            g.pipes.push_back(pipe("n" + std::to_string(i - 1), "n" + std::to_string(i), 0.01));
        outside += windingNumber(buoy, p) < 0.5;
    }
    ASSERT_GT(outside, 100u);
    ASSERT_LT(outside, 550u);
    const GraphReport r = validateGraph(g, &buoy);
    std::size_t flagged = 0;
    for (const GraphProblem& p : r.problems) flagged += p.kind == GraphProblemKind::NodeOutsideMesh;
    EXPECT_EQ(flagged, outside);
    for (std::size_t i = 0; i < g.nodes.size(); ++i) {
        const bool warned = r.format().find("node " + std::to_string(i) + " 'n" +
                                            std::to_string(i) + "' at") != std::string::npos;
        EXPECT_EQ(warned, windingNumber(buoy, g.nodes[i].position) < 0.5) << "node " << i;
    }
}

TEST(GraphValidation, DisconnectedGraphIsAWarning) {
    WaterGraph g = threeNodes();
    g.pipes[1].open = false;
    const GraphReport r = validateGraph(g);
    EXPECT_FALSE(r.hasErrors());
    EXPECT_TRUE(r.has(GraphProblemKind::Disconnected));
}

// --- flow inside ---------------------------------------------------------------------------

TEST(GraphFlow, FigureSevenWaterReachesTheLowNodeThroughTheFullOne) {
    // A partly filled above, B full in the middle, C empty below: A discharges into C
    // directly; B never takes water in or gives it up (nothing passes upward).
    WaterGraphSimulation sim = simulationOf(threeNodes());
    const Eigen::Matrix3d upright = Eigen::Matrix3d::Identity();
    EXPECT_EQ(sim.findDischargeNode(0, upright), 2);
    EXPECT_EQ(sim.findDischargeNode(1, upright), 2);  // B itself can drain into C
    double previousA = sim.graph().nodes[0].water;
    for (int i = 0; i < 2000; ++i) {
        sim.flowInside(upright, 1.0 / 60.0);
        const auto& n = sim.graph().nodes;
        // A only loses, C only gains, B stays full as long as A has water (A goes first or
        // B refills from A; B never rises above full nor drops while A is non-empty).
        EXPECT_LE(n[0].water, previousA + 1e-15);
        previousA = n[0].water;
        for (const GraphNode& x : n) {
            EXPECT_GE(x.water, 0.0);
            EXPECT_LE(x.water, x.capacity);
        }
    }
    const auto& n = sim.graph().nodes;
    EXPECT_GT(n[2].water, 0.5);  // C received A's water and more
    EXPECT_NEAR(n[0].water + n[1].water + n[2].water, 1.5, 1e-12);
    // Everything ran down as far as it can: A empty, C full, B holding the rest.
    EXPECT_NEAR(n[0].water, 0.0, 1e-12);
    EXPECT_NEAR(n[2].water, 1.0, 1e-12);
}

TEST(GraphFlow, FigureSevenAHigherNodeIsABarrier) {
    // The same, but B lies above A (its lowest point above A's water): A cannot reach C, and
    // never loses water; B, full and on top, may drain into either.
    WaterGraph g = threeNodes();
    g.nodes[1].position.y() = 6.0;
    WaterGraphSimulation sim = simulationOf(g);
    const Eigen::Matrix3d upright = Eigen::Matrix3d::Identity();
    EXPECT_EQ(sim.findDischargeNode(0, upright), -1);
    double previousA = sim.graph().nodes[0].water;
    for (int i = 0; i < 500; ++i) {
        sim.flowInside(upright, 1.0 / 60.0);
        EXPECT_GE(sim.graph().nodes[0].water, previousA);
        previousA = sim.graph().nodes[0].water;
    }
    EXPECT_NEAR(sim.graph().totalWater(), 1.5, 1e-12);
    // With B sealed, nothing moves at all.
    g.nodes[1].sealed = true;
    WaterGraphSimulation sealed = simulationOf(g);
    for (int i = 0; i < 100; ++i) EXPECT_FALSE(sealed.flowInside(upright, 1.0 / 60.0));
    EXPECT_DOUBLE_EQ(sealed.graph().nodes[0].water, 0.5);
    EXPECT_DOUBLE_EQ(sealed.graph().nodes[2].water, 0.0);
}

TEST(GraphFlow, FindDischargeNodeSkipsAHigherNodeEvenWhenFull) {
    // Turn the body upside down: C is now on top, A at the bottom. A (partly filled) has no
    // node below it, so it cannot discharge; C (empty) has nothing to give.
    WaterGraphSimulation sim = simulationOf(threeNodes());
    const Eigen::Matrix3d flipped =
        Eigen::AngleAxisd(std::numbers::pi, Eigen::Vector3d::UnitX()).toRotationMatrix();
    EXPECT_EQ(sim.findDischargeNode(0, flipped), -1);
    EXPECT_EQ(sim.findDischargeNode(2, flipped), -1);
    // B (full, now above A) discharges into A.
    EXPECT_EQ(sim.findDischargeNode(1, flipped), 0);
}

TEST(GraphFlow, PoiseuilleRateMatchesTheFormulaForOnePipe) {
    // A half-full sphere 10 m above an empty one; a long thin pipe, so the step is not
    // limited: moved = pi rho g dh r^4 dt / (8 mu L), dh from the two water levels.
    const double capacity = 2.0, radius = 0.004, length = 3.0, dt = 0.01;
    WaterGraph g;
    g.nodes = {node("a", {0, 10, 0}, capacity, capacity / 2), node("b", {0, 0, 0}, capacity, 0)};
    g.pipes = {pipe("a", "b", radius, length)};
    GraphSettings s;
    s.density = 1000;
    s.viscosity = 1.0e-3;
    s.gravity = 9.81;
    WaterGraphSimulation sim = simulationOf(g, s);
    // Half-full sphere: level at its centre; empty sphere: level at its bottom.
    const double dh = 10.0 - (0.0 - sphereRadius(capacity));
    const double expected =
        std::numbers::pi * (1000 * 9.81 * dh) * std::pow(radius, 4) * dt / (8 * 1.0e-3 * length);
    ASSERT_TRUE(sim.flowInside(Eigen::Matrix3d::Identity(), dt));
    EXPECT_NEAR(sim.graph().nodes[1].water, expected, 1e-9 * expected);
    EXPECT_NEAR(sim.graph().nodes[0].water, capacity / 2 - expected, 1e-12);
    EXPECT_NEAR(WaterGraphSimulation::poiseuilleRate(1000 * 9.81 * dh, radius, 1e-3, length) * dt,
                expected, 1e-12 * expected);
    std::printf("  Poiseuille: %.6e m^3 in %.2f s (formula %.6e)\n", sim.graph().nodes[1].water, dt,
                expected);
}

TEST(GraphFlow, NeverOvershootsConnectedLevelsNeverSwap) {
    // Side by side, one full and one empty, a wide pipe and a long step: without the limit a
    // step would send far more than the difference and the two would swap every step.
    WaterGraph g;
    g.nodes = {node("a", {0, 0, 0}, 1.0, 1.0), node("b", {3, -0.2, 0}, 0.5, 0.0),
               node("c", {6, 0.1, 0}, 2.0, 0.3)};
    g.pipes = {pipe("a", "b", 0.5), pipe("b", "c", 0.5)};
    WaterGraphSimulation sim = simulationOf(g);
    const Eigen::Matrix3d upright = Eigen::Matrix3d::Identity();
    auto levels = [&] {
        std::vector<double> l;
        for (std::size_t i = 0; i < 3; ++i) {
            l.push_back(sim.graph().nodes[i].position.y() +
                        sim.levelOffset(i, sim.graph().nodes[i].water, upright));
        }
        return l;
    };
    std::vector<double> before = levels();
    const double total = sim.graph().totalWater();
    for (int step = 0; step < 200; ++step) {
        sim.flowInside(upright, 1.0);
        const std::vector<double> after = levels();
        for (const auto& [i, j] : {std::pair{0, 1}, std::pair{1, 2}}) {
            const double was = before[i] - before[j], is = after[i] - after[j];
            // The higher one stays higher (or they meet).
            if (std::abs(was) > 1e-9)
                EXPECT_GE(is * (was > 0 ? 1.0 : -1.0), -1e-9) << "step " << step;
        }
        before = after;
    }
    EXPECT_NEAR(sim.graph().totalWater(), total, 1e-12);
}

TEST(GraphFlow, DiffusionEvensOutFillWhateverTheHeight) {
    // Absorbent material: water moves from the fuller node to the emptier, even upward, and
    // stops when both are equally full (no overshoot).
    WaterGraph g;
    g.nodes = {node("low", {0, 0, 0}, 1.0, 0.9), node("high", {0, 1, 0}, 3.0, 0.0)};
    g.pipes = {pipe("low", "high", 0.05)};
    GraphSettings s;
    s.flow = FlowMode::Diffusion;
    s.diffusionPressure = 2000;
    WaterGraphSimulation sim = simulationOf(g, s);
    const double dt = 0.5;
    const double rate =
        WaterGraphSimulation::poiseuilleRate(2000 * 0.9, 0.05, 1e-3, 1.0) * dt;  // first step
    sim.flowInside(Eigen::Matrix3d::Identity(), dt);
    EXPECT_NEAR(sim.graph().nodes[1].water, std::min(rate, 0.9 * 3.0 / 4.0), 1e-12);
    for (int i = 0; i < 500; ++i) {
        sim.flowInside(Eigen::Matrix3d::Identity(), dt);
        const auto& n = sim.graph().nodes;
        EXPECT_GE(n[0].water / n[0].capacity, n[1].water / n[1].capacity - 1e-12);
    }
    const auto& n = sim.graph().nodes;
    EXPECT_NEAR(n[0].water / 1.0, 0.9 / 4.0, 1e-9);
    EXPECT_NEAR(n[1].water / 3.0, 0.9 / 4.0, 1e-9);
}

TEST(GraphFlow, DeterministicForASeed) {
    WaterGraph g;
    for (int i = 0; i < 6; ++i) {
        g.nodes.push_back(node("n" + std::to_string(i), {double(i % 3), double(i / 3), 0.3 * i},
                               0.5 + 0.1 * i, 0.05 * i));
    }
    for (int i = 0; i + 1 < 6; ++i)
        g.pipes.push_back(
            pipe("n" + std::to_string(i), "n" + std::to_string(i + 1), 0.02 + 0.01 * i));
    g.pipes.push_back(pipe("n0", "n5", 0.03));
    GraphSettings s;
    s.seed = 42;
    WaterGraphSimulation x = simulationOf(g, s), y = simulationOf(g, s);
    const Eigen::Matrix3d r =
        Eigen::AngleAxisd(0.3, Eigen::Vector3d(1, 0, 1).normalized()).toRotationMatrix();
    for (int i = 0; i < 300; ++i) {
        x.flowInside(r, 0.05);
        y.flowInside(r, 0.05);
    }
    for (std::size_t i = 0; i < g.nodes.size(); ++i) {
        EXPECT_EQ(x.graph().nodes[i].water, y.graph().nodes[i].water);
    }
}

// --- exchange with the outside -------------------------------------------------------------

/// One texel entry at `position` with area `area`, in an otherwise empty set of textures.
SurfaceTextures oneEntry(const Eigen::Vector3d& position, double area) {
    SurfaceTextures t;
    t.size = 16;
    t.texelIndex = {0};
    t.position = {position};
    t.areaVector = {Eigen::Vector3d(0, -area, 0)};
    t.area = {area};
    t.coverage = {1.0};
    return t;
}

TEST(GraphExchange, LinearAndTorricelliRatesMatchTheirFormulas) {
    // One texel 0.3 m under flat water, permeability 0.5, area 0.01 m^2, feeding an empty
    // node: inflow in one step is rate k A h dt, or C_d k A sqrt(2 g h) dt.
    const double depth = 0.3, k = 0.5, area = 0.01, dt = 0.02;
    WaterGraph g;
    g.nodes = {node("n", {0, 0, 0}, 1.0)};
    const SurfaceTextures t = oneEntry({0, -depth, 0}, area);
    for (InflowModel model : {InflowModel::Linear, InflowModel::Torricelli}) {
        GraphSettings s;
        s.inflow = model;
        s.inflowRate = 2.0;
        s.dischargeCoefficient = 0.6;
        s.gravity = 9.81;
        Result<WaterGraphSimulation> sim = WaterGraphSimulation::create(g, t, {k}, s);
        ASSERT_TRUE(sim.ok()) << sim.error().message;
        ASSERT_EQ(sim->samples().size(), 1u);
        sim->exchange(Pose{}, WaterModel::flat(0.0), 0.0, dt);
        const double expected = model == InflowModel::Linear
                                    ? 2.0 * k * area * depth * dt
                                    : 0.6 * k * area * std::sqrt(2 * 9.81 * depth) * dt;
        EXPECT_NEAR(sim->graph().nodes[0].water, expected, 1e-15) << inflowModelName(model);
        EXPECT_NEAR(sim->totals().entered, expected, 1e-15);
    }
}

TEST(GraphExchange, TexelNodeMapIsTheNearestNodeAndFeedsTheSamples) {
    // Three nodes on a line; a sphere node and a box node: a texel goes to the nearest node
    // (distance to the box, not its centre), and the simulation's samples follow the map,
    // leaving out the sealed node's texels and those with no permeability.
    WaterGraph g;
    g.nodes = {node("a", {0, 0, 0}, 1.0), node("b", {4, 0, 0}, 1.0), node("c", {8, 0, 0}, 1.0)};
    g.nodes[1].boxSize = {4.0, 0.5, 0.5};  // exactly 1 m^3: x from 2 to 6
    g.nodes[2].sealed = true;
    SurfaceTextures t;
    t.size = 16;
    for (double x : {0.5, 1.9, 2.1, 5.9, 6.9, 7.5, 9.0}) {
        t.texelIndex.push_back(static_cast<std::uint32_t>(t.texelIndex.size()));
        t.position.push_back({x, 0, 0});
        t.areaVector.push_back({0, -0.01, 0});
        t.area.push_back(0.01);
        t.coverage.push_back(1.0);
    }
    const std::vector<std::int32_t> map = texelNodeMap(g, t);
    EXPECT_EQ(map, (std::vector<std::int32_t>{0, 1, 1, 1, 1, 2, 2}));
    EXPECT_EQ(nearestNode(WaterGraph{}, Eigen::Vector3d::Zero()), -1);
    const std::vector<double> permeability = {1, 1, 0, 1, 1, 1, 1};
    Result<WaterGraphSimulation> sim = WaterGraphSimulation::create(g, t, permeability, {});
    ASSERT_TRUE(sim.ok()) << sim.error().message;
    ASSERT_EQ(sim->samples().size(), 4u);  // the zero-permeability and the sealed texels out
    const std::vector<std::uint32_t> expected = {0, 1, 1, 1};
    for (std::size_t i = 0; i < 4; ++i) EXPECT_EQ(sim->samples()[i].node, expected[i]);
}

// The texel map went through a scan of every node per texel (1e10 distances for a graph of
// kMaxGraphNodes); the tree that replaces it must give the scan's node for every point, ties
// included: nodes on a grid (many equidistant), coincident nodes (ties broken by index), box
// nodes holding the point (distance 0) and points far outside.
TEST(GraphExchange, TheTexelMapsTreeGivesTheScansNodeTiesIncluded) {
    WaterGraph g;
    std::uint64_t state = 12345;
    auto uniform = [&] {  // splitmix-style LCG, in [0, 1)
        state = state * 6364136223846793005ull + 1442695040888963407ull;
        return static_cast<double>(state >> 11) / 9007199254740992.0;
    };
    for (int i = 0; i < 6; ++i)
        for (int j = 0; j < 6; ++j)
            for (int k = 0; k < 6; ++k)
                g.nodes.push_back(
                    node("g" + std::to_string(g.nodes.size()), {0.1 * i, 0.1 * j, 0.1 * k}, 1e-4));
    for (int i = 0; i < 40; ++i)
        g.nodes.push_back(node("c" + std::to_string(i), {0.2, 0.2, 0.2}, 1e-4));
    for (int i = 0; i < 400; ++i) {
        GraphNode n = node("r" + std::to_string(i), {uniform(), uniform(), uniform()}, 1e-4);
        if (i % 3 == 0)
            n.boxSize = {0.01 + 0.2 * uniform(), 0.01 + 0.1 * uniform(), 0.01 + 0.05 * uniform()};
        g.nodes.push_back(n);
    }
    SurfaceTextures t;
    t.size = 1024;
    auto add = [&](const Eigen::Vector3d& p) {
        t.texelIndex.push_back(static_cast<std::uint32_t>(t.texelIndex.size()));
        t.position.push_back(p);
        t.areaVector.push_back({0, -0.01, 0});
        t.area.push_back(0.01);
        t.coverage.push_back(1.0);
    };
    for (int i = 0; i < 11; ++i)
        for (int j = 0; j < 11; ++j)
            for (int k = 0; k < 11; ++k) add({0.05 * i, 0.05 * j, 0.05 * k});  // midpoints: ties
    for (int i = 0; i < 3000; ++i) add({3 * uniform() - 1, 3 * uniform() - 1, 3 * uniform() - 1});
    const std::vector<std::int32_t> map = texelNodeMap(g, t);
    ASSERT_EQ(map.size(), t.position.size());
    std::size_t ties = 0;
    for (std::size_t i = 0; i < map.size(); ++i) {
        // The scan, its tie rule written out here: nearest compartment, then centre, then index
        // (the distances from the shared formula, so that rounding is the same on both sides).
        int best = -1;
        double bestDistance = 0, bestCentre = 0;
        const plimsoll_eval::Vec3 p{t.position[i].x(), t.position[i].y(), t.position[i].z()};
        for (std::size_t j = 0; j < g.nodes.size(); ++j) {
            const GraphNode& n = g.nodes[j];
            const plimsoll_eval::NodeShape shape{{n.position.x(), n.position.y(), n.position.z()},
                                                 {n.boxSize.x(), n.boxSize.y(), n.boxSize.z()}};
            const double d = plimsoll_eval::nodeDistance(shape, p);
            const double c = plimsoll_eval::norm(shape.centre - p);
            if (best >= 0 && d == bestDistance && c == bestCentre) ++ties;
            if (best < 0 || d < bestDistance || (d == bestDistance && c < bestCentre)) {
                best = static_cast<int>(j);
                bestDistance = d;
                bestCentre = c;
            }
        }
        ASSERT_EQ(map[i], best) << "point " << i << " at " << t.position[i].transpose();
        EXPECT_EQ(nearestNode(g, t.position[i]), best);
    }
    EXPECT_GT(ties, 100u);  // the grid and the coincident nodes did tie
}

/// Tied nodes (many at one point, or boxes that all contain the points asked) must not turn
/// the tree into a scan: the nodes a query examines stay a few leaves' worth, the answer the
/// scan's. Counted through the index's own tally, not timed.
TEST(GraphExchange, TiedNodesCostTheTreeNoMoreThanDistinctOnes) {
    std::uint64_t state = 777;
    auto uniform = [&] {
        state = state * 6364136223846793005ull + 1442695040888963407ull;
        return static_cast<double>(state >> 11) / 9007199254740992.0;
    };
    using plimsoll_eval::NodeShape;
    std::vector<NodeShape> atOnePoint(100000, NodeShape{{0.5, 0.25, 0.125}, {0, 0, 0}});
    atOnePoint.push_back({{0.9, 0.9, 0.9}, {0, 0, 0}});
    std::vector<NodeShape> containing;  // boxes of distinct centres and sizes, all holding [0,1]^3
    for (int i = 0; i < 20000; ++i)
        containing.push_back({{0.5 + 0.1 * uniform(), 0.5 + 0.1 * uniform(), 0.5 + 0.1 * uniform()},
                              {2 + uniform(), 2 + uniform(), 2 + uniform()}});
    for (const std::vector<NodeShape>* nodes : {&atOnePoint, &containing}) {
        const plimsoll_eval::NearestNodeIndex index(*nodes);
        std::size_t worst = 0;
        for (int q = 0; q < 200; ++q) {
            const plimsoll_eval::Vec3 p{uniform(), uniform(), uniform()};
            std::size_t examined = 0;
            const int found = index.nearest(p, &examined);
            worst = std::max(worst, examined);
            if (q < 20) EXPECT_EQ(found, plimsoll_eval::nearestNodeByScan(*nodes, p));
        }
        // A scan examines every node (100001 or 20000); the tree a few leaves of 8.
        EXPECT_LT(worst, 2000u) << nodes->size() << " nodes";
    }
    // 100000 nodes at one point: the lowest index answers wherever the point is, bar the
    // lone node nearer to it.
    const plimsoll_eval::NearestNodeIndex index(atOnePoint);
    EXPECT_EQ(index.nearest({0.5, 0.25, 0.2}), 0);
    EXPECT_EQ(index.nearest({1, 1, 1}), 100000);
}

TEST(GraphExchange, WaterLeavesAboveTheOutsideWaterAndBelowTheInsideLevel) {
    // A full node whose texel is above the water: the water runs out through it.
    WaterGraph g;
    g.nodes = {node("n", {0, 0, 0}, 1.0, 1.0)};
    const double r = sphereRadius(1.0);
    const SurfaceTextures t = oneEntry({0, -0.5 * r, 0}, 0.01);
    GraphSettings s;
    s.inflowRate = 1.0;
    Result<WaterGraphSimulation> sim = WaterGraphSimulation::create(g, t, {1.0}, s);
    ASSERT_TRUE(sim.ok());
    // Water far below: the texel is dry outside; inside head = top of the sphere - texel.
    sim->exchange(Pose{}, WaterModel::flat(-10.0), 0.0, 0.1);
    EXPECT_NEAR(sim->totals().left, 1.0 * 0.01 * (r + 0.5 * r) * 0.1, 1e-12);
    EXPECT_EQ(sim->totals().entered, 0.0);
    // A texel above the inside level lets nothing out: drain until the level reaches it.
    for (int i = 0; i < 20000; ++i) sim->exchange(Pose{}, WaterModel::flat(-10.0), 0.0, 0.1);
    EXPECT_NEAR(sim->levelOffset(0, sim->graph().nodes[0].water, Eigen::Matrix3d::Identity()),
                -0.5 * r, 1e-3);
    EXPECT_LT(sim->conservationError(), 1e-12);
}

TEST(GraphExchange, ConservationOverARunInAndOut) {
    // A 2 x 1 x 1 m box, permeable everywhere at 0.3, three nodes along x; lowered into the
    // water, turned, and lifted out again so that water enters, moves and leaves. At every
    // step: entered + initial = stored + left within 1e-9 relative, every node in bounds.
    const TriangleMesh box = makeBox({2.0, 1.0, 1.0});
    const SurfaceTextures t = test::bakeOrFail(box, 64);
    WaterGraph g;
    g.nodes = {node("stern", {-0.66, 0, 0}, 0.6, 0.1), node("mid", {0, 0, 0}, 0.6),
               node("bow", {0.66, 0, 0}, 0.6)};
    for (GraphNode& n : g.nodes) n.boxSize = {0.66, 1.0, 1.0};
    g.pipes = {pipe("stern", "mid", 0.03), pipe("mid", "bow", 0.03)};
    for (bool torricelli : {false, true}) {
        GraphSettings s;
        s.inflow = torricelli ? InflowModel::Torricelli : InflowModel::Linear;
        s.inflowRate = 0.8;
        s.freeSurface = torricelli;
        Result<WaterGraphSimulation> sim =
            WaterGraphSimulation::create(g, t, std::vector<double>(t.coveredCount(), 0.3), s);
        ASSERT_TRUE(sim.ok()) << sim.error().message;
        double worst = 0;
        const int steps = 1200;
        for (int i = 0; i < steps; ++i) {
            const double phase = double(i) / steps;
            // Down to 0.8 m under, then up to 2 m above, heeling and pitching.
            const double y = phase < 0.5 ? -0.8 * std::sin(phase * 2 * std::numbers::pi)
                                         : 2.0 * std::sin((phase - 0.5) * 2 * std::numbers::pi);
            const Pose pose = Pose::fromEulerDegrees(
                {0, y, 0}, {20 * std::sin(9 * phase), 0, 25 * std::sin(5 * phase)});
            sim->step(pose, WaterModel::flat(0.0), 0.0, 1.0 / 60.0);
            worst = std::max(worst, sim->conservationError());
            for (const GraphNode& n : sim->graph().nodes) {
                ASSERT_GE(n.water, 0.0);
                ASSERT_LE(n.water, n.capacity);
            }
        }
        const GraphTotals& tot = sim->totals();
        EXPECT_GT(tot.entered, 0.1);
        EXPECT_GT(tot.left, 0.1);
        EXPECT_GT(tot.moved, 0.0);
        EXPECT_LT(worst, 1e-9);
        std::printf(
            "  %s: entered %.6f m^3, left %.6f, stored %.6f, moved %.6f; worst "
            "conservation error %.2e\n",
            inflowModelName(s.inflow), tot.entered, tot.left, sim->storedWater(), tot.moved, worst);
    }
}

// --- mass properties -----------------------------------------------------------------------

TEST(GraphMass, PointMassesComposeByTheParallelAxisTheorem) {
    WaterGraph g;
    g.nodes = {node("a", {1, 0, 0}, 1.0, 0.2), node("b", {0, 2, -1}, 1.0, 0.5)};
    GraphSettings s;
    s.density = 1000;
    WaterGraphSimulation sim = simulationOf(g, s);
    const MassProperties w = sim.waterMassProperties(Eigen::Matrix3d::Identity());
    EXPECT_DOUBLE_EQ(w.mass, 700.0);  // eq. 15
    const Eigen::Vector3d c =
        (200.0 * Eigen::Vector3d(1, 0, 0) + 500.0 * Eigen::Vector3d(0, 2, -1)) / 700.0;
    EXPECT_NEAR((w.centerOfMass - c).norm(), 0.0, 1e-14);  // eq. 16
    // Eq. 17 about the origin, then moved to the centre of mass.
    Eigen::Matrix3d origin = Eigen::Matrix3d::Zero();
    for (const auto& [m, p] : {std::pair{200.0, Eigen::Vector3d(1, 0, 0)},
                               std::pair{500.0, Eigen::Vector3d(0, 2, -1)}}) {
        origin(0, 0) += m * (p.y() * p.y() + p.z() * p.z());
        origin(1, 1) += m * (p.x() * p.x() + p.z() * p.z());
        origin(2, 2) += m * (p.x() * p.x() + p.y() * p.y());
        origin(0, 1) -= m * p.x() * p.y();
        origin(1, 2) -= m * p.y() * p.z();
        origin(0, 2) -= m * p.x() * p.z();
    }
    origin(1, 0) = origin(0, 1), origin(2, 1) = origin(1, 2), origin(2, 0) = origin(0, 2);
    const Eigen::Matrix3d aboutC =
        origin - 700.0 * (c.squaredNorm() * Eigen::Matrix3d::Identity() - c * c.transpose());
    EXPECT_LT((w.inertia - aboutC).norm(), 1e-10 * aboutC.norm());

    // Composed with a solid body: total mass, weighted centre, and the same inertia as the
    // exact solid plus the point masses about the common centre.
    const MassProperties body = exactSolidMassProperties(makeBox({3, 1, 1}), 100.0);
    const MassProperties total = sim.compose(body, Eigen::Matrix3d::Identity());
    EXPECT_DOUBLE_EQ(total.mass, body.mass + 700.0);
    const Eigen::Vector3d ct = (body.mass * body.centerOfMass + 700.0 * c) / total.mass;
    EXPECT_LT((total.centerOfMass - ct).norm(), 1e-14);
    const Eigen::Vector3d d = body.centerOfMass - ct, e = c - ct;
    const Eigen::Matrix3d expected =
        body.inertia +
        body.mass * (d.squaredNorm() * Eigen::Matrix3d::Identity() - d * d.transpose()) + aboutC +
        700.0 * (e.squaredNorm() * Eigen::Matrix3d::Identity() - e * e.transpose());
    EXPECT_LT((total.inertia - expected).norm(), 1e-10 * expected.norm());
    EXPECT_DOUBLE_EQ(total.volume, body.volume);
}

TEST(GraphMass, FreeSurfaceWaterSitsAtTheLowestSide) {
    // Half-full sphere node: the cap's centroid is 3R/8 below the centre, along gravity,
    // whichever way the body is turned.
    WaterGraph g;
    g.nodes = {node("s", {1, 2, 3}, 1.0, 0.5)};
    GraphSettings s;
    s.freeSurface = true;
    WaterGraphSimulation sim = simulationOf(g, s);
    const double r = sphereRadius(1.0);
    for (double angle : {0.0, 0.4, 2.0}) {
        const Eigen::Matrix3d rot =
            Eigen::AngleAxisd(angle, Eigen::Vector3d(1, 0, 1).normalized()).toRotationMatrix();
        const MassProperties w = sim.waterMassProperties(rot);
        // World offset of the centroid from the node: straight down by 3R/8.
        const Eigen::Vector3d world = rot * (w.centerOfMass - Eigen::Vector3d(1, 2, 3));
        EXPECT_NEAR((world - Eigen::Vector3d(0, -3 * r / 8, 0)).norm(), 0.0, 1e-9) << angle;
    }
    // A box compartment 2 m wide, 1 m tall, 1 m long with 0.5 m^3 of water: upright, a
    // 0.25 m layer with its centroid 0.375 m below the centre; heeled 90 degrees about z, the
    // water lies along the box's +x or -x wall.
    WaterGraph b;
    b.nodes = {node("box", {0, 0, 0}, 2.0, 0.5)};
    b.nodes[0].boxSize = {2.0, 1.0, 1.0};
    WaterGraphSimulation boxSim = simulationOf(b, s);
    const MassProperties upright = boxSim.waterMassProperties(Eigen::Matrix3d::Identity());
    EXPECT_NEAR((upright.centerOfMass - Eigen::Vector3d(0, -0.375, 0)).norm(), 0.0, 1e-9);
    const Eigen::Matrix3d heeled =
        Eigen::AngleAxisd(std::numbers::pi / 2, Eigen::Vector3d::UnitZ()).toRotationMatrix();
    // World down is object +x... rot^T (0,-1,0) = object direction of gravity.
    const Eigen::Vector3d down = heeled.transpose() * Eigen::Vector3d(0, -1, 0);
    const MassProperties side = boxSim.waterMassProperties(heeled);
    // 0.5 m^3 against a 1 x 1 m wall: a 0.5 m layer, centroid 1 - 0.25 = 0.75 m from the centre.
    EXPECT_NEAR((side.centerOfMass - 0.75 * down).norm(), 0.0, 1e-9);
    // Without the model the water stays at the node.
    WaterGraphSimulation fixed = simulationOf(b);
    EXPECT_NEAR(fixed.waterMassProperties(heeled).centerOfMass.norm(), 0.0, 1e-15);
}

}  // namespace
}  // namespace test_graph
}  // namespace plimsoll
