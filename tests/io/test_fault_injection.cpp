// No lost work: every writer (project save with its maps, bundle export, editor autosave,
// painted-map save, bake output) is interrupted at each of its steps in turn
// (failFileStepForTesting(k) for k = 1, 2, ... until the operation goes through). After each
// interruption the folder must hold exactly the previous files, byte for byte, and no
// temporary file; the uninterrupted run must then write the new version.
#include "test_support.h"
#include "world_support.h"

#include "document/command.h"
#include "document/document.h"

#include "plimsoll/bake/bake.h"
#include "plimsoll/io/painted_map_io.h"
#include "plimsoll/io/bake_io.h"
#include "plimsoll/export/bundle.h"
#include "plimsoll/io/file_util.h"

#include "io/test_hooks.h"
#include "plimsoll/surface/painted_map.h"
#include "plimsoll/samples/primitives.h"
#include "plimsoll/project/project.h"
#include "plimsoll/scene/world.h"

#include "compute/opencl_backend.h"

#include <algorithm>
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <functional>
#include <iterator>
#include <cstdlib>
#include <map>
#include <tuple>
#include <unistd.h>

namespace plimsoll {
namespace test_fault_injection {
namespace {

namespace fs = std::filesystem;

/// Every regular file under `dir` (relative path -> bytes).
std::map<std::string, std::string> snapshot(const fs::path& dir) {
    std::map<std::string, std::string> files;
    for (const auto& entry : fs::recursive_directory_iterator(dir)) {
        if (!entry.is_regular_file()) continue;
        files[fs::relative(entry.path(), dir).generic_string()] = test::readFile(entry.path());
    }
    return files;
}

/// Runs `operation` with the k-th file step failing, k = 1, 2, ..., checking after each failure
/// that `dir` is exactly as before; returns how many steps the operation has (the k at which it
/// went through, less one).
int interruptAtEveryStep(const fs::path& dir, const std::function<Status()>& operation) {
    const std::map<std::string, std::string> before = snapshot(dir);
    int k = 1;
    for (;; ++k) {
        failFileStepForTesting(k);
        const Status status = operation();
        failFileStepForTesting(0);
        if (status.ok()) break;
        SCOPED_TRACE("interrupted at step " + std::to_string(k));
        EXPECT_NE(status.error().message.find("injected fault"), std::string::npos)
            << status.error().message;
        const std::map<std::string, std::string> after = snapshot(dir);
        for (const auto& [path, bytes] : before) {
            const auto it = after.find(path);
            if (it == after.end()) {
                ADD_FAILURE() << path << " is gone";
                continue;
            }
            EXPECT_TRUE(it->second == bytes) << path << " changed";
        }
        for (const auto& [path, bytes] : after) {
            EXPECT_TRUE(before.count(path)) << path << " left behind";
        }
        if (::testing::Test::HasFailure() || k > 200) break;
    }
    // The successful run left no temporary either.
    for (const auto& [path, bytes] : snapshot(dir)) {
        EXPECT_EQ(path.find(".tmp"), std::string::npos) << path << " left behind";
    }
    return k - 1;
}

PaintedMap gradient(int size, float scale) {
    PaintedMap map{size, size, {}};
    for (int i = 0; i < size * size; ++i) map.values.push_back(scale * float(i) / (size * size));
    return map;
}

TEST(FaultInjection, PaintedMapSaveKeepsThePreviousMap) {
    const fs::path dir = test::freshFolder("fault", "map");
    const fs::path path = dir / "map.png";
    ASSERT_TRUE(savePaintedMap(gradient(32, 1.0f), path).ok());
    const int steps =
        interruptAtEveryStep(dir, [&] { return savePaintedMap(gradient(32, 0.5f), path); });
    EXPECT_EQ(steps, 2);  // the temporary file, the rename
    EXPECT_NEAR(loadPaintedMap(path)->values.back(), 0.5f * (1023.0f / 1024.0f), 1e-4);
}

TEST(FaultInjection, BakeOutputIsReplacedAsAWhole) {
    const fs::path dir = test::freshFolder("fault", "bake");
    const TriangleMesh box = makeBox({1.0, 0.5, 0.25});
    BakeSettings settings;
    settings.size = 16;
    Result<SurfaceTextures> first = bakeSurfaceTextures(box, settings);
    ASSERT_TRUE(first.ok()) << first.error().message;
    ASSERT_TRUE(writeBakedTextures(*first, dir, "box").ok());
    settings.size = 32;
    Result<SurfaceTextures> second = bakeSurfaceTextures(box, settings);
    ASSERT_TRUE(second.ok());
    const int steps =
        interruptAtEveryStep(dir, [&] { return writeBakedTextures(*second, dir, "box"); });
    EXPECT_EQ(steps, 12);  // five files written, the journal written and committed, five renamed
    Result<SurfaceTextures> read = readBakedTextures(dir);
    ASSERT_TRUE(read.ok()) << read.error().message;
    EXPECT_EQ(read->size, 32);
    EXPECT_EQ(read->coveredCount(), second->coveredCount());
}

/// A project on the box asset, beside its own copy of a painted map.
fs::path writeBoxProject(const fs::path& dir, double density) {
    const fs::path path = dir / "box.plim.json";
    std::ofstream(path)
        << R"({"schema_version": 1, "name": "box", "bodies": [{"name": "box", "mesh": ")"
        << test::assetPath("box.obj").string()
        << R"(", "texture_size": 16, "permeability_map": "perm.png",
                           "material": {"density": )"
        << density << "}}]}";
    EXPECT_TRUE(savePaintedMap(gradient(16, 1.0f), dir / "perm.png").ok());
    return path;
}

TEST(FaultInjection, BundleExportLeavesThePreviousBundleUntouched) {
    const fs::path dir = test::freshFolder("fault", "bundle");
    const fs::path projectDir = dir / "project", out = dir / "export";
    fs::create_directories(projectDir);
    fs::create_directories(out);
    Result<Project> a = loadProject(writeBoxProject(projectDir, 500.0));
    ASSERT_TRUE(a.ok()) << a.error().message;
    ASSERT_TRUE(writeBodyBundle(*a, 0, out / "box").ok());
    Result<Project> b = loadProject(writeBoxProject(projectDir, 700.0));
    ASSERT_TRUE(b.ok());
    // The box radiates by default: its radiation cache (a best-effort write beside the project,
    // whose failure is only a note) is written once here, so that the interrupted exports below
    // read it and every injected fault lands in the bundle's own files.
    ASSERT_TRUE(writeBodyBundle(*b, 0, dir / "warm").ok());
    const int steps = interruptAtEveryStep(out, [&]() -> Status {
        Result<BundleReport> r = writeBodyBundle(*b, 0, out / "box");
        return r.ok() ? Status(Ok{}) : Status(r.error());
    });
    EXPECT_GE(steps, 13);  // 5 bake files x 2, area.exr renamed, permeability.png, the exchange
    ASSERT_TRUE(verifyBundle(out / "box").ok());
    EXPECT_NE(test::readFile(out / "box" / "manifest.json").find("700"), std::string::npos);
}

TEST(FaultInjection, ProjectSaveWithItsMapsKeepsThePreviousFiles) {
    const fs::path dir = test::freshFolder("fault", "save");
    const fs::path path = writeBoxProject(dir, 500.0);
    Result<std::unique_ptr<editor::Document>> opened = editor::Document::open(path);
    ASSERT_TRUE(opened.ok()) << opened.error().message;
    editor::Document& d = **opened;
    ASSERT_TRUE(d.save().ok());
    auto fill = editor::makeFillAllCommand(d, 0, editor::MapChannel::Permeability, 0.25);
    ASSERT_TRUE(fill.ok());
    ASSERT_TRUE(d.execute(std::move(fill).value()).ok());
    auto rename = editor::makeSetPropertyCommand(d, "/name", "changed");
    ASSERT_TRUE(rename.ok());
    ASSERT_TRUE(d.execute(std::move(rename).value()).ok());
    const int steps = interruptAtEveryStep(dir, [&] { return d.save(); });
    EXPECT_EQ(steps,
              6);  // map and project written, the journal written and committed, both renamed
    EXPECT_EQ(loadProject(path)->name, "changed");
    EXPECT_NEAR(loadPaintedMap(dir / "perm.png")->values[0], 0.25f, 1e-4);
}

TEST(FaultInjection, AutosaveKeepsThePreviousAutosave) {
    const fs::path dir = test::freshFolder("fault", "autosave");
    const fs::path path = writeBoxProject(dir, 500.0);
    Result<std::unique_ptr<editor::Document>> opened = editor::Document::open(path);
    ASSERT_TRUE(opened.ok()) << opened.error().message;
    editor::Document& d = **opened;
    auto first = editor::makeSetPropertyCommand(d, "/bodies/0/drag_coefficient", 0.7);
    ASSERT_TRUE(first.ok());
    ASSERT_TRUE(d.execute(std::move(first).value()).ok());
    ASSERT_TRUE(d.autosave().ok());
    auto second = editor::makeSetPropertyCommand(d, "/bodies/0/drag_coefficient", 0.9);
    ASSERT_TRUE(second.ok());
    ASSERT_TRUE(d.execute(std::move(second).value()).ok());
    const int steps = interruptAtEveryStep(dir, [&] { return d.autosave(); });
    EXPECT_EQ(steps, 2);
    Result<std::unique_ptr<editor::Document>> recovered =
        editor::Document::recover(*editor::Document::findAutosave(path));
    ASSERT_TRUE(recovered.ok()) << recovered.error().message;
    EXPECT_EQ((*recovered)->project().bodies[0].dragCoefficient, 0.9);
}

// --- OpenCL failures ---------------------------------------------------------------------------

/// The box project on the water (box_half_draft), a few frames' worth of buoyancy evaluations.
Project boxProject() {
    Result<Project> p =
        loadProject(fs::path(PLIMSOLL_SOURCE_DIR) / "projects" / "box_half_draft.plim.json");
    EXPECT_TRUE(p.ok()) << p.error().message;
    return p.ok() ? *p : Project{};
}

/// Runs `frames` frames and returns the bodies' final states and every log line.
struct SimulationRun {
    std::vector<RigidBodyState> states;
    std::vector<std::string> log;
    BackendKind backend = BackendKind::reference;  ///< the backend the run ended on
};
SimulationRun simulate(std::unique_ptr<BuoyancyBackend> backend, int frames) {
    SimulationRun run;
    auto world = World::create(test::sceneOrFail(boxProject()), std::move(backend),
                               [&](const std::string& line) { run.log.push_back(line); });
    EXPECT_TRUE(world.ok()) << world.error().message;
    if (!world.ok()) return run;
    for (int f = 0; f < frames; ++f) {
        const Status s = (*world)->advanceFrame();
        EXPECT_TRUE(s.ok()) << s.error().message;
    }
    for (const SimulatedBody& b : (*world)->bodies()) run.states.push_back(b.state);
    run.backend = (*world)->backend().kind();
    return run;
}

struct OpenClFaultCase {
    detail::OpenClFault kind;
    const char* call;
    const char* code;
};

// ctest lists the case by the call that fails, not by its bytes.
void PrintTo(const OpenClFaultCase& faultCase, std::ostream* out) {
    *out << faultCase.call << " fails with " << faultCase.code;
}

class OpenClFaults : public ::testing::TestWithParam<OpenClFaultCase> {};

// A failure at the first evaluation (buffers, launch or read-back) moves the world to the
// reference backend: one line on the log names the call and the code, and the run then equals
// a run on the reference backend from the start, exactly.
TEST_P(OpenClFaults, WorldFallsBackToTheReferenceOnceAndMatchesIt) {
    const std::vector<ComputeDevice> devices = listComputeDevices();
    if (devices.empty()) GTEST_SKIP() << test::noOpenClDeviceReason();
    const OpenClFaultCase c = GetParam();
    auto opencl = createBuoyancyBackend(std::to_string(devices[0].index));
    ASSERT_TRUE(opencl.ok()) << opencl.error().message;
    detail::failOpenClCallsForTesting(c.kind, 1);
    const SimulationRun fellBack = simulate(std::move(*opencl), 5);
    detail::failOpenClCallsForTesting(c.kind, 0);
    const SimulationRun reference = simulate(createReferenceBackend(), 5);

    int notices = 0;
    for (const std::string& line : fellBack.log) {
        if (line.find("reference backend") == std::string::npos) continue;
        ++notices;
        EXPECT_NE(line.find(c.call), std::string::npos) << line;
        EXPECT_NE(line.find(c.code), std::string::npos) << line;
        EXPECT_NE(line.find("OpenCL"), std::string::npos) << line;
    }
    EXPECT_EQ(notices, 1);
    EXPECT_EQ(fellBack.backend, BackendKind::reference);
    ASSERT_EQ(fellBack.states.size(), reference.states.size());
    for (std::size_t i = 0; i < reference.states.size(); ++i) {
        EXPECT_EQ(fellBack.states[i].position, reference.states[i].position);
        EXPECT_EQ(fellBack.states[i].orientation.coeffs(),
                  reference.states[i].orientation.coeffs());
        EXPECT_EQ(fellBack.states[i].linearMomentum, reference.states[i].linearMomentum);
    }
}

INSTANTIATE_TEST_SUITE_P(
    Kinds, OpenClFaults,
    ::testing::Values(OpenClFaultCase{detail::OpenClFault::BufferAllocation, "clCreateBuffer",
                                      "CL_MEM_OBJECT_ALLOCATION_FAILURE (-4)"},
                      OpenClFaultCase{detail::OpenClFault::Launch, "clEnqueueNDRangeKernel",
                                      "CL_OUT_OF_RESOURCES (-5)"},
                      OpenClFaultCase{detail::OpenClFault::LostDevice, "clEnqueueReadBuffer",
                                      "CL_DEVICE_NOT_AVAILABLE (-2)"}),
    [](const ::testing::TestParamInfo<OpenClFaultCase>& info) {
        return std::string(info.param.call);
    });

TEST(OpenClFaultsBuild, BuildFailureNamesTheCallAndCodeAndAutomaticChoiceFallsBack) {
    const std::vector<ComputeDevice> devices = listComputeDevices();
    if (devices.empty()) GTEST_SKIP() << test::noOpenClDeviceReason();
    // Asked for by name: the error, with the failing call and its code.
    detail::failOpenClCallsForTesting(detail::OpenClFault::Build, 1);
    auto named = createBuoyancyBackend(std::to_string(devices[0].index));
    ASSERT_FALSE(named.ok());
    EXPECT_EQ(named.error().kind, ErrorKind::kernelBuild);
    EXPECT_NE(named.error().message.find("clBuildProgram failed: CL_BUILD_PROGRAM_FAILURE (-11)"),
              std::string::npos)
        << named.error().message;
    // Chosen automatically: a GPU that fails gives way to the fast CPU path, and the notice
    // says why; without a GPU the fast CPU path is the choice and no kernel is built.
    detail::failOpenClCallsForTesting(detail::OpenClFault::Build, 1);
    std::string notice;
    auto automatic = createBuoyancyBackend("", &notice);
    detail::failOpenClCallsForTesting(detail::OpenClFault::Build, 0);
    if (std::getenv("PLIMSOLL_OPENCL_DEVICE")) GTEST_SKIP() << "device chosen by the environment";
    ASSERT_TRUE(automatic.ok()) << automatic.error().message;
    EXPECT_EQ((*automatic)->kind(), BackendKind::fastCpu) << (*automatic)->deviceName();
    const bool gpu =
        std::any_of(devices.begin(), devices.end(), [](const ComputeDevice& d) { return d.isGpu; });
    if (gpu) {
        EXPECT_NE(notice.find("CL_BUILD_PROGRAM_FAILURE"), std::string::npos) << notice;
        EXPECT_NE(notice.find("fast CPU path"), std::string::npos) << notice;
    } else {
        EXPECT_EQ(notice, "");
    }
}

// Buffers are checked against the device's limits before they are allocated: the error names
// the buffer, its size and the limit; the world then goes on on the reference backend.
TEST(OpenClFaultsBuild, BuffersBeyondTheDeviceLimitsAreRefusedBeforeAllocation) {
    const std::vector<ComputeDevice> devices = listComputeDevices();
    if (devices.empty()) GTEST_SKIP() << test::noOpenClDeviceReason();
    for (const auto& [maxAlloc, global, phrase] :
         {std::tuple{std::uint64_t{1024}, std::uint64_t{0},
                     "CL_DEVICE_MAX_MEM_ALLOC_SIZE (1.0 KB)"},
          std::tuple{std::uint64_t{0}, std::uint64_t{4096},
                     "CL_DEVICE_GLOBAL_MEM_SIZE (4.0 KB)"}}) {
        auto opencl = createBuoyancyBackend(std::to_string(devices[0].index));
        ASSERT_TRUE(opencl.ok()) << opencl.error().message;
        detail::setOpenClMemoryLimitsForTesting(maxAlloc, global);
        const SimulationRun run = simulate(std::move(*opencl), 1);
        detail::setOpenClMemoryLimitsForTesting(0, 0);
        bool named = false;
        for (const std::string& line : run.log)
            named = named || line.find(phrase) != std::string::npos;
        EXPECT_TRUE(named) << phrase;
        EXPECT_EQ(run.backend, BackendKind::reference);
    }
}

}  // namespace
}  // namespace test_fault_injection
}  // namespace plimsoll
