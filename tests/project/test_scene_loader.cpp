// The adapter that reads a project into a Scene (scene_loader.h): it names the file and the JSON
// path of every problem, a scene from disk equals the same body baked in memory, and a World
// runs on once the project's files are gone.
#include "plimsoll/geometry/box.h"
#include "plimsoll/io/mesh_io.h"
#include "plimsoll/project/level_cache.h"
#include "plimsoll/project/scene_loader.h"
#include "plimsoll/scene/world.h"

#include "test_support.h"
#include "world_support.h"

#include <gtest/gtest.h>

#include <fstream>
#include <sstream>

namespace plimsoll {
namespace test_scene_loader {
namespace {

namespace fs = std::filesystem;

TEST(SceneLoader, NamesTheFileAndTheJsonPathOfEveryBodysProblem) {
    const fs::path folder = test::scratchFolder("scene_loader");
    Project project;
    project.folder = folder;
    project.fileStem = "harbour";
    BodyDesc missingMesh;
    missingMesh.name = "ghost";
    missingMesh.mesh = "no_such_mesh.obj";
    missingMesh.material.density = 500.0;
    BodyDesc missingMap;
    missingMap.name = "ball";
    missingMap.mesh = test::assetPath("sphere.obj").string();
    missingMap.textureSize = 32;
    missingMap.material.shellSurfaceDensity = 2.0;
    missingMap.material.shellDensityMap = "no_such_map.png";
    BodyDesc missingGraph = missingMap;
    missingGraph.name = "hull";
    missingGraph.material.shellDensityMap.clear();
    missingGraph.waterGraph = WaterGraphDesc{};
    missingGraph.waterGraph->graph = "no_such.graph.json";
    project.bodies = {missingMesh, missingMap, missingGraph};
    Result<Scene> scene = loadScene(project);
    ASSERT_FALSE(scene.ok());
    const std::string& message = scene.error().message;
    std::istringstream lines(message);
    std::vector<std::string> starts;
    for (std::string line; std::getline(lines, line);) starts.push_back(line);
    ASSERT_EQ(starts.size(), 3u) << message;
    EXPECT_EQ(
        starts[0].rfind("harbour.plim.json: bodies[0].mesh: body 'ghost' (no_such_mesh.obj): ", 0),
        0u)
        << message;
    EXPECT_NE(starts[0].find("no_such_mesh.obj"), std::string::npos) << message;
    EXPECT_EQ(starts[1].rfind("harbour.plim.json: bodies[1].material.map: body 'ball' (", 0), 0u)
        << message;
    EXPECT_NE(starts[1].find("no_such_map.png"), std::string::npos) << message;
    EXPECT_EQ(starts[2].rfind("harbour.plim.json: bodies[2].water_graph.graph: body 'hull' (", 0),
              0u)
        << message;
    EXPECT_NE(starts[2].find("no_such.graph.json"), std::string::npos) << message;
}

TEST(SceneLoader, ASceneFromDiskEqualsTheSameBodyBakedInMemory) {
    // The adapter only reads: baking the mesh it read, in memory, gives the same textures and
    // mass properties, and two worlds of one scene share the bodies' data instead of copying it.
    Result<Project> project =
        loadProject(fs::path(PLIMSOLL_SOURCE_DIR) / "projects" / "neutral_ball.plim.json");
    ASSERT_TRUE(project.ok()) << project.error().message;
    const Scene scene = test::sceneOrFail(*project);
    ASSERT_EQ(scene.bodies.size(), 1u);
    const SceneBody& loaded = scene.bodies[0];
    const SceneBody again = test::bodyOrFail(loaded.desc, *loaded.parts.mesh);
    EXPECT_EQ(again.textures->position, loaded.textures->position);
    EXPECT_EQ(again.textures->areaVector, loaded.textures->areaVector);
    EXPECT_EQ(again.mass->mass, loaded.mass->mass);
    EXPECT_EQ(again.mass->inertia, loaded.mass->inertia);

    std::unique_ptr<World> first = test::worldOrFail(scene);
    std::unique_ptr<World> second = test::worldOrFail(scene);
    ASSERT_TRUE(first && second);
    EXPECT_EQ(first->scene().bodies[0].textures.get(), loaded.textures.get());
    EXPECT_EQ(second->scene().bodies[0].parts.mesh.get(), loaded.parts.mesh.get());
}

TEST(SceneLoader, AWorldRunsOnWithItsProjectsFilesGone) {
    // The sample projects with frames (balloon), a painted map (buoy) and a water graph with a
    // permeability map (damaged boat), copied, read into scenes, and the copies removed: World
    // reads nothing, so it runs on, frame for frame as a world of the files still there.
    const fs::path root = test::scratchFolder("scene_files_gone");
    const fs::path source = PLIMSOLL_SOURCE_DIR;
    for (const char* name : {"balloon", "buoy", "damaged_boat"}) {
        SCOPED_TRACE(name);
        fs::remove_all(root);
        fs::create_directories(root);
        fs::copy(source / "assets", root / "assets", fs::copy_options::recursive);
        fs::copy(source / "projects", root / "projects", fs::copy_options::recursive);
        const std::string file = std::string(name) + ".plim.json";
        Result<Project> copy = loadProject(root / "projects" / file);
        Result<Project> original = loadProject(source / "projects" / file);
        ASSERT_TRUE(copy.ok() && original.ok());
        Scene scene = test::sceneOrFail(*copy);
        fs::remove_all(root);
        ASSERT_FALSE(fs::exists(root));
        std::unique_ptr<World> orphan = test::worldOrFail(std::move(scene));
        std::unique_ptr<World> reference = test::worldOrFail(test::sceneOrFail(*original));
        ASSERT_TRUE(orphan && reference);
        const Eigen::Vector3d start = orphan->bodies()[0].state.position;
        for (int f = 0; f < 30; ++f) {
            ASSERT_TRUE(orphan->advanceFrame().ok());
            ASSERT_TRUE(reference->advanceFrame().ok());
        }
        const RigidBodyState& a = orphan->bodies()[0].state;
        const RigidBodyState& b = reference->bodies()[0].state;
        EXPECT_EQ(a.position, b.position);
        EXPECT_EQ(a.orientation.coeffs(), b.orientation.coeffs());
        EXPECT_EQ(a.linearMomentum, b.linearMomentum);
        EXPECT_GT((a.position - start).norm(), 1e-4);  // it moved
    }
}

// The level ladder comes through the project's cache: the first load bakes and caches the
// coarser levels, the next reads them back (the same sizes and stated errors, the samples to
// float32) instead of baking; another mesh or a damaged cache bakes again.
TEST(SceneLoader, TheLevelLadderIsCachedAndReadBackInsteadOfBakedAgain) {
    const fs::path root = test::scratchFolder("scene_loader_levels");
    fs::remove_all(root);
    fs::create_directories(root);
    ASSERT_TRUE(writeObj(makeBox(Eigen::Vector3d(1.0, 0.25, 0.8)), root / "box.obj").ok());
    Project project;
    project.name = "levels";
    project.folder = root;
    BodyDesc desc;
    desc.name = "box";
    desc.mesh = "box.obj";
    desc.textureSize = 64;
    desc.material.density = 500;
    desc.lod = LodDesc{{16, 32}};
    project.bodies.push_back(desc);
    const auto load = [&](std::string& said) {
        said.clear();
        Result<SceneBody> body =
            loadSceneBody(project, 0, [&](const std::string& line) { said += line + "\n"; });
        EXPECT_TRUE(body.ok()) << body.error().message;
        return body;
    };
    std::string said;
    Result<SceneBody> baked = load(said);
    ASSERT_TRUE(baked.ok() && baked->levels);
    EXPECT_NE(said.find("levels cached in"), std::string::npos) << said;
    const fs::path folder = project.levelCacheFolder(0);
    EXPECT_TRUE(fs::is_regular_file(folder / "levels.json"));
    EXPECT_TRUE(fs::is_regular_file(folder / "16" / "samples.exr"));
    EXPECT_TRUE(fs::is_regular_file(folder / "32" / "samples.exr"));

    Result<SceneBody> cached = load(said);
    ASSERT_TRUE(cached.ok() && cached->levels);
    EXPECT_NE(said.find("levels from the cache"), std::string::npos) << said;
    EXPECT_EQ(said.find("levels cached in"), std::string::npos) << said;
    const std::vector<BuoyancyLevel>& a = *baked->levels;
    const std::vector<BuoyancyLevel>& b = *cached->levels;
    ASSERT_EQ(a.size(), 3u);
    ASSERT_EQ(b.size(), 3u);
    EXPECT_EQ(b[2].textures, cached->textures);  // the finest is the body's own bake
    for (std::size_t k = 0; k < 2; ++k) {
        SCOPED_TRACE(k);
        EXPECT_EQ(b[k].size, a[k].size);
        EXPECT_EQ(b[k].forceError, a[k].forceError);
        EXPECT_EQ(b[k].torqueError, a[k].torqueError);
        EXPECT_EQ(b[k].evaluationUs, a[k].evaluationUs);
        ASSERT_EQ(b[k].textures->texelIndex, a[k].textures->texelIndex);
        for (std::size_t i = 0; i < a[k].textures->coveredCount(); ++i) {
            EXPECT_NEAR((b[k].textures->position[i] - a[k].textures->position[i]).norm(), 0.0,
                        1e-6);
            EXPECT_NEAR(b[k].textures->area[i], a[k].textures->area[i],
                        1e-6 * a[k].textures->area[i]);
        }
    }

    // Another mesh: the key differs, the levels are baked again.
    ASSERT_TRUE(writeObj(makeBox(Eigen::Vector3d(1.0, 0.3, 0.8)), root / "box.obj").ok());
    Result<SceneBody> other = load(said);
    ASSERT_TRUE(other.ok() && other->levels);
    EXPECT_NE(said.find("levels cached in"), std::string::npos) << said;
    EXPECT_NE((*other->levels)[0].forceError, a[0].forceError);

    // A damaged cache is said and replaced.
    std::ofstream(folder / "levels.json") << "{";
    Result<SceneBody> again = load(said);
    ASSERT_TRUE(again.ok() && again->levels);
    EXPECT_NE(said.find("not a readable level cache"), std::string::npos) << said;
    EXPECT_NE(said.find("levels cached in"), std::string::npos) << said;
}

}  // namespace
}  // namespace test_scene_loader
}  // namespace plimsoll
