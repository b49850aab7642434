// The adapter that reads a project into a Scene (scene_loader.h): it names the file and the JSON
// path of every problem, a scene from disk equals the same body baked in memory, and a World
// runs on once the project's files are gone.
#include "plimsoll/project/scene_loader.h"
#include "plimsoll/scene/world.h"

#include "test_support.h"
#include "world_support.h"

#include <gtest/gtest.h>

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
    EXPECT_EQ(starts[0].rfind("harbour.plim.json: bodies[0].mesh: body 'ghost' (no_such_mesh.obj): ", 0), 0u)
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

}  // namespace
}  // namespace test_scene_loader
}  // namespace plimsoll
