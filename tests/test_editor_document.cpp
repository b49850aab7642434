// The editor's GL-free core: painting (3D brush in world distance across UV seams), the command
// layer (one undo step per stroke, byte-exact undo), projects (atomic save under an injected
// interruption, autosave and recovery) and headless edit scripts.
#include "cli_runner.h"
#include "test_support.h"

#include "document/command.h"
#include "document/document.h"
#include "document/paint.h"
#include "document/script.h"
#include "document/settings.h"

#include "plimsoll/file_util.h"
#include "plimsoll/mesh_io.h"
#include "plimsoll/painted_map.h"

#include <gtest/gtest.h>

#include <cstring>
#include <fstream>
#include <iterator>
#include <sys/wait.h>
#include <unistd.h>

namespace plimsoll::editor {
namespace {

namespace fs = std::filesystem;

fs::path freshDir(const std::string& name) {
    const fs::path dir = fs::temp_directory_path() / "plimsoll_tests" /
                         (name + "_" + std::to_string(::getpid()));
    fs::remove_all(dir);
    fs::create_directories(dir);
    return dir;
}

std::string readAll(const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), {});
}

/// A project with one body on `mesh` (solid + shell, so every channel can be painted).
fs::path writeProject(const fs::path& dir, const std::string& mesh) {
    const fs::path path = dir / "test.plim.json";
    std::ofstream(path) << R"({"schema_version": 1, "name": "t", "bodies": [{"name": "ball", "mesh": ")"
                        << test::assetPath(mesh).string()
                        << R"(", "material": {"density": 500, "shell": {"surface_density": 10}}}]})";
    return path;
}

std::unique_ptr<Document> openOrFail(const fs::path& path) {
    Result<std::unique_ptr<Document>> d = Document::open(path);
    EXPECT_TRUE(d.ok()) << (d.ok() ? "" : d.error().message);
    return d.ok() ? std::move(d).value() : nullptr;
}

void executeOrFail(Document& d, Result<std::unique_ptr<Command>> command) {
    ASSERT_TRUE(command.ok()) << command.error().message;
    Status s = d.execute(std::move(command).value());
    ASSERT_TRUE(s.ok()) << s.error().message;
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

TEST(EditorPaint, StrokeRaisesOnlyWithinWorldRadiusAcrossUvSeam) {
    const fs::path dir = freshDir("paint_seam");
    auto d = openOrFail(writeProject(dir, "sphere.obj"));
    ASSERT_TRUE(d);
    executeOrFail(*d, makeNewMapCommand(*d, 0, MapChannel::Permeability, kMap, kMap, 0.0, ""));
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
    const fs::path dir = freshDir("paint_mirror");
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
        const double d2 = segDist(p.point, hitA->point.cwiseProduct(m), hitB->point.cwiseProduct(m));
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

TEST(EditorPaint, FillAllEraseAndSmooth) {
    const fs::path dir = freshDir("paint_fill");
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
    const fs::path dir = freshDir("paint_island");
    auto d = openOrFail(writeProject(dir, "box.obj"));
    ASSERT_TRUE(d);
    executeOrFail(*d, makeNewMapCommand(*d, 0, MapChannel::Permeability, 96, 64, 0.0, ""));
    const TriangleMesh& mesh = *d->assets(0).mesh;
    // The box is 1.0 x 0.5 x 0.25: the +x face is at x = 0.5.
    executeOrFail(*d, makeFillIslandCommand(*d, 0, MapChannel::Permeability, {0.5, 0.1, 0.05},
                                            1.0, /*mirrorX=*/false));
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
    executeOrFail(*d, makeFillIslandCommand(*d, 0, MapChannel::Permeability, {0.5, 0.1, 0.05},
                                            0.25, /*mirrorX=*/true));
    for (const PixelPoint& p : pixelPoints(mesh, 96, 64)) {
        if (std::abs(std::abs(p.point.x()) - 0.5) < 1e-9) {
            EXPECT_EQ(map->values[p.pixel], 0.25f);
        }
    }
}

TEST(EditorPaint, PickReadsTheValueUnderThePoint) {
    const fs::path dir = freshDir("paint_pick");
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
    const fs::path dir = freshDir("png16");
    ASSERT_TRUE(savePaintedMap(map, dir / "m.png").ok());
    const std::string bytes = readAll(dir / "m.png");
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
    EXPECT_EQ(readAll(dir / "m2.png"), bytes);
}

TEST(EditorProject, DirtyMarkerFollowsTheHistory) {
    const fs::path dir = freshDir("dirty");
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

TEST(EditorProject, InterruptedSaveLeavesThePreviousFileIntact) {
    const fs::path dir = freshDir("atomic");
    const fs::path path = writeProject(dir, "sphere.obj");
    auto d = openOrFail(path);
    ASSERT_TRUE(d);
    executeOrFail(*d, makeFillAllCommand(*d, 0, MapChannel::Permeability, 0.5));
    ASSERT_TRUE(d->save().ok());
    const std::string savedProject = readAll(path);
    const fs::path mapPath = d->assets(0).maps[0].path;
    const std::string savedMap = readAll(mapPath);
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
    EXPECT_EQ(readAll(path), savedProject);
    EXPECT_EQ(readAll(mapPath), savedMap);
    EXPECT_TRUE(loadProject(path).ok());
    // And a save that is not interrupted goes through.
    ASSERT_TRUE(d->save().ok());
    EXPECT_EQ(loadProject(path)->name, "changed");
    EXPECT_NEAR(loadPaintedMap(mapPath)->values[0], 1.0f, 1e-6);
}

TEST(EditorProject, AutosaveIsOfferedAfterACrashAndRecoversTheEdits) {
    const fs::path dir = freshDir("autosave");
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
    const fs::path dir = freshDir("saveas");
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
    const fs::path dir = freshDir("saveas_outside");
    fs::create_directories(dir / "a");
    fs::create_directories(dir / "maps");
    PaintedMap original;
    original.width = original.height = 32;
    original.values.assign(32 * 32, 0.5f);
    ASSERT_TRUE(savePaintedMap(original, dir / "maps" / "ball.png").ok());
    const std::string before = readAll(dir / "maps" / "ball.png");
    const fs::path path = dir / "a" / "test.plim.json";
    std::ofstream(path) << R"({"schema_version": 1, "name": "t", "bodies": [{"name": "ball", "mesh": ")"
                        << test::assetPath("sphere.obj").string()
                        << R"(", "permeability_map": "../maps/ball.png", "material": {"density": 500}}]})";
    auto d = openOrFail(path);
    ASSERT_TRUE(d);
    executeOrFail(*d, makeFillAllCommand(*d, 0, MapChannel::Permeability, 0.25));
    fs::create_directories(dir / "b");
    ASSERT_TRUE(d->saveAs(dir / "b" / "copy.plim.json").ok());
    EXPECT_EQ(readAll(dir / "maps" / "ball.png"), before);  // the original project's map
    Result<Project> copy = loadProject(dir / "b" / "copy.plim.json");
    ASSERT_TRUE(copy.ok()) << copy.error().message;
    const fs::path written = copy->resolvePath(copy->bodies[0].permeabilityMap);
    EXPECT_EQ(written.parent_path(), dir / "b");
    Result<PaintedMap> back = loadPaintedMap(written);
    ASSERT_TRUE(back.ok()) << back.error().message;
    EXPECT_NEAR(back->values[7], 0.25f, 1e-4);
}

TEST(EditorSettings, RecentFilesPersistInTheConfigFolder) {
    const fs::path dir = freshDir("settings");
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
    const fs::path dir = freshDir("script");
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

}  // namespace
}  // namespace plimsoll::editor
