// Helpers shared by the tests: where the data lives, and error measures.
#pragma once

#include "plimsoll/physics/massprops.h"
#include "plimsoll/graph_auto/graph_auto.h"
#include "plimsoll/geometry/mesh.h"
#include "plimsoll/io/mesh_io.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <mutex>
#include <set>
#include <sstream>
#include <optional>
#include <string>

/// `text` (anything a std::string is made from) contains `part`; the message shows `text`.
#define EXPECT_CONTAINS(text, part) \
    EXPECT_NE(std::string(text).find(part), std::string::npos) << (text)

namespace plimsoll::test {

/// True in the ASan + UBSan build (PLIMSOLL_SANITIZE, scripts/test-sanitized.sh), where numeric
/// loops run about twenty times slower: the few tests whose cost is simulated time use less of
/// it there, and say what they check instead.
#ifdef PLIMSOLL_SANITIZED_BUILD
inline constexpr bool kSanitizedBuild = true;
#else
inline constexpr bool kSanitizedBuild = false;
#endif

/// A mesh in ../shared/meshes, or nothing when the folder is absent (a user's machine).
inline std::optional<std::filesystem::path> sharedMesh(const std::string& name) {
    std::filesystem::path path = std::filesystem::path(PLIMSOLL_SHARED_DIR) / "meshes" / name;
    if (!std::filesystem::exists(path)) return std::nullopt;
    return path;
}

inline std::filesystem::path assetPath(const std::string& name) {
    return std::filesystem::path(PLIMSOLL_ASSETS_DIR) / name;
}

/// Errors of a mass-property result against a reference, in the measures the issue fixes:
/// volume relative, centre of mass relative to the bounding-box diagonal, inertia relative in
/// the Frobenius norm.
struct MassPropsError {
    double volume;
    double centerOfMass;
    double inertia;
};

inline MassPropsError compare(const MassProperties& result, const MassProperties& reference,
                              double boundsDiagonal) {
    return {std::abs(result.volume - reference.volume) / std::abs(reference.volume),
            (result.centerOfMass - reference.centerOfMass).norm() / boundsDiagonal,
            (result.inertia - reference.inertia).norm() / reference.inertia.norm()};
}

}  // namespace plimsoll::test

#include "plimsoll/bake/bake.h"

namespace plimsoll::test {

inline SurfaceTextures bakeOrFail(const TriangleMesh& mesh, const BakeSettings& settings) {
    Result<SurfaceTextures> r = bakeSurfaceTextures(mesh, settings);
    EXPECT_TRUE(r.ok()) << (r.ok() ? "" : r.error().message);
    return r.ok() ? std::move(r).value() : SurfaceTextures{};
}

inline SurfaceTextures bakeOrFail(const TriangleMesh& mesh, int size) {
    BakeSettings settings;
    settings.size = size;
    return bakeOrFail(mesh, settings);
}

inline std::string readFile(const std::filesystem::path& path) {
    std::ifstream in(path, std::ios::binary);
    std::ostringstream text;
    text << in.rdbuf();
    return text.str();
}

/// The scratch folders a test process made, removed when it exits: a suite run leaves nothing
/// in the temporary folder. They stay for a look where a test of the process failed or
/// PLIMSOLL_KEEP_TEST_FILES is set. A child the test forked leaves them to its parent.
class ScratchFolders {
public:
    void add(const std::filesystem::path& dir) {
        const std::lock_guard<std::mutex> lock(mutex_);
        folders_.insert(dir);
    }
    ~ScratchFolders() {
        if (::getpid() != owner_ || std::getenv("PLIMSOLL_KEEP_TEST_FILES")) return;
        const testing::UnitTest* run = testing::UnitTest::GetInstance();
        if (run && run->failed_test_count() > 0) return;
        for (const std::filesystem::path& dir : folders_) {
            std::error_code ignored;
            std::filesystem::remove_all(dir, ignored);
        }
    }

private:
    const pid_t owner_ = ::getpid();
    std::mutex mutex_;
    std::set<std::filesystem::path> folders_;
};

inline ScratchFolders& scratchFolders() {
    static ScratchFolders folders;
    return folders;
}

/// A folder of the test's own under the temporary folder, created on first use.
inline std::filesystem::path scratchFolder(const std::string& name) {
    // One folder per process: ctest runs the suite's tests as parallel processes, and two
    // checkouts' suites may run at once.
    const std::filesystem::path dir =
        std::filesystem::path(testing::TempDir()) / (name + "_" + std::to_string(::getpid()));
    std::filesystem::create_directories(dir);
    scratchFolders().add(dir);
    return dir;
}

/// An empty folder `name` inside the process's scratch folder `area` (emptied if it exists).
inline std::filesystem::path freshFolder(const std::string& area, const std::string& name) {
    const std::filesystem::path dir = scratchFolder(area) / name;
    std::filesystem::remove_all(dir);
    std::filesystem::create_directories(dir);
    return dir;
}

/// Replaces the file at `path` with exactly `bytes`.
inline void writeFile(const std::filesystem::path& path, const std::string& bytes) {
    std::ofstream(path, std::ios::binary | std::ios::trunc) << bytes;
}

/// The error message of a Status or Result, empty when it succeeded.
template <typename StatusOrResult>
std::string messageOf(const StatusOrResult& r) {
    return r.ok() ? std::string() : r.error().message;
}

/// A mesh of ../shared/meshes loaded, or nothing when the folder is absent (a failed load
/// fails the test).
inline std::optional<TriangleMesh> loadSharedMesh(const std::string& name) {
    const std::optional<std::filesystem::path> path = sharedMesh(name);
    if (!path) return std::nullopt;
    Result<TriangleMesh> mesh = loadMesh(*path);
    EXPECT_TRUE(mesh.ok()) << messageOf(mesh);
    if (!mesh.ok()) return std::nullopt;
    return std::move(mesh).value();
}

/// ../shared/real-assets: the game models as artists have them (may be absent).
inline std::filesystem::path realAssetsDir() {
    return std::filesystem::path(PLIMSOLL_SHARED_DIR) / "real-assets";
}

/// The acceptance measure for texture mass properties: at N = 256 the volume within
/// 1e-3 relative, the centre of mass within 2e-4 of the bounding-box diagonal, the inertia
/// within 3e-3 relative (Frobenius); at N = 512 every error at most 0.35 of its N = 256 value
/// (second order). The convergence check applies where the N = 256 error is at least 1% of its
/// tolerance: far below that, the error is what is left after symmetric parts of the surface
/// cancel (the centre of mass of a symmetric body: the facets alias against the texel grid),
/// and it halves or doubles with N at random (cylinder.obj: 5.7e-8, 3.1e-8, 2.9e-8, then
/// 1e-10 at N = 4096).
/// `secondOrder` false leaves out the N = 512 convergence check (for atlases packed for N = 256,
/// whose errors far below the tolerance scatter with N).
inline void expectTextureMatchesExact(const TriangleMesh& mesh, bool secondOrder = true) {
    SCOPED_TRACE(mesh.source);
    const double diagonal = computeBounds(mesh).diagonal();
    const MassProperties exact = exactSolidMassProperties(mesh, 1000.0);
    const SurfaceTextures t256 = bakeOrFail(mesh, 256);
    const SurfaceTextures t512 = bakeOrFail(mesh, 512);
    EXPECT_LT(t256.closureError(), 1e-9);
    EXPECT_LT(t512.closureError(), 1e-9);
    const MassPropsError e256 = compare(textureSolidMassProperties(t256, 1000.0), exact, diagonal);
    const MassPropsError e512 = compare(textureSolidMassProperties(t512, 1000.0), exact, diagonal);
    EXPECT_LT(e256.volume, 1e-3);
    EXPECT_LT(e256.centerOfMass, 2e-4);
    EXPECT_LT(e256.inertia, 3e-3);
    const auto expectSecondOrder = [secondOrder](double coarse, double fine, double tolerance,
                                                 const char* what) {
        if (secondOrder && coarse >= 0.01 * tolerance) EXPECT_LE(fine, 0.35 * coarse) << what;
    };
    expectSecondOrder(e256.volume, e512.volume, 1e-3, "volume");
    expectSecondOrder(e256.centerOfMass, e512.centerOfMass, 2e-4, "centre of mass");
    expectSecondOrder(e256.inertia, e512.inertia, 3e-3, "inertia");
    std::printf(
        "  %-28s N=256: vol %.2e com %.2e inertia %.2e | N=512: vol %.2e com %.2e "
        "inertia %.2e\n",
        std::filesystem::path(mesh.source).filename().c_str(), e256.volume, e256.centerOfMass,
        e256.inertia, e512.volume, e512.centerOfMass, e512.inertia);
}

}  // namespace plimsoll::test

#include "plimsoll/compute/compute.h"
#include "plimsoll/graph/graph.h"

#include <memory>
#include <vector>

namespace plimsoll::test {

/// Why a test that needs an OpenCL device skips here: the machine has none, or the build.
inline const char* noOpenClDeviceReason() {
    return openClAvailable() ? "no OpenCL device"
                             : "this build has no OpenCL (PLIMSOLL_WITH_OPENCL=OFF)";
}

/// Skips a test of automatic water graphs in a build without CGAL's segmentation.
#define PLIMSOLL_SKIP_WITHOUT_CGAL()              \
    if (!::plimsoll::meshSegmentationAvailable()) \
    GTEST_SKIP() << "this build has no CGAL (PLIMSOLL_WITH_CGAL=OFF): no automatic graphs"

/// A backend on every OpenCL device the machine has (none is fine: the kernels then have
/// nothing to check).
inline std::vector<std::unique_ptr<BuoyancyBackend>> openClBackends() {
    std::vector<std::unique_ptr<BuoyancyBackend>> out;
    for (const ComputeDevice& device : listComputeDevices()) {
        auto backend = createBuoyancyBackend(std::to_string(device.index));
        EXPECT_TRUE(backend.ok()) << backend.error().message;
        if (backend.ok()) out.push_back(std::move(*backend));
    }
    return out;
}

}  // namespace plimsoll::test
