// Runtime bundle export (bundle.h, docs/bundle.md).
#include "plimsoll/bundle.h"

#include "plimsoll/bake.h"
#include "plimsoll/bake_io.h"
#include "plimsoll/body_setup.h"
#include "plimsoll/deform.h"
#include "plimsoll/file_util.h"
#include "plimsoll/limits.h"
#include "plimsoll/graph.h"
#include "plimsoll/massprops.h"
#include "plimsoll/painted_map.h"

#include "exr_io.h"
#include "gltf_writer.h"
#include "texture_facts_json.h"

#include <nlohmann/json.hpp>
#include <openssl/evp.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <cstdio>
#include <fstream>
#include <iterator>
#include <set>
#include <system_error>
#include <unistd.h>

namespace plimsoll {

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

constexpr const char* kManifestFile = "manifest.json";

std::string toHex(const unsigned char* data, unsigned int size) {
    static constexpr char kDigits[] = "0123456789abcdef";
    std::string hex;
    hex.reserve(2 * size);
    for (unsigned int i = 0; i < size; ++i) {
        hex += kDigits[data[i] >> 4];
        hex += kDigits[data[i] & 15];
    }
    return hex;
}

Result<std::string> readBytes(const fs::path& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) return makeError(path.string() + ": cannot open");
    std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    if (in.bad()) return makeError(path.string() + ": read error");
    return bytes;
}

// Files of the staging folder are written directly: the folder as a whole is renamed into
// place only once complete (writeBodyBundle), which is what makes the export atomic.
Status writeBytes(const fs::path& path, const std::string& bytes) {
    if (Status step = fileStep("writing", path); !step.ok()) return step;
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
    out.close();
    if (!out) return makeError(path.string() + ": cannot write");
    return Ok{};
}

json vec3(const Eigen::Vector3d& v) { return json::array({v.x(), v.y(), v.z()}); }

json massJson(const MassProperties& p) {
    json inertia = json::array();
    for (int r = 0; r < 3; ++r) {
        inertia.push_back(json::array({p.inertia(r, 0), p.inertia(r, 1), p.inertia(r, 2)}));
    }
    return json{{"mass", p.mass},
                {"volume", p.volume},
                {"center_of_mass", vec3(p.centerOfMass)},
                {"inertia", inertia}};
}

/// Relative paths of the regular files under `folder`, sorted.
std::vector<std::string> filesUnder(const fs::path& folder) {
    std::vector<std::string> files;
    std::error_code ec;
    if (!fs::is_directory(folder, ec)) return files;
    for (fs::recursive_directory_iterator it(folder, ec), end; !ec && it != end; it.increment(ec)) {
        if (it->is_regular_file(ec)) files.push_back(fs::relative(it->path(), folder).generic_string());
    }
    std::sort(files.begin(), files.end());
    return files;
}

/// A hidden sibling of `folder` unique to this process and call.
fs::path siblingFor(const fs::path& folder, const std::string& kind) {
    static std::atomic<unsigned> counter{0};
    return folder.parent_path() / ("." + folder.filename().string() + "." + kind + "-" +
                                   std::to_string(::getpid()) + "-" +
                                   std::to_string(counter++));
}

/// The texel-to-node map as an N x N image (row 0 at the top, as the other images): 1 + the
/// node index (graph.json order) of each covered texel, 0 where nothing is covered. The node is
/// plimsoll::texelNodeMap's (nearestNode of the entry's point, the rule WaterGraphSimulation
/// feeds texels by); a texel with several entries (shared by two UV islands, or refined) takes
/// the node of its largest-area entry, the first on a tie: one value a texel, so a runtime that
/// wants the simulation's exact per-entry feed recomputes nearestNode over samples.exr there.
detail::UintImage texelNodeImage(const WaterGraph& graph, const SurfaceTextures& t) {
    const std::vector<std::int32_t> nodes = texelNodeMap(graph, t);
    detail::UintImage image;
    image.width = image.height = t.size;
    image.channel = "node";
    image.pixels.assign(static_cast<std::size_t>(t.size) * t.size, 0u);
    for (std::size_t first = 0, last; first < t.coveredCount(); first = last) {
        std::size_t largest = first;
        for (last = first; last < t.coveredCount() && t.texelIndex[last] == t.texelIndex[first];
             ++last) {
            if (t.area[last] > t.area[largest]) largest = last;
        }
        const std::size_t x = t.texelIndex[first] % t.size, y = t.texelIndex[first] / t.size;
        const std::size_t pixel = (static_cast<std::size_t>(t.size) - 1 - y) * t.size + x;
        image.pixels[pixel] = static_cast<std::uint32_t>(nodes[largest] + 1);
    }
    return image;
}

/// Writes the whole bundle of body `index` into `staging` (an empty folder).
Result<BundleReport> buildBundle(const Project& project, std::size_t index, const fs::path& staging,
                                 const std::function<void(const std::string&)>& log) {
    const BodyDesc& desc = project.bodies.at(index);
    const std::string label = bodyLabel(desc);
    auto say = [&](const std::string& line) {
        if (log) log(line);
    };
    Result<PreparedBodyMesh> prepared = prepareBodyMesh(project, index);
    if (!prepared) return prepared.error();
    if (!prepared->atlas.notice.empty()) say(label + ": " + prepared->atlas.notice);
    const TriangleMesh& mesh = prepared->mesh;

    // A deforming body: its frames as World loads them; the bake records its pieces so every
    // frame's textures are regathered from them (deform.h), exactly as World steps them.
    std::vector<TriangleMesh> frames;
    SurfacePieceTable pieces;
    if (desc.deforms()) {
        std::vector<fs::path> paths{project.resolvePath(desc.mesh)};
        for (const std::string& frame : desc.meshFrames) paths.push_back(project.resolvePath(frame));
        Result<std::vector<TriangleMesh>> loaded = loadMeshFrames(paths);
        if (!loaded) return Error{label + ": " + loaded.error().message};
        frames = std::move(*loaded);
    }

    BakeSettings settings;
    settings.size = desc.textureSize;
    settings.maxTexelStretch = desc.maxTexelStretch;
    Result<SurfaceTextures> textures =
        bakeSurfaceTextures(mesh, settings, desc.deforms() ? &pieces : nullptr);
    if (!textures) return Error{label + ": " + textures.error().message};
    Result<MassProperties> textureMass = bodyMaterialMass(*textures, desc.material, project, label);
    if (!textureMass) return textureMass.error();

    // Exact mass from the mesh itself (divergence theorem per triangle): defined for a uniform
    // solid and a uniform shell; a painted shell has no closed form here.
    const MaterialDesc& m = desc.material;
    json exact = nullptr;
    if (m.shellDensityMap.empty() && m.shellThicknessMap.empty()) {
        MassProperties total;
        if (m.density) total = exactSolidMassProperties(mesh, *m.density);
        if (m.shellSurfaceDensity) {
            const MassProperties shell = exactShellMassProperties(mesh, *m.shellSurfaceDensity);
            total = m.density ? total + shell : shell;
        }
        exact = massJson(total);
    }

    // Images and the sample list: the bake's own writer (float32, ZIP, lossless).
    if (Status s = writeBakedTextures(*textures, staging, desc.mesh); !s.ok()) return s.error();
    std::error_code ec;
    if (Status step = fileStep("renaming", staging / "area.exr"); !step.ok()) return step.error();
    fs::rename(staging / "area_vector.exr", staging / "area.exr", ec);
    if (ec) return makeError((staging / "area.exr").string() + ": " + ec.message());

    // Frames of a deforming body: frames/NNN/ holds position.exr, area.exr and samples.exr
    // (the texels, coverage and sample order are the bake's in every frame; only points and
    // area vectors move), and the manifest each frame's mass properties.
    json deforming = nullptr;
    if (desc.deforms()) {
        json frameMass = json::array();
        SurfaceTextures frame = *textures;
        for (std::size_t k = 0; k < frames.size(); ++k) {
            regatherSurface(pieces, frames[k], frame);
            char name[24];
            std::snprintf(name, sizeof name, "%03zu", k);
            const fs::path folder = staging / "frames" / name;
            if (Status s = writeBakedTextures(frame, folder, desc.mesh); !s.ok()) return s.error();
            fs::rename(folder / "area_vector.exr", folder / "area.exr", ec);
            if (!ec) fs::remove(folder / "coverage.exr", ec);  // the bake's, every frame
            if (!ec) fs::remove(folder / "manifest.json", ec);
            if (ec) return makeError(folder.string() + ": " + ec.message());
            Result<MassProperties> mass = bodyMaterialMass(frame, desc.material, project, label);
            if (!mass) return mass.error();
            frameMass.push_back(massJson(*mass));
        }
        deforming = {{"frames", frames.size()},
                     {"frames_per_second", desc.framesPerSecond},
                     {"exported", "all frames"},
                     {"frame_folder", "frames/NNN (000 = the first frame)"},
                     {"frame_files", json::array({"position.exr", "area.exr", "samples.exr"})},
                     {"frame_mass_properties", frameMass}};
        say(label + ": deforming: " + std::to_string(frames.size()) + " frames exported");
    }

    json sources = json::object();
    auto addSource = [&](const std::string& role, const std::string& path) -> Status {
        Result<std::string> sha = sha256OfFile(project.resolvePath(path));
        if (!sha) return Error{label + ": " + sha.error().message};
        sources[role] = {{"path", path}, {"sha256", *sha}};
        return Ok{};
    };
    if (Status s = addSource("mesh", desc.mesh); !s.ok()) return s.error();

    // Painted maps, re-encoded as 16-bit greyscale PNG (over the baked UVs).
    json maps = json::object();
    const std::array<std::pair<const char*, const std::string*>, 3> painted = {
        std::pair{"permeability", &desc.permeabilityMap},
        std::pair{"shell_density", &m.shellDensityMap},
        std::pair{"shell_thickness", &m.shellThicknessMap}};
    for (const auto& [role, path] : painted) {
        if (path->empty()) continue;
        Result<PaintedMap> map = loadPaintedMap(project.resolvePath(*path));
        if (!map) return Error{label + ": " + map.error().message};
        const std::string file = std::string(role) + ".png";
        if (Status s = writeBytes(staging / file, encodePaintedMapPng16(*map)); !s.ok())
            return s.error();
        if (Status s = addSource(std::string(role) + "_map", *path); !s.ok()) return s.error();
        maps[role] = {{"path", file}, {"width", map->width}, {"height", map->height}};
    }

    json graphJson = nullptr;
    if (desc.waterGraph) {
        const WaterGraphDesc& g = *desc.waterGraph;
        std::string warnings;
        Result<WaterGraph> graph = loadGraph(project.resolvePath(g.graph), &mesh, &warnings);
        if (!graph) return Error{label + ": water graph: " + graph.error().message};
        if (!warnings.empty()) say(warnings);
        if (Status s = writeBytes(staging / "graph.json", graphToJson(*graph)); !s.ok())
            return s.error();
        if (Status s = addSource("water_graph", g.graph); !s.ok()) return s.error();
        if (Status s = detail::writeExr(staging / "texel_nodes.exr", texelNodeImage(*graph, *textures));
            !s.ok())
            return s.error();
        graphJson = {{"path", "graph.json"},
                     {"texel_nodes", "texel_nodes.exr"},
                     {"nodes", graph->nodes.size()},
                     {"pipes", graph->pipes.size()},
                     {"total_capacity", graph->totalCapacity()},
                     {"permeability", g.permeability},
                     {"inflow", inflowModelName(g.inflow)},
                     {"inflow_rate", g.inflowRate},
                     {"discharge_coefficient", g.dischargeCoefficient},
                     {"flow", flowModelName(g.flow)},
                     {"diffusion_pressure", g.diffusionPressure},
                     {"free_surface", g.freeSurface},
                     {"seed", g.seed}};
    }

    // The mesh as glTF 2.0 over the baked UVs, its node pointing back at this manifest (the
    // glTF lies in the bundle folder, so the path is the manifest's own name).
    const std::string gltfStem = bundleFolderName(project, index);
    {
        json extras = {{"plimsoll_bundle",
                        {{"manifest", kManifestFile},
                         {"format", "plimsoll-runtime-bundle"},
                         {"schema_version", kBundleSchemaMajor},
                         {"schema_minor", kBundleSchemaMinor},
                         {"body", desc.name},
                         {"mass", textureMass->mass},
                         {"texture_size", textures->size},
                         {"texcoord", "TEXCOORD_0 = the UVs the bundle's textures were baked "
                                      "over"}}}};
        const detail::GltfFiles gltf = detail::encodeGltf(mesh, textures->placement,
                                                          gltfStem + ".bin", desc.name, extras);
        if (Status s = writeBytes(staging / (gltfStem + ".gltf"), gltf.gltf); !s.ok())
            return s.error();
        if (Status s = writeBytes(staging / (gltfStem + ".bin"), gltf.bin); !s.ok())
            return s.error();
    }

    BundleReport report;
    report.body = desc.name;
    report.textureSize = textures->size;
    report.coveredTexels = textures->distinctTexelCount();
    json files = json::array();
    for (const std::string& path : filesUnder(staging)) {
        if (path == kManifestFile) continue;
        Result<std::string> bytes = readBytes(staging / path);
        if (!bytes) return bytes.error();
        BundleFile file{path, sha256Hex(*bytes), bytes->size()};
        files.push_back({{"path", file.path}, {"sha256", file.sha256}, {"bytes", file.bytes}});
        report.files.push_back(std::move(file));
    }

    json material = json::object();
    material["model"] = m.density && m.shellSurfaceDensity ? "solid+shell"
                        : m.density                        ? "solid"
                                                           : "shell";
    material["density"] = m.density ? json(*m.density) : json(nullptr);
    material["shell_surface_density"] =
        m.shellSurfaceDensity ? json(*m.shellSurfaceDensity) : json(nullptr);
    material["shell_density_map"] = maps.contains("shell_density") ? json("shell_density.png")
                                                                    : json(nullptr);
    material["shell_thickness_map"] = maps.contains("shell_thickness")
                                          ? json("shell_thickness.png") : json(nullptr);

    const SurfaceTextures& t = *textures;
    json manifest = {
        // bake_io.h reads these four: readBakedTextures() loads a bundle's sample list.
        {"schema_version", kBundleSchemaMajor},
        {"schema_minor", kBundleSchemaMinor},
        {"format", "plimsoll-runtime-bundle"},
        {"generator", "plimsoll"},
        {"project", project.name},
        {"body", desc.name},
        {"units", {{"length", "m"}, {"area", "m^2"}, {"volume", "m^3"}, {"mass", "kg"},
                   {"inertia", "kg m^2"}, {"density", "kg/m^3"},
                   {"surface_density", "kg/m^2"}}},
        {"axes", {{"space", "object space of the source mesh"}, {"up", "+y"},
                  {"handedness", "right"}}},
        {"image_rows", "row 0 of each image is the top of the texture (v = 1): texel (x, y) is "
                       "pixel (x, N - 1 - y)"},
        {"atlas", {{"mode", atlasModeName(desc.atlas)},
                   {"generated", prepared->atlas.generated},
                   {"charts", prepared->atlas.chartCount}}},
        {"deforming", deforming},
        {"material", material},
        {"mass_properties", {{"exact", exact}, {"texture", massJson(*textureMass)}}},
        {"hydrodynamics", {{"drag_coefficient", desc.dragCoefficient},
                           {"friction_coefficient", desc.frictionCoefficient},
                           {"linear_damping", desc.linearDamping},
                           {"angular_damping", desc.angularDamping}}},
        {"painted_maps", maps},
        {"gltf", gltfStem + ".gltf"},
        {"water_graph", graphJson},
        {"sources", sources},
        {"files", files}};
    manifest.update(textureFactsJson(t));
    const std::string text = manifest.dump(2) + "\n";
    if (Status s = writeBytes(staging / kManifestFile, text); !s.ok()) return s.error();
    report.files.push_back({kManifestFile, sha256Hex(text), text.size()});
    return report;
}

}  // namespace

std::string sha256Hex(std::string_view bytes) {
    std::array<unsigned char, EVP_MAX_MD_SIZE> digest{};
    unsigned int size = 0;
    EVP_Digest(bytes.data(), bytes.size(), digest.data(), &size, EVP_sha256(), nullptr);
    return toHex(digest.data(), size);
}

Result<std::string> sha256OfFile(const fs::path& path) {
    Result<std::string> bytes = readBytes(path);
    if (!bytes) return bytes.error();
    return sha256Hex(*bytes);
}

std::uintmax_t BundleReport::totalBytes() const {
    std::uintmax_t total = 0;
    for (const BundleFile& f : files) total += f.bytes;
    return total;
}

std::string bundleFolderName(const Project& project, std::size_t index) {
    auto sanitized = [&](std::size_t i) {
        std::string name = project.bodies[i].name;
        for (char& c : name) {
            const bool ok = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') ||
                            (c >= '0' && c <= '9') || c == '.' || c == '_' || c == '-';
            if (!ok) c = '_';
        }
        if (name.empty() || name == "." || name == ".." || name.front() == '.')
            name = "body" + std::to_string(i) + name;
        return name;
    };
    std::string name = sanitized(index);
    for (std::size_t i = 0; i < index; ++i) {
        if (sanitized(i) == name) return name + "-" + std::to_string(index);
    }
    return name;
}

Result<BundleReport> writeBodyBundle(const Project& project, std::size_t index,
                                     const fs::path& folder,
                                     const std::function<void(const std::string&)>& log) {
    if (index >= project.bodies.size()) return makeError("no body " + std::to_string(index));
    const fs::path target = folder.filename().empty() ? folder.parent_path() : folder;
    std::error_code ec;
    if (!target.parent_path().empty()) fs::create_directories(target.parent_path(), ec);
    if (ec) return makeError(target.parent_path().string() + ": cannot create folder: " + ec.message());
    const fs::path staging = siblingFor(target, "tmp");
    fs::remove_all(staging, ec);
    fs::create_directories(staging, ec);
    if (ec) return makeError(staging.string() + ": cannot create folder: " + ec.message());
    Result<BundleReport> report = buildBundle(project, index, staging, log);
    if (!report) {
        fs::remove_all(staging, ec);
        return report.error();
    }
    // Swap the folders: the old bundle is moved aside, the new one renamed into place, the old
    // one removed. Each rename is atomic; a failure puts the old bundle back.
    const fs::path old = siblingFor(target, "old");
    const bool hadOld = fs::exists(target, ec);
    if (hadOld) {
        if (Status step = fileStep("renaming", target); !step.ok()) {
            fs::remove_all(staging, ec);
            return step.error();
        }
        fs::rename(target, old, ec);
        if (ec) {
            fs::remove_all(staging, ec);
            return makeError(target.string() + ": cannot replace: " + ec.message());
        }
    }
    Status moved = fileStep("renaming", staging);
    if (moved.ok()) fs::rename(staging, target, ec);
    if (!moved.ok() || ec) {
        const std::string message =
            moved.ok() ? target.string() + ": cannot replace: " + ec.message()
                       : moved.error().message;
        std::error_code ignored;
        if (hadOld) fs::rename(old, target, ignored);
        fs::remove_all(staging, ignored);
        return makeError(message);
    }
    if (hadOld) fs::remove_all(old, ec);
    report->folder = target;
    return report;
}

Result<BundleManifestInfo> parseBundleManifest(const std::string& text, const std::string& source) {
    const std::string where = source + ": ";
    BundleManifestInfo info;
    try {
        const json manifest = json::parse(text);
        if (manifest.value("format", std::string()) != "plimsoll-runtime-bundle")
            return makeError(where + "not a Plimsoll runtime bundle (\"format\" is not "
                             "\"plimsoll-runtime-bundle\")");
        info.schemaMajor = manifest.at("schema_version").get<int>();
        info.schemaMinor = manifest.at("schema_minor").get<int>();
        if (info.schemaMajor != kBundleSchemaMajor) {
            return makeError(where + "bundle schema " + std::to_string(info.schemaMajor) + "." +
                             std::to_string(info.schemaMinor) +
                             (info.schemaMajor > kBundleSchemaMajor ? " is newer than" : " is older than") +
                             " this reader's " + std::to_string(kBundleSchemaMajor) +
                             ".x: export the bundle again with this version of plimsoll" +
                             (info.schemaMajor > kBundleSchemaMajor ? " or update the reader" : ""));
        }
        info.body = manifest.value("body", std::string());
        for (const json& f : manifest.at("files")) {
            info.files.push_back({f.at("path").get<std::string>(), f.at("sha256").get<std::string>(),
                                  f.at("bytes").get<std::uintmax_t>()});
        }
    } catch (const std::exception& e) {
        return makeError(where + "malformed manifest: " + e.what());
    }
    for (const BundleFile& f : info.files) {
        const fs::path relative(f.path);
        if (f.path.empty() || relative.is_absolute() ||
            std::any_of(relative.begin(), relative.end(), [](const fs::path& c) { return c == ".."; }))
            return makeError(where + "file path \"" + f.path + "\" leaves the bundle");
    }
    return info;
}

Result<BundleManifestInfo> verifyBundle(const fs::path& folder) {
    const fs::path manifestPath = folder / kManifestFile;
    Result<std::string> text = readWholeFile(manifestPath, kMaxJsonFileBytes, "kMaxJsonFileBytes");
    if (!text) return text.error();
    Result<BundleManifestInfo> info = parseBundleManifest(*text, manifestPath.string());
    if (!info) return info.error();
    for (const BundleFile& f : info->files) {
        const fs::path path = folder / f.path;
        std::error_code ec;
        if (!fs::is_regular_file(path, ec)) return makeError(path.string() + ": missing");
        Result<std::string> bytes = readBytes(path);
        if (!bytes) return bytes.error();
        if (bytes->size() != f.bytes) {
            return makeError(path.string() + ": " + std::to_string(bytes->size()) +
                             " bytes, the manifest says " + std::to_string(f.bytes) +
                             " (truncated or replaced)");
        }
        const std::string sha = sha256Hex(*bytes);
        if (sha != f.sha256) {
            return makeError(path.string() + ": SHA-256 " + sha + " does not match the manifest's " +
                             f.sha256);
        }
    }
    return info;
}

Result<BundleReport> checkBodyBundle(const Project& project, std::size_t index,
                                     const fs::path& folder) {
    if (index >= project.bodies.size()) return makeError("no body " + std::to_string(index));
    const fs::path target = folder.filename().empty() ? folder.parent_path() : folder;
    // Built beside the temporary directory's other files, not in the bundle's folder, which
    // a check must not touch.
    const fs::path staging =
        siblingFor(fs::temp_directory_path() / "plimsoll-check" / target.filename(), "check");
    std::error_code ec;
    fs::create_directories(staging, ec);
    if (ec) return makeError(staging.string() + ": cannot create folder: " + ec.message());
    Result<BundleReport> report = buildBundle(project, index, staging, {});
    if (!report) {
        fs::remove_all(staging, ec);
        return report.error();
    }
    const std::vector<std::string> fresh = filesUnder(staging), existing = filesUnder(target);
    std::set<std::string> differing;
    for (const std::string& path : fresh) {
        Result<std::string> now = readBytes(staging / path);
        Result<std::string> before = std::binary_search(existing.begin(), existing.end(), path)
                                         ? readBytes(target / path)
                                         : Result<std::string>(makeError("missing"));
        if (!now || !before || *now != *before) differing.insert(path);
    }
    for (const std::string& path : existing) {
        if (!std::binary_search(fresh.begin(), fresh.end(), path)) differing.insert(path);
    }
    fs::remove_all(staging, ec);
    report->folder = target;
    report->outOfDate.assign(differing.begin(), differing.end());
    return report;
}

}  // namespace plimsoll
