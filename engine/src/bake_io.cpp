#include "plimsoll/bake_io.h"

#include "exr_io.h"
#include "plimsoll/file_util.h"

#include <nlohmann/json.hpp>

#include <fstream>
#include <system_error>

namespace plimsoll {

namespace fs = std::filesystem;
using detail::FloatImage;

namespace {

constexpr const char* kPositionFile = "position.exr";
constexpr const char* kAreaVectorFile = "area_vector.exr";
constexpr const char* kCoverageFile = "coverage.exr";
constexpr const char* kManifestFile = "manifest.json";

std::size_t pixelOf(std::uint32_t texel, int size) {
    const std::size_t x = texel % size, y = texel / size;
    return (static_cast<std::size_t>(size) - 1 - y) * size + x;
}

FloatImage blankImage(int size, std::vector<std::string> channels) {
    FloatImage image;
    image.width = image.height = size;
    image.pixels.assign(static_cast<std::size_t>(size) * size * channels.size(), 0.0f);
    image.channels = std::move(channels);
    return image;
}

nlohmann::json manifestFor(const SurfaceTextures& t, const std::string& sourceMesh) {
    using nlohmann::json;
    return json{
        {"schema_version", kBakeSchemaVersion},
        {"generator", "plimsoll"},
        {"source_mesh", sourceMesh},
        {"texture_size", t.size},
        {"covered_texels", t.coveredCount()},
        {"uv_coverage", t.uvCoverage()},
        {"surface_area", t.surfaceArea()},
        {"closure_error", t.closureError()},
        {"uv_placement", {{"scale", t.placement.scale},
                          {"offset", {t.placement.offset.x(), t.placement.offset.y()}}}},
        {"conventions",
         {{"units", "SI: positions in m, area vectors and areas in m^2 (mesh units)"},
          {"space", "object space of the source mesh, y up"},
          {"texel", "texel (x, y) covers texture uv [x/N,(x+1)/N] x [y/N,(y+1)/N]; "
                    "texture uv = scale * mesh uv + offset"},
          {"image_rows", "row 0 of each image is the top of the texture (v = 1)"}}},
        {"files",
         {{"position", {{"path", kPositionFile},
                        {"channels", "RGB = area centroid of the texel's surface, "
                                     "A = 1 if covered"}}},
          {"area_vector", {{"path", kAreaVectorFile},
                           {"channels", "RGB = integral of n dS, A = surface area"}}},
          {"coverage", {{"path", kCoverageFile},
                        {"channels", "Y = covered share of the texel's UV square"}}}}}};
}

}  // namespace

Status writeBakedTextures(const SurfaceTextures& t, const fs::path& folder,
                          const std::string& sourceMesh) {
    std::error_code ec;
    fs::create_directories(folder, ec);
    if (ec) return makeError(folder.string() + ": cannot create folder: " + ec.message());

    FloatImage position = blankImage(t.size, {"R", "G", "B", "A"});
    FloatImage areaVector = blankImage(t.size, {"R", "G", "B", "A"});
    FloatImage coverage = blankImage(t.size, {"Y"});
    for (std::size_t i = 0; i < t.coveredCount(); ++i) {
        const std::size_t pixel = pixelOf(t.texelIndex[i], t.size);
        for (int k = 0; k < 3; ++k) {
            position.pixels[4 * pixel + k] = static_cast<float>(t.position[i][k]);
            areaVector.pixels[4 * pixel + k] = static_cast<float>(t.areaVector[i][k]);
        }
        position.pixels[4 * pixel + 3] = 1.0f;
        areaVector.pixels[4 * pixel + 3] = static_cast<float>(t.area[i]);
        coverage.pixels[pixel] = static_cast<float>(t.coverage[i]);
    }
    for (const auto& [name, image] : {std::pair{kPositionFile, &position},
                                      std::pair{kAreaVectorFile, &areaVector},
                                      std::pair{kCoverageFile, &coverage}}) {
        if (Status s = detail::writeExr(folder / name, *image); !s.ok()) return s;
    }
    const std::string manifest = manifestFor(t, sourceMesh).dump(2) + "\n";
    return writeFileAtomically(folder / kManifestFile, [&](std::ostream& out) {
        out << manifest;
        return static_cast<bool>(out);
    });
}

Result<SurfaceTextures> readBakedTextures(const fs::path& folder) {
    const fs::path manifestPath = folder / kManifestFile;
    std::ifstream in(manifestPath);
    if (!in) return makeError(manifestPath.string() + ": cannot open");
    nlohmann::json manifest;
    try {
        in >> manifest;
    } catch (const std::exception& e) {
        return makeError(manifestPath.string() + ": malformed JSON: " + e.what());
    }
    if (manifest.value("schema_version", 0) != kBakeSchemaVersion) {
        return makeError(manifestPath.string() + ": unsupported schema_version (expected " +
                         std::to_string(kBakeSchemaVersion) + ")");
    }
    SurfaceTextures t;
    try {
        t.size = manifest.at("texture_size").get<int>();
        t.placement.scale = manifest.at("uv_placement").at("scale").get<double>();
        const auto& offset = manifest.at("uv_placement").at("offset");
        t.placement.offset = Eigen::Vector2d(offset.at(0).get<double>(), offset.at(1).get<double>());
    } catch (const std::exception& e) {
        return makeError(manifestPath.string() + ": " + e.what());
    }
    if (t.size < kMinTextureSize || t.size > kMaxTextureSize) {
        return makeError(manifestPath.string() + ": texture_size out of range");
    }

    auto position = detail::readExr(folder / kPositionFile, {"R", "G", "B", "A"});
    if (!position) return position.error();
    auto areaVector = detail::readExr(folder / kAreaVectorFile, {"R", "G", "B", "A"});
    if (!areaVector) return areaVector.error();
    auto coverage = detail::readExr(folder / kCoverageFile, {"Y"});
    if (!coverage) return coverage.error();
    for (const FloatImage* image : {&*position, &*areaVector, &*coverage}) {
        if (image->width != t.size || image->height != t.size) {
            return makeError(folder.string() + ": image size differs from the manifest's " +
                             std::to_string(t.size));
        }
    }
    const std::uint32_t texels = static_cast<std::uint32_t>(t.size) * t.size;
    for (std::uint32_t texel = 0; texel < texels; ++texel) {
        const std::size_t pixel = pixelOf(texel, t.size);
        if (position->pixels[4 * pixel + 3] == 0.0f) continue;
        t.texelIndex.push_back(texel);
        const float* p = &position->pixels[4 * pixel];
        const float* a = &areaVector->pixels[4 * pixel];
        t.position.emplace_back(p[0], p[1], p[2]);
        t.areaVector.emplace_back(a[0], a[1], a[2]);
        t.area.push_back(a[3]);
        t.coverage.push_back(coverage->pixels[pixel]);
    }
    return t;
}

}  // namespace plimsoll
