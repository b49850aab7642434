#include "plimsoll/bake_io.h"

#include "exr_io.h"
#include "texture_facts_json.h"
#include "plimsoll/file_util.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <fstream>
#include <system_error>

namespace plimsoll {

namespace fs = std::filesystem;
using detail::FloatImage;

namespace {

constexpr const char* kPositionFile = "position.exr";
constexpr const char* kAreaVectorFile = "area_vector.exr";
constexpr const char* kCoverageFile = "coverage.exr";
constexpr const char* kSamplesFile = "samples.exr";
// The sample list as an image: rows of kSamplesWidth entries, one channel per field.
constexpr int kSamplesWidth = 1024;
const std::vector<std::string> kSampleChannels = {"x", "y", "px", "py", "pz", "ax", "ay", "az",
                                                  "area", "coverage"};
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
    json manifest{
        {"schema_version", kBakeSchemaVersion},
        {"generator", "plimsoll"},
        {"source_mesh", sourceMesh},
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
                        {"channels", "Y = covered share of the texel's UV square"}}},
          {"samples", {{"path", kSamplesFile},
                       {"channels", "x, y = texel; px, py, pz = point (m); ax, ay, az = area "
                                    "vector (m^2); area (m^2); coverage. One entry per texel "
                                    "and surface piece, rows of 1024, unused entries have "
                                    "coverage 0: the exact list the physics sums run over; "
                                    "the images above merge a texel's entries"}}}}}};
    manifest.update(textureFactsJson(t));
    return manifest;
}

}  // namespace

Status writeBakedTextures(const SurfaceTextures& t, const fs::path& folder,
                          const std::string& sourceMesh) {
    std::error_code ec;
    fs::create_directories(folder, ec);
    if (ec) return makeError(folder.string() + ": cannot create folder: " + ec.message());

    // Images: a texel's entries merged (sum of area vectors and areas, area-weighted point).
    FloatImage position = blankImage(t.size, {"R", "G", "B", "A"});
    FloatImage areaVector = blankImage(t.size, {"R", "G", "B", "A"});
    FloatImage coverage = blankImage(t.size, {"Y"});
    for (std::size_t first = 0, last; first < t.coveredCount(); first = last) {
        Eigen::Vector3d sumA = Eigen::Vector3d::Zero(), weighted = Eigen::Vector3d::Zero();
        double area = 0, covered = 0;
        for (last = first; last < t.coveredCount() && t.texelIndex[last] == t.texelIndex[first];
             ++last) {
            sumA += t.areaVector[last];
            weighted += t.area[last] * t.position[last];
            area += t.area[last];
            covered += t.coverage[last];
        }
        const std::size_t pixel = pixelOf(t.texelIndex[first], t.size);
        const Eigen::Vector3d point = weighted / area;
        for (int k = 0; k < 3; ++k) {
            position.pixels[4 * pixel + k] = static_cast<float>(point[k]);
            areaVector.pixels[4 * pixel + k] = static_cast<float>(sumA[k]);
        }
        position.pixels[4 * pixel + 3] = 1.0f;
        areaVector.pixels[4 * pixel + 3] = static_cast<float>(area);
        coverage.pixels[pixel] = static_cast<float>(covered);
    }

    FloatImage samples;
    samples.width = kSamplesWidth;
    samples.height = std::max<int>(1, static_cast<int>((t.coveredCount() + kSamplesWidth - 1) /
                                                       kSamplesWidth));
    samples.channels = kSampleChannels;
    samples.pixels.assign(static_cast<std::size_t>(samples.width) * samples.height *
                              kSampleChannels.size(), 0.0f);
    for (std::size_t i = 0; i < t.coveredCount(); ++i) {
        float* out = &samples.pixels[i * kSampleChannels.size()];
        out[0] = static_cast<float>(t.texelIndex[i] % t.size);
        out[1] = static_cast<float>(t.texelIndex[i] / t.size);
        for (int k = 0; k < 3; ++k) {
            out[2 + k] = static_cast<float>(t.position[i][k]);
            out[5 + k] = static_cast<float>(t.areaVector[i][k]);
        }
        out[8] = static_cast<float>(t.area[i]);
        out[9] = static_cast<float>(t.coverage[i]);
    }

    // The images and the manifest are replaced together: a failure at any step leaves the
    // previous bake as it was, never new images beside an old manifest.
    const std::string manifest = manifestFor(t, sourceMesh).dump(2) + "\n";
    std::vector<FileWriter> files;
    for (const auto& [name, image] : {std::pair{kPositionFile, &position},
                                      std::pair{kAreaVectorFile, &areaVector},
                                      std::pair{kCoverageFile, &coverage},
                                      std::pair{kSamplesFile, &samples}}) {
        const fs::path target = folder / name;
        const detail::FloatImage* pixels = image;
        files.emplace_back(target, [pixels, target](const fs::path& temp) {
            return detail::writeExrFile(temp, *pixels, target);
        });
    }
    const fs::path manifestPath = folder / kManifestFile;
    files.push_back(bytesFileWriter(manifestPath, manifest));
    return replaceFilesTogether(files);
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
        return makeError(manifestPath.string() + ": texture_size " + std::to_string(t.size) +
                         " is outside " + std::to_string(kMinTextureSize) + ".." +
                         std::to_string(kMaxTextureSize) +
                         " (the limit kMaxTextureSize, limits.h)");
    }

    auto samples = detail::readExr(folder / kSamplesFile, kSampleChannels);
    if (!samples) return samples.error();
    const std::size_t count = manifest.value("texel_samples", std::size_t{0});
    if (count > static_cast<std::size_t>(samples->width) * samples->height) {
        return makeError((folder / kSamplesFile).string() + ": holds fewer samples than the "
                         "manifest's texel_samples (" + std::to_string(count) + ")");
    }
    for (std::size_t i = 0; i < count; ++i) {
        const float* in = &samples->pixels[i * kSampleChannels.size()];
        const int x = static_cast<int>(in[0]), y = static_cast<int>(in[1]);
        if (x < 0 || y < 0 || x >= t.size || y >= t.size || in[9] <= 0.0f) {
            return makeError((folder / kSamplesFile).string() + ": sample " + std::to_string(i) +
                             " is not a covered texel of the texture");
        }
        t.texelIndex.push_back(static_cast<std::uint32_t>(y) * t.size + x);
        t.position.emplace_back(in[2], in[3], in[4]);
        t.areaVector.emplace_back(in[5], in[6], in[7]);
        t.area.push_back(in[8]);
        t.coverage.push_back(in[9]);
    }
    return t;
}

}  // namespace plimsoll
