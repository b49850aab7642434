// The fast backend (fast_backend.h): the batch call gives the same numbers on the caller's task
// system as on its own pool and as one body at a time, and it is the default where no GPU is
// found.
#include "plimsoll/compute/compute.h"
#include "plimsoll/samples/primitives.h"

#include "eval/fast_support.h"

#include <gtest/gtest.h>

#include <atomic>
#include <cstdlib>

namespace plimsoll {
namespace test_fast_backend {
namespace {

using namespace fast_test;

/// A task system of the caller's that runs every range at once on the calling thread and
/// counts its calls.
struct CountingTasks {
    std::atomic<int> enqueued{0}, finished{0};
    static void* enqueue(ev::TaskCallback* task, int count, int minRange, void* context,
                         void* user) {
        auto* self = static_cast<CountingTasks*>(user);
        ++self->enqueued;
        for (int begin = 0; begin < count; begin += std::max(1, minRange))
            task(begin, std::min(count, begin + std::max(1, minRange)), 0, context);
        return self;
    }
    static void finish(void* handle, void* user) {
        EXPECT_EQ(handle, user);
        ++static_cast<CountingTasks*>(user)->finished;
    }
};

TEST(FastBackend, BatchesOnTheCallersTaskSystemAsOnItsOwnPool) {
    const Body sphere = makeBody(makeUvSphere(0.5, 32, 16), 48);
    const Body buoy = makeBody(makeBuoy(), 48);
    CountingTasks counting;
    FastBackendOptions callers;
    callers.tasks.enqueue = CountingTasks::enqueue;
    callers.tasks.finish = CountingTasks::finish;
    callers.tasks.userContext = &counting;
    FastBackendOptions pool;
    pool.threads = 2;
    auto a = createFastBackend(callers), b = createFastBackend(pool);
    std::vector<BodyRequest> requests;
    std::mt19937 random(3);
    for (int i = 0; i < 64; ++i) {
        const Body& body = i % 2 ? buoy : sphere;
        BodyRequest request;
        request.body = a->addBody(body.textures, body.props.centerOfMass);
        EXPECT_EQ(b->addBody(body.textures, body.props.centerOfMass), request.body);
        request.frame = randomFrame(random, body, i % 3);
        requests.push_back(request);
    }
    const WaterModel water = buoyWaves();
    std::vector<BuoyancyResult> ra(requests.size()), rb(requests.size());
    ASSERT_TRUE(a->evaluate(requests, water, ra).ok());
    ASSERT_TRUE(b->evaluate(requests, water, rb).ok());
    EXPECT_EQ(counting.enqueued.load(), 1);
    EXPECT_EQ(counting.finished.load(), 1);
    ev::FastScratch scratch;
    for (std::size_t i = 0; i < requests.size(); ++i) {
        const Body& body = i % 2 ? buoy : sphere;
        BodyFrame frame = requests[i].frame;
        frame.centerOfMass = body.props.centerOfMass;
        const BuoyancyResult one = evaluateBuoyancyFast(body.fast, frame, water, {}, scratch);
        EXPECT_EQ(ra[i].submergedVolume, one.submergedVolume) << i;
        EXPECT_EQ(rb[i].submergedVolume, one.submergedVolume) << i;
        EXPECT_EQ(ra[i].dragTorque, one.dragTorque) << i;
        EXPECT_EQ(rb[i].pressureTorque, one.pressureTorque) << i;
    }
    BodyRequest unknown;
    unknown.body = 999;
    BuoyancyResult out;
    const Status refused = a->evaluate({&unknown, 1}, water, {&out, 1});
    ASSERT_FALSE(refused.ok());
    EXPECT_EQ(refused.error().kind, ErrorKind::invalidArgument);
}

TEST(FastBackend, IsTheDefaultWhereNoGpuIsFound) {
    if (std::getenv("PLIMSOLL_OPENCL_DEVICE")) GTEST_SKIP() << "device chosen by the environment";
    for (const ComputeDevice& d : listComputeDevices())
        if (d.isGpu) GTEST_SKIP() << "a GPU is the default here";
    auto backend = createBuoyancyBackend("");
    ASSERT_TRUE(backend.ok()) << backend.error().message;
    EXPECT_EQ((*backend)->kind(), BackendKind::fastCpu) << (*backend)->deviceName();
    auto named = createBuoyancyBackend("fast");
    ASSERT_TRUE(named.ok());
    EXPECT_EQ((*named)->kind(), BackendKind::fastCpu);
}

}  // namespace
}  // namespace test_fast_backend
}  // namespace plimsoll
