// A generated physics atlas (surface/atlas.h) kept in a file, so that a body's painted maps
// stay attached to the same atlas from one run to the next.
#pragma once

#include "plimsoll/surface/atlas.h"
#include "plimsoll/core/result.h"

#include <filesystem>

namespace plimsoll {

/// The generated atlas for `mesh`, from `cacheFile` when it holds one made from the same mesh
/// and settings, else generated and saved there (atomically). Empty path: no cache. The file
/// is JSON (format "plimsoll-physics-atlas": the mesh's hash, the settings, and the atlas's
/// vertices, UVs with 17 digits, triangles and charts); an unreadable or stale one is replaced.
Result<PhysicsAtlas> cachedPhysicsAtlas(const TriangleMesh& mesh, const AtlasSettings& settings,
                                        const std::filesystem::path& cacheFile);

/// chooseAtlas whose generated atlas goes through cachedPhysicsAtlas (an empty `cacheFile`:
/// no cache).
Result<AtlasChoice> chooseCachedAtlas(const TriangleMesh& mesh, const ValidationReport& report,
                                      AtlasMode mode, const AtlasSettings& settings,
                                      const std::filesystem::path& cacheFile);

}  // namespace plimsoll
