// The window's physics textures baked off the UI thread (document/physics_bakes.h): a new
// texture size bakes on a worker while the old size's textures stay in use, the result is the
// synchronous bake's exactly, Cancel and a return to a size still held need no bake, and a bake
// made stale by a later edit never reaches the document.
#include "test_support.h"
#include "editor/document_test_support.h"

#include "document/command.h"
#include "document/physics_bakes.h"
#include "plimsoll/scene/level_ladder.h"

#include <nlohmann/json.hpp>

#include <gtest/gtest.h>

#include <chrono>
#include <fstream>
#include <thread>
#include <unistd.h>

namespace plimsoll::editor {
namespace test_editor_physics_bakes {
namespace {

namespace fs = std::filesystem;
using test::executeOrFail;
using test::openOrFail;

fs::path sphereProject(const std::string& name, int textureSize) {
    const fs::path dir =
        fs::temp_directory_path() / "plimsoll_tests" / (name + "_" + std::to_string(::getpid()));
    fs::remove_all(dir);
    fs::create_directories(dir);
    const fs::path path = dir / "bakes.plim.json";
    std::ofstream(path)
        << R"({"schema_version": 1, "name": "t", "bodies": [{"name": "ball", "mesh": ")"
        << test::assetPath("sphere.obj").string() << R"(", "texture_size": )" << textureSize
        << R"(, "material": {"density": 500}}]})";
    return path;
}

void setSize(Document& d, int size) {
    executeOrFail(d, makeSetPropertyCommand(d, "/bodies/0/texture_size", size));
}

/// Polls until a bake arrives (at most a minute: a bake of these sizes takes well under one).
bool waitForArrival(PhysicsBakes& bakes, Document& d) {
    for (int i = 0; i < 12000; ++i) {
        if (bakes.poll(d)) return true;
        std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
    return false;
}

void expectSameTextures(const SurfaceTextures& a, const SurfaceTextures& b) {
    EXPECT_EQ(a.size, b.size);
    EXPECT_EQ(a.texelIndex, b.texelIndex);
    EXPECT_EQ(a.position, b.position);
    EXPECT_EQ(a.areaVector, b.areaVector);
    EXPECT_EQ(a.area, b.area);
    EXPECT_EQ(a.coverage, b.coverage);
}

TEST(EditorPhysicsBakes, NewSizeBakesOnAWorkerWhileTheOldSizeStaysInUse) {
    auto d = openOrFail(sphereProject("bakes_worker", 32));
    ASSERT_TRUE(d);
    PhysicsBakes bakes;
    // The first bake: nothing to show meanwhile, and nothing baked on this thread.
    EXPECT_EQ(bakes.texturesFor(*d, 0), nullptr);
    EXPECT_EQ(d->bakedPhysics(0), nullptr);
    ASSERT_TRUE(bakes.progress(0));
    EXPECT_EQ(bakes.progress(0)->size, 32);
    EXPECT_EQ(bakes.progress(0)->previousSize, 0);
    ASSERT_TRUE(waitForArrival(bakes, *d));
    EXPECT_NE(bakes.lastWorker(0), std::thread::id());
    EXPECT_NE(bakes.lastWorker(0), std::this_thread::get_id());
    const auto at32 = bakes.texturesFor(*d, 0);
    ASSERT_TRUE(at32);
    EXPECT_EQ(at32, d->bakedPhysics(0));
    EXPECT_FALSE(bakes.busy());

    // A new size: the 32^2 textures stay in use until the 64^2 ones arrive.
    setSize(*d, 64);
    EXPECT_EQ(bakes.texturesFor(*d, 0), at32);
    ASSERT_TRUE(bakes.progress(0));
    EXPECT_EQ(bakes.progress(0)->size, 64);
    EXPECT_EQ(bakes.progress(0)->previousSize, 32);
    ASSERT_TRUE(waitForArrival(bakes, *d));
    const auto at64 = bakes.texturesFor(*d, 0);
    ASSERT_TRUE(at64);
    // Exactly what the synchronous bake gives.
    Result<SurfaceTextures> direct =
        bakeSurfaceTextures(*d->assets(0).mesh, d->physicsBakeSettings(0));
    ASSERT_TRUE(direct.ok()) << direct.error().message;
    expectSameTextures(*at64, *direct);
    EXPECT_EQ(at64->size, 64);

    // Cancel: the size to set back is the one in use, whose textures come back with no bake.
    setSize(*d, 128);
    EXPECT_EQ(bakes.texturesFor(*d, 0), at64);
    EXPECT_EQ(bakes.cancel(0), 64);
    EXPECT_FALSE(bakes.progress(0));
    setSize(*d, 64);
    EXPECT_EQ(bakes.texturesFor(*d, 0), at64);
    EXPECT_EQ(d->bakedPhysics(0), at64);
    EXPECT_FALSE(bakes.busy());
}

TEST(EditorPhysicsBakes, ABakeMadeStaleByALaterEditNeverReachesTheDocument) {
    auto d = openOrFail(sphereProject("bakes_stale", 32));
    ASSERT_TRUE(d);
    PhysicsBakes bakes;
    (void)bakes.texturesFor(*d, 0);
    ASSERT_TRUE(waitForArrival(bakes, *d));
    // 256 asked for and, before it is done, 64: the 256 bake is dropped, 64 arrives.
    setSize(*d, 256);
    (void)bakes.texturesFor(*d, 0);
    setSize(*d, 64);
    (void)bakes.texturesFor(*d, 0);
    ASSERT_TRUE(bakes.progress(0));
    EXPECT_EQ(bakes.progress(0)->size, 64);
    ASSERT_TRUE(waitForArrival(bakes, *d));
    ASSERT_TRUE(d->bakedPhysics(0));
    EXPECT_EQ(d->bakedPhysics(0)->size, 64);
    // Textures of a size the body no longer has are refused.
    auto old = d->bakedPhysics(0);
    BakeSettings settings = d->physicsBakeSettings(0);
    setSize(*d, 32);
    EXPECT_FALSE(d->adoptPhysics(0, d->assets(0).mesh.get(), settings, old));
    EXPECT_EQ(d->bakedPhysics(0), nullptr);
}

}  // namespace
}  // namespace test_editor_physics_bakes
}  // namespace plimsoll::editor

namespace plimsoll::editor {
namespace test_editor_physics_bakes {
namespace {

TEST(EditorPhysicsBakes, AToleranceIsPickedOnAWorkerAndShownWithItsError) {
    auto d = openOrFail(sphereProject("bakes_tolerance", 32));
    ASSERT_TRUE(d);
    // From a size to a tolerance: one undoable step, the body's JSON with one key for the other.
    const std::string before = projectToJson(d->project());
    nlohmann::json body = nlohmann::json::parse(before)["bodies"][0];
    body.erase("texture_size");
    body["tolerance"] = 2e-3;
    executeOrFail(*d, makeSetPropertyCommand(*d, "/bodies/0", body));
    EXPECT_FALSE(d->levelChoice(0));
    EXPECT_EQ(d->physicsBakeSettings(0).size, 0);  // not known yet

    PhysicsBakes bakes;
    EXPECT_EQ(bakes.texturesFor(*d, 0), nullptr);
    ASSERT_TRUE(waitForArrival(bakes, *d));
    const std::optional<LevelChoice> choice = d->levelChoice(0);
    ASSERT_TRUE(choice);
    EXPECT_LE(choice->forceError, 2e-3);
    const auto textures = bakes.texturesFor(*d, 0);
    ASSERT_TRUE(textures);
    EXPECT_EQ(textures->size, choice->size);
    EXPECT_EQ(d->physicsBakeSettings(0).size, choice->size);
    // What a project run picks for the same mesh and tolerance, with its error.
    Result<LevelChoice> direct =
        chooseLevelForTolerance(*d->assets(0).mesh, 2e-3, d->physicsBakeSettings(0));
    ASSERT_TRUE(direct.ok()) << direct.error().message;
    EXPECT_EQ(direct->size, choice->size);
    EXPECT_EQ(direct->forceError, choice->forceError);
    expectSameTextures(*textures, *direct->textures);

    // A tighter tolerance is a new pick; undo brings the size back, byte for byte.
    executeOrFail(*d, makeSetPropertyCommand(*d, "/bodies/0/tolerance", 1e-4));
    EXPECT_FALSE(d->levelChoice(0));
    ASSERT_TRUE(d->undo());
    ASSERT_TRUE(d->undo());
    EXPECT_EQ(projectToJson(d->project()), before);
    EXPECT_FALSE(d->levelChoice(0));
    EXPECT_EQ(d->physicsBakeSettings(0).size, 32);
}

}  // namespace
}  // namespace test_editor_physics_bakes
}  // namespace plimsoll::editor
