// Project files: defaults, exact round trips, validation that names every problem with its JSON
// path, malformed and missing files, path resolution.
#include "plimsoll/project/project.h"

#include <gtest/gtest.h>

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <iterator>
#include <sstream>
#include <string>
#include <vector>

namespace plimsoll {
namespace test_project {
namespace {

namespace fs = std::filesystem;

// Every feature of the schema: Gerstner waves and a grid, a deforming body with a shell given
// by thickness and a painted map, a solid body, every simulation setting.
constexpr const char* kFullProject = R"({
  "schema_version": 1,
  "name": "harbour",
  "medium": {"name": "water", "density": 1025, "viscosity": 0.00108},
  "water": {
    "model": "gerstner",
    "level": -0.25,
    "gravity": 9.80665,
    "waves": [
      {"amplitude": 0.4, "wavelength": 12.5, "direction": [1, 0.2], "steepness": 0.7,
       "phase": 0.5},
      {"amplitude": 0.15, "wavelength": 5, "direction": [-0.3, 1], "steepness": 0,
       "phase": 2.1}
    ],
    "grid": {"count": [3, 2], "spacing": 0.5, "origin": [-1, 2.5],
             "heights": [0.1, -0.2, 0.3, 1.25, 0, -3.7]}
  },
  "simulation": {"gravity": [0, -9.80665, 0.1], "time_step": 0.01, "sub_steps": 8,
                 "integrator": "rk4", "duration": 30.5},
  "bodies": [
    {"name": "jelly", "mesh": "../assets/jelly_000.obj",
     "mesh_frames": ["../assets/jelly_001.obj", "../assets/jelly_002.obj"],
     "frames_per_second": 30, "texture_size": 512, "max_texel_stretch": 2,
     "material": {"density": 1010, "shell": {"thickness": 0.01, "material_density": 1200},
                  "map": "maps/density.png"},
     "position": [1, 2, 3], "rotation_deg": [10, 20, 30], "velocity": [0.5, 0, -0.5],
     "angular_velocity": [0, 1, 0], "drag_coefficient": 0.8, "friction_coefficient": 0.02},
    {"name": "buoy", "mesh": "/abs/buoy.obj", "material": {"density": 600}}
  ]
})";

/// A folder of its own for each test (several test processes may run at once).
class ProjectFiles : public ::testing::Test {
protected:
    void SetUp() override {
        const auto* test = ::testing::UnitTest::GetInstance()->current_test_info();
        folder_ = fs::temp_directory_path() / "plimsoll_tests" /
                  ("project_" + std::to_string(::getpid()) + "_" + test->name());
        fs::create_directories(folder_);
    }
    void TearDown() override { fs::remove_all(folder_); }

    fs::path write(const std::string& name, const std::string& text) const {
        const fs::path path = folder_ / name;
        std::ofstream(path, std::ios::binary) << text;
        return path;
    }

    static std::string read(const fs::path& path) {
        std::ifstream in(path, std::ios::binary);
        return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
    }

    fs::path folder_;
};

Project loaded(const Result<Project>& result) {
    EXPECT_TRUE(result.ok()) << result.error().message;
    return result.ok() ? result.value() : Project{};
}

std::vector<std::string> lines(const std::string& text) {
    std::vector<std::string> out;
    std::istringstream in(text);
    for (std::string line; std::getline(in, line);) out.push_back(line);
    return out;
}

/// The problems reported for `text`, named "scene.plim.json".
std::vector<std::string> problems(const std::string& text) {
    const Result<Project> result = parseProject(text, "scene.plim.json", "/scenes");
    EXPECT_FALSE(result.ok());
    return result.ok() ? std::vector<std::string>{} : lines(result.error().message);
}

std::string joined(const std::vector<std::string>& all) {
    std::string text;
    for (const std::string& line : all) text += line + "\n";
    return text;
}

void expectProblems(const std::string& text, const std::vector<std::string>& expected) {
    const std::vector<std::string> reported = problems(text);
    for (const std::string& line : expected) {
        EXPECT_NE(std::find(reported.begin(), reported.end(), "scene.plim.json: " + line),
                  reported.end())
            << "missing: " << line << "\nreported:\n"
            << joined(reported);
    }
    EXPECT_EQ(reported.size(), expected.size()) << joined(reported);
}

/// A valid project with `body` as its only body and `extra` top-level members.
std::string withBody(const std::string& body, const std::string& extra = "") {
    return R"({"schema_version": 1, )" + extra + R"("bodies": [)" + body + "]}";
}

TEST_F(ProjectFiles, AbsentKeysTakeTheDefaults) {
    const fs::path path = write("minimal.plim.json", withBody(R"({"mesh": "buoy.obj",
                                                        "material": {"density": 600}})"));
    const Project project = loaded(loadProject(path));
    Project expected;
    BodyDesc& body = expected.bodies.emplace_back();
    body.mesh = "buoy.obj";
    body.material.density = 600.0;
    EXPECT_EQ(project, expected);
    EXPECT_EQ(project.folder, folder_);
    EXPECT_EQ(project.water, WaterModel::flat(0.0));
    EXPECT_EQ(project.simulation.integrator, Integrator::SemiImplicitEuler);
    EXPECT_EQ(project.bodies[0].textureSize, 256);
}

// As in JSON Schema, a number without a fraction is an integer whatever its spelling.
TEST(Project, IntegersMayBeWrittenAsWholeNumbers) {
    const Project project = loaded(parseProject(
        withBody(R"({"mesh": "a.obj", "material": {"density": 600}, "texture_size": 512.0})",
                 R"("simulation": {"sub_steps": 2e1}, )"),
        "whole", ""));
    EXPECT_EQ(project.bodies[0].textureSize, 512);
    EXPECT_EQ(project.simulation.subSteps, 20);
}

TEST_F(ProjectFiles, EveryFeatureIsRead) {
    const Project project = loaded(parseProject(kFullProject, "full", "/scenes"));
    EXPECT_EQ(project.name, "harbour");
    EXPECT_EQ(project.medium.density, 1025.0);
    EXPECT_EQ(project.water.kind, WaterModel::Kind::Gerstner);
    ASSERT_EQ(project.water.waves.size(), 2u);
    EXPECT_EQ(project.water.waves[1].direction, Eigen::Vector2d(-0.3, 1.0));
    EXPECT_EQ(project.water.grid.countX, 3);
    EXPECT_EQ(project.water.grid.heights[5], -3.7f);
    EXPECT_EQ(project.simulation.integrator, Integrator::RK4);
    EXPECT_EQ(project.simulation.subSteps, 8);
    ASSERT_EQ(project.bodies.size(), 2u);
    const BodyDesc& jelly = project.bodies[0];
    EXPECT_TRUE(jelly.deforms());
    EXPECT_EQ(jelly.meshFrames[1], "../assets/jelly_002.obj");
    EXPECT_EQ(jelly.material.density, 1010.0);
    EXPECT_EQ(jelly.material.shellSurfaceDensity, 0.01 * 1200.0);
    EXPECT_EQ(jelly.material.shellDensityMap, "maps/density.png");
    EXPECT_EQ(jelly.rotationDegrees, Eigen::Vector3d(10, 20, 30));
    EXPECT_EQ(jelly.frictionCoefficient, 0.02);
    EXPECT_FALSE(project.bodies[1].material.shellSurfaceDensity.has_value());
}

// Load, save, load again: the same project, and saving it again gives the same text.
TEST_F(ProjectFiles, FullProjectRoundTrips) {
    const Project first = loaded(loadProject(write("full.plim.json", kFullProject)));
    const fs::path saved = folder_ / "saved.plim.json";
    ASSERT_TRUE(saveProject(first, saved).ok());
    const Project second = loaded(loadProject(saved));
    EXPECT_EQ(second, first);
    const fs::path again = folder_ / "again.plim.json";
    ASSERT_TRUE(saveProject(second, again).ok());
    EXPECT_EQ(read(again), read(saved));
    EXPECT_EQ(read(saved).rfind("{\n  \"schema_version\": 1,\n", 0), 0u) << read(saved);
}

// Values that only survive with full precision, built in code rather than read.
TEST_F(ProjectFiles, BuiltProjectRoundTripsExactly) {
    Project project;
    project.name = "precision \"quoted\" \u00e9";
    project.medium = {"air", 1.2041, 1.81e-5};
    project.water.kind = WaterModel::Kind::HeightField;
    project.water.level = 1.0 / 3.0;
    project.water.grid = {2, 2, 0.1, {1e-300, -2.0 / 7.0}, {0.1f, 1.0f / 3.0f, -1e-30f, 3e38f}};
    project.simulation.timeStep = 1.0 / 60.0;
    project.simulation.integrator = Integrator::ExplicitEuler;
    project.simulation.duration = 0.0;
    BodyDesc body;
    body.mesh = "C:/meshes/balloon.obj";
    body.material.shellSurfaceDensity = 0.1 + 0.2;
    body.position = {std::nextafter(1.0, 2.0), -0.0, 6.02214076e23};
    body.angularVelocity = {0.0, 1.0 / 7.0, 0.0};
    project.bodies = {body, body};
    project.bodies[1].name = "second";

    const fs::path path = folder_ / "built.plim.json";
    ASSERT_TRUE(saveProject(project, path).ok());
    const Project back = loaded(loadProject(path));
    EXPECT_EQ(back, project);
    ASSERT_TRUE(saveProject(back, folder_ / "again.plim.json").ok());
    EXPECT_EQ(read(folder_ / "again.plim.json"), read(path));
    // Grid heights are floats: written in their own shortest form, not widened to 17 digits.
    EXPECT_EQ(read(path).find("0.10000000149011612"), std::string::npos) << read(path);
}

TEST(Project, EqualityIgnoresTheFolder) {
    Project a, b;
    a.folder = "/one";
    b.folder = "/two";
    EXPECT_EQ(a, b);
    b.simulation.subSteps = 5;
    EXPECT_FALSE(a == b);
}

TEST(Project, ReportsWrongTypesWithTheirPaths) {
    expectProblems(
        withBody(R"({"name": 3, "mesh": ["a.obj"], "material": {"density": "600"},
                                "position": [1, 2], "velocity": [1, "2", 3],
                                "texture_size": 256.5, "mesh_frames": "b.obj"})",
                 R"("name": null, "medium": [], "simulation": {"sub_steps": "4",
                               "integrator": 4}, "water": {"waves": {}}, )"),
        {"name: must be a string", "medium: must be an object", "water.waves: must be an array",
         "simulation.sub_steps: must be an integer", "simulation.integrator: must be a string",
         "bodies[0].name: must be a string", "bodies[0].mesh: must be a string",
         "bodies[0].mesh_frames: must be an array", "bodies[0].texture_size: must be an integer",
         "bodies[0].material.density: must be a number",
         "bodies[0].position: must be an array of 3 numbers",
         "bodies[0].velocity[1]: must be a number"});
}

TEST(Project, ReportsValuesOutOfRange) {
    const std::string body0 = R"({"mesh": "a.obj", "material": {"density": 600},
                                  "texture_size": 8, "frames_per_second": 0,
                                  "max_texel_stretch": -1, "drag_coefficient": -0.5})";
    const std::string body1 = R"({"mesh": "b.obj", "texture_size": 8193,
                                  "material": {"density": -1, "shell": {"surface_density": 0}}})";
    expectProblems(
        withBody(body0 + ", " + body1,
                 R"("medium": {"density": 0, "viscosity": -1},
                               "simulation": {"time_step": 0, "sub_steps": 0, "duration": -1},
                               "water": {"gravity": 0}, )"),
        {"medium.density: must be > 0", "medium.viscosity: must be >= 0",
         "water.gravity: must be > 0", "simulation.time_step: must be > 0",
         "simulation.sub_steps: must be in 1..20000", "simulation.duration: must be >= 0",
         "bodies[0].frames_per_second: must be > 0", "bodies[0].texture_size: must be in 16..8192",
         "bodies[0].max_texel_stretch: must be >= 0", "bodies[0].drag_coefficient: must be >= 0",
         "bodies[1].texture_size: must be in 16..8192: 8193 is more than the limit "
         "kMaxTextureSize (limits.h); its texels would need up to 4.5 GB",
         "bodies[1].material.density: must be > 0",
         "bodies[1].material.shell.surface_density: must be > 0"});
}

TEST(Project, RadiationSettingsRoundTripAndAreChecked) {
    const Project project =
        loaded(parseProject(withBody(R"({"mesh": "a.obj", "material": {"density": 600},
                     "radiation": {"enabled": false, "panel_edge": 0.25, "frequencies": 12,
                                   "min_frequency": 0.5, "max_frequency": 9}})"),
                            "scene", "/scenes"));
    ASSERT_TRUE(project.bodies[0].radiation);
    const RadiationDesc& r = *project.bodies[0].radiation;
    EXPECT_FALSE(r.enabled);
    EXPECT_FALSE(project.bodies[0].radiates());
    EXPECT_EQ(r.panelEdge, 0.25);
    EXPECT_EQ(r.frequencies, 12);
    EXPECT_EQ(r.minFrequency, 0.5);
    EXPECT_EQ(r.maxFrequency, 9.0);
    EXPECT_EQ(loaded(parseProject(projectToJson(project), "again", "/scenes")), project);
    // An empty object is radiation on with the automatic settings.
    const Project automatic = loaded(parseProject(
        withBody(R"({"mesh": "a.obj", "material": {"density": 600}, "radiation": {}})"), "s", "/"));
    EXPECT_TRUE(automatic.bodies[0].radiates());
    EXPECT_TRUE(automatic.bodies[0].radiationRequired());
    EXPECT_EQ(*automatic.bodies[0].radiation, RadiationDesc{});
    // Absent: on by default (where it applies), not required; false: off, and saved as false.
    const Project byDefault = loaded(
        parseProject(withBody(R"({"mesh": "a.obj", "material": {"density": 600}})"), "s", "/"));
    EXPECT_FALSE(byDefault.bodies[0].radiation);
    EXPECT_TRUE(byDefault.bodies[0].radiates());
    EXPECT_FALSE(byDefault.bodies[0].radiationRequired());
    EXPECT_FALSE(byDefault.bodies[0].linearDamping);
    EXPECT_EQ(byDefault.bodies[0].standInLinearDamping(true), kRadiatingHorizontalDamping);
    EXPECT_EQ(byDefault.bodies[0].standInVerticalDamping(true), kRadiatingVerticalDamping);
    EXPECT_EQ(byDefault.bodies[0].standInLinearDamping(false), kStandInDamping);
    EXPECT_EQ(byDefault.bodies[0].standInVerticalDamping(false), kStandInDamping);
    EXPECT_EQ(loaded(parseProject(projectToJson(byDefault), "again", "/")), byDefault);
    const Project off = loaded(parseProject(
        withBody(R"({"mesh": "a.obj", "material": {"density": 600}, "radiation": false})"), "s",
        "/"));
    ASSERT_TRUE(off.bodies[0].radiation);
    EXPECT_FALSE(off.bodies[0].radiates());
    EXPECT_EQ(projectToJson(off).find("\"radiation\":false") != std::string::npos ||
                  projectToJson(off).find("\"radiation\": false") != std::string::npos,
              true);
    EXPECT_EQ(loaded(parseProject(projectToJson(off), "again", "/")), off);
    expectProblems(withBody(R"({"mesh": "a.obj", "material": {"density": 600},
                                "radiation": {"frequencies": 3, "panel_edge": -1, "lid": true}})"),
                   {"bodies[0].radiation.lid: unknown key",
                    "bodies[0].radiation.frequencies: must be in 4..200",
                    "bodies[0].radiation.panel_edge: must be >= 0"});
    expectProblems(withBody(R"({"mesh": "a.obj", "material": {"density": 600},
                                "radiation": {"min_frequency": 2, "max_frequency": 1}})"),
                   {"bodies[0].radiation.max_frequency: must be more than min_frequency"});
}

TEST(Project, CapSettingsRoundTripAndAreChecked) {
    const Project project = loaded(parseProject(
        withBody(R"({"mesh": "a.obj", "material": {"density": 600}, "openings": "sealed",
                     "caps": [{"mode": "open", "height": 0.125}, {}, {"height": -0.5}]})"),
        "scene", "/scenes"));
    const BodyDesc& body = project.bodies[0];
    ASSERT_EQ(body.caps.size(), 3u);
    EXPECT_EQ(body.caps[0].mode, OpeningsMode::Open);
    EXPECT_EQ(body.caps[0].height, 0.125);
    EXPECT_EQ(body.caps[1], CapDesc{});
    EXPECT_FALSE(body.caps[2].mode);
    EXPECT_EQ(body.caps[2].height, -0.5);
    // Each cap's mode: its own, else the body's; openings past the list take the body's.
    EXPECT_EQ(body.capMode(0), OpeningsMode::Open);
    EXPECT_EQ(body.capMode(1), OpeningsMode::Sealed);
    EXPECT_EQ(body.capMode(7), OpeningsMode::Sealed);
    const std::string text = projectToJson(project);
    EXPECT_EQ(loaded(parseProject(text, "again", "/scenes")), project);
    EXPECT_EQ(projectToJson(loaded(parseProject(text, "again", "/scenes"))), text);
    // With "openings": "none" there are no caps, whatever the list says.
    Project none = project;
    none.bodies[0].openings = OpeningsMode::None;
    EXPECT_EQ(none.bodies[0].capMode(0), OpeningsMode::None);
    // Absent: no list, and none is written.
    const Project plain = loaded(
        parseProject(withBody(R"({"mesh": "a.obj", "material": {"density": 600}})"), "s", "/"));
    EXPECT_TRUE(plain.bodies[0].caps.empty());
    EXPECT_EQ(projectToJson(plain).find("\"caps\""), std::string::npos);
    expectProblems(
        withBody(R"({"mesh": "a.obj", "material": {"density": 600},
                                "caps": [{"mode": "none"}, {"height": "low"}, {"hieght": 1}, 3]})"),
        {"bodies[0].caps[0].mode: unknown 'none' (open, sealed)",
         "bodies[0].caps[1].height: must be a number", "bodies[0].caps[2].hieght: unknown key",
         "bodies[0].caps[3]: must be an object"});
    expectProblems(
        withBody(R"({"mesh": "a.obj", "material": {"density": 600}, "caps": {"mode": "open"}})"),
        {"bodies[0].caps: must be an array"});
}

TEST(Project, LevelLadderRoundTripsAndIsChecked) {
    const Project project = loaded(
        parseProject(withBody(R"({"mesh": "a.obj", "material": {"density": 600}, "texture_size": 64,
                     "lod": {"levels": [16, 32]}})"),
                     "scene", "/scenes"));
    ASSERT_TRUE(project.bodies[0].lod);
    EXPECT_EQ(project.bodies[0].lod->levels, (std::vector<int>{16, 32}));
    EXPECT_EQ(loaded(parseProject(projectToJson(project), "again", "/scenes")), project);
    // Absent: no ladder, and none is written.
    const Project plain = loaded(
        parseProject(withBody(R"({"mesh": "a.obj", "material": {"density": 600}})"), "s", "/"));
    EXPECT_FALSE(plain.bodies[0].lod);
    EXPECT_EQ(projectToJson(plain).find("\"lod\""), std::string::npos);
    expectProblems(withBody(R"({"mesh": "a.obj", "material": {"density": 600}, "texture_size": 64,
                                "lod": {"levels": [8, 128], "size": 1}})"),
                   {"bodies[0].lod.size: unknown key", "bodies[0].lod.levels[0]: must be in 16..64",
                    "bodies[0].lod.levels[1]: must be in 16..64"});
    expectProblems(withBody(R"({"mesh": "a.obj", "material": {"density": 600}, "lod": {}})"),
                   {"bodies[0].lod.levels: required (texture sizes, e.g. [16, 32])"});
}

TEST(Project, ReportsBadWater) {
    std::string waves;
    for (int i = 0; i < kMaxGerstnerWaves + 1; ++i) waves += R"({"amplitude": 0.1},)";
    waves += R"({"wavelength": 0, "steepness": 1.5, "direction": [0, 0], "amplitude": -1})";
    expectProblems(
        withBody(R"({"mesh": "a.obj", "material": {"density": 600}})",
                 R"("water": {"model": "heightfield", "waves": [)" + waves + "]}, "),
        {"water.waves: at most 16", "water.waves[17].amplitude: must be >= 0",
         "water.waves[17].wavelength: must be > 0", "water.waves[17].direction: must not be [0, 0]",
         "water.waves[17].steepness: must be in 0..1",
         "water.grid: required for model 'heightfield'"});
    expectProblems(
        withBody(R"({"mesh": "a.obj", "material": {"density": 600}})",
                 R"("water": {"model": "gerstner", "grid": {"count": [2, 0],
                               "spacing": -1, "heights": [1, "x", 3, null, null]}}, )"),
        {"water.waves: model 'gerstner' needs at least one wave",
         "water.grid.count[1]: must be >= 1", "water.grid.spacing: must be > 0",
         "water.grid.heights[1]: must be a number", "water.grid.heights: 2 more invalid values"});
    expectProblems(withBody(R"({"mesh": "a.obj", "material": {"density": 600}})",
                            R"("water": {"model": "swell", "grid": {"count": [2, 3],
                               "heights": [1, 2, 3, 4, 1e39]}}, )"),
                   {"water.model: unknown 'swell' (flat, gerstner, heightfield)",
                    "water.grid.heights: 5 values; count [2, 3] needs 6",
                    "water.grid.heights[4]: outside the float range"});
}

TEST(Project, ReportsMissingAndUnknownKeys) {
    expectProblems(
        R"({"nmae": "typo", "simulation": {"integrator": "leapfrog", "dt": 0.1},
                       "bodies": [{"material": {"densty": 5}},
                                  {"mesh": "", "material": {}, "mesh_frames": ["a", ""]},
                                  {"mesh": "c.obj"}]})",
        {"schema_version: required", "nmae: unknown key", "simulation.dt: unknown key",
         "simulation.integrator: unknown 'leapfrog' (explicit-euler, "
         "semi-implicit-euler, rk4)",
         "bodies[0].mesh: required", "bodies[0].material.densty: unknown key",
         "bodies[0].material: needs density or shell", "bodies[1].mesh: must not be empty",
         "bodies[1].mesh_frames[1]: must not be empty",
         "bodies[1].material: needs density or shell",
         "bodies[2].material: required (density or shell)"});
    expectProblems(R"({"schema_version": 1, "bodies": []})",
                   {"bodies: at least one body required"});
    expectProblems(R"({"schema_version": 0})",
                   {"schema_version: must be >= 1", "bodies: required"});
    expectProblems("[1, 2]", {"must be a JSON object"});
}

TEST(Project, ReportsBadShells) {
    expectProblems(
        withBody(R"({"mesh": "a.obj", "material": {"shell": {"thickness": 0.01}}},
                    {"mesh": "b.obj", "material": {"shell": {"surface_density": 2,
                                                            "thickness": 0.01}}},
                    {"mesh": "c.obj", "material": {"shell": {"thickness": 0,
                                                            "material_density": 900}}},
                    {"mesh": "d.obj", "material": {"density": 600, "map": "m.png"}},
                    {"mesh": "e.obj", "material": {"shell": {}}})"),
        {"bodies[0].material.shell.material_density: required with thickness",
         "bodies[1].material.shell: surface_density, or thickness and material_density, not both",
         "bodies[2].material.shell.thickness: must be > 0", "bodies[3].material.map: needs a shell",
         "bodies[4].material.shell: needs surface_density, or thickness and material_density"});
}

// A file from a newer Plimsoll may use keys this one does not know: only the version is named.
TEST(Project, NewerSchemaIsTheOnlyProblem) {
    expectProblems(R"({"schema_version": 2, "hull": {}, "bodies": "later"})",
                   {"schema_version: 2 is newer than this Plimsoll reads (1)"});
}

TEST(Project, MalformedJsonNamesThePosition) {
    const std::vector<std::string> reported =
        problems("{\n  \"schema_version\": 1,\n  \"bodies\": [}\n");
    ASSERT_EQ(reported.size(), 1u);
    EXPECT_EQ(reported[0].rfind("scene.plim.json: parse error at line 3, column ", 0), 0u)
        << reported[0];
    // Numbers beyond a double are refused by the parser (JSON has no infinity).
    const std::vector<std::string> overflow = problems(withBody(R"({"mesh": "a.obj",
        "material": {"density": 1e999}})"));
    ASSERT_EQ(overflow.size(), 1u);
    EXPECT_NE(overflow[0].find("1e999"), std::string::npos) << overflow[0];
}

TEST_F(ProjectFiles, MissingFileIsNamed) {
    const fs::path path = folder_ / "absent.plim.json";
    const Result<Project> result = loadProject(path);
    ASSERT_FALSE(result.ok());
    EXPECT_EQ(result.error().message, path.string() + ": no such file");
}

TEST_F(ProjectFiles, ErrorsNameTheFile) {
    const fs::path path = write("bad.plim.json", withBody(R"({"mesh": "a.obj"})"));
    const Result<Project> result = loadProject(path);
    ASSERT_FALSE(result.ok());
    EXPECT_EQ(result.error().message,
              path.string() + ": bodies[0].material: required (density or shell)");
}

TEST(Project, ResolvesPathsAgainstItsFolder) {
    Project project;
    project.folder = "/data/scenes";
    EXPECT_EQ(project.resolvePath("../assets/buoy.obj"), fs::path("/data/assets/buoy.obj"));
    EXPECT_EQ(project.resolvePath("maps/./density.png"), fs::path("/data/scenes/maps/density.png"));
    EXPECT_EQ(project.resolvePath("/abs/mesh.obj"), fs::path("/abs/mesh.obj"));
    project.folder.clear();
    EXPECT_EQ(project.resolvePath("buoy.obj"), fs::path("buoy.obj"));
}

}  // namespace
}  // namespace test_project
}  // namespace plimsoll
