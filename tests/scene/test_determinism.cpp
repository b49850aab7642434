// Determinism: every sample project, simulated for a few seconds on the C++ reference backend,
// gives a pinned hash of the raw bytes of every body's state (centre of mass, orientation,
// linear and angular momentum) at every frame. Any change in any bit of any frame changes it.
//
// The pinned values hold for one build type and platform: what changes them is the compiler
// or its version, the compiler flags (optimisation that contracts a * b + c into one fused
// operation, -march, -ffast-math), the platform's libm (sin, cos, sqrt of the waves and
// rotations) and the backend (the OpenCL kernels compute in float; only the reference is pinned
// here). A change to the physics, the bake or a sample project changes them too: then the new
// values are pinned on purpose, in the same commit, and the commit says why.
#include "plimsoll/project/project.h"
#include "plimsoll/scene/world.h"

#include "test_support.h"
#include "world_support.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <string>

namespace plimsoll {
namespace test_determinism {
namespace {

/// Simulated seconds per project: every body moves (falls, floods, inflates, rolls) in it.
constexpr double kSeconds = 2.0;

/// 64-bit FNV-1a over bytes.
struct TrajectoryHash {
    std::uint64_t value = 0xcbf29ce484222325ull;
    void add(const double* numbers, std::size_t count) {
        const auto* bytes = reinterpret_cast<const unsigned char*>(numbers);
        for (std::size_t i = 0; i < count * sizeof(double); ++i) {
            value ^= bytes[i];
            value *= 0x100000001b3ull;
        }
    }
    void add(const RigidBodyState& s) {
        add(s.position.data(), 3);
        add(s.orientation.coeffs().data(), 4);
        add(s.linearMomentum.data(), 3);
        add(s.angularMomentum.data(), 3);
    }
};

std::uint64_t trajectoryHash(const std::string& name) {
    Result<Project> project = loadProject(std::filesystem::path(PLIMSOLL_SOURCE_DIR) / "projects" /
                                          (name + ".plim.json"));
    EXPECT_TRUE(project.ok()) << project.error().message;
    if (!project) return 0;
    std::unique_ptr<World> world = test::worldOrFail(test::sceneOrFail(*project));
    if (!world) return 0;
    TrajectoryHash hash;
    const long frames = std::lround(kSeconds / project->simulation.timeStep);
    for (long f = 0; f < frames; ++f) {
        const Status s = world->advanceFrame();
        EXPECT_TRUE(s.ok()) << s.error().message;
        if (!s) return 0;
        for (const SimulatedBody& body : world->bodies()) hash.add(body.state);
    }
    return hash.value;
}

struct PinnedTrajectory {
    const char* project;
    std::uint64_t hash;
};

void PrintTo(const PinnedTrajectory& p, std::ostream* out) { *out << p.project; }

class Determinism : public testing::TestWithParam<PinnedTrajectory> {};

TEST_P(Determinism, SampleProjectTrajectoryHashIsPinned) {
    // Instrumented builds compile other code (and may schedule floating point differently):
    // the values are pinned for the Release build.
    if (test::kSanitizedBuild) GTEST_SKIP() << "hashes are pinned for the Release build";
    const std::uint64_t hash = trajectoryHash(GetParam().project);
    char text[32];
    std::snprintf(text, sizeof text, "0x%016llx", static_cast<unsigned long long>(hash));
    EXPECT_EQ(hash, GetParam().hash)
        << GetParam().project << ": trajectory hash " << text
        << "; pin it only if the change is meant (see the top of this file)";
}

INSTANTIATE_TEST_SUITE_P(SampleProjects, Determinism,
                         testing::Values(PinnedTrajectory{"balloon", 0xf2c16e55757f4024ull},
                                         PinnedTrajectory{"box_half_draft", 0x76484adabbfc84b1ull},
                                         PinnedTrajectory{"buoy", 0x62474a97edaff46cull},
                                         PinnedTrajectory{"damaged_boat", 0x7ce0f45b5dda2e17ull},
                                         PinnedTrajectory{"heavy_side_ball", 0xcccac98d0791c20bull},
                                         PinnedTrajectory{"neutral_ball", 0xcea0716e68e8fd59ull},
                                         PinnedTrajectory{"plush", 0x55f45ab2c46ad123ull}),
                         [](const testing::TestParamInfo<PinnedTrajectory>& info) {
                             return std::string(info.param.project);
                         });

}  // namespace
}  // namespace test_determinism
}  // namespace plimsoll
