// A scene in memory: what World simulates. Every body already holds what it is made of (mesh,
// frames, water graph, painted maps) and what the bake made of it (textures, mass properties),
// each immutable and shared, so that a rebuilt world, the editor's document and an export can
// hold the very same data. The scene has one gravity vector. Nothing here reads or writes a
// file: scene_loader.h turns a project on disk into a Scene, the editor turns its document into
// one, tests and the benchmark build one from generated meshes.
#pragma once

#include "plimsoll/bake/bake.h"
#include "plimsoll/surface/painted_map.h"
#include "plimsoll/core/result.h"
#include "plimsoll/geometry/mesh.h"
#include "plimsoll/geometry/validate.h"
#include "plimsoll/graph/graph.h"
#include "plimsoll/physics/massprops.h"
#include "plimsoll/physics/water.h"
#include "plimsoll/scene/level_ladder.h"
#include "plimsoll/scene/scene_desc.h"

#include <Eigen/Core>

#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace plimsoll {

/// Called with one line of text for things a user should know (skips, recomputations, notices).
using LogFunction = std::function<void(const std::string&)>;

/// What a body is made of, before baking. The BodyDesc it goes with says how to use it; the
/// file names in that BodyDesc are names only (for messages): what is here is what is used.
struct BodyParts {
    /// The surface with the UVs it is baked with (its atlas applied); for a deforming body its
    /// first frame. Required.
    std::shared_ptr<const TriangleMesh> mesh;
    /// Whether `mesh`'s UVs are a generated physics atlas, and of how many charts (manifests
    /// say so).
    bool generatedAtlas = false;
    std::size_t atlasCharts = 0;
    /// A deforming body's frames, the first included, all with `mesh`'s triangles and UVs
    /// (loadMeshFrames checks files); null for a rigid body.
    std::shared_ptr<const std::vector<TriangleMesh>> frames;
    /// Required when the BodyDesc has a waterGraph; null otherwise.
    std::shared_ptr<const WaterGraph> waterGraph;
    /// Painted maps over `mesh`'s UVs; null: not painted (uniform, or impermeable).
    std::shared_ptr<const PaintedMap> permeabilityMap;
    std::shared_ptr<const PaintedMap> shellDensityMap;
    std::shared_ptr<const PaintedMap> shellThicknessMap;
    /// The space inside `mesh` that holds no material: the compartments behind the caps of an
    /// open hull's openings (physics_solid.h, Opening::cavity), at density 1 (mass = volume).
    /// A solid material fills the rest only. Zero mass: none.
    MassProperties hollow;
    /// Triangles of `mesh` that are no material (the caps of those openings): a shell does not
    /// lie on them. Empty: the whole surface is wall.
    std::vector<std::uint32_t> capTriangles;
};

struct BodyRadiation;  // scene_radiation.h

/// A body ready to simulate: its settings, its parts, and their bake.
struct SceneBody {
    BodyDesc desc;
    std::string label;  ///< how messages name the body: "body 'NAME' (MESH)"
    BodyParts parts;
    std::shared_ptr<const SurfaceTextures> textures;  ///< at desc.textureSize
    /// The bake's pieces, from which a deforming body's frames are regathered; null if rigid.
    std::shared_ptr<const SurfacePieceTable> pieces;
    std::shared_ptr<const MassProperties> mass;  ///< of desc.material on `textures`
    /// Its wave radiation (scene_radiation.h), required when desc.radiates(); null otherwise.
    std::shared_ptr<const BodyRadiation> radiation;
    /// Its level ladder (level_ladder.h), coarsest first, the last `textures` itself at
    /// desc.textureSize, each with its stated error: made when desc.lod asks for one on a rigid
    /// body without a water graph; null otherwise (one level).
    std::shared_ptr<const std::vector<BuoyancyLevel>> levels;
    /// Where desc.tolerance set the texture size: the size it picked and its measured errors
    /// (desc.textureSize is then that size).
    std::optional<LevelChoice> levelChoice;
    /// Per entry of `textures`, the share of its area that is wall, not cap
    /// (parts.capTriangles): what a shell's surface density is scaled by. Null: all wall.
    std::shared_ptr<const std::vector<double>> wallShare;
};

struct Scene {
    std::string name;
    std::vector<SceneBody> bodies;
    MediumDesc medium;
    /// The medium's surface. Its `gravity` (the waves' dispersion relation) is not a second
    /// gravity: World takes it from simulation.gravity.
    WaterModel water;
    /// simulation.gravity is the scene's one gravity vector (checkGravity).
    SimulationDesc simulation;
};

/// Bakes `desc`'s textures over parts.mesh (at the size desc.tolerance picks, where it is given)
/// (recording the pieces of a deforming body), its level ladder where desc.lod asks for one, and
/// computes the mass properties of its material: what World, the editor's preview and the bundle
/// export all simulate or write. Refuses parts that do not fit `desc` (no mesh, frames without
/// mesh_frames or the reverse, a water graph missing). Errors start with the label.
Result<SceneBody> bakeSceneBody(BodyDesc desc, BodyParts parts);

/// The ladder's sizes `body`'s desc.lod asks for (level_ladder.h ladderSizes, coarsest first,
/// desc.textureSize last); nullopt when it asks for none, or only textureSize, or the body
/// deforms or has a water graph (they keep their own level), or (with `status` set) when a
/// size is out of range.
std::optional<std::vector<int>> bodyLadderSizes(const SceneBody& body, Status& status);

/// The level ladder of a baked `body` (its textures and mass set): bakeLevelLadder at
/// bodyLadderSizes about its centre of mass; null for a body with one level.
Result<std::shared_ptr<const std::vector<BuoyancyLevel>>> bakeBodyLevels(const SceneBody& body,
                                                                         unsigned threads = 0);

/// Mass properties of `material` on `textures`: a solid of uniform density (V = sum A_y y) and
/// a shell of point masses, its surface density scaled by `shellDensityMap` and by the relative
/// thickness `shellThicknessMap` where they are given (the two multiply; null: uniform).
/// `label` starts messages.
Result<MassProperties> materialMassProperties(const SurfaceTextures& textures,
                                              const MaterialDesc& material,
                                              const PaintedMap* shellDensityMap,
                                              const std::string& label,
                                              const PaintedMap* shellThicknessMap = nullptr);

/// A body's own mass properties (no water in it): materialMassProperties with the shell scaled
/// by `wallShare` (per entry, null: 1) and the solid material kept out of `hollow` (the space
/// behind an open hull's caps; no mass: none). What bakeSceneBody and World compute.
Result<MassProperties> bodyMassProperties(const SurfaceTextures& textures,
                                          const MaterialDesc& material,
                                          const PaintedMap* shellDensityMap,
                                          const std::vector<double>* wallShare,
                                          const MassProperties& hollow, const std::string& label,
                                          const PaintedMap* shellThicknessMap = nullptr);

/// Per entry of `textures` (baked from `mesh` with `pieces` recorded), the share of its area
/// on triangles not in `caps`: 1 on walls, 0 on a cap, between where an entry holds both.
std::vector<double> wallShares(const TriangleMesh& mesh, const SurfaceTextures& textures,
                               const SurfacePieceTable& pieces,
                               const std::vector<std::uint32_t>& caps);

/// Refuses a surface with errors no atlas can fix (holes, bad orientation, ...: every problem
/// of `report` that is not about UVs, one a line after "LABEL:").
Status checkBakeableSurface(const ValidationReport& report, const std::string& label);

/// Gravity as World can simulate it: straight down (-y) or zero. Buoyancy takes the water
/// surface as horizontal with y up, so a tilted or upward gravity is refused (unsupported).
Status checkGravity(const Eigen::Vector3d& gravity);

/// "body 'NAME' (MESH)": how messages name a body.
std::string bodyLabel(const BodyDesc& body);

}  // namespace plimsoll
