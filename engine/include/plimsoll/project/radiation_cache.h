// A body's radiation (scene_radiation.h) through a cache file: the panel method runs once per
// mesh and settings, later loads read its coefficients back (the memory fit is redone, it is
// cheap and deterministic). The file is JSON, keyed by radiationKey; a file with another key is
// stale and replaced, a file that does not read is reported on the log and replaced. Written
// atomically (file_util.h): a killed run leaves the previous cache or none, never half a file.
#pragma once

#include "plimsoll/core/result.h"
#include "plimsoll/scene/scene.h"
#include "plimsoll/scene/scene_radiation.h"

#include <filesystem>
#include <memory>
#include <optional>
#include <string>

namespace plimsoll {

/// The cached coefficients at `file` when they were computed for `key`; nullopt when the file
/// is absent or stale; an error (ErrorKind::format, naming the file and what is wrong) when it
/// is not a radiation cache or is damaged.
Result<std::optional<BodyRadiation>> readRadiationCache(const std::filesystem::path& file,
                                                        const std::string& key);

/// Writes `radiation`'s coefficients under `key` (creating the cache folder).
Status writeRadiationCache(const std::filesystem::path& file, const std::string& key,
                           const BodyRadiation& radiation);

/// computeBodyRadiation through the cache at `cacheFile` (empty: no cache). The log hears where
/// the coefficients came from, how long they took, and a damaged cache being replaced.
Result<std::shared_ptr<const BodyRadiation>> cachedBodyRadiation(
    const SceneBody& body, const RadiationDesc& desc, const MediumDesc& medium,
    const Eigen::Vector3d& gravity, const std::filesystem::path& cacheFile, const LogFunction& log,
    const ProgressCallback& progress);

}  // namespace plimsoll
