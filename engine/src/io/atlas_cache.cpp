// The generated physics atlas cached as JSON beside the project (atlas_cache.h).
#include "plimsoll/io/atlas_cache.h"
#include "plimsoll/io/json_depth.h"

#include "plimsoll/core/hash.h"
#include "plimsoll/core/limits.h"
#include "plimsoll/io/file_util.h"

#include <nlohmann/json.hpp>

#include <Eigen/Geometry>

#include <optional>
#include <string>
#include <vector>

namespace plimsoll {

namespace {

std::string meshHash(const TriangleMesh& mesh) {
    std::uint64_t h = kFnv1aBasis;
    for (const Eigen::Vector3d& p : mesh.positions) h = fnv1a(h, p.data(), 3 * sizeof(double));
    for (const Triangle& t : mesh.triangles) h = fnv1a(h, t.data(), sizeof(Triangle));
    return hashText(h);
}

nlohmann::json settingsJson(const AtlasSettings& s) {
    return {{"texture_size", s.textureSize},
            {"gutter_texels", s.gutterTexels},
            {"max_chart_angle_degrees", s.maxChartAngleDegrees},
            {"max_chart_radius", s.maxChartRadius},
            {"generator_version", kAtlasGeneratorVersion}};
}

std::optional<PhysicsAtlas> readCache(const TriangleMesh& mesh, const AtlasSettings& settings,
                                      const std::filesystem::path& file) {
    // A cache that is not a regular file (a FIFO planted there) is no cache: never block on it.
    Result<std::string> text = readWholeFile(file, kMaxJsonFileBytes, "kMaxJsonFileBytes");
    if (!text || !checkJsonDepth(*text, file.string()).ok()) return std::nullopt;
    try {
        const nlohmann::json j = nlohmann::json::parse(*text);
        if (j.at("format") != "plimsoll-physics-atlas" || j.at("mesh_hash") != meshHash(mesh) ||
            j.at("settings") != settingsJson(settings)) {
            return std::nullopt;
        }
        PhysicsAtlas atlas;
        atlas.mesh.source = mesh.source;
        atlas.sourceVertex = j.at("source_vertex").get<std::vector<std::uint32_t>>();
        const auto uv = j.at("uv").get<std::vector<double>>();
        const auto triangles = j.at("triangles").get<std::vector<std::uint32_t>>();
        atlas.chartOfTriangle = j.at("chart").get<std::vector<std::uint32_t>>();
        atlas.chartCount = j.at("chart_count").get<std::size_t>();
        atlas.uvCoverage = j.at("uv_coverage").get<double>();
        atlas.uvPerMetre = j.at("uv_per_metre").get<double>();
        const std::size_t vertices = atlas.sourceVertex.size();
        if (uv.size() != 2 * vertices || triangles.size() != 3 * mesh.triangleCount() ||
            atlas.chartOfTriangle.size() != mesh.triangleCount()) {
            return std::nullopt;
        }
        for (std::size_t v = 0; v < vertices; ++v) {
            if (atlas.sourceVertex[v] >= mesh.vertexCount()) return std::nullopt;
            atlas.mesh.positions.push_back(mesh.positions[atlas.sourceVertex[v]]);
            atlas.mesh.uvs.emplace_back(uv[2 * v], uv[2 * v + 1]);
        }
        for (std::size_t t = 0; t < mesh.triangleCount(); ++t) {
            Triangle tri{triangles[3 * t], triangles[3 * t + 1], triangles[3 * t + 2]};
            for (int k = 0; k < 3; ++k) {
                if (tri[k] >= vertices || atlas.sourceVertex[tri[k]] != mesh.triangles[t][k]) {
                    return std::nullopt;
                }
            }
            atlas.mesh.triangles.push_back(tri);
        }
        return atlas;
    } catch (const nlohmann::json::exception&) {
        return std::nullopt;  // unreadable: regenerated and replaced
    }
}

Status writeCache(const PhysicsAtlas& atlas, const TriangleMesh& mesh,
                  const AtlasSettings& settings, const std::filesystem::path& file) {
    std::vector<double> uv;
    uv.reserve(2 * atlas.mesh.vertexCount());
    for (const Eigen::Vector2d& p : atlas.mesh.uvs) {
        uv.push_back(p.x());
        uv.push_back(p.y());
    }
    std::vector<std::uint32_t> triangles;
    for (const Triangle& t : atlas.mesh.triangles)
        triangles.insert(triangles.end(), t.begin(), t.end());
    nlohmann::json j = {{"format", "plimsoll-physics-atlas"},
                        {"mesh", mesh.source},
                        {"mesh_hash", meshHash(mesh)},
                        {"settings", settingsJson(settings)},
                        {"chart_count", atlas.chartCount},
                        {"uv_coverage", atlas.uvCoverage},
                        {"uv_per_metre", atlas.uvPerMetre},
                        {"source_vertex", atlas.sourceVertex},
                        {"uv", uv},
                        {"triangles", triangles},
                        {"chart", atlas.chartOfTriangle}};
    std::error_code ec;
    if (!file.parent_path().empty()) std::filesystem::create_directories(file.parent_path(), ec);
    const std::string text = j.dump() + "\n";
    return writeFileAtomically(file, [&](std::ostream& out) { return bool(out << text); });
}

}  // namespace

Result<PhysicsAtlas> cachedPhysicsAtlas(const TriangleMesh& mesh, const AtlasSettings& settings,
                                        const std::filesystem::path& cacheFile) {
    if (!cacheFile.empty()) {
        if (std::optional<PhysicsAtlas> cached = readCache(mesh, settings, cacheFile)) {
            return std::move(*cached);
        }
    }
    Result<PhysicsAtlas> atlas = generatePhysicsAtlas(mesh, settings);
    if (!atlas || cacheFile.empty()) return atlas;
    if (Status saved = writeCache(*atlas, mesh, settings, cacheFile); !saved) {
        return withContext(mesh.source + ": could not cache the physics atlas: ", saved.error());
    }
    return atlas;
}

Result<AtlasChoice> chooseCachedAtlas(const TriangleMesh& mesh, const ValidationReport& report,
                                      AtlasMode mode, const AtlasSettings& settings,
                                      const std::filesystem::path& cacheFile) {
    return chooseAtlas(mesh, report, mode, settings,
                       [&](const TriangleMesh& m, const AtlasSettings& s) {
                           return cachedPhysicsAtlas(m, s, cacheFile);
                       });
}

}  // namespace plimsoll
