// Runtime bundle export (bundle.h, docs/bundle.md).
#include "plimsoll/export/bundle.h"
#include "plimsoll/io/json_depth.h"
#include "plimsoll/io/painted_map_io.h"
#include "plimsoll/io/graph_json.h"

#include "plimsoll/bake/bake.h"
#include "plimsoll/io/bake_io.h"
#include "plimsoll/project/scene_loader.h"
#include "plimsoll/scene/level_ladder.h"
#include "plimsoll/scene/scene_radiation.h"
#include "plimsoll/surface/deform.h"
#include "plimsoll/io/file_util.h"
#include "plimsoll/core/limits.h"
#include "plimsoll/graph/graph.h"
#include "plimsoll/physics/massprops.h"
#include "plimsoll/physics/pose.h"
#include "plimsoll/physics/rigid_body.h"
#include "plimsoll/surface/painted_map.h"

#include "io/exr_io.h"
#include "io/gltf_physics.h"
#include "io/gltf_writer.h"
#include "io/graph_settings_json.h"
#include "io/texture_facts_json.h"

#include "plimsoll_runtime/runtime.hpp"

#include <nlohmann/json.hpp>
#include <openssl/evp.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fcntl.h>
#include <fstream>
#include <iterator>
#include <optional>
#include <set>
#include <stdexcept>
#include <system_error>
#include <tuple>
#include <unistd.h>

namespace plimsoll {

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

constexpr const char* kManifestFile = plimsoll_eval::kManifestFile;

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

/// A bundle's file or a source it records (a mesh: the largest files read whole).
Result<std::string> readBytes(const fs::path& path) {
    return readWholeFile(path, kMaxMeshFileBytes, "kMaxMeshFileBytes");
}

// Files of the staging folder are written directly: the folder as a whole is renamed into
// place only once complete (writeBodyBundle), which is what makes the export atomic.
Status writeBytes(const fs::path& path, const std::string& bytes) {
    if (Status step = fileStep("writing", path); !step.ok()) return step;
    // Written with write(2), so that a failure names its cause (a full disk).
    const int fd = ::open(path.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0666);
    int error = fd < 0 ? errno : 0;
    for (std::size_t done = 0; error == 0 && done < bytes.size();) {
        const ssize_t k = ::write(fd, bytes.data() + done, bytes.size() - done);
        if (k < 0 && errno == EINTR) continue;
        if (k <= 0)
            error = k < 0 ? errno : ENOSPC;
        else
            done += static_cast<std::size_t>(k);
    }
    if (fd >= 0 && ::close(fd) != 0 && error == 0) error = errno;
    if (error != 0)
        return makeError(ErrorKind::io, path.string() + ": write failed: " + std::strerror(error));
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

/// A radiating body's Cummins model for the runtime (docs/bundle.md "Radiation"): the
/// infinite-frequency added mass and the memory filters of each mode, body axes about the
/// centre of mass of mass_properties.texture; null for a body that does not radiate.
json radiationJson(const SceneBody& body) {
    if (!body.desc.radiates() || !body.radiation) return nullptr;
    const CumminsModel& model = body.radiation->model;
    json added = json::array();
    for (int r = 0; r < 6; ++r) {
        json row = json::array();
        for (int c = 0; c < 6; ++c) row.push_back(model.addedMassInfinity(r, c));
        added.push_back(row);
    }
    json memory = json::array();
    for (const std::vector<MemoryTerm>& mode : model.memory) {
        json terms = json::array();
        for (const MemoryTerm& t : mode)
            terms.push_back(
                {{"gain", t.gain}, {"frequency", t.frequency}, {"damping_ratio", t.dampingRatio}});
        memory.push_back(terms);
    }
    return {{"modes", {"surge_x", "heave_y", "sway_z", "roll_x", "yaw_y", "pitch_z"}},
            {"rest_volume", body.radiation->restVolume},
            {"panels", body.radiation->panelCount},
            {"added_mass_infinity", added},
            {"memory", memory}};
}

/// The world the body was simulated in (manifest "world", schema 1.4): the medium, the
/// water model, the step settings and the body's starting state, so that a runtime can
/// replay what the editor shows (docs/bundle.md "World"). The orientation is the World's own
/// quaternion of the start pose (RigidBodyState::orientation), w first.
json worldJson(const Project& project, const BodyDesc& desc) {
    const WaterModel& w = project.water;
    json water = {{"model", w.kind == WaterModel::Kind::Flat       ? "flat"
                            : w.kind == WaterModel::Kind::Gerstner ? "gerstner"
                                                                   : "height_grid"},
                  {"level", w.level}};
    json waves = json::array();
    for (const GerstnerWave& g : w.waves)
        waves.push_back({{"amplitude", g.amplitude},
                         {"wavelength", g.wavelength},
                         {"direction", {g.direction.x(), g.direction.y()}},
                         {"steepness", g.steepness},
                         {"phase", g.phase}});
    if (w.kind == WaterModel::Kind::Gerstner) water["waves"] = waves;
    if (w.kind == WaterModel::Kind::HeightField)
        water["grid"] = {{"count_x", w.grid.countX},
                         {"count_z", w.grid.countZ},
                         {"spacing", w.grid.spacing},
                         {"origin", {w.grid.origin.x(), w.grid.origin.y()}},
                         {"heights", w.grid.heights}};
    const Pose start = Pose::fromEulerDegrees(desc.position, desc.rotationDegrees);
    const Eigen::Quaterniond q = Eigen::Quaterniond(start.rotation).normalized();
    const SimulationDesc& sim = project.simulation;
    return {
        {"medium", {{"density", project.medium.density}, {"viscosity", project.medium.viscosity}}},
        {"gravity", vec3(sim.gravity)},
        {"water", water},
        {"simulation",
         {{"time_step", sim.timeStep},
          {"sub_steps", sim.subSteps},
          {"max_phase_step", sim.maxPhaseStep},
          {"integrator", integratorName(sim.integrator)},
          {"sleep",
           {{"enabled", sim.sleep.enabled},
            {"linear_speed", sim.sleep.linearSpeed},
            {"angular_speed", sim.sleep.angularSpeed},
            {"linear_acceleration", sim.sleep.linearAcceleration},
            {"angular_acceleration", sim.sleep.angularAcceleration},
            {"rest_time", sim.sleep.restTime},
            {"wake_height", sim.sleep.wakeHeight}}}}},
        {"start",
         {{"position", vec3(start.translation)},
          {"orientation_wxyz", {q.w(), q.x(), q.y(), q.z()}},
          {"velocity", vec3(desc.velocity)},
          {"angular_velocity", vec3(desc.angularVelocity)}}}};
}

/// A compact sample list's manifest "sample_encoding" (docs/bundle.md "Compact bundles").
json sampleEncodingJson(const CompactSamples& compact) {
    return {{"type", plimsoll_eval::kCompactSampleEncoding},
            {"channels", compactSampleChannels()},
            {"position_origin", vec3(compact.origin)},
            {"position_scale", compact.positionScale},
            {"area_scale", compact.areaScale},
            {"rule",
             "x, y: texel (float32); point = position_origin + position_scale * (hpx, "
             "hpy, hpz); area vector = area_scale * (hax, hay, haz); area = area_scale "
             "* harea; coverage; all but x, y are HALF"}};
}

/// The manifest's "levels" (docs/bundle.md "Levels"), coarsest first: each coarser level's
/// sample list alone in levels/<size>/samples.exr (the images a bake writes beside it are of no
/// use to a runtime), compact when the bundle is, over an encoding of its own; the finest level
/// is the body's own samples.exr. Each with its stated errors and cost.
Result<json> writeLevels(const std::vector<BuoyancyLevel>& ladder, const SurfaceTextures& finest,
                         const fs::path& staging, const std::string& sourceMesh, bool compact) {
    json levels = json::array();
    for (const BuoyancyLevel& level : ladder) {
        const SurfaceTextures& t = *level.textures;
        json entry = {{"size", t.size},
                      {"texel_samples", t.coveredCount()},
                      {"samples", plimsoll_eval::kSamplesFile},
                      {"sample_encoding", nullptr},
                      {"force_error", level.forceError},
                      {"torque_error", level.torqueError},
                      {"evaluation_us", level.evaluationUs}};
        if (&t == &finest) {
            entry.erase("sample_encoding");  // the bundle's own
            levels.push_back(std::move(entry));
            continue;
        }
        const std::string folderName = "levels/" + std::to_string(t.size);
        const fs::path folder = staging / folderName;
        const std::optional<CompactSamples> encoding =
            compact ? std::optional(compactSamplesFor(t)) : std::nullopt;
        if (Status s = encoding ? writeCompactBakedTextures(t, folder, sourceMesh, *encoding)
                                : writeBakedTextures(t, folder, sourceMesh);
            !s.ok())
            return s.error();
        std::error_code ec;
        for (const char* extra :
             {"position.exr", "area_vector.exr", "coverage.exr", kManifestFile}) {
            if (Status step = fileStep("removing", folder / extra); !step.ok()) return step.error();
            fs::remove(folder / extra, ec);
            if (ec)
                return makeError(ErrorKind::io, (folder / extra).string() + ": " + ec.message());
        }
        entry["samples"] = folderName + "/" + plimsoll_eval::kSamplesFile;
        if (encoding) entry["sample_encoding"] = sampleEncodingJson(*encoding);
        levels.push_back(std::move(entry));
    }
    return levels;
}

/// Relative paths of the regular files under `folder`, sorted.
std::vector<std::string> filesUnder(const fs::path& folder) {
    std::vector<std::string> files;
    std::error_code ec;
    if (!fs::is_directory(folder, ec)) return files;
    for (fs::recursive_directory_iterator it(folder, ec), end; !ec && it != end; it.increment(ec)) {
        if (it->is_regular_file(ec))
            files.push_back(fs::relative(it->path(), folder).generic_string());
    }
    std::sort(files.begin(), files.end());
    return files;
}

/// A hidden sibling of `folder` unique to this process and call.
fs::path siblingFor(const fs::path& folder, const std::string& kind) {
    static std::atomic<unsigned> counter{0};
    return folder.parent_path() / ("." + folder.filename().string() + "." + kind + "-" +
                                   std::to_string(::getpid()) + "-" + std::to_string(counter++));
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

/// The glTF node's extensions: the physics drafts with `mass` (the manifest's
/// `mass_properties.<massSource>`), and PLIMSOLL_buoyancy_bundle naming the bundle and the
/// files written before the glTF (`files`, relative to the glTF's folder).
json gltfNodeExtensions(const Project& project, const BodyDesc& desc, const MassProperties& mass,
                        const std::string& massSource, const std::vector<std::string>& files) {
    json extensions = detail::physicsNodeExtensions(mass);
    json others = json::array();
    // The bake already left its own manifest.json in the staging folder; the bundle's
    // replaces it and is named by "manifest".
    for (const std::string& file : files)
        if (file != kManifestFile) others.push_back(file);
    extensions["PLIMSOLL_buoyancy_bundle"] = {{"manifest", kManifestFile},
                                              {"format", plimsoll_eval::kBundleFormat},
                                              {"schema_version", kBundleSchemaMajor},
                                              {"schema_minor", kBundleSchemaMinor},
                                              {"project", project.name},
                                              {"body", desc.name},
                                              {"mass_properties", massSource},
                                              {"files", others}};
    return extensions;
}

/// Exact mass from the mesh itself (divergence theorem per triangle): defined for a uniform
/// solid and a uniform shell; a painted shell has no closed form here.
std::optional<MassProperties> exactMassOf(const MaterialDesc& m, const TriangleMesh& mesh,
                                          const BodyParts& parts) {
    if (!m.shellDensityMap.empty() || !m.shellThicknessMap.empty()) return std::nullopt;
    MassProperties total;
    // An open hull: the solid fills the walls, not the space behind its caps.
    if (m.density)
        total = withoutHollow(exactSolidMassProperties(mesh, *m.density), parts.hollow, *m.density);
    if (m.shellSurfaceDensity) {
        const MassProperties shell = exactShellMassProperties(mesh, *m.shellSurfaceDensity);
        total = m.density ? total + shell : shell;
    }
    return total;
}

/// The images and the sample list: the bake's own writer (float32, ZIP, lossless; or compact:
/// half floats over a per-body origin and scales, the encoding the manifest records), the area
/// vectors named area.exr.
Status writeBodyImages(const SurfaceTextures& textures, const fs::path& staging,
                       const std::string& mesh, const std::optional<CompactSamples>& compact) {
    if (Status s = compact ? writeCompactBakedTextures(textures, staging, mesh, *compact)
                           : writeBakedTextures(textures, staging, mesh);
        !s.ok())
        return s;
    if (Status step = fileStep("renaming", staging / "area.exr"); !step.ok()) return step;
    std::error_code ec;
    fs::rename(staging / "area_vector.exr", staging / "area.exr", ec);
    if (ec) return makeError(ErrorKind::io, (staging / "area.exr").string() + ": " + ec.message());
    return Ok{};
}

/// Frames of a deforming body: frames/NNN/ holds position.exr, area.exr and samples.exr (the
/// texels, coverage and sample order are the bake's in every frame; only points and area
/// vectors move), and the manifest each frame's mass properties. Its manifest entry.
Result<json> writeDeformingFrames(const BodyDesc& desc, const SceneBody& body,
                                  const fs::path& staging, const std::string& label) {
    // A deforming body's frames are regathered from its bake's pieces, as World steps them.
    const std::vector<TriangleMesh>& frames = *body.parts.frames;
    json frameMass = json::array();
    SurfaceTextures frame = *body.textures;
    std::error_code ec;
    for (std::size_t k = 0; k < frames.size(); ++k) {
        regatherSurface(*body.pieces, frames[k], frame);
        char name[24];
        std::snprintf(name, sizeof name, "%03zu", k);
        const fs::path folder = staging / "frames" / name;
        if (Status s = writeBakedTextures(frame, folder, desc.mesh); !s.ok()) return s.error();
        fs::rename(folder / "area_vector.exr", folder / "area.exr", ec);
        if (!ec) fs::remove(folder / "coverage.exr", ec);  // the bake's, every frame
        if (!ec) fs::remove(folder / kManifestFile, ec);
        if (ec) return makeError(ErrorKind::io, folder.string() + ": " + ec.message());
        Result<MassProperties> mass =
            materialMassProperties(frame, desc.material, body.parts.shellDensityMap.get(), label,
                                   body.parts.shellThicknessMap.get());
        if (!mass) return mass.error();
        frameMass.push_back(massJson(*mass));
    }
    return json{
        {"frames", frames.size()},
        {"frames_per_second", desc.framesPerSecond},
        {"exported", "all frames"},
        {"frame_folder", "frames/NNN (000 = the first frame)"},
        {"frame_files", json::array({"position.exr", "area.exr", plimsoll_eval::kSamplesFile})},
        {"frame_mass_properties", frameMass}};
}

/// The manifest's "sources": each input the project names, with its checksum. A map or graph
/// the loader made (the caps of an open hull's openings) has no path and no entry.
struct BundleSources {
    const Project& project;
    const std::string& label;
    json entries = json::object();

    Status add(const std::string& role, const std::string& path) {
        if (path.empty()) return Ok{};
        Result<std::string> sha = sha256OfFile(project.resolvePath(path));
        if (!sha) return withContext(label + ": ", sha.error());
        entries[role] = {{"path", path}, {"sha256", *sha}};
        return Ok{};
    }
};

/// Painted maps, re-encoded as 16-bit greyscale PNG (over the baked UVs). Their manifest
/// entries, by role.
Result<json> writePaintedMaps(const BodyDesc& desc, const SceneBody& body, const fs::path& staging,
                              BundleSources& sources) {
    const MaterialDesc& m = desc.material;
    json maps = json::object();
    const std::array<std::tuple<const char*, const std::string*, const PaintedMap*>, 3> painted = {
        std::tuple{"permeability", &desc.permeabilityMap, body.parts.permeabilityMap.get()},
        std::tuple{"shell_density", &m.shellDensityMap, body.parts.shellDensityMap.get()},
        std::tuple{"shell_thickness", &m.shellThicknessMap, body.parts.shellThicknessMap.get()}};
    for (const auto& [role, path, map] : painted) {
        if (!map) continue;
        const std::string file = std::string(role) + ".png";
        if (Status s = writeBytes(staging / file, encodePaintedMapPng16(*map)); !s.ok())
            return s.error();
        if (Status s = sources.add(std::string(role) + "_map", *path); !s.ok()) return s.error();
        maps[role] = {{"path", file}, {"width", map->width}, {"height", map->height}};
    }
    return maps;
}

/// The water graph's JSON and its texel-to-node image; its manifest entry (null without one).
Result<json> writeWaterGraph(const SceneBody& body, const fs::path& staging,
                             BundleSources& sources) {
    if (!body.desc.waterGraph) return json(nullptr);
    const WaterGraphDesc& g = *body.desc.waterGraph;
    const std::shared_ptr<const WaterGraph>& graph = body.parts.waterGraph;
    if (Status s = writeBytes(staging / plimsoll_eval::kGraphFile, graphToJson(*graph)); !s.ok())
        return s.error();
    if (Status s = sources.add("water_graph", g.graph); !s.ok()) return s.error();
    if (Status s = detail::writeExr(staging / plimsoll_eval::kTexelNodesFile,
                                    texelNodeImage(*graph, *body.textures));
        !s.ok())
        return s.error();
    json entry{{"path", plimsoll_eval::kGraphFile},
               {"texel_nodes", plimsoll_eval::kTexelNodesFile},
               {"nodes", graph->nodes.size()},
               {"pipes", graph->pipes.size()},
               {"total_capacity", graph->totalCapacity()},
               {"permeability", g.permeability}};
    writeGraphModels(g.settings, entry);
    return entry;
}

/// The mesh as glTF 2.0 over the baked UVs, its node pointing back at this manifest (the glTF
/// lies in the bundle folder, so the path is the manifest's own name). Its physics carries
/// the exact mass where there is one, else the texture's.
Status writeBundleGltf(const Project& project, const BodyDesc& desc, const SceneBody& body,
                       const fs::path& staging, const std::string& gltfStem,
                       const std::optional<MassProperties>& exactMass) {
    const SurfaceTextures& textures = *body.textures;
    json extras = {{"plimsoll_bundle",
                    {{"manifest", kManifestFile},
                     {"format", plimsoll_eval::kBundleFormat},
                     {"schema_version", kBundleSchemaMajor},
                     {"schema_minor", kBundleSchemaMinor},
                     {"body", desc.name},
                     {"mass", body.mass->mass},
                     {"texture_size", textures.size},
                     {"texcoord",
                      "TEXCOORD_0 = the UVs the bundle's textures were baked "
                      "over"}}}};
    const detail::GltfFiles gltf = detail::encodeGltf(
        *body.parts.mesh, textures.placement, gltfStem + ".bin", desc.name, extras,
        gltfNodeExtensions(project, desc, exactMass ? *exactMass : *body.mass,
                           exactMass ? "exact" : "texture", filesUnder(staging)));
    if (Status s = writeBytes(staging / (gltfStem + ".gltf"), gltf.gltf); !s.ok()) return s;
    return writeBytes(staging / (gltfStem + ".bin"), gltf.bin);
}

/// The manifest's "files": every file written so far, with its checksum and size, also
/// recorded in the report.
Result<json> listBundleFiles(const fs::path& staging, BundleReport& report) {
    json files = json::array();
    for (const std::string& path : filesUnder(staging)) {
        if (path == kManifestFile) continue;
        Result<std::string> bytes = readBytes(staging / path);
        if (!bytes) return bytes.error();
        BundleFile file{path, sha256Hex(*bytes), bytes->size()};
        files.push_back({{"path", file.path}, {"sha256", file.sha256}, {"bytes", file.bytes}});
        report.files.push_back(std::move(file));
    }
    return files;
}

json materialJson(const MaterialDesc& m, const json& maps) {
    json material = json::object();
    material["model"] = m.density && m.shellSurfaceDensity ? "solid+shell"
                        : m.density                        ? "solid"
                                                           : "shell";
    material["density"] = m.density ? json(*m.density) : json(nullptr);
    material["shell_surface_density"] =
        m.shellSurfaceDensity ? json(*m.shellSurfaceDensity) : json(nullptr);
    material["shell_density_map"] =
        maps.contains("shell_density") ? json("shell_density.png") : json(nullptr);
    material["shell_thickness_map"] =
        maps.contains("shell_thickness") ? json("shell_thickness.png") : json(nullptr);
    return material;
}

/// What the manifest gathers besides the body's fixed facts: each part written before it.
struct BundleParts {
    json exact, levels, deforming, maps, graph, sources, files;
    std::string gltfStem, inputHash;
    std::optional<CompactSamples> compact;
};

/// The manifest of `desc`'s bundle (the project's description; `body` as loaded and baked).
json manifestJson(const Project& project, const BodyDesc& desc, const SceneBody& body,
                  const BundleParts& parts) {
    // As the World runs it: radiation wherever it was computed, unless turned off.
    const bool radiates = body.desc.radiates() && body.radiation;
    json manifest = {
        // bake_io.h reads these four: readBakedTextures() loads a bundle's sample list.
        {"schema_version", kBundleSchemaMajor},
        {"schema_minor", kBundleSchemaMinor},
        {"format", plimsoll_eval::kBundleFormat},
        {"generator", "plimsoll"},
        {"project", project.name},
        {"body", desc.name},
        {"units",
         {{"length", "m"},
          {"area", "m^2"},
          {"volume", "m^3"},
          {"mass", "kg"},
          {"inertia", "kg m^2"},
          {"density", "kg/m^3"},
          {"surface_density", "kg/m^2"}}},
        {"axes",
         {{"space", "object space of the source mesh"}, {"up", "+y"}, {"handedness", "right"}}},
        {"image_rows",
         "row 0 of each image is the top of the texture (v = 1): texel (x, y) is "
         "pixel (x, N - 1 - y)"},
        {"atlas",
         {{"mode", atlasModeName(desc.atlas)},
          {"generated", body.parts.generatedAtlas},
          {"charts", body.parts.atlasCharts}}},
        {"deforming", parts.deforming},
        {"material", materialJson(desc.material, parts.maps)},
        {"mass_properties", {{"exact", parts.exact}, {"texture", massJson(*body.mass)}}},
        {"hydrodynamics",
         {{"drag_coefficient", desc.dragCoefficient},
          {"friction_coefficient", desc.frictionCoefficient},
          {"linear_damping", desc.standInLinearDamping(radiates)},
          {"angular_damping", desc.standInAngularDamping(radiates)}}},
        {"radiation", radiationJson(body)},
        {"levels", parts.levels},
        {"world", worldJson(project, desc)},
        {"painted_maps", parts.maps},
        {"gltf", parts.gltfStem + ".gltf"},
        {"water_graph", parts.graph},
        {"sources", parts.sources},
        {"input_sha256", parts.inputHash},
        {"files", parts.files}};
    manifest.update(textureFactsJson(*body.textures));
    // Written only where it differs from linear_damping (a radiating body's default), so that
    // the manifest of every other body stays as it was.
    if (desc.standInVerticalDamping(radiates) != desc.standInLinearDamping(radiates))
        manifest["hydrodynamics"]["vertical_damping"] = desc.standInVerticalDamping(radiates);
    if (parts.compact) {
        // Absent in a float32 bundle (every reader's default). Its channels have other names
        // than the float32 list's, so a reader that knows only that list refuses the file.
        manifest["sample_encoding"] = sampleEncodingJson(*parts.compact);
        manifest["sample_encoding"]["images"] =
            "position.exr, area.exr and coverage.exr hold HALF channels (same meaning); frames/ "
            "stay float32";
    }
    return manifest;
}

/// Writes the whole bundle of body `index` into `staging` (an empty folder): the images and
/// sample lists, the levels, a deforming body's frames, the painted maps, the water graph, the
/// glTF, then the manifest that lists them all.
Result<BundleReport> buildBundle(const Project& project, std::size_t index, const fs::path& staging,
                                 const std::function<void(const std::string&)>& log,
                                 const BundleOptions& options) {
    const BodyDesc& desc = project.bodies.at(index);
    const std::string label = bodyLabel(desc);
    auto say = [&](const std::string& line) {
        if (log) log(line);
    };
    // The body exactly as World simulates it: the same adapter reads and bakes it.
    Result<SceneBody> body = loadSceneBody(project, index, log);
    if (!body) return body.error();
    BundleParts parts;
    // After loading, which writes the atlas cache the hash covers when it is missing.
    Result<std::string> inputHash = bundleInputHash(project, index, options);
    if (!inputHash) return inputHash.error();
    parts.inputHash = *inputHash;
    const SurfaceTextures& textures = *body->textures;
    const std::optional<MassProperties> exactMass =
        exactMassOf(desc.material, *body->parts.mesh, body->parts);
    parts.exact = exactMass ? massJson(*exactMass) : json(nullptr);

    if (options.compact) parts.compact = compactSamplesFor(textures);
    if (Status s = writeBodyImages(textures, staging, desc.mesh, parts.compact); !s.ok())
        return s.error();
    parts.levels = nullptr;
    if (body->levels && body->levels->size() > 1) {
        Result<json> written =
            writeLevels(*body->levels, textures, staging, desc.mesh, options.compact);
        if (!written) return written.error();
        parts.levels = std::move(*written);
        say(label + ": " + std::to_string(body->levels->size()) + " levels exported");
    }
    parts.deforming = nullptr;
    if (desc.deforms()) {
        Result<json> frames = writeDeformingFrames(desc, *body, staging, label);
        if (!frames) return frames.error();
        parts.deforming = std::move(*frames);
        say(label + ": deforming: " + std::to_string(body->parts.frames->size()) +
            " frames exported");
    }

    BundleSources sources{project, label};
    if (Status s = sources.add("mesh", desc.mesh); !s.ok()) return s.error();
    Result<json> maps = writePaintedMaps(desc, *body, staging, sources);
    if (!maps) return maps.error();
    parts.maps = std::move(*maps);
    Result<json> graph = writeWaterGraph(*body, staging, sources);
    if (!graph) return graph.error();
    parts.graph = std::move(*graph);
    parts.sources = std::move(sources.entries);

    parts.gltfStem = bundleFolderName(project, index);
    if (Status s = writeBundleGltf(project, desc, *body, staging, parts.gltfStem, exactMass);
        !s.ok())
        return s.error();

    BundleReport report;
    report.body = desc.name;
    report.textureSize = textures.size;
    if (body->levelChoice) {
        report.tolerance = body->levelChoice->tolerance;
        report.forceError = body->levelChoice->forceError;
    }
    report.coveredTexels = textures.distinctTexelCount();
    Result<json> files = listBundleFiles(staging, report);
    if (!files) return files.error();
    parts.files = std::move(*files);

    const std::string text = manifestJson(project, desc, *body, parts).dump(2) + "\n";
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
        return safeFileName(project.bodies[i].name, "body" + std::to_string(i));
    };
    std::string name = sanitized(index);
    for (std::size_t i = 0; i < index; ++i) {
        if (sanitized(i) == name) return name + "-" + std::to_string(index);
    }
    return name;
}

Result<std::string> bundleInputHash(const Project& project, std::size_t index,
                                    const BundleOptions& options) {
    if (index >= project.bodies.size())
        return makeError(ErrorKind::invalidArgument, "no body " + std::to_string(index));
    const BodyDesc& desc = project.bodies[index];
    Project alone = project;
    alone.bodies = {desc};
    json sources = json::array();
    auto addSource = [&](const std::string& path) -> Status {
        if (path.empty()) return Ok{};
        Result<std::string> sha = sha256OfFile(project.resolvePath(path));
        if (!sha) return withContext(bodyLabel(desc) + ": ", sha.error());
        sources.push_back({{"path", path}, {"sha256", *sha}});
        return Ok{};
    };
    std::vector<std::string> paths{desc.mesh};
    paths.insert(paths.end(), desc.meshFrames.begin(), desc.meshFrames.end());
    paths.push_back(desc.permeabilityMap);
    paths.push_back(desc.material.shellDensityMap);
    paths.push_back(desc.material.shellThicknessMap);
    if (desc.waterGraph) paths.push_back(desc.waterGraph->graph);
    for (const std::string& path : paths)
        if (Status s = addSource(path); !s.ok()) return s.error();
    // A generated atlas comes from the project's atlas cache when that matches the mesh: its
    // bytes decide the bundle's UVs too.
    std::error_code ec;
    const fs::path atlasCache = project.atlasCacheFile(index);
    std::string atlasCacheSha;
    if (fs::is_regular_file(atlasCache, ec)) {
        Result<std::string> sha = sha256OfFile(atlasCache);
        if (!sha) return withContext(bodyLabel(desc) + ": ", sha.error());
        atlasCacheSha = *sha;
    }
    json inputs = {{"generator", std::string("plimsoll ") + PLIMSOLL_VERSION},
                   {"bundle_schema", {kBundleSchemaMajor, kBundleSchemaMinor}},
                   {"body_index", index},
                   {"folder", bundleFolderName(project, index)},
                   {"project", json::parse(projectToJson(alone))},
                   {"sources", sources},
                   {"atlas_cache", atlasCacheSha}};
    // Only when set, so a float32 bundle's hash is what it was before the option existed.
    if (options.compact) inputs["sample_encoding"] = plimsoll_eval::kCompactSampleEncoding;
    return sha256Hex(inputs.dump());
}

std::optional<BundleReport> unchangedBodyBundle(const Project& project, std::size_t index,
                                                const fs::path& folder,
                                                const BundleOptions& options) {
    Result<std::string> hash = bundleInputHash(project, index, options);
    if (!hash) return std::nullopt;  // the export itself reports the unreadable source
    Result<BundleManifestInfo> info = verifyBundle(folder);
    if (!info) return std::nullopt;
    Result<std::string> text = readBytes(folder / kManifestFile);
    if (!text) return std::nullopt;
    BundleReport report;
    if (!checkJsonDepth(*text, kManifestFile).ok()) return std::nullopt;
    try {
        const json manifest = json::parse(*text);
        if (manifest.value("input_sha256", std::string()) != *hash) return std::nullopt;
        report.textureSize = manifest.at("texture_size").get<int>();
        report.coveredTexels = manifest.at("covered_texels").get<std::size_t>();
    } catch (const std::exception&) {
        return std::nullopt;
    }
    report.body = project.bodies[index].name;
    report.folder = folder;
    report.files = std::move(info->files);
    report.files.push_back({kManifestFile, sha256Hex(*text), text->size()});
    report.unchanged = true;
    return report;
}

Result<BundleReport> writeBodyBundle(const Project& project, std::size_t index,
                                     const fs::path& folder,
                                     const std::function<void(const std::string&)>& log,
                                     const BundleOptions& options) {
    if (index >= project.bodies.size())
        return makeError(ErrorKind::invalidArgument, "no body " + std::to_string(index));
    const fs::path target = folder.filename().empty() ? folder.parent_path() : folder;
    std::error_code ec;
    if (!target.parent_path().empty()) fs::create_directories(target.parent_path(), ec);
    if (ec)
        return makeError(ErrorKind::io,
                         target.parent_path().string() + ": cannot create folder: " + ec.message());
    if (Status restored = restoreInterruptedFolderSwap(target); !restored.ok())
        return restored.error();
    const fs::path staging = siblingFor(target, "tmp");
    fs::remove_all(staging, ec);
    fs::create_directories(staging, ec);
    if (ec)
        return makeError(ErrorKind::io,
                         staging.string() + ": cannot create folder: " + ec.message());
    Result<BundleReport> report = buildBundle(project, index, staging, log, options);
    if (!report) {
        fs::remove_all(staging, ec);
        return report.error();
    }
    if (Status placed = replaceFolder(staging, target, siblingFor(target, "old")); !placed.ok()) {
        fs::remove_all(staging, ec);
        return placed.error();
    }
    report->folder = target;
    return report;
}

namespace {

/// What the runtime's manifest reader (the one games load with) returned, in the engine's
/// types. Its messages name the file and the problem; it gives no kind, so every refusal is a
/// format error.
Result<BundleManifestInfo> manifestInfo(bool ok, const plimsoll_runtime::BundleManifest& manifest,
                                        const std::string& error) {
    if (!ok) return makeError(ErrorKind::format, error);
    BundleManifestInfo info;
    info.schemaMajor = manifest.schemaMajor;
    info.schemaMinor = manifest.schemaMinor;
    info.body = manifest.body;
    for (const plimsoll_runtime::BundleManifest::File& f : manifest.files)
        info.files.push_back({f.path, f.sha256, f.bytes});
    return info;
}

}  // namespace

Result<BundleManifestInfo> parseBundleManifest(const std::string& text, const std::string& source) {
    plimsoll_runtime::BundleManifest manifest;
    std::string error;
    const bool ok = plimsoll_runtime::parseBundleManifest(text, source, manifest, error);
    return manifestInfo(ok, manifest, error);
}

Result<BundleManifestInfo> verifyBundle(const fs::path& folder) {
    plimsoll_runtime::BundleManifest manifest;
    std::string error;
    const bool ok = plimsoll_runtime::readBundleManifest(folder.string(), manifest, error);
    return manifestInfo(ok, manifest, error);
}

Result<BundleReport> checkBodyBundle(const Project& project, std::size_t index,
                                     const fs::path& folder, const BundleOptions& options) {
    if (index >= project.bodies.size())
        return makeError(ErrorKind::invalidArgument, "no body " + std::to_string(index));
    const fs::path target = folder.filename().empty() ? folder.parent_path() : folder;
    // Built beside the temporary directory's other files, not in the bundle's folder, which
    // a check must not touch.
    // mkdtemp: a new folder of a random name, created exclusively, so nothing planted in the
    // temporary directory (a link named like it) is written through.
    std::error_code ec;
    std::string pattern = (fs::temp_directory_path(ec) / "plimsoll-check-XXXXXX").string();
    if (::mkdtemp(pattern.data()) == nullptr)
        return makeError(ErrorKind::io,
                         pattern + ": cannot create folder: " + std::strerror(errno));
    const fs::path staging = pattern;
    Result<BundleReport> report = buildBundle(project, index, staging, {}, options);
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
                                         : Result<std::string>(makeError(ErrorKind::io, "missing"));
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
