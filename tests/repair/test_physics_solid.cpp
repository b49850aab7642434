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

#include <algorithm>
#include <cmath>
#include <iostream>
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
    for (const Triangle& t : b.triangles)
        out.triangles.push_back({base + t[0], base + t[1], base + t[2]});
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
    const TriangleMesh mesh =
        joined(makeBox({1, 1, 1}), translated(makeBox({1, 1, 1}), {0.5, 0.2, 0.1}));
    ASSERT_FALSE(validateSurface(mesh).closedSolid() &&
                 exactSolidMassProperties(mesh, 1).volume < 1.9);
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
            cracked.positions.push_back(
                box.positions[v] + Eigen::Vector3d(jitter(random), jitter(random), jitter(random)));
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

/// An open box of the given size standing on y = 0, centred on x and z, without its top and
/// without thickness: a hull or tub modelled as one surface (its five faces share their corners).
TriangleMesh openTub(const Eigen::Vector3d& size) {
    TriangleMesh tub;
    tub.source = "tub";
    const double x = size.x() / 2, y = size.y(), z = size.z() / 2;
    tub.positions = {{-x, 0, -z}, {x, 0, -z}, {x, 0, z}, {-x, 0, z},
                     {-x, y, -z}, {x, y, -z}, {x, y, z}, {-x, y, z}};
    // Outward normals: bottom down, sides out.
    tub.triangles = {{0, 1, 2}, {0, 2, 3},                         // bottom
                     {0, 4, 5}, {0, 5, 1}, {1, 5, 6}, {1, 6, 2},   // z = -z, x = +x
                     {2, 6, 7}, {2, 7, 3}, {3, 7, 4}, {3, 4, 0}};  // z = +z, x = -x
    return tub;
}

/// A closed box from `min` to `max`, its UVs dropped.
TriangleMesh boxBetween(const Eigen::Vector3d& min, const Eigen::Vector3d& max) {
    TriangleMesh box = translated(makeBox(max - min), 0.5 * (min + max));
    box.uvs.clear();
    return box;
}

/// A sail: a vertical sheet in x and y, bellied along z (a quarter of its width deep), n x n
/// quads, free along all its edges.
TriangleMesh bellySail(const Eigen::Vector3d& corner, double width, double height, int n) {
    TriangleMesh sail;
    sail.source = "sail";
    for (int j = 0; j <= n; ++j)
        for (int i = 0; i <= n; ++i) {
            const double u = double(i) / n, v = double(j) / n;
            sail.positions.push_back(
                corner + Eigen::Vector3d(u * width, v * height,
                                         0.25 * width * std::sin(std::numbers::pi * u)));
        }
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            const auto a = std::uint32_t(j * (n + 1) + i), b = a + 1, c = a + n + 2, d = a + n + 1;
            sail.triangles.push_back({a, b, c});
            sail.triangles.push_back({a, c, d});
        }
    return sail;
}

TEST(PhysicsSolid, AnOpenHullBesideAMastIsKeptAsThinWallsAndCapped) {
    SKIP_WITHOUT_REPAIR();
    // A 2 x 0.5 x 1 m tub without thickness and a closed 0.1 m square mast standing in it from
    // 0.1 m to 1.6 m: the sealed hull is the tub's box and the mast above its rim.
    const Eigen::Vector3d size(2, 0.5, 1);
    const TriangleMesh mast = boxBetween({-0.05, 0.1, -0.05}, {0.05, 1.6, 0.05});
    const TriangleMesh mesh = joined(openTub(size), mast);
    Result<PhysicsSolid> built = physicsSolidFor(mesh, validateSurface(mesh));
    ASSERT_TRUE(built.ok()) << built.error().message;
    const PhysicsSolid& solid = *built;
    EXPECT_TRUE(validateSurface(solid.mesh).closedSolid());
    ASSERT_NE(findRepair(solid, "open-hulls"), nullptr) << describeRepairs(solid.repairs);
    EXPECT_EQ(findRepair(solid, "open-hulls")->count, 1u);
    EXPECT_EQ(findRepair(solid, "open-sheets"), nullptr);
    ASSERT_EQ(solid.openings.size(), 1u) << describeRepairs(solid.repairs);
    const double sealed = size.prod() + 0.1 * 0.1 * (1.6 - size.y());
    // The walls are as thick as the wrap's two offsets, a share of the box's diagonal: a few
    // millimetres on 5 m^2, and the cap sits at the rim within them.
    const double diagonal = Eigen::Vector3d(2, 1.6, 1).norm();
    const double walls = 5.0 * 2 * RepairSettings{}.wrapOffset * diagonal;
    EXPECT_NEAR(solid.openings[0].capHeight, size.y(), 4 * RepairSettings{}.wrapOffset * diagonal);
    EXPECT_NEAR(solid.displacementVolume, sealed, 0.02 * sealed);
    EXPECT_GT(solid.materialVolume, 0.1 * 0.1 * 1.5);              // the mast ...
    EXPECT_LT(solid.materialVolume, 0.1 * 0.1 * 1.5 + 3 * walls);  // ... and thin walls
    EXPECT_NEAR(exactSolidMassProperties(solid.mesh, 1.0).volume, solid.displacementVolume,
                1e-9 * solid.displacementVolume);
}

TEST(PhysicsSolid, ASailAndAnUpsideDownTubStayOutOfTheVolume) {
    SKIP_WITHOUT_REPAIR();
    const TriangleMesh mast = boxBetween({-0.05, 0, -0.05}, {0.05, 2, 0.05});
    // A bellied sail beside the mast: it opens sideways, and holds no water.
    const PhysicsSolid sailed = solidOf(joined(mast, bellySail({0.1, 0.3, 0}, 1.0, 1.5, 8)));
    EXPECT_NEAR(sailed.materialVolume, 0.1 * 0.1 * 2, 1e-12);
    ASSERT_NE(findRepair(sailed, "open-sheets"), nullptr);
    EXPECT_EQ(findRepair(sailed, "open-sheets")->count, 1u);
    EXPECT_EQ(findRepair(sailed, "open-hulls"), nullptr);
    EXPECT_TRUE(sailed.openings.empty());
    // The tub turned over (a roof, an awning) opens downwards: it holds no water either.
    TriangleMesh roof = openTub({1, 0.3, 1});
    for (Eigen::Vector3d& p : roof.positions) p = Eigen::Vector3d(p.x() + 1, 2.5 - p.y(), p.z());
    for (Triangle& t : roof.triangles) std::swap(t[1], t[2]);
    const PhysicsSolid roofed = solidOf(joined(mast, roof));
    EXPECT_NEAR(roofed.materialVolume, 0.1 * 0.1 * 2, 1e-12);
    EXPECT_EQ(findRepair(roofed, "open-hulls"), nullptr);
    // A tub too small beside the rest to count (a cup on a table): 1% of the volume.
    const TriangleMesh block = boxBetween({-1, -1, -1}, {1, 0, 1});
    const PhysicsSolid cupped =
        solidOf(joined(block, translated(openTub({0.2, 0.2, 0.2}), {0, 0.5, 0})));
    EXPECT_NEAR(cupped.materialVolume, 4.0, 1e-12);
    EXPECT_EQ(findRepair(cupped, "open-hulls"), nullptr);
}

TEST(PhysicsSolid, ASolidModelledTwiceAtOnePlaceIsOneSolid) {
    SKIP_WITHOUT_REPAIR();
    // A 2 x 1 x 1 box, and the same box again as two closed halves (upper and lower, as a
    // game's buoyancy hull beside its visible hull): the halves share their bottom and top
    // faces with the whole, so merging equal faces tears them into open pieces, which together
    // still bound the box.
    const TriangleMesh whole = boxBetween({-1, 0, -0.5}, {1, 1, 0.5});
    const TriangleMesh halves =
        joined(boxBetween({-1, 0, -0.5}, {1, 0.5, 0.5}), boxBetween({-1, 0.5, -0.5}, {1, 1, 0.5}));
    const PhysicsSolid solid = solidOf(joined(whole, halves));
    // The wrap lies its offset outside the box: 10 m^2 of surface.
    const double offset = RepairSettings{}.wrapOffset * Eigen::Vector3d(2, 1, 1).norm();
    EXPECT_NEAR(solid.materialVolume, 2.0 + 10 * offset, 3 * 10 * offset)
        << describeRepairs(solid.repairs);
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
        const Eigen::Vector3d p =
            box.min + size.cwiseProduct(Eigen::Vector3d(unit(random), unit(random), unit(random)));
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

/// Whether the ray from `origin` along `direction` crosses triangle (a, b, c) (Möller-Trumbore).
bool crosses(const Eigen::Vector3d& origin, const Eigen::Vector3d& direction,
             const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c) {
    const Eigen::Vector3d ab = b - a, ac = c - a, h = direction.cross(ac);
    const double det = ab.dot(h);
    if (std::abs(det) < 1e-300) return false;
    const Eigen::Vector3d s = origin - a;
    const double u = s.dot(h) / det;
    const Eigen::Vector3d q = s.cross(ab);
    const double v = direction.dot(q) / det;
    return u >= 0 && v >= 0 && u + v <= 1 && ac.dot(q) / det > 0;
}

/// An estimate, independent of the repair, of what the artist's surface displaces sealed at its
/// rims: the share of random points in its box that are inside it (generalized winding number
/// at least 1/2) or from which water cannot run out (no ray, level in 12 directions or 45
/// degrees down in 6, or straight down, leaves without crossing the surface).
double sealedEstimate(const TriangleMesh& mesh, int samples) {
    const Bounds3 box = computeBounds(mesh);
    std::vector<Eigen::Vector3d> ways{-Eigen::Vector3d::UnitY()};
    for (int k = 0; k < 12; ++k) {
        const double angle = std::numbers::pi * k / 6;
        ways.emplace_back(std::cos(angle), 0, std::sin(angle));
        if (k % 2 == 1) ways.emplace_back(std::cos(angle), -1, std::sin(angle));
    }
    std::mt19937_64 random(11);
    std::uniform_real_distribution<double> unit(0, 1);
    int held = 0;
    for (int i = 0; i < samples; ++i) {
        const Eigen::Vector3d p =
            box.min + (box.max - box.min)
                          .cwiseProduct(Eigen::Vector3d(unit(random), unit(random), unit(random)));
        bool in = windingNumber(mesh, p) >= 0.5;
        if (!in) {
            in = std::all_of(ways.begin(), ways.end(), [&](const Eigen::Vector3d& way) {
                return std::any_of(mesh.triangles.begin(), mesh.triangles.end(),
                                   [&](const Triangle& t) {
                                       return crosses(p, way, mesh.positions[t[0]],
                                                      mesh.positions[t[1]], mesh.positions[t[2]]);
                                   });
            });
        }
        if (in) ++held;
    }
    return (box.max - box.min).prod() * held / samples;
}

TEST(PhysicsSolid, TheShipsWithSheetsBesideTheirHullsDisplaceTheirSealedHulls) {
    SKIP_WITHOUT_REPAIR();
    if (!std::filesystem::exists(test::realAssetsDir()))
        GTEST_SKIP() << "../shared/real-assets not present";
    // The three-masted ship: a hull whose holes are small but which cuts through itself; the
    // motor boat: one closed boat modelled again as two closed halves and a half hull, which
    // merging tears into open pieces.
    for (const char* name : {"quaternius/Sail_ship.fbx", "dawn-of-the-duck/boat2.glb"}) {
        SCOPED_TRACE(name);
        Result<TriangleMesh> mesh = loadMesh(test::realAssetsDir() / name);
        ASSERT_TRUE(mesh.ok()) << mesh.error().message;
        const PhysicsSolid solid = solidOf(*mesh);
        const double estimate = sealedEstimate(*mesh, 4000);
        std::cout << name << ": material " << solid.materialVolume << " m^3, displacement "
                  << solid.displacementVolume << " m^3, sealed estimate " << estimate << " m^3, "
                  << solid.openings.size() << " openings, " << describeRepairs(solid.repairs)
                  << "\n";
        EXPECT_NEAR(solid.displacementVolume, estimate, 0.15 * estimate);
        // Whatever the solid adds, sheets left out and the wrap's offset, is a small share.
        EXPECT_LE(solid.materialVolume, solid.displacementVolume);
        EXPECT_GT(solid.materialVolume, 0.5 * estimate);
    }
}

}  // namespace
}  // namespace test_physics_solid
}  // namespace plimsoll
