// Every sample project in projects/ runs headless through `plimsoll simulate`, and its
// trajectory meets a physical expectation (not a stored copy of its own output).
#include "cli_runner.h"
#include "test_support.h"

#include <Eigen/Geometry>

#include <fstream>
#include <sstream>

namespace plimsoll {
namespace test_projects {
namespace {

namespace fs = std::filesystem;

struct Row {
    double time;
    Eigen::Vector3d position;  // centre of mass, world
    Eigen::Quaterniond orientation;
    Eigen::Vector3d velocity, angularVelocity;
    double submergedVolume;
    Eigen::Vector3d buoyantForce;
    double mass;
    Eigen::Vector3d centerOfMass;  // object space
};

/// Runs the project for `seconds` and reads its trajectory CSV.
std::vector<Row> simulate(const std::string& project, double seconds) {
    const fs::path csv = fs::temp_directory_path() / "plimsoll_tests" /
                         (project + "_" + std::to_string(::getpid()) + ".csv");
    const fs::path file = fs::path(PLIMSOLL_SOURCE_DIR) / "projects" / (project + ".plim.json");
    const test::CommandOutput r =
        test::runPlimsoll("simulate '" + file.string() + "' --seconds " + std::to_string(seconds) +
                          " --out '" + csv.string() + "'");
    EXPECT_EQ(r.exitCode, 0) << r.err;
    std::vector<Row> rows;
    std::ifstream in(csv);
    std::string line;
    std::getline(in, line);  // header
    while (std::getline(in, line)) {
        std::stringstream fields(line);
        std::string cell;
        std::vector<double> v;
        int column = 0;
        while (std::getline(fields, cell, ',')) {
            if (column++ != 1) v.push_back(std::stod(cell));  // column 1: body name
        }
        if (v.size() != 22) continue;
        Row row;
        row.time = v[0];
        row.position = {v[1], v[2], v[3]};
        row.orientation = Eigen::Quaterniond(v[4], v[5], v[6], v[7]);
        row.velocity = {v[8], v[9], v[10]};
        row.angularVelocity = {v[11], v[12], v[13]};
        row.submergedVolume = v[14];
        row.buoyantForce = {v[15], v[16], v[17]};
        row.mass = v[18];
        row.centerOfMass = {v[19], v[20], v[21]};
        rows.push_back(row);
    }
    fs::remove(csv);
    EXPECT_FALSE(rows.empty()) << project;
    return rows;
}

double meanSubmerged(const std::vector<Row>& rows, double from) {
    double sum = 0;
    int n = 0;
    for (const Row& r : rows) {
        if (r.time < from) continue;
        sum += r.submergedVolume;
        ++n;
    }
    return n ? sum / n : 0.0;
}

TEST(SampleProjects, BuoyRidesTheWavesAtItsDraft) {
    const std::vector<Row> rows = simulate("buoy", 5.0);
    ASSERT_FALSE(rows.empty());
    // Archimedes on average: the displaced sea water weighs what the buoy weighs.
    const double displaced = rows.front().mass / 1025.0;
    EXPECT_NEAR(meanSubmerged(rows, 1.0), displaced, 0.1 * displaced);
    double meanHeight = 0;
    for (const Row& r : rows) meanHeight += r.position.y() / rows.size();
    for (const Row& r : rows) {
        ASSERT_TRUE(r.position.allFinite());
        // Bobbing with waves of 0.17 m at most, once the start has settled.
        if (r.time > 2.0) EXPECT_LT(std::abs(r.position.y() - meanHeight), 0.3) << r.time;
        // Stable: it never heels past 30 degrees.
        const Eigen::Vector3d up = r.orientation * Eigen::Vector3d::UnitY();
        EXPECT_GT(up.y(), std::cos(30.0 * 3.141592653589793 / 180.0)) << r.time;
    }
}

TEST(SampleProjects, UniformBallIsNeutral) {
    const std::vector<Row> rows = simulate("neutral_ball", 5.0);
    ASSERT_FALSE(rows.empty());
    const Row& last = rows.back();
    EXPECT_NEAR(last.submergedVolume, last.mass / 1000.0, 0.01 * last.mass / 1000.0);
    // No righting torque whatever its orientation, but for the facets: this 64 x 32 polyhedron
    // turned (35, 0, 20) degrees has its centre of buoyancy 1.5e-4 m off the vertical through
    // its centre, 0.34 N m of torque by the textures and by the exact clip alike, so it drifts
    // a few degrees towards a facet's rest, not the ninety a ball with a heavy side turns.
    EXPECT_LT(last.angularVelocity.norm(), 0.1);
    const double turned =
        2 * std::acos(std::min(1.0, std::abs(last.orientation.dot(rows.front().orientation))));
    EXPECT_LT(turned, 15.0 * 3.141592653589793 / 180.0);
}

TEST(SampleProjects, HeavySideTurnsDown) {
    const std::vector<Row> rows = simulate("heavy_side_ball", 15.0);
    ASSERT_FALSE(rows.empty());
    auto offsetOf = [](const Row& r) {
        // Centre of mass relative to the ball's centre (the mesh origin), world axes.
        return Eigen::Vector3d(r.orientation * r.centerOfMass);
    };
    const Eigen::Vector3d start = offsetOf(rows.front()), end = offsetOf(rows.back());
    EXPECT_LT(std::abs(start.y()), 0.1 * start.norm());  // starts sideways
    EXPECT_LT(end.y(), -0.95 * end.norm());              // ends pointing down
}

TEST(SampleProjects, FlatBoxSettlesAtHalfDraft) {
    const std::vector<Row> rows = simulate("box_half_draft", 10.0);
    ASSERT_FALSE(rows.empty());
    const double displaced = rows.front().mass / 1000.0;
    EXPECT_NEAR(meanSubmerged(rows, 6.0), displaced, 0.02 * displaced);
    // It stays lying flat: its short side (object y, turned onto the world's z) stays level.
    const Eigen::Vector3d axis = rows.back().orientation * Eigen::Vector3d::UnitY();
    EXPECT_LT(std::abs(axis.y()), std::sin(5.0 * 3.141592653589793 / 180.0));
}

TEST(SampleProjects, BalloonLiftGrowsAsItInflates) {
    const std::vector<Row> rows = simulate("balloon", 1.9);
    ASSERT_GT(rows.size(), 10u);
    // 24 frames at 12 fps: the radius doubles over 2 s, the volume grows eightfold.
    const double first = rows.front().buoyantForce.y(), last = rows.back().buoyantForce.y();
    EXPECT_GT(first, 0.0);
    EXPECT_GT(last / first, 5.0);
    EXPECT_GT(rows.back().velocity.y(), 0.0);  // it rises
}

}  // namespace
}  // namespace test_projects
}  // namespace plimsoll
