// Deforming bodies: the textures of a mesh whose vertices move but whose triangles and UVs stay
// (docs/design.md, "The textures"). The bake records, once, which triangle pieces make up every
// entry (SurfacePieceTable); each frame the entries are regathered from the moved vertices.
// The map from UV to the surface is affine on every triangle, so this is exact: the same
// entries a bake of the deformed mesh would give, without clipping again.
#pragma once

#include "plimsoll/bake/bake.h"
#include "plimsoll/geometry/mesh.h"
#include "plimsoll/core/result.h"

#include <vector>

namespace plimsoll {

/// Recomputes every entry's position (area centroid of its pieces), areaVector and area from
/// the deformed vertex positions; texel indices, coverage and placement do not change.
///
/// Precondition (asserted): `deformed` has the triangles (vertex indices) and UVs of the mesh
/// the table was baked from, and `textures` is that bake or an earlier regather of it. The
/// asserts check the triangle and entry counts; loadMeshFrames (io/mesh_io.h) is what checks files
/// a user gave. The vertices may move anywhere. The entries stay those of the bake: the islands and
/// the sub-texel refinement chosen for the baked shape are kept, where a fresh bake of a strongly
/// stretched frame might refine other triangles.
///
/// Meant to run every frame: it allocates nothing, and large tables are split over worker
/// threads started by the first such call and kept (a call made while another holds them runs
/// on the calling thread alone).
void regatherSurface(const SurfacePieceTable& table, const TriangleMesh& deformed,
                     SurfaceTextures& textures);

}  // namespace plimsoll
