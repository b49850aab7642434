// Painted maps moved between parameterisations keep what they say about the surface: the
// integral of the map over the surface survives a round trip mesh UVs -> generated atlas -> mesh
// UVs within 1%, and the nearest-surface-point search finds the right point.
#include "plimsoll/surface/atlas.h"
#include "plimsoll/io/painted_map_io.h"
#include "plimsoll/surface/map_transfer.h"
#include "plimsoll/io/mesh_io.h"
#include "plimsoll/surface/painted_map.h"
#include "plimsoll/samples/primitives.h"

#include "cli_runner.h"
#include "test_support.h"

#include <nlohmann/json.hpp>

#include <functional>
#include <optional>
#include <random>

namespace plimsoll {
namespace test_map_transfer {
namespace {

using Field = std::function<double(const Eigen::Vector3d&)>;
using test::CommandOutput;
using test::runPlimsoll;

// Paints `field` into a width x height map over the mesh's UVs (independently of the engine's
// transfer): every texel whose centre lies in a UV triangle takes the field at the surface
// point there; texels outside every triangle are left 0 unless a triangle lies within a texel.
PaintedMap paint(const TriangleMesh& mesh, const Field& field, int size) {
    PaintedMap map;
    map.width = map.height = size;
    map.values.assign(static_cast<std::size_t>(size) * size, 0.0f);
    std::vector<bool> inside(map.values.size(), false);
    for (const Triangle& t : mesh.triangles) {
        std::array<Eigen::Vector2d, 3> p;
        for (int k = 0; k < 3; ++k) {
            const Eigen::Vector2d& uv = mesh.uvs[t[static_cast<std::size_t>(k)]];
            p[static_cast<std::size_t>(k)] = {uv.x() * size - 0.5, (1.0 - uv.y()) * size - 0.5};
        }
        const double area =
            (p[1] - p[0]).x() * (p[2] - p[0]).y() - (p[1] - p[0]).y() * (p[2] - p[0]).x();
        if (area == 0) continue;
        const int x0 =
            std::max(0, static_cast<int>(std::floor(std::min({p[0].x(), p[1].x(), p[2].x()}))));
        const int x1 = std::min(
            size - 1, static_cast<int>(std::ceil(std::max({p[0].x(), p[1].x(), p[2].x()}))));
        const int y0 =
            std::max(0, static_cast<int>(std::floor(std::min({p[0].y(), p[1].y(), p[2].y()}))));
        const int y1 = std::min(
            size - 1, static_cast<int>(std::ceil(std::max({p[0].y(), p[1].y(), p[2].y()}))));
        for (int y = y0; y <= y1; ++y) {
            for (int x = x0; x <= x1; ++x) {
                const Eigen::Vector2d q(x, y);
                const auto edge = [&](const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
                    return ((b - a).x() * (q - a).y() - (b - a).y() * (q - a).x()) / area;
                };
                const double b0 = edge(p[1], p[2]), b1 = edge(p[2], p[0]), b2 = edge(p[0], p[1]);
                if (b0 < 0 || b1 < 0 || b2 < 0) continue;
                const Eigen::Vector3d point = b0 * mesh.positions[t[0]] +
                                              b1 * mesh.positions[t[1]] + b2 * mesh.positions[t[2]];
                const std::size_t i = static_cast<std::size_t>(y) * size + x;
                map.values[i] = static_cast<float>(field(point));
                inside[i] = true;
            }
        }
    }
    // Border texels (centres just outside every triangle) take their neighbour's value, as a
    // painting tool bleeds paint past UV edges.
    for (int pass = 0; pass < 2; ++pass) {
        std::vector<bool> next = inside;
        for (int y = 0; y < size; ++y) {
            for (int x = 0; x < size; ++x) {
                const std::size_t i = static_cast<std::size_t>(y) * size + x;
                if (inside[i]) continue;
                for (const auto& [dx, dy] : {std::pair{1, 0}, {-1, 0}, {0, 1}, {0, -1}}) {
                    const int nx = x + dx, ny = y + dy;
                    if (nx < 0 || ny < 0 || nx >= size || ny >= size) continue;
                    const std::size_t n = static_cast<std::size_t>(ny) * size + nx;
                    if (!inside[n]) continue;
                    map.values[i] = map.values[n];
                    next[i] = true;
                    break;
                }
            }
        }
        inside = next;
    }
    return map;
}

// The map's integral over the surface, through a bake of the mesh's UVs: sum of value x area.
double surfaceIntegral(const PaintedMap& map, const TriangleMesh& mesh) {
    const SurfaceTextures textures = test::bakeOrFail(mesh, 256);
    const std::vector<double> values = sampleAtTexels(map, textures, 1.0);
    double sum = 0;
    for (std::size_t i = 0; i < values.size(); ++i) sum += values[i] * textures.area[i];
    return sum;
}

// The field's integral by the centroid rule (exact for a linear field).
double exactIntegral(const TriangleMesh& mesh, const Field& field) {
    double sum = 0;
    for (const Triangle& t : mesh.triangles) {
        const Eigen::Vector3d c =
            (mesh.positions[t[0]] + mesh.positions[t[1]] + mesh.positions[t[2]]) / 3.0;
        sum += triangleAreaVector(mesh, t).norm() * field(c);
    }
    return sum;
}

void expectRoundTripKeepsTheIntegral(const TriangleMesh& mesh, const Field& field, bool linear) {
    SCOPED_TRACE(mesh.source);
    constexpr int kMapSize = 512;
    const PaintedMap original = paint(mesh, field, kMapSize);
    Result<PhysicsAtlas> atlas = generatePhysicsAtlas(mesh, {});
    ASSERT_TRUE(atlas.ok()) << atlas.error().message;
    Result<PaintedMap> onAtlas =
        transferPaintedMap(original, mesh, atlas->mesh, kMapSize, kMapSize);
    ASSERT_TRUE(onAtlas.ok()) << onAtlas.error().message;
    Result<PaintedMap> back = transferPaintedMap(*onAtlas, atlas->mesh, mesh, kMapSize, kMapSize);
    ASSERT_TRUE(back.ok()) << back.error().message;

    const double before = surfaceIntegral(original, mesh);
    const double moved = surfaceIntegral(*onAtlas, atlas->mesh);
    const double after = surfaceIntegral(*back, mesh);
    std::printf("  %-26s integral %.6g, on the atlas %.6g (%+.3f%%), back %.6g (%+.3f%%)\n",
                mesh.source.c_str(), before, moved, 100 * (moved / before - 1), after,
                100 * (after / before - 1));
    EXPECT_NEAR(moved, before, 0.01 * std::abs(before));
    EXPECT_NEAR(after, before, 0.01 * std::abs(before));
    if (linear) EXPECT_NEAR(before, exactIntegral(mesh, field), 0.01 * std::abs(before));
}

TEST(MapTransfer, RoundTripThroughAGeneratedAtlasKeepsTheIntegral) {
    // A gradient over the height, and a damage patch with a sharp edge.
    const Field gradient = [](const Eigen::Vector3d& p) { return 0.5 + 0.4 * p.y() + 0.2 * p.x(); };
    const Field patch = [](const Eigen::Vector3d& p) {
        return (p - Eigen::Vector3d(0.35, 0.1, 0.2)).norm() < 0.3 ? 1.0 : 0.0;
    };
    const TriangleMesh sphere = makeUvSphere(0.5, 64, 32);
    expectRoundTripKeepsTheIntegral(sphere, gradient, true);
    expectRoundTripKeepsTheIntegral(sphere, patch, false);
    // A real mesh's generated atlas too; left to the normal build in the sanitized one (14k
    // triangles: most of this test's minute there, through the same code as the sphere's).
    const auto blub =
        test::kSanitizedBuild ? std::nullopt : test::sharedMesh("blub_triangulated.obj");
    if (blub) {
        Result<TriangleMesh> mesh = loadMesh(*blub);
        ASSERT_TRUE(mesh.ok());
        expectRoundTripKeepsTheIntegral(*mesh, gradient, true);
        expectRoundTripKeepsTheIntegral(*mesh, patch, false);
    }
}

TEST(MapTransfer, BetweenDifferentTessellationsGoesThroughTheNearestSurfacePoint) {
    // The same sphere meshed twice: the map follows the surface, not the triangle ids.
    const Field gradient = [](const Eigen::Vector3d& p) { return 0.5 + 0.8 * p.y(); };
    const TriangleMesh coarse = makeUvSphere(0.5, 48, 24);
    const TriangleMesh fine = makeUvSphere(0.5, 80, 40);
    const PaintedMap painted = paint(coarse, gradient, 256);
    Result<PaintedMap> moved = transferPaintedMap(painted, coarse, fine, 256, 256);
    ASSERT_TRUE(moved.ok());
    EXPECT_NEAR(surfaceIntegral(*moved, fine), exactIntegral(fine, gradient),
                0.01 * exactIntegral(fine, gradient));
}

TEST(MapTransfer, NearestSurfacePointMatchesBruteForce) {
    const TriangleMesh mesh = makeBuoy();
    const SurfaceLocator locator(mesh);
    std::mt19937 random(7);
    std::uniform_real_distribution<double> coordinate(-1.5, 1.5);
    for (int i = 0; i < 50; ++i) {
        const Eigen::Vector3d q(coordinate(random), coordinate(random), coordinate(random));
        const SurfaceLocator::Hit hit = locator.nearest(q);
        // Brute force over every triangle, sampling its barycentric grid finely enough to
        // bound the distance from above.
        double best = std::numeric_limits<double>::infinity();
        for (const Triangle& t : mesh.triangles) {
            for (int a = 0; a <= 12; ++a) {
                for (int b = 0; a + b <= 12; ++b) {
                    const Eigen::Vector3d p =
                        mesh.positions[t[0]] +
                        a / 12.0 * (mesh.positions[t[1]] - mesh.positions[t[0]]) +
                        b / 12.0 * (mesh.positions[t[2]] - mesh.positions[t[0]]);
                    best = std::min(best, (p - q).norm());
                }
            }
        }
        EXPECT_LE(hit.distance, best + 1e-12);
        EXPECT_NEAR((hit.point - q).norm(), hit.distance, 1e-12);
        EXPECT_NEAR(hit.barycentric.sum(), 1.0, 1e-12);
    }
}

TEST(MapTransfer, BadInputIsRefused) {
    const TriangleMesh sphere = makeUvSphere(0.5, 16, 8);
    TriangleMesh noUvs = sphere;
    noUvs.uvs.clear();
    PaintedMap map;
    map.width = map.height = 4;
    map.values.assign(16, 0.5f);
    const auto kindOf = [](const Result<PaintedMap>& r) {
        return r.ok() ? std::optional<ErrorKind>() : r.error().kind;
    };
    EXPECT_EQ(kindOf(transferPaintedMap(map, noUvs, sphere, 64, 64)), ErrorKind::invalidArgument);
    EXPECT_EQ(kindOf(transferPaintedMap(map, sphere, noUvs, 64, 64)), ErrorKind::invalidArgument);
    EXPECT_EQ(kindOf(transferPaintedMap(map, sphere, sphere, 100000, 64)), ErrorKind::limit);
    PaintedMap empty;
    EXPECT_EQ(kindOf(transferPaintedMap(empty, sphere, sphere, 64, 64)),
              ErrorKind::invalidArgument);
}

TEST(MapTransfer, CommandLineGeneratesAnAtlasAndMovesAMapOntoIt) {
    const std::filesystem::path dir = test::scratchFolder("atlas-cli");
    const std::string sphere = test::assetPath("sphere.obj").string();
    const std::string atlas = (dir / "atlas.obj").string();
    const CommandOutput made =
        runPlimsoll("atlas generate '" + sphere + "' --out '" + atlas + "' --size 128 --json");
    ASSERT_EQ(made.exitCode, 0) << made.err;
    const nlohmann::json j = nlohmann::json::parse(made.out);
    EXPECT_GE(j.at("uv_coverage").get<double>(), 0.55);
    EXPECT_LE(j.at("uv_area_spread").get<double>(), kMaxUvAreaSpread);
    // A map painted over the sphere's UVs (a gradient along v), moved onto the atlas: the
    // surface integral survives; the map file is a 16-bit PNG of the requested size.
    Result<TriangleMesh> mesh = loadMesh(sphere);
    Result<TriangleMesh> atlasMesh = loadMesh(atlas);
    ASSERT_TRUE(mesh.ok() && atlasMesh.ok());
    const Field height = [](const Eigen::Vector3d& p) { return 0.5 + 0.9 * p.y(); };
    const PaintedMap painted = paint(*mesh, height, 256);
    ASSERT_TRUE(savePaintedMap(painted, dir / "height.png").ok());
    const CommandOutput moved = runPlimsoll(
        "atlas transfer-map '" + (dir / "height.png").string() + "' --from '" + sphere +
        "' --to '" + atlas + "' --out '" + (dir / "height_atlas.png").string() + "' --width 200");
    ASSERT_EQ(moved.exitCode, 0) << moved.err;
    Result<PaintedMap> onAtlas = loadPaintedMap(dir / "height_atlas.png");
    ASSERT_TRUE(onAtlas.ok());
    EXPECT_EQ(onAtlas->width, 200);
    EXPECT_EQ(onAtlas->height, 256);
    const double before = surfaceIntegral(painted, *mesh);
    EXPECT_NEAR(surfaceIntegral(*onAtlas, *atlasMesh), before, 0.01 * before);
    // Bad input names the file.
    const CommandOutput bad =
        runPlimsoll("atlas transfer-map /no/such.png --from '" + sphere + "' --to '" + atlas +
                    "' --out '" + (dir / "x.png").string() + "'");
    EXPECT_NE(bad.exitCode, 0);
    EXPECT_NE(bad.err.find("/no/such.png"), std::string::npos) << bad.err;
}

}  // namespace
}  // namespace test_map_transfer
}  // namespace plimsoll
