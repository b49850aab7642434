// The exact-clipping bake: conservation (closure, area, UV coverage), exactness on planes,
// determinism, limits, and the EXR round trip.
#include "plimsoll/bake/bake.h"
#include "plimsoll/bake/bake_cost.h"
#include "plimsoll/bake/cancellable_bake.h"
#include "plimsoll/io/bake_io.h"
#include "plimsoll/physics/massprops.h"
#include "plimsoll/io/mesh_io.h"
#include "plimsoll/samples/primitives.h"
#include "plimsoll/geometry/uv_layout.h"
#include "plimsoll/geometry/validate.h"

#include "test_support.h"

#include "io/exr_io.h"

#include <nlohmann/json.hpp>

#include <cmath>
#include <fstream>
#include <map>

namespace plimsoll {
namespace test_bake {
namespace {

namespace fs = std::filesystem;

SurfaceTextures bake(const TriangleMesh& mesh, int size, unsigned threads = 0) {
    BakeSettings settings;
    settings.size = size;
    settings.threads = threads;
    return test::bakeOrFail(mesh, settings);
}

std::vector<TriangleMesh> sampleSolids() {
    return {makeUvSphere(0.5, 48, 24), makeBox(Eigen::Vector3d(1.0, 0.5, 0.25)),
            makeCylinder(0.3, 1.0, 40), makeBuoy()};
}

double meshArea(const TriangleMesh& mesh) {
    double area = 0;
    for (const auto& t : mesh.triangles) area += triangleAreaVector(mesh, t).norm();
    return area;
}

double meshUvArea(const TriangleMesh& mesh) {
    double area = 0;
    for (const auto& t : mesh.triangles) area += std::abs(triangleUvArea(mesh, t));
    return area;
}

TEST(Bake, ConservesAreaAndClosesForEverySampleAndOddSizes) {
    for (const TriangleMesh& mesh : sampleSolids()) {
        for (int size : {16, 100, 257, 512}) {
            SCOPED_TRACE(mesh.source + " at " + std::to_string(size));
            const SurfaceTextures t = bake(mesh, size);
            EXPECT_LT(t.closureError(), 1e-12);
            EXPECT_NEAR(t.surfaceArea(), meshArea(mesh), 1e-11 * meshArea(mesh));
            EXPECT_NEAR(t.uvCoverage(), meshUvArea(mesh), 1e-12);
            for (std::size_t i = 0; i < t.coveredCount(); ++i) {
                ASSERT_GT(t.coverage[i], 0.0);
                ASSERT_LE(t.coverage[i], 1.0 + 1e-12);
                ASSERT_GE(t.area[i] * (1 + 1e-12), t.areaVector[i].norm());
            }
        }
    }
}

// One planar quad mapped affinely onto the whole texture: every texel is fully covered, its
// area vector is exactly the quad's divided by N^2 and its centroid the image of the texel
// centre.
TEST(Bake, PlanarQuadGivesExactTexels) {
    TriangleMesh quad;
    quad.source = "quad";
    quad.positions = {{0, 0, 0}, {2, 0, 0}, {2, 0, -3}, {0, 0, -3}};
    quad.uvs = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
    quad.triangles = {{0, 1, 2}, {0, 2, 3}};
    const int n = 37;
    const SurfaceTextures t = bake(quad, n);
    ASSERT_EQ(t.coveredCount(), static_cast<std::size_t>(n * n));
    for (std::size_t i = 0; i < t.coveredCount(); ++i) {
        const int x = t.texelIndex[i] % n, y = t.texelIndex[i] / n;
        const Eigen::Vector3d centre(2.0 * (x + 0.5) / n, 0.0, -3.0 * (y + 0.5) / n);
        EXPECT_LT((t.position[i] - centre).norm(), 1e-13);
        EXPECT_LT((t.areaVector[i] - Eigen::Vector3d(0, 6.0 / (n * n), 0)).norm(), 1e-15);
        EXPECT_NEAR(t.coverage[i], 1.0, 1e-12);
    }
}

TEST(Bake, MirroredTrianglesCountWithTheirOwnOrientation) {
    TriangleMesh box = makeBox(Eigen::Vector3d(1.0, 0.5, 0.25));
    // Mirror every UV (u -> 1 - u): each triangle's UV orientation flips, the surface does not.
    for (auto& uv : box.uvs) uv.x() = 1.0 - uv.x();
    const SurfaceTextures t = bake(box, 64);
    EXPECT_LT(t.closureError(), 1e-12);
    EXPECT_NEAR(t.surfaceArea(), meshArea(box), 1e-12);
    EXPECT_NEAR(textureSolidMassProperties(t, 1.0).volume, 0.125, 1e-12);
}

// A box whose six face charts sit in a row 0.001 apart: at N = 16 most chart borders fall
// inside a texel. A merged point between two faces would give a wrong volume; one entry per
// island keeps even this coarse bake exact on a box.
TEST(Bake, TexelsSharedByIslandsKeepOneEntryPerIsland) {
    TriangleMesh box = makeBox(Eigen::Vector3d(1.0, 0.5, 0.25));
    const std::vector<std::uint32_t> island = uvIslands(box);
    std::map<std::uint32_t, int> slot;
    for (std::uint32_t id : island) slot.try_emplace(id, static_cast<int>(slot.size()));
    ASSERT_EQ(slot.size(), 6u);
    for (auto& uv : box.uvs) uv *= 0.5;  // six charts in a row fit in the unit square
    std::vector<int> slotOfVertex(box.vertexCount());
    for (std::size_t t = 0; t < box.triangleCount(); ++t)
        for (std::uint32_t v : box.triangles[t]) slotOfVertex[v] = slot[island[t]];
    std::map<int, Eigen::Vector2d> lo, hi;
    for (std::size_t v = 0; v < box.vertexCount(); ++v) {
        auto [l, fresh] = lo.try_emplace(slotOfVertex[v], box.uvs[v]);
        auto [h, unused] = hi.try_emplace(slotOfVertex[v], box.uvs[v]);
        l->second = l->second.cwiseMin(box.uvs[v]);
        h->second = h->second.cwiseMax(box.uvs[v]);
    }
    double cursor = 0.01;
    std::vector<Eigen::Vector2d> shift(6);
    for (int k = 0; k < 6; ++k) {
        shift[k] = Eigen::Vector2d(cursor, 0.01) - lo[k];
        cursor += hi[k].x() - lo[k].x() + 0.001;
    }
    ASSERT_LT(cursor, 1.0);
    for (std::size_t v = 0; v < box.vertexCount(); ++v) box.uvs[v] += shift[slotOfVertex[v]];
    ASSERT_TRUE(validateMesh(box).usableForTexture()) << validateMesh(box).format();
    const SurfaceTextures t = bake(box, 16);
    EXPECT_GT(t.coveredCount(), t.distinctTexelCount());
    const MassProperties p = textureSolidMassProperties(t, 1.0);
    EXPECT_NEAR(p.volume, 0.125, 1e-15);
    EXPECT_LT(p.centerOfMass.norm(), 1e-15);
}

// v -> v^3 keeps the buoy's map bijective but squeezes its keel into a few rows of texels; the
// squeezed triangles are cut on a finer grid, and the result stays within the bake's usual
// error (without refinement the volume error here is 2e-2).
TEST(Bake, SqueezedUvRegionsAreRefined) {
    TriangleMesh buoy = makeBuoy();
    const SurfaceTextures plain = bake(buoy, 256);
    for (auto& uv : buoy.uvs) uv.y() = std::pow(uv.y(), 3.0);
    const SurfaceTextures squeezed = bake(buoy, 256);
    EXPECT_GT(squeezed.coveredCount(), 2 * squeezed.distinctTexelCount());
    EXPECT_EQ(plain.coveredCount(), plain.distinctTexelCount());
    EXPECT_LT(squeezed.closureError(), 1e-12);
    const MassProperties exact = exactSolidMassProperties(buoy, 1.0);
    const test::MassPropsError e = test::compare(textureSolidMassProperties(squeezed, 1.0), exact,
                                                 computeBounds(buoy).diagonal());
    EXPECT_LT(e.volume, 1e-3);
    EXPECT_LT(e.centerOfMass, 2e-4);
    EXPECT_LT(e.inertia, 3e-3);
}

TEST(Bake, ResultDoesNotDependOnThreadCount) {
    const TriangleMesh buoy = makeBuoy();
    const SurfaceTextures one = bake(buoy, 300, 1), three = bake(buoy, 300, 3);
    ASSERT_EQ(one.texelIndex, three.texelIndex);
    for (std::size_t i = 0; i < one.coveredCount(); ++i) {
        ASSERT_EQ(one.position[i], three.position[i]);
        ASSERT_EQ(one.areaVector[i], three.areaVector[i]);
    }
}

TEST(Bake, CancelStopsAfterTheBandUnderWayAndNeverChangesAFinishedBake) {
    // An editor's Cancel (cancellable_bake.h): on one thread, a cancel raised by the first
    // progress report stops the bake before its second band of rows (size 256: 16 bands).
    const TriangleMesh buoy = makeBuoy();
    BakeSettings settings;
    settings.size = 256;
    settings.threads = 1;
    bool cancel = false;
    int reports = 0;
    settings.progress = [&](double) {
        ++reports;
        cancel = true;
    };
    Result<SurfaceTextures> stopped =
        bakeSurfaceTextures(buoy, settings, nullptr, [&] { return cancel; });
    ASSERT_FALSE(stopped.ok());
    EXPECT_EQ(reports, 1);
    EXPECT_EQ(stopped.error().kind, ErrorKind::invalidArgument);
    const std::string& message = stopped.error().message;
    EXPECT_EQ(message.substr(message.size() - std::string(kBakeCancelledMessage).size()),
              kBakeCancelledMessage);
    // Never asked to stop: the plain bake, entry for entry, with every band reported.
    reports = 0;
    settings.progress = [&](double) { ++reports; };
    Result<SurfaceTextures> full =
        bakeSurfaceTextures(buoy, settings, nullptr, [] { return false; });
    ASSERT_TRUE(full.ok());
    EXPECT_EQ(reports, 16);
    const SurfaceTextures plain = bake(buoy, 256, 1);
    ASSERT_EQ(full->texelIndex, plain.texelIndex);
    for (std::size_t i = 0; i < plain.coveredCount(); ++i) {
        ASSERT_EQ(full->position[i], plain.position[i]);
        ASSERT_EQ(full->areaVector[i], plain.areaVector[i]);
    }
}

TEST(Bake, UvsOutsideTheUnitSquareAreRemappedNotRefused) {
    TriangleMesh sphere = makeUvSphere(0.5, 32, 16);
    for (auto& uv : sphere.uvs) uv = 3.0 * uv + Eigen::Vector2d(-4.0, 7.0);
    const SurfaceTextures t = bake(sphere, 128);
    EXPECT_NEAR(t.placement.scale, 1.0 / 3.0, 1e-15);
    // Placed back exactly where the original UVs were.
    EXPECT_NEAR(t.uvCoverage(), meshUvArea(sphere) / 9.0, 1e-12);
    EXPECT_NEAR(t.uvCoverage(), meshUvArea(makeUvSphere(0.5, 32, 16)), 1e-12);
    EXPECT_LT(t.closureError(), 1e-12);
}

TEST(Bake, RefusesAbsurdSizesAndMissingUvs) {
    TriangleMesh box = makeBox(Eigen::Vector3d::Ones());
    box.source = "box.obj";
    for (int size : {0, 15, 8193, -4}) {
        BakeSettings settings;
        settings.size = size;
        Result<SurfaceTextures> r = bakeSurfaceTextures(box, settings);
        ASSERT_FALSE(r.ok());
        EXPECT_EQ(r.error().kind, ErrorKind::limit);
        EXPECT_NE(r.error().message.find("box.obj"), std::string::npos);
        EXPECT_NE(r.error().message.find(std::to_string(size)), std::string::npos);
    }
    box.uvs.clear();
    EXPECT_EQ(bakeSurfaceTextures(box, BakeSettings{}).error().kind, ErrorKind::invalidArgument);
}

TEST(Bake, ExrRoundTripKeepsFloatPrecision) {
    const TriangleMesh buoy = makeBuoy();
    const SurfaceTextures t = bake(buoy, 96);
    const fs::path dir = fs::temp_directory_path() / "plimsoll_tests" / "bake_roundtrip";
    fs::remove_all(dir);
    ASSERT_TRUE(writeBakedTextures(t, dir, "buoy.obj").ok());
    Result<SurfaceTextures> back = readBakedTextures(dir);
    ASSERT_TRUE(back.ok()) << back.error().message;
    ASSERT_EQ(back->texelIndex, t.texelIndex);
    for (std::size_t i = 0; i < t.coveredCount(); ++i) {
        ASSERT_LT((back->position[i] - t.position[i]).norm(), 1e-6);
        ASSERT_LT((back->areaVector[i] - t.areaVector[i]).norm(), 1e-7 * t.area[i] + 1e-30);
        ASSERT_NEAR(back->area[i], t.area[i], 1e-7 * t.area[i]);
        ASSERT_NEAR(back->coverage[i], t.coverage[i], 1e-7);
    }
    // The merged images, written a block of rows at a time: every texel's area-weighted point,
    // summed area vector and area, and coverage; zero where nothing maps (row 0 = the top).
    Result<detail::FloatImage> position =
        detail::readExr(dir / "position.exr", {"R", "G", "B", "A"});
    Result<detail::FloatImage> areaVector =
        detail::readExr(dir / "area_vector.exr", {"R", "G", "B", "A"});
    Result<detail::FloatImage> coverage = detail::readExr(dir / "coverage.exr", {"Y"});
    ASSERT_TRUE(position.ok() && areaVector.ok() && coverage.ok());
    std::vector<char> covered(96 * 96, 0);
    for (std::size_t first = 0, last; first < t.coveredCount(); first = last) {
        Eigen::Vector3d sumA = Eigen::Vector3d::Zero(), weighted = Eigen::Vector3d::Zero();
        double area = 0, share = 0;
        for (last = first; last < t.coveredCount() && t.texelIndex[last] == t.texelIndex[first];
             ++last) {
            sumA += t.areaVector[last];
            weighted += t.area[last] * t.position[last];
            area += t.area[last];
            share += t.coverage[last];
        }
        const std::size_t x = t.texelIndex[first] % 96, y = t.texelIndex[first] / 96;
        const std::size_t pixel = (95 - y) * 96 + x;
        covered[pixel] = 1;
        for (int k = 0; k < 3; ++k) {
            ASSERT_NEAR(position->pixels[4 * pixel + k], weighted[k] / area, 1e-6) << pixel;
            ASSERT_NEAR(areaVector->pixels[4 * pixel + k], sumA[k], 1e-7 * area + 1e-30) << pixel;
        }
        ASSERT_EQ(position->pixels[4 * pixel + 3], 1.0f);
        ASSERT_NEAR(areaVector->pixels[4 * pixel + 3], area, 1e-7 * area);
        ASSERT_NEAR(coverage->pixels[pixel], share, 1e-7);
    }
    for (std::size_t pixel = 0; pixel < covered.size(); ++pixel) {
        if (covered[pixel]) continue;
        ASSERT_EQ(position->pixels[4 * pixel + 3], 0.0f) << pixel;
        ASSERT_EQ(coverage->pixels[pixel], 0.0f) << pixel;
    }
    std::ifstream in(dir / "manifest.json");
    const nlohmann::json manifest = nlohmann::json::parse(in);
    EXPECT_EQ(manifest.at("texture_size").get<int>(), 96);
    EXPECT_EQ(manifest.at("covered_texels").get<std::size_t>(), t.coveredCount());
    EXPECT_EQ(manifest.at("schema_version").get<int>(), kBakeSchemaVersion);

    // A corrupt manifest is reported with the file name, and the images stay.
    std::ofstream(dir / "manifest.json") << "{ not json";
    Result<SurfaceTextures> broken = readBakedTextures(dir);
    ASSERT_FALSE(broken.ok());
    EXPECT_NE(broken.error().message.find("manifest.json"), std::string::npos);
    EXPECT_TRUE(fs::exists(dir / "position.exr"));
}

// The cost said before a large bake (bake_cost.h) counts the entries the bake makes: the UV
// area times N^2, within a few percent (border texels, refinement), for every sample solid.
TEST(BakeCost, TheEstimateCountsTheEntriesTheBakeMakes) {
    for (const TriangleMesh& mesh : sampleSolids()) {
        const SurfaceTextures t = bake(mesh, 256);
        const BakeCost cost = estimateBakeCost(mesh, 256);
        EXPECT_NEAR(cost.entries, double(t.coveredCount()), 0.1 * double(t.coveredCount()));
        EXPECT_GT(cost.bytes, kBakeBytesPerEntry * cost.entries);
        EXPECT_GT(cost.seconds, 0.0);
    }
    const TriangleMesh box = makeBox(Eigen::Vector3d(1.0, 0.5, 0.25));
    EXPECT_EQ(describeBakeCost(box, 256), "");  // small bakes say nothing
    const std::string large = describeBakeCost(box, 8192);
    EXPECT_NE(large.find("a 8192^2 bake of about"), std::string::npos) << large;
    EXPECT_NE(large.find("GB of memory"), std::string::npos) << large;
}

}  // namespace
}  // namespace test_bake
}  // namespace plimsoll
