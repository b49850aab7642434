// Runtime bundle export (bundle.h, plimsoll export): byte-identical repeats, checksums that
// sha256sum confirms, --check naming a changed painted map or graph, a failed export leaving
// the previous bundle as it was, and the EXR files read back by OpenEXR's own exrheader.
#include "cli_runner.h"
#include "test_support.h"
#include "world_support.h"

#include "io/exr_io.h"
#include "plimsoll/io/bake_io.h"
#include "plimsoll/io/painted_map_io.h"
#include "plimsoll/io/graph_json.h"
#include "plimsoll/export/bundle.h"
#include "plimsoll/graph/graph.h"
#include "plimsoll/physics/massprops.h"
#include "plimsoll/io/mesh_io.h"
#include "plimsoll/surface/painted_map.h"
#include "plimsoll/project/scene_loader.h"
#include "plimsoll/scene/level_ladder.h"
#include "plimsoll/scene/world.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <array>
#include <cctype>
#include <cstdio>
#include <algorithm>
#include <map>
#include <sys/stat.h>

namespace plimsoll {
namespace test_export {
namespace {

namespace fs = std::filesystem;
using test::readFile;
using test::runPlimsoll;

/// Output of a shell command (stdout), or nothing when it could not run.
std::string shell(const std::string& command, int* exitCode = nullptr) {
    std::string out;
    FILE* pipe = ::popen(command.c_str(), "r");
    if (!pipe) return out;
    std::array<char, 4096> buffer;
    while (std::size_t n = std::fread(buffer.data(), 1, buffer.size(), pipe))
        out.append(buffer.data(), n);
    const int status = ::pclose(pipe);
    if (exitCode) *exitCode = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    return out;
}

bool haveTool(const std::string& name) {
    int rc = 1;
    shell("command -v " + name + " >/dev/null 2>&1", &rc);
    return rc == 0;
}

/// A private copy of a sample project with the files it names, laid out as in the repository
/// (projects/ and assets/), so tests can change its sources and its atlas cache stays here.
fs::path copyProject(const std::string& test, const std::string& stem) {
    const fs::path root = test::scratchFolder("export_" + test);
    fs::remove_all(root);
    fs::create_directories(root / "projects");
    const fs::path source = fs::path(PLIMSOLL_SOURCE_DIR);
    fs::copy(source / "assets", root / "assets", fs::copy_options::recursive);
    fs::copy(source / "projects" / "maps", root / "projects" / "maps", fs::copy_options::recursive);
    for (const char* file : {"boat.graph.json", "plush.graph.json"})
        fs::copy_file(source / "projects" / file, root / "projects" / file);
    fs::copy_file(source / "projects" / (stem + ".plim.json"),
                  root / "projects" / (stem + ".plim.json"));
    return root;
}

/// Relative path -> content of every regular file under `folder`.
std::map<std::string, std::string> contents(const fs::path& folder) {
    std::map<std::string, std::string> files;
    for (const auto& entry : fs::recursive_directory_iterator(folder)) {
        if (entry.is_regular_file())
            files[fs::relative(entry.path(), folder).generic_string()] = readFile(entry.path());
    }
    return files;
}

std::string quoted(const fs::path& path) { return "'" + path.string() + "'"; }

TEST(Export, FolderNamesAreSanitizedAndUnique) {
    Project project;
    project.bodies.resize(4);
    project.bodies[0].name = "boat hull";
    project.bodies[1].name = "boat/hull";
    project.bodies[2].name = "";
    project.bodies[3].name = "..";
    EXPECT_EQ(bundleFolderName(project, 0), "boat_hull");
    EXPECT_EQ(bundleFolderName(project, 1), "boat_hull-1");
    EXPECT_EQ(bundleFolderName(project, 2), "body2");
    EXPECT_EQ(bundleFolderName(project, 3), "body3..");
}

TEST(Export, Sha256MatchesKnownDigests) {
    // FIPS 180-2 examples.
    EXPECT_EQ(sha256Hex(""), "e3b0c44298fc1c149afbf4c8996fb92427ae41e4649b934ca495991b7852b855");
    EXPECT_EQ(sha256Hex("abc"), "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad");
}

TEST(ExportCli, HelpAndUsage) {
    const test::CommandOutput help = runPlimsoll("export --help");
    EXPECT_EQ(help.exitCode, 0);
    EXPECT_NE(help.out.find("--check"), std::string::npos) << help.out;
    const test::CommandOutput noOut = runPlimsoll(
        "export " + (fs::path(PLIMSOLL_SOURCE_DIR) / "projects" / "buoy.plim.json").string());
    EXPECT_NE(noOut.exitCode, 0);
    EXPECT_NE(noOut.err.find("--out"), std::string::npos) << noOut.err;
}

// The bundle bakes what World bakes (the same UVs, the same samples) and holds its mass.
TEST(Export, BundleHoldsWhatWorldSimulates) {
    for (const std::string stem : {"buoy", "damaged_boat", "box_half_draft"}) {
        SCOPED_TRACE(stem);
        const fs::path root = copyProject("world_" + stem, stem);
        if (stem == "box_half_draft") {
            // A generated atlas: both go through the project's atlas cache with one setting.
            const fs::path path = root / "projects" / (stem + ".plim.json");
            std::string text = readFile(path);
            const std::string key = "\"texture_size\": 128,";
            ASSERT_NE(text.find(key), std::string::npos);
            text.replace(text.find(key), key.size(), key + " \"atlas\": \"generate\",");
            std::ofstream(path) << text;
        }
        Result<Project> project = loadProject(root / "projects" / (stem + ".plim.json"));
        ASSERT_TRUE(project.ok()) << project.error().message;
        const fs::path folder = root / "out" / bundleFolderName(*project, 0);
        Result<BundleReport> report = writeBodyBundle(*project, 0, folder);
        ASSERT_TRUE(report.ok()) << report.error().message;
        Result<std::unique_ptr<World>> world =
            World::create(test::sceneOrFail(*project), createReferenceBackend(), {});
        ASSERT_TRUE(world.ok()) << world.error().message;
        const SimulatedBody& body = (*world)->bodies().at(0);
        const nlohmann::json manifest = nlohmann::json::parse(readFile(folder / "manifest.json"));
        EXPECT_EQ(manifest["atlas"]["generated"].get<bool>(), stem == "box_half_draft");
        EXPECT_EQ(manifest.at("texel_samples").get<std::size_t>(), body.textures.coveredCount());
        EXPECT_EQ(report->coveredTexels, body.textures.distinctTexelCount());
        const nlohmann::json& mass = manifest["mass_properties"]["texture"];
        if (stem != "damaged_boat") {  // sealed: World's mass is the body's own
            EXPECT_DOUBLE_EQ(mass["mass"].get<double>(), body.mass.mass);
            for (int k = 0; k < 3; ++k)
                EXPECT_DOUBLE_EQ(mass["center_of_mass"][k].get<double>(),
                                 body.mass.centerOfMass[k]);
        }
        if (stem == "buoy") {
            EXPECT_TRUE(manifest["mass_properties"]["exact"].is_null());  // painted shell
            EXPECT_EQ(manifest["material"]["shell_density_map"], "shell_density.png");
        }
        EXPECT_DOUBLE_EQ(mass["volume"].get<double>(), body.volume);
        Result<SurfaceTextures> samples = readBakedTextures(folder);
        ASSERT_TRUE(samples.ok()) << samples.error().message;
        ASSERT_EQ(samples->texelIndex, body.textures.texelIndex);
        for (std::size_t i = 0; i < body.textures.coveredCount(); i += 97) {
            EXPECT_NEAR(samples->position[i].x(), body.textures.position[i].x(), 1e-6);
            EXPECT_NEAR(samples->area[i], body.textures.area[i],
                        1e-6 * body.textures.area[i] + 1e-12);
        }
    }
}

// levels (schema 1.6): a body with a level ladder ships each coarser level's own bake as a
// sample list beside samples.exr, with its stated errors; compact, each level is half floats
// over its own encoding and a small file.
TEST(Export, LevelLadderShipsEachLevelsOwnSampleList) {
    const fs::path root = copyProject("levels", "box_half_draft");
    Result<Project> project = loadProject(root / "projects" / "box_half_draft.plim.json");
    ASSERT_TRUE(project.ok()) << project.error().message;
    project->bodies[0].lod = LodDesc{{16, 32}};
    Result<SceneBody> body = loadSceneBody(*project, 0, {});
    ASSERT_TRUE(body.ok()) << body.error().message;
    ASSERT_TRUE(body->levels);
    const std::vector<BuoyancyLevel>& ladder = *body->levels;
    ASSERT_EQ(ladder.size(), 3u);
    Result<TriangleMesh> mesh = loadMesh(project->resolvePath(project->bodies[0].mesh));
    ASSERT_TRUE(mesh.ok()) << mesh.error().message;
    const double exactVolume = exactSolidMassProperties(*mesh, 1.0).volume;
    for (const bool compact : {false, true}) {
        SCOPED_TRACE(compact ? "compact" : "float32");
        const fs::path folder = root / (compact ? "compact" : "float32");
        BundleOptions options;
        options.compact = compact;
        Result<BundleReport> report = writeBodyBundle(*project, 0, folder, {}, options);
        ASSERT_TRUE(report.ok()) << report.error().message;
        ASSERT_TRUE(verifyBundle(folder).ok());
        const nlohmann::json manifest = nlohmann::json::parse(readFile(folder / "manifest.json"));
        EXPECT_EQ(manifest.at("schema_minor"), 6);
        const nlohmann::json& levels = manifest.at("levels");
        ASSERT_EQ(levels.size(), 3u);
        const std::uintmax_t finestBytes = fs::file_size(folder / "samples.exr");
        for (std::size_t k = 0; k < 3; ++k) {
            SCOPED_TRACE(k);
            const nlohmann::json& level = levels[k];
            const SurfaceTextures& t = *ladder[k].textures;
            EXPECT_EQ(level.at("size").get<int>(), ladder[k].size);
            EXPECT_EQ(level.at("texel_samples").get<std::size_t>(), t.coveredCount());
            EXPECT_EQ(level.at("force_error").get<double>(), ladder[k].forceError);
            EXPECT_EQ(level.at("torque_error").get<double>(), ladder[k].torqueError);
            EXPECT_GT(level.at("evaluation_us").get<double>(), 0.0);
            const std::string path = level.at("samples").get<std::string>();
            if (k == 2) {
                EXPECT_EQ(path, "samples.exr");
                EXPECT_FALSE(level.contains("sample_encoding"));
                continue;
            }
            EXPECT_EQ(path, "levels/" + std::to_string(ladder[k].size) + "/samples.exr");
            EXPECT_EQ(level.at("sample_encoding").is_null(), !compact);
            // Only the sample list: the images a bake writes beside it stay out.
            EXPECT_EQ(contents(folder / "levels" / std::to_string(ladder[k].size)).size(), 1u);
            EXPECT_LT(fs::file_size(folder / path), finestBytes / 2);
            // The level's sample list is its own closed surface: V = sum A_y y (float32 points;
            // half floats about the encoding's origin in a compact bundle).
            const std::vector<std::string> channels = compact
                                                          ? std::vector<std::string>{"hpy", "hay"}
                                                          : std::vector<std::string>{"py", "ay"};
            Result<detail::FloatImage> list = detail::readExr(folder / path, channels);
            ASSERT_TRUE(list.ok()) << list.error().message;
            const double positionScale =
                compact ? level["sample_encoding"]["position_scale"].get<double>() : 1.0;
            const double areaScale =
                compact ? level["sample_encoding"]["area_scale"].get<double>() : 1.0;
            double volume = 0;
            for (std::size_t i = 0; i < t.coveredCount(); ++i)
                volume += areaScale * list->pixels[2 * i + 1] * positionScale * list->pixels[2 * i];
            EXPECT_NEAR(volume, exactVolume, (compact ? 2e-3 : 1e-5) * exactVolume);
        }
    }
}

// texel_nodes.exr (schema 1.1): every covered texel holds 1 + the node nearestNode gives for
// its surface (WaterGraphSimulation's rule), uncovered texels 0; OpenEXR reads it back as UINT.
TEST(Export, TexelNodeMapHoldsTheNearestNodeOfEveryCoveredTexel) {
    std::size_t shared = 0;  // texels with several entries, over all cases
    for (const std::string name : {"damaged_boat", "plush", "refined"}) {
        SCOPED_TRACE(name);
        // "refined": the boat cut into sub-texel cells wherever a texel stretches more than
        // 1.2 times the typical one, so that many texels hold several entries.
        const std::string stem = name == "refined" ? "damaged_boat" : name;
        const fs::path root = copyProject("texel_nodes_" + name, stem);
        if (name == "refined") {
            const fs::path path = root / "projects" / (stem + ".plim.json");
            std::string text = readFile(path);
            const std::string key = "\"texture_size\": 128,";
            ASSERT_NE(text.find(key), std::string::npos);
            text.replace(text.find(key), key.size(), key + " \"max_texel_stretch\": 1.2,");
            std::ofstream(path) << text;
        }
        Result<Project> project = loadProject(root / "projects" / (stem + ".plim.json"));
        ASSERT_TRUE(project.ok()) << project.error().message;
        const fs::path folder = root / "out" / bundleFolderName(*project, 0);
        ASSERT_TRUE(writeBodyBundle(*project, 0, folder).ok());
        Result<std::unique_ptr<World>> world =
            World::create(test::sceneOrFail(*project), createReferenceBackend(), {});
        ASSERT_TRUE(world.ok()) << world.error().message;
        const SurfaceTextures& t = (*world)->bodies().at(0).textures;
        Result<WaterGraph> graph =
            loadGraph(project->resolvePath(project->bodies[0].waterGraph->graph));
        ASSERT_TRUE(graph.ok()) << graph.error().message;
        ASSERT_GE(graph->nodes.size(), 2u);

        Result<detail::UintImage> map = detail::readExrUint(folder / "texel_nodes.exr", "node");
        ASSERT_TRUE(map.ok()) << map.error().message;
        ASSERT_EQ(map->width, t.size);
        ASSERT_EQ(map->height, t.size);
        // Covered where position.exr's alpha says so, and nowhere else.
        Result<detail::FloatImage> position = detail::readExr(folder / "position.exr", {"A"});
        ASSERT_TRUE(position.ok()) << position.error().message;
        std::size_t nonzero = 0;
        for (std::size_t p = 0; p < map->pixels.size(); ++p) {
            ASSERT_EQ(map->pixels[p] != 0, position->pixels[p] == 1.0f) << p;
            ASSERT_LE(map->pixels[p], graph->nodes.size()) << p;
            nonzero += map->pixels[p] != 0;
        }
        EXPECT_EQ(nonzero, t.distinctTexelCount());
        // Each texel's node is its nearest: the entry's own for a texel with one entry, the
        // largest entry's where islands share the texel. Every node feeds some texels.
        std::vector<std::size_t> fed(graph->nodes.size(), 0);
        for (std::size_t first = 0, last; first < t.coveredCount(); first = last) {
            std::size_t largest = first;
            for (last = first; last < t.coveredCount() && t.texelIndex[last] == t.texelIndex[first];
                 ++last)
                if (t.area[last] > t.area[largest]) largest = last;
            shared += last - first > 1;
            const std::size_t x = t.texelIndex[first] % t.size, y = t.texelIndex[first] / t.size;
            const std::uint32_t value = map->pixels[(t.size - 1 - y) * t.size + x];
            ASSERT_EQ(value,
                      static_cast<std::uint32_t>(nearestNode(*graph, t.position[largest]) + 1))
                << "texel " << x << ", " << y;
            ++fed[value - 1];
        }
        for (std::size_t n = 0; n < fed.size(); ++n) EXPECT_GT(fed[n], 0u) << "node " << n;

        const nlohmann::json manifest = nlohmann::json::parse(readFile(folder / "manifest.json"));
        EXPECT_EQ(manifest["water_graph"]["texel_nodes"], "texel_nodes.exr");
        EXPECT_EQ(manifest["schema_minor"], kBundleSchemaMinor);
        bool listed = false;
        for (const auto& f : manifest["files"])
            if (f["path"] == "texel_nodes.exr") {
                listed = true;
                EXPECT_EQ(f["sha256"], sha256Hex(readFile(folder / "texel_nodes.exr")));
            }
        EXPECT_TRUE(listed);

        if (haveTool("exrheader")) {
            int rc = 1;
            const std::string header =
                shell("exrheader " + quoted(folder / "texel_nodes.exr") + " 2>&1", &rc);
            EXPECT_EQ(rc, 0) << header;
            EXPECT_NE(header.find("node, 32-bit unsigned integer"), std::string::npos) << header;
            const std::string last = std::to_string(t.size - 1);
            EXPECT_NE(header.find("(0 0) - (" + last + " " + last + ")"), std::string::npos)
                << header;
        }
    }
    // The refined boat's texels hold several entries: the largest-entry rule is exercised.
    EXPECT_GT(shared, 0u);
}

TEST(ExportCli, DamagedBoatBundleIsCompleteDeterministicAndChecksummed) {
    const fs::path root = copyProject("boat", "damaged_boat");
    const fs::path project = root / "projects" / "damaged_boat.plim.json";
    const fs::path outA = root / "outA", outB = root / "outB";
    const test::CommandOutput a =
        runPlimsoll("export " + quoted(project) + " --out " + quoted(outA) + " --summary " +
                    quoted(root / "summary.json"));
    ASSERT_EQ(a.exitCode, 0) << a.err;
    const test::CommandOutput b =
        runPlimsoll("export " + quoted(project) + " --out " + quoted(outB) + " --quiet");
    ASSERT_EQ(b.exitCode, 0) << b.err;
    EXPECT_TRUE(b.err.empty()) << b.err;

    const fs::path bundle = outA / "damaged_boat" / "boat";
    const auto first = contents(bundle);
    std::vector<std::string> names;
    for (const auto& [name, bytes] : first) names.push_back(name);
    EXPECT_EQ(names, (std::vector<std::string>{"area.exr", "boat.bin", "boat.gltf", "coverage.exr",
                                               "graph.json", "manifest.json", "permeability.png",
                                               "position.exr", "samples.exr", "texel_nodes.exr"}));
    // Two exports into different folders, and a third over the first: byte-identical.
    EXPECT_EQ(contents(outB / "damaged_boat" / "boat"), first);
    ASSERT_EQ(
        runPlimsoll("export " + quoted(project) + " --out " + quoted(outA) + " --quiet").exitCode,
        0);
    EXPECT_EQ(contents(bundle), first);
    // Nothing left beside the bundle (temporary or old folders).
    std::vector<std::string> siblings;
    for (const auto& e : fs::directory_iterator(outA / "damaged_boat"))
        siblings.push_back(e.path().filename());
    EXPECT_EQ(siblings, std::vector<std::string>{"boat"});

    // The summary: stdout and --summary agree; every body written.
    const nlohmann::json summary = nlohmann::json::parse(a.out);
    EXPECT_EQ(nlohmann::json::parse(readFile(root / "summary.json")), summary);
    EXPECT_TRUE(summary.at("ok").get<bool>());
    ASSERT_EQ(summary.at("bodies").size(), 1u);
    EXPECT_EQ(summary["bodies"][0]["status"], "written");
    EXPECT_EQ(summary["bodies"][0]["folder"], bundle.generic_string());

    // The manifest lists every other file with a SHA-256 that sha256sum confirms.
    const nlohmann::json manifest = nlohmann::json::parse(first.at("manifest.json"));
    EXPECT_EQ(manifest.at("schema_version"), kBundleSchemaMajor);
    EXPECT_EQ(manifest.at("schema_minor"), kBundleSchemaMinor);
    EXPECT_EQ(manifest.at("texture_size"), 128);
    EXPECT_EQ(manifest.at("units").at("length"), "m");
    EXPECT_EQ(manifest.at("axes").at("up"), "+y");
    EXPECT_EQ(manifest.at("material").at("model"), "shell");
    EXPECT_EQ(manifest.at("atlas").at("mode"), "auto");
    EXPECT_EQ(manifest.at("water_graph").at("path"), "graph.json");
    EXPECT_GT(manifest.at("covered_texels").get<int>(), 1000);
    const double textureMass = manifest["mass_properties"]["texture"]["mass"];
    const double exactMass = manifest["mass_properties"]["exact"]["mass"];
    EXPECT_NEAR(textureMass, exactMass, 1e-3 * exactMass);
    ASSERT_EQ(manifest.at("files").size(), first.size() - 1);
    for (const auto& f : manifest.at("files")) {
        const std::string path = f.at("path");
        ASSERT_TRUE(first.count(path)) << path;
        EXPECT_EQ(f.at("bytes").get<std::size_t>(), first.at(path).size()) << path;
        if (haveTool("sha256sum")) {
            const std::string line = shell("sha256sum " + quoted(bundle / path));
            EXPECT_EQ(line.substr(0, 64), f.at("sha256").get<std::string>()) << path;
        }
    }
    EXPECT_EQ(summary["bodies"][0]["files"].back()["sha256"], sha256Hex(first.at("manifest.json")));

    // The bundle's sample list reads back through the bake reader (float32).
    Result<SurfaceTextures> samples = readBakedTextures(bundle);
    ASSERT_TRUE(samples.ok()) << samples.error().message;
    EXPECT_EQ(samples->coveredCount(), manifest.at("texel_samples").get<std::size_t>());
    EXPECT_EQ(samples->distinctTexelCount(), manifest.at("covered_texels").get<std::size_t>());

    // The painted map: 16-bit greyscale PNG as another decoder (file(1)) reads the header, and
    // the values it holds equal the source map's after 16-bit rounding.
    if (haveTool("file")) {
        const std::string described = shell("file -b " + quoted(bundle / "permeability.png"));
        EXPECT_NE(described.find("PNG image data"), std::string::npos) << described;
        EXPECT_NE(described.find("16-bit grayscale"), std::string::npos) << described;
    }
    Result<PaintedMap> exported = loadPaintedMap(bundle / "permeability.png");
    Result<PaintedMap> source = loadPaintedMap(root / "assets" / "hull_stern_damage.png");
    ASSERT_TRUE(exported.ok() && source.ok());
    ASSERT_EQ(exported->values.size(), source->values.size());
    for (std::size_t i = 0; i < source->values.size(); ++i)
        ASSERT_NEAR(exported->values[i], source->values[i], 0.5 / 65535.0 + 1e-7) << i;
}

TEST(Export, VerifyAcceptsABundleAndNamesWhatIsWrongWithABadOne) {
    const fs::path root = copyProject("verify", "box_half_draft");
    Result<Project> project = loadProject(root / "projects" / "box_half_draft.plim.json");
    ASSERT_TRUE(project.ok()) << project.error().message;
    const fs::path good = root / "good";
    ASSERT_TRUE(writeBodyBundle(*project, 0, good).ok());
    Result<BundleManifestInfo> info = verifyBundle(good);
    ASSERT_TRUE(info.ok()) << info.error().message;
    EXPECT_EQ(info->schemaMajor, kBundleSchemaMajor);
    EXPECT_EQ(info->body, "box");
    EXPECT_EQ(info->files.size(), 6u);  // 4 EXR, box.gltf, box.bin

    auto broken = [&](const std::string& name, const std::function<void(const fs::path&)>& spoil) {
        const fs::path folder = root / name;
        fs::remove_all(folder);
        fs::copy(good, folder, fs::copy_options::recursive);
        spoil(folder);
        Result<BundleManifestInfo> r = verifyBundle(folder);
        EXPECT_FALSE(r.ok()) << name;
        return r.ok() ? std::string() : r.error().message;
    };
    EXPECT_NE(broken("missing", [](const fs::path& f) { fs::remove(f / "area.exr"); })
                  .find("area.exr: missing"),
              std::string::npos);
    EXPECT_NE(
        broken("truncated", [](const fs::path& f) { fs::resize_file(f / "position.exr", 100); })
            .find("position.exr: 100 bytes, the manifest says"),
        std::string::npos);
    EXPECT_NE(broken("changed",
                     [](const fs::path& f) {
                         std::string bytes = readFile(f / "samples.exr");
                         bytes[bytes.size() / 2] ^= 1;
                         std::ofstream(f / "samples.exr", std::ios::binary) << bytes;
                     })
                  .find("samples.exr: SHA-256"),
              std::string::npos);
    auto withManifest = [](const std::function<void(nlohmann::json&)>& edit) {
        return [edit](const fs::path& f) {
            nlohmann::json m = nlohmann::json::parse(readFile(f / "manifest.json"));
            edit(m);
            std::ofstream(f / "manifest.json") << m.dump(2);
        };
    };
    EXPECT_NE(broken("newer_major", withManifest([](nlohmann::json& m) {
                         m["schema_version"] = 2;
                         m["schema_minor"] = 0;
                     }))
                  .find("bundle schema 2.0 is newer than this reader's 1.x"),
              std::string::npos);
    // A newer minor only adds: accepted.
    {
        const fs::path folder = root / "newer_minor";
        fs::copy(good, folder, fs::copy_options::recursive);
        withManifest([](nlohmann::json& m) {
            m["schema_minor"] = 7;
            m["a_later_field"] = true;
        })(folder);
        Result<BundleManifestInfo> r = verifyBundle(folder);
        ASSERT_TRUE(r.ok()) << r.error().message;
        EXPECT_EQ(r->schemaMinor, 7);
    }
    EXPECT_NE(
        broken("escape", withManifest([](nlohmann::json& m) { m["files"][0]["path"] = "../x"; }))
            .find("$.files[0].path: file path \"../x\" leaves the bundle"),
        std::string::npos);
    EXPECT_NE(
        broken("not_json", [](const fs::path& f) { std::ofstream(f / "manifest.json") << "{"; })
            .find("malformed manifest"),
        std::string::npos);
    // Nested past the limit: refused where the parser reaches the limit, the manifest named.
    const std::string deep = broken("deep", [](const fs::path& f) {
        std::ofstream(f / "manifest.json")
            << "{\"format\": " + std::string(200000, '[') + std::string(200000, ']') + "}";
    });
    EXPECT_NE(deep.find("manifest.json: malformed manifest: "), std::string::npos) << deep;
    EXPECT_NE(deep.find("nested more than 128 deep, more than the limit kMaxJsonDepth"),
              std::string::npos)
        << deep;
    // A file listed again (or spelled again) would be read and hashed once per listing.
    const std::string repeated = broken("repeated", withManifest([](nlohmann::json& m) {
                                            for (int i = 0; i < 2000; ++i)
                                                m["files"].push_back(m["files"][1]);
                                        }));
    EXPECT_NE(repeated.find("manifest.json: $.files[6].path: \"" + info->files[1].path +
                            "\" is listed twice (also $.files[1])"),
              std::string::npos)
        << repeated;
    EXPECT_NE(broken("respelled", withManifest([](nlohmann::json& m) {
                         nlohmann::json again = m["files"][0];
                         again["path"] = "./" + again["path"].get<std::string>();
                         m["files"].push_back(again);
                     }))
                  .find("is listed twice (also $.files[0])"),
              std::string::npos);
}

// Versions: this reader (1.6) reads 1.0 to 1.6 bundles and refuses 2.0 naming both versions.
TEST(Export, VerifyAcceptsCurrentAndPreviousMinorsAndRefusesANewerMajor) {
    ASSERT_EQ(kBundleSchemaMajor, 1);
    ASSERT_EQ(kBundleSchemaMinor, 6);
    const fs::path root = copyProject("versions", "box_half_draft");
    Result<Project> project = loadProject(root / "projects" / "box_half_draft.plim.json");
    ASSERT_TRUE(project.ok()) << project.error().message;
    const fs::path good = root / "good";
    ASSERT_TRUE(writeBodyBundle(*project, 0, good).ok());
    for (const auto& [major, minor] :
         {std::pair{1, 0}, std::pair{1, 1}, std::pair{1, 2}, std::pair{1, 3}, std::pair{1, 4},
          std::pair{1, 5}, std::pair{1, 6}, std::pair{2, 0}}) {
        const fs::path folder = root / ("v" + std::to_string(major) + "." + std::to_string(minor));
        fs::copy(good, folder, fs::copy_options::recursive);
        nlohmann::json m = nlohmann::json::parse(readFile(folder / "manifest.json"));
        m["schema_version"] = major;
        m["schema_minor"] = minor;
        if (minor == 0) m.erase("gltf");      // 1.0 had no glTF
        if (minor < 3) m.erase("radiation");  // nor did 1.2 radiation
        if (minor < 4)
            m.erase("world");  // nor did 1.3 the world
        else if (minor < 5)
            m["world"]["simulation"].erase("sleep");  // nor 1.4 sleeping
        if (minor < 6) m.erase("levels");             // nor 1.5 levels
        std::ofstream(folder / "manifest.json") << m.dump(2);
        Result<BundleManifestInfo> r = verifyBundle(folder);
        if (major == 1) {
            ASSERT_TRUE(r.ok()) << r.error().message;
            EXPECT_EQ(r->schemaMinor, minor);
        } else {
            ASSERT_FALSE(r.ok());
            EXPECT_NE(r.error().message.find("bundle schema 2.0 is newer than this reader's 1.x"),
                      std::string::npos)
                << r.error().message;
            EXPECT_NE(r.error().message.find((folder / "manifest.json").string()),
                      std::string::npos);
        }
    }
}

/// Cuts `file` of a bundle in half and rewrites the manifest's size and SHA-256 for it, so that
/// only an EXR decoder can tell.
void truncateKeepingManifestConsistent(const fs::path& bundle, const std::string& file) {
    fs::resize_file(bundle / file, fs::file_size(bundle / file) / 2);
    nlohmann::json m = nlohmann::json::parse(readFile(bundle / "manifest.json"));
    for (auto& f : m["files"]) {
        if (f["path"] != file) continue;
        const std::string bytes = readFile(bundle / file);
        f["bytes"] = bytes.size();
        f["sha256"] = sha256Hex(bytes);
    }
    std::ofstream(bundle / "manifest.json") << m.dump(2);
}

// A truncated EXR that the manifest vouches for: the readers fail with the file's name, no
// crash (and the sanitizer build runs this too).
TEST(Export, TruncatedExrGivesAnErrorNamingTheFile) {
    const fs::path root = copyProject("truncated", "damaged_boat");
    Result<Project> project = loadProject(root / "projects" / "damaged_boat.plim.json");
    ASSERT_TRUE(project.ok()) << project.error().message;
    const fs::path good = root / "good";
    ASSERT_TRUE(writeBodyBundle(*project, 0, good).ok());
    ASSERT_TRUE(readBakedTextures(good).ok());

    for (const std::string file : {"samples.exr", "position.exr", "area.exr", "texel_nodes.exr"}) {
        SCOPED_TRACE(file);
        const fs::path bundle = root / ("cut_" + file);
        fs::copy(good, bundle, fs::copy_options::recursive);
        truncateKeepingManifestConsistent(bundle, file);
        ASSERT_TRUE(verifyBundle(bundle).ok());  // sizes and checksums agree: only decoding fails
        std::string message;
        if (file == "samples.exr") {
            Result<SurfaceTextures> r = readBakedTextures(bundle);
            ASSERT_FALSE(r.ok());
            message = r.error().message;
        } else if (file == "texel_nodes.exr") {
            Result<detail::UintImage> r = detail::readExrUint(bundle / file, "node");
            ASSERT_FALSE(r.ok());
            message = r.error().message;
        } else {
            Result<detail::FloatImage> r = detail::readExr(bundle / file, {"R", "G", "B", "A"});
            ASSERT_FALSE(r.ok());
            message = r.error().message;
        }
        EXPECT_NE(message.find((bundle / file).string()), std::string::npos) << message;
        EXPECT_NE(message.find("cannot read EXR"), std::string::npos) << message;
    }
}

// A deforming body (the balloon, 24 frames): every frame's textures in frames/NNN/, regathered
// from the bake; each frame's sample list encloses that frame mesh's exact volume, and the
// manifest's per-frame mass properties say the same.
TEST(Export, DeformingBodyExportsEveryFrame) {
    const fs::path root = test::scratchFolder("export_deforming");
    Result<Project> project =
        loadProject(fs::path(PLIMSOLL_SOURCE_DIR) / "projects" / "balloon.plim.json");
    ASSERT_TRUE(project.ok()) << project.error().message;
    const BodyDesc& desc = project->bodies.at(0);
    ASSERT_TRUE(desc.deforms());
    const fs::path folder = root / "balloon";
    std::vector<std::string> notices;
    Result<BundleReport> report = writeBodyBundle(
        *project, 0, folder, [&](const std::string& line) { notices.push_back(line); });
    ASSERT_TRUE(report.ok()) << report.error().message;
    ASSERT_TRUE(verifyBundle(folder).ok());
    const nlohmann::json manifest = nlohmann::json::parse(readFile(folder / "manifest.json"));
    const nlohmann::json& deforming = manifest.at("deforming");
    const std::size_t frames = desc.meshFrames.size() + 1;
    EXPECT_EQ(deforming.at("frames").get<std::size_t>(), frames);
    EXPECT_EQ(deforming.at("exported"), "all frames");
    EXPECT_DOUBLE_EQ(deforming.at("frames_per_second").get<double>(), desc.framesPerSecond);
    ASSERT_EQ(deforming.at("frame_mass_properties").size(), frames);
    const std::size_t samples = manifest.at("texel_samples").get<std::size_t>();

    double firstVolume = 0, lastVolume = 0;
    for (std::size_t k = 0; k < frames; ++k) {
        SCOPED_TRACE(k);
        char name[8];
        std::snprintf(name, sizeof name, "%03zu", k);
        const fs::path frameFolder = folder / "frames" / name;
        for (const char* file : {"position.exr", "area.exr", "samples.exr"})
            EXPECT_TRUE(fs::is_regular_file(frameFolder / file)) << file;
        // The exact volume of this frame's mesh (per triangle, Mirtich), not via textures.
        Result<TriangleMesh> mesh =
            loadMesh(project->resolvePath(k == 0 ? desc.mesh : desc.meshFrames[k - 1]));
        ASSERT_TRUE(mesh.ok()) << mesh.error().message;
        const double exact = exactSolidMassProperties(*mesh, 1.0).volume;
        // The frame's sample list (float32): V = sum A_y y about the first sample's point.
        Result<detail::FloatImage> list =
            detail::readExr(frameFolder / "samples.exr", {"py", "ay"});
        ASSERT_TRUE(list.ok()) << list.error().message;
        ASSERT_GE(list->pixels.size(), 2 * samples);
        double volume = 0;
        const double y0 = list->pixels[0];
        for (std::size_t i = 0; i < samples; ++i)
            volume += double(list->pixels[2 * i + 1]) * (double(list->pixels[2 * i]) - y0);
        EXPECT_NEAR(volume, exact, 1e-5 * exact);
        const double listed = deforming["frame_mass_properties"][k]["volume"].get<double>();
        EXPECT_NEAR(listed, exact, 1e-9 * exact);
        if (k == 0) firstVolume = exact;
        lastVolume = exact;
    }
    EXPECT_GT(lastVolume, 1.5 * firstVolume);  // the balloon inflates: the frames differ
    EXPECT_NEAR(manifest["mass_properties"]["texture"]["volume"].get<double>(), firstVolume,
                1e-9 * firstVolume);
    const bool said = std::any_of(notices.begin(), notices.end(), [&](const std::string& line) {
        return line.find(std::to_string(frames) + " frames exported") != std::string::npos;
    });
    EXPECT_TRUE(said);
}

TEST(ExportCli, ExrFilesReadBackWithOpenExrTools) {
    if (!haveTool("exrheader")) GTEST_SKIP() << "exrheader (package openexr) is not installed";
    const fs::path root = copyProject("exr", "box_half_draft");
    const fs::path out = root / "out";
    const test::CommandOutput r =
        runPlimsoll("export " + quoted(root / "projects" / "box_half_draft.plim.json") + " --out " +
                    quoted(out) + " --quiet");
    ASSERT_EQ(r.exitCode, 0) << r.err;
    const fs::path bundle = out / "box_half_draft" / "box";
    for (const char* file : {"position.exr", "area.exr"}) {
        int rc = 1;
        const std::string header = shell("exrheader " + quoted(bundle / file) + " 2>&1", &rc);
        EXPECT_EQ(rc, 0) << header;
        for (const char* expected :
             {"R, 32-bit floating-point", "G, 32-bit floating-point", "B, 32-bit floating-point",
              "A, 32-bit floating-point", "zip, multi-scanline blocks", "(0 0) - (127 127)"}) {
            EXPECT_NE(header.find(expected), std::string::npos) << file << ": " << expected << "\n"
                                                                << header;
        }
    }
    const std::string coverage = shell("exrheader " + quoted(bundle / "coverage.exr") + " 2>&1");
    EXPECT_NE(coverage.find("Y, 32-bit floating-point"), std::string::npos) << coverage;
}

TEST(ExportCli, CheckNamesAChangedPaintedMapAndAChangedGraph) {
    const fs::path root = copyProject("check", "damaged_boat");
    const std::string project = quoted(root / "projects" / "damaged_boat.plim.json");
    const fs::path out = root / "out";
    const fs::path bundle = out / "damaged_boat" / "boat";
    // No bundle yet: out of date.
    test::CommandOutput r =
        runPlimsoll("export " + project + " --out " + quoted(out) + " --check --quiet");
    EXPECT_EQ(r.exitCode, 1);
    EXPECT_NE(r.err.find("out of date: " + (bundle / "manifest.json").generic_string()),
              std::string::npos)
        << r.err;
    ASSERT_EQ(runPlimsoll("export " + project + " --out " + quoted(out) + " --quiet").exitCode, 0);
    const auto exported = contents(bundle);
    r = runPlimsoll("export " + project + " --out " + quoted(out) + " --check");
    EXPECT_EQ(r.exitCode, 0) << r.err;
    EXPECT_EQ(nlohmann::json::parse(r.out)["bodies"][0]["status"], "up_to_date");

    // A painted map changed: the PNG (and the manifest) named, nothing written.
    const fs::path mapPath = root / "assets" / "hull_stern_damage.png";
    const std::string originalMap = readFile(mapPath);
    Result<PaintedMap> map = loadPaintedMap(mapPath);
    ASSERT_TRUE(map.ok());
    map->values[map->values.size() / 2] = map->values[map->values.size() / 2] > 0.5f ? 0.0f : 1.0f;
    ASSERT_TRUE(savePaintedMap(*map, mapPath).ok());
    r = runPlimsoll("export " + project + " --out " + quoted(out) + " --check --quiet");
    EXPECT_EQ(r.exitCode, 1);
    EXPECT_NE(r.err.find("out of date: " + (bundle / "permeability.png").generic_string()),
              std::string::npos)
        << r.err;
    EXPECT_EQ(r.err.find("graph.json"), std::string::npos) << r.err;
    const nlohmann::json summary = nlohmann::json::parse(r.out);
    EXPECT_FALSE(summary["ok"].get<bool>());
    EXPECT_EQ(summary["bodies"][0]["out_of_date"],
              (nlohmann::json{"manifest.json", "permeability.png"}));
    EXPECT_EQ(contents(bundle), exported);
    { std::ofstream(mapPath, std::ios::binary) << originalMap; }

    // The graph changed: graph.json named.
    const fs::path graphPath = root / "projects" / "boat.graph.json";
    Result<WaterGraph> graph = loadGraph(graphPath);
    ASSERT_TRUE(graph.ok());
    graph->nodes.front().capacity *= 0.9;
    ASSERT_TRUE(saveGraph(*graph, graphPath).ok());
    r = runPlimsoll("export " + project + " --out " + quoted(out) + " --check --quiet");
    EXPECT_EQ(r.exitCode, 1);
    EXPECT_NE(r.err.find("out of date: " + (bundle / "graph.json").generic_string()),
              std::string::npos)
        << r.err;
    EXPECT_EQ(r.err.find("permeability.png"), std::string::npos) << r.err;
    EXPECT_EQ(contents(bundle), exported);

    // Exported again: up to date once more.
    ASSERT_EQ(runPlimsoll("export " + project + " --out " + quoted(out) + " --quiet").exitCode, 0);
    EXPECT_EQ(
        runPlimsoll("export " + project + " --out " + quoted(out) + " --check --quiet").exitCode,
        0);
}

// export --check builds the bundle in a temporary folder to compare it: a folder mkdtemp makes
// (a new one, of a random name), so a link planted in the temporary directory under the fixed
// name once used (TMPDIR/plimsoll-check, to a folder of the victim's) is never written through.
TEST(ExportCli, CheckNeverWritesThroughALinkPlantedInTheTemporaryDirectory) {
    const fs::path root = copyProject("check_link", "box_half_draft");
    const std::string project = quoted(root / "projects" / "box_half_draft.plim.json");
    const fs::path tmp = root / "tmp", victim = root / "victim";
    fs::create_directories(tmp);
    fs::create_directories(victim);
    test::writeFile(victim / "precious.txt", "keep");
    fs::create_directory_symlink(victim, tmp / "plimsoll-check");
    struct stat before {};
    ASSERT_EQ(::stat(victim.c_str(), &before), 0);
    const test::CommandOutput r =
        runPlimsoll("export " + project + " --out " + quoted(root / "out") + " --check --quiet",
                    "TMPDIR=" + quoted(tmp));
    EXPECT_EQ(r.exitCode, 1) << r.err;  // no bundle yet: out of date
    EXPECT_NE(r.err.find("out of date"), std::string::npos) << r.err;
    // Nothing was made or removed in the victim's folder (its time of change is the same) and
    // the check left nothing in the temporary directory but the link.
    struct stat after {};
    ASSERT_EQ(::stat(victim.c_str(), &after), 0);
    EXPECT_EQ(after.st_mtim.tv_sec, before.st_mtim.tv_sec);
    EXPECT_EQ(after.st_mtim.tv_nsec, before.st_mtim.tv_nsec);
    EXPECT_EQ(contents(victim), (std::map<std::string, std::string>{{"precious.txt", "keep"}}));
    std::vector<std::string> left;
    for (const auto& entry : fs::directory_iterator(tmp)) left.push_back(entry.path().filename());
    EXPECT_EQ(left, std::vector<std::string>{"plimsoll-check"});
    EXPECT_TRUE(fs::is_symlink(tmp / "plimsoll-check"));
    EXPECT_FALSE(fs::exists(root / "out"));
}

TEST(ExportCli, FailedExportLeavesThePreviousBundle) {
    const fs::path root = copyProject("failed", "damaged_boat");
    const std::string project = quoted(root / "projects" / "damaged_boat.plim.json");
    const fs::path out = root / "out";
    ASSERT_EQ(runPlimsoll("export " + project + " --out " + quoted(out) + " --quiet").exitCode, 0);
    const auto before = contents(out / "damaged_boat" / "boat");
    // The graph now fails to load: the export fails, naming it, and the bundle stays.
    { std::ofstream(root / "projects" / "boat.graph.json") << "{ not json"; }
    const test::CommandOutput r =
        runPlimsoll("export " + project + " --out " + quoted(out) + " --quiet");
    EXPECT_EQ(r.exitCode, 1);
    EXPECT_NE(r.err.find("water graph"), std::string::npos) << r.err;
    EXPECT_EQ(nlohmann::json::parse(r.out)["bodies"][0]["status"], "failed");
    EXPECT_EQ(contents(out / "damaged_boat" / "boat"), before);
    std::vector<std::string> siblings;
    for (const auto& e : fs::directory_iterator(out / "damaged_boat"))
        siblings.push_back(e.path().filename());
    EXPECT_EQ(siblings, std::vector<std::string>{"boat"});
}

TEST(ExportCli, SeveralProjectsInParallelMatchOneAtATime) {
    const fs::path root = copyProject("jobs", "damaged_boat");
    fs::copy_file(fs::path(PLIMSOLL_SOURCE_DIR) / "projects" / "box_half_draft.plim.json",
                  root / "projects" / "box_half_draft.plim.json");
    const std::string projects = quoted(root / "projects" / "damaged_boat.plim.json") + " " +
                                 quoted(root / "projects" / "box_half_draft.plim.json");
    const test::CommandOutput serial =
        runPlimsoll("export " + projects + " --out " + quoted(root / "serial") + " --quiet");
    const test::CommandOutput parallel = runPlimsoll(
        "export " + projects + " --out " + quoted(root / "parallel") + " --jobs 2 --quiet");
    ASSERT_EQ(serial.exitCode, 0) << serial.err;
    ASSERT_EQ(parallel.exitCode, 0) << parallel.err;
    EXPECT_EQ(nlohmann::json::parse(parallel.out)["jobs"], 2);
    const auto a = contents(root / "serial"), b = contents(root / "parallel");
    EXPECT_EQ(a.size(), 10u + 7u);  // boat: 10 files; box: 4 images, glTF + bin, manifest
    EXPECT_EQ(a, b);
    EXPECT_TRUE(a.count("box_half_draft/box/manifest.json"));
}

/// Every sample project, copied beside the one copyProject copied.
std::vector<fs::path> copyAllSampleProjects(const std::string& test) {
    const fs::path root = copyProject(test, "box_half_draft");
    std::vector<fs::path> projects;
    for (const auto& e : fs::directory_iterator(fs::path(PLIMSOLL_SOURCE_DIR) / "projects")) {
        const std::string name = e.path().filename().string();
        if (name.size() < 10 || name.substr(name.size() - 10) != ".plim.json") continue;
        const fs::path copy = root / "projects" / name;
        if (!fs::exists(copy)) fs::copy_file(e.path(), copy);
        projects.push_back(copy);
    }
    std::sort(projects.begin(), projects.end());
    return projects;
}

std::string quotedAll(const std::vector<fs::path>& paths) {
    std::string all;
    for (const fs::path& p : paths) all += " " + quoted(p);
    return all;
}

/// project/body folder -> status, from an export summary.
std::map<std::string, std::string> statuses(const std::string& summaryText, const fs::path& out) {
    std::map<std::string, std::string> result;
    const nlohmann::json summary = nlohmann::json::parse(summaryText);  // outlives the loop
    for (const auto& b : summary.at("bodies"))
        result[fs::relative(b.at("folder").get<std::string>(), out).generic_string()] =
            b.at("status").get<std::string>();
    return result;
}

// CI at scale: three shards export every body of the sample projects exactly once between
// them; the full export afterwards finds every bundle made from the same inputs and rewrites
// nothing (same files, same modification times) and says so; a changed source (bytes only)
// re-exports its body alone; --force rewrites all.
TEST(ExportCli, ShardsCoverEveryBodyOnceAndARepeatRewritesNothing) {
    const std::vector<fs::path> projects = copyAllSampleProjects("shards");
    ASSERT_GE(projects.size(), 7u);
    const fs::path root = projects.front().parent_path().parent_path(), out = root / "out";
    std::map<std::string, int> exported;
    for (int k = 1; k <= 3; ++k) {
        const test::CommandOutput r =
            runPlimsoll("export" + quotedAll(projects) + " --out " + quoted(out) +
                        " --jobs 2 --shard " + std::to_string(k) + "/3");
        ASSERT_EQ(r.exitCode, 0) << r.err;
        const nlohmann::json summary = nlohmann::json::parse(r.out);
        EXPECT_EQ(summary["shard"]["index"], k);
        EXPECT_EQ(summary["shard"]["count"], 3);
        for (const auto& [body, status] : statuses(r.out, out)) {
            EXPECT_EQ(status, "written") << body;
            ++exported[body];
        }
    }
    std::size_t bodies = 0;
    for (const fs::path& p : projects) bodies += loadProject(p)->bodies.size();
    EXPECT_EQ(exported.size(), bodies);
    for (const auto& [body, count] : exported) EXPECT_EQ(count, 1) << body;

    std::map<std::string, fs::file_time_type> times;
    for (const auto& e : fs::recursive_directory_iterator(out))
        times[e.path().string()] = e.last_write_time();
    const test::CommandOutput again =
        runPlimsoll("export" + quotedAll(projects) + " --out " + quoted(out));
    ASSERT_EQ(again.exitCode, 0) << again.err;
    const std::map<std::string, std::string> second = statuses(again.out, out);
    EXPECT_EQ(second.size(), bodies);
    for (const auto& [body, status] : second) {
        EXPECT_EQ(status, "unchanged") << body;
        EXPECT_EQ(exported.count(body), 1u) << body;
    }
    EXPECT_EQ(nlohmann::json::parse(again.out)["unchanged"], bodies);
    EXPECT_NE(
        again.err.find("all " + std::to_string(bodies) + " bundles unchanged, nothing rewritten"),
        std::string::npos)
        << again.err;
    EXPECT_EQ(again.err.find("[1/"), std::string::npos)
        << "progress lines off a terminal: " << again.err;
    for (const auto& e : fs::recursive_directory_iterator(out))
        EXPECT_EQ(e.last_write_time(), times[e.path().string()]) << e.path();

    // The box's mesh gains a comment: its bytes, so its input hash, change; only it is written.
    { std::ofstream(root / "assets" / "box.obj", std::ios::app) << "# changed\n"; }
    const test::CommandOutput changed =
        runPlimsoll("export" + quotedAll(projects) + " --out " + quoted(out) + " --progress");
    ASSERT_EQ(changed.exitCode, 0) << changed.err;
    EXPECT_NE(changed.err.find(": unchanged"), std::string::npos)
        << changed.err;  // --progress lines
    for (const auto& [body, status] : statuses(changed.out, out))
        EXPECT_EQ(status, body.rfind("box_half_draft/", 0) == 0 ? "written" : "unchanged") << body;
    const test::CommandOutput forced =
        runPlimsoll("export" + quotedAll(projects) + " --out " + quoted(out) + " --force --quiet");
    ASSERT_EQ(forced.exitCode, 0) << forced.err;
    EXPECT_TRUE(forced.err.empty()) << forced.err;
    for (const auto& [body, status] : statuses(forced.out, out))
        EXPECT_EQ(status, "written") << body;

    for (const char* bad : {"0/3", "4/3", "1/0", "x/3", "1/3/4", "/3", "-1/3"}) {
        const test::CommandOutput r = runPlimsoll("export" + quotedAll(projects) + " --out " +
                                                  quoted(out) + " --shard " + bad);
        EXPECT_EQ(r.exitCode, 2) << bad;
        EXPECT_NE(r.err.find("expected K/N"), std::string::npos) << r.err;
    }
}

// A generated atlas comes from the project's atlas cache: the first export writes the cache
// and a repeat keeps the bundle; with the cache gone the body is exported again (which
// writes it again), then kept once more.
TEST(ExportCli, TheAtlasCacheIsPartOfTheInputs) {
    const fs::path root = copyProject("atlas_cache", "box_half_draft");
    const fs::path project = root / "projects" / "box_half_draft.plim.json";
    nlohmann::json text = nlohmann::json::parse(readFile(project));
    text["bodies"][0]["atlas"] = "generate";
    { std::ofstream(project) << text.dump(2); }
    const fs::path out = root / "out", cache = root / "projects" / "box_half_draft.cache";
    auto status = [&] {
        const test::CommandOutput r =
            runPlimsoll("export " + quoted(project) + " --out " + quoted(out) + " --quiet");
        EXPECT_EQ(r.exitCode, 0) << r.err;
        return statuses(r.out, out)["box_half_draft/box"];
    };
    EXPECT_EQ(status(), "written");
    ASSERT_TRUE(fs::is_directory(cache));
    EXPECT_EQ(status(), "unchanged");
    fs::remove_all(cache);
    EXPECT_EQ(status(), "written");
    EXPECT_TRUE(fs::is_directory(cache));
    EXPECT_EQ(status(), "unchanged");
}

// --junit: one test case per body, validated by xmllint against the JUnit schema CI
// dashboards read (tests/data/junit/junit.xsd); a body whose water graph is broken is a
// <failure> carrying the export's message, the others pass.
TEST(ExportCli, JunitReportHasOneCasePerBodyAndMarksABrokenOneAsFailed) {
    const fs::path root = copyProject("junit", "damaged_boat");
    fs::copy_file(fs::path(PLIMSOLL_SOURCE_DIR) / "projects" / "buoy.plim.json",
                  root / "projects" / "buoy.plim.json");
    { std::ofstream(root / "projects" / "boat.graph.json") << "{ not json"; }
    const fs::path junit = root / "report.xml";
    const test::CommandOutput r =
        runPlimsoll("export " + quoted(root / "projects" / "damaged_boat.plim.json") + " " +
                    quoted(root / "projects" / "buoy.plim.json") + " --out " +
                    quoted(root / "out") + " --quiet --junit " + quoted(junit));
    EXPECT_EQ(r.exitCode, 1);
    ASSERT_TRUE(fs::exists(junit)) << r.err;
    const std::string xml = readFile(junit);
    if (!haveTool("xmllint")) GTEST_SKIP() << "xmllint (package libxml2-utils) is not installed";
    int rc = 1;
    const fs::path schema =
        fs::path(PLIMSOLL_SOURCE_DIR) / "tests" / "data" / "junit" / "junit.xsd";
    const std::string check =
        shell("xmllint --noout --schema " + quoted(schema) + " " + quoted(junit) + " 2>&1", &rc);
    EXPECT_EQ(rc, 0) << check << "\n" << xml;
    auto xpath = [&](const std::string& expression) {
        // Double quotes: the expressions hold single-quoted XPath strings.
        std::string value =
            shell("xmllint --xpath \"" + expression + "\" " + quoted(junit) + " 2>/dev/null");
        while (!value.empty() && std::isspace(static_cast<unsigned char>(value.back())))
            value.pop_back();
        return value;
    };
    EXPECT_EQ(xpath("count(//testcase)"), "2");
    EXPECT_EQ(xpath("string(/testsuites/@tests)"), "2");
    EXPECT_EQ(xpath("string(/testsuites/@failures)"), "1");
    EXPECT_EQ(xpath("count(//testcase[@classname='damaged_boat' and @name='boat']/failure)"), "1");
    EXPECT_EQ(xpath("count(//testcase[@classname='buoy' and @name='buoy']/failure)"), "0");
    const std::string message = xpath("string(//failure/@message)");
    EXPECT_NE(message.find("boat.graph.json"), std::string::npos) << message;

    // A project that does not load: one failed case for it, still schema-valid.
    {
        std::ofstream(root / "projects" / "buoy.plim.json")
            << "{ \"schema_version\": 1, \"bodies\": 3 }";
    }
    const test::CommandOutput broken =
        runPlimsoll("export " + quoted(root / "projects" / "buoy.plim.json") + " --out " +
                    quoted(root / "out") + " --quiet --junit " + quoted(junit));
    EXPECT_EQ(broken.exitCode, 1);
    const std::string recheck =
        shell("xmllint --noout --schema " + quoted(schema) + " " + quoted(junit) + " 2>&1", &rc);
    EXPECT_EQ(rc, 0) << recheck << "\n" << readFile(junit);
    EXPECT_EQ(xpath("count(//testsuite[@name='buoy.plim.json']/testcase[@name='project']/failure)"),
              "1");
}

}  // namespace
}  // namespace test_export
}  // namespace plimsoll
