// Accuracy budgets (docs/project-schema.md, "tolerance"): a body may give the force error it
// accepts instead of a texture size, and the bake keeps the smallest of 16, 32, 64, ... whose
// error against the exact clip is within it. The errors are measured here again, by this file's
// own loop over the same poses, on every shared mesh and real asset.
#include "cli_runner.h"
#include "test_support.h"
#include "world_support.h"

#include "plimsoll/physics/buoyancy.h"
#include "plimsoll/physics/massprops.h"
#include "plimsoll/project/project.h"
#include "plimsoll/project/scene_loader.h"
#include "plimsoll/repair/physics_solid.h"
#include "plimsoll/samples/primitives.h"
#include "plimsoll/scene/level_ladder.h"
#include "plimsoll/scene/scene.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>

namespace plimsoll {
namespace test_level_tolerance {
namespace {

namespace fs = std::filesystem;

constexpr double kTolerance = 1e-3;

/// The largest |F - F_exact| / (rho g V) over levelErrorPoses, F both Archimedes' force and the
/// pressure integral of `textures`, F_exact the clip of `mesh`, V its volume: written out here
/// rather than taken from LevelErrorMeter, which is what is under test.
double forceError(const TriangleMesh& mesh, const SurfaceTextures& textures,
                  const Eigen::Vector3d& centerOfMass) {
    const FluidSettings fluid;
    const double volume = exactSolidMassProperties(mesh, 1.0).mass;
    double worst = 0;
    for (const LevelPose& pose : levelErrorPoses(mesh, centerOfMass)) {
        BodyFrame frame;
        frame.pose.rotation = pose.rotation;
        frame.pose.translation = -(pose.rotation * centerOfMass);
        frame.centerOfMass = centerOfMass;
        const BuoyancyResult exact = evaluateBuoyancyExact(mesh, frame, pose.waterLevel, fluid);
        const BuoyancyResult texture =
            evaluateBuoyancyReference(textures, frame, WaterModel::flat(pose.waterLevel), fluid);
        worst = std::max({worst, (texture.force - exact.force).norm(),
                          (texture.pressureForce - exact.pressureForce).norm()});
    }
    return worst / (fluid.density * fluid.gravity * volume);
}

/// A project of one body: `file` at the default settings, as simulate --mesh makes one.
Project meshProject(const fs::path& file) {
    Project project;
    project.sourceName = file.string();
    BodyDesc& body = project.bodies.emplace_back();
    body.name = file.stem().string();
    body.mesh = file.string();
    body.material.density = 500.0;
    return project;
}

/// Every shared mesh and real asset, as a project run bakes it (its physics solid, with a
/// generated atlas where its own UVs do not do). The real assets need the repair (CGAL), and
/// the sanitized build, twenty times slower, has neither the time nor CGAL: it checks the
/// shared meshes.
std::vector<std::pair<std::string, TriangleMesh>> everyMesh() {
    std::vector<fs::path> folders = {fs::path(PLIMSOLL_SHARED_DIR) / "meshes"};
    if (repairAvailable() && !test::kSanitizedBuild) folders.push_back(test::realAssetsDir());
    std::vector<fs::path> files;
    for (const fs::path& folder : folders) {
        if (!fs::exists(folder)) continue;
        for (const auto& entry : fs::recursive_directory_iterator(folder)) {
            const std::string ext = entry.path().extension().string();
            if (ext == ".fbx" || ext == ".glb" || ext == ".obj" || ext == ".stl")
                files.push_back(entry.path());
        }
    }
    std::sort(files.begin(), files.end());
    std::vector<std::pair<std::string, TriangleMesh>> meshes;
    for (const fs::path& file : files) {
        // The sanitized build checks the search's memory, not its picks: two small closed
        // meshes do that (the full build checks every pick).
        const std::string name = file.filename().string();
        if (test::kSanitizedBuild && name != "cube.obj" && name != "sphere.obj") continue;
        Result<PreparedBodyMesh> prepared = prepareBodyMesh(meshProject(file), 0);
        // Without CGAL a mesh that is not one closed solid (the shared teapot) cannot be
        // prepared at all; the builds with repair check it.
        if (!prepared && !repairAvailable()) continue;
        EXPECT_TRUE(prepared.ok()) << file << ": " << test::messageOf(prepared);
        if (prepared) meshes.emplace_back(file.filename().string(), std::move(prepared->mesh));
    }
    return meshes;
}

TEST(LevelTolerance, PicksTheSmallestSizeWithinItOnEverySharedMeshAndRealAsset) {
    const auto meshes = everyMesh();
    if (meshes.empty()) GTEST_SKIP() << "../shared is absent";
    for (const auto& [name, mesh] : meshes) {
        SCOPED_TRACE(name);
        const Eigen::Vector3d center = exactSolidMassProperties(mesh, 1.0).centerOfMass;
        Result<LevelChoice> choice = chooseLevelForTolerance(mesh, kTolerance, BakeSettings{});
        ASSERT_TRUE(choice.ok()) << test::messageOf(choice);
        ASSERT_TRUE(choice->textures);
        EXPECT_EQ(choice->textures->size, choice->size);
        // Its error, measured again, is what it states and within the tolerance.
        const double chosen = forceError(mesh, *choice->textures, center);
        EXPECT_LE(chosen, kTolerance);
        EXPECT_NEAR(chosen, choice->forceError, 1e-9);
        // The next smaller size, baked here, misses it: the choice is the smallest.
        ASSERT_EQ(choice->coarser.size(), static_cast<std::size_t>(std::log2(choice->size / 16)));
        if (choice->size > kMinTextureSize) {
            BakeSettings coarser;
            coarser.size = choice->size / 2;
            const double below = forceError(mesh, test::bakeOrFail(mesh, coarser), center);
            EXPECT_GT(below, kTolerance) << "size " << coarser.size;
            EXPECT_NEAR(below, choice->coarser.back().second, 1e-9);
        }
        std::printf("%-28s %5d texels  force error %.2e\n", name.c_str(), choice->size, chosen);
    }
}

TEST(LevelTolerance, AToleranceNoSizeMeetsIsRefusedNamingTheFinestError) {
    const TriangleMesh sphere = makeUvSphere(0.5, 24, 12);
    const Result<LevelChoice> choice = chooseLevelForTolerance(sphere, 1e-9, BakeSettings{}, 64);
    ASSERT_FALSE(choice.ok());
    EXPECT_NE(choice.error().message.find("no texture size up to 64 meets the tolerance 1.0e-09"),
              std::string::npos)
        << choice.error().message;
    EXPECT_NE(choice.error().message.find("the finest, 64, has a force error of"),
              std::string::npos);
    EXPECT_FALSE(chooseLevelForTolerance(sphere, 0.0, BakeSettings{}).ok());
}

TEST(LevelTolerance, ABodysToleranceSetsItsTextureSizeAndMass) {
    BodyDesc desc;
    desc.name = "ball";
    desc.mesh = "generated";
    desc.material.density = 500.0;
    desc.tolerance = 2e-3;
    const TriangleMesh sphere = makeUvSphere(0.5, 48, 24);
    const SceneBody body = test::bodyOrFail(desc, sphere);
    ASSERT_TRUE(body.levelChoice);
    EXPECT_EQ(body.desc.textureSize, body.levelChoice->size);
    EXPECT_EQ(body.textures->size, body.levelChoice->size);
    EXPECT_LE(forceError(sphere, *body.textures, Eigen::Vector3d::Zero()), 2e-3);
    // The same body at that size by name bakes the same texture and mass.
    BodyDesc bySize = desc;
    bySize.tolerance.reset();
    bySize.textureSize = body.levelChoice->size;
    const SceneBody same = test::bodyOrFail(bySize, sphere);
    EXPECT_FALSE(same.levelChoice);
    EXPECT_EQ(same.mass->mass, body.mass->mass);
    EXPECT_EQ(same.mass->centerOfMass, body.mass->centerOfMass);
}

TEST(LevelTolerance, TheProjectFileGivesAToleranceOrASizeNotBoth) {
    const std::string head =
        R"({"schema_version": 1, "bodies": [{"mesh": "ball.obj", "material": {"density": 500}, )";
    Result<Project> tolerance = parseProject(head + R"("tolerance": 0.002}]})", "t.plim.json", ".");
    ASSERT_TRUE(tolerance.ok()) << test::messageOf(tolerance);
    ASSERT_TRUE(tolerance->bodies[0].tolerance);
    EXPECT_EQ(*tolerance->bodies[0].tolerance, 0.002);
    // Saved and read back, it is still a tolerance and no size.
    const std::string saved = projectToJson(*tolerance);
    EXPECT_EQ(saved.find("texture_size"), std::string::npos);
    Result<Project> again = parseProject(saved, "t.plim.json", ".");
    ASSERT_TRUE(again.ok()) << test::messageOf(again);
    EXPECT_TRUE(*again == *tolerance);

    const Result<Project> both =
        parseProject(head + R"("tolerance": 0.002, "texture_size": 64}]})", "t.plim.json", ".");
    ASSERT_FALSE(both.ok());
    EXPECT_NE(
        both.error().message.find("bodies[0].tolerance: give texture_size or tolerance, not both"),
        std::string::npos)
        << both.error().message;
    for (const char* bad : {"0", "-1e-3", "1", "\"fine\""}) {
        const Result<Project> r =
            parseProject(head + "\"tolerance\": " + bad + "}]}", "t.plim.json", ".");
        EXPECT_FALSE(r.ok()) << bad;
    }
}

TEST(LevelToleranceCli, BakeSaysWhichSizeItPickedAndRefusesBothOptions) {
    const fs::path out = test::freshFolder("level_tolerance", "bake");
    const std::string mesh = test::assetPath("sphere.obj").string();
    const test::CommandOutput r =
        test::runPlimsoll("bake '" + mesh + "' --tolerance 2e-3 --out '" + out.string() + "'");
    ASSERT_EQ(r.exitCode, 0) << r.err;
    EXPECT_NE(r.out.find("  tolerance       0.002: "), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("within 2.0e-03"), std::string::npos) << r.out;
    EXPECT_TRUE(fs::exists(out / "manifest.json"));
    EXPECT_EQ(test::runPlimsoll("bake '" + mesh + "' --tolerance 2e-3 --size 64 --out '" +
                                out.string() + "'")
                  .exitCode,
              2);
    EXPECT_EQ(test::runPlimsoll("bake '" + mesh + "' --tolerance 0 --out '" + out.string() + "'")
                  .exitCode,
              2);
}

TEST(LevelToleranceCli, ExportsSummarySaysTheSizeATolerancePickedAndItsError) {
    const fs::path dir = test::freshFolder("level_tolerance", "export");
    const fs::path project = dir / "ball.plim.json";
    test::writeFile(
        project, R"({"schema_version": 1, "name": "ball", "bodies": [{"name": "ball", "mesh": ")" +
                     test::assetPath("sphere.obj").string() +
                     R"(", "tolerance": 0.002, "material": {"density": 500}}]})");
    const test::CommandOutput r = test::runPlimsoll("export '" + project.string() + "' --out '" +
                                                    (dir / "out").string() + "'");
    ASSERT_EQ(r.exitCode, 0) << r.err;
    const nlohmann::json summary = nlohmann::json::parse(r.out);
    const nlohmann::json& body = summary["bodies"][0];
    EXPECT_EQ(body["tolerance"].get<double>(), 0.002);
    EXPECT_LE(body["force_error"].get<double>(), 0.002);
    // The size is the one the pick makes on the same mesh, and the bundle's manifest has it.
    Result<PreparedBodyMesh> prepared = prepareBodyMesh(*loadProject(project), 0);
    ASSERT_TRUE(prepared.ok()) << test::messageOf(prepared);
    const Result<LevelChoice> choice =
        chooseLevelForTolerance(prepared->mesh, 0.002, BakeSettings{});
    ASSERT_TRUE(choice.ok());
    EXPECT_EQ(body["texture_size"].get<int>(), choice->size);
    EXPECT_EQ(body["force_error"].get<double>(), choice->forceError);
    const nlohmann::json manifest =
        nlohmann::json::parse(test::readFile(dir / "out" / "ball" / "ball" / "manifest.json"));
    EXPECT_EQ(manifest["texture_size"].get<int>(), choice->size);
}

}  // namespace
}  // namespace test_level_tolerance
}  // namespace plimsoll
