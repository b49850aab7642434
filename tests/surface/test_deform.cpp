// Deforming meshes: the bake's piece table, the per-frame regather against fresh bakes and the
// exact integrals, and loading the frames of the balloon sample.
#include "plimsoll/bake/bake.h"
#include "plimsoll/surface/deform.h"
#include "plimsoll/physics/massprops.h"
#include "plimsoll/io/mesh_io.h"
#include "plimsoll/samples/primitives.h"

#include "test_support.h"

#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <string>
#include <thread>

namespace plimsoll {
namespace test_deform {
namespace {

namespace fs = std::filesystem;

constexpr int kBalloonFrames = 24;

struct BakeWithPieces {
    SurfaceTextures textures;
    SurfacePieceTable pieces;
};

BakeWithPieces bakeWithPieces(const TriangleMesh& mesh, int size, double maxTexelStretch = 4.0) {
    BakeSettings settings;
    settings.size = size;
    settings.maxTexelStretch = maxTexelStretch;
    BakeWithPieces out;
    Result<SurfaceTextures> r = bakeSurfaceTextures(mesh, settings, &out.pieces);
    EXPECT_TRUE(r.ok()) << (r.ok() ? "" : r.error().message);
    if (r.ok()) out.textures = std::move(r).value();
    return out;
}

SurfaceTextures bakeWithout(const TriangleMesh& mesh, int size, double maxTexelStretch = 4.0) {
    BakeSettings settings;
    settings.size = size;
    settings.maxTexelStretch = maxTexelStretch;
    return test::bakeOrFail(mesh, settings);
}

/// Same entries in the same order, and every value within `tolerance`: positions relative to
/// `length`, area vectors and areas relative to the entry's area.
void expectSameTextures(const SurfaceTextures& a, const SurfaceTextures& b, double length,
                        double tolerance) {
    ASSERT_EQ(a.size, b.size);
    ASSERT_EQ(a.texelIndex, b.texelIndex);
    ASSERT_EQ(a.coverage, b.coverage);
    ASSERT_EQ(a.position.size(), b.position.size());
    for (std::size_t i = 0; i < a.coveredCount(); ++i) {
        ASSERT_LE((a.position[i] - b.position[i]).norm(), tolerance * length) << "entry " << i;
        ASSERT_LE((a.areaVector[i] - b.areaVector[i]).norm(), tolerance * b.area[i])
            << "entry " << i;
        ASSERT_LE(std::abs(a.area[i] - b.area[i]), tolerance * b.area[i]) << "entry " << i;
    }
}

/// The textures with every regathered field overwritten, so a regather must fill them all.
SurfaceTextures scrambled(SurfaceTextures t) {
    for (auto& p : t.position) p.setConstant(-7.0);
    for (auto& a : t.areaVector) a.setConstant(3.0);
    for (double& a : t.area) a = 0.5;
    return t;
}

/// The buoy stretched differently along each axis and bent by a smooth displacement; the same
/// triangles and UVs.
TriangleMesh deformedBuoy() {
    TriangleMesh mesh = makeBuoy();
    for (Eigen::Vector3d& p : mesh.positions) {
        const Eigen::Vector3d q(1.3 * p.x(), 0.8 * p.y(), 1.1 * p.z());
        p = q + 0.04 * Eigen::Vector3d(std::sin(3 * q.y()), std::cos(2 * q.x()) * q.z(),
                                       std::sin(2 * q.z() + q.x()));
    }
    return mesh;
}

std::string balloonFrameName(int k) {
    char name[32];
    std::snprintf(name, sizeof name, "balloon/frame_%03d.obj", k);
    return name;
}

std::vector<fs::path> balloonFramePaths() {
    std::vector<fs::path> paths;
    for (int k = 0; k < kBalloonFrames; ++k) paths.push_back(test::assetPath(balloonFrameName(k)));
    return paths;
}

/// Radius of balloon frame k, as `plimsoll samples` generates it.
double balloonRadius(int k) { return 0.3 * std::pow(2.0, k / (kBalloonFrames - 1.0)); }

TEST(PieceTable, RecordingChangesNoEntry) {
    // Shared texels (box charts at N = 16), sub-texel cells (stretch limit 1) and the plain case.
    const struct {
        TriangleMesh mesh;
        int size;
        double maxTexelStretch;
    } cases[] = {
        {makeBox({1.0, 0.5, 0.25}), 16, 4.0}, {makeBuoy(), 64, 1.0}, {makeBuoy(), 256, 4.0}};
    for (const auto& c : cases) {
        SCOPED_TRACE(c.mesh.source + " at " + std::to_string(c.size));
        const BakeWithPieces with = bakeWithPieces(c.mesh, c.size, c.maxTexelStretch);
        const SurfaceTextures without = bakeWithout(c.mesh, c.size, c.maxTexelStretch);
        expectSameTextures(with.textures, without, 1.0, 0.0);
        EXPECT_EQ(with.pieces.entryCount(), without.coveredCount());
        EXPECT_EQ(with.pieces.firstPiece.back(), with.pieces.pieces.size());
        EXPECT_EQ(with.pieces.triangleCount, c.mesh.triangleCount());
        // Every triangle is cut into pieces that cover it exactly once.
        std::vector<double> share(c.mesh.triangleCount(), 0.0);
        for (const SurfacePiece& piece : with.pieces.pieces) share[piece.triangle] += piece.share;
        for (std::size_t t = 0; t < share.size(); ++t)
            ASSERT_NEAR(share[t], 1.0, 1e-12) << "triangle " << t;
    }
}

TEST(Regather, UndeformedMeshGivesTheBakeBack) {
    const struct {
        TriangleMesh mesh;
        int size;
        double maxTexelStretch;
    } cases[] = {{makeBox({1.0, 0.5, 0.25}), 16, 4.0},  // shared texels, one thread
                 {makeBuoy(), 64, 1.0},                 // sub-texel cells
                 {makeBuoy(), 512, 4.0}};               // worker threads
    for (const auto& c : cases) {
        SCOPED_TRACE(c.mesh.source + " at " + std::to_string(c.size));
        const BakeWithPieces baked = bakeWithPieces(c.mesh, c.size, c.maxTexelStretch);
        SurfaceTextures regathered = scrambled(baked.textures);
        regatherSurface(baked.pieces, c.mesh, regathered);
        expectSameTextures(regathered, baked.textures, computeBounds(c.mesh).diagonal(), 1e-12);
    }
}

TEST(Regather, DeformedMeshEqualsAFreshBake) {
    const TriangleMesh buoy = makeBuoy();
    const TriangleMesh deformed = deformedBuoy();
    for (int size : {128, 512}) {
        SCOPED_TRACE("N = " + std::to_string(size));
        const BakeWithPieces baked = bakeWithPieces(buoy, size);
        SurfaceTextures regathered = baked.textures;
        regatherSurface(baked.pieces, deformed, regathered);
        const SurfaceTextures fresh = bakeWithout(deformed, size);
        expectSameTextures(regathered, fresh, computeBounds(deformed).diagonal(), 1e-9);
        EXPECT_LT(regathered.closureError(), 1e-12);
    }
}

TEST(Regather, ConcurrentCallsGiveWhatOneCallGives) {
    // Two bodies regathered on two threads: one call gets the worker threads, the other runs
    // alone; neither may disturb the other.
    const TriangleMesh buoy = makeBuoy();
    const TriangleMesh deformed = deformedBuoy();
    const BakeWithPieces baked = bakeWithPieces(buoy, 512);
    SurfaceTextures expected = baked.textures;
    regatherSurface(baked.pieces, deformed, expected);
    std::vector<SurfaceTextures> results(4, scrambled(baked.textures));
    std::vector<std::thread> threads;
    for (SurfaceTextures& result : results)
        threads.emplace_back([&] { regatherSurface(baked.pieces, deformed, result); });
    for (std::thread& t : threads) t.join();
    for (const SurfaceTextures& result : results) expectSameTextures(result, expected, 1.0, 0.0);
}

TEST(Regather, BalloonVolumeFollowsTheFrames) {
    Result<std::vector<TriangleMesh>> frames = loadMeshFrames(balloonFramePaths());
    ASSERT_TRUE(frames.ok()) << frames.error().message;
    const BakeWithPieces baked = bakeWithPieces(frames->front(), 256);
    SurfaceTextures textures = baked.textures;
    double firstVolume = 0;
    for (int k = 0; k < kBalloonFrames; ++k) {
        SCOPED_TRACE("frame " + std::to_string(k));
        const TriangleMesh& frame = (*frames)[k];
        regatherSurface(baked.pieces, frame, textures);
        EXPECT_LT(textures.closureError(), 1e-12);
        const double volume = textureSolidMassProperties(textures, 1000.0).volume;
        const double exact = exactSolidMassProperties(frame, 1000.0).volume;
        EXPECT_NEAR(volume, exact, 1e-3 * exact);
        if (k == 0) firstVolume = volume;
        // assimp reads OBJ coordinates as floats: the frames are scaled copies of the first to
        // 1e-7 only.
        const double growth = std::pow(balloonRadius(k) / balloonRadius(0), 3);
        EXPECT_NEAR(volume / firstVolume, growth, 1e-6 * growth);
    }
    // Except the last: twice the first radius, and doubling commutes with rounding to float.
    EXPECT_NEAR(textureSolidMassProperties(textures, 1000.0).volume / firstVolume, 8.0, 1e-12);
}

TEST(MeshFrames, BalloonFramesAreTheGeneratorOutput) {
    for (int k = 0; k < kBalloonFrames; ++k) {
        const fs::path written = test::scratchFolder("plimsoll_test_deform") / "frame.obj";
        ASSERT_TRUE(writeObj(makeUvSphere(balloonRadius(k), 32, 16), written).ok());
        const std::string expected = test::readFile(test::assetPath(balloonFrameName(k)));
        ASSERT_FALSE(expected.empty()) << balloonFrameName(k) << " missing";
        EXPECT_TRUE(test::readFile(written) == expected)
            << balloonFrameName(k)
            << " differs from the generator: run `plimsoll samples --out assets`";
    }
}

TEST(MeshFrames, BalloonFramesLoadWithOneTopology) {
    Result<std::vector<TriangleMesh>> frames = loadMeshFrames(balloonFramePaths());
    ASSERT_TRUE(frames.ok()) << frames.error().message;
    ASSERT_EQ(frames->size(), static_cast<std::size_t>(kBalloonFrames));
    const TriangleMesh sphere = makeUvSphere(0.3, 32, 16);
    for (const TriangleMesh& frame : *frames) {
        // Not joined: one vertex per triangle corner, so no frame depends on which of its
        // positions coincide.
        EXPECT_EQ(frame.triangleCount(), sphere.triangleCount());
        EXPECT_EQ(frame.vertexCount(), 3 * sphere.triangleCount());
        EXPECT_EQ(frame.triangles, frames->front().triangles);
        EXPECT_EQ(frame.uvs, frames->front().uvs);
    }
}

TEST(MeshFrames, OtherTopologyOrUvsAreRefusedNamingTheFile) {
    const fs::path first = test::assetPath(balloonFrameName(0));
    const fs::path coarser = test::scratchFolder("plimsoll_test_deform") / "coarser.obj";
    ASSERT_TRUE(writeObj(makeUvSphere(0.4, 24, 16), coarser).ok());
    Result<std::vector<TriangleMesh>> frames = loadMeshFrames({first, coarser});
    ASSERT_FALSE(frames.ok());
    EXPECT_NE(frames.error().message.find(coarser.string()), std::string::npos)
        << frames.error().message;
    EXPECT_NE(frames.error().message.find("720 triangles"), std::string::npos)
        << frames.error().message;
    EXPECT_NE(frames.error().message.find("has 960"), std::string::npos) << frames.error().message;

    TriangleMesh shifted = makeUvSphere(0.4, 32, 16);
    for (Eigen::Vector2d& uv : shifted.uvs) uv.x() = 0.5 * uv.x();
    const fs::path otherUvs = test::scratchFolder("plimsoll_test_deform") / "other_uvs.obj";
    ASSERT_TRUE(writeObj(shifted, otherUvs).ok());
    frames = loadMeshFrames({first, otherUvs});
    ASSERT_FALSE(frames.ok());
    EXPECT_NE(frames.error().message.find(otherUvs.string()), std::string::npos)
        << frames.error().message;
    EXPECT_NE(frames.error().message.find("texture coordinates"), std::string::npos)
        << frames.error().message;

    frames = loadMeshFrames({first, test::scratchFolder("plimsoll_test_deform") / "missing.obj"});
    ASSERT_FALSE(frames.ok());
    EXPECT_NE(frames.error().message.find("missing.obj"), std::string::npos);
}

}  // namespace
}  // namespace test_deform
}  // namespace plimsoll
