// The steps that turn a project's body into something to bake, shared by World and the bundle
// export (bundle.h) so both bake exactly the same UVs and compute the same mass.
#pragma once

#include "plimsoll/atlas.h"
#include "plimsoll/massprops.h"
#include "plimsoll/mesh.h"
#include "plimsoll/project.h"
#include "plimsoll/result.h"

#include <string>

namespace plimsoll {

struct SurfaceTextures;

/// A body's mesh with the UVs it is baked with.
struct PreparedBodyMesh {
    TriangleMesh mesh;          ///< the first frame for a deforming body; atlas applied
    AtlasChoice atlas;          ///< atlas.mesh is moved into `mesh` (left empty here)
};

/// Loads body `index` of `project` (its first frame when it deforms), refuses it when the
/// surface has errors no atlas can fix (the validation report, one problem a line), and applies
/// the body's atlas mode with the project's atlas cache (Project::atlasCacheFile), as World does.
/// Errors start with "body 'NAME' (MESH): ".
Result<PreparedBodyMesh> prepareBodyMesh(const Project& project, std::size_t index);

/// Mass properties of `material` on `textures` (texture path: solid V = sum A_y y, shell point
/// masses with the painted surface-density map when there is one). `label` starts messages.
Result<MassProperties> bodyMaterialMass(const SurfaceTextures& textures,
                                        const MaterialDesc& material, const Project& project,
                                        const std::string& label);

/// "body 'NAME' (MESH)": how messages name a body.
std::string bodyLabel(const BodyDesc& body);

}  // namespace plimsoll
