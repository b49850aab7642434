// The water-graph exchange pass (kernels/graph.cl) on every OpenCL device against its C++
// reference (evaluateExchangeReference), on every water model, both rate laws, sample counts
// that are not multiples of the work-group size; and the damaged boat run end to end on the
// default device.
#include "plimsoll/bake/bake.h"
#include "plimsoll/compute/compute.h"
#include "plimsoll/graph/graph.h"
#include "plimsoll/project/project.h"
#include "plimsoll/samples/primitives.h"
#include "plimsoll/scene/world.h"

#include "cli_runner.h"
#include "test_support.h"
#include "world_support.h"

#include <Eigen/Geometry>
#include <nlohmann/json.hpp>

#include <cmath>
#include <limits>
#include <random>

namespace plimsoll {
namespace test_graph_kernels {
namespace {

std::vector<WaterModel> waterModels() {
    WaterModel waves;
    waves.kind = WaterModel::Kind::Gerstner;
    waves.level = 0.05;
    waves.waves = {{0.2, 5.0, {1.0, 0.3}, 0.6, 0.2}, {0.07, 1.9, {-0.4, 1.0}, 0.5, 1.1}};
    WaterModel grid;
    grid.kind = WaterModel::Kind::HeightField;
    grid.level = -0.1;
    grid.grid.countX = 23;
    grid.grid.countZ = 31;
    grid.grid.spacing = 0.3;
    grid.grid.origin = {-3.5, -4.5};
    for (int j = 0; j < grid.grid.countZ; ++j)
        for (int i = 0; i < grid.grid.countX; ++i)
            grid.grid.heights.push_back(0.15f * std::sin(0.7f * i) * std::cos(0.5f * j));
    return {WaterModel::flat(0.02), waves, grid};
}

TEST(GraphKernels, ExchangeMatchesTheReferenceOnEveryDevice) {
    // The hull's texels, a random share of them permeable, feeding 7 nodes.
    const SurfaceTextures t = test::bakeOrFail(makeHull(), 48);
    std::mt19937 random(7);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    std::vector<ExchangeSample> samples;
    for (std::size_t i = 0; i < t.coveredCount(); ++i) {
        if (unit(random) < 0.4) continue;
        samples.push_back(
            {t.position[i], unit(random) * t.area[i], static_cast<std::uint32_t>(random() % 7)});
    }
    ASSERT_NE(samples.size() % 128, 0u);  // not a multiple of the work-group size
    const double inf = std::numeric_limits<double>::infinity();
    const std::vector<std::unique_ptr<BuoyancyBackend>> devices = test::openClBackends();
    if (devices.empty()) GTEST_SKIP() << test::noOpenClDeviceReason();
    std::unique_ptr<BuoyancyBackend> reference = createReferenceBackend();
    const std::size_t refSet = reference->addExchangeSet(samples, 7);
    int cases = 0;
    double worst = 0, lattice = 0;
    for (const auto& device : devices) {
        const std::size_t set = device->addExchangeSet(samples, 7);
        for (const WaterModel& water : waterModels()) {
            for (bool torricelli : {false, true}) {
                for (const auto& [depth, roll] :
                     {std::pair{0.3, 0.0}, std::pair{-0.2, 25.0}, std::pair{1e5, 10.0}}) {
                    // A pose far away (1e5 m) keeps its digits: positions go relative.
                    const Pose pose = Pose::fromEulerDegrees(
                        {depth > 1e4 ? 1e5 : 0.3, depth > 1e4 ? -0.1 : -depth,
                         depth > 1e4 ? -1e5 : 0.2},
                        {4.0, 30.0, roll});
                    const std::vector<double> surface = {
                        pose.translation.y() - 0.2,  -inf, pose.translation.y() + 0.1, -inf,
                        pose.translation.y() - 0.45, -inf, pose.translation.y()};
                    ExchangeFrame frame;
                    frame.pose = pose;
                    frame.time = 1.7;
                    frame.nodeSurface = surface;
                    frame.torricelli = torricelli;
                    frame.factor = torricelli ? 0.6 * std::sqrt(2 * 9.81) : 0.8;
                    ExchangeSums expected, got, viaBackend;
                    evaluateExchangeReference(samples, 7, frame, water, expected);
                    ASSERT_TRUE(reference->evaluateExchange(refSet, frame, water, viaBackend).ok());
                    EXPECT_EQ(viaBackend.inflow, expected.inflow);
                    ASSERT_TRUE(device->evaluateExchange(set, frame, water, got).ok());
                    // Scale: all the flow of the pass.
                    double scale = 0;
                    for (std::size_t n = 0; n < 7; ++n)
                        scale += expected.inflow[n] + expected.outflow[n];
                    ASSERT_GT(scale, 0.0);
                    for (std::size_t n = 0; n < 7; ++n) {
                        const double e = std::max(std::abs(got.inflow[n] - expected.inflow[n]),
                                                  std::abs(got.outflow[n] - expected.outflow[n])) /
                                         scale;
                        worst = std::max(worst, e);
                        EXPECT_LT(e, 2e-4) << device->deviceName() << " node " << n;
                        if (expected.inflow[n] > 1e-3 * scale) {
                            EXPECT_NEAR(got.outsideTop[n], expected.outsideTop[n], 2e-3)
                                << device->deviceName();
                        }
                    }
                    // What the lattice moves (the pass with the water's own height at every
                    // sample): the devices must follow the lattice far closer than that.
                    ExchangeSums pointwise;
                    evaluateExchangePointwise(samples, 7, frame, water, pointwise);
                    for (std::size_t n = 0; n < 7; ++n) {
                        lattice = std::max(
                            lattice,
                            std::max(std::abs(pointwise.inflow[n] - expected.inflow[n]),
                                     std::abs(pointwise.outflow[n] - expected.outflow[n])) /
                                scale);
                    }
                    ++cases;
                }
            }
        }
    }
    std::printf(
        "  %zu samples, 7 nodes, %d cases: worst per-node error %.2e of the pass's flow "
        "(the lattice against the water at every sample: %.2e)\n",
        samples.size(), cases, worst, lattice);
    EXPECT_GT(lattice, 100.0 * worst);
}

TEST(GraphKernels, DamagedBoatSinksOnTheDefaultDevice) {
    // The sample project through `plimsoll simulate` (the default device: OpenCL where there
    // is one, so the exchange runs in the kernel): deep under after 30 s.
    const std::filesystem::path project =
        std::filesystem::path(PLIMSOLL_SOURCE_DIR) / "projects" / "damaged_boat.plim.json";
    const test::CommandOutput r =
        test::runPlimsoll("simulate '" + project.string() + "' --seconds 30 --json");
    ASSERT_EQ(r.exitCode, 0) << r.err;
    const nlohmann::json j = nlohmann::json::parse(r.out);
    EXPECT_LT(j.at("position").at(1).get<double>(), -1.0) << r.out;
}

TEST(GraphKernels, AHullSealedEverywhereBuildsAndStepsOnEveryDevice) {
    // The damaged boat without its damage map: permeability 0 everywhere and no openings, so
    // its graph has no permeable sample. Such a world once failed to build on PoCL's CPU device
    // (clCreateBuffer: a copy from an empty vector's null data).
    const std::vector<std::unique_ptr<BuoyancyBackend>> probe = test::openClBackends();
    if (probe.empty()) GTEST_SKIP() << test::noOpenClDeviceReason();
    const std::filesystem::path source = std::filesystem::path(PLIMSOLL_SOURCE_DIR) / "projects";
    Result<Project> project = loadProject(source / "damaged_boat.plim.json");
    ASSERT_TRUE(project.ok()) << project.error().message;
    project->bodies.at(0).permeabilityMap.clear();
    // The empty set on its own: no flow in or out, and no error.
    for (const std::unique_ptr<BuoyancyBackend>& backend : probe) {
        const std::size_t set = backend->addExchangeSet({}, 4);
        const std::vector<double> surfaces(4, 0.0);
        ExchangeFrame frame;
        frame.nodeSurface = surfaces;
        ExchangeSums sums;
        ASSERT_TRUE(backend->evaluateExchange(set, frame, WaterModel::flat(0), sums).ok())
            << backend->deviceName();
        EXPECT_EQ(sums.inflow, std::vector<double>(4, 0.0));
        EXPECT_EQ(sums.outflow, std::vector<double>(4, 0.0));
    }
    for (const ComputeDevice& device : listComputeDevices()) {
        Result<std::unique_ptr<BuoyancyBackend>> backend =
            createBuoyancyBackend(std::to_string(device.index));
        ASSERT_TRUE(backend.ok()) << backend.error().message;
        Result<std::unique_ptr<World>> world =
            World::create(test::sceneOrFail(*project), std::move(*backend));
        ASSERT_TRUE(world.ok()) << device.name << ": " << world.error().message;
        for (int i = 0; i < 30; ++i) ASSERT_TRUE((*world)->advanceFrame().ok()) << device.name;
        ASSERT_NE((*world)->waterGraph(0), nullptr);
        EXPECT_EQ((*world)->waterGraph(0)->graph().totalWater(), 0.0) << device.name;
    }
}

}  // namespace
}  // namespace test_graph_kernels
}  // namespace plimsoll
