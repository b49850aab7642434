// A Plimsoll project (`*.plim.json`): the scene every tool works on — bodies with their meshes,
// materials and starting state, the medium and its surface, gravity and the simulation
// settings. Paths are stored as written in the file (relative to the project file's folder,
// or absolute); resolvePath() makes them usable. The schema is versioned and written down in
// docs/project-schema.md.
#pragma once

#include "plimsoll/scene/scene_desc.h"
#include "plimsoll/core/result.h"
#include "plimsoll/physics/water.h"

#include <Eigen/Core>

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace plimsoll {

inline constexpr int kProjectSchemaVersion = 1;

struct Project {
    std::string name;
    std::vector<BodyDesc> bodies;
    MediumDesc medium;
    /// The medium's surface (for air: a level far above everything).
    WaterModel water;
    SimulationDesc simulation;
    /// Folder the relative paths are relative to (the project file's folder); not saved.
    std::filesystem::path folder;

    /// `path` as written in the project, made usable: absolute paths stay, relative ones are
    /// taken from `folder`.
    std::filesystem::path resolvePath(const std::string& path) const;
    /// Where body `index`'s generated atlas is cached: `<project folder>/<project file
    /// stem>.cache/atlas-<index>.json` (empty when the project has no folder: no cache).
    std::filesystem::path atlasCacheFile(std::size_t index) const;
    /// Where body `index`'s radiation coefficients are cached: beside its atlas cache,
    /// `radiation-<index>.json` (empty when the project has no folder).
    std::filesystem::path radiationCacheFile(std::size_t index) const;
    /// Where body `index`'s level ladder is cached: beside its atlas cache, the folder
    /// `levels-<index>` (empty when the project has no folder).
    std::filesystem::path levelCacheFolder(std::size_t index) const;
    /// The project file's name without ".plim.json" (set by loadProject; "project" otherwise).
    std::string fileStem = "project";
    /// What messages call a project that has no file (simulate --mesh: the mesh); empty: the
    /// project file's name.
    std::string sourceName;
    bool operator==(const Project& other) const;  ///< content, not `folder`
};

/// Reads and checks a project file. Every problem is reported, one per line, with its JSON
/// path: "scene.plim.json: bodies[1].material.density: must be > 0".
Result<Project> loadProject(const std::filesystem::path& path);

/// Parses project JSON text (`source` names it in messages; `folder` as for Project).
Result<Project> parseProject(const std::string& text, const std::string& source,
                             const std::filesystem::path& folder);

/// The project as JSON text (schema_version first, 2-space indent).
std::string projectToJson(const Project& project);

/// Writes atomically (temporary file + rename).
Status saveProject(const Project& project, const std::filesystem::path& path);

}  // namespace plimsoll
