// A body's level ladder (level_ladder.h) through the project's cache: the coarser levels are
// baked and measured once per mesh and settings, and later loads read them back. The cache is a
// folder (Project::levelCacheFolder): levels.json (keyed by levelKey, with each level's size
// and stated errors and cost) and one bake folder per coarser level (bake_io.h, float32). A
// folder with another key is stale and replaced; one that does not read is reported on the log
// and replaced. levels.json is written last and atomically: a killed run leaves a folder whose
// key does not match, never levels that pass for the body's.
#pragma once

#include "plimsoll/core/result.h"
#include "plimsoll/scene/scene.h"

#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace plimsoll {

/// What decides a body's ladder: its mesh (positions, UVs, triangles), the sizes, the texel
/// stretch limit and the centre of mass the errors are measured about.
std::string levelKey(const SceneBody& body, const std::vector<int>& sizes);

/// The cached ladder in `folder` for `body` (its finest level is body.textures) when it was
/// made for `key`; nullopt when the folder is absent or stale; an error (ErrorKind::format,
/// naming the file) when it is damaged. A cached level's samples are the bake's rounded to
/// float32 (what the bundle ships).
Result<std::optional<std::vector<BuoyancyLevel>>> readLevelCache(
    const std::filesystem::path& folder, const std::string& key, const SceneBody& body);

/// Writes `levels` (coarsest first; the last, the finest, is not written) under `key`.
Status writeLevelCache(const std::filesystem::path& folder, const std::string& key,
                       const std::vector<BuoyancyLevel>& levels);

/// bakeBodyLevels through the cache in `folder` (empty: no cache). The log hears where the
/// levels came from and a damaged cache being replaced.
Result<std::shared_ptr<const std::vector<BuoyancyLevel>>> cachedBodyLevels(
    const SceneBody& body, const std::filesystem::path& folder, const LogFunction& log);

}  // namespace plimsoll
