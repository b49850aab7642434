// The public meshes in ../shared/meshes (skipped where that folder is absent): exact values
// from its README, texture results against them, and the meshes that must be refused.
#include "plimsoll/physics/massprops.h"
#include "plimsoll/io/mesh_io.h"
#include "plimsoll/geometry/validate.h"

#include "test_support.h"

namespace plimsoll {
namespace test_shared_meshes {
namespace {

struct ReadmeValues {
    const char* file;
    double volume;
    Eigen::Vector3d centroid;
};

// Exact rational volumes and centroids from shared/meshes/README.md. assimp reads floats:
// the README bounds the effect of float32 coordinates by 3.3e-8 relative.
const ReadmeValues kReadme[] = {
    {"spot.obj", 0.71825878809986465, {-1.21811e-06, -0.0103440994451, 0.188277059136}},
    {"blub_triangulated.obj", 1.1294754495158845, {5.45074e-07, 0.0109857452351, -0.026067175659}},
    {"boat.obj", 11.917735678366384, {-3.25606140147, 1.64702917226, -1.13713098}},
    {"cube.obj", 8.0, {0, 0, 0}},
    {"sphere.obj", 4.1526848700457224, {0, 0, 0}},
    {"torus.obj", 1.2187844954159752, {0, 0, 0}},
    {"bunny.obj", 0.74933410816064661, {-0.0408643799386, -0.233787993823, 0.125095737593}},
};

TEST(SharedMeshes, ExactMassPropertiesMatchTheReadme) {
    int checked = 0;
    for (const ReadmeValues& expected : kReadme) {
        std::optional<TriangleMesh> mesh = test::loadSharedMesh(expected.file);
        if (!mesh) continue;
        SCOPED_TRACE(expected.file);
        const ValidationReport report = validateMesh(*mesh);
        EXPECT_TRUE(report.closedSolid()) << report.format();
        const MassProperties p = exactSolidMassProperties(*mesh, 1.0);
        EXPECT_NEAR(p.volume, expected.volume, 5e-8 * expected.volume);
        EXPECT_LT((p.centerOfMass - expected.centroid).norm(),
                  1e-6 * computeBounds(*mesh).diagonal());
        ++checked;
    }
    if (checked == 0) GTEST_SKIP() << "../shared/meshes not present";
}

TEST(SharedMeshes, TextureResultsMatchExactOnMeshesWithUsableUvs) {
    int checked = 0;
    for (const char* name : {"spot.obj", "blub_triangulated.obj", "cube.obj"}) {
        std::optional<TriangleMesh> mesh = test::loadSharedMesh(name);
        if (!mesh) continue;
        const ValidationReport report = validateMesh(*mesh);
        ASSERT_TRUE(report.usableForTexture()) << report.format();
        test::expectTextureMatchesExact(*mesh);
        ++checked;
    }
    if (checked == 0) GTEST_SKIP() << "../shared/meshes not present";
}

TEST(SharedMeshes, BoatUvsAreOutOfRangeAndOverlapSoTheTexturePathRefusesIt) {
    std::optional<TriangleMesh> boat = test::loadSharedMesh("boat.obj");
    if (!boat) GTEST_SKIP() << "../shared/meshes not present";
    const ValidationReport report = validateMesh(*boat);
    EXPECT_TRUE(report.has(ProblemKind::UvOutOfRange));
    EXPECT_TRUE(report.has(ProblemKind::UvOverlap));
    EXPECT_FALSE(report.usableForTexture());
    EXPECT_TRUE(report.closedSolid());  // the exact path still works
    for (const Problem& p : report.problems) {
        const bool expected =
            p.kind == ProblemKind::UvOutOfRange || p.kind == ProblemKind::UvOverlap;
        EXPECT_TRUE(expected) << "unexpected problem: " << p.message;
    }
}

TEST(SharedMeshes, OpenTeapotAndUvlessMeshesAreReported) {
    std::optional<TriangleMesh> teapot = test::loadSharedMesh("teapot.obj");
    if (!teapot) GTEST_SKIP() << "../shared/meshes not present";
    const ValidationReport open = validateMesh(*teapot);
    EXPECT_TRUE(open.has(ProblemKind::OpenSurface));
    EXPECT_FALSE(open.closedSolid());
    for (const char* name : {"bunny.obj", "sphere.obj", "torus.obj"}) {
        std::optional<TriangleMesh> mesh = test::loadSharedMesh(name);
        ASSERT_TRUE(mesh);
        const ValidationReport report = validateMesh(*mesh);
        EXPECT_TRUE(report.has(ProblemKind::MissingUvs)) << name;
        EXPECT_TRUE(report.closedSolid()) << name;
    }
}

}  // namespace
}  // namespace test_shared_meshes
}  // namespace plimsoll
