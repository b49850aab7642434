// `plimsoll hydrostatics` end to end on the box of projects/box_half_draft.plim.json (1 x 0.5 x
// 0.25 m, density 500, upright in its own axes): its figures against the closed forms, both
// methods and their difference, the GZ plot, and the errors on bad input.
#include "cli_runner.h"
#include "test_support.h"

#include <nlohmann/json.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <string>

namespace plimsoll {
namespace test_cli_hydrostatics {
namespace {

using test::CommandOutput;
using test::runPlimsoll;

const std::string kProject =
    std::string(PLIMSOLL_SOURCE_DIR) + "/projects/box_half_draft.plim.json";

// The box's closed forms: length 1 (x), height 0.5 (y), beam 0.25 (z), half submerged.
constexpr double kDraft = 0.25, kKb = 0.125, kKg = 0.25;
constexpr double kBmTransverse = 0.25 * 0.25 / (12 * kDraft);
constexpr double kBmLongitudinal = 1.0 / (12 * kDraft);

nlohmann::json hydrostaticsJson(const std::string& arguments) {
    const CommandOutput r = runPlimsoll("hydrostatics '" + kProject + "' --json " + arguments);
    EXPECT_EQ(r.exitCode, 0) << r.err;
    if (r.exitCode != 0) return nlohmann::json::object();
    return nlohmann::json::parse(r.out);
}

void expectBox(const nlohmann::json& j, double relative) {
    auto near = [&](const char* key, double want) {
        EXPECT_NEAR(j.at(key).get<double>(), want, relative * std::abs(want))
            << key << " (" << j.at("method") << ")";
    };
    near("draft", kDraft);
    near("displacement", 1.0 * 0.25 * kDraft);
    near("waterplane_area", 0.25);
    near("kb", kKb);
    near("bm_transverse", kBmTransverse);
    near("bm_longitudinal", kBmLongitudinal);
    near("gm_transverse", kKb + kBmTransverse - kKg);
    near("gm_longitudinal", kKb + kBmLongitudinal - kKg);
    EXPECT_NEAR(j.at("heel_deg").get<double>(), 0.0, 1e-9);
    EXPECT_NEAR(j.at("trim_deg").get<double>(), 0.0, 1e-9);
}

TEST(CliHydrostatics, ExactClipOfTheBoxMatchesItsClosedForms) {
    const nlohmann::json j = hydrostaticsJson("--exact");
    ASSERT_FALSE(j.empty());
    EXPECT_EQ(j.at("method"), "exact");
    EXPECT_FALSE(j.contains("exact"));
    expectBox(j, 1e-6);
    // Taller than wide across: a negative GM, no righting range, and the 37 points of the
    // default 5 degree curve from 0 to 180 degrees.
    EXPECT_LT(j.at("gm_transverse").get<double>(), 0.0);
    EXPECT_NEAR(j.at("vanishing_stability_deg").get<double>(), 0.0, 1e-9);
    ASSERT_EQ(j.at("gz").size(), 37u);
    EXPECT_DOUBLE_EQ(j.at("gz")[36][0].get<double>(), 180.0);
    EXPECT_LT(j.at("gz")[1][1].get<double>(), 0.0);
}

TEST(CliHydrostatics, TexturesBesideTheExactClip) {
    const nlohmann::json j = hydrostaticsJson("--step 10");
    ASSERT_FALSE(j.empty());
    EXPECT_EQ(j.at("method"), "textures");
    EXPECT_EQ(j.at("texture_size"), 128);
    expectBox(j, 1e-4);
    ASSERT_TRUE(j.contains("exact"));
    expectBox(j.at("exact"), 1e-6);
    ASSERT_EQ(j.at("gz").size(), 19u);
    for (std::size_t i = 0; i < j.at("gz").size(); ++i) {
        EXPECT_NEAR(j.at("gz")[i][1].get<double>(), j.at("exact").at("gz")[i][1].get<double>(),
                    1e-3 * 0.25)
            << j.at("gz")[i][0];
    }
}

TEST(CliHydrostatics, TableShowsBothMethodsAndTheSvgTheCurve) {
    const std::string svg = (test::scratchFolder("cli_hydrostatics") / "gz.svg").string();
    const CommandOutput r = runPlimsoll("hydrostatics '" + kProject + "' --svg '" + svg + "'");
    ASSERT_EQ(r.exitCode, 0) << r.err;
    EXPECT_NE(r.out.find("difference"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("GM transverse"), std::string::npos) << r.out;
    const std::string plot = test::readFile(svg);
    EXPECT_EQ(plot.rfind("<svg", 0), 0u);
    EXPECT_NE(plot.find("<polyline"), std::string::npos);
    EXPECT_NE(plot.find("textures"), std::string::npos);
}

TEST(CliHydrostatics, BadInputIsRefusedClearly) {
    const CommandOutput noBody = runPlimsoll("hydrostatics '" + kProject + "' --body nosuch");
    EXPECT_EQ(noBody.exitCode, 1);
    EXPECT_NE(noBody.err.find("no body named 'nosuch'"), std::string::npos) << noBody.err;
    EXPECT_NE(noBody.err.find("'box'"), std::string::npos) << noBody.err;

    const CommandOutput missing = runPlimsoll("hydrostatics /no/such/project.plim.json");
    EXPECT_EQ(missing.exitCode, 1);
    EXPECT_NE(missing.err.find("/no/such/project.plim.json"), std::string::npos) << missing.err;

    EXPECT_EQ(runPlimsoll("hydrostatics '" + kProject + "' --step 0").exitCode, 2);
    EXPECT_EQ(runPlimsoll("hydrostatics '" + kProject + "' --step nan").exitCode, 2);
    EXPECT_EQ(runPlimsoll("hydrostatics").exitCode, 2);
    const CommandOutput unwritable =
        runPlimsoll("hydrostatics '" + kProject + "' --exact --svg /no/such/folder/gz.svg");
    EXPECT_EQ(unwritable.exitCode, 1);
    EXPECT_NE(unwritable.err.find("/no/such/folder"), std::string::npos) << unwritable.err;
}

}  // namespace
}  // namespace test_cli_hydrostatics
}  // namespace plimsoll
