// Texture mass properties against the exact mesh integrals, on the sample assets and under
// transformations; shells and combined materials.
#include "plimsoll/physics/massprops.h"
#include "plimsoll/io/painted_map_io.h"
#include "plimsoll/io/mesh_io.h"
#include "plimsoll/surface/painted_map.h"
#include "plimsoll/samples/primitives.h"

#include "test_support.h"

#include <Eigen/Geometry>
#include <stb_image_write.h>

#include <numbers>
#include <unistd.h>

namespace plimsoll {
namespace test_massprops_texture {
namespace {

using test::bakeOrFail;

TEST(TextureMassProperties, SampleAssetsMatchExactWithSecondOrderConvergence) {
    for (const char* name : {"sphere.obj", "box.obj", "cylinder.obj", "buoy.obj"}) {
        Result<TriangleMesh> mesh = loadMesh(test::assetPath(name));
        ASSERT_TRUE(mesh.ok()) << mesh.error().message;
        test::expectTextureMatchesExact(*mesh);
    }
}

TEST(TextureMassProperties, FarFromTheOriginKeepsItsDigits) {
    // A translation changes no texel: only rounding separates the two results.
    const TriangleMesh buoy = makeBuoy();
    const Eigen::Vector3d t(1e5, 3e4, -1e5);
    TriangleMesh moved = buoy;
    for (auto& x : moved.positions) x += t;
    const MassProperties here = textureSolidMassProperties(bakeOrFail(buoy, 256), 1.0);
    const MassProperties there = textureSolidMassProperties(bakeOrFail(moved, 256), 1.0);
    EXPECT_NEAR(there.volume, here.volume, 1e-9 * here.volume);
    EXPECT_LT((there.centerOfMass - (here.centerOfMass + t)).norm(), 1e-9);
    EXPECT_LT((there.inertia - here.inertia).norm(), 1e-8 * here.inertia.norm());
}

TEST(TextureMassProperties, RotatedBodyStaysWithinTheDiscretisationError) {
    // A rotation changes which area-vector component carries each integral, so the results
    // differ by the discretisation error, not more.
    const TriangleMesh buoy = makeBuoy();
    const Eigen::Matrix3d R =
        Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, -2, 0.5).normalized()).toRotationMatrix();
    TriangleMesh turned = buoy;
    for (auto& x : turned.positions) x = R * x;
    const MassProperties exact = exactSolidMassProperties(turned, 1.0);
    const MassProperties textured = textureSolidMassProperties(bakeOrFail(turned, 256), 1.0);
    const test::MassPropsError e = test::compare(textured, exact, computeBounds(buoy).diagonal());
    EXPECT_LT(e.volume, 1e-3);
    EXPECT_LT(e.centerOfMass, 2e-4);
    EXPECT_LT(e.inertia, 3e-3);
}

TEST(TextureMassProperties, ShellMatchesExactShell) {
    for (const TriangleMesh& mesh : {makeBuoy(), makeBox(Eigen::Vector3d(1.0, 0.5, 0.25))}) {
        SCOPED_TRACE(mesh.source);
        const MassProperties exact = exactShellMassProperties(mesh, 12.0);
        const MassProperties textured = textureShellMassProperties(bakeOrFail(mesh, 256), 12.0);
        // Per-texel areas are exact, so the mass is too; centre and inertia are midpoint sums.
        EXPECT_NEAR(textured.mass, exact.mass, 1e-12 * exact.mass);
        EXPECT_LT((textured.centerOfMass - exact.centerOfMass).norm(),
                  2e-4 * computeBounds(mesh).diagonal());
        EXPECT_LT((textured.inertia - exact.inertia).norm(), 1e-3 * exact.inertia.norm());
        EXPECT_NEAR(textured.volume, exactSolidMassProperties(mesh, 1.0).volume,
                    1e-3 * textured.volume);
    }
}

TEST(TextureMassProperties, PaintedShellDensityWeightsTheTexels) {
    // Paint the upper half twice as heavy: the centre of mass moves up, the mass is the
    // area-weighted sum.
    const TriangleMesh box = makeBox(Eigen::Vector3d(1, 1, 1));
    const SurfaceTextures t = bakeOrFail(box, 128);
    std::vector<double> sigma(t.coveredCount());
    double expectedMass = 0;
    for (std::size_t i = 0; i < sigma.size(); ++i) {
        sigma[i] = t.position[i].y() > 0 ? 2.0 : 1.0;
        expectedMass += sigma[i] * t.area[i];
    }
    const MassProperties painted = textureShellMassProperties(t, 0.0, sigma);
    EXPECT_NEAR(painted.mass, expectedMass, 1e-12 * expectedMass);
    EXPECT_GT(painted.centerOfMass.y(), 0.05);
}

// The upper half of a lat-long sphere painted white: a hemispherical shell, whose mass is half
// the sphere's and whose centre sits at r/2 above the centre.
TEST(TextureMassProperties, PaintedMapFileGivesAHemisphericalShell) {
    const int w = 64, h = 256;
    std::vector<std::uint8_t> pixels(w * h);
    for (int row = 0; row < h; ++row)
        for (int x = 0; x < w; ++x) pixels[row * w + x] = row < h / 2 ? 255 : 0;  // row 0: v = 1
    const std::filesystem::path path = std::filesystem::temp_directory_path() /
                                       ("hemisphere_" + std::to_string(::getpid()) + ".png");
    ASSERT_TRUE(stbi_write_png(path.c_str(), w, h, 1, pixels.data(), w));
    Result<PaintedMap> map = loadPaintedMap(path);
    std::filesystem::remove(path);
    ASSERT_TRUE(map.ok()) << map.error().message;

    const double r = 0.5, sigma = 4.0;
    const SurfaceTextures t = bakeOrFail(makeUvSphere(r, 128, 64), 256);
    const MassProperties shell = textureShellMassProperties(t, 0.0, sampleAtTexels(*map, t, sigma));
    const double sphereMass = sigma * 4 * std::numbers::pi * r * r;
    EXPECT_NEAR(shell.mass, 0.5 * sphereMass, 5e-3 * sphereMass);
    EXPECT_NEAR(shell.centerOfMass.y(), 0.5 * r, 5e-3 * r);
    EXPECT_LT(std::hypot(shell.centerOfMass.x(), shell.centerOfMass.z()), 1e-9);

    EXPECT_FALSE(loadPaintedMap("/no/such/map.png").ok());
}

TEST(TextureMassProperties, SolidPlusShellIsTheSumOfBoth) {
    const TriangleMesh sphere = makeUvSphere(0.5, 64, 32);
    const SurfaceTextures t = bakeOrFail(sphere, 256);
    const MassProperties solid = textureSolidMassProperties(t, 500.0);
    const MassProperties shell = textureShellMassProperties(t, 8.0);
    const MassProperties both = solid + shell;
    EXPECT_NEAR(both.mass, solid.mass + shell.mass, 1e-12 * both.mass);
    // Concentric: the inertias just add.
    EXPECT_LT((both.inertia - solid.inertia - shell.inertia).norm(), 1e-6 * both.inertia.norm());
}

}  // namespace
}  // namespace test_massprops_texture
}  // namespace plimsoll
