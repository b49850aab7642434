// Building scenes and worlds in tests: a project on disk through the adapter (scene_loader.h),
// or a generated mesh handed to the bake in memory, as the editor and the benchmark do.
#pragma once

#include "plimsoll/compute/compute.h"
#include "plimsoll/compute/fast_backend.h"
#include "plimsoll/scene/scene.h"
#include "plimsoll/project/project.h"
#include "plimsoll/project/scene_loader.h"
#include "plimsoll/scene/world.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <memory>
#include <utility>

namespace plimsoll::test {

/// `project` read and baked; an empty scene (and a failure) if it cannot be.
inline Scene sceneOrFail(const Project& project, const LogFunction& log = {}) {
    Result<Scene> scene = loadScene(project, log);
    EXPECT_TRUE(scene.ok()) << (scene.ok() ? "" : scene.error().message);
    return scene.ok() ? std::move(scene).value() : Scene{};
}

/// A rigid body `desc` made of `mesh` (with its own UVs), baked; a failure if it cannot be.
inline SceneBody bodyOrFail(const BodyDesc& desc, TriangleMesh mesh) {
    Result<SceneBody> body =
        bakeSceneBody(desc, {.mesh = std::make_shared<const TriangleMesh>(std::move(mesh))});
    EXPECT_TRUE(body.ok()) << (body.ok() ? "" : body.error().message);
    return body.ok() ? std::move(body).value() : SceneBody{};
}

/// The world of `scene` on `backend` (none: the C++ reference backend); null (and a failure)
/// if it cannot be made.
inline std::unique_ptr<World> worldOrFail(Scene scene, LogFunction log = {},
                                          std::unique_ptr<BuoyancyBackend> backend = nullptr) {
    if (!backend) backend = createReferenceBackend();
    Result<std::unique_ptr<World>> world =
        World::create(std::move(scene), std::move(backend), std::move(log));
    EXPECT_TRUE(world.ok()) << (world.ok() ? "" : world.error().message);
    return world.ok() ? std::move(world).value() : nullptr;
}

/// The world of `scene` on the fast CPU path: the backend simulate, the editor and the runtime
/// use when no device is named, held within 1e-5 of the reference's forces on flat water
/// (FastPath tests). For tests whose cost is simulated time: the reference costs about ten
/// times as much per evaluation.
inline std::unique_ptr<World> fastWorldOrFail(Scene scene, LogFunction log = {}) {
    return worldOrFail(std::move(scene), std::move(log), createFastBackend());
}

/// A ball of density 500 in fresh water; `waterLevel` far below keeps it in the air.
inline Project ballProject(double waterLevel, const Eigen::Vector3d& gravity) {
    Project project;
    project.folder = std::filesystem::temp_directory_path();
    BodyDesc body;
    body.name = "ball";
    body.mesh = assetPath("sphere.obj").string();
    body.textureSize = 64;
    body.material.density = 500.0;
    body.position = Eigen::Vector3d(0.2, 0.3, -0.1);
    project.bodies.push_back(body);
    project.water = WaterModel::flat(waterLevel);
    project.simulation.gravity = gravity;
    return project;
}

}  // namespace plimsoll::test
