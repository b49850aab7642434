// Per-frame buoyancy: every backend (the C++ reference and each OpenCL device found) against
// the reference, the textures against the exact clip, conservation on full submersion, and
// the extremes.
#include "plimsoll/bake/bake.h"
#include "plimsoll/physics/buoyancy.h"
#include "plimsoll/compute/compute.h"
#include "plimsoll/physics/massprops.h"
#include "plimsoll/samples/primitives.h"

#include "compute/opencl_backend.h"
#include "cli_runner.h"
#include "test_support.h"

#include <Eigen/Geometry>

#include <cmath>
#include <functional>
#include <numbers>
#include <random>

namespace plimsoll {
namespace test_buoyancy_kernels {
namespace {

using test::bakeOrFail;

struct Body {
    TriangleMesh mesh;
    SurfaceTextures textures;
    MassProperties props;  // texture solid, density 1: volume and centre
    double boundingRadius = 0;
};

Body makeBody(TriangleMesh mesh, int size) {
    Body b;
    b.textures = bakeOrFail(mesh, size);
    b.props = textureSolidMassProperties(b.textures, 1.0);
    for (const auto& p : mesh.positions)
        b.boundingRadius = std::max(b.boundingRadius, (p - b.props.centerOfMass).norm());
    b.mesh = std::move(mesh);
    return b;
}

std::vector<WaterModel> waterModels() {
    WaterModel waves;
    waves.kind = WaterModel::Kind::Gerstner;
    waves.level = 0.05;
    waves.waves = {{0.08, 3.0, {1.0, 0.3}, 0.6, 0.2},
                   {0.05, 1.3, {-0.4, 1.0}, 0.5, 1.1},
                   {0.02, 0.7, {0.1, -1.0}, 0.8, 2.5}};
    WaterModel grid;
    grid.kind = WaterModel::Kind::HeightField;
    grid.level = -0.1;
    grid.grid.countX = 17;
    grid.grid.countZ = 13;
    grid.grid.spacing = 0.15;
    grid.grid.origin = {-1.2, -0.9};
    for (int j = 0; j < grid.grid.countZ; ++j)
        for (int i = 0; i < grid.grid.countX; ++i)
            grid.grid.heights.push_back(0.1f * std::sin(0.7f * i) * std::cos(0.5f * j));
    return {WaterModel::flat(0.02), waves, grid};
}

/// Compares every quantity in its natural scale: volumes by the body's volume, forces by
/// rho g V, torques and moments by rho g V times the bounding radius.
void expectAgree(const BuoyancyResult& a, const BuoyancyResult& b, const Body& body,
                 const FluidSettings& fluid, double speed, double tolerance) {
    const double V = body.props.volume, R = body.boundingRadius;
    const double F = fluid.density * fluid.gravity * V;
    // Drag scales with rho v^2 times the area; skin friction alike.
    const double area = body.textures.surfaceArea();
    const double D = fluid.density * std::max(speed * speed, 1e-12) * area;
    EXPECT_NEAR(a.submergedVolume, b.submergedVolume, tolerance * V);
    EXPECT_LT(((a.centerOfBuoyancy - b.centerOfBuoyancy) * b.submergedVolume).norm(),
              tolerance * V * R + tolerance * R * std::abs(a.submergedVolume - b.submergedVolume));
    EXPECT_LT((a.force - b.force).norm(), tolerance * F);
    EXPECT_LT((a.torque - b.torque).norm(), tolerance * F * R);
    EXPECT_LT((a.pressureForce - b.pressureForce).norm(), tolerance * F);
    EXPECT_LT((a.pressureTorque - b.pressureTorque).norm(), tolerance * F * R);
    EXPECT_LT((a.dragForce - b.dragForce).norm(), tolerance * D);
    EXPECT_LT((a.dragTorque - b.dragTorque).norm(), tolerance * D * R);
    EXPECT_NEAR(a.wettedArea, b.wettedArea, tolerance * area);
}

TEST(BuoyancyKernels, EveryDeviceMatchesTheReference) {
    auto backends = test::openClBackends();
    if (backends.empty()) GTEST_SKIP() << test::noOpenClDeviceReason();
    // Entry counts that are not multiples of the work-group or tile size.
    std::vector<Body> bodies;
    bodies.push_back(makeBody(makeUvSphere(0.5, 48, 24), 100));
    bodies.push_back(makeBody(makeBuoy(), 77));
    std::mt19937 random(1234);
    std::uniform_real_distribution<double> unit(-1.0, 1.0);
    FluidSettings fluid;
    fluid.frictionCoefficient = 0.004;
    for (auto& backend : backends) {
        SCOPED_TRACE(backend->deviceName());
        std::vector<std::size_t> ids;
        for (const Body& b : bodies)
            ids.push_back(backend->addBody(b.textures, b.props.centerOfMass));
        for (const WaterModel& water : waterModels()) {
            for (int trial = 0; trial < 12; ++trial) {
                const std::size_t which = trial % bodies.size();
                const Body& body = bodies[which];
                BodyRequest request;
                request.body = ids[which];
                request.fluid = fluid;
                request.frame.pose = Pose::fromEulerDegrees(
                    {0.3 * unit(random), 0.4 * unit(random), 0.3 * unit(random)},
                    {180 * unit(random), 90 * unit(random), 180 * unit(random)});
                request.frame.motion.linear = {unit(random), 0.5 * unit(random), unit(random)};
                request.frame.motion.angular = {2 * unit(random), 2 * unit(random), unit(random)};
                request.frame.time = 3.0 * trial;
                request.frame.centerOfMass = body.props.centerOfMass;
                BuoyancyResult result;
                ASSERT_TRUE(backend->evaluate({&request, 1}, water, {&result, 1}).ok());
                const BuoyancyResult expected =
                    evaluateBuoyancyReference(body.textures, request.frame, water, fluid);
                const double speed = request.frame.motion.linear.norm() +
                                     request.frame.motion.angular.norm() * body.boundingRadius +
                                     1.0;
                expectAgree(result, expected, body, fluid, speed, 1e-5);
            }
        }
        // Bodies at rest on flat water: tiles wholly under water take the closed form from
        // their moments, the others the per-texel loop.
        for (int trial = 0; trial < 12; ++trial) {
            const Body& body = bodies[trial % bodies.size()];
            BodyRequest request;
            request.body = ids[trial % bodies.size()];
            request.frame.pose = Pose::fromEulerDegrees({0.1 * unit(random), 0, 0.1 * unit(random)},
                                                        {180 * unit(random), 90 * unit(random), 0});
            request.frame.centerOfMass = body.props.centerOfMass;
            const WaterModel water = WaterModel::flat(0.1 * trial - 0.5);
            BuoyancyResult result;
            ASSERT_TRUE(backend->evaluate({&request, 1}, water, {&result, 1}).ok());
            expectAgree(result, evaluateBuoyancyReference(body.textures, request.frame, water, {}),
                        body, {}, 1.0, 1e-5);
            EXPECT_EQ(result.submergedSamples,
                      evaluateBuoyancyReference(body.textures, request.frame, water, {})
                          .submergedSamples);
        }
        // Texels exactly at the water surface: a flat level through entries' own heights.
        const Body& sphere = bodies[0];
        for (std::size_t entry : {0ul, 777ul, 2000ul}) {
            BodyRequest request;
            request.body = ids[0];
            request.frame.centerOfMass = sphere.props.centerOfMass;
            const WaterModel water = WaterModel::flat(sphere.textures.position[entry].y());
            BuoyancyResult result;
            ASSERT_TRUE(backend->evaluate({&request, 1}, water, {&result, 1}).ok());
            expectAgree(result,
                        evaluateBuoyancyReference(sphere.textures, request.frame, water, {}),
                        sphere, {}, 1.0, 1e-5);
        }
    }
}

// Jolt's deliberately failing shader: a kernel that does not compile is reported with the
// device's build log, naming the offending identifier.
TEST(BuoyancyKernels, ABrokenKernelIsReportedWithItsBuildLog) {
    const std::vector<ComputeDevice> devices = listComputeDevices();
    if (devices.empty()) GTEST_SKIP() << test::noOpenClDeviceReason();
    EXPECT_TRUE(detail::compileKernelSource(
                    devices[0].index, "__kernel void fine(__global float* x) { x[0] = 1.0f; }")
                    .ok());
    const Status broken = detail::compileKernelSource(
        devices[0].index, "__kernel void broken(__global float* x) { x[0] = undeclared_thing; }");
    ASSERT_FALSE(broken.ok());
    EXPECT_EQ(broken.error().kind, ErrorKind::kernelBuild);
    EXPECT_NE(broken.error().message.find("undeclared_thing"), std::string::npos);
}

TEST(BuoyancyKernels, UnknownDeviceSpecsAreClearErrors) {
    for (const char* spec : {"banana", "99", "-1"}) {
        auto backend = createBuoyancyBackend(spec);
        if (listComputeDevices().empty()) continue;  // no platform: the reference answers
        ASSERT_FALSE(backend.ok()) << spec;
        EXPECT_EQ(backend.error().kind, ErrorKind::invalidArgument) << spec;
        EXPECT_NE(backend.error().message.find(spec), std::string::npos);
    }
    auto reference = createBuoyancyBackend("reference");
    ASSERT_TRUE(reference.ok());
    EXPECT_EQ((*reference)->deviceName(), "reference (C++)");
}

TEST(BuoyancyKernels, BackendsReportTheirKind) {
    EXPECT_EQ(createReferenceBackend()->kind(), BackendKind::reference);
    const std::vector<ComputeDevice> devices = listComputeDevices();
    for (const ComputeDevice& device : devices) {
        auto backend = createBuoyancyBackend(std::to_string(device.index));
        ASSERT_TRUE(backend.ok()) << backend.error().message;
        EXPECT_EQ((*backend)->kind(),
                  device.isGpu ? BackendKind::openClGpu : BackendKind::openClCpu)
            << device.name;
        EXPECT_TRUE(isOpenCl((*backend)->kind()));
    }
    if (devices.empty()) GTEST_SKIP() << test::noOpenClDeviceReason();
}

// A build without OpenCL runs on the fast CPU path (the default wherever no GPU is used) when
// nothing is asked for, and refuses, as unsupported, every device asked for by name.
TEST(BuoyancyKernels, WithoutOpenClANamedDeviceIsUnsupported) {
    if (openClAvailable()) GTEST_SKIP() << "this build has OpenCL";
    EXPECT_TRUE(listComputeDevices().empty());
    for (const char* spec : {"gpu", "cpu", "0"}) {
        auto backend = createBuoyancyBackend(spec);
        ASSERT_FALSE(backend.ok()) << spec;
        EXPECT_EQ(backend.error().kind, ErrorKind::unsupported) << backend.error().message;
    }
    std::string notice;
    auto automatic = createBuoyancyBackend("", &notice);
    ASSERT_TRUE(automatic.ok());
    EXPECT_EQ((*automatic)->kind(), BackendKind::fastCpu);
    EXPECT_NE(notice.find("no OpenCL"), std::string::npos) << notice;
    EXPECT_EQ(measureCopyBandwidth("cpu", 1024).error().kind, ErrorKind::unsupported);

    const std::string box = test::assetPath("box.obj").string();
    const test::CommandOutput run = test::runPlimsoll(
        "simulate --mesh '" + box + "' --density 400 --size 16 --seconds 0.1 --device gpu");
    EXPECT_EQ(run.exitCode, 1);
    EXPECT_NE(run.err.find("this build has no OpenCL"), std::string::npos) << run.err;
}

// Four million entries through the per-texel path (moving, so no closed form): single-
// precision terms, summed per work-item over only a few entries and in double from the group
// reduction on, keep the totals at 1e-6 relative.
TEST(BuoyancyKernels, PrecisionHoldsOverMillionsOfEntries) {
    auto backends = test::openClBackends();
    if (backends.empty()) GTEST_SKIP() << test::noOpenClDeviceReason();
    const Body sphere = makeBody(makeUvSphere(0.5, 64, 32), 2048);
    ASSERT_GT(sphere.textures.coveredCount(), 4000000u);
    BodyRequest request;
    request.frame.pose = Pose::fromEulerDegrees({0.0, -2.0, 0.0}, {10, 20, 30});
    request.frame.motion.linear = {0.5, -0.2, 0.1};
    request.frame.centerOfMass = sphere.props.centerOfMass;
    const WaterModel water = WaterModel::flat(0.0);
    const BuoyancyResult expected =
        evaluateBuoyancyReference(sphere.textures, request.frame, water, {});
    for (auto& backend : backends) {
        SCOPED_TRACE(backend->deviceName());
        request.body = backend->addBody(sphere.textures, sphere.props.centerOfMass);
        BuoyancyResult result;
        ASSERT_TRUE(backend->evaluate({&request, 1}, water, {&result, 1}).ok());
        EXPECT_NEAR(result.submergedVolume, expected.submergedVolume,
                    1e-6 * expected.submergedVolume);
        EXPECT_LT((result.pressureForce - expected.pressureForce).norm(),
                  1e-6 * expected.pressureForce.norm());
        EXPECT_LT((result.dragForce - expected.dragForce).norm(), 1e-6 * expected.dragForce.norm());
        EXPECT_NEAR(result.wettedArea, expected.wettedArea, 1e-6 * expected.wettedArea);
    }
}

TEST(BuoyancyKernels, ABatchGivesWhatSeparateCallsGive) {
    auto backends = test::openClBackends();
    backends.push_back(createReferenceBackend());
    const Body sphere = makeBody(makeUvSphere(0.5, 32, 16), 64);
    const Body buoy = makeBody(makeBuoy(), 48);
    const WaterModel water = waterModels()[1];
    for (auto& backend : backends) {
        SCOPED_TRACE(backend->deviceName());
        std::vector<BodyRequest> requests;
        for (int i = 0; i < 40; ++i) {
            const Body& body = i % 3 == 0 ? buoy : sphere;
            BodyRequest request;
            request.body = backend->addBody(body.textures, body.props.centerOfMass);
            request.frame.pose = Pose::fromEulerDegrees({3.0 * i, 0.1 * std::sin(i), -2.0 * i},
                                                        {7.0 * i, 11.0 * i, 13.0 * i});
            request.frame.motion.linear = {0.1 * i, 0, 0};
            request.frame.centerOfMass = body.props.centerOfMass;
            requests.push_back(request);
        }
        // Every other body in the batch: skipped bodies must not disturb the rest.
        std::vector<BodyRequest> some;
        for (std::size_t i = 0; i < requests.size(); i += 2) some.push_back(requests[i]);
        std::vector<BuoyancyResult> batch(some.size());
        ASSERT_TRUE(backend->evaluate(some, water, batch).ok());
        for (std::size_t i = 0; i < some.size(); ++i) {
            BuoyancyResult alone;
            ASSERT_TRUE(backend->evaluate({&some[i], 1}, water, {&alone, 1}).ok());
            EXPECT_NEAR(batch[i].submergedVolume, alone.submergedVolume, 1e-12);
            EXPECT_LT((batch[i].pressureForce - alone.pressureForce).norm(), 1e-9);
            EXPECT_LT((batch[i].dragTorque - alone.dragTorque).norm(), 1e-9);
        }
    }
}

/// The request for body `id`, moving and spinning, its centre `depth` under the mean level,
/// turned differently for each `trial`.
BodyRequest movingRequest(std::size_t id, const Body& body, double depth, int trial) {
    BodyRequest request;
    request.body = id;
    request.frame.pose = Pose::fromEulerDegrees({0.1 * trial, -depth, -0.05 * trial},
                                                {17.0 * trial, 31.0 * trial, -11.0 * trial});
    request.frame.motion.linear = {1.2, -0.3, 0.5};
    request.frame.motion.angular = {0.4, -0.7, 0.3};
    request.frame.time = 1.7 * trial;
    request.frame.centerOfMass = body.props.centerOfMass;
    return request;
}

/// The speed the drag of a movingRequest is measured against, on the sample sphere (radius
/// 0.5): about |linear| + |angular| x radius, and 1 m/s of the water's own.
constexpr double kMovingSphereSpeed = 1.3 + 0.9 * 0.5 + 1.0;

/// The largest errors over several results, each in its natural scale: the pressure force of
/// rho g V, its torque of rho g V R, the drag of rho u^2 S, the wetted area of S.
struct WorstErrors {
    double pressureForce = 0, pressureTorque = 0, drag = 0, wetted = 0;
    void add(const BuoyancyResult& got, const BuoyancyResult& want, const Body& body,
             const FluidSettings& fluid, double speed) {
        const double F = fluid.density * fluid.gravity * body.props.volume;
        const double S = body.textures.surfaceArea(), D = fluid.density * speed * speed * S;
        pressureForce =
            std::max(pressureForce, (got.pressureForce - want.pressureForce).norm() / F);
        pressureTorque =
            std::max(pressureTorque,
                     (got.pressureTorque - want.pressureTorque).norm() / (F * body.boundingRadius));
        drag = std::max(drag, (got.dragForce - want.dragForce).norm() / D);
        wetted = std::max(wetted, std::abs(got.wettedArea - want.wettedArea) / S);
    }
};

// How the host waits for the totals, and whether the queue records timestamps, changes when
// evaluate() returns, never what it returns: every combination gives the same bits on every
// water model, and the timings are there exactly where they were asked for.
TEST(BuoyancyKernels, WaitAndTimingsLeaveTheSumsAlone) {
    const Body sphere = makeBody(makeUvSphere(0.5, 32, 16), 64);
    for (const ComputeDevice& device : listComputeDevices()) {
        SCOPED_TRACE(device.name);
        struct Variant {
            std::unique_ptr<BuoyancyBackend> backend;
            bool timed;
        };
        std::vector<Variant> variants;
        for (OpenClWait wait : {OpenClWait::block, OpenClWait::spin, OpenClWait::automatic}) {
            for (bool timed : {false, true}) {
                auto made =
                    createBuoyancyBackend(std::to_string(device.index), nullptr,
                                          OpenClOptions{.wait = wait, .deviceTimings = timed});
                ASSERT_TRUE(made.ok()) << made.error().message;
                for (int i = 0; i < 3; ++i)
                    (*made)->addBody(sphere.textures, sphere.props.centerOfMass);
                variants.push_back({std::move(*made), timed});
            }
        }
        for (const WaterModel& water : waterModels()) {
            std::vector<BuoyancyResult> first;
            for (std::size_t b = 0; b < variants.size(); ++b) {
                BuoyancyBackend& backend = *variants[b].backend;
                std::vector<BodyRequest> requests;
                for (int i = 0; i < 3; ++i)
                    requests.push_back(movingRequest(i, sphere, 0.1 * i, i + 1));
                std::vector<BuoyancyResult> results(requests.size());
                ASSERT_TRUE(backend.evaluate(requests, water, results).ok());
                const FrameTimings t = backend.lastTimings();
                EXPECT_GT(t.totalMs, 0.0);
                if (variants[b].timed) {
                    EXPECT_GT(t.kernelMs, 0.0);
                    EXPECT_GE(t.kernelMs, t.reduceMs);
                } else {
                    EXPECT_EQ(t.kernelMs, 0.0);
                    EXPECT_EQ(t.readbackMs, 0.0);
                }
                if (b == 0) {
                    first = results;
                    EXPECT_GT(first[1].submergedVolume, 0.0);
                    continue;
                }
                for (std::size_t i = 0; i < results.size(); ++i) {
                    EXPECT_EQ(results[i].submergedVolume, first[i].submergedVolume);
                    EXPECT_EQ(results[i].pressureForce, first[i].pressureForce);
                    EXPECT_EQ(results[i].pressureTorque, first[i].pressureTorque);
                    EXPECT_EQ(results[i].dragForce, first[i].dragForce);
                }
            }
        }
    }
}

// The items per work-item set the tiles' size: more, smaller tiles at 1, 2 and 4 than at the
// default 8, and on every water model the same answer as the reference (waves entry by entry,
// waveTolerance 0, so that no tile's closed form under the water's quadratic differs).
TEST(BuoyancyKernels, ItemsPerThreadChangeTheTilesNotTheAnswer) {
    const Body sphere = makeBody(makeUvSphere(0.5, 48, 24), 200);
    FluidSettings fluid;
    fluid.frictionCoefficient = 0.004;
    for (const ComputeDevice& device : listComputeDevices()) {
        SCOPED_TRACE(device.name);
        std::size_t tilesBefore = 0;
        for (int items : {16, 8, 4, 2, 1}) {
            SCOPED_TRACE(items);
            auto made =
                createBuoyancyBackend(std::to_string(device.index), nullptr,
                                      OpenClOptions{.waveTolerance = 0.0, .itemsPerThread = items});
            ASSERT_TRUE(made.ok()) << made.error().message;
            BuoyancyBackend& backend = **made;
            const std::size_t id = backend.addBody(sphere.textures, sphere.props.centerOfMass);
            for (const WaterModel& water : waterModels()) {
                for (int trial = 1; trial <= 2; ++trial) {
                    BodyRequest request = movingRequest(id, sphere, 0.15 * trial, trial);
                    request.fluid = fluid;
                    BuoyancyResult result;
                    ASSERT_TRUE(backend.evaluate({&request, 1}, water, {&result, 1}).ok());
                    const double speed =
                        request.frame.motion.linear.norm() +
                        request.frame.motion.angular.norm() * sphere.boundingRadius + 1.0;
                    expectAgree(
                        result,
                        evaluateBuoyancyReference(sphere.textures, request.frame, water, fluid),
                        sphere, fluid, speed, 1e-5);
                }
            }
            // At most kOpenClWorkGroupSize x items entries a tile, in blocks of the texture:
            // halving the items at least doubles the tiles, less the blocks' ragged edges.
            const std::size_t tiles = backend.lastTileCounts().tiles;
            const std::size_t floor =
                sphere.textures.coveredCount() / (kOpenClWorkGroupSize * items);
            EXPECT_GE(tiles, floor);
            if (tilesBefore) EXPECT_GT(tiles, tilesBefore * 3 / 2);
            tilesBefore = tiles;
        }
    }
    if (listComputeDevices().empty()) return;
    for (int items : {-1, kMaxOpenClItemsPerThread + 1}) {
        auto made = createBuoyancyBackend("0", nullptr, OpenClOptions{.itemsPerThread = items});
        ASSERT_FALSE(made.ok());
        EXPECT_NE(made.error().message.find("items per thread"), std::string::npos)
            << made.error().message;
    }
}

// Under flat water the tiles' closed forms are exact: a body wholly under water takes every
// tile's hydrostatics from its moments, and the drag of every tile whose normals keep one
// sign against the flow, and agrees with the reference as the per-entry sums do (1e-5).
TEST(BuoyancyKernels, TilesUnderFlatWaterTakeExactClosedForms) {
    auto backends = test::openClBackends();
    if (backends.empty()) GTEST_SKIP() << test::noOpenClDeviceReason();
    const Body sphere = makeBody(makeUvSphere(0.5, 48, 24), 512);  // 256 tiles on the device
    const double speed = kMovingSphereSpeed;
    for (auto& backend : backends) {
        SCOPED_TRACE(backend->deviceName());
        const std::size_t id = backend->addBody(sphere.textures, sphere.props.centerOfMass);
        for (double depth : {2.0, 0.2}) {
            for (int trial = 0; trial < 3; ++trial) {
                const BodyRequest request = movingRequest(id, sphere, depth, trial);
                const WaterModel water = WaterModel::flat(0.0);
                BuoyancyResult result;
                ASSERT_TRUE(backend->evaluate({&request, 1}, water, {&result, 1}).ok());
                const TileCounts counts = backend->lastTileCounts();
                expectAgree(
                    result,
                    evaluateBuoyancyReference(sphere.textures, request.frame, water, request.fluid),
                    sphere, request.fluid, speed, 1e-5);
                EXPECT_EQ(result.submergedSamples,
                          evaluateBuoyancyReference(sphere.textures, request.frame, water, {})
                              .submergedSamples);
                if (depth > 1) {
                    EXPECT_EQ(counts.closedForm, counts.tiles);
                    EXPECT_GT(counts.dragClosedForm, counts.tiles / 2);
                } else {
                    EXPECT_GT(counts.closedForm, 0u);
                    EXPECT_GT(counts.perEntry(), 0u);
                }
            }
        }
    }
}

// On waves a tile takes the water's quadratic over it where that quadratic misses the surface
// by at most OpenClOptions::waveTolerance of the body's radius, its entries at the waterline
// too: its depths are then off by about that much, so the pressure force by about rho g
// (tolerance x radius) x the wetted area, and the wetted area by about (tolerance x radius) x
// the waterline's length, here at most two great circles of the sphere (4 pi radius, a
// waterline bent by the waves): tolerance x its surface. With the tolerance at 0 every tile
// that reaches the water goes entry by entry, under the waves themselves (1e-5 as everywhere).
TEST(BuoyancyKernels, TilesUnderWavesStayWithinTheirStatedError) {
    if (listComputeDevices().empty()) GTEST_SKIP() << test::noOpenClDeviceReason();
    const Body sphere = makeBody(makeUvSphere(0.5, 48, 24), 512);
    const double radius = sphere.boundingRadius;
    const double speed = kMovingSphereSpeed;
    const FluidSettings fluid;
    const double F = fluid.density * fluid.gravity * sphere.props.volume;
    const double D = fluid.density * speed * speed * sphere.textures.surfaceArea();
    const std::vector<WaterModel> waters = {waterModels()[1], waterModels()[2]};
    for (double tolerance : {0.0, 1e-4, OpenClOptions{}.waveTolerance, 1e-2}) {
        SCOPED_TRACE(tolerance);
        OpenClOptions options;
        options.waveTolerance = tolerance;
        auto backend = createBuoyancyBackend("0", nullptr, options);
        ASSERT_TRUE(backend.ok()) << backend.error().message;
        const std::size_t id = (*backend)->addBody(sphere.textures, sphere.props.centerOfMass);
        for (std::size_t model = 0; model < waters.size(); ++model) {
            const WaterModel& water = waters[model];
            std::size_t closed = 0, dragClosed = 0, dry = 0, tiles = 0;
            WorstErrors worst;
            for (int trial = 0; trial < 4; ++trial) {
                const BodyRequest request = movingRequest(id, sphere, trial % 2 ? 0.1 : 0.4, trial);
                BuoyancyResult result;
                ASSERT_TRUE((*backend)->evaluate({&request, 1}, water, {&result, 1}).ok());
                const TileCounts counts = (*backend)->lastTileCounts();
                closed += counts.closedForm;
                dragClosed += counts.dragClosedForm;
                dry += counts.dry;
                tiles += counts.tiles;
                const BuoyancyResult expected =
                    evaluateBuoyancyReference(sphere.textures, request.frame, water, fluid);
                const double wetted = expected.wettedArea;
                const double bound =
                    fluid.density * fluid.gravity * tolerance * radius * wetted + 1e-5 * F;
                EXPECT_LT((result.pressureForce - expected.pressureForce).norm(), bound);
                EXPECT_LT((result.pressureTorque - expected.pressureTorque).norm(), bound * radius);
                EXPECT_NEAR(result.submergedVolume, expected.submergedVolume,
                            bound / (fluid.density * fluid.gravity));
                EXPECT_NEAR(result.wettedArea, expected.wettedArea,
                            (tolerance + 1e-5) * sphere.textures.surfaceArea());
                worst.add(result, expected, sphere, fluid, speed);
                // The drag of a closed-form tile takes the water's velocity as linear over it.
                EXPECT_LT((result.dragForce - expected.dragForce).norm(),
                          (tolerance > 0 ? 1e-3 : 1e-5) * D);
                EXPECT_LT((result.dragTorque - expected.dragTorque).norm(),
                          (tolerance > 0 ? 1e-3 : 1e-5) * D * radius);
            }
            std::printf(
                "  %s, tolerance %.0e: of %zu tiles in 4 frames %zu dry, %zu closed-form "
                "(%zu with drag); pressure force error %.2e of rho g V, drag %.2e of rho u^2 S, "
                "wetted "
                "area %.2e of S\n",
                model == 0 ? "Gerstner" : "height field", tolerance, tiles, dry, closed, dragClosed,
                worst.pressureForce, worst.drag, worst.wetted);
            if (tolerance == 0) {
                EXPECT_EQ(closed, 0u);
            } else if (model == 0) {
                EXPECT_GT(closed, 0u);  // the sample waves are smooth over a tile
                EXPECT_GT(dragClosed, 0u);
            }
        }
    }
}

// Where the water over a tile is all but a quadratic and its velocity all but linear, the
// tiles that take them (at the waterline entry by entry too) give the reference's answer to
// the 1e-5 the exact paths hold. A long swell (80 m, 0.9 m high, 0.7 m/s): the next terms, k^3
// A rho^3 and k^2 A omega rho^2 over a tile of radius rho (about 0.15 m here), are some 1e-7 m
// and 1e-5 m/s. A shorter wave (16 m) curves the surface enough over a tile (A k^2 rho^2 / 2,
// about 5e-4 m) that a wrong curvature shows, while its cubic term stays near 1e-5 m; its
// velocity is not linear enough over a tile for 1e-5, so the drag is off there (C_d = 0). The
// wetted area, which the waterline's entries alone decide, is held to 1e-6 of the surface
// (measured 2e-8 on both; a curvature a fifth short gave 3e-6 on the 16 m wave).
TEST(BuoyancyKernels, WhereTheWaterIsNearlyQuadraticTilesGiveTheReferencesAnswer) {
    if (listComputeDevices().empty()) GTEST_SKIP() << test::noOpenClDeviceReason();
    const Body sphere = makeBody(makeUvSphere(0.5, 48, 24), 512);
    struct Case {
        const char* name;
        GerstnerWave wave;
        double dragCoefficient;
    };
    const Case cases[] = {{"swell", {0.9, 80.0, {1.0, 0.4}, 0.6, 0.3}, 1.0},
                          {"16 m wave, no drag", {0.3, 16.0, {-0.3, 1.0}, 0.6, 1.1}, 0.0}};
    const double speed = kMovingSphereSpeed;
    auto backend = createBuoyancyBackend("0", nullptr, OpenClOptions{});
    ASSERT_TRUE(backend.ok()) << backend.error().message;
    const std::size_t id = (*backend)->addBody(sphere.textures, sphere.props.centerOfMass);
    for (const Case& c : cases) {
        SCOPED_TRACE(c.name);
        WaterModel water;
        water.kind = WaterModel::Kind::Gerstner;
        water.level = 0.05;
        water.waves = {c.wave};
        FluidSettings fluid;
        fluid.dragCoefficient = c.dragCoefficient;
        std::size_t closed = 0, perEntry = 0;
        WorstErrors worst;
        for (int trial = 0; trial < 6; ++trial) {
            BodyRequest request = movingRequest(id, sphere, trial % 2 ? 0.1 : 0.4, trial);
            request.fluid = fluid;
            BuoyancyResult result;
            ASSERT_TRUE((*backend)->evaluate({&request, 1}, water, {&result, 1}).ok());
            closed += (*backend)->lastTileCounts().closedForm;
            perEntry += (*backend)->lastTileCounts().perEntry();
            const BuoyancyResult expected =
                evaluateBuoyancyReference(sphere.textures, request.frame, water, fluid);
            worst.add(result, expected, sphere, fluid, speed);
        }
        std::printf(
            "  %s: %zu tiles closed-form, %zu entry by entry; pressure force error %.2e of rho g "
            "V, "
            "torque %.2e, drag %.2e of rho u^2 S, wetted area %.2e of S\n",
            c.name, closed, perEntry, worst.pressureForce, worst.pressureTorque, worst.drag,
            worst.wetted);
        EXPECT_GT(closed, 0u);
        EXPECT_GT(perEntry, 0u);
        EXPECT_LT(worst.pressureForce, 1e-5);
        EXPECT_LT(worst.pressureTorque, 1e-5);
        EXPECT_LT(worst.drag, 1e-5);
        EXPECT_LT(worst.wetted, 1e-6);
    }
}

/// Largest submerged-volume error over the paper's figure 9 sweep (depth -0.5 .. 0.5 of the
/// sample sphere, three orientations), as a share of the sphere's volume.
double sphereSweepError(int size) {
    const TriangleMesh sphere = makeUvSphere(0.5, 64, 32);
    const SurfaceTextures textures = bakeOrFail(sphere, size);
    const MassProperties props = textureSolidMassProperties(textures, 1.0);
    const double volume = exactSolidMassProperties(sphere, 1.0).volume;
    double worst = 0;
    for (const Eigen::Vector3d& degrees :
         {Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(30, 0, 0), Eigen::Vector3d(20, 40, 60)}) {
        for (int step = 0; step <= 20; ++step) {
            const double level = -0.5 + 0.05 * step;
            BodyFrame frame;
            frame.pose = Pose::fromEulerDegrees(Eigen::Vector3d::Zero(), degrees);
            frame.centerOfMass = props.centerOfMass;
            const BuoyancyResult textured =
                evaluateBuoyancyReference(textures, frame, WaterModel::flat(level), {});
            const BuoyancyResult exact = evaluateBuoyancyExact(sphere, frame, level, {});
            worst = std::max(worst,
                             std::abs(textured.submergedVolume - exact.submergedVolume) / volume);
        }
    }
    return worst;
}

TEST(BuoyancyAccuracy, SphereSweepAgainstTheExactClip) {
    // The 1024^2 sweep is left to the normal build in the sanitized one, where it took most of
    // this test's minute: 256 and 512 run the same code.
    const double e256 = sphereSweepError(256), e512 = sphereSweepError(512),
                 e1024 = test::kSanitizedBuild ? 0.0 : sphereSweepError(1024);
    std::printf("  sphere sweep, worst |V_s error| / V: N=256 %.2e, 512 %.2e, 1024 %.2e\n", e256,
                e512, e1024);
    EXPECT_LT(e256, 1e-3);
    if (!test::kSanitizedBuild) EXPECT_LT(e1024, 2e-4);
    EXPECT_GE(e256 / e512, 2.5);
}

TEST(BuoyancyAccuracy, FullySubmergedGivesArchimedes) {
    const Body buoy = makeBody(makeBuoy(), 256);
    const FluidSettings fluid;
    const double exactVolume = exactSolidMassProperties(buoy.mesh, 1.0).volume;
    const double volumeError = std::abs(buoy.props.volume - exactVolume) / exactVolume;
    // Upright (any place, any water level above it): V_s = sum A_y (y - h) is the dry body's
    // texture volume sum A_y y less h times the closure, so they agree to rounding. Turned,
    // the world y of each area vector mixes the object axes, and they agree to the volume's
    // discretisation error.
    for (const Eigen::Vector3d& degrees :
         {Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(25, -40, 10)}) {
        SCOPED_TRACE(degrees.transpose());
        const bool upright = degrees.isZero();
        BodyFrame frame;
        frame.pose = Pose::fromEulerDegrees({0.2, -5.0, 0.1}, degrees);
        frame.centerOfMass = buoy.props.centerOfMass;
        const BuoyancyResult r =
            evaluateBuoyancyReference(buoy.textures, frame, WaterModel::flat(3.0), fluid);
        const double weightOfDisplaced = fluid.density * fluid.gravity * buoy.props.volume;
        const double agreement = upright ? 1e-9 : 2 * volumeError;
        EXPECT_NEAR(r.force.y(), weightOfDisplaced, agreement * weightOfDisplaced);
        EXPECT_EQ(r.submergedSamples, buoy.textures.coveredCount());
        // The pressure integral gives the same force within the volume error, and its
        // horizontal part is discretisation error only.
        EXPECT_NEAR(r.pressureForce.y(), r.force.y(),
                    std::max(volumeError, 1e-9) * 2 * r.force.y());
        EXPECT_LT(std::hypot(r.pressureForce.x(), r.pressureForce.z()), 1e-3 * r.pressureForce.y());
        // Fully under water the centre of buoyancy is the centre of volume.
        EXPECT_LT((r.centerOfBuoyancy - frame.pose.apply(buoy.props.centerOfMass)).norm(),
                  upright ? 1e-9 : 2e-4 * computeBounds(buoy.mesh).diagonal());
    }
}

TEST(BuoyancyExtremes, ResultsStayFiniteAndContinuous) {
    auto backends = test::openClBackends();
    backends.push_back(createReferenceBackend());
    for (auto& backend : backends) {
        SCOPED_TRACE(backend->deviceName());
        for (double scale : {1e-3, 1.0, 1e3}) {
            TriangleMesh mesh = makeUvSphere(0.5 * scale, 32, 16);
            const Body body = makeBody(mesh, 128);
            const std::size_t id = backend->addBody(body.textures, body.props.centerOfMass);
            double lowest = 1e300;
            for (const auto& p : body.textures.position) lowest = std::min(lowest, p.y());
            const double V = body.props.volume;
            const double r = 0.5 * scale;
            struct Case {
                const char* what;
                Eigen::Vector3d position;
                double level;
                double spin;
            };
            const Case cases[] = {
                {"barely touching", {0, 0, 0}, lowest + 1e-7 * r, 0},
                {"fully out", {0, 0, 0}, -3 * r, 0},
                {"fully under", {0, 0, 0}, 3 * r, 0},
                {"far away", {1e5, 0, -1e5}, 0.1 * r, 0},
                {"spinning", {0, 0, 0}, 0.2 * r, 1e3},
            };
            for (const Case& c : cases) {
                SCOPED_TRACE(std::string(c.what) + " at scale " + std::to_string(scale));
                BodyRequest request;
                request.body = id;
                request.frame.pose.translation = c.position;
                request.frame.motion.angular = {c.spin, 0.3 * c.spin, 0};
                request.frame.motion.linear = {1.0, 0.0, 0.0};
                request.frame.centerOfMass = body.props.centerOfMass;
                BuoyancyResult result;
                ASSERT_TRUE(
                    backend->evaluate({&request, 1}, WaterModel::flat(c.level), {&result, 1}).ok());
                EXPECT_TRUE(std::isfinite(result.submergedVolume));
                EXPECT_TRUE(result.centerOfBuoyancy.allFinite());
                EXPECT_TRUE(result.force.allFinite() && result.torque.allFinite());
                EXPECT_TRUE(result.pressureForce.allFinite() && result.pressureTorque.allFinite());
                EXPECT_TRUE(result.dragForce.allFinite() && result.dragTorque.allFinite());
                EXPECT_GE(result.submergedVolume, -1e-6 * V);
                EXPECT_LE(result.submergedVolume, V * (1 + 1e-5));
            }
            // Continuity: lowering the water in steps of r/500 changes the force smoothly, by
            // at most rho g (waterplane area) (step) with some slack.
            double previous = 0;
            const double step = r / 500;
            for (int i = 0; i <= 200; ++i) {
                BodyRequest request;
                request.body = id;
                request.frame.centerOfMass = body.props.centerOfMass;
                BuoyancyResult result;
                ASSERT_TRUE(backend
                                ->evaluate({&request, 1}, WaterModel::flat(-0.2 * r + i * step),
                                           {&result, 1})
                                .ok());
                const double bound = 1.5 * 1000 * 9.81 * std::numbers::pi * r * r * step;
                if (i > 0) EXPECT_LE(std::abs(result.pressureForce.y() - previous), bound) << i;
                previous = result.pressureForce.y();
            }
        }
    }
}

}  // namespace
}  // namespace test_buoyancy_kernels
}  // namespace plimsoll
