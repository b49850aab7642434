// The level cache (level_cache.h).
#include "plimsoll/project/level_cache.h"

#include "plimsoll/core/hash.h"
#include "plimsoll/core/limits.h"
#include "plimsoll/io/bake_io.h"
#include "plimsoll/io/file_util.h"
#include "plimsoll/io/json_depth.h"

#include <nlohmann/json.hpp>

#include <cmath>
#include <stdexcept>

namespace plimsoll {

namespace fs = std::filesystem;

namespace {

constexpr const char* kFormat = "plimsoll-levels";
constexpr const char* kIndexFile = "levels.json";
/// Changes when what a level holds or how its error is measured changes.
constexpr double kLevelCacheVersion = 1;

double finiteAtLeastZero(const nlohmann::json& j, const char* what) {
    const double v = j.get<double>();
    if (!std::isfinite(v) || v < 0)
        throw std::runtime_error(std::string(what) + ": not a finite number >= 0");
    return v;
}

}  // namespace

std::string levelKey(const SceneBody& body, const std::vector<int>& sizes) {
    std::uint64_t h = kFnv1aBasis;
    auto add = [&h](double v) { h = fnv1a(h, &v, sizeof v); };
    add(kLevelCacheVersion);
    if (const TriangleMesh* mesh = body.parts.mesh.get()) {
        for (const Eigen::Vector3d& p : mesh->positions) h = fnv1a(h, p.data(), 3 * sizeof(double));
        for (const Eigen::Vector2d& uv : mesh->uvs) h = fnv1a(h, uv.data(), 2 * sizeof(double));
        for (const Triangle& t : mesh->triangles) h = fnv1a(h, t.data(), sizeof(Triangle));
    }
    for (int size : sizes) add(size);
    add(body.desc.maxTexelStretch);
    if (body.mass)
        for (int k = 0; k < 3; ++k) add(body.mass->centerOfMass[k]);
    return hashText(h);
}

Result<std::optional<std::vector<BuoyancyLevel>>> readLevelCache(const fs::path& folder,
                                                                 const std::string& key,
                                                                 const SceneBody& body) {
    using Levels = std::optional<std::vector<BuoyancyLevel>>;
    const fs::path index = folder / kIndexFile;
    std::error_code ec;
    if (!fs::exists(index, ec)) return Levels{};
    Result<std::string> text = readWholeFile(index, kMaxJsonFileBytes, "kMaxJsonFileBytes");
    if (!text) return text.error();
    const auto damaged = [&](const std::string& why) {
        return makeError(ErrorKind::format,
                         index.string() + ": not a readable level cache: " + why);
    };
    if (Status depth = checkJsonDepth(*text, index.string()); !depth.ok()) return depth.error();
    std::vector<BuoyancyLevel> levels;
    try {
        const nlohmann::json j = nlohmann::json::parse(*text);
        if (!j.is_object() || j.value("format", "") != kFormat)
            return damaged("no \"format\": \"" + std::string(kFormat) + "\"");
        if (j.at("key").get<std::string>() != key) return Levels{};
        for (const nlohmann::json& entry : j.at("levels")) {
            BuoyancyLevel level;
            level.size = entry.at("size").get<int>();
            level.forceError = finiteAtLeastZero(entry.at("force_error"), "force_error");
            level.torqueError = finiteAtLeastZero(entry.at("torque_error"), "torque_error");
            level.evaluationUs = finiteAtLeastZero(entry.at("evaluation_us"), "evaluation_us");
            levels.push_back(std::move(level));
        }
    } catch (const std::exception& e) {
        return damaged(e.what());
    }
    if (levels.size() < 2 || levels.back().size != body.desc.textureSize)
        return damaged("its finest level is not the body's texture_size");
    for (std::size_t k = 0; k + 1 < levels.size(); ++k) {
        const fs::path bake = folder / std::to_string(levels[k].size);
        Result<SurfaceTextures> textures = readBakedTextures(bake);
        if (!textures)
            return withContext(index.string() + ": not a readable level cache: ", textures.error());
        if (textures->size != levels[k].size) return damaged(bake.string() + " holds another size");
        levels[k].textures = std::make_shared<const SurfaceTextures>(std::move(*textures));
    }
    levels.back().textures = body.textures;
    return Levels{std::move(levels)};
}

Status writeLevelCache(const fs::path& folder, const std::string& key,
                       const std::vector<BuoyancyLevel>& levels) {
    std::error_code ec;
    // The index first goes: a run killed while the bakes are replaced leaves no index to trust.
    fs::remove(folder / kIndexFile, ec);
    nlohmann::json entries = nlohmann::json::array();
    for (std::size_t k = 0; k < levels.size(); ++k) {
        const BuoyancyLevel& level = levels[k];
        if (k + 1 < levels.size()) {
            if (Status s = writeBakedTextures(*level.textures, folder / std::to_string(level.size),
                                              "level cache");
                !s.ok())
                return s;
        }
        entries.push_back({{"size", level.size},
                           {"force_error", level.forceError},
                           {"torque_error", level.torqueError},
                           {"evaluation_us", level.evaluationUs}});
    }
    const nlohmann::json j = {{"format", kFormat}, {"key", key}, {"levels", entries}};
    const std::string text = j.dump(1) + "\n";
    return writeFileAtomically(folder / kIndexFile,
                               [&](std::ostream& out) { return bool(out << text); });
}

Result<std::shared_ptr<const std::vector<BuoyancyLevel>>> cachedBodyLevels(const SceneBody& body,
                                                                           const fs::path& folder,
                                                                           const LogFunction& log) {
    using Ladder = std::shared_ptr<const std::vector<BuoyancyLevel>>;
    const auto say = [&](const std::string& line) {
        if (log) log(line);
    };
    Status status = Ok{};
    const std::optional<std::vector<int>> sizes = bodyLadderSizes(body, status);
    if (!status) return status.error();
    if (!sizes) return Ladder{};
    const std::string key = levelKey(body, *sizes);
    if (!folder.empty()) {
        Result<std::optional<std::vector<BuoyancyLevel>>> cached =
            readLevelCache(folder, key, body);
        if (!cached) {
            say(body.label + ": " + cached.error().message + "; baking the levels again");
        } else if (*cached) {
            say(body.label + ": levels from the cache " + folder.string());
            return std::make_shared<const std::vector<BuoyancyLevel>>(std::move(**cached));
        }
    }
    Result<Ladder> baked = bakeBodyLevels(body);
    if (!baked) return baked.error();
    if (!folder.empty() && *baked) {
        if (Status saved = writeLevelCache(folder, key, **baked); !saved)
            return withContext(body.label + ": could not cache the levels: ", saved.error());
        say(body.label + ": levels cached in " + folder.string());
    }
    return baked;
}

}  // namespace plimsoll
