// The runtime library (engine/runtime, docs/bundle.md "Runtime library") against the engine:
// every sample project's bundles are exported with writeBodyBundle and loaded with the
// runtime. Both compile the same evaluation core (plimsoll_eval), so for 200 random poses per
// bundle (random rotations, positions around the waterline, random velocities, flat water and
// Gerstner waves) the runtime's forces must equal the engine's fast CPU path over the same
// sample list (readBakedTextures of the bundle) bit for bit; how close that path is to the
// double-precision reference is tests/eval/test_fast_path.cpp's business. A
// water-graph run (damaged_boat) must give the engine's WaterGraphSimulation's water, node by
// node.
#include "test_support.h"

#include "plimsoll/bake/bake.h"
#include "plimsoll/io/painted_map_io.h"
#include "plimsoll/io/graph_json.h"
#include "plimsoll/compute/fast_backend.h"
#include "plimsoll/io/bake_io.h"
#include "plimsoll/export/bundle.h"
#include "plimsoll/physics/buoyancy.h"
#include "plimsoll/graph/graph.h"
#include "plimsoll/surface/painted_map.h"
#include "plimsoll/project/project.h"

#include "plimsoll_eval/graph.hpp"
#include "plimsoll_runtime.h"
#include "plimsoll_runtime/runtime.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <Eigen/Geometry>
#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfOutputFile.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <random>
#include <unistd.h>

namespace plimsoll {
namespace test_runtime_conformance {
namespace {

namespace fs = std::filesystem;
namespace rt = plimsoll_runtime;

/// A private copy of a sample project (projects/ and assets/), so an atlas cache stays here.
fs::path copyProjects(const std::string& name) {
    const fs::path root = test::scratchFolder("runtime_" + name);
    fs::remove_all(root);
    fs::create_directories(root);
    const fs::path source = fs::path(PLIMSOLL_SOURCE_DIR);
    fs::copy(source / "assets", root / "assets", fs::copy_options::recursive);
    fs::copy(source / "projects", root / "projects", fs::copy_options::recursive);
    return root;
}

WaterModel wavyWater() {
    WaterModel water;
    water.kind = WaterModel::Kind::Gerstner;
    water.level = 0.0;
    GerstnerWave a;
    a.amplitude = 0.12;
    a.wavelength = 7.0;
    a.direction = {1.0, 0.3};
    a.steepness = 0.4;
    GerstnerWave b;
    b.amplitude = 0.05;
    b.wavelength = 2.5;
    b.direction = {-0.2, 1.0};
    b.steepness = 0.3;
    b.phase = 0.7;
    water.waves = {a, b};
    return water;
}

rt::Water runtimeWater(const WaterModel& water) {
    rt::Water w;
    w.level = water.level;
    w.height = [&water](double x, double z, double t) { return water.height(x, z, t); };
    w.velocity = [&water](const rt::Vec3& p, double t) {
        const Eigen::Vector3d v = water.velocity({p.x, p.y, p.z}, t);
        return rt::Vec3{v.x(), v.y(), v.z()};
    };
    // The batched queries the engine's fast path makes (WaterModel::heights, ::velocities):
    // the same water to the bit on both sides.
    w.heights = [&water](std::size_t n, const double* x, const double* z, double t, double* out) {
        water.heights(n, x, z, t, out);
    };
    w.velocities = [&water](std::size_t n, const double* x, const double* y, const double* z,
                            double t, double* out) { water.velocities(n, x, y, z, t, out); };
    return w;
}

Eigen::Vector3d eig(const rt::Vec3& v) { return {v.x, v.y, v.z}; }

struct Exported {
    std::string label;
    fs::path folder;
    const BodyDesc* desc;
    const Project* project;
};

/// Every body of every sample project, exported once for the whole suite.
class RuntimeConformance : public testing::Test {
protected:
    static void SetUpTestSuite() {
        // One folder per process: ctest runs each test of the suite in its own process, in
        // parallel, and every one exports (and at the end removes) its own bundles.
        root_ = new fs::path(copyProjects("conformance-" + std::to_string(::getpid())));
        projects_ = new std::vector<std::unique_ptr<Project>>();
        bundles_ = new std::vector<Exported>();
        std::vector<fs::path> files;
        for (const auto& entry : fs::directory_iterator(*root_ / "projects")) {
            const std::string name = entry.path().filename().string();
            if (name.size() > 10 && name.substr(name.size() - 10) == ".plim.json")
                files.push_back(entry.path());
        }
        std::sort(files.begin(), files.end());
        for (const fs::path& file : files) {
            Result<Project> project = loadProject(file);
            ASSERT_TRUE(project.ok()) << project.error().message;
            projects_->push_back(std::make_unique<Project>(std::move(*project)));
            const Project& p = *projects_->back();
            for (std::size_t i = 0; i < p.bodies.size(); ++i) {
                const fs::path folder = *root_ / "out" / p.fileStem / bundleFolderName(p, i);
                Result<BundleReport> report = writeBodyBundle(p, i, folder);
                ASSERT_TRUE(report.ok()) << file << ": " << report.error().message;
                bundles_->push_back(
                    {p.fileStem + "/" + p.bodies[i].name, folder, &p.bodies[i], &p});
            }
        }
    }
    static void TearDownTestSuite() {
        delete bundles_;
        delete projects_;
        fs::remove_all(*root_);
        fs::remove_all(test::scratchFolder("runtime_bad-" + std::to_string(::getpid())));
        delete root_;
    }
    static fs::path* root_;
    static std::vector<std::unique_ptr<Project>>* projects_;
    static std::vector<Exported>* bundles_;
};

fs::path* RuntimeConformance::root_ = nullptr;
std::vector<std::unique_ptr<Project>>* RuntimeConformance::projects_ = nullptr;
std::vector<Exported>* RuntimeConformance::bundles_ = nullptr;

TEST_F(RuntimeConformance, ForcesEqualTheEngineBitForBit) {
    const std::vector<std::string> required = {"buoy", "box_half_draft", "damaged_boat",
                                               "heavy_side_ball"};
    for (const std::string& stem : required) {
        EXPECT_TRUE(std::any_of(bundles_->begin(), bundles_->end(), [&](const Exported& e) {
            return e.label.rfind(stem + "/", 0) == 0;
        })) << stem;
    }
    const WaterModel waves = wavyWater();
    for (const Exported& e : *bundles_) {
        SCOPED_TRACE(e.label);
        std::string error;
        std::unique_ptr<rt::Bundle> bundle = rt::loadBundle(e.folder.string(), error);
        ASSERT_TRUE(bundle) << error;
        Result<SurfaceTextures> textures = readBakedTextures(e.folder);
        ASSERT_TRUE(textures.ok()) << textures.error().message;
        ASSERT_EQ(bundle->samples().size(), textures->coveredCount());
        // The manifest's hydrodynamics and mass as the runtime read them.
        EXPECT_EQ(bundle->fluid().dragCoefficient, e.desc->dragCoefficient);
        EXPECT_EQ(bundle->fluid().frictionCoefficient, e.desc->frictionCoefficient);
        const bool radiates = bundle->radiation() != nullptr;
        EXPECT_EQ(bundle->linearDamping(), e.desc->standInLinearDamping(radiates));
        EXPECT_EQ(bundle->verticalDamping(), e.desc->standInVerticalDamping(radiates));
        EXPECT_EQ(bundle->angularDamping(), e.desc->standInAngularDamping(radiates));
        const nlohmann::json manifest =
            nlohmann::json::parse(test::readFile(e.folder / "manifest.json"));
        const nlohmann::json& mass = manifest["mass_properties"]["texture"];
        EXPECT_EQ(bundle->mass().mass, mass["mass"].get<double>());
        const Eigen::Vector3d com(mass["center_of_mass"][0].get<double>(),
                                  mass["center_of_mass"][1].get<double>(),
                                  mass["center_of_mass"][2].get<double>());
        double reach = 0;
        for (const Eigen::Vector3d& p : textures->position)
            reach = std::max(reach, (p - com).norm());
        // The engine's CPU evaluation of the same entries.
        const plimsoll_eval::FastBody engine = makeFastBody(*textures, com);
        plimsoll_eval::FastScratch scratch;

        FluidSettings fluid;
        fluid.density = e.project->medium.density;
        fluid.gravity = 9.81;
        fluid.dragCoefficient = e.desc->dragCoefficient;
        fluid.frictionCoefficient = 0.01;  // friction on, so its branch is compared too
        rt::Fluid rtFluid;
        rtFluid.density = fluid.density;
        rtFluid.gravity = fluid.gravity;
        rtFluid.dragCoefficient = fluid.dragCoefficient;
        rtFluid.frictionCoefficient = fluid.frictionCoefficient;

        std::mt19937_64 rng(20261123);
        std::normal_distribution<double> normal;
        std::uniform_real_distribution<double> uniform(-1.0, 1.0);
        int wetPoses = 0;
        for (int k = 0; k < 200; ++k) {
            // Half on flat water, half on waves; every third pose without friction, so that
            // the closed-form drag of submerged tiles is compared too.
            const WaterModel water = k % 2 ? waves : WaterModel::flat(0.1 * uniform(rng));
            rt::Water rtWater = runtimeWater(water);
            if (water.kind == WaterModel::Kind::Flat)
                rtWater.height = nullptr, rtWater.velocity = nullptr, rtWater.heights = nullptr,
                rtWater.velocities = nullptr;
            rtWater.minHeight = water.minHeight();
            rtWater.maxHeight = water.maxHeight();
            fluid.frictionCoefficient = rtFluid.frictionCoefficient = k % 3 ? 0.01 : 0.0;
            Eigen::Quaterniond q(normal(rng), normal(rng), normal(rng), normal(rng));
            q.normalize();
            const Eigen::Vector3d centre(2.0 * uniform(rng), 0.9 * reach * uniform(rng),
                                         2.0 * uniform(rng));
            const Eigen::Matrix3d R = q.toRotationMatrix();
            BodyFrame frame;
            frame.pose.rotation = R;
            frame.pose.translation = centre - R * com;
            frame.centerOfMass = com;
            frame.motion.linear = Eigen::Vector3d(normal(rng), normal(rng), normal(rng));
            frame.motion.angular = k % 5 ? Eigen::Vector3d(normal(rng), normal(rng), normal(rng))
                                         : Eigen::Vector3d::Zero();
            frame.time = 10.0 * (uniform(rng) + 1.0);
            const BuoyancyResult ref = evaluateBuoyancyFast(engine, frame, water, fluid, scratch);

            rt::Pose pose;
            pose.position = {frame.pose.translation.x(), frame.pose.translation.y(),
                             frame.pose.translation.z()};
            pose.orientation = {q.w(), q.x(), q.y(), q.z()};
            rt::Velocity velocity;
            velocity.linear = {frame.motion.linear.x(), frame.motion.linear.y(),
                               frame.motion.linear.z()};
            velocity.angular = {frame.motion.angular.x(), frame.motion.angular.y(),
                                frame.motion.angular.z()};
            const rt::Forces got = bundle->evaluate(pose, velocity, rtWater, rtFluid, frame.time);
            EXPECT_EQ(got.submergedVolume, ref.submergedVolume) << k;
            EXPECT_EQ(eig(got.centerOfBuoyancy), ref.centerOfBuoyancy) << k;
            EXPECT_EQ(eig(got.force), ref.force) << k;
            EXPECT_EQ(eig(got.torque), ref.torque) << k;
            EXPECT_EQ(eig(got.pressureForce), ref.pressureForce) << k;
            EXPECT_EQ(eig(got.pressureTorque), ref.pressureTorque) << k;
            EXPECT_EQ(eig(got.dragForce), ref.dragForce) << k;
            EXPECT_EQ(eig(got.dragTorque), ref.dragTorque) << k;
            EXPECT_EQ(got.wettedArea, ref.wettedArea) << k;
            EXPECT_EQ(got.submergedSamples, ref.submergedSamples) << k;
            wetPoses += ref.submergedVolume > 0;
            if (k % 10 == 1) {
                // One point per call gives the same heights and velocities as the batches, so
                // the same forces.
                rt::Water single = rtWater;
                single.heights = nullptr;
                single.velocities = nullptr;
                if (water.kind != WaterModel::Kind::Flat) {
                    single.height = [&water](double x, double z, double t) {
                        double out = 0;
                        water.heights(1, &x, &z, t, &out);
                        return out;
                    };
                    single.velocity = [&water](const rt::Vec3& p, double t) {
                        double out[3];
                        water.velocities(1, &p.x, &p.y, &p.z, t, out);
                        return rt::Vec3{out[0], out[1], out[2]};
                    };
                }
                const rt::Forces again =
                    bundle->evaluate(pose, velocity, single, rtFluid, frame.time);
                EXPECT_EQ(again.submergedVolume, got.submergedVolume) << k;
                EXPECT_EQ(eig(again.dragTorque), eig(got.dragTorque)) << k;
            }
        }
        // The poses must exercise the water: most wet, some dry.
        EXPECT_GT(wetPoses, 60);
        EXPECT_LT(wetPoses, 200);
    }
}

TEST_F(RuntimeConformance, WaterGraphStepsEqualTheEngine) {
    const auto it = std::find_if(bundles_->begin(), bundles_->end(), [](const Exported& e) {
        return e.label.rfind("damaged_boat/", 0) == 0;
    });
    ASSERT_NE(it, bundles_->end());
    const Exported& e = *it;
    std::string error;
    std::unique_ptr<rt::Bundle> bundle = rt::loadBundle(e.folder.string(), error);
    ASSERT_TRUE(bundle) << error;
    ASSERT_NE(bundle->graph(), nullptr);
    rt::Body body(*bundle);
    rt::WaterGraph* graph = body.graph();
    ASSERT_NE(graph, nullptr);

    // The engine's simulation from the same files.
    Result<SurfaceTextures> textures = readBakedTextures(e.folder);
    ASSERT_TRUE(textures.ok());
    Result<WaterGraph> engineGraph = loadGraph(e.folder / "graph.json");
    ASSERT_TRUE(engineGraph.ok()) << engineGraph.error().message;
    Result<PaintedMap> map = loadPaintedMap(e.folder / "permeability.png");
    ASSERT_TRUE(map.ok()) << map.error().message;
    const WaterGraphDesc& g = *e.desc->waterGraph;
    GraphSettings settings = g.settings;
    settings.density = e.project->medium.density;
    settings.viscosity = e.project->medium.viscosity;
    settings.gravity = 9.81;
    Result<WaterGraphSimulation> sim = WaterGraphSimulation::create(
        *engineGraph, *textures, sampleAtTexels(*map, *textures, g.permeability), settings);
    ASSERT_TRUE(sim.ok()) << sim.error().message;
    graph->setMedium(settings.density, settings.viscosity, settings.gravity);

    // The same texel-to-node map and permeable samples.
    const std::vector<std::int32_t> nodes = texelNodeMap(*engineGraph, *textures);
    ASSERT_EQ(graph->layout().sampleNodes().size(), nodes.size());
    for (std::size_t i = 0; i < nodes.size(); ++i)
        ASSERT_EQ(graph->layout().sampleNodes()[i], nodes[i]) << i;
    ASSERT_EQ(graph->layout().permeableSamples(), sim->samples().size());
    // Bundle 1.1 carries texel_nodes.exr: the map above came from it.
    EXPECT_TRUE(bundle->texelNodesFromFile());
    ASSERT_GT(graph->layout().permeableSamples(), 0u);

    // Flooding by the stern on waves, trimmed and heeled, with water already in the stern and
    // the fore hold so the flow between nodes runs from the start.
    sim->setWater(0, 1.0);
    graph->setWater(0, 1.0);
    sim->setWater(2, 0.4);
    graph->setWater(2, 0.4);
    const WaterModel water = wavyWater();
    const rt::Water rtWater = runtimeWater(water);
    const double capacity = engineGraph->totalCapacity();
    double worstInflow = 0, worstWater = 0;
    // The lattice's error in the exchange (against the pass with the water's own height at
    // every sample). Its outside surface misses the water's by at most
    // delta = s^2 / 8 (max |f_xx| + max |f_zz|) (bilinear interpolation on cells of side s), and
    // the outside depth max(0, f - y) moves by no more than f does, so a linear pass's net
    // flux into a node moves by at most factor w delta per sample, and only at samples below
    // f + delta (above, both surfaces leave them dry); Torricelli's by factor w sqrt(2 delta).
    // The curvature is the waves' own, taken by second differences at random places over and
    // about the boat (6 m along z) in the run's 15 s, with a quarter more for the peaks the
    // draws miss; it comes to 0.59 /m, the sum of the two crests' a k^2 / (1 - Q k a)^2 (Q k a
    // the steepness over the two waves), so delta is 5.8 mm.
    double curvature = 0;
    {
        std::mt19937_64 draws(11);
        std::uniform_real_distribution<double> across(-8.0, 8.0), when(0.0, 15.0);
        const double h = 1e-3;
        for (int k = 0; k < 20000; ++k) {
            const double x = across(draws), z = 0.5 * across(draws), t = when(draws);
            const double f = water.height(x, z, t);
            const double fxx =
                (water.height(x + h, z, t) - 2 * f + water.height(x - h, z, t)) / (h * h);
            const double fzz =
                (water.height(x, z + h, t) - 2 * f + water.height(x, z - h, t)) / (h * h);
            curvature = std::max(curvature, std::abs(fxx) + std::abs(fzz));
        }
    }
    const double spacing = plimsoll_eval::kExchangeLatticeSpacing;
    const double delta = 1.25 * spacing * spacing / 8.0 * curvature;
    double latticeShare = 0, latticeSum = 0, stepSum = 0, flowSum = 0, boundUse = 0;
    const double dt = 1.0 / 60.0;
    // 15 s; 5 s in the sanitized build (about fifteen times slower there): the same code, a
    // third of the poses.
    const int steps = test::kSanitizedBuild ? 300 : 900;
    for (int step = 0; step < steps; ++step) {
        const double t = step * dt;
        const Eigen::Quaterniond q =
            Eigen::AngleAxisd(0.06 * std::sin(0.7 * t), Eigen::Vector3d::UnitZ()) *
            Eigen::AngleAxisd(-0.08 + 0.02 * std::sin(0.3 * t), Eigen::Vector3d::UnitX());
        Pose pose;
        pose.rotation = q.toRotationMatrix();
        pose.translation = Eigen::Vector3d(0.0, -0.25 + 0.05 * std::sin(0.5 * t), 0.0);
        rt::Pose rtPose;
        rtPose.position = {pose.translation.x(), pose.translation.y(), pose.translation.z()};
        rtPose.orientation = {q.w(), q.x(), q.y(), q.z()};

        // Inflow per node at this pose.
        ExchangeSums sums;
        const ExchangeFrame frame = sim->exchangeFrame(pose, t);
        evaluateExchangeReference(sim->samples(), engineGraph->nodes.size(), frame, water, sums);
        const rt::NodeInflow in = graph->inflow(rtPose, rtWater, t);
        double scale = 1e-12;
        for (double v : sums.inflow) scale = std::max(scale, v);
        for (double v : sums.outflow) scale = std::max(scale, v);
        for (std::size_t n = 0; n < sums.inflow.size(); ++n) {
            worstInflow = std::max({worstInflow, std::abs(in.inflow[n] - sums.inflow[n]) / scale,
                                    std::abs(in.outflow[n] - sums.outflow[n]) / scale});
        }
        // The lattice's error: the pass against the water's height at every sample, net per
        // node, as a share of the pass's whole flow; and the step's own (the flux held over
        // dt: half its change to the next step's water and pose, at this step's nodes).
        ExchangeSums pointwise, next;
        evaluateExchangePointwise(sim->samples(), engineGraph->nodes.size(), frame, water,
                                  pointwise);
        ExchangeFrame later = frame;
        later.time = t + dt;
        later.pose.rotation =
            (Eigen::AngleAxisd(0.06 * std::sin(0.7 * (t + dt)), Eigen::Vector3d::UnitZ()) *
             Eigen::AngleAxisd(-0.08 + 0.02 * std::sin(0.3 * (t + dt)), Eigen::Vector3d::UnitX()))
                .toRotationMatrix();
        later.pose.translation = Eigen::Vector3d(0.0, -0.25 + 0.05 * std::sin(0.5 * (t + dt)), 0.0);
        evaluateExchangePointwise(sim->samples(), engineGraph->nodes.size(), later, water, next);
        double flow = 0, latticeMiss = 0, stepChange = 0;
        for (std::size_t n = 0; n < sums.inflow.size(); ++n) {
            flow += pointwise.inflow[n] + pointwise.outflow[n];
            const double net = pointwise.inflow[n] - pointwise.outflow[n];
            latticeMiss += std::abs((sums.inflow[n] - sums.outflow[n]) - net);
            stepChange += 0.5 * std::abs((next.inflow[n] - next.outflow[n]) - net);
        }
        double bound = 0;
        for (const ExchangeSample& s : sim->samples()) {
            const Eigen::Vector3d p = frame.pose.apply(s.position);
            if (p.y() < water.height(p.x(), p.z(), t) + delta)
                bound +=
                    frame.factor * s.weight * (frame.torricelli ? std::sqrt(2.0 * delta) : delta);
        }
        EXPECT_LE(latticeMiss, bound) << "step " << step;
        if (bound > 0) boundUse = std::max(boundUse, latticeMiss / bound);
        if (flow > 0) latticeShare = std::max(latticeShare, latticeMiss / flow);
        latticeSum += latticeMiss;
        stepSum += stepChange;
        flowSum += flow;

        sim->step(pose, water, t, dt);
        graph->step(rtPose, rtWater, t, dt);
        for (std::size_t n = 0; n < engineGraph->nodes.size(); ++n) {
            worstWater = std::max(
                worstWater, std::abs(graph->water(n) - sim->graph().nodes[n].water) / capacity);
        }
    }
    // The run must have moved water: entered through the stern and spread.
    EXPECT_GT(sim->totals().entered, 0.1);
    EXPECT_GT(sim->totals().moved, 0.1);
    EXPECT_NEAR(graph->entered(), sim->totals().entered, 1e-6 * capacity);
    EXPECT_NEAR(graph->left(), sim->totals().left, 1e-6 * capacity);
    std::printf(
        "  water graph (damaged_boat, %d steps): max inflow diff %.2e, max water diff "
        "%.2e of capacity; entered %.4f m^3, moved %.4f m^3\n",
        steps, worstInflow, worstWater, sim->totals().entered, sim->totals().moved);
    EXPECT_LE(worstInflow, 1e-6);
    EXPECT_LE(worstWater, 1e-6);
    std::printf(
        "  exchange on the lattice against the water at every sample (delta %.2e m): net flux "
        "error %.2e of the flow on the run (%.2e at worst in a step, %.2f of its bound); the "
        "step's own (half the flux's change over a step) %.2e\n",
        delta, latticeSum / flowSum, latticeShare, boundUse, stepSum / flowSum);
    // The flow is held over each step as it was at its start, which misses by about half its
    // change over the step: the lattice must add less than that error the step already makes.
    EXPECT_LE(latticeSum, stepSum);

    // The water's mass properties.
    const Eigen::Matrix3d R = Eigen::AngleAxisd(0.2, Eigen::Vector3d::UnitX()).toRotationMatrix();
    const Eigen::Quaterniond q(Eigen::AngleAxisd(0.2, Eigen::Vector3d::UnitX()));
    const MassProperties ref = sim->waterMassProperties(R);
    const rt::MassProperties got = graph->waterMass({q.w(), q.x(), q.y(), q.z()});
    // The mass is the density times the water held, so the two differ by at most the density
    // times the nodes' differences in water (held above to 1e-6 of the capacity each), and by
    // rounding where those are zero.
    double waterDifference = 0;
    for (std::size_t n = 0; n < engineGraph->nodes.size(); ++n)
        waterDifference += std::abs(graph->water(n) - sim->graph().nodes[n].water);
    EXPECT_NEAR(got.mass, ref.mass, settings.density * waterDifference + 1e-12 * ref.mass);
    EXPECT_LE((eig(got.centerOfMass) - ref.centerOfMass).norm(), 1e-6);
}

// The C API gives the C++ API's numbers and reports errors as strings.
TEST_F(RuntimeConformance, CApiMatchesAndReportsErrors) {
    const Exported& e = bundles_->front();
    plimsoll_bundle* b = plimsoll_bundle_load(e.folder.string().c_str(), 1);
    ASSERT_NE(b, nullptr) << plimsoll_runtime_last_error();
    std::string error;
    auto bundle = rt::loadBundle(e.folder.string(), error);
    ASSERT_TRUE(bundle);
    const plimsoll_pose pose = {{0.1, -0.05, 0.2},
                                {0.9238795325112867, 0.0, 0.0, 0.3826834323650898}};
    const plimsoll_velocity velocity = {{0.3, -0.2, 0.1}, {0.0, 0.5, 0.1}};
    const plimsoll_water water = {0.02, nullptr, nullptr, nullptr};
    const plimsoll_fluid fluid = plimsoll_bundle_default_fluid(b);
    plimsoll_forces f;
    ASSERT_EQ(plimsoll_bundle_evaluate(b, &pose, &velocity, &water, &fluid, 0.0, &f), 1);
    rt::Pose p{{0.1, -0.05, 0.2}, {0.9238795325112867, 0.0, 0.0, 0.3826834323650898}};
    rt::Water w;
    w.level = 0.02;
    const rt::Forces ref =
        bundle->evaluate(p, {{0.3, -0.2, 0.1}, {0.0, 0.5, 0.1}}, w, bundle->fluid());
    EXPECT_GT(ref.submergedVolume, 0);
    EXPECT_EQ(f.submerged_volume, ref.submergedVolume);
    EXPECT_EQ(f.force[1], ref.force.y);
    EXPECT_EQ(f.drag_force[0], ref.dragForce.x);
    EXPECT_EQ(f.torque[2], ref.torque.z);
    plimsoll_bundle_free(b);

    EXPECT_EQ(plimsoll_bundle_load((e.folder / "nowhere").string().c_str(), 1), nullptr);
    EXPECT_NE(std::string(plimsoll_runtime_last_error()).find("manifest.json: missing"),
              std::string::npos)
        << plimsoll_runtime_last_error();
    EXPECT_EQ(plimsoll_bundle_load(nullptr, 1), nullptr);
    EXPECT_EQ(plimsoll_bundle_evaluate(nullptr, &pose, &velocity, &water, &fluid, 0.0, &f), 0);
}

/// A copy of a bundle to damage.
fs::path copyBundle(const fs::path& from, const std::string& name) {
    const fs::path to = test::scratchFolder("runtime_bad-" + std::to_string(::getpid())) / name;
    fs::remove_all(to);
    fs::copy(from, to, fs::copy_options::recursive);
    return to;
}

void replaceInFile(const fs::path& path, const std::string& from, const std::string& to) {
    std::string text = test::readFile(path);
    const std::size_t at = text.find(from);
    ASSERT_NE(at, std::string::npos) << from;
    text.replace(at, from.size(), to);
    std::ofstream(path, std::ios::binary | std::ios::trunc) << text;
}

std::string loadError(const fs::path& folder, bool verify = true) {
    std::string error;
    rt::LoadOptions options;
    options.verifyChecksums = verify;
    EXPECT_FALSE(rt::loadBundle(folder.string(), error, options)) << folder;
    return error;
}

TEST_F(RuntimeConformance, BadBundlesGiveClearErrors) {
    const fs::path good = bundles_->front().folder;
    {
        const fs::path b = copyBundle(good, "newer_major");
        replaceInFile(b / "manifest.json", "\"schema_version\": 1", "\"schema_version\": 2");
        const std::string error = loadError(b);
        EXPECT_NE(error.find("bundle schema 2."), std::string::npos) << error;
        EXPECT_NE(error.find("is newer than this reader's 1.x"), std::string::npos) << error;
    }
    {
        const fs::path b = copyBundle(good, "newer_minor");  // a newer minor only adds: read
        replaceInFile(b / "manifest.json", "\"schema_minor\": ",
                      "\"an_unknown_field\": [1, {\"x\": null}],\n  \"schema_minor\": 7");
        std::string error;
        EXPECT_TRUE(rt::loadBundle(b.string(), error)) << error;
    }
    {
        const fs::path b = copyBundle(good, "missing_file");
        fs::remove(b / "area.exr");
        const std::string error = loadError(b);
        EXPECT_NE(error.find("area.exr: missing"), std::string::npos) << error;
    }
    {
        const fs::path b = copyBundle(good, "wrong_checksum");
        std::string bytes = test::readFile(b / "coverage.exr");
        bytes[bytes.size() - 3] ^= 0x55;
        std::ofstream(b / "coverage.exr", std::ios::binary | std::ios::trunc) << bytes;
        const std::string error = loadError(b);
        EXPECT_NE(error.find("coverage.exr: SHA-256 "), std::string::npos) << error;
        EXPECT_NE(error.find("does not match the manifest's"), std::string::npos) << error;
    }
    {
        const fs::path b = copyBundle(good, "truncated_exr");
        const std::string bytes = test::readFile(b / "samples.exr");
        std::ofstream(b / "samples.exr", std::ios::binary | std::ios::trunc)
            << bytes.substr(0, bytes.size() / 2);
        std::string error = loadError(b);
        EXPECT_NE(error.find("samples.exr: " + std::to_string(bytes.size() / 2) +
                             " bytes, the manifest says"),
                  std::string::npos)
            << error;
        // Without checksums the EXR reader itself must refuse it.
        error = loadError(b, false);
        EXPECT_NE(error.find("samples.exr: cannot read EXR"), std::string::npos) << error;
    }
    {
        const fs::path b = copyBundle(good, "not_json");
        replaceInFile(b / "manifest.json", "\"format\"", "\"format\" ,");
        const std::string error = loadError(b);
        EXPECT_NE(error.find("manifest.json: malformed manifest: line "), std::string::npos)
            << error;
    }
    {
        const fs::path b = copyBundle(good, "escaping_path");
        replaceInFile(b / "manifest.json", "\"path\": \"area.exr\"", "\"path\": \"../area.exr\"");
        const std::string error = loadError(b);
        EXPECT_NE(error.find("leaves the bundle"), std::string::npos) << error;
    }
}

// The runtime's SHA-256 against OpenSSL's (the engine's sha256Hex) across the padding cases.
TEST(RuntimeSha256, MatchesOpenSsl) {
    EXPECT_EQ(rt::sha256Hex("abc", 3),
              "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad");
    std::mt19937 rng(7);
    std::string data;
    for (std::size_t n = 0; n < 300; ++n) {
        EXPECT_EQ(rt::sha256Hex(data.data(), data.size()), sha256Hex(data)) << n;
        data += static_cast<char>(rng() & 0xFF);
    }
}

}  // namespace
}  // namespace test_runtime_conformance
}  // namespace plimsoll

namespace plimsoll {
namespace test_runtime_conformance {
namespace {

/// Writes `folder`/texel_nodes.exr as docs/bundle.md describes it (one UINT channel `node`,
/// N x N, 1 + node index for covered texels, row 0 = top) and lists it in the manifest.
void addTexelNodes(const fs::path& folder, const std::vector<std::uint32_t>& pixels, int size) {
    {
        Imf::Header header(size, size);
        header.channels().insert("node", Imf::Channel(Imf::UINT));
        header.compression() = Imf::ZIP_COMPRESSION;
        Imf::OutputFile file((folder / "texel_nodes.exr").c_str(), header);
        Imf::FrameBuffer frame;
        frame.insert("node",
                     Imf::Slice(Imf::UINT,
                                reinterpret_cast<char*>(const_cast<std::uint32_t*>(pixels.data())),
                                sizeof(std::uint32_t), sizeof(std::uint32_t) * size));
        file.setFrameBuffer(frame);
        file.writePixels(size);
    }
    const std::string bytes = test::readFile(folder / "texel_nodes.exr");
    nlohmann::json manifest = nlohmann::json::parse(test::readFile(folder / "manifest.json"));
    // Bundles since 1.1 already list the exporter's own texel_nodes.exr: replace its entry.
    nlohmann::json& files = manifest["files"];
    for (auto f = files.begin(); f != files.end();)
        f = (*f)["path"] == "texel_nodes.exr" ? files.erase(f) : f + 1;
    files.push_back(
        {{"path", "texel_nodes.exr"}, {"sha256", sha256Hex(bytes)}, {"bytes", bytes.size()}});
    std::ofstream(folder / "manifest.json", std::ios::binary | std::ios::trunc) << manifest.dump(2);
}

// A bundle with texel_nodes.exr: the runtime takes the nodes from it (a texel with one sample)
// and gets the engine's map; a covered texel mapped to no node is refused.
TEST_F(RuntimeConformance, ReadsTheTexelNodeMap) {
    const auto it = std::find_if(bundles_->begin(), bundles_->end(), [](const Exported& e) {
        return e.label.rfind("damaged_boat/", 0) == 0;
    });
    ASSERT_NE(it, bundles_->end());
    Result<SurfaceTextures> textures = readBakedTextures(it->folder);
    ASSERT_TRUE(textures.ok());
    Result<WaterGraph> graph = loadGraph(it->folder / "graph.json");
    ASSERT_TRUE(graph.ok());
    const std::vector<std::int32_t> nodes = texelNodeMap(*graph, *textures);
    const int size = textures->size;
    std::vector<std::uint32_t> pixels(static_cast<std::size_t>(size) * size, 0u);
    for (std::size_t i = 0; i < nodes.size(); ++i) {
        const std::uint32_t x = textures->texelIndex[i] % size, y = textures->texelIndex[i] / size;
        pixels[(static_cast<std::size_t>(size) - 1 - y) * size + x] =
            static_cast<std::uint32_t>(nodes[i] + 1);
    }
    const fs::path good = copyBundle(it->folder, "texel_nodes");
    addTexelNodes(good, pixels, size);
    std::string error;
    auto bundle = rt::loadBundle(good.string(), error);
    ASSERT_TRUE(bundle) << error;
    EXPECT_TRUE(bundle->texelNodesFromFile());
    ASSERT_EQ(bundle->graph()->sampleNodes().size(), nodes.size());
    for (std::size_t i = 0; i < nodes.size(); ++i)
        ASSERT_EQ(bundle->graph()->sampleNodes()[i], nodes[i]) << i;

    const fs::path bad = copyBundle(it->folder, "texel_nodes_bad");
    // A texel with one sample (the map decides it; shared texels follow the per-sample rule).
    std::size_t single = 0;
    while (single + 1 < nodes.size() &&
           ((single > 0 && textures->texelIndex[single - 1] == textures->texelIndex[single]) ||
            textures->texelIndex[single + 1] == textures->texelIndex[single]))
        ++single;
    const std::uint32_t x = textures->texelIndex[single] % size,
                        y = textures->texelIndex[single] / size;
    pixels[(static_cast<std::size_t>(size) - 1 - y) * size + x] = 0;
    addTexelNodes(bad, pixels, size);
    const std::string message = loadError(bad);
    EXPECT_NE(message.find("texel_nodes.exr: texel (" + std::to_string(x) + ", " +
                           std::to_string(y) + ") is covered but maps to 0"),
              std::string::npos)
        << message;
}

}  // namespace
}  // namespace test_runtime_conformance
}  // namespace plimsoll
