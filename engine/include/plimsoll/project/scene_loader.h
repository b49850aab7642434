// The one adapter from a project on disk to a scene in memory (scene.h): it reads every body's
// mesh (the atlas applied, through the project's atlas cache), its frames, water graph and
// painted maps, and bakes them. Every problem names the project file and the JSON path of the
// entry that caused it: "boat.plim.json: bodies[0].water_graph.graph: body 'boat' (boat.obj):
// water graph: boat.graph.json: cannot open".
#pragma once

#include "plimsoll/repair/physics_solid.h"

#include "plimsoll/surface/atlas.h"
#include "plimsoll/core/result.h"
#include "plimsoll/geometry/mesh.h"
#include "plimsoll/project/project.h"
#include "plimsoll/scene/scene.h"

#include <functional>
#include <memory>
#include <string>
#include <vector>

namespace plimsoll {

/// A body's mesh with the UVs it is baked with.
struct PreparedBodyMesh {
    TriangleMesh mesh;  ///< the first frame for a deforming body; atlas applied
    AtlasChoice atlas;  ///< atlas.mesh is moved into `mesh` (left empty here)
    /// The repairs of the physics solid when the surface was not one closed solid as it is:
    /// `mesh` is then the solid, and `artist` the mesh as loaded (for its painted maps).
    std::vector<Repair> repairs;
    std::shared_ptr<const TriangleMesh> artist;
    /// The openings closed by caps (their triangles index `mesh`); empty with "openings": "none".
    std::vector<Opening> openings;
};

/// Loads body `index` of `project` (its first frame when it deforms) in metres, replaces a
/// rigid surface that is not one closed solid, or that has openings to close (BodyDesc::openings),
/// by its physics solid (physics_solid.h), refuses
/// it when no solid can be made (or a deforming one has surface errors), and applies
/// the body's atlas mode with the project's atlas cache (Project::atlasCacheFile).
/// Errors start with "body 'NAME' (MESH): ".
Result<PreparedBodyMesh> prepareBodyMesh(const Project& project, std::size_t index);

/// prepareBodyMesh for a mesh already loaded (in metres, as prepareBodyMesh loads it): an
/// editor's. With `uvsChosen` the mesh already has the UVs the body bakes with (the atlas
/// applied), and is used as it is unless it is repaired.
Result<PreparedBodyMesh> prepareLoadedBodyMesh(const Project& project, std::size_t index,
                                               TriangleMesh loaded, bool uvsChosen = false);

/// What the artist painted and built for a body, in memory (read from the project's files, or
/// an editor's edits): maps over the UVs of `paintedOver` (the artist's mesh with the UVs it is
/// painted over; null: PreparedBodyMesh::artist, or the prepared mesh when not repaired) and the
/// body's own water graph (null: none).
struct BodyPaint {
    std::shared_ptr<const TriangleMesh> paintedOver;
    std::shared_ptr<const PaintedMap> permeabilityMap, shellDensityMap, shellThicknessMap;
    std::shared_ptr<const WaterGraph> waterGraph;
};

/// The parts bakeSceneBody takes, from a prepared mesh and its paint: maps painted over the
/// artist's mesh moved onto a physics solid, and an open hull's open caps (BodyDesc::capMode)
/// made compartments of its water graph (a graph made for them, with Torricelli's inflow, when
/// `desc` has none; `desc` then gains it), those caps painted permeable over what is painted and
/// sealed ones impermeable, the space behind every cap kept out of a solid material
/// (BodyParts::hollow) and the caps out of a shell (BodyParts::capTriangles). Frames are the
/// caller's.
Result<BodyParts> assembleBodyParts(BodyDesc& desc, PreparedBodyMesh prepared,
                                    const BodyPaint& paint, const LogFunction& log = {});

/// The frames of deforming body `index` (mesh, then mesh_frames), checked against each other.
Result<std::shared_ptr<const std::vector<TriangleMesh>>> loadBodyFrames(const Project& project,
                                                                        std::size_t index);

/// Progress of one long task (the task named, "body 'x' (mesh): radiation"): the CLI shows a
/// percentage on a terminal. Empty: none.
using ProgressFactory = std::function<ProgressCallback(const std::string& task)>;

/// Body `index` of `project`, read and baked; the log hears the atlas's notice and the water
/// graph's warnings. A body with radiation on gets it computed (or read back from the
/// project's cache, Project::radiationCacheFile), with `progress` while it computes.
Result<SceneBody> loadSceneBody(const Project& project, std::size_t index,
                                const LogFunction& log = {}, const ProgressFactory& progress = {});

/// Every body of `project` (loadSceneBody) and its medium, water and simulation settings. A
/// gravity World cannot simulate, or Gerstner waves whose water.gravity is not the magnitude of
/// simulation.gravity, are refused here with their JSON path.
Result<Scene> loadScene(const Project& project, const LogFunction& log = {},
                        const ProgressFactory& progress = {});

/// How the adapter names the project file in messages: "<file stem>.plim.json".
std::string projectFileName(const Project& project);

}  // namespace plimsoll
