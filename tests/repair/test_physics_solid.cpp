// The physics solid of surfaces that are not one closed solid: every repair against an exact
// volume (boxes, their unions) or an independent estimate (generalized winding numbers).
#include "test_support.h"
#include "repair/repair_support.h"

#include "plimsoll/graph/graph.h"  // windingNumber: the independent inside test
#include "plimsoll/geometry/box.h"
#include "plimsoll/geometry/validate.h"
#include "plimsoll/io/mesh_io.h"
#include "plimsoll/physics/massprops.h"
#include "plimsoll/repair/physics_solid.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>

namespace plimsoll {
namespace test_physics_solid {
namespace {

TriangleMesh translated(TriangleMesh mesh, const Eigen::Vector3d& by) {
    for (Eigen::Vector3d& p : mesh.positions) p += by;
    return mesh;
}

/// The two meshes' triangles in one mesh (vertices not shared).
TriangleMesh joined(const TriangleMesh& a, const TriangleMesh& b) {
    TriangleMesh out = a;
    out.source = "joined";
    const auto base = static_cast<std::uint32_t>(out.positions.size());
    out.positions.insert(out.positions.end(), b.positions.begin(), b.positions.end());
    out.uvs.insert(out.uvs.end(), b.uvs.begin(), b.uvs.end());
    for (const Triangle& t : b.triangles) out.triangles.push_back({base + t[0], base + t[1], base + t[2]});
    return out;
}

const Repair* findRepair(const PhysicsSolid& solid, const std::string& kind) {
    for (const Repair& r : solid.repairs)
        if (r.kind == kind) return &r;
    return nullptr;
}

PhysicsSolid solidOf(const TriangleMesh& mesh) {
    Result<PhysicsSolid> solid = physicsSolidFor(mesh, validateSurface(mesh));
    EXPECT_TRUE(solid.ok()) << solid.error().message;
    if (!solid) return {};
    EXPECT_TRUE(validateSurface(solid->mesh).closedSolid());
    // The reported volume is the solid's own.
    EXPECT_NEAR(exactSolidMassProperties(solid->mesh, 1.0).volume, solid->materialVolume,
                1e-9 * std::max(1.0, solid->materialVolume));
    return std::move(*solid);
}


TEST(PhysicsSolid, AClosedMeshIsUsedAsItIs) {
    const TriangleMesh box = makeBox({1, 2, 3});
    const PhysicsSolid solid = solidOf(box);
    EXPECT_TRUE(solid.repairs.empty());
    EXPECT_EQ(solid.mesh.positions, box.positions);  // UVs, vertices and all
    EXPECT_EQ(solid.mesh.uvs, box.uvs);
    EXPECT_NEAR(solid.materialVolume, 6.0, 1e-12);
    EXPECT_EQ(solid.displacementVolume, solid.materialVolume);
}

TEST(PhysicsSolid, OverlappingBoxesCountTheirOverlapOnce) {
    SKIP_WITHOUT_REPAIR();
    // Two unit cubes overlapping by half along x: the union is 1.5 m^3, the sum 2.
    const TriangleMesh mesh = joined(makeBox({1, 1, 1}), translated(makeBox({1, 1, 1}), {0.5, 0.2, 0.1}));
    ASSERT_FALSE(validateSurface(mesh).closedSolid() && exactSolidMassProperties(mesh, 1).volume < 1.9);
    const PhysicsSolid solid = solidOf(mesh);
    const double overlap = 0.5 * 0.8 * 0.9;
    EXPECT_NEAR(solid.materialVolume, 2.0 - overlap, 1e-9);
    const Repair* unionRepair = findRepair(solid, "union");
    ASSERT_NE(unionRepair, nullptr);
    EXPECT_EQ(unionRepair->count, 1u);
    EXPECT_NEAR(unionRepair->volumeChange, -overlap, 1e-9);
}

TEST(PhysicsSolid, ADuplicateCopyAndBackToBackFacesAreDropped) {
    SKIP_WITHOUT_REPAIR();
    const TriangleMesh box = makeBox({1, 1, 1});
    const PhysicsSolid copy = solidOf(joined(box, box));
    EXPECT_NEAR(copy.materialVolume, 1.0, 1e-12);
    ASSERT_NE(findRepair(copy, "duplicate-faces"), nullptr);
    EXPECT_EQ(findRepair(copy, "duplicate-faces")->count, 12u);
    // Double-sided: every face again, turned the other way.
    TriangleMesh back = box;
    for (Triangle& t : back.triangles) std::swap(t[1], t[2]);
    const PhysicsSolid doubled = solidOf(joined(box, back));
    EXPECT_NEAR(doubled.materialVolume, 1.0, 1e-12);
    EXPECT_EQ(findRepair(doubled, "duplicate-faces")->count, 12u);
}

TEST(PhysicsSolid, FlippedAndInwardFacesAreOriented) {
    SKIP_WITHOUT_REPAIR();
    TriangleMesh box = makeBox({2, 1, 1});
    std::swap(box.triangles[3][1], box.triangles[3][2]);
    std::swap(box.triangles[7][1], box.triangles[7][2]);
    const PhysicsSolid fixed = solidOf(box);
    EXPECT_NEAR(fixed.materialVolume, 2.0, 1e-12);
    ASSERT_NE(findRepair(fixed, "orient"), nullptr);
    // Inside out: every face turned.
    TriangleMesh inward = makeBox({2, 1, 1});
    for (Triangle& t : inward.triangles) std::swap(t[1], t[2]);
    const PhysicsSolid outward = solidOf(inward);
    EXPECT_NEAR(outward.materialVolume, 2.0, 1e-12);
    EXPECT_EQ(findRepair(outward, "orient")->count, 12u);
}

TEST(PhysicsSolid, ACrackWithinTheToleranceIsWelded) {
    SKIP_WITHOUT_REPAIR();
    // Each face its own vertices, moved by up to 1e-8 m: a box whose seams do not meet.
    const TriangleMesh box = makeBox({1, 1, 1});
    TriangleMesh cracked;
    cracked.source = "cracked";
    std::mt19937 random(3);
    std::uniform_real_distribution<double> jitter(-1e-8, 1e-8);
    for (const Triangle& t : box.triangles) {
        const auto base = static_cast<std::uint32_t>(cracked.positions.size());
        for (std::uint32_t v : t)
            cracked.positions.push_back(box.positions[v] + Eigen::Vector3d(jitter(random), jitter(random), jitter(random)));
        cracked.triangles.push_back({base, base + 1, base + 2});
    }
    ASSERT_FALSE(validateSurface(cracked).closedSolid());
    const PhysicsSolid solid = solidOf(cracked);
    EXPECT_NEAR(solid.materialVolume, 1.0, 1e-6);
    ASSERT_NE(findRepair(solid, "weld"), nullptr);
}

TEST(PhysicsSolid, AnOpenSheetIsLeftOutOfTheVolume) {
    SKIP_WITHOUT_REPAIR();
    // A unit cube with a 2 x 2 sail standing on it.
    TriangleMesh sail;
    sail.positions = {{-1, 0.5, 0}, {1, 0.5, 0}, {1, 2.5, 0}, {-1, 2.5, 0}};
    sail.triangles = {{0, 1, 2}, {0, 2, 3}};
    TriangleMesh box = makeBox({1, 1, 1});
    box.uvs.clear();
    const PhysicsSolid solid = solidOf(joined(box, sail));
    EXPECT_NEAR(solid.materialVolume, 1.0, 1e-12);
    ASSERT_NE(findRepair(solid, "open-sheets"), nullptr);
    EXPECT_EQ(findRepair(solid, "open-sheets")->count, 1u);
    EXPECT_EQ(findRepair(solid, "wrap"), nullptr);
}

TEST(PhysicsSolid, NoSolidFromNothing) {
    SKIP_WITHOUT_REPAIR();
    TriangleMesh empty;
    empty.source = "empty.obj";
    Result<PhysicsSolid> none = buildPhysicsSolid(empty);
    ASSERT_FALSE(none.ok());
    EXPECT_NE(none.error().message.find("empty.obj"), std::string::npos);
    EXPECT_NE(none.error().message.find("no triangles"), std::string::npos);
    // A point cloud: triangles whose corners coincide.
    TriangleMesh cloud;
    cloud.source = "cloud.ply";
    for (int i = 0; i < 30; ++i) {
        cloud.positions.push_back(Eigen::Vector3d(i, i * i % 7, i % 3));
        cloud.triangles.push_back({std::uint32_t(i), std::uint32_t(i), std::uint32_t(i)});
    }
    Result<PhysicsSolid> points = buildPhysicsSolid(cloud);
    ASSERT_FALSE(points.ok());
    EXPECT_NE(points.error().message.find("cloud.ply"), std::string::npos);
    EXPECT_NE(points.error().message.find("no face with area"), std::string::npos);
    TriangleMesh nan = makeBox({1, 1, 1});
    nan.source = "nan.obj";
    nan.positions[0].x() = std::nan("");
    EXPECT_FALSE(buildPhysicsSolid(nan).ok());
}

TEST(PhysicsSolid, TheBarrelsVolumeIsItsUnionsByMonteCarlo) {
    SKIP_WITHOUT_REPAIR();
    const std::filesystem::path file =
        std::filesystem::path(PLIMSOLL_SHARED_DIR) / "real-assets" / "quaternius" / "Barrel.fbx";
    if (!std::filesystem::exists(file)) GTEST_SKIP() << "../shared/real-assets not present";
    Result<TriangleMesh> barrel = loadMesh(file);
    ASSERT_TRUE(barrel.ok()) << barrel.error().message;
    const PhysicsSolid solid = solidOf(*barrel);
    ASSERT_NE(findRepair(solid, "union"), nullptr);
    const double summed = exactSolidMassProperties(*barrel, 1.0).volume;  // the parts added up

    // Independent estimate: uniform points in the bounding box, inside the union where the
    // winding number of the artist's surface is at least 1/2.
    const Bounds3 box = computeBounds(*barrel);
    const Eigen::Vector3d size = box.max - box.min;
    std::mt19937_64 random(7);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    const int samples = 80000;
    int inside = 0;
    for (int i = 0; i < samples; ++i) {
        const Eigen::Vector3d p = box.min + size.cwiseProduct(Eigen::Vector3d(unit(random), unit(random), unit(random)));
        if (windingNumber(*barrel, p) >= 0.5) ++inside;
    }
    const double share = double(inside) / samples;
    const double estimate = share * size.prod();
    const double standardError = std::sqrt(share * (1 - share) / samples) * size.prod();
    std::cout << "Barrel.fbx: union " << solid.materialVolume << " m^3, Monte Carlo " << estimate
              << " +- " << standardError << " m^3 (" << samples << " points), parts summed "
              << summed << " m^3\n";
    ASSERT_LT(3 * standardError, 0.01 * estimate);  // the estimate is good to better than 1%
    EXPECT_NEAR(solid.materialVolume, estimate, 0.02 * estimate);
    EXPECT_LT(solid.materialVolume, summed);  // the hoops overlap the body
}

}  // namespace
}  // namespace test_physics_solid
}  // namespace plimsoll
