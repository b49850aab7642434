// `plimsoll hydrostatics` end to end on the box of projects/box_half_draft.plim.json (1 x 0.5 x
// 0.25 m, density 500, upright in its own axes): its figures against the closed forms, both
// methods and their difference, the GZ plot, the stability report (and the damaged boat's
// downflooding), and the errors on bad input.
#include "cli_runner.h"
#include "test_support.h"

#include <nlohmann/json.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
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
    for (const char* row : {"TPC (t/cm)", "MCT1cm (t m/cm)", "GZ max (m)",
                            "downflooding angle (deg)", "IMO 2008 IS Code", "area_0_30 (m rad)",
                            "verdict", "KN (m), textures", "KN (m), exact"}) {
        EXPECT_NE(r.out.find(row), std::string::npos) << row << "\n" << r.out;
    }
    const std::string plot = test::readFile(svg);
    EXPECT_EQ(plot.rfind("<svg", 0), 0u);
    EXPECT_NE(plot.find("<polyline"), std::string::npos);
    EXPECT_NE(plot.find("textures"), std::string::npos);
}

TEST(CliHydrostatics, StabilityReportOfTheBox) {
    // TPC = rho A_wp / 10^5 = 1000 * 0.25 / 10^5; MCT1cm = Delta GM_L / (100 L) with
    // Delta = 0.0625 t and L = 1 m, the waterline's length; no openings; KN at each
    // displacement: wall-sided for the box's own, and 0.25 m (the keel to the mid-plane) on
    // its side at 90 degrees for every displacement; the IS Code fails on its negative GM.
    const nlohmann::json j = hydrostaticsJson("--exact");
    ASSERT_FALSE(j.empty());
    const double gmL = kKb + kBmLongitudinal - kKg;
    EXPECT_NEAR(j.at("tpc").get<double>(), 0.0025, 1e-9);
    EXPECT_NEAR(j.at("mct1cm").get<double>(), 0.0625 * gmL / 100, 1e-9);
    EXPECT_NEAR(j.at("waterline_length").get<double>(), 1.0, 1e-9);
    EXPECT_TRUE(j.at("downflooding_angle_deg").is_null());
    EXPECT_EQ(j.at("openings"), 0);
    EXPECT_GT(j.at("gz_max").get<double>(), 0.0);  // on its side, far over
    EXPECT_GT(j.at("gz_max_angle_deg").get<double>(), 90.0);
    const nlohmann::json& is = j.at("is_code_2008");
    EXPECT_EQ(is.at("pass"), false);
    const char* names[] = {"area_0_30", "area_0_40", "area_30_40", "gz_30", "angle_gz_max", "gm0"};
    const double required[] = {0.055, 0.09, 0.03, 0.20, 25.0, 0.15};
    ASSERT_EQ(is.at("criteria").size(), 6u);
    for (std::size_t i = 0; i < 6; ++i) {
        const nlohmann::json& c = is.at("criteria")[i];
        EXPECT_EQ(c.at("name"), names[i]);
        EXPECT_DOUBLE_EQ(c.at("required").get<double>(), required[i]);
        EXPECT_EQ(c.at("pass").get<bool>(), c.at("value").get<double>() >= required[i]) << names[i];
    }
    EXPECT_NEAR(is.at("criteria")[5].at("value").get<double>(), kKb + kBmTransverse - kKg, 1e-6);
    const nlohmann::json& curves = j.at("kn_cross_curves");
    ASSERT_EQ(curves.size(), 5u);
    for (const nlohmann::json& c : curves) {
        const nlohmann::json& last = c.at("kn").back();
        EXPECT_DOUBLE_EQ(last[0].get<double>(), 90.0);
        EXPECT_NEAR(last[1].get<double>(), 0.25, 1e-6) << c.at("displacement");
    }
    const nlohmann::json& own = curves[2];
    EXPECT_NEAR(own.at("displacement").get<double>(), 0.0625, 1e-12);
    EXPECT_NEAR(own.at("displacement_t").get<double>(), 0.0625, 1e-12);
    for (const nlohmann::json& p : own.at("kn")) {
        const double heel = p[0].get<double>() * std::numbers::pi / 180;
        if (p[0].get<double>() > 60) continue;  // the deck edge immerses at 63 degrees
        const double t = std::tan(heel);
        EXPECT_NEAR(p[1].get<double>(),
                    std::sin(heel) * (kKb + kBmTransverse + kBmTransverse / 2 * t * t), 1e-6)
            << p[0];
    }
}

TEST(CliHydrostatics, DamagedBoatFloodsUpright) {
    // The damaged boat's stern is painted permeable under its waterline: its openings are
    // under water upright, so its downflooding angle is 0 and no area to 40 degrees counts.
    const std::string boat = std::string(PLIMSOLL_SOURCE_DIR) + "/projects/damaged_boat.plim.json";
    const CommandOutput r = runPlimsoll("hydrostatics '" + boat + "' --exact --json --step 30");
    ASSERT_EQ(r.exitCode, 0) << r.err;
    const nlohmann::json j = nlohmann::json::parse(r.out);
    EXPECT_GT(j.at("openings").get<int>(), 0);
    EXPECT_EQ(j.at("downflooding_angle_deg"), 0.0);
    EXPECT_EQ(j.at("is_code_2008").at("criteria")[1].at("value"), 0.0);
    EXPECT_EQ(j.at("is_code_2008").at("pass"), false);
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
