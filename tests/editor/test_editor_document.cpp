// The editor's GL-free core: painting (3D brush in world distance across UV seams), the command
// layer (one undo step per stroke, byte-exact undo), projects (atomic save under an injected
// interruption, autosave and recovery) and headless edit scripts.
#include "cli_runner.h"
#include "test_support.h"
#include "editor/document_test_support.h"

#include "document/command.h"
#include "document/document.h"
#include "document/graph_edit.h"
#include "document/overlay.h"
#include "document/paint.h"
#include "document/panel_layout.h"
#include "document/script.h"
#include "document/settings.h"

#include "plimsoll/io/file_util.h"
#include "plimsoll/io/painted_map_io.h"

#include "io/test_hooks.h"
#include "plimsoll/io/mesh_io.h"
#include "plimsoll/surface/painted_map.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <numbers>
#include <fstream>
#include <iterator>
#include <sys/wait.h>
#include <unistd.h>

namespace plimsoll::editor {
namespace test_editor_document {
namespace {

namespace fs = std::filesystem;
using test::executeOrFail;
using test::openOrFail;

/// A project with one body on `mesh` (solid + shell, so every channel can be painted).
fs::path writeProject(const fs::path& dir, const std::string& mesh) {
    const fs::path path = dir / "test.plim.json";
    std::ofstream(path)
        << R"({"schema_version": 1, "name": "t", "bodies": [{"name": "ball", "mesh": ")"
        << test::assetPath(mesh).string()
        << R"(", "material": {"density": 500, "shell": {"surface_density": 10}}}]})";
    return path;
}

/// The surface point at every pixel centre, found from the mesh alone (not the paint surface).
struct PixelPoint {
    std::size_t pixel;
    Eigen::Vector2d uv;
    Eigen::Vector3d point;
};
std::vector<PixelPoint> pixelPoints(const TriangleMesh& mesh, int w, int h) {
    std::vector<PixelPoint> out;
    for (int y = 0; y < h; ++y) {
        for (int x = 0; x < w; ++x) {
            const Eigen::Vector2d uv((x + 0.5) / w, 1.0 - (y + 0.5) / h);
            if (auto hit = surfaceAtUv(mesh, uv)) {
                out.push_back({static_cast<std::size_t>(y) * w + x, uv, hit->point});
            }
        }
    }
    return out;
}

/// A point on the sphere's UV seam (the vertex with the smallest u near the equator).
Eigen::Vector3d seamPoint(const TriangleMesh& mesh) {
    std::size_t best = 0;
    for (std::size_t i = 0; i < mesh.vertexCount(); ++i) {
        const double score = mesh.uvs[i].x() + std::abs(mesh.uvs[i].y() - 0.5);
        if (score < mesh.uvs[best].x() + std::abs(mesh.uvs[best].y() - 0.5)) best = i;
    }
    return mesh.positions[best];
}

constexpr int kMap = 128;

/// The ball in a fresh folder `name` with a blank kMap x kMap map on `channel` (null, with a
/// failure, when it cannot be made).
std::unique_ptr<Document> ballWithBlankMap(const std::string& name, MapChannel channel) {
    auto d = openOrFail(writeProject(test::freshFolder("editor_document", name), "sphere.obj"));
    if (!d) return nullptr;
    Result<std::unique_ptr<Command>> blank = makeNewMapCommand(*d, 0, channel, kMap, kMap, 0.0, "");
    if (!blank || !d->execute(std::move(blank).value())) {
        ADD_FAILURE() << "no blank map";
        return nullptr;
    }
    return d;
}

TEST(EditorPaint, StrokeRaisesOnlyWithinWorldRadiusAcrossUvSeam) {
    auto d = ballWithBlankMap("paint_seam", MapChannel::Permeability);
    ASSERT_TRUE(d);
    const TriangleMesh& mesh = *d->assets(0).mesh;
    const Eigen::Vector3d centre = seamPoint(mesh);
    Brush brush;
    brush.radius = 0.1;
    brush.falloff = Falloff::Constant;
    const std::vector<float> before = d->map(0, MapChannel::Permeability)->values;
    const std::vector<Eigen::Vector3d> points{centre};
    executeOrFail(*d, makeStrokeCommand(*d, 0, MapChannel::Permeability, brush, points));
    const std::vector<float> after = d->map(0, MapChannel::Permeability)->values;

    // One pixel of this map spans about 2 pi 0.5 / (0.97 * 128) = 0.025 m of the equator: a
    // pixel's value comes from the surface inside it, so its centre may be that far off.
    const double slack = 0.03;
    int inside = 0, left = 0, right = 0;
    for (const PixelPoint& p : pixelPoints(mesh, kMap, kMap)) {
        const double distance = (p.point - centre).norm();
        if (distance > brush.radius + slack) {
            EXPECT_EQ(after[p.pixel], 0.0f) << "outside the brush at " << distance << " m";
        } else if (distance < brush.radius - slack) {
            EXPECT_EQ(after[p.pixel], 1.0f) << "inside the brush at " << distance << " m";
            ++inside;
            if (p.uv.x() < 0.2) ++left;
            if (p.uv.x() > 0.8) ++right;
        }
    }
    EXPECT_GT(inside, 20);
    // Both sides of the seam, which lie at opposite ends of the UV square.
    EXPECT_GT(left, 5);
    EXPECT_GT(right, 5);

    // One undo step restores the map byte for byte; redo re-applies it.
    ASSERT_TRUE(d->undo());
    const std::vector<float>& undone = d->map(0, MapChannel::Permeability)->values;
    ASSERT_EQ(undone.size(), before.size());
    EXPECT_EQ(std::memcmp(undone.data(), before.data(), before.size() * sizeof(float)), 0);
    ASSERT_TRUE(d->redo());
    EXPECT_EQ(d->map(0, MapChannel::Permeability)->values, after);
}

TEST(EditorPaint, StrokeAlongPointsIsOneUndoStepAndMirrorPaintsTheOtherSide) {
    const fs::path dir = test::freshFolder("editor_document", "paint_mirror");
    auto d = openOrFail(writeProject(dir, "sphere.obj"));
    ASSERT_TRUE(d);
    executeOrFail(*d, makeNewMapCommand(*d, 0, MapChannel::Density, kMap, kMap, 0.0, ""));
    const TriangleMesh& mesh = *d->assets(0).mesh;
    Brush brush;
    brush.radius = 0.06;
    brush.falloff = Falloff::Constant;
    brush.mirrorX = true;
    brush.value = 0.75;
    const double s = std::sqrt(0.5);
    // A short stroke on the +x side; a ray from far out finds the surface.
    auto hitA = raycast(mesh, {2, 0.1, 0.3}, {-1, 0, 0});
    auto hitB = raycast(mesh, {2, 0.2, 0.1}, {-1, 0, 0});
    ASSERT_TRUE(hitA && hitB);
    const std::vector<Eigen::Vector3d> points{hitA->point, hitB->point};
    executeOrFail(*d, makeStrokeCommand(*d, 0, MapChannel::Density, brush, points));
    (void)s;
    const std::vector<float>& v = d->map(0, MapChannel::Density)->values;
    int mirrored = 0, direct = 0;
    for (const PixelPoint& p : pixelPoints(mesh, kMap, kMap)) {
        // Distance to the stroke segment and to its mirror image.
        auto segDist = [](const Eigen::Vector3d& q, Eigen::Vector3d a, Eigen::Vector3d b) {
            const double t = std::clamp((q - a).dot(b - a) / (b - a).squaredNorm(), 0.0, 1.0);
            return (q - (a + t * (b - a))).norm();
        };
        const Eigen::Vector3d m(-1, 1, 1);
        const double d1 = segDist(p.point, hitA->point, hitB->point);
        const double d2 =
            segDist(p.point, hitA->point.cwiseProduct(m), hitB->point.cwiseProduct(m));
        const double d = std::min(d1, d2);
        if (d > brush.radius + 0.03) EXPECT_EQ(v[p.pixel], 0.0f);
        if (d < brush.radius - 0.03) {
            EXPECT_FLOAT_EQ(v[p.pixel], 0.75f);
            (d1 < d2 ? direct : mirrored)++;
        }
    }
    EXPECT_GT(direct, 5);
    EXPECT_GT(mirrored, 5);
    EXPECT_EQ(d->undoName(), "Paint density");
    ASSERT_TRUE(d->undo());  // the whole stroke
    for (float x : d->map(0, MapChannel::Density)->values) ASSERT_EQ(x, 0.0f);
}

TEST(EditorPaint, FalloffPresetsFollowBlendersCurves) {
    // s = d / r, p = 1 - s; at the centre every curve is 1, at the rim 0 (Constant: 1 to the
    // rim), and they never rise outward.
    const double r = 2.0;
    EXPECT_EQ(parseFalloff("custom"), Falloff::Custom);
    for (int i = 0; i < kFalloffPresetCount; ++i) {
        const Falloff f = static_cast<Falloff>(i);
        EXPECT_EQ(parseFalloff(falloffName(f)), f);
        EXPECT_DOUBLE_EQ(falloffWeight(f, 0.0, r), 1.0) << falloffName(f);
        EXPECT_DOUBLE_EQ(falloffWeight(f, r, r), f == Falloff::Constant ? 1.0 : 0.0)
            << falloffName(f);
        EXPECT_EQ(falloffWeight(f, 1.01 * r, r), 0.0);
        for (double d = 0.05; d <= r; d += 0.05) {
            EXPECT_LE(falloffWeight(f, d, r), falloffWeight(f, d - 0.05, r) + 1e-15)
                << falloffName(f);
        }
    }
    EXPECT_FALSE(parseFalloff("gaussian"));
    // Values with exact answers: a 3-4-5 triangle for the sphere, squares for the rest.
    EXPECT_NEAR(falloffWeight(Falloff::Sphere, 0.6 * r, r), 0.8, 1e-15);
    EXPECT_NEAR(falloffWeight(Falloff::Root, 0.75 * r, r), 0.5, 1e-15);
    EXPECT_NEAR(falloffWeight(Falloff::Sharp, 0.5 * r, r), 0.25, 1e-15);
    EXPECT_NEAR(falloffWeight(Falloff::InverseSquare, 0.5 * r, r), 0.75, 1e-15);
    EXPECT_NEAR(falloffWeight(Falloff::Linear, 0.25 * r, r), 0.75, 1e-15);
}

TEST(EditorPaint, CustomFalloffCurvePassesThroughItsPointsAndNeverOvershoots) {
    // Blender's custom curve, interpolated by a monotone cubic (Fritsch-Carlson): through every
    // control point, within the range of each segment's two ends (a falling curve never rises,
    // a flat stretch stays flat), 0 past the rim.
    const FalloffCurve shoulder = FalloffCurve::sanitised({{0, 1}, {0.5, 1}, {0.6, 0.2}, {1, 0}});
    ASSERT_EQ(shoulder.points.size(), 4u);
    for (const Eigen::Vector2d& p : shoulder.points) EXPECT_NEAR(shoulder(p.x()), p.y(), 1e-12);
    double previous = 1.0;
    for (int k = 0; k <= 1000; ++k) {
        const double s = k / 1000.0, w = shoulder(s);
        if (s <= 0.5) EXPECT_NEAR(w, 1.0, 1e-15) << "s = " << s;
        if (s >= 0.5 && s <= 0.6) EXPECT_TRUE(w <= 1.0 && w >= 0.2) << "s = " << s;
        EXPECT_LE(w, previous + 1e-15) << "s = " << s;
        previous = w;
    }
    Brush brush;
    brush.radius = 2.0;
    brush.falloff = Falloff::Custom;
    brush.curve = shoulder;
    EXPECT_NEAR(dabWeight(brush, Eigen::Vector3d(1.2, 0, 0)), 0.2, 1e-12);
    EXPECT_EQ(dabWeight(brush, Eigen::Vector3d(2.01, 0, 0)), 0.0);
    // A preset's starting shape: nine points on its formula, the cubic between them within
    // 0.01 of the formula for the presets of finite slope (Sphere and Root are vertical at the
    // rim: only through their points).
    for (int i = 0; i < kFalloffPresetCount; ++i) {
        const Falloff f = static_cast<Falloff>(i);
        const FalloffCurve curve = FalloffCurve::preset(f);
        ASSERT_EQ(curve.points.size(), 9u);
        double worst = 0;
        for (int k = 0; k <= 1000; ++k) {
            const double s = k / 1000.0;
            worst = std::max(worst, std::abs(curve(s) - falloffWeight(f, s, 1.0)));
        }
        for (const Eigen::Vector2d& p : curve.points)
            EXPECT_NEAR(curve(p.x()), falloffWeight(f, p.x(), 1.0), 1e-12) << falloffName(f);
        if (f != Falloff::Sphere && f != Falloff::Root) EXPECT_LT(worst, 0.01) << falloffName(f);
    }
    // Anything made valid: sorted, clamped, NaN dropped, near-duplicates merged, ends added.
    const FalloffCurve odd = FalloffCurve::sanitised(
        {{0.8, -3}, {std::nan(""), 0.5}, {0.2, 0.9}, {0.205, 0.1}, {0.5, 2}});
    ASSERT_EQ(odd.points.size(), 5u);
    EXPECT_EQ(odd.points[0], Eigen::Vector2d(0, 0.9));
    EXPECT_EQ(odd.points[1], Eigen::Vector2d(0.2, 0.9));
    EXPECT_EQ(odd.points[2], Eigen::Vector2d(0.5, 1));
    EXPECT_EQ(odd.points[3], Eigen::Vector2d(0.8, 0));
    EXPECT_EQ(odd.points[4], Eigen::Vector2d(1, 0));
    EXPECT_TRUE(FalloffCurve::sanitised({}) == FalloffCurve{});
}

TEST(EditorPaint, SymmetryPaintsEveryMirrorImageAndRadialCopy) {
    // Radial 4 about y with a Y mirror: one dab paints 8 places, each a quarter turn
    // ((x, y, z) -> (z, y, -x)) or a flip of y from another; nothing else changes.
    auto d = ballWithBlankMap("paint_symmetry", MapChannel::Permeability);
    ASSERT_TRUE(d);
    const TriangleMesh& mesh = *d->assets(0).mesh;
    auto hit = raycast(mesh, {2, 0.2, 0.3}, {-1, 0, 0});
    ASSERT_TRUE(hit);
    Brush brush;
    brush.radius = 0.08;
    brush.falloff = Falloff::Constant;
    brush.mirrorY = true;
    brush.radial = 4;
    std::vector<Eigen::Vector3d> expected;
    Eigen::Vector3d q = hit->point;
    for (int k = 0; k < 4; ++k) {
        expected.push_back(q);
        expected.emplace_back(q.x(), -q.y(), q.z());
        q = Eigen::Vector3d(q.z(), q.y(), -q.x());
    }
    const std::vector<Eigen::Vector3d> copies = symmetricPoints(brush, hit->point);
    ASSERT_EQ(copies.size(), 8u);
    for (const Eigen::Vector3d& e : expected) {
        double nearest = 1e9;
        for (const Eigen::Vector3d& c : copies) nearest = std::min(nearest, (c - e).norm());
        EXPECT_LT(nearest, 1e-12) << e.transpose();
    }
    const std::vector<Eigen::Vector3d> points{hit->point};
    executeOrFail(*d, makeStrokeCommand(*d, 0, MapChannel::Permeability, brush, points));
    const std::vector<float>& v = d->map(0, MapChannel::Permeability)->values;
    std::vector<int> inside(expected.size(), 0);
    for (const PixelPoint& p : pixelPoints(mesh, kMap, kMap)) {
        double nearest = 1e9;
        for (std::size_t k = 0; k < expected.size(); ++k) {
            const double distance = (p.point - expected[k]).norm();
            nearest = std::min(nearest, distance);
            if (distance < brush.radius - 0.03) {
                EXPECT_EQ(v[p.pixel], 1.0f) << "copy " << k;
                ++inside[k];
            }
        }
        if (nearest > brush.radius + 0.03) EXPECT_EQ(v[p.pixel], 0.0f);
    }
    for (std::size_t k = 0; k < expected.size(); ++k) EXPECT_GT(inside[k], 2) << "copy " << k;
    EXPECT_EQ(d->undoName(), "Paint permeability");  // one step for all eight
}

TEST(EditorPaint, SpacingLeavesGapsBetweenDabsOrJoinsThem) {
    // A 0.15 m stroke with a 0.015 m constant brush. At 4.5 radii the dabs may be 0.0675 m
    // apart: ceil(0.15 / 0.0675) = 3 gaps of 0.05 m, so a pixel is painted exactly when one of
    // the four dabs reaches its piece of surface (the parallelogram of its sides around its
    // sample), and the surface between them stays bare. At the default quarter radius the
    // line is solid.
    const fs::path dir = test::freshFolder("editor_document", "paint_spacing");
    auto d = openOrFail(writeProject(dir, "sphere.obj"));
    ASSERT_TRUE(d);
    const TriangleMesh& mesh = *d->assets(0).mesh;
    constexpr int kFine = 512;  // 3 to 6 mm pixels on the ball's equator
    Result<PaintSurface> surface = buildPaintSurface(mesh, kFine, kFine);
    ASSERT_TRUE(surface.ok());
    PaintedMap blank;
    blank.width = blank.height = kFine;
    blank.values.assign(std::size_t(kFine) * kFine, 0.0f);
    auto a = raycast(mesh, {2, 0.0, -0.075}, {-1, 0, 0});
    auto b = raycast(mesh, {2, 0.0, 0.075}, {-1, 0, 0});
    ASSERT_TRUE(a && b);
    const std::vector<Eigen::Vector3d> points{a->point, b->point};
    Brush brush;
    brush.radius = 0.015;
    brush.falloff = Falloff::Constant;
    auto paintedPixels = [&](const PixelChange& change) {
        std::vector<char> painted(blank.values.size(), 0);
        for (std::size_t i = 0; i < change.pixels.size(); ++i)
            painted[change.pixels[i]] = change.after[i] > 0;
        return painted;
    };
    auto segmentDistance = [&](const Eigen::Vector3d& q) {
        const Eigen::Vector3d ab = b->point - a->point;
        const double t = std::clamp((q - a->point).dot(ab) / ab.squaredNorm(), 0.0, 1.0);
        return (q - (a->point + t * ab)).norm();
    };

    brush.spacing = 4.5;
    const std::vector<char> dotted = paintedPixels(strokeChange(blank, *surface, brush, points));
    // Per pixel, its pieces' nearest distance to a dab: by brute force over a 41 x 41 grid of
    // each piece's parallelogram (within 1/40 of its sides of the exact nearest point).
    std::vector<double> nearest(blank.values.size(), 1e9);
    for (std::size_t i = 0; i < surface->sampleCount(); ++i) {
        const Eigen::Vector3d q = surface->position[i].cast<double>();
        const Eigen::Vector3d hu = surface->halfU[i].cast<double>(),
                              hv = surface->halfV[i].cast<double>();
        for (int k = 0; k <= 3; ++k) {
            const Eigen::Vector3d dab = a->point + (b->point - a->point) * (k / 3.0);
            double& n = nearest[surface->pixel[i]];
            const double far =
                (q - dab).norm() - (hu.norm() + hv.norm());  // nearest the piece can be
            if (far > 2 * brush.radius) {
                n = std::min(n, far);
                continue;
            }
            for (int x = -20; x <= 20; ++x) {
                for (int y = -20; y <= 20; ++y)
                    n = std::min(n, (q + hu * (x / 20.0) + hv * (y / 20.0) - dab).norm());
            }
        }
    }
    double side = 0;  // the longest pixel side: the grid's error is within 1/40 of it
    for (std::size_t i = 0; i < surface->sampleCount(); ++i)
        side = std::max(side, 2.0 * double(surface->halfU[i].norm() + surface->halfV[i].norm()));
    int bareOnTheLine = 0, paintedCount = 0;
    for (std::size_t i = 0; i < surface->sampleCount(); ++i) {
        const std::uint32_t pixel = surface->pixel[i];
        if (std::abs(nearest[pixel] - brush.radius) < 1e-4 + side / 40)
            continue;  // the grid, rounding
        EXPECT_EQ(dotted[pixel] != 0, nearest[pixel] < brush.radius) << "pixel " << pixel;
        paintedCount += dotted[pixel] != 0;
        const Eigen::Vector3d q = surface->position[i].cast<double>();
        bareOnTheLine += !dotted[pixel] && segmentDistance(q) < 0.5 * brush.radius;
    }
    EXPECT_GT(paintedCount, 20);
    EXPECT_GT(bareOnTheLine, 10) << "gaps expected between the dabs";

    brush.spacing = 0.25;  // dabs at most 3.75 mm apart: 1.9 mm from the line at most
    const std::vector<char> solid = paintedPixels(strokeChange(blank, *surface, brush, points));
    int onTheLine = 0;
    for (std::size_t i = 0; i < surface->sampleCount(); ++i) {
        const Eigen::Vector3d q = surface->position[i].cast<double>();
        if (segmentDistance(q) >= brush.radius - 0.002) continue;
        EXPECT_TRUE(solid[surface->pixel[i]]) << "a gap in a solid line at " << q.transpose();
        ++onTheLine;
    }
    EXPECT_GT(onTheLine, 50);
}

TEST(EditorPaint, LazyMouseTrailsTheCursorOnItsString) {
    // Blender's stabilised stroke: the brush stays while the cursor is within the string's
    // length, then follows it at exactly that length behind.
    LazyMouse lazy(20.0);
    EXPECT_EQ(lazy.follow({100, 100}), Eigen::Vector2d(100, 100));  // starts under the cursor
    // A shaky hand within 20 px: the brush does not move.
    for (const Eigen::Vector2d& jitter :
         {Eigen::Vector2d(110, 95), Eigen::Vector2d(88, 104), Eigen::Vector2d(100, 119.5)}) {
        EXPECT_EQ(lazy.follow(jitter), Eigen::Vector2d(100, 100));
    }
    // Pulled 50 px right: 30 px along, 20 behind the cursor; then on along the string.
    const Eigen::Vector2d a = lazy.follow({150, 100});
    EXPECT_NEAR(a.x(), 130, 1e-12);
    EXPECT_NEAR(a.y(), 100, 1e-12);
    const Eigen::Vector2d b = lazy.follow({130, 160});
    EXPECT_NEAR((Eigen::Vector2d(130, 160) - b).norm(), 20.0, 1e-9);
    EXPECT_NEAR(b.x(), 130, 1e-12);  // straight down the string
    // A zero-length string: the brush is the cursor.
    LazyMouse off(0.0);
    off.follow({0, 0});
    EXPECT_EQ(off.follow({3, 4}), Eigen::Vector2d(3, 4));
}

TEST(EditorPaint, LineStrokeSamplesTheScreenLineAndPaintsAlongIt) {
    // Shift-click's line: samples at most `step` apart, both ends included.
    const std::vector<Eigen::Vector2d> samples = lineSamples({10, 20}, {40, 60}, 3.0);  // 50 px
    ASSERT_EQ(samples.size(), 18u);  // ceil(50 / 3) = 17 steps
    EXPECT_EQ(samples.front(), Eigen::Vector2d(10, 20));
    EXPECT_EQ(samples.back(), Eigen::Vector2d(40, 60));
    for (std::size_t i = 1; i < samples.size(); ++i) {
        EXPECT_NEAR((samples[i] - samples[i - 1]).norm(), 50.0 / 17, 1e-9);
    }
    EXPECT_EQ(lineSamples({5, 5}, {5, 5}, 3.0).size(), 2u);  // a click on the end itself

    // Picked on the sphere by an orthographic front view (pixel = 100 px per metre), the line
    // paints a band from one end to the other, one undo step.
    const fs::path dir = test::freshFolder("editor_document", "paint_line");
    auto d = openOrFail(writeProject(dir, "sphere.obj"));
    ASSERT_TRUE(d);
    executeOrFail(*d, makeNewMapCommand(*d, 0, MapChannel::Density, kMap, kMap, 0.0, ""));
    const TriangleMesh& mesh = *d->assets(0).mesh;
    std::vector<Eigen::Vector3d> points;
    for (const Eigen::Vector2d& p : lineSamples({-30, 10}, {35, -20}, 3.0)) {
        if (auto hit = raycast(mesh, {p.x() / 100, p.y() / 100, 2}, {0, 0, -1}))
            points.push_back(hit->point);
    }
    ASSERT_GT(points.size(), 20u);
    Brush brush;
    brush.radius = 0.05;
    brush.falloff = Falloff::Constant;
    brush.value = 1.0;
    executeOrFail(*d, makeStrokeCommand(*d, 0, MapChannel::Density, brush, points));
    const std::vector<float>& v = d->map(0, MapChannel::Density)->values;
    // The band along the picked path (a curve on the sphere: the samples 3 cm apart).
    auto distanceToPath = [&](const Eigen::Vector3d& q) {
        double best = 1e300;
        for (std::size_t i = 1; i < points.size(); ++i) {
            const Eigen::Vector3d a = points[i - 1], b = points[i];
            const double t =
                std::clamp((q - a).dot(b - a) / std::max((b - a).squaredNorm(), 1e-30), 0.0, 1.0);
            best = std::min(best, (q - (a + t * (b - a))).norm());
        }
        return best;
    };
    int inside = 0;
    for (const PixelPoint& p : pixelPoints(mesh, kMap, kMap)) {
        const double dist = distanceToPath(p.point);
        if (dist < brush.radius - 0.02) {
            EXPECT_EQ(v[p.pixel], 1.0f) << p.point.transpose();
            ++inside;
        }
        if (dist > brush.radius + 0.02) EXPECT_EQ(v[p.pixel], 0.0f) << p.point.transpose();
    }
    EXPECT_GT(inside, 20);
    EXPECT_EQ(d->undoName(), "Paint density");
}

TEST(EditorPaint, AlphaImageScalesEachDabAndIsUprightAcrossItsAxis) {
    // A 2 x 2 alpha: left column white, right column black; across +z, image right is +x.
    Brush brush;
    brush.radius = 0.1;
    brush.falloff = Falloff::Constant;
    auto alpha = std::make_shared<PaintedMap>();
    alpha->width = alpha->height = 2;
    alpha->values = {1, 0, 1, 0};
    brush.alpha = alpha;
    brush.alphaAxis = Eigen::Vector3d::UnitZ();
    // The left edge's value is 1, the right edge's 0, the middle half way (bilinear).
    EXPECT_NEAR(dabWeight(brush, {-0.099, 0, 0}), 1.0, 1e-9);
    EXPECT_NEAR(dabWeight(brush, {0.099, 0, 0}), 0.0, 1e-9);
    EXPECT_NEAR(dabWeight(brush, {0, 0.05, 0}), 0.5, 1e-9);
    EXPECT_NEAR(dabWeight(brush, {0, 0, 0.05}), 0.5, 1e-9);  // along the axis: the centre column
    EXPECT_EQ(dabWeight(brush, {-0.11, 0, 0}), 0.0);         // outside the radius
    // Top white, bottom black: up is +y across +z.
    alpha->values = {1, 1, 0, 0};
    EXPECT_NEAR(dabWeight(brush, {0, 0.099, 0}), 1.0, 1e-9);
    EXPECT_NEAR(dabWeight(brush, {0, -0.099, 0}), 0.0, 1e-9);
    // Times the falloff.
    // Times the falloff: at a quarter radius up, linear 0.75 and the image 0.75 (a quarter of
    // the way from the top row's centre to the bottom one's).
    brush.falloff = Falloff::Linear;
    EXPECT_NEAR(dabWeight(brush, {0, 0.025, 0}), 0.75 * 0.75, 1e-9);
    // Without an image the falloff alone.
    brush.alpha.reset();
    EXPECT_NEAR(dabWeight(brush, {0, 0.025, 0}), 0.75, 1e-9);

    // A stroke with the left-white alpha on the sphere's front paints only left of the dab.
    const fs::path dir = test::freshFolder("editor_document", "paint_alpha");
    auto d = openOrFail(writeProject(dir, "sphere.obj"));
    ASSERT_TRUE(d);
    executeOrFail(*d, makeNewMapCommand(*d, 0, MapChannel::Density, kMap, kMap, 0.0, ""));
    const TriangleMesh& mesh = *d->assets(0).mesh;
    auto hit = raycast(mesh, {0.05, 0.1, 2}, {0, 0, -1});
    ASSERT_TRUE(hit);
    alpha->values = {1, 0, 1, 0};
    brush.alpha = alpha;
    brush.falloff = Falloff::Constant;
    brush.radius = 0.15;
    executeOrFail(*d, makeStrokeCommand(*d, 0, MapChannel::Density, brush,
                                        std::vector<Eigen::Vector3d>{hit->point}));
    const std::vector<float>& v = d->map(0, MapChannel::Density)->values;
    int left = 0, right = 0;
    for (const PixelPoint& p : pixelPoints(mesh, kMap, kMap)) {
        const Eigen::Vector3d offset = p.point - hit->point;
        if (offset.norm() > brush.radius - 0.02 || p.point.z() < 0) continue;
        if (offset.x() < -0.04) left += v[p.pixel] > 0.6f;
        if (offset.x() > 0.04) right += v[p.pixel] > 0.4f;
    }
    EXPECT_GT(left, 10);
    EXPECT_EQ(right, 0);
    // A file that is not an image: a clear error naming it, the brush unchanged.
    const fs::path bogus = dir / "not_an_image.png";
    std::ofstream(bogus) << "hello";
    const Status bad = loadBrushAlpha(brush, bogus);
    ASSERT_FALSE(bad.ok());
    EXPECT_NE(bad.error().message.find("not_an_image.png"), std::string::npos)
        << bad.error().message;
    EXPECT_EQ(brush.alpha, alpha);
}

TEST(EditorPaint, FillAllEraseAndSmooth) {
    const fs::path dir = test::freshFolder("editor_document", "paint_fill");
    auto d = openOrFail(writeProject(dir, "sphere.obj"));
    ASSERT_TRUE(d);
    const TriangleMesh& mesh = *d->assets(0).mesh;
    // The first edit on a body without a map makes one (same undo step).
    executeOrFail(*d, makeFillAllCommand(*d, 0, MapChannel::Thickness, 0.5));
    const PaintedMap* map = d->map(0, MapChannel::Thickness);
    ASSERT_TRUE(map);
    EXPECT_EQ(map->width, kDefaultMapSize);
    for (float x : map->values) ASSERT_EQ(x, 0.5f);
    EXPECT_FALSE(d->project().bodies[0].material.shellThicknessMap.empty());

    Brush erase;
    erase.mode = BrushMode::Erase;
    erase.radius = 0.08;
    erase.falloff = Falloff::Linear;
    const Eigen::Vector3d top(0, 0.5, 0);
    const std::vector<Eigen::Vector3d> points{top};
    const std::vector<float> filled = map->values;
    executeOrFail(*d, makeStrokeCommand(*d, 0, MapChannel::Thickness, erase, points));
    int lowered = 0;
    for (const PixelPoint& p : pixelPoints(mesh, 64, 64)) {
        // Sample the 512 map at this pixel centre's own pixel.
        const int x = static_cast<int>(p.uv.x() * 512), y = static_cast<int>((1 - p.uv.y()) * 512);
        const float value = map->values[static_cast<std::size_t>(y) * 512 + x];
        const double distance = (p.point - top).norm();
        if (distance > erase.radius + 0.01) EXPECT_EQ(value, 0.5f);
        if (distance < 0.5 * erase.radius) {
            EXPECT_LT(value, 0.5f * 0.6f);  // linear falloff: weight > 0.5 in the inner half
            ++lowered;
        }
    }
    EXPECT_GT(lowered, 0);

    // Smooth pulls values toward their neighbourhood's mean: the edge of the erased spot rises
    // or falls toward it, nothing leaves 0..0.5, nothing far away moves.
    Brush smooth;
    smooth.mode = BrushMode::Smooth;
    smooth.radius = 0.1;
    const std::vector<float> erased = map->values;
    executeOrFail(*d, makeStrokeCommand(*d, 0, MapChannel::Thickness, smooth, points));
    bool changed = false;
    for (std::size_t i = 0; i < erased.size(); ++i) {
        ASSERT_GE(map->values[i], 0.0f);
        ASSERT_LE(map->values[i], 0.5f + 1e-6f);
        changed |= map->values[i] != erased[i];
    }
    EXPECT_TRUE(changed);
    ASSERT_TRUE(d->undo());
    EXPECT_EQ(map->values, erased);
    ASSERT_TRUE(d->undo());
    EXPECT_EQ(map->values, filled);
    ASSERT_TRUE(d->undo());  // the fill, and the map it made
    EXPECT_EQ(d->map(0, MapChannel::Thickness), nullptr);
    EXPECT_TRUE(d->project().bodies[0].material.shellThicknessMap.empty());
    EXPECT_FALSE(d->dirty());
}

TEST(EditorPaint, FillIslandFillsOnlyTheChartUnderThePoint) {
    const fs::path dir = test::freshFolder("editor_document", "paint_island");
    auto d = openOrFail(writeProject(dir, "box.obj"));
    ASSERT_TRUE(d);
    executeOrFail(*d, makeNewMapCommand(*d, 0, MapChannel::Permeability, 96, 64, 0.0, ""));
    const TriangleMesh& mesh = *d->assets(0).mesh;
    // The box is 1.0 x 0.5 x 0.25: the +x face is at x = 0.5.
    executeOrFail(*d, makeFillIslandCommand(*d, 0, MapChannel::Permeability, {0.5, 0.1, 0.05}, 1.0,
                                            /*mirrorX=*/false));
    const PaintedMap* map = d->map(0, MapChannel::Permeability);
    int onFace = 0;
    for (const PixelPoint& p : pixelPoints(mesh, 96, 64)) {
        const bool plusX = std::abs(p.point.x() - 0.5) < 1e-9;
        const bool minusX = std::abs(p.point.x() + 0.5) < 1e-9;
        if (plusX) {
            EXPECT_EQ(map->values[p.pixel], 1.0f);
            ++onFace;
        } else if (!minusX) {
            EXPECT_EQ(map->values[p.pixel], 0.0f) << p.point.transpose();
        }
    }
    EXPECT_GT(onFace, 10);
    // Mirrored, the -x face fills too.
    executeOrFail(*d, makeFillIslandCommand(*d, 0, MapChannel::Permeability, {0.5, 0.1, 0.05}, 0.25,
                                            /*mirrorX=*/true));
    for (const PixelPoint& p : pixelPoints(mesh, 96, 64)) {
        if (std::abs(std::abs(p.point.x()) - 0.5) < 1e-9) {
            EXPECT_EQ(map->values[p.pixel], 0.25f);
        }
    }
}

TEST(EditorPaint, PickReadsTheValueUnderThePoint) {
    const fs::path dir = test::freshFolder("editor_document", "paint_pick");
    auto d = openOrFail(writeProject(dir, "sphere.obj"));
    ASSERT_TRUE(d);
    executeOrFail(*d, makeNewMapCommand(*d, 0, MapChannel::Permeability, 64, 64, 0.3, ""));
    auto surface = d->paintSurface(0, MapChannel::Permeability);
    ASSERT_TRUE(surface.ok());
    auto v = pickValue(*d->map(0, MapChannel::Permeability), **surface, {0, 0.5, 0});
    ASSERT_TRUE(v);
    EXPECT_FLOAT_EQ(*v, 0.3f);
}

TEST(EditorMaps, SixteenBitPngRoundTrips) {
    PaintedMap map;
    map.width = 37;
    map.height = 5;
    for (int i = 0; i < map.width * map.height; ++i) map.values.push_back(i / 184.0f);
    const fs::path dir = test::freshFolder("editor_document", "png16");
    ASSERT_TRUE(savePaintedMap(map, dir / "m.png").ok());
    const std::string bytes = test::readFile(dir / "m.png");
    ASSERT_GT(bytes.size(), 33u);
    EXPECT_EQ(static_cast<unsigned char>(bytes[24]), 16);  // IHDR bit depth
    Result<PaintedMap> back = loadPaintedMap(dir / "m.png");
    ASSERT_TRUE(back.ok()) << back.error().message;
    EXPECT_EQ(back->width, 37);
    EXPECT_EQ(back->height, 5);
    for (std::size_t i = 0; i < map.values.size(); ++i) {
        EXPECT_NEAR(back->values[i], map.values[i], 0.5 / 65535 + 1e-7);
    }
    // Loading what was saved and saving it again gives the same bytes.
    ASSERT_TRUE(savePaintedMap(*back, dir / "m2.png").ok());
    EXPECT_EQ(test::readFile(dir / "m2.png"), bytes);
}

TEST(EditorProject, DirtyMarkerFollowsTheHistory) {
    const fs::path dir = test::freshFolder("editor_document", "dirty");
    auto d = openOrFail(writeProject(dir, "box.obj"));
    ASSERT_TRUE(d);
    EXPECT_FALSE(d->dirty());
    EXPECT_EQ(d->title(), "test.plim.json");
    executeOrFail(*d, makeSetPropertyCommand(*d, "/bodies/0/material/density", 700.0));
    EXPECT_TRUE(d->dirty());
    EXPECT_EQ(d->title(), "*test.plim.json");
    EXPECT_EQ(*d->project().bodies[0].material.density, 700.0);
    d->undo();
    EXPECT_FALSE(d->dirty());
    EXPECT_EQ(*d->project().bodies[0].material.density, 500.0);
    d->redo();
    ASSERT_TRUE(d->save().ok());
    EXPECT_FALSE(d->dirty());
    d->undo();
    EXPECT_TRUE(d->dirty());
    // An invalid value is refused, with the project's own message.
    auto bad = makeSetPropertyCommand(*d, "/bodies/0/material/density", -1.0);
    ASSERT_FALSE(bad.ok());
    EXPECT_NE(bad.error().message.find("material.density"), std::string::npos);
}

TEST(EditorProject, HistoryJumpsUndoAndRedoToExactlyEachStepsState) {
    // The undo-history panel's click: to any step and back, each state byte for byte as it
    // was after that step; a new edit after a jump back drops the steps past it.
    const fs::path dir = test::freshFolder("editor_document", "history");
    auto d = openOrFail(writeProject(dir, "sphere.obj"));
    ASSERT_TRUE(d);
    const TriangleMesh& mesh = *d->assets(0).mesh;
    struct State {
        std::optional<std::vector<float>> map;
        double density;
    };
    auto now = [&] {
        const PaintedMap* map = d->map(0, MapChannel::Density);
        return State{map ? std::optional(map->values) : std::nullopt,
                     *d->project().bodies[0].material.density};
    };
    std::vector<State> states{now()};
    std::vector<std::string> names;
    auto step = [&](Result<std::unique_ptr<Command>> command) {
        executeOrFail(*d, std::move(command));
        states.push_back(now());
        names.push_back(d->undoName());
    };
    Brush brush;
    brush.radius = 0.1;
    auto hitA = raycast(mesh, {2, 0.1, 0.3}, {-1, 0, 0});
    auto hitB = raycast(mesh, {0.1, 2, 0.2}, {0, -1, 0});
    ASSERT_TRUE(hitA && hitB);
    step(makeNewMapCommand(*d, 0, MapChannel::Density, kMap, kMap, 0.0, ""));
    brush.value = 0.75;
    step(makeStrokeCommand(*d, 0, MapChannel::Density, brush,
                           std::vector<Eigen::Vector3d>{hitA->point}));
    step(makeSetPropertyCommand(*d, "/bodies/0/material/density", 700.0));
    brush.value = 0.3;
    step(makeStrokeCommand(*d, 0, MapChannel::Density, brush,
                           std::vector<Eigen::Vector3d>{hitB->point, hitA->point}));
    EXPECT_EQ(d->historyNames(), names);
    EXPECT_EQ(d->historyPosition(), 4u);
    auto expectState = [&](std::size_t i) {
        const State s = now();
        EXPECT_EQ(s.map.has_value(), states[i].map.has_value()) << "step " << i;
        if (s.map && states[i].map) EXPECT_TRUE(*s.map == *states[i].map) << "step " << i;
        EXPECT_EQ(s.density, states[i].density) << "step " << i;
    };
    for (std::size_t to : {1u, 4u, 0u, 2u, 3u, 1u}) {
        ASSERT_TRUE(d->jumpToHistory(to));
        EXPECT_EQ(d->historyPosition(), to);
        EXPECT_EQ(d->historyNames(), names) << "a jump keeps every step";
        expectState(to);
    }
    EXPECT_TRUE(d->dirty());
    ASSERT_TRUE(d->jumpToHistory(0));
    EXPECT_FALSE(d->dirty()) << "the state as opened";
    ASSERT_TRUE(d->jumpToHistory(99));  // clamped to the last step
    EXPECT_EQ(d->historyPosition(), 4u);
    // Back to step 2 and a new edit: steps 3 and 4 are gone.
    ASSERT_TRUE(d->jumpToHistory(2));
    executeOrFail(*d, makeSetPropertyCommand(*d, "/bodies/0/material/density", 650.0));
    ASSERT_EQ(d->historyNames().size(), 3u);
    EXPECT_EQ(d->historyNames()[1], names[1]);
    ASSERT_TRUE(d->jumpToHistory(2));
    expectState(2);
}

TEST(EditorProject, InterruptedSaveLeavesThePreviousFileIntact) {
    const fs::path dir = test::freshFolder("editor_document", "atomic");
    const fs::path path = writeProject(dir, "sphere.obj");
    auto d = openOrFail(path);
    ASSERT_TRUE(d);
    executeOrFail(*d, makeFillAllCommand(*d, 0, MapChannel::Permeability, 0.5));
    ASSERT_TRUE(d->save().ok());
    const std::string savedProject = test::readFile(path);
    const fs::path mapPath = d->assets(0).maps[0].path;
    const std::string savedMap = test::readFile(mapPath);
    ASSERT_FALSE(savedMap.empty());

    executeOrFail(*d, makeFillAllCommand(*d, 0, MapChannel::Permeability, 1.0));
    executeOrFail(*d, makeSetPropertyCommand(*d, "/name", "changed"));
    // The save dies (as in a crash or a power cut) after writing a file and before renaming
    // it over the old one.
    const pid_t child = ::fork();
    ASSERT_GE(child, 0);
    if (child == 0) {
        setBeforeReplaceHookForTesting([](const fs::path&, const fs::path&) { ::_exit(42); });
        (void)d->save();
        ::_exit(0);
    }
    int status = 0;
    ::waitpid(child, &status, 0);
    ASSERT_TRUE(WIFEXITED(status));
    EXPECT_EQ(WEXITSTATUS(status), 42);  // it did die inside the save
    EXPECT_EQ(test::readFile(path), savedProject);
    EXPECT_EQ(test::readFile(mapPath), savedMap);
    EXPECT_TRUE(loadProject(path).ok());
    // And a save that is not interrupted goes through.
    ASSERT_TRUE(d->save().ok());
    EXPECT_EQ(loadProject(path)->name, "changed");
    EXPECT_NEAR(loadPaintedMap(mapPath)->values[0], 1.0f, 1e-6);
}

TEST(EditorProject, AutosaveIsOfferedAfterACrashAndRecoversTheEdits) {
    const fs::path dir = test::freshFolder("editor_document", "autosave");
    const fs::path path = writeProject(dir, "sphere.obj");
    std::vector<float> painted;
    {
        auto d = openOrFail(path);
        ASSERT_TRUE(d);
        EXPECT_FALSE(Document::findAutosave(path));
        executeOrFail(*d, makeNewMapCommand(*d, 0, MapChannel::Permeability, 64, 64, 0.0, ""));
        Brush brush;
        brush.radius = 0.2;
        brush.value = 0.8;
        const std::vector<Eigen::Vector3d> points{{0, 0.5, 0}};
        executeOrFail(*d, makeStrokeCommand(*d, 0, MapChannel::Permeability, brush, points));
        executeOrFail(*d, makeSetPropertyCommand(*d, "/bodies/0/drag_coefficient", 0.7));
        painted = d->map(0, MapChannel::Permeability)->values;
        ASSERT_TRUE(d->autosave().ok());
        // The editor "crashes": the document goes away without save or discardAutosave.
    }
    const std::optional<fs::path> offered = Document::findAutosave(path);
    ASSERT_TRUE(offered);
    // The project on disk is the old one.
    EXPECT_EQ(loadProject(path)->bodies[0].dragCoefficient, 1.0);
    Result<std::unique_ptr<Document>> recovered = Document::recover(*offered);
    ASSERT_TRUE(recovered.ok()) << recovered.error().message;
    Document& r = **recovered;
    EXPECT_TRUE(r.dirty());
    EXPECT_EQ(fs::absolute(r.path()), fs::absolute(path).lexically_normal());
    EXPECT_EQ(r.project().bodies[0].dragCoefficient, 0.7);
    const PaintedMap* map = r.map(0, MapChannel::Permeability);
    ASSERT_TRUE(map);
    ASSERT_EQ(map->values.size(), painted.size());
    for (std::size_t i = 0; i < painted.size(); ++i) {
        ASSERT_NEAR(map->values[i], painted[i], 0.5 / 65535 + 1e-7);
    }
    ASSERT_TRUE(r.save().ok());
    EXPECT_FALSE(Document::findAutosave(path));  // a clean save retires it
    EXPECT_EQ(loadProject(path)->bodies[0].dragCoefficient, 0.7);
    EXPECT_TRUE(fs::exists(r.assets(0).maps[0].path));
}

TEST(EditorProject, ImportMeshAndSaveAsRebasePaths) {
    const fs::path dir = test::freshFolder("editor_document", "saveas");
    auto d = openOrFail(writeProject(dir, "sphere.obj"));
    ASSERT_TRUE(d);
    executeOrFail(*d, makeImportMeshCommand(*d, test::assetPath("box.obj"), std::nullopt));
    ASSERT_EQ(d->bodyCount(), 2u);
    ASSERT_TRUE(d->assets(1).mesh);
    executeOrFail(*d, makeFillAllCommand(*d, 1, MapChannel::Permeability, 0.25));
    ASSERT_TRUE(d->saveAs(dir / "sub" / "moved.plim.json").ok());
    Result<Project> moved = loadProject(dir / "sub" / "moved.plim.json");
    ASSERT_TRUE(moved.ok()) << moved.error().message;
    EXPECT_TRUE(fs::exists(moved->resolvePath(moved->bodies[1].mesh)));
    EXPECT_TRUE(fs::exists(moved->resolvePath(moved->bodies[1].permeabilityMap)));
    EXPECT_NEAR(loadPaintedMap(moved->resolvePath(moved->bodies[1].permeabilityMap))->values[7],
                0.25f, 1e-4);
    d->undo();
    d->undo();
    EXPECT_EQ(d->bodyCount(), 1u);
}

TEST(EditorProject, SaveAsNeverWritesOutsideTheNewFolder) {
    // A map beside the project's folder ("../maps/ball.png"): Save As into a sibling folder
    // must not write the painted map back through "../" over the original project's file.
    const fs::path dir = test::freshFolder("editor_document", "saveas_outside");
    fs::create_directories(dir / "a");
    fs::create_directories(dir / "maps");
    PaintedMap original;
    original.width = original.height = 32;
    original.values.assign(32 * 32, 0.5f);
    ASSERT_TRUE(savePaintedMap(original, dir / "maps" / "ball.png").ok());
    const std::string before = test::readFile(dir / "maps" / "ball.png");
    const fs::path path = dir / "a" / "test.plim.json";
    std::ofstream(path)
        << R"({"schema_version": 1, "name": "t", "bodies": [{"name": "ball", "mesh": ")"
        << test::assetPath("sphere.obj").string()
        << R"(", "permeability_map": "../maps/ball.png", "material": {"density": 500}}]})";
    auto d = openOrFail(path);
    ASSERT_TRUE(d);
    executeOrFail(*d, makeFillAllCommand(*d, 0, MapChannel::Permeability, 0.25));
    fs::create_directories(dir / "b");
    ASSERT_TRUE(d->saveAs(dir / "b" / "copy.plim.json").ok());
    EXPECT_EQ(test::readFile(dir / "maps" / "ball.png"), before);  // the original project's map
    Result<Project> copy = loadProject(dir / "b" / "copy.plim.json");
    ASSERT_TRUE(copy.ok()) << copy.error().message;
    const fs::path written = copy->resolvePath(copy->bodies[0].permeabilityMap);
    EXPECT_EQ(written.parent_path(), dir / "b");
    Result<PaintedMap> back = loadPaintedMap(written);
    ASSERT_TRUE(back.ok()) << back.error().message;
    EXPECT_NEAR(back->values[7], 0.25f, 1e-4);
}

TEST(EditorLayout, PanelsTileTheWindowAndComeBackAfterItShrinksAndGrows) {
    // Panels did not come back after the window shrank and grew again. The
    // layout is shares of the column, so the same window size gives the same panels.
    const PanelLayout layout;
    auto check = [](const WindowLayout& l, float width, float height, float menu, float status) {
        EXPECT_FLOAT_EQ(l.view.x, 0);
        EXPECT_FLOAT_EQ(l.view.y, menu);
        EXPECT_FLOAT_EQ(l.view.w + l.panels[0].w, width);
        float y = menu;
        for (const PanelRect& p : l.panels) {
            EXPECT_FLOAT_EQ(p.x, l.view.w);
            EXPECT_NEAR(p.y, y, 1e-3);
            y += p.h;
        }
        EXPECT_NEAR(y, height - status, 1e-3);  // down to the status line, no gap
        // The column is the four panels together, right of the view.
        EXPECT_FLOAT_EQ(l.column.x, l.view.w);
        EXPECT_FLOAT_EQ(l.column.y, l.panels[0].y);
        EXPECT_FLOAT_EQ(l.column.w, l.panels[0].w);
        EXPECT_NEAR(l.column.y + l.column.h, l.panels[3].y + l.panels[3].h, 1e-3);
    };
    const WindowLayout big = windowLayout(layout, 1024, 640, 19, 23);
    check(big, 1024, 640, 19, 23);
    EXPECT_FLOAT_EQ(big.panels[0].w, 400);  // min(400, 0.4 of the width)
    for (const PanelRect& p : big.panels) EXPECT_GE(p.h, kMinPanelHeight);
    const WindowLayout small = windowLayout(layout, 300, 200, 19, 23);
    check(small, 300, 200, 19, 23);
    EXPECT_FLOAT_EQ(small.panels[0].w, 180);
    for (const PanelRect& p : small.panels)
        EXPECT_GE(p.h, std::min(kMinPanelHeight, 158.0f / 4) - 1e-3);
    const WindowLayout again = windowLayout(layout, 1024, 640, 19, 23);
    for (int i = 0; i < 4; ++i) {
        EXPECT_EQ(again.panels[i].y, big.panels[i].y);
        EXPECT_EQ(again.panels[i].h, big.panels[i].h);
    }
    // A window with no room at all: nothing negative.
    const WindowLayout none = windowLayout(layout, 40, 30, 19, 23);
    for (const PanelRect& p : none.panels) EXPECT_GE(p.h, 0);
    EXPECT_GE(none.view.w, 0);
}

TEST(EditorLayout, UvViewBesideTheViewIsASquareAndTheColumnKeepsThreePanels) {
    PanelLayout layout;
    layout.uvBesideView = true;
    // A wide window: the UV view is a square as tall as the view.
    const float width = 2560, height = 1000, menu = 19, status = 23, below = height - menu - status;
    const WindowLayout l = windowLayout(layout, width, height, menu, status);
    EXPECT_EQ(l.columnPanels, 3);
    // The 3D view, then the UV view as tall as it (a square), then the column: side by side,
    // tiling the width.
    const PanelRect& uv = l.panels[3];
    EXPECT_FLOAT_EQ(l.view.x, 0);
    EXPECT_FLOAT_EQ(uv.x, l.view.w);
    EXPECT_FLOAT_EQ(uv.y, menu);
    EXPECT_FLOAT_EQ(uv.h, below);
    EXPECT_FLOAT_EQ(uv.w, below);
    EXPECT_FLOAT_EQ(l.column.x, uv.x + uv.w);
    EXPECT_FLOAT_EQ(l.column.x + l.column.w, width);
    EXPECT_GT(l.view.w, uv.w);
    // The other three panels fill the column top to bottom in their shares.
    float y = menu;
    for (int i = 0; i < 3; ++i) {
        EXPECT_FLOAT_EQ(l.panels[i].x, l.column.x);
        EXPECT_NEAR(l.panels[i].y, y, 1e-3);
        y += l.panels[i].h;
    }
    EXPECT_NEAR(y, menu + below, 1e-3);
    EXPECT_NEAR(l.panels[0].h / l.panels[1].h, layout.shares[0] / layout.shares[1], 1e-4);
    // 1600 x 900: the UV view takes at most half of what the column leaves.
    const WindowLayout narrow = windowLayout(layout, 1600, 900, menu, status);
    EXPECT_FLOAT_EQ(narrow.panels[3].w, 600);
    EXPECT_FLOAT_EQ(narrow.view.w, 600);
    EXPECT_FLOAT_EQ(narrow.panels[3].h, 900 - menu - status);
    // Off: the four panels in the column as before.
    layout.uvBesideView = false;
    EXPECT_EQ(windowLayout(layout, width, height, menu, status).columnPanels, 4);
}

TEST(EditorLayout, SplittersTradeHeightBetweenNeighboursDownToTheMinimum) {
    PanelLayout layout;
    const float column = 598;
    const WindowLayout before = windowLayout(layout, 1024, 640, 19, 23);
    dragRowSplitter(layout, 1, 50, column);  // Layers grows, the Inspector gives it up
    const WindowLayout after = windowLayout(layout, 1024, 640, 19, 23);
    EXPECT_NEAR(after.panels[0].h, before.panels[0].h, 1e-3);
    EXPECT_NEAR(after.panels[1].h, before.panels[1].h + 50, 1e-3);
    EXPECT_NEAR(after.panels[2].h, before.panels[2].h - 50, 1e-3);
    EXPECT_NEAR(after.panels[3].h, before.panels[3].h, 1e-3);
    // Far past the Inspector: it keeps its minimum.
    dragRowSplitter(layout, 1, 10000, column);
    EXPECT_NEAR(windowLayout(layout, 1024, 640, 19, 23).panels[2].h, kMinPanelHeight, 1e-2);
    float sum = 0;
    for (float share : layout.shares) sum += share;
    EXPECT_NEAR(sum, 1.0f, 1e-6);
    // The column: dragged left it widens, up to 0.4 of the window; right, down to its minimum.
    dragColumnSplitter(layout, -100, 1600);
    EXPECT_FLOAT_EQ(layout.columnWidth, 500);
    dragColumnSplitter(layout, -1000, 1600);
    EXPECT_FLOAT_EQ(layout.columnWidth, 640);
    dragColumnSplitter(layout, 5000, 1600);
    EXPECT_FLOAT_EQ(layout.columnWidth, kMinColumnWidth);
    // A width kept from a bigger window: the drag starts from the 320 px shown at 800.
    layout.columnWidth = 400;
    dragColumnSplitter(layout, 100, 800);
    EXPECT_FLOAT_EQ(layout.columnWidth, 220);
    // A hand-edited settings file's nonsense comes back in range.
    PanelLayout odd;
    odd.columnWidth = std::nanf("");
    odd.shares = {-1.0f, 0.0f, 2.0f, 2.0f};
    const PanelLayout fixed = sanitised(odd);
    EXPECT_FLOAT_EQ(fixed.columnWidth, 400);
    for (float share : fixed.shares) EXPECT_GT(share, 0);
}

TEST(EditorSettings, LayoutAndBrushAreKeptBetweenSessions) {
    const fs::path dir = test::freshFolder("editor_document", "settings_brush");
    Settings s;
    s.layout.columnWidth = 321;
    s.layout.shares = {0.1f, 0.2f, 0.3f, 0.4f};
    s.brush.radius = 0.2;
    s.brush.falloff = Falloff::Sharp;
    s.brush.spacing = 1.5;
    s.brush.mirrorZ = true;
    s.brush.radial = 6;
    s.brush.curve = FalloffCurve::sanitised({{0, 1}, {0.3, 0.9}, {0.7, 0.2}, {1, 0}});
    ASSERT_TRUE(s.save(dir).ok());
    const Settings back = Settings::load(dir);
    EXPECT_TRUE(back.brush.curve == s.brush.curve);
    EXPECT_FLOAT_EQ(back.layout.columnWidth, 321);
    for (int i = 0; i < 4; ++i) EXPECT_NEAR(back.layout.shares[i], 0.1f * (i + 1), 1e-6);
    EXPECT_EQ(back.brush.radius, 0.2);
    EXPECT_EQ(back.brush.falloff, Falloff::Sharp);
    EXPECT_EQ(back.brush.spacing, 1.5);
    EXPECT_TRUE(back.brush.mirrorZ);
    EXPECT_FALSE(back.brush.mirrorY);
    EXPECT_EQ(back.brush.radial, 6);
    EXPECT_FALSE(back.layout.uvBesideView);
    EXPECT_TRUE(back.seaFloor.enabled);  // the preview's floor: on, 5 m down, by default
    EXPECT_EQ(back.seaFloor.depth, SeaFloor::kDefaultDepth);
    // The UV view as a main view and the sea floor are kept between sessions.
    s.layout.uvBesideView = true;
    s.seaFloor = SeaFloor{.enabled = false, .depth = 12.5};
    ASSERT_TRUE(s.save(dir).ok());
    const Settings kept = Settings::load(dir);
    EXPECT_TRUE(kept.layout.uvBesideView);
    EXPECT_FALSE(kept.seaFloor.enabled);
    EXPECT_EQ(kept.seaFloor.depth, 12.5);
    // Nonsense in the file: the defaults for those fields, not a brush the panel cannot show.
    std::ofstream(dir / "settings.json")
        << R"({"brush": {"radius": -1, "strength": 7, "radial": 900,
        "falloff": "wobbly"}})";
    const Settings odd = Settings::load(dir);
    EXPECT_EQ(odd.brush.radius, Brush{}.radius);
    EXPECT_EQ(odd.brush.strength, Brush{}.strength);
    EXPECT_EQ(odd.brush.radial, kMaxRadialCopies);
    EXPECT_EQ(odd.brush.falloff, Brush{}.falloff);
}

TEST(EditorSettings, BrushPresetsRoundTripThroughTheSettingsFile) {
    const fs::path dir = test::freshFolder("editor_document", "settings_presets");
    Settings s;
    Brush brush;
    brush.mode = BrushMode::Erase;
    brush.radius = 0.0375;
    brush.strength = 0.3;
    brush.value = 0.125;
    brush.falloff = Falloff::Custom;
    brush.curve = FalloffCurve::sanitised({{0, 1}, {0.4, 0.8}, {1, 0}});
    brush.spacing = 0.5;
    ASSERT_TRUE(s.saveBrushPreset(" Rust spots ", brush).ok());
    brush.falloff = Falloff::Sharp;
    ASSERT_TRUE(s.saveBrushPreset("Drip", brush).ok());
    // The painter's presets cannot take a built-in's name or no name; one of the same name is
    // replaced, not doubled.
    EXPECT_FALSE(s.saveBrushPreset("Hole", brush).ok());
    EXPECT_FALSE(s.saveBrushPreset("  ", brush).ok());
    brush.radius = 0.04;
    ASSERT_TRUE(s.saveBrushPreset("Drip", brush).ok());
    ASSERT_EQ(s.brushPresets.size(), 2u);
    EXPECT_EQ(s.brushPresets[0].name, "Rust spots");
    EXPECT_EQ(s.brushPresets[1].radius, 0.04);
    ASSERT_TRUE(s.save(dir).ok());

    const Settings back = Settings::load(dir);
    ASSERT_EQ(back.brushPresets.size(), 2u);
    EXPECT_TRUE(back.brushPresets[0] == s.brushPresets[0]);
    EXPECT_TRUE(back.brushPresets[1] == s.brushPresets[1]);
    EXPECT_EQ(back.brushPresets[0].mode, BrushMode::Erase);
    EXPECT_EQ(back.brushPresets[0].falloff, Falloff::Custom);

    // Applied, a preset sets the tip and leaves the symmetry alone.
    Brush painting;
    painting.mirrorX = true;
    painting.radial = 4;
    applyBrushPreset(back.brushPresets[0], painting);
    EXPECT_TRUE(brushHasPreset(painting, s.brushPresets[0]));
    EXPECT_EQ(painting.radius, 0.0375);
    EXPECT_EQ(painting.value, 0.125);
    EXPECT_TRUE(painting.curve == s.brushPresets[0].curve);
    EXPECT_TRUE(painting.mirrorX);
    EXPECT_EQ(painting.radial, 4);
    EXPECT_FALSE(brushHasPreset(painting, s.brushPresets[1]));
    Settings removed = back;
    EXPECT_TRUE(removed.removeBrushPreset("Rust spots"));
    EXPECT_FALSE(removed.removeBrushPreset("Rust spots"));
    ASSERT_EQ(removed.brushPresets.size(), 1u);

    // The built-ins do what their names say on a permeability map.
    const auto builtins = builtinBrushPresets();
    auto builtin = [&](const std::string& name) {
        const auto it = std::find_if(builtins.begin(), builtins.end(),
                                     [&](const BrushPreset& p) { return p.name == name; });
        EXPECT_NE(it, builtins.end()) << name;
        return it == builtins.end() ? BrushPreset{} : *it;
    };
    EXPECT_EQ(builtin("Hole").value, 1.0);
    EXPECT_EQ(builtin("Hole").strength, 1.0);
    EXPECT_LT(builtin("Hole").radius, Brush{}.radius);
    EXPECT_LT(builtin("Seep").strength, 0.5);
    EXPECT_EQ(builtin("Seal").value, 0.0);
    EXPECT_EQ(builtin("Seal").mode, BrushMode::Paint);

    // A hand-edited file: a preset out of range or without a name, a second of one name and
    // one named as a built-in are left out; the good one is kept.
    std::ofstream(dir / "settings.json") << R"({"brush_presets": [
        {"name": "Good", "radius": 0.2, "strength": 0.5, "value": 0.5, "falloff": "linear"},
        {"name": "Huge", "radius": -3},
        {"radius": 0.1},
        {"name": "Odd", "falloff": "wobbly"},
        {"name": "Good", "radius": 0.3},
        {"name": "Hole", "radius": 0.5},
        7]})";
    const Settings odd = Settings::load(dir);
    ASSERT_EQ(odd.brushPresets.size(), 1u);
    EXPECT_EQ(odd.brushPresets[0].name, "Good");
    EXPECT_EQ(odd.brushPresets[0].radius, 0.2);
    EXPECT_EQ(odd.brushPresets[0].falloff, Falloff::Linear);
}

TEST(EditorSettings, RecentFilesPersistInTheConfigFolder) {
    const fs::path dir = test::freshFolder("editor_document", "settings");
    Settings s;
    s.addRecent(dir / "a.plim.json");
    s.addRecent(dir / "b.plim.json");
    s.addRecent(dir / "a.plim.json");
    ASSERT_TRUE(s.save(dir).ok());
    const Settings back = Settings::load(dir);
    ASSERT_EQ(back.recentFiles.size(), 2u);
    EXPECT_EQ(fs::path(back.recentFiles[0]).filename(), "a.plim.json");
}

TEST(EditorScript, HeadlessEditScriptPaintsUndoesAndSaves) {
    const fs::path dir = test::freshFolder("editor_document", "script");
    const fs::path project = writeProject(dir, "sphere.obj");
    const fs::path script = dir / "commands.json";
    std::ofstream(script) << R"([
      {"op": "new_map", "channel": "permeability", "size": 64, "value": 0},
      {"op": "brush", "radius": 0.15, "falloff": "constant", "value": 1},
      {"op": "paint", "rays": [{"origin": [0, 3, 0], "direction": [0, -1, 0]}]},
      {"op": "paint", "points": [[0, -0.5, 0]]},
      {"op": "undo"},
      {"op": "pick", "points": [[0, 0.5, 0]]},
      {"op": "set", "pointer": "/bodies/0/drag_coefficient", "value": 0.9}
    ])";
    const test::CommandOutput run =
        test::runPlimsoll("edit '" + project.string() + "' --script '" + script.string() + "'");
    ASSERT_EQ(run.exitCode, 0) << run.err;
    const nlohmann::json report = nlohmann::json::parse(run.out);
    EXPECT_EQ(report["results"][5]["value"], 1.0);
    Result<Project> saved = loadProject(project);
    ASSERT_TRUE(saved.ok()) << saved.error().message;
    EXPECT_EQ(saved->bodies[0].dragCoefficient, 0.9);
    Result<PaintedMap> map = loadPaintedMap(saved->resolvePath(saved->bodies[0].permeabilityMap));
    ASSERT_TRUE(map.ok()) << map.error().message;
    // Top (v near 1: row 0) painted, bottom (undone) not.
    auto sphere = loadMesh(test::assetPath("sphere.obj"));
    ASSERT_TRUE(sphere.ok());
    for (const PixelPoint& p : pixelPoints(*sphere, 64, 64)) {
        if (p.point.y() > 0.495) EXPECT_EQ(map->values[p.pixel], 1.0f);
        if (p.point.y() < 0.3) EXPECT_EQ(map->values[p.pixel], 0.0f);
    }
    // A failing command is named.
    std::ofstream(script) << R"([{"op": "paint", "channel": "colour", "points": [[0, 0, 0]]}])";
    const test::CommandOutput bad =
        test::runPlimsoll("edit '" + project.string() + "' --script '" + script.string() + "'");
    EXPECT_EQ(bad.exitCode, 1);
    EXPECT_NE(bad.err.find("command 0"), std::string::npos) << bad.err;
}

// A script nested past the limit is refused before it is parsed (a set value or a graph deep
// enough overflowed the stack of the commands that print and re-parse them), naming the
// script; a value quoted in a message is an excerpt.
TEST(EditorScript, DeepScriptsAreRefusedAndMessagesQuoteExcerpts) {
    const fs::path dir = test::freshFolder("editor_document", "script_deep");
    const fs::path project = writeProject(dir, "sphere.obj");
    const std::string before = test::readFile(project);
    const fs::path script = dir / "commands.json";
    const std::string deep = std::string(200000, '[') + std::string(200000, ']');
    for (const std::string op :
         {R"({"op": "set", "pointer": "/bodies/0/drag_coefficient", "value": )",
          R"({"op": "graph_replace", "graph": )"}) {
        test::writeFile(script, "[" + op + deep + "}]");
        const test::CommandOutput run =
            test::runPlimsoll("edit '" + project.string() + "' --script '" + script.string() + "'");
        EXPECT_EQ(run.exitCode, 1) << run.err;
        EXPECT_CONTAINS(run.err, "commands.json: JSON nested more than 128");
        EXPECT_EQ(test::readFile(project), before);
    }
    test::writeFile(script, R"([{"op": ")" + std::string(100000, 'x') + R"("}])");
    const test::CommandOutput unknown =
        test::runPlimsoll("edit '" + project.string() + "' --script '" + script.string() + "'");
    EXPECT_EQ(unknown.exitCode, 1);
    EXPECT_CONTAINS(unknown.err, "unknown op \"xxxxxxxx");
    EXPECT_LT(unknown.err.size(), 400u) << "the message quotes the whole op";
}

// Labels over a 1024 x 640 view (from y = 20): the legend in the lower-left corner; above the
// Live preview window where that window opens there; right of a window too tall to go above;
// the corner again where nothing is clear. The performance readout in the lower-right corner,
// the mirror image: left of a window too tall, above the window and the legend together when
// both reach its corner. Never under what it avoids when a clear place exists, never outside
// the view or in its title line.
TEST(EditorOverlay, LabelsKeepClearOfTheLivePreviewWindowAndEachOther) {
    const Eigen::AlignedBox2f view(Eigen::Vector2f(0, 20), Eigen::Vector2f(1024, 660));
    const Eigen::Vector2f size(200, 48);
    auto box = [](float x0, float y0, float x1, float y1) {
        return Eigen::AlignedBox2f(Eigen::Vector2f(x0, y0), Eigen::Vector2f(x1, y1));
    };
    auto clear = [&](const Eigen::Vector2f& at, std::initializer_list<Eigen::AlignedBox2f> avoid) {
        const Eigen::AlignedBox2f label(at, at + size);
        for (const auto& b : avoid)
            if (b.intersects(label)) return false;
        return view.contains(label) && at.y() >= 20 + 24;
    };
    auto place = [&](std::initializer_list<Eigen::AlignedBox2f> avoid, ViewCorner corner) {
        const std::vector<Eigen::AlignedBox2f> boxes(avoid);
        return overlayPlace(view, size, boxes, corner);
    };
    const Eigen::Vector2f corner = place({}, ViewCorner::LowerLeft);
    EXPECT_EQ(corner, Eigen::Vector2f(10, 660 - 10 - 48));
    EXPECT_EQ(place({Eigen::AlignedBox2f()}, ViewCorner::LowerLeft), corner);  // empty: nothing
    // A window elsewhere leaves it there.
    EXPECT_EQ(place({box(700, 300, 1000, 650)}, ViewCorner::LowerLeft), corner);
    // The preview's first place: the view's lower-left corner, 340 wide, 260 high.
    const Eigen::AlignedBox2f preview = box(8, 392, 348, 652);
    const Eigen::Vector2f above = place({preview}, ViewCorner::LowerLeft);
    EXPECT_EQ(above, Eigen::Vector2f(10, 392 - 6 - 48));
    EXPECT_TRUE(clear(above, {preview}));
    // Unfolded to nearly the view's height: to its right.
    const Eigen::AlignedBox2f tall = box(8, 40, 348, 652);
    const Eigen::Vector2f right = place({tall}, ViewCorner::LowerLeft);
    EXPECT_EQ(right, Eigen::Vector2f(348 + 6, corner.y()));
    EXPECT_TRUE(clear(right, {tall}));
    // Across the whole view: nowhere is clear, the corner stays.
    EXPECT_EQ(place({box(0, 40, 1024, 660)}, ViewCorner::LowerLeft), corner);

    // The lower-right corner mirrors it.
    EXPECT_EQ(place({}, ViewCorner::LowerRight), Eigen::Vector2f(1024 - 10 - 200, corner.y()));
    const Eigen::AlignedBox2f tallRight = box(700, 40, 1016, 652);
    EXPECT_EQ(place({tallRight}, ViewCorner::LowerRight),
              Eigen::Vector2f(700 - 6 - 200, corner.y()));
    // A narrow view (300 wide) with the preview and the legend above it both in its corner:
    // above the two, clear of both.
    const Eigen::AlignedBox2f narrow(Eigen::Vector2f(0, 20), Eigen::Vector2f(300, 660));
    const Eigen::AlignedBox2f legend(above, above + size);
    const std::vector<Eigen::AlignedBox2f> both = {preview, legend};
    const Eigen::Vector2f readout = overlayPlace(narrow, size, both, ViewCorner::LowerRight);
    EXPECT_EQ(readout, Eigen::Vector2f(300 - 10 - 200, legend.min().y() - 6 - 48));
    EXPECT_FALSE(preview.intersects(Eigen::AlignedBox2f(readout, readout + size)));
    EXPECT_FALSE(legend.intersects(Eigen::AlignedBox2f(readout, readout + size)));
}

TEST(EditorOverlay, LegendGivesTheDensityMapItsShellScale) {
    BodyDesc body;
    body.material.shellSurfaceDensity = 12.5;
    const OverlayLegend density = overlayLegend(Overlay::Density, &body);
    EXPECT_TRUE(density.ramp);
    EXPECT_EQ(density.low, "0 kg/m^2");
    EXPECT_EQ(density.high, "12.5 kg/m^2");
    EXPECT_NE(overlayLegend(Overlay::Density, nullptr).high.find("no shell"), std::string::npos);
    EXPECT_FALSE(overlayLegend(Overlay::Position, &body).ramp);
    EXPECT_TRUE(overlayLegend(Overlay::None, &body).meaning.empty());
    for (Overlay o : kOverlays) {
        if (o != Overlay::None)
            EXPECT_FALSE(overlayLegend(o, &body).meaning.empty()) << overlayName(o);
    }
}

TEST(EditorOverlay, HoverReadoutGivesDepthPressureAndTheNodeFed) {
    // Beside the map's value, the physics at the point under the
    // cursor. The damaged boat floats 0.15 m up, unrotated, on flat water at 0, in fresh water;
    // its four compartments run along z (stern at -2.25, forepeak at +2.25).
    Result<std::unique_ptr<Document>> opened = Document::open(
        std::filesystem::path(PLIMSOLL_SOURCE_DIR) / "projects" / "damaged_boat.plim.json");
    ASSERT_TRUE(opened.ok()) << opened.error().message;
    const Document& boat = **opened;
    // 0.35 m below the body's origin: 0.2 m under water, rho g h = 1000 * 9.81 * 0.2 Pa.
    EXPECT_EQ(surfacePointPhysics(boat, 0, Eigen::Vector3d(0, -0.35, -2.2), 0.0),
              "submerged 0.200 m: 1.96 kPa\nfeeds stern (stern compartment (engine room))");
    EXPECT_EQ(surfacePointPhysics(boat, 0, Eigen::Vector3d(0, 0.5, 2.2), 0.0),
              "dry: 0.650 m above the water\nfeeds bow (forepeak)");
    // A body without a graph: the depth line alone.
    Document plain;
    executeOrFail(plain, makeImportMeshCommand(plain, test::assetPath("box.obj"), std::nullopt));
    const std::string line = surfacePointPhysics(plain, 0, Eigen::Vector3d(0, 0, 0), 0.0);
    EXPECT_EQ(line.find('\n'), std::string::npos) << line;
    EXPECT_EQ(line.find("feeds"), std::string::npos) << line;
}

/// Two bodies (ball on sphere.obj, box on box.obj at x = 3), each with a blank kMap map of
/// permeability and then a stroke on it, unsaved: what a remove or an insert must carry along.
std::unique_ptr<Document> twoPaintedBodies(const std::string& name) {
    const fs::path dir = test::freshFolder("editor_document", name);
    const fs::path path = dir / "two.plim.json";
    std::ofstream(path) << R"({"schema_version": 1, "name": "two", "bodies": [)"
                        << R"({"name": "ball", "mesh": ")" << test::assetPath("sphere.obj").string()
                        << R"(", "material": {"density": 500}},)"
                        << R"({"name": "box", "mesh": ")" << test::assetPath("box.obj").string()
                        << R"(", "material": {"density": 400}, "position": [3, 0, 0]}]})";
    auto d = openOrFail(path);
    if (!d) return nullptr;
    Brush brush;
    brush.radius = 0.2;
    for (std::size_t b = 0; b < 2; ++b) {
        executeOrFail(*d, makeNewMapCommand(*d, b, MapChannel::Permeability, kMap, kMap, 0.0, ""));
        const TriangleMesh& mesh = *d->assets(b).mesh;
        executeOrFail(*d, makeStrokeCommand(*d, b, MapChannel::Permeability, brush,
                                            std::vector<Eigen::Vector3d>{mesh.positions[b * 7]}));
        const std::vector<float>& v = d->map(b, MapChannel::Permeability)->values;
        EXPECT_GT(std::count_if(v.begin(), v.end(), [](float x) { return x > 0.5f; }), 0)
            << "body " << b;
    }
    return d;
}

/// What a body edit must give back exactly: the project's JSON and every body's map pixels.
struct DocumentState {
    std::string project;
    std::vector<std::optional<std::vector<float>>> maps;
    bool operator==(const DocumentState&) const = default;
};
DocumentState stateOf(const Document& d) {
    DocumentState s{projectToJson(d.project()), {}};
    for (std::size_t b = 0; b < d.bodyCount(); ++b) {
        const PaintedMap* map = d.map(b, MapChannel::Permeability);
        s.maps.push_back(map ? std::optional(map->values) : std::nullopt);
    }
    return s;
}

TEST(EditorBodies, RemoveTakesTheBodyOutAndUndoRedoRestoreEveryBodysUnsavedPaint) {
    // Remove bodies as one undoable step. Removing the first of two painted
    // (unsaved) bodies leaves the second at index 0 with its own paint; undo gives both back
    // byte for byte (project and pixels), redo removes it again the same way.
    auto d = twoPaintedBodies("bodies_remove");
    ASSERT_TRUE(d);
    const DocumentState before = stateOf(*d);
    const std::vector<float> boxPaint = *before.maps[1];
    executeOrFail(*d, makeRemoveBodyCommand(*d, 0));
    EXPECT_EQ(d->undoName(), "Remove ball");
    ASSERT_EQ(d->bodyCount(), 1u);
    EXPECT_EQ(d->project().bodies[0].name, "box");
    ASSERT_TRUE(d->map(0, MapChannel::Permeability)) << "the box's unsaved map was lost";
    EXPECT_TRUE(d->map(0, MapChannel::Permeability)->values == boxPaint);
    EXPECT_EQ(d->assets(0).meshPath, test::assetPath("box.obj"));
    const DocumentState removed = stateOf(*d);
    d->undo();
    EXPECT_TRUE(stateOf(*d) == before) << "undo of a remove";
    d->redo();
    EXPECT_TRUE(stateOf(*d) == removed) << "redo of a remove";
    // Removing the last body: the box's paint also comes back.
    executeOrFail(*d, makeRemoveBodyCommand(*d, 0));
    EXPECT_EQ(d->bodyCount(), 0u);
    d->undo();
    EXPECT_TRUE(stateOf(*d) == removed);
    // Bad input: a clear error naming the index.
    auto bad = makeRemoveBodyCommand(*d, 5);
    ASSERT_FALSE(bad.ok());
    EXPECT_NE(bad.error().message.find("no body 5"), std::string::npos) << bad.error().message;
}

TEST(EditorBodies, DuplicatePutsAUniquelyNamedCopyBesideTheOriginal) {
    // A copy of the ball after it, named "ball copy" (then "ball copy 2"), one mesh width and
    // a tenth along x, with the ball's material, its unsaved paint and its water graph under
    // files of its own (two bodies saving their edits over one file would lose one's); the
    // box after it keeps its unsaved paint.
    auto d = twoPaintedBodies("bodies_duplicate");
    ASSERT_TRUE(d);
    executeOrFail(*d, makeCreateGraphCommand(*d, 0, ""));
    GraphNode hold;
    hold.id = "hold";
    hold.position = Eigen::Vector3d(0, -0.2, 0);
    hold.capacity = 0.05;
    executeOrFail(*d, makeAddNodeCommand(*d, 0, hold));
    const DocumentState before = stateOf(*d);
    executeOrFail(*d, makeDuplicateBodyCommand(*d, 0));
    EXPECT_EQ(d->undoName(), "Duplicate ball");
    ASSERT_EQ(d->bodyCount(), 3u);
    const BodyDesc& original = d->project().bodies[0];
    const BodyDesc& copy = d->project().bodies[1];
    EXPECT_EQ(copy.name, "ball copy");
    EXPECT_EQ(copy.mesh, original.mesh);
    EXPECT_EQ(*copy.material.density, 500.0);
    // The unit sphere's mesh spans about 1 m along x (a faceted sphere of radius 0.5).
    EXPECT_NEAR(copy.position.x(), 1.1, 0.02);
    EXPECT_EQ(copy.position.y(), 0.0);
    EXPECT_EQ(copy.permeabilityMap, "maps/two_ball_copy_permeability.png");
    ASSERT_TRUE(d->map(1, MapChannel::Permeability));
    EXPECT_TRUE(d->map(1, MapChannel::Permeability)->values == *before.maps[0])
        << "the ball's paint";
    ASSERT_TRUE(copy.waterGraph);
    EXPECT_EQ(copy.waterGraph->graph, "two_ball_copy.graph.json");
    ASSERT_TRUE(d->graph(1));
    ASSERT_EQ(d->graph(1)->nodes.size(), 1u);
    EXPECT_EQ(d->graph(1)->nodes[0].id, "hold");
    EXPECT_EQ(d->project().bodies[2].name, "box");
    ASSERT_TRUE(d->map(2, MapChannel::Permeability));
    EXPECT_TRUE(d->map(2, MapChannel::Permeability)->values == *before.maps[1]);
    const DocumentState duplicated = stateOf(*d);
    d->undo();
    EXPECT_TRUE(stateOf(*d) == before) << "undo of a duplicate";
    d->redo();
    EXPECT_TRUE(stateOf(*d) == duplicated) << "redo of a duplicate";
    ASSERT_TRUE(d->graph(1));
    EXPECT_EQ(d->graph(1)->nodes.size(), 1u) << "the copy's graph after redo";
    // Painting the copy (opposite the ball's stroke) leaves the original as it was.
    const std::vector<Eigen::Vector3d>& vertices = d->assets(1).mesh->positions;
    const Eigen::Vector3d far = *std::max_element(
        vertices.begin(), vertices.end(), [&](const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
            return (a - vertices[0]).norm() < (b - vertices[0]).norm();
        });
    Brush brush;
    brush.radius = 0.2;
    executeOrFail(*d, makeStrokeCommand(*d, 1, MapChannel::Permeability, brush,
                                        std::vector<Eigen::Vector3d>{far}));
    EXPECT_TRUE(d->map(0, MapChannel::Permeability)->values == *before.maps[0]);
    EXPECT_FALSE(d->map(1, MapChannel::Permeability)->values == *before.maps[0]);
    executeOrFail(*d, makeDuplicateBodyCommand(*d, 0));
    EXPECT_EQ(d->project().bodies[1].name, "ball copy 2");
    EXPECT_EQ(d->project().bodies[1].permeabilityMap, "maps/two_ball_copy_2_permeability.png");
    // Saved with the project: each copy's files are written, and the reopened project has
    // the copies with their own paint and graphs.
    ASSERT_TRUE(d->save().ok());
    auto reopened = openOrFail(d->path());
    ASSERT_TRUE(reopened);
    EXPECT_EQ(projectToJson(reopened->project()), projectToJson(d->project()));
    for (std::size_t b = 0; b < 3; ++b) {
        SCOPED_TRACE("body " + std::to_string(b));
        ASSERT_TRUE(reopened->map(b, MapChannel::Permeability));
        ASSERT_TRUE(reopened->graph(b));
        EXPECT_EQ(reopened->graph(b)->nodes.size(), 1u);
    }
    EXPECT_TRUE(reopened->map(1, MapChannel::Permeability)->values ==
                reopened->map(0, MapChannel::Permeability)->values);
    EXPECT_FALSE(reopened->map(2, MapChannel::Permeability)->values ==
                 reopened->map(0, MapChannel::Permeability)->values)
        << "the painted copy";
}

TEST(EditorBodies, TransformEditMovesAndRotatesTheBodyAsOneStep) {
    // Body transforms editable in the inspector. One step sets position and
    // rotation, named after what changed; undo and redo give each project back byte for byte;
    // the saved project has the new place; a non-finite value is refused.
    auto d = twoPaintedBodies("bodies_transform");
    ASSERT_TRUE(d);
    const DocumentState before = stateOf(*d);
    executeOrFail(*d, makeSetBodyTransformCommand(*d, 1, Eigen::Vector3d(3, 0.25, -1),
                                                  Eigen::Vector3d::Zero()));
    EXPECT_EQ(d->undoName(), "Move box");
    executeOrFail(*d, makeSetBodyTransformCommand(*d, 1, Eigen::Vector3d(3, 0.25, -1),
                                                  Eigen::Vector3d(0, 90, 0)));
    EXPECT_EQ(d->undoName(), "Rotate box");
    const DocumentState after = stateOf(*d);
    EXPECT_NEAR(d->bodyPose(1).apply(Eigen::Vector3d(1, 0, 0)).z(), -1 - 1.0, 1e-9)
        << "Ry(90) turns +x to -z";
    d->undo();
    d->undo();
    EXPECT_TRUE(stateOf(*d) == before);
    d->redo();
    d->redo();
    EXPECT_TRUE(stateOf(*d) == after);
    ASSERT_TRUE(d->save().ok());
    Result<Project> saved = loadProject(d->path());
    ASSERT_TRUE(saved.ok()) << saved.error().message;
    EXPECT_EQ(saved->bodies[1].position, Eigen::Vector3d(3, 0.25, -1));
    EXPECT_EQ(saved->bodies[1].rotationDegrees, Eigen::Vector3d(0, 90, 0));
    auto bad = makeSetBodyTransformCommand(*d, 1, Eigen::Vector3d(std::nan(""), 0, 0),
                                           Eigen::Vector3d::Zero());
    ASSERT_FALSE(bad.ok());
    EXPECT_NE(bad.error().message.find("finite"), std::string::npos);
}

/// One dab of a brush 1.2 m across at the front of the unit sphere, (0, 0, 0.5), the viewer
/// toward +z: every texel of the sphere is within reach. Per pixel: the value painted (0..1,
/// from a blank map toward 1 at full strength, constant falloff) and the largest z of its
/// samples' normals (the side of the sphere it lies on).
struct FacingCase {
    PaintSurface surface;
    std::vector<float> painted;
    std::vector<float> maxNormalZ;
    std::vector<int> samples;
};
FacingCase paintFacing(const Brush& settings) {
    FacingCase out;
    Result<TriangleMesh> sphere = loadMesh(test::assetPath("sphere.obj"));
    EXPECT_TRUE(sphere.ok());
    Result<PaintSurface> surface = buildPaintSurface(*sphere, 64, 64);
    EXPECT_TRUE(surface.ok()) << surface.error().message;
    out.surface = *surface;
    EXPECT_EQ(out.surface.normal.size(), out.surface.sampleCount());
    PaintedMap blank;
    blank.width = blank.height = 64;
    blank.values.assign(64 * 64, 0.0f);
    Brush brush = settings;
    brush.radius = 1.2;
    brush.falloff = Falloff::Constant;
    brush.value = 1.0;
    brush.alphaAxis = Eigen::Vector3d::UnitZ();
    const std::vector<Eigen::Vector3d> dab{Eigen::Vector3d(0, 0, 0.5)};
    const PixelChange change = strokeChange(blank, out.surface, brush, dab);
    out.painted = blank.values;
    for (std::size_t k = 0; k < change.pixels.size(); ++k)
        out.painted[change.pixels[k]] = change.after[k];
    out.maxNormalZ.assign(64 * 64, -2.0f);
    out.samples.assign(64 * 64, 0);
    for (std::size_t i = 0; i < out.surface.sampleCount(); ++i) {
        float& z = out.maxNormalZ[out.surface.pixel[i]];
        z = std::max(z, out.surface.normal[i].z());
        ++out.samples[out.surface.pixel[i]];
        EXPECT_NEAR(out.surface.normal[i].norm(), 1.0f, 1e-4f) << "sample " << i;
    }
    return out;
}

TEST(EditorPaint, FrontFacesOnlyLeavesTheFarSideOfTheBodyUnpainted) {
    // Backface culling. A dab that reaches the whole sphere paints all of
    // it without the option, and with it only the texels facing the viewer (+z): the far
    // hemisphere stays blank. With Z mirror on, the mirrored dab on the far side faces a
    // mirrored viewer and paints that side too.
    Brush brush;
    const FacingCase all = paintFacing(brush);
    brush.frontFacesOnly = true;
    const FacingCase front = paintFacing(brush);
    int facing = 0, away = 0;
    for (std::size_t p = 0; p < front.painted.size(); ++p) {
        if (front.samples[p] == 0) continue;
        EXPECT_EQ(all.painted[p], 1.0f) << "pixel " << p << " out of reach without culling";
        if (front.maxNormalZ[p] > 0.01f) {
            ++facing;
            EXPECT_EQ(front.painted[p], 1.0f) << "pixel " << p << " faces the viewer";
        } else if (front.maxNormalZ[p] < -0.01f) {
            ++away;
            EXPECT_EQ(front.painted[p], 0.0f)
                << "pixel " << p << " faces away (normal z " << front.maxNormalZ[p] << ")";
        }
    }
    EXPECT_GT(facing, 500);
    EXPECT_GT(away, 500);
    brush.mirrorZ = true;
    const FacingCase mirrored = paintFacing(brush);
    for (std::size_t p = 0; p < mirrored.painted.size(); ++p) {
        if (mirrored.samples[p] > 0 && std::abs(mirrored.maxNormalZ[p]) > 0.01f) {
            EXPECT_EQ(mirrored.painted[p], 1.0f) << "pixel " << p;
        }
    }
}

TEST(EditorPaint, NormalFalloffFadesTexelsTurnedFromTheView) {
    // Blender's normal falloff at 60 degrees: texels within 30 degrees of the view direction
    // take the full weight, beyond 60 none, linearly between (45 degrees: half). Checked per
    // single-sample pixel against the angle of its own normal; at 180 the option is off.
    Brush brush;
    brush.normalAngle = 60.0;
    const FacingCase c = paintFacing(brush);
    int full = 0, partial = 0, none = 0;
    for (std::size_t p = 0; p < c.painted.size(); ++p) {
        if (c.samples[p] != 1) continue;
        const double angle =
            std::acos(std::clamp<double>(c.maxNormalZ[p], -1, 1)) * 180 / std::numbers::pi;
        const double expected = angle <= 30 ? 1.0 : angle >= 60 ? 0.0 : (60 - angle) / 30;
        EXPECT_NEAR(c.painted[p], expected, 1e-5) << "pixel " << p << " at " << angle << " degrees";
        full += expected == 1.0;
        none += expected == 0.0;
        partial += expected > 0 && expected < 1;
    }
    EXPECT_GT(full, 50);
    EXPECT_GT(partial, 50);
    EXPECT_GT(none, 500);
    EXPECT_DOUBLE_EQ(facingWeight(Brush{}, Eigen::Vector3d(0, 0, -1), Eigen::Vector3d::UnitZ()),
                     1.0);
    brush.normalAngle = 60.0;
    EXPECT_NEAR(facingWeight(brush,
                             Eigen::Vector3d(std::sin(0.25 * std::numbers::pi), 0,
                                             std::cos(0.25 * std::numbers::pi)),
                             Eigen::Vector3d::UnitZ()),
                0.5, 1e-12);
}

TEST(EditorPaint, OcclusionLeavesTexelsHiddenBehindOtherSurfaceUnpainted) {
    // Occlusion. Two plates face the viewer (+z): A at z = 0 over
    // x in [-0.5, 0.5], B 0.5 m behind it over x in [0, 1] (u: A left half, B right half). A dab
    // of radius 0.4 at (0.5, 0, -0.25) reaches both. Without occlusion it paints B also where A
    // hides it (x < 0.5); with it, B only where it shows (x > 0.5), and A as before.
    TriangleMesh plates;
    plates.source = "two plates";
    auto quad = [&](double x0, double x1, double z, double u0, double u1) {
        const auto first = static_cast<std::uint32_t>(plates.positions.size());
        for (auto [x, y, u, v] : {std::array{x0, -0.5, u0, 0.0}, std::array{x1, -0.5, u1, 0.0},
                                  std::array{x1, 0.5, u1, 1.0}, std::array{x0, 0.5, u0, 1.0}}) {
            plates.positions.emplace_back(x, y, z);
            plates.uvs.emplace_back(u, v);
        }
        plates.triangles.push_back({first, first + 1, first + 2});
        plates.triangles.push_back({first, first + 2, first + 3});
    };
    quad(-0.5, 0.5, 0.0, 0.0, 0.5);
    quad(0.0, 1.0, -0.5, 0.5, 1.0);
    Result<PaintSurface> surface = buildPaintSurface(plates, 64, 64);
    ASSERT_TRUE(surface.ok()) << surface.error().message;
    PaintedMap blank;
    blank.width = blank.height = 64;
    blank.values.assign(64 * 64, 0.0f);
    Brush brush;
    brush.radius = 0.4;
    brush.falloff = Falloff::Constant;
    brush.alphaAxis = Eigen::Vector3d::UnitZ();
    const Eigen::Vector3d centre(0.5, 0, -0.25);
    const std::vector<Eigen::Vector3d> dab{centre};
    auto paint = [&] {
        std::vector<float> values = blank.values;
        const PixelChange change = strokeChange(blank, *surface, brush, dab);
        for (std::size_t k = 0; k < change.pixels.size(); ++k)
            values[change.pixels[k]] = change.after[k];
        return values;
    };
    const std::vector<float> open = paint();
    brush.occlusion = true;
    const std::vector<float> occluded = paint();
    int hiddenB = 0, shownB = 0, onA = 0;
    for (std::size_t i = 0; i < surface->sampleCount(); ++i) {
        const Eigen::Vector3d p = surface->position[i].cast<double>();
        if ((p - centre).norm() > 0.37) continue;  // clearly inside the dab
        const std::uint32_t px = surface->pixel[i];
        if (p.z() > -0.25) {
            ++onA;
            EXPECT_EQ(occluded[px], 1.0f) << "A at x " << p.x();
        } else if (p.x() < 0.45) {
            ++hiddenB;
            EXPECT_EQ(open[px], 1.0f) << "B at x " << p.x() << " without occlusion";
            EXPECT_EQ(occluded[px], 0.0f) << "B at x " << p.x() << " is behind A";
        } else if (p.x() > 0.55) {
            ++shownB;
            EXPECT_EQ(occluded[px], 1.0f) << "B at x " << p.x() << " shows beside A";
        }
    }
    EXPECT_GT(onA, 20);
    EXPECT_GT(hiddenB, 20);
    EXPECT_GT(shownB, 20);

    // Perspective: from an eye 0.5 m in front of A, every ray to B's part in the dab crosses
    // A (a point (x, y) of B is seen through A's (x/2, y/2)), so none of B gets paint, while
    // the orthographic view showed its right half. An eye far away sees as the orthographic
    // view does.
    brush.eye = Eigen::Vector3d(0, 0, 0.5);
    const std::vector<float> near = paint();
    brush.eye = Eigen::Vector3d(0, 0, 1e4);
    const std::vector<float> far = paint();
    int seenNear = 0;
    for (std::size_t i = 0; i < surface->sampleCount(); ++i) {
        const Eigen::Vector3d p = surface->position[i].cast<double>();
        if ((p - centre).norm() > 0.37) continue;
        const std::uint32_t px = surface->pixel[i];
        EXPECT_EQ(far[px], occluded[px]) << "at " << p.transpose() << " seen from far away";
        if (p.z() > -0.25) {
            EXPECT_EQ(near[px], 1.0f) << "A at x " << p.x() << " in perspective";
        } else {
            ++seenNear;
            EXPECT_EQ(near[px], 0.0f) << "B at x " << p.x() << " is behind A in perspective";
        }
    }
    EXPECT_GT(seenNear, 40);

    // The normal falloff in perspective takes each texel's own direction toward the eye: A's
    // texel at (x, y, 0) sees the eye at (0, 0, 0.5) at atan(|(x, y)| / 0.5) from its normal,
    // so a 60 degree falloff leaves it (60 - angle) / 30 of full weight from 30 degrees on
    // (the orthographic view, straight on, gave all of A full weight).
    brush.occlusion = false;
    brush.normalAngle = 60;
    brush.eye = Eigen::Vector3d(0, 0, 0.5);
    const std::vector<float> faded = paint();
    int fading = 0;
    for (std::size_t i = 0; i < surface->sampleCount(); ++i) {
        const Eigen::Vector3d p = surface->position[i].cast<double>();
        if ((p - centre).norm() > 0.37 || p.z() < -0.25) continue;
        const double angle = std::atan2(std::hypot(p.x(), p.y()), 0.5) * 180 / std::numbers::pi;
        const double expected = std::clamp((60 - angle) / 30, 0.0, 1.0);
        if (expected > 0 && expected < 1) ++fading;
        EXPECT_NEAR(faded[surface->pixel[i]], expected, 1e-5) << "A at " << p.transpose();
    }
    EXPECT_GT(fading, 20);
}

}  // namespace
}  // namespace test_editor_document
}  // namespace plimsoll::editor
