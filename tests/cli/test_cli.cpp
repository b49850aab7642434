// The plimsoll executable end to end: sub-commands, JSON output, exit codes, error messages.
#include "plimsoll/physics/massprops.h"
#include "plimsoll/io/json_depth.h"
#include "plimsoll/io/mesh_io.h"
#include "plimsoll/io/painted_map_io.h"

#include "cli_runner.h"
#include "test_support.h"
#include "world_support.h"

#include <nlohmann/json.hpp>

#include <fstream>
#include <sstream>

namespace plimsoll {
namespace test_cli {
namespace {

namespace fs = std::filesystem;

using test::CommandOutput;
using test::runPlimsoll;

const std::string kSphere = test::assetPath("sphere.obj").string();

TEST(Cli, HelpOnEverySubcommand) {
    for (const char* sub : {"", "validate", "bake", "massprops", "samples"}) {
        const CommandOutput r = runPlimsoll(std::string(sub) + " --help");
        EXPECT_EQ(r.exitCode, 0) << sub;
        EXPECT_NE(r.out.find("Usage"), std::string::npos) << sub;
    }
}

TEST(Cli, MassPropsJsonMatchesTheEngine) {
    Result<TriangleMesh> mesh = loadMesh(kSphere);
    ASSERT_TRUE(mesh.ok());
    const MassProperties exact = exactSolidMassProperties(*mesh, 900.0);

    const CommandOutput r =
        runPlimsoll("massprops '" + kSphere + "' --size 256 --density 900 --json");
    ASSERT_EQ(r.exitCode, 0) << r.err;
    const nlohmann::json j = nlohmann::json::parse(r.out);
    EXPECT_EQ(j.at("method"), "texture");
    EXPECT_EQ(j.at("texture_size"), 256);
    EXPECT_GT(j.at("covered_texels").get<int>(), 256 * 200);
    EXPECT_NEAR(j.at("volume").get<double>(), exact.volume, 1e-3 * exact.volume);
    EXPECT_NEAR(j.at("mass").get<double>(), exact.mass, 1e-3 * exact.mass);
    ASSERT_EQ(j.at("center_of_mass").size(), 3u);
    ASSERT_EQ(j.at("inertia").size(), 3u);
    for (int a = 0; a < 3; ++a)
        for (int b = 0; b < 3; ++b)
            EXPECT_NEAR(j["inertia"][a][b].get<double>(), exact.inertia(a, b),
                        3e-3 * exact.inertia.norm());

    const CommandOutput e = runPlimsoll("massprops '" + kSphere + "' --exact --json");
    ASSERT_EQ(e.exitCode, 0) << e.err;
    const nlohmann::json je = nlohmann::json::parse(e.out);
    EXPECT_EQ(je.at("method"), "exact");
    EXPECT_NEAR(je.at("mass").get<double>(), 1000.0 * exact.volume, 1e-9 * exact.mass);
}

TEST(Cli, BakeWritesTexturesAndManifest) {
    const fs::path out = fs::temp_directory_path() / "plimsoll_tests" / "cli_bake";
    fs::remove_all(out);
    const CommandOutput r =
        runPlimsoll("bake '" + kSphere + "' --size 64 --out '" + out.string() + "'");
    ASSERT_EQ(r.exitCode, 0) << r.err;
    for (const char* f : {"position.exr", "area_vector.exr", "coverage.exr", "manifest.json"})
        EXPECT_TRUE(fs::exists(out / f)) << f;
    EXPECT_NE(r.out.find("closure error"), std::string::npos);
}

// A file name is bytes and JSON is UTF-8: a mesh named in Latin-1 still bakes, and its name in
// the manifest (a note for people) shows the byte it cannot hold as U+FFFD.
TEST(Cli, BakeOfAMeshWhoseNameIsNotUtf8) {
    const fs::path out = fs::temp_directory_path() / "plimsoll_tests" / "cli_bake_latin1";
    fs::remove_all(out);
    fs::create_directories(out);
    const fs::path mesh = out / "caf\xe9.obj";
    fs::copy_file(kSphere, mesh);
    const CommandOutput r = runPlimsoll("bake '" + mesh.string() + "' --size 32 --out '" +
                                        (out / "textures").string() + "'");
    ASSERT_EQ(r.exitCode, 0) << r.err;
    const nlohmann::json manifest =
        nlohmann::json::parse(test::readFile(out / "textures" / "manifest.json"));
    EXPECT_EQ(manifest.at("source_mesh").get<std::string>(),
              (out / "caf\xef\xbf\xbd.obj").string());
}

TEST(Cli, BadInputGivesAClearErrorAndNonZeroExit) {
    const CommandOutput missing = runPlimsoll("massprops /no/such/mesh.obj --json");
    EXPECT_NE(missing.exitCode, 0);
    EXPECT_NE(missing.err.find("/no/such/mesh.obj"), std::string::npos);
    EXPECT_TRUE(missing.out.empty());

    const CommandOutput tiny = runPlimsoll("bake '" + kSphere + "' --size 8 --out /tmp/x");
    EXPECT_NE(tiny.exitCode, 0);
    EXPECT_NE(tiny.err.find("--size"), std::string::npos);

    const CommandOutput both = runPlimsoll("massprops '" + kSphere + "' --size 64 --exact");
    EXPECT_NE(both.exitCode, 0);

    const fs::path dir = fs::temp_directory_path() / "plimsoll_tests";
    const fs::path empty = dir / "empty.obj";
    std::ofstream(empty).close();
    const CommandOutput emptyRun = runPlimsoll("massprops '" + empty.string() + "' --exact");
    EXPECT_EQ(emptyRun.exitCode, 1);
    EXPECT_NE(emptyRun.err.find(empty.string()), std::string::npos);

    const fs::path nan = dir / "nan.obj";
    std::ofstream(nan) << "v 0 0 0\nv 1 0 0\nv 0 nan 0\nv 0 0 1\n"
                          "f 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n";
    const CommandOutput nanRun = runPlimsoll("massprops '" + nan.string() + "' --exact --json");
    EXPECT_EQ(nanRun.exitCode, 1);
    EXPECT_NE(nanRun.err.find("non-finite"), std::string::npos);
    EXPECT_TRUE(nanRun.out.empty());
}

TEST(Cli, SimulateOneBodyFromFlags) {
    const std::string box = test::assetPath("box.obj").string();
    const CommandOutput r = runPlimsoll("simulate --mesh '" + box +
                                        "' --density 400 --size 48 --water-level=-0.5 "
                                        "--position=0,3,0 --rotation-deg=0,0,0 --seconds 0.5 "
                                        "--device reference --json");
    ASSERT_EQ(r.exitCode, 0) << r.err;
    const nlohmann::json j = nlohmann::json::parse(r.out);
    for (const char* key : {"time", "position", "orientation", "velocity", "angular_velocity",
                            "submerged_volume", "mass"})
        EXPECT_TRUE(j.contains(key)) << key;
    EXPECT_NEAR(j.at("time").get<double>(), 0.5, 1e-9);
    // Half a second of free fall from 3 m: nowhere near the water yet.
    EXPECT_NEAR(j.at("velocity")[1].get<double>(), -9.81 * 0.5, 1e-6);
    EXPECT_NEAR(j.at("mass").get<double>(), 400 * 0.125, 1e-9);
    EXPECT_NE(r.err.find("skips the buoyancy kernels"), std::string::npos);

    const CommandOutput bad = runPlimsoll("simulate /no/such/scene.plim.json");
    EXPECT_NE(bad.exitCode, 0);
    EXPECT_NE(bad.err.find("/no/such/scene.plim.json"), std::string::npos);
}

TEST(Cli, ValidateExitCodes) {
    EXPECT_EQ(runPlimsoll("validate '" + kSphere + "'").exitCode, 0);
    const auto boat = test::sharedMesh("boat.obj");
    if (!boat) GTEST_SKIP() << "../shared/meshes not present";
    // Its UVs overlap: not usable as is, but usable through a generated physics atlas (exit 0,
    // with the reasons); "cannot be used" (exit 1) is for meshes no repair or atlas rescues.
    const CommandOutput r = runPlimsoll("validate '" + boat->string() + "'");
    EXPECT_EQ(r.exitCode, 0);
    EXPECT_NE(r.out.find("usable through a generated physics atlas"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("uv-overlap"), std::string::npos);
    EXPECT_NE(r.out.find("uv-out-of-range"), std::string::npos);
    EXPECT_NE(r.out.find("boat.obj"), std::string::npos);
    // Its own UVs are refused with the reason; by default a physics atlas replaces them, and
    // says so; the exact path accepts the mesh as it is.
    const CommandOutput refused =
        runPlimsoll("massprops '" + boat->string() + "' --size 64 --atlas mesh --json");
    EXPECT_NE(refused.exitCode, 0);
    EXPECT_NE(refused.err.find("uv-overlap"), std::string::npos);
    const CommandOutput generated =
        runPlimsoll("massprops '" + boat->string() + "' --size 64 --json");
    EXPECT_EQ(generated.exitCode, 0) << generated.err;
    EXPECT_NE(generated.err.find("generated physics atlas"), std::string::npos) << generated.err;
    EXPECT_EQ(nlohmann::json::parse(generated.out).at("atlas"), "generated");
    EXPECT_NE(runPlimsoll("massprops '" + boat->string() + "' --atlas sideways").exitCode, 0);
    EXPECT_EQ(runPlimsoll("massprops '" + boat->string() + "' --exact --json").exitCode, 0);
}

/// A project of the box asset (texture 256: bundle files above 8 KB) in `dir`, named "box".
fs::path writeBoxProject(const fs::path& dir) {
    fs::copy_file(test::assetPath("box.obj"), dir / "box.obj",
                  fs::copy_options::overwrite_existing);
    const fs::path path = dir / "box.plim.json";
    std::ofstream(path)
        << R"({"schema_version": 1, "name": "box", "bodies": [{"name": "box", "mesh": "box.obj",
        "texture_size": 256, "material": {"density": 500.0}}]})";
    return path;
}

// A write that fails (a full disk; here the file size limit, which fails write() with EFBIG
// as a full disk fails it with ENOSPC) exits 1 with a line naming the file and the cause:
// simulate --out said nothing, and export counted the bundle it failed as written.
TEST(CliWrites, AFailedWriteNamesTheFileAndTheCauseAndTalliesCountWhatWasWritten) {
    const fs::path dir = test::freshFolder("cli", "failed_writes");
    const fs::path project = writeBoxProject(dir);
    // Files of at most 8 blocks (4 or 8 KB, by the shell); SIGXFSZ ignored so that the
    // write fails instead of the signal ending the process.
    const std::string smallFiles = "trap '' XFSZ; ulimit -f 8;";
    const CommandOutput simulate =
        runPlimsoll("simulate '" + project.string() + "' --seconds 5 --device reference --out '" +
                        (dir / "t.csv").string() + "'",
                    smallFiles);
    EXPECT_EQ(simulate.exitCode, 1) << simulate.err;
    EXPECT_CONTAINS(simulate.err, "t.csv: write failed: File too large");
    EXPECT_FALSE(fs::exists(dir / "t.csv"));

    const CommandOutput exported = runPlimsoll(
        "export '" + project.string() + "' --out '" + (dir / "out").string() + "'", smallFiles);
    EXPECT_EQ(exported.exitCode, 1) << exported.err;
    EXPECT_CONTAINS(exported.err, "write failed: File too large");
    EXPECT_CONTAINS(exported.err, "export: 0 of 1 bundles written, 0 unchanged, 1 failed");
    EXPECT_EQ(exported.err.find("1 of 1 bundles written"), std::string::npos) << exported.err;
}

// Bytes that are not UTF-8 in a mesh's text and in a file's name: every report stays valid
// UTF-8 (nlohmann's dump() threw on them, a second error after the first, and the summary was
// not written); a message quotes the mesh's text as a bounded excerpt.
TEST(CliWrites, ReportsStayValidUtf8WhateverTheInput) {
    const fs::path dir = test::freshFolder("cli", "utf8_reports");
    const std::string bad = "\xff\xfe";
    // A vertex line with text after its numbers: refused, quoting the text.
    test::writeFile(dir / "bad.obj",
                    "v 0 0 0\nv 1 0 0\nv 0 1 x" + bad + std::string(1000, 'y') + "\nf 1 2 3\n");
    const CommandOutput validate =
        runPlimsoll("validate '" + (dir / "bad.obj").string() + "' --json");
    EXPECT_EQ(validate.exitCode, 1) << validate.err;
    EXPECT_CONTAINS(validate.err, "bad.obj: line 3: 'x??yyy");
    EXPECT_LT(validate.err.size(), 400u) << validate.err;

    // A project whose file name has the bytes, and whose body fails: the summary and the JUnit
    // report are written, valid UTF-8, and name the failure.
    const fs::path project = dir / ("p" + bad + ".plim.json");
    std::ofstream(project)
        << R"({"schema_version": 1, "name": "p", "bodies": [{"name": "b", "mesh": "bad.obj", "material": {"density": 500}}]})";
    const fs::path summary = dir / "summary.json", junit = dir / "junit.xml";
    const CommandOutput exported =
        runPlimsoll("export '" + project.string() + "' --out '" + (dir / "out").string() +
                    "' --summary '" + summary.string() + "' --junit '" + junit.string() + "'");
    EXPECT_EQ(exported.exitCode, 1) << exported.err;
    EXPECT_EQ(exported.err.find("json.exception"), std::string::npos) << exported.err;
    EXPECT_CONTAINS(exported.err, "export: 0 of 1 bundles written, 0 unchanged, 1 failed");
    for (const std::string& text : {exported.out, test::readFile(summary), test::readFile(junit)}) {
        EXPECT_EQ(validUtf8(text), text) << text;
        EXPECT_CONTAINS(text, "bad.obj: line 3");
    }
    const nlohmann::json report = nlohmann::json::parse(test::readFile(summary));
    std::string shown = project.string();
    shown.replace(shown.find(bad), bad.size(), "\xEF\xBF\xBD\xEF\xBF\xBD");
    EXPECT_EQ(report["bodies"][0]["project"], shown);
}

// export --web copies the viewer page (from $PLIMSOLL_WEB_VIEWER here, a stand-in folder, so the
// test needs no emscripten) into OUT beside the bundles and lists them in bundles.json; without
// a built viewer it refuses before exporting anything, naming where it looked and what to run.
TEST(CliExportWeb, WritesTheViewerBesideTheBundlesAndListsThem) {
    const fs::path dir = test::freshFolder("cli", "export_web");
    const fs::path project = writeBoxProject(dir);
    const fs::path viewer = dir / "viewer";
    fs::create_directories(viewer / "vendor" / "lib");
    std::ofstream(viewer / "index.html") << "<!doctype html><title>viewer</title>";
    std::ofstream(viewer / "viewer.js") << "// viewer";
    std::ofstream(viewer / "vendor" / "lib" / "x.js") << "export const x = 1;";
    const std::string env = "PLIMSOLL_WEB_VIEWER='" + viewer.string() + "'";

    const CommandOutput r = runPlimsoll(
        "export '" + project.string() + "' --out '" + (dir / "out").string() + "' --web --quiet",
        env);
    ASSERT_EQ(r.exitCode, 0) << r.err;
    EXPECT_EQ(test::readFile(dir / "out" / "index.html"), test::readFile(viewer / "index.html"));
    EXPECT_EQ(test::readFile(dir / "out" / "vendor" / "lib" / "x.js"), "export const x = 1;");
    const nlohmann::json listed =
        nlohmann::json::parse(test::readFile(dir / "out" / "bundles.json"));
    ASSERT_EQ(listed.at("bundles").size(), 1u);
    const std::string bundle = listed["bundles"][0].get<std::string>();
    EXPECT_EQ(bundle.rfind("box/", 0), 0u) << bundle;
    EXPECT_TRUE(fs::is_regular_file(dir / "out" / bundle / "manifest.json")) << bundle;

    const CommandOutput missing = runPlimsoll(
        "export '" + project.string() + "' --out '" + (dir / "out2").string() + "' --web --quiet",
        "PLIMSOLL_WEB_VIEWER='" + (dir / "nowhere").string() + "'");
    EXPECT_EQ(missing.exitCode, 1);
    EXPECT_CONTAINS(missing.err, (dir / "nowhere").string());
    EXPECT_CONTAINS(missing.err, "scripts/build-web.sh");
    EXPECT_FALSE(fs::exists(dir / "out2"));

    const CommandOutput check = runPlimsoll(
        "export '" + project.string() + "' --out '" + (dir / "out").string() + "' --web --check",
        env);
    EXPECT_NE(check.exitCode, 0);
    EXPECT_CONTAINS(check.err, "--web");
}

/// A project of the sphere with a solid of 300 kg/m^3 and a shell of 10 kg/m^2 whose painted
/// thickness is 1 over half the UV square (u < 0.5) and 0.2 over the other half; without
/// `thickness`, the same shell unpainted.
fs::path thickShellProject(const std::string& name, bool thickness) {
    const fs::path dir = test::scratchFolder("massprops_" + name);
    fs::create_directories(dir);
    PaintedMap map;
    map.width = map.height = 32;
    for (int y = 0; y < 32; ++y)
        for (int x = 0; x < 32; ++x) map.values.push_back(x < 16 ? 1.0f : 0.2f);
    EXPECT_TRUE(savePaintedMap(map, dir / "thick.png").ok());
    const fs::path path = dir / "shell.plim.json";
    std::ofstream(path)
        << R"({"schema_version": 1, "name": "t", "bodies": [{"name": "ball", "mesh": ")" << kSphere
        << R"(", "texture_size": 64, "radiation": false,)"
        << R"("material": {"density": 300, "shell": {"surface_density": 10})"
        << (thickness ? R"(, "thickness_map": "thick.png")" : "") << "}}]}";
    return path;
}

TEST(Cli, MassPropsOfAProjectBodyWeighsItsThicknessMapAsTheWorldDoes) {
    const fs::path project = thickShellProject("thick", true);
    const CommandOutput r = runPlimsoll("massprops '" + project.string() + "' --json");
    ASSERT_EQ(r.exitCode, 0) << r.err;
    const nlohmann::json j = nlohmann::json::parse(r.out);
    EXPECT_EQ(j.at("body"), "ball");
    EXPECT_EQ(j.at("shell_thickness_map"), "thick.png");

    Result<Project> loaded = loadProject(project);
    ASSERT_TRUE(loaded.ok()) << loaded.error().message;
    std::unique_ptr<World> world = test::worldOrFail(test::sceneOrFail(*loaded));
    ASSERT_TRUE(world);
    const MassDistribution& m = world->bodies().at(0).mass;
    EXPECT_NEAR(j.at("mass").get<double>(), m.mass, 1e-9 * m.mass);
    for (int a = 0; a < 3; ++a) {
        EXPECT_NEAR(j["center_of_mass"][a].get<double>(), m.centerOfMass[a], 1e-9);
        for (int b = 0; b < 3; ++b)
            EXPECT_NEAR(j["inertia"][a][b].get<double>(), m.inertia(a, b), 1e-9 * m.inertia.norm());
    }
    // The map counts: the same shell unpainted is heavier, and centred.
    const CommandOutput plain =
        runPlimsoll("massprops '" + thickShellProject("plain", false).string() + "' --json");
    ASSERT_EQ(plain.exitCode, 0) << plain.err;
    const nlohmann::json jp = nlohmann::json::parse(plain.out);
    const double sphereShell = 10.0 * M_PI;  // 10 kg/m^2 over a sphere of radius 0.5
    EXPECT_NEAR(jp.at("mass").get<double>() - j.at("mass").get<double>(), 0.4 * sphereShell,
                0.02 * sphereShell);
    EXPECT_GT(
        (Eigen::Vector3d(j["center_of_mass"][0], j["center_of_mass"][1], j["center_of_mass"][2]))
            .norm(),
        1e-3);

    // A project's body has its own material: mesh flags are refused.
    const CommandOutput mixed =
        runPlimsoll("massprops '" + project.string() + "' --density 500 --json");
    EXPECT_NE(mixed.exitCode, 0);
    EXPECT_NE(mixed.err.find("has its own material"), std::string::npos) << mixed.err;
}

}  // namespace
}  // namespace test_cli
}  // namespace plimsoll
