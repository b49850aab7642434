#include "plimsoll/io/bake_io.h"
#include "plimsoll/io/json_depth.h"

#include "io/exr_io.h"
#include "io/texture_facts_json.h"
#include "plimsoll/core/limits.h"
#include "plimsoll/io/file_util.h"
#include "plimsoll_eval/format.hpp"

#include "plimsoll_eval/format.hpp"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <iterator>
#include <system_error>

namespace plimsoll {

namespace fs = std::filesystem;

namespace {

constexpr const char* kPositionFile = "position.exr";
constexpr const char* kAreaVectorFile = "area_vector.exr";
constexpr const char* kCoverageFile = "coverage.exr";
// The bake folder is the bundle's base: these two names are the bundle format's.
constexpr const char* kSamplesFile = plimsoll_eval::kSamplesFile;
// The sample list as an image: rows of kSamplesWidth entries, one channel per field.
constexpr int kSamplesWidth = 1024;
const std::vector<std::string> kSampleChannels = {"x",  "y",  "px", "py",   "pz",
                                                  "ax", "ay", "az", "area", "coverage"};
constexpr const char* kManifestFile = plimsoll_eval::kManifestFile;

nlohmann::json manifestFor(const SurfaceTextures& t, const std::string& sourceMesh) {
    using nlohmann::json;
    json manifest{
        {"schema_version", kBakeSchemaVersion},
        {"generator", "plimsoll"},
        {"source_mesh", sourceMesh},
        {"conventions",
         {{"units", "SI: positions in m, area vectors and areas in m^2 (mesh units)"},
          {"space", "object space of the source mesh, y up"},
          {"texel",
           "texel (x, y) covers texture uv [x/N,(x+1)/N] x [y/N,(y+1)/N]; "
           "texture uv = scale * mesh uv + offset"},
          {"image_rows", "row 0 of each image is the top of the texture (v = 1)"}}},
        {"files",
         {{"position",
           {{"path", kPositionFile},
            {"channels",
             "RGB = area centroid of the texel's surface, "
             "A = 1 if covered"}}},
          {"area_vector",
           {{"path", kAreaVectorFile}, {"channels", "RGB = integral of n dS, A = surface area"}}},
          {"coverage",
           {{"path", kCoverageFile}, {"channels", "Y = covered share of the texel's UV square"}}},
          {"samples",
           {{"path", kSamplesFile},
            {"channels",
             "x, y = texel; px, py, pz = point (m); ax, ay, az = area "
             "vector (m^2); area (m^2); coverage. One entry per texel "
             "and surface piece, rows of 1024, unused entries have "
             "coverage 0: the exact list the physics sums run over; "
             "the images above merge a texel's entries"}}}}}};
    manifest.update(textureFactsJson(t));
    return manifest;
}

}  // namespace

// The compact channel names are the runtime's (plimsoll_eval/format.hpp: one source).
const std::vector<std::string> kCompactSampleChannels(
    std::begin(plimsoll_eval::kCompactSampleChannels),
    std::end(plimsoll_eval::kCompactSampleChannels));
// The largest finite half float: a value beyond it would be stored as infinity.
constexpr double kHalfMax = 65504.0;

/// writeBakedTextures, float32 or (with `compact`) in the compact encoding.
static Status writeTextures(const SurfaceTextures& t, const fs::path& folder,
                            const std::string& sourceMesh, const CompactSamples* compact) {
    std::error_code ec;
    fs::create_directories(folder, ec);
    if (ec)
        return makeError(ErrorKind::io,
                         folder.string() + ": cannot create folder: " + ec.message());

    // Images: a texel's entries merged (sum of area vectors and areas, area-weighted point),
    // made a block of rows at a time as they are written: dense N x N images of an 8192^2 bake
    // held 2.4 GB, most of it zeros. Entries ascend by texel (y * N + x), so texel row y's are
    // entries rowStart[y] .. rowStart[y + 1]; image row 0 is the top of the texture (y = N - 1).
    const int n = t.size;
    std::vector<std::size_t> rowStart(static_cast<std::size_t>(n) + 1, t.coveredCount());
    for (std::size_t i = t.coveredCount(); i-- > 0;) rowStart[t.texelIndex[i] / n] = i;
    for (int y = n - 1; y >= 0; --y) rowStart[y] = std::min(rowStart[y], rowStart[y + 1]);
    struct Merged {
        Eigen::Vector3d point, areaVector;
        double area, coverage;
    };
    // Calls use(merged, pixel) for every covered texel of image rows first .. first + count,
    // pixel counting from the block's first pixel.
    auto forEachTexel = [&](int first, int count, const auto& use) {
        for (int r = first; r < first + count; ++r) {
            const int y = n - 1 - r;
            for (std::size_t begin = rowStart[y], last; begin < rowStart[y + 1]; begin = last) {
                Merged m{Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero(), 0.0, 0.0};
                Eigen::Vector3d weighted = Eigen::Vector3d::Zero();
                for (last = begin;
                     last < rowStart[y + 1] && t.texelIndex[last] == t.texelIndex[begin]; ++last) {
                    m.areaVector += t.areaVector[last];
                    weighted += t.area[last] * t.position[last];
                    m.area += t.area[last];
                    m.coverage += t.coverage[last];
                }
                m.point = weighted / m.area;
                const int x = static_cast<int>(t.texelIndex[begin] % n);
                use(m, static_cast<std::size_t>(r - first) * n + x);
            }
        }
    };
    detail::FloatRows position{n, n, {"R", "G", "B", "A"}, [&](float* rows, int first, int count) {
                                   forEachTexel(
                                       first, count, [&](const Merged& m, std::size_t pixel) {
                                           for (int k = 0; k < 3; ++k)
                                               rows[4 * pixel + k] = static_cast<float>(m.point[k]);
                                           rows[4 * pixel + 3] = 1.0f;
                                       });
                               }};
    detail::FloatRows areaVector{
        n, n, {"R", "G", "B", "A"}, [&](float* rows, int first, int count) {
            forEachTexel(first, count, [&](const Merged& m, std::size_t pixel) {
                for (int k = 0; k < 3; ++k)
                    rows[4 * pixel + k] = static_cast<float>(m.areaVector[k]);
                rows[4 * pixel + 3] = static_cast<float>(m.area);
            });
        }};
    detail::FloatRows coverage{n, n, {"Y"}, [&](float* rows, int first, int count) {
                                   forEachTexel(first, count,
                                                [&](const Merged& m, std::size_t pixel) {
                                                    rows[pixel] = static_cast<float>(m.coverage);
                                                });
                               }};
    // A compact bundle stores points about `origin` and everything but the texel indices as
    // half floats in [-1, 1] (docs/bundle.md "Compact bundles").
    const Eigen::Vector3d origin = compact ? compact->origin : Eigen::Vector3d::Zero();
    const double positionScale = compact ? compact->positionScale : 1.0;
    const double areaScale = compact ? compact->areaScale : 1.0;
    detail::FloatRows samples{
        kSamplesWidth,
        std::max<int>(1, static_cast<int>((t.coveredCount() + kSamplesWidth - 1) / kSamplesWidth)),
        compact ? kCompactSampleChannels : kSampleChannels, [&](float* rows, int first, int count) {
            const std::size_t begin = static_cast<std::size_t>(first) * kSamplesWidth;
            const std::size_t end =
                std::min(t.coveredCount(), begin + static_cast<std::size_t>(count) * kSamplesWidth);
            for (std::size_t i = begin; i < end; ++i) {
                float* out = &rows[(i - begin) * kSampleChannels.size()];
                out[0] = static_cast<float>(t.texelIndex[i] % n);
                out[1] = static_cast<float>(t.texelIndex[i] / n);
                for (int k = 0; k < 3; ++k) {
                    out[2 + k] = static_cast<float>((t.position[i][k] - origin[k]) / positionScale);
                    out[5 + k] = static_cast<float>(t.areaVector[i][k] / areaScale);
                }
                out[8] = static_cast<float>(t.area[i] / areaScale);
                out[9] = static_cast<float>(t.coverage[i]);
            }
        }};
    if (compact) {
        // The texel indices stay float32; everything else is half. The merged images must fit
        // a half's range: checked before anything is written.
        double worst = 0;
        forEachTexel(0, n, [&](const Merged& m, std::size_t) {
            for (int k = 0; k < 3; ++k)
                worst = std::max({worst, std::abs(m.point[k]), std::abs(m.areaVector[k])});
            worst = std::max({worst, m.area, m.coverage});
        });
        if (!(worst <= kHalfMax))
            return makeError(ErrorKind::limit, (folder / kPositionFile).string() +
                                                   ": a point or area of " + std::to_string(worst) +
                                                   " does not fit a half float (|v| <= " +
                                                   "65504): export this body without --compact");
        samples.half.assign(samples.channels.size(), true);
        samples.half[0] = samples.half[1] = false;
        for (detail::FloatRows* image : {&position, &areaVector, &coverage})
            image->half.assign(image->channels.size(), true);
    }

    // The images and the manifest are replaced together: a failure at any step leaves the
    // previous bake as it was, never new images beside an old manifest.
    // The source mesh's name is only a note for people, and a file name need not be UTF-8 (as
    // JSON is): a byte that is not is written as U+FFFD rather than refusing the bake.
    const std::string manifest =
        manifestFor(t, sourceMesh).dump(2, ' ', false, nlohmann::json::error_handler_t::replace) +
        "\n";
    std::vector<FileWriter> files;
    for (const auto& [name, image] :
         {std::pair{kPositionFile, &position}, std::pair{kAreaVectorFile, &areaVector},
          std::pair{kCoverageFile, &coverage}, std::pair{kSamplesFile, &samples}}) {
        const fs::path target = folder / name;
        const detail::FloatRows* pixels = image;
        files.emplace_back(target, [pixels, target](const fs::path& temp) {
            return detail::writeExrFile(temp, *pixels, target);
        });
    }
    const fs::path manifestPath = folder / kManifestFile;
    files.push_back(bytesFileWriter(manifestPath, manifest));
    return replaceFilesTogether(files);
}

Status writeBakedTextures(const SurfaceTextures& t, const fs::path& folder,
                          const std::string& sourceMesh) {
    return writeTextures(t, folder, sourceMesh, nullptr);
}

Status writeCompactBakedTextures(const SurfaceTextures& t, const fs::path& folder,
                                 const std::string& sourceMesh, const CompactSamples& compact) {
    return writeTextures(t, folder, sourceMesh, &compact);
}

const std::vector<std::string>& compactSampleChannels() { return kCompactSampleChannels; }

CompactSamples compactSamplesFor(const SurfaceTextures& t) {
    CompactSamples c;
    if (t.coveredCount() == 0) return c;
    Eigen::Vector3d lo = t.position[0], hi = t.position[0];
    for (std::size_t i = 0; i < t.coveredCount(); ++i) {
        lo = lo.cwiseMin(t.position[i]);
        hi = hi.cwiseMax(t.position[i]);
    }
    c.origin = 0.5 * (lo + hi);
    double extent = 0, area = 0;
    for (std::size_t i = 0; i < t.coveredCount(); ++i) {
        extent = std::max(extent, (t.position[i] - c.origin).cwiseAbs().maxCoeff());
        area = std::max({area, t.areaVector[i].cwiseAbs().maxCoeff(), t.area[i]});
    }
    // A zero scale (one point, no area) would divide by zero: any positive scale stores zeros.
    c.positionScale = extent > 0 ? extent : 1.0;
    c.areaScale = area > 0 ? area : 1.0;
    return c;
}

Result<SurfaceTextures> readBakedTextures(const fs::path& folder) {
    const fs::path manifestPath = folder / kManifestFile;
    if (Status finished = finishInterruptedReplace(manifestPath); !finished.ok())
        return finished.error();
    Result<std::string> text = readWholeFile(manifestPath, kMaxJsonFileBytes, "kMaxJsonFileBytes");
    if (!text) return text.error();
    if (Status depth = checkJsonDepth(*text, manifestPath.string()); !depth.ok())
        return depth.error();
    nlohmann::json manifest;
    try {
        manifest = nlohmann::json::parse(*text);
    } catch (const std::exception& e) {
        return makeError(ErrorKind::format, manifestPath.string() + ": malformed JSON: " +
                                                boundedExcerpt(e.what(), 200));
    }
    SurfaceTextures t;
    std::size_t count = 0;
    // The member being read names itself in the error: nlohmann's own message ("type must be
    // number, but is string") does not say which.
    std::string field = "schema_version";
    try {
        if (manifest.value(field, 0) != kBakeSchemaVersion) {
            return makeError(ErrorKind::format, manifestPath.string() +
                                                    ": unsupported schema_version (expected " +
                                                    std::to_string(kBakeSchemaVersion) + ")");
        }
        field = "texture_size";
        t.size = manifest.at(field).get<int>();
        field = "uv_placement.scale";
        t.placement.scale = manifest.at("uv_placement").at("scale").get<double>();
        field = "uv_placement.offset";
        const auto& offset = manifest.at("uv_placement").at("offset");
        t.placement.offset =
            Eigen::Vector2d(offset.at(0).get<double>(), offset.at(1).get<double>());
        field = "texel_samples";
        count = manifest.value(field, std::size_t{0});
    } catch (const std::exception& e) {
        std::string what = boundedExcerpt(e.what(), 200);
        if (const std::size_t tag = what.find("] "); tag != std::string::npos)
            what.erase(0, tag + 2);
        return makeError(ErrorKind::format, manifestPath.string() + ": " + field + ": " + what);
    }
    if (t.size < kMinTextureSize || t.size > kMaxTextureSize) {
        return makeError(ErrorKind::limit, manifestPath.string() + ": texture_size " +
                                               std::to_string(t.size) + " is outside " +
                                               std::to_string(kMinTextureSize) + ".." +
                                               std::to_string(kMaxTextureSize) +
                                               " (the limit kMaxTextureSize, limits.h)");
    }

    auto samples = detail::readExr(folder / kSamplesFile, kSampleChannels);
    if (!samples) return samples.error();
    if (count > static_cast<std::size_t>(samples->width) * samples->height) {
        return makeError(ErrorKind::format, (folder / kSamplesFile).string() +
                                                ": holds fewer samples than the "
                                                "manifest's texel_samples (" +
                                                std::to_string(count) + ")");
    }
    for (std::size_t i = 0; i < count; ++i) {
        const float* in = &samples->pixels[i * kSampleChannels.size()];
        const int x = static_cast<int>(in[0]), y = static_cast<int>(in[1]);
        if (x < 0 || y < 0 || x >= t.size || y >= t.size || in[9] <= 0.0f) {
            return makeError(ErrorKind::format, (folder / kSamplesFile).string() + ": sample " +
                                                    std::to_string(i) +
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
