// `plimsoll hydro` end to end on a project of its own (assets/box.obj, 1 x 0.5 x 0.25 m, half the
// water's density, radiation on): A(omega) and B(omega) per mode with their physical signs, the
// convergence study, the radiation cache (a second run reads it, a damaged one is reported and
// replaced), the SVG plot, `simulate` with radiation (a project's and the one-body scene's), and
// the errors on bad settings.
#include "cli_runner.h"
#include "test_support.h"

#include <nlohmann/json.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <string>
#include <vector>

namespace plimsoll {
namespace test_cli_hydro {
namespace {

namespace fs = std::filesystem;
using test::CommandOutput;
using test::runPlimsoll;

/// A project in its own scratch folder (so that its cache is its own) with `radiation` as the
/// body's radiation object and `density` as its material.
fs::path writeProject(const std::string& name, const std::string& radiation,
                      double density = 500.0) {
    const fs::path folder = test::scratchFolder("cli_hydro_" + name);
    fs::remove_all(folder / "box.cache");
    const fs::path file = folder / "box.plim.json";
    std::ofstream(file) << R"({"schema_version": 1, "name": "radiating box",
  "medium": {"name": "water", "density": 1000.0},
  "water": {"model": "flat", "level": 0.0},
  "simulation": {"gravity": [0.0, -9.81, 0.0], "time_step": 0.016666666666666666, "sub_steps": 4},
  "bodies": [{"name": "box", "mesh": ")"
                        << PLIMSOLL_SOURCE_DIR << R"(/assets/box.obj", "texture_size": 64,
    "material": {"density": )"
                        << density << R"(}, "radiation": )" << radiation << "}]}\n";
    return file;
}

// Below the box's irregular frequencies (docs/radiation.md), where B turns negative; 72 panels.
const std::string kRadiation =
    R"({"panel_edge": 0.3, "frequencies": 6, "min_frequency": 1.5, "max_frequency": 8})";

nlohmann::json hydroJson(const fs::path& project, const std::string& arguments,
                         std::string* err = nullptr) {
    const CommandOutput r = runPlimsoll("hydro '" + project.string() + "' --json " + arguments);
    EXPECT_EQ(r.exitCode, 0) << r.err;
    if (err) *err = r.err;
    if (r.exitCode != 0) return nlohmann::json::object();
    return nlohmann::json::parse(r.out);
}

TEST(CliHydro, CoefficientsPerModeHaveTheirPhysicalSigns) {
    const fs::path project = writeProject("signs", kRadiation);
    const nlohmann::json j = hydroJson(project, "--no-convergence");
    ASSERT_FALSE(j.empty());
    EXPECT_EQ(j.at("body"), "box");
    // Half the water's density: displaces half of 0.125 m^3.
    EXPECT_NEAR(j.at("rest_volume").get<double>(), 0.0625, 1e-3 * 0.0625);
    // Split to the 0.3 m edge (each wetted triangle halved at its longest edge: 72 panels), far
    // more than the box's own triangles.
    EXPECT_GT(j.at("panels").get<int>(), 50);
    const nlohmann::json& f = j.at("frequencies");
    ASSERT_EQ(f.size(), 6u);
    for (std::size_t k = 0; k < f.size(); ++k) {
        if (k > 0) EXPECT_GT(f[k].at("omega").get<double>(), f[k - 1].at("omega").get<double>());
        // Radiated power is never negative: B_jj >= 0; heave and the horizontal translations
        // radiate at every frequency.
        for (int mode = 0; mode < 6; ++mode)
            EXPECT_GE(f[k].at("damping")[mode].get<double>(), -1e-6);
        for (int mode = 0; mode < 3; ++mode)
            EXPECT_GT(f[k].at("damping")[mode].get<double>(), 0.0) << mode;
    }
    // Infinite-frequency added mass: positive on the diagonal, symmetric to within the
    // collocation's discretisation (the exact operator is symmetric; 72 flat panels are so to
    // a few tenths of a percent of the heave term).
    const nlohmann::json& a = j.at("added_mass_infinity");
    for (int i = 0; i < 6; ++i) {
        EXPECT_GT(a[i][i].get<double>(), 0.0) << i;
        for (int k = 0; k < 6; ++k)
            EXPECT_NEAR(a[i][k].get<double>(), a[k][i].get<double>(), 0.01 * a[1][1].get<double>())
                << i << " " << k;
    }
    // Heave's memory is fitted (it has damping to fit).
    EXPECT_FALSE(j.at("memory")[1].empty());
    EXPECT_TRUE(j.at("convergence").empty());
}

TEST(CliHydro, ConvergenceWithPanelCount) {
    const fs::path project = writeProject("convergence", kRadiation);
    const nlohmann::json j = hydroJson(project, "");
    ASSERT_FALSE(j.empty());
    const nlohmann::json& c = j.at("convergence");
    ASSERT_EQ(c.size(), 3u);
    // Panels are split in four at a time (refinedPanels): counts rise in steps.
    for (std::size_t k = 1; k < c.size(); ++k) {
        EXPECT_LT(c[k].at("panel_edge").get<double>(), c[k - 1].at("panel_edge").get<double>());
        EXPECT_GE(c[k].at("panels").get<int>(), c[k - 1].at("panels").get<int>());
    }
    EXPECT_GT(c[2].at("panels").get<int>(), 2 * c[0].at("panels").get<int>());
    // The finest is the body's own solution, and the heave figures settle as panels are added:
    // the last step moves them less than 5%.
    EXPECT_EQ(c[2].at("panels"), j.at("panels"));
    for (const char* what : {"added_mass_infinity", "added_mass", "damping"}) {
        const double fine = c[2].at(what)[1].get<double>(), middle = c[1].at(what)[1].get<double>();
        EXPECT_NEAR(middle, fine, 0.05 * std::abs(fine)) << what;
    }
}

TEST(CliHydro, SecondRunReadsTheCacheAndADamagedCacheIsReplaced) {
    const fs::path project = writeProject("cache", kRadiation);
    std::string err;
    const nlohmann::json first = hydroJson(project, "--no-convergence", &err);
    EXPECT_NE(err.find("radiation computed over"), std::string::npos) << err;
    const fs::path cache = project.parent_path() / "box.cache" / "radiation-0.json";
    ASSERT_TRUE(fs::exists(cache));
    const nlohmann::json second = hydroJson(project, "--no-convergence", &err);
    EXPECT_NE(err.find("radiation from the cache"), std::string::npos) << err;
    EXPECT_EQ(first.at("frequencies"), second.at("frequencies"));
    EXPECT_EQ(first.at("memory"), second.at("memory"));
    // Damaged: reported with its file, recomputed, the same figures, and the cache whole again.
    std::ofstream(cache, std::ios::trunc) << R"({"format": "plimsoll-radiation", "key": )";
    const nlohmann::json third = hydroJson(project, "--no-convergence", &err);
    EXPECT_NE(err.find("not a readable radiation cache"), std::string::npos) << err;
    EXPECT_NE(err.find(cache.string()), std::string::npos) << err;
    EXPECT_EQ(first.at("frequencies"), third.at("frequencies"));
    EXPECT_TRUE(nlohmann::json::accept(test::readFile(cache))) << "the cache is whole JSON again";
    // Other settings are another key: recomputed, not read back.
    const fs::path changed = writeProject(
        "cache",
        R"({"panel_edge": 0.3, "frequencies": 5, "min_frequency": 1.5, "max_frequency": 8})");
    const nlohmann::json fourth = hydroJson(changed, "--no-convergence", &err);
    EXPECT_NE(err.find("radiation computed over"), std::string::npos) << err;
    EXPECT_EQ(fourth.at("frequencies").size(), 5u);
}

TEST(CliHydro, TableAndSvgPlot) {
    const fs::path project = writeProject("svg", kRadiation);
    const std::string svg = (project.parent_path() / "ab.svg").string();
    const CommandOutput r =
        runPlimsoll("hydro '" + project.string() + "' --no-convergence --svg '" + svg + "'");
    ASSERT_EQ(r.exitCode, 0) << r.err;
    EXPECT_NE(r.out.find("heave y A"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("infinity"), std::string::npos) << r.out;
    const std::string plot = test::readFile(svg);
    EXPECT_EQ(plot.rfind("<svg", 0), 0u);
    EXPECT_NE(plot.find("<polyline"), std::string::npos);
    EXPECT_NE(plot.find("heave y B"), std::string::npos);
}

TEST(CliHydro, SimulateRunsWithRadiation) {
    const fs::path project = writeProject("simulate", kRadiation);
    const std::string csv = (project.parent_path() / "run.csv").string();
    const CommandOutput r =
        runPlimsoll("simulate '" + project.string() + "' --seconds 0.5 --out '" + csv + "'");
    ASSERT_EQ(r.exitCode, 0) << r.err;
    EXPECT_NE(r.err.find("radiation over"), std::string::npos) << r.err;
    EXPECT_TRUE(fs::exists(project.parent_path() / "box.cache" / "radiation-0.json"));
}

// The one-body scene radiates by default, as a project's body does; --no-radiation is that
// body's "radiation": false: no panel solve, and a drop that moves with less added mass. It has
// no project file, so it caches nothing: the folder it runs in holds only the mesh afterwards.
TEST(CliHydro, TheOneBodySceneRadiatesUnlessToldNotAndCachesNothing) {
    const fs::path folder = test::scratchFolder("cli_hydro_one_body");
    fs::remove_all(folder);
    fs::create_directories(folder);
    fs::copy_file(PLIMSOLL_SOURCE_DIR "/assets/box.obj", folder / "box.obj");
    const std::string inFolder = "cd '" + folder.string() + "' &&";
    const std::string drop =
        "simulate --mesh box.obj --size 16 --density 500 --position=0,0.1,0 --seconds 0.5 --json";
    const CommandOutput with = runPlimsoll(drop, inFolder);
    const CommandOutput without = runPlimsoll(drop + " --no-radiation", inFolder);
    ASSERT_EQ(with.exitCode, 0) << with.err;
    ASSERT_EQ(without.exitCode, 0) << without.err;
    EXPECT_NE(with.err.find("radiation over"), std::string::npos) << with.err;
    EXPECT_EQ(without.err.find("radiation over"), std::string::npos) << without.err;
    const double heightWith = nlohmann::json::parse(with.out)["position"][1].get<double>();
    const double heightWithout = nlohmann::json::parse(without.out)["position"][1].get<double>();
    EXPECT_GT(std::abs(heightWith - heightWithout), 1e-4) << heightWith << " vs " << heightWithout;
    std::vector<std::string> left;
    for (const auto& entry : fs::directory_iterator(folder))
        left.push_back(entry.path().filename().string());
    EXPECT_EQ(left, std::vector<std::string>{"box.obj"});

    const CommandOutput usage = runPlimsoll("simulate --no-radiation --seconds 0.1");
    EXPECT_EQ(usage.exitCode, 2) << usage.err;
    EXPECT_NE(usage.err.find("--mesh"), std::string::npos) << usage.err;
}

TEST(CliHydro, BadSettingsAreRefusedWithTheirJsonPath) {
    const CommandOutput few =
        runPlimsoll("hydro '" + writeProject("bad", R"({"frequencies": 2})").string() + "'");
    EXPECT_EQ(few.exitCode, 1);
    EXPECT_NE(few.err.find("bodies[0].radiation.frequencies"), std::string::npos) << few.err;
    const CommandOutput half =
        runPlimsoll("hydro '" + writeProject("bad", R"({"min_frequency": 1})").string() + "'");
    EXPECT_EQ(half.exitCode, 1);
    EXPECT_NE(half.err.find("bodies[0].radiation: min_frequency and max_frequency go together"),
              std::string::npos)
        << half.err;
    const CommandOutput unknown = runPlimsoll(
        "simulate '" + writeProject("bad", R"({"panels": 100})").string() + "' --seconds 0.1");
    EXPECT_EQ(unknown.exitCode, 1);
    EXPECT_NE(unknown.err.find("bodies[0].radiation.panels"), std::string::npos) << unknown.err;
    const CommandOutput tiny =
        runPlimsoll("simulate '" + writeProject("bad", R"({"panel_edge": 0.0001})").string() +
                    "' --seconds 0.1");
    EXPECT_EQ(tiny.exitCode, 1);
    EXPECT_NE(tiny.err.find("bodies[0].radiation"), std::string::npos) << tiny.err;
    EXPECT_NE(tiny.err.find("kMaxRadiationPanels"), std::string::npos) << tiny.err;
    const CommandOutput sinks =
        runPlimsoll("simulate '" + writeProject("bad", "{}", 2000.0).string() + "' --seconds 0.1");
    EXPECT_EQ(sinks.exitCode, 1);
    EXPECT_NE(sinks.err.find("does not float"), std::string::npos) << sinks.err;
    const fs::path good = writeProject("bad", kRadiation);
    const CommandOutput noBody = runPlimsoll("hydro '" + good.string() + "' --body nosuch");
    EXPECT_EQ(noBody.exitCode, 1);
    EXPECT_NE(noBody.err.find("no body named 'nosuch'"), std::string::npos) << noBody.err;
    EXPECT_EQ(runPlimsoll("hydro").exitCode, 2);
    const CommandOutput unwritable =
        runPlimsoll("hydro '" + good.string() + "' --no-convergence --svg /no/such/folder/ab.svg");
    EXPECT_EQ(unwritable.exitCode, 1);
    EXPECT_NE(unwritable.err.find("/no/such/folder"), std::string::npos) << unwritable.err;
}

}  // namespace
}  // namespace test_cli_hydro
}  // namespace plimsoll
