// What the artist previews is what the game gets: every sample project's body, exported as a
// bundle, replayed by the runtime (plimsoll_runtime::Simulation, and the installed example's
// `float_body BUNDLE SECONDS --csv FILE` through the C API) and by the editor's World on the
// fast CPU path (what `plimsoll simulate` runs), 20 s each, on the project's own water and on
// waves, flooding included. Both evaluate the same sample list with the same evaluation core;
// the steps are the same sequence of operations written twice (Eigen in the World, the core's
// vectors in the runtime), so rigid bodies agree to rounding, which the floating bodies do not
// amplify: within 1e-6 m on the centre of mass over the whole run (about 2e-7 m measured),
// with the engine's water or the runtime's own model (double-precision waves against the
// World's single-precision sines). A flooding body's water exchange runs per point in the
// runtime and in one backend pass in the World, which differ by about 1e-6 of the flow; that
// difference in the water moves the body, within 5e-4 m over 20 s (0.12 mm measured, the plush
// toy on flat water; 0.20 mm the damaged boat, whose heave the radiating body's lower stand-in
// damps less: 2e-7 m with linear_damping 0.5). The figures are printed.
#include "test_support.h"
#include "world_support.h"

#include "plimsoll/export/bundle.h"
#include "plimsoll/project/project.h"

#include "plimsoll_runtime.h"
#include "plimsoll_runtime/runtime.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <cstdlib>
#include <fstream>
#include <numbers>
#include <random>
#include <sstream>
#include <unistd.h>

namespace plimsoll {
namespace test_runtime_trajectory {
namespace {

namespace fs = std::filesystem;
namespace rt = plimsoll_runtime;

/// Simulated time of each comparison. The sanitized build runs the two step sequences about
/// twenty times slower and checks their memory, which the first seconds exercise as fully.
constexpr double kSeconds = test::kSanitizedBuild ? 4.0 : 20.0;
/// A rigid body: the two step sequences differ by rounding only.
constexpr double kRigidBound = 1e-6;  // m
/// A flooding body: the water exchange's own differences (about 1e-6 of the flow) move it.
constexpr double kFloodingBound = 5e-4;  // m

WaterModel testWaves() {
    WaterModel water;
    water.kind = WaterModel::Kind::Gerstner;
    GerstnerWave a;
    a.amplitude = 0.12;
    a.wavelength = 9.0;
    a.direction = {1.0, 0.2};
    a.steepness = 0.5;
    GerstnerWave b;
    b.amplitude = 0.05;
    b.wavelength = 4.0;
    b.direction = {0.3, 1.0};
    b.steepness = 0.4;
    b.phase = 1.3;
    water.waves = {a, b};
    return water;
}

/// The engine's own water as the runtime's callbacks: the same heights to the bit.
rt::Water engineWater(const WaterModel& water) {
    rt::Water w;
    w.level = water.level;
    if (water.kind == WaterModel::Kind::Flat) return w;
    w.height = [&water](double x, double z, double t) { return water.height(x, z, t); };
    w.heights = [&water](std::size_t n, const double* x, const double* z, double t, double* out) {
        water.heights(n, x, z, t, out);
    };
    w.velocities = [&water](std::size_t n, const double* x, const double* y, const double* z,
                            double t, double* out) { water.velocities(n, x, y, z, t, out); };
    w.minHeight = water.minHeight();
    w.maxHeight = water.maxHeight();
    return w;
}

struct Frame {
    double time;
    Eigen::Vector3d center;
    Eigen::Vector4d q;  // w, x, y, z
    double mass;
    bool asleep;
};

std::vector<Frame> worldRun(const Project& project, long frames) {
    std::vector<Frame> out;
    std::unique_ptr<World> world = test::fastWorldOrFail(test::sceneOrFail(project));
    if (!world) return out;
    for (long f = 0; f < frames; ++f) {
        EXPECT_TRUE(world->advanceFrame().ok());
        const SimulatedBody& b = world->bodies().front();
        const Eigen::Quaterniond& q = b.state.orientation;
        out.push_back(
            {world->time(), b.state.position, {q.w(), q.x(), q.y(), q.z()}, b.mass.mass, b.asleep});
    }
    return out;
}

std::vector<Frame> runtimeRun(rt::Bundle& bundle, const rt::Water& water, long frames) {
    std::vector<Frame> out;
    std::string error;
    std::unique_ptr<rt::Simulation> s = rt::Simulation::create(bundle, error);
    EXPECT_TRUE(s) << error;
    if (!s) return out;
    for (long f = 0; f < frames; ++f) {
        EXPECT_TRUE(s->advanceFrame(water, error)) << error;
        const rt::Vec3& c = s->centerOfMass();
        const rt::Quat& q = s->orientation();
        out.push_back(
            {s->time(), {c.x, c.y, c.z}, {q.w, q.x, q.y, q.z}, s->mass().mass, s->asleep()});
    }
    return out;
}

struct Gap {
    double position = 0, orientation = 0, mass = 0, travel = 0;
    long sleptFrames = 0;  ///< frames both runs slept through
};

Gap compare(const std::vector<Frame>& a, const std::vector<Frame>& b) {
    Gap g;
    EXPECT_EQ(a.size(), b.size());
    for (std::size_t i = 0; i < std::min(a.size(), b.size()); ++i) {
        EXPECT_NEAR(a[i].time, b[i].time, 1e-9);
        // Both fall asleep and wake on the same frames: one rule (plimsoll_eval/sleep.hpp).
        EXPECT_EQ(a[i].asleep, b[i].asleep) << "frame " << i;
        g.sleptFrames += a[i].asleep && b[i].asleep;
        g.position = std::max(g.position, (a[i].center - b[i].center).norm());
        g.orientation =
            std::max(g.orientation, std::min((a[i].q - b[i].q).norm(), (a[i].q + b[i].q).norm()));
        g.mass = std::max(g.mass, std::abs(a[i].mass - b[i].mass) / a[i].mass);
        g.travel = std::max(g.travel, (a[i].center - a.front().center).norm());
    }
    return g;
}

/// Every sample project's rigid bodies, and each flat one again on waves.
class RuntimeTrajectory : public testing::Test {
protected:
    static fs::path root() {
        static const fs::path r = [] {
            const fs::path p =
                test::scratchFolder("runtime_trajectory-" + std::to_string(::getpid()));
            fs::remove_all(p);
            fs::create_directories(p);
            fs::copy(fs::path(PLIMSOLL_SOURCE_DIR) / "assets", p / "assets",
                     fs::copy_options::recursive);
            fs::copy(fs::path(PLIMSOLL_SOURCE_DIR) / "projects", p / "projects",
                     fs::copy_options::recursive);
            return p;
        }();
        return r;
    }
    static void TearDownTestSuite() { fs::remove_all(root()); }

    /// The sample projects, each flat one also on waves (named "<stem>+waves").
    static std::vector<Project> cases() {
        std::vector<fs::path> files;
        for (const auto& entry : fs::directory_iterator(root() / "projects")) {
            const std::string name = entry.path().filename().string();
            if (name.size() > 10 && name.substr(name.size() - 10) == ".plim.json")
                files.push_back(entry.path());
        }
        std::sort(files.begin(), files.end());
        std::vector<Project> out;
        for (const fs::path& file : files) {
            Result<Project> project = loadProject(file);
            EXPECT_TRUE(project.ok()) << project.error().message;
            if (!project.ok()) continue;
            if (project->bodies.size() != 1 || project->bodies[0].deforms()) {
                // A deforming body's frames are the engine's (the runtime reads frame 0 only).
                std::printf("  %s: skipped (a deforming body: the runtime steps rigid bodies)\n",
                            project->fileStem.c_str());
                continue;
            }
            out.push_back(*project);
            if (project->water.kind == WaterModel::Kind::Flat && project->medium.density > 100) {
                Project wavy = *project;
                wavy.water = testWaves();
                wavy.water.level = project->water.level;
                wavy.fileStem += "+waves";
                out.push_back(std::move(wavy));
            }
        }
        return out;
    }

    /// The sample box with strong damping: it comes to rest, and sleeps, within seconds.
    static Project dampedBox() {
        Result<Project> loaded = loadProject(root() / "projects" / "box_half_draft.plim.json");
        EXPECT_TRUE(loaded.ok()) << loaded.error().message;
        Project project = loaded.ok() ? *loaded : Project{};
        project.fileStem = "box_half_draft+damped";
        project.bodies[0].linearDamping = 4.0;
        project.bodies[0].angularDamping = 4.0;
        return project;
    }

    /// The bundle of `project`'s body, exported once per process.
    static fs::path exported(const Project& project) {
        const fs::path folder = root() / "out" / project.fileStem;
        if (!fs::exists(folder / "manifest.json")) {
            Result<BundleReport> report = writeBodyBundle(project, 0, folder);
            EXPECT_TRUE(report.ok()) << report.error().message;
        }
        return folder;
    }
};

TEST_F(RuntimeTrajectory, EverySampleProjectFollowsTheWorld) {
    const std::vector<Project> projects = cases();
    ASSERT_GE(projects.size(), 8u);
    bool sawFlooding = false, sawWaves = false;
    const long frames =
        static_cast<long>(std::ceil(kSeconds / projects.front().simulation.timeStep - 1e-9));
    for (const Project& project : projects) {
        SCOPED_TRACE(project.fileStem);
        const fs::path folder = exported(project);
        std::string error;
        std::unique_ptr<rt::Bundle> bundle = rt::loadBundle(folder.string(), error);
        ASSERT_TRUE(bundle) << error;
        ASSERT_TRUE(bundle->world().present);
        EXPECT_EQ(bundle->fluid().density, project.medium.density);
        const std::vector<Frame> world = worldRun(project, frames);
        // Both runs on one bundle: each Simulation steps its own water from the exported start.
        const std::vector<Frame> same = runtimeRun(*bundle, engineWater(project.water), frames);
        const rt::Water own = bundle->world().water.water();
        const std::vector<Frame> mine = runtimeRun(*bundle, own, frames);
        const Gap g = compare(world, same), h = compare(world, mine);
        const bool floods = bundle->graph() != nullptr;
        sawFlooding |= floods;
        sawWaves |= project.water.kind == WaterModel::Kind::Gerstner;
        std::printf(
            "  %-22s %s%s: travel %.3f m; runtime vs World, same water: %.2e m, %.2e (q), mass "
            "%.1e; "
            "own water: %.2e m; asleep %ld frames\n",
            project.fileStem.c_str(),
            project.water.kind == WaterModel::Kind::Flat ? "flat " : "waves",
            floods ? " floods" : "       ", g.travel, g.position, g.orientation, g.mass, h.position,
            g.sleptFrames);
        const double bound = floods ? kFloodingBound : kRigidBound;
        EXPECT_LE(g.position, bound);
        EXPECT_LE(h.position, bound);
        // The run must do something: a body that never moved would pass any bound (the
        // neutral ball on flat water, let go in equilibrium, moves least: 0.4 mm in 20 s, 8 um
        // in the sanitized build's 4 s).
        EXPECT_GT(g.travel, test::kSanitizedBuild ? 1e-6 : 1e-4);
    }
    EXPECT_TRUE(sawFlooding);
    EXPECT_TRUE(sawWaves);
}

// Sleeping: a damped box comes to rest; the runtime's Simulation falls asleep on the World's
// frame, stays where the World holds it, and a snapshot taken asleep restores asleep.
TEST_F(RuntimeTrajectory, ARestingBodySleepsOnTheWorldsFrame) {
    const Project project = dampedBox();
    const fs::path folder = exported(project);
    std::string error;
    std::unique_ptr<rt::Bundle> bundle = rt::loadBundle(folder.string(), error);
    ASSERT_TRUE(bundle) << error;
    ASSERT_TRUE(bundle->world().sleep.enabled);
    const long frames = 900;  // 15 s
    const std::vector<Frame> world = worldRun(project, frames);
    const std::vector<Frame> runtime = runtimeRun(*bundle, bundle->world().water.water(), frames);
    const Gap g = compare(world, runtime);
    EXPECT_GT(g.sleptFrames, 300) << "the box did not sleep its last 5 s";
    EXPECT_LE(g.position, kRigidBound);

    std::unique_ptr<rt::Simulation> s = rt::Simulation::create(*bundle, error);
    ASSERT_TRUE(s) << error;
    const rt::Water water = bundle->world().water.water();
    while (!s->asleep() && s->time() < 15.0) ASSERT_TRUE(s->advanceFrame(water, error)) << error;
    ASSERT_TRUE(s->asleep());
    const std::vector<std::uint8_t> snapshot = s->save();
    std::unique_ptr<rt::Simulation> copy = rt::Simulation::create(*bundle, error);
    ASSERT_TRUE(copy->restore(snapshot, error)) << error;
    EXPECT_TRUE(copy->asleep());
    for (int f = 0; f < 60; ++f) {
        ASSERT_TRUE(s->advanceFrame(water, error));
        ASSERT_TRUE(copy->advanceFrame(water, error));
        ASSERT_EQ(s->stateHash(), copy->stateHash()) << "frame " << f;
    }
    // Asleep, the body stays put; wake() and a push of the water wake it.
    const rt::Vec3 at = s->centerOfMass();
    ASSERT_TRUE(s->advanceFrame(water, error));
    EXPECT_EQ(s->centerOfMass().y, at.y);
    s->wake();
    EXPECT_FALSE(s->asleep());
    rt::WaterModel raised = bundle->world().water;
    raised.level += 0.01;
    ASSERT_TRUE(copy->advanceFrame(raised.water(), error));
    EXPECT_FALSE(copy->asleep());
}

// Snapshots: saved at a random frame k and restored into a fresh simulation of a freshly
// loaded bundle, the run continues with the same state hash every frame, bit for bit.
TEST_F(RuntimeTrajectory, RestoreAtARandomFrameContinuesBitForBit) {
    const std::vector<Project> projects = cases();
    ASSERT_GE(projects.size(), 8u);
    std::mt19937 rng(20261205);
    const long frames = 300;
    for (const Project& project : projects) {
        SCOPED_TRACE(project.fileStem);
        const fs::path folder = exported(project);
        std::string error;
        std::unique_ptr<rt::Bundle> bundle = rt::loadBundle(folder.string(), error);
        ASSERT_TRUE(bundle) << error;
        const rt::Water water = bundle->world().water.water();
        std::unique_ptr<rt::Simulation> a = rt::Simulation::create(*bundle, error);
        ASSERT_TRUE(a) << error;
        const long k = std::uniform_int_distribution<long>(1, frames - 1)(rng);
        std::vector<std::uint64_t> hashes;
        std::vector<std::uint8_t> snapshot;
        for (long f = 0; f < frames; ++f) {
            if (f == k) snapshot = a->save();
            ASSERT_TRUE(a->advanceFrame(water, error)) << error;
            hashes.push_back(a->stateHash());
        }
        // The hash follows the state: a run that changes nothing would make this test vacuous.
        EXPECT_NE(hashes[k], hashes[frames - 1]);
        std::unique_ptr<rt::Bundle> again = rt::loadBundle(folder.string(), error);
        ASSERT_TRUE(again) << error;
        std::unique_ptr<rt::Simulation> b = rt::Simulation::create(*again, error);
        ASSERT_TRUE(b) << error;
        ASSERT_TRUE(b->restore(snapshot, error)) << error;
        for (long f = k; f < frames; ++f) {
            ASSERT_TRUE(b->advanceFrame(water, error)) << error;
            ASSERT_EQ(b->stateHash(), hashes[f]) << "frame " << f << " after a restore at " << k;
        }
        EXPECT_EQ(b->centerOfMass().y, a->centerOfMass().y);
        if (b->graph()) {
            for (std::size_t n = 0; n < b->graph()->nodeCount(); ++n)
                EXPECT_EQ(b->graph()->water(n), a->graph()->water(n)) << n;
        }
        // A damaged snapshot is refused and changes nothing.
        const std::uint64_t before = b->stateHash();
        std::vector<std::uint8_t> cut(snapshot.begin(), snapshot.end() - 3);
        EXPECT_FALSE(b->restore(cut, error));
        EXPECT_EQ(b->stateHash(), before);
        std::printf("  %-22s restored at frame %3ld of %ld: %zu bytes, hashes equal to the end\n",
                    project.fileStem.c_str(), k, frames, snapshot.size());
    }
}

double nanHeight(void*, double, double, double) { return std::nan(""); }

// The C API: every call clears the last error when it succeeds and sets it when it fails, misuse
// included; the header's version is the library's; a simulation snapshot round-trips through C.
TEST_F(RuntimeTrajectory, CApiReportsMisuseAndClearsTheError) {
    int major = -1, minor = -1, patch = -1;
    plimsoll_runtime_version(&major, &minor, &patch);
    EXPECT_EQ(major, PLIMSOLL_RUNTIME_VERSION_MAJOR);
    EXPECT_EQ(minor, PLIMSOLL_RUNTIME_VERSION_MINOR);
    EXPECT_EQ(patch, PLIMSOLL_RUNTIME_VERSION_PATCH);
    Result<Project> project = loadProject(root() / "projects" / "damaged_boat.plim.json");
    ASSERT_TRUE(project.ok()) << project.error().message;
    plimsoll_bundle* boat = plimsoll_bundle_load(exported(*project).string().c_str(), 1);
    ASSERT_NE(boat, nullptr) << plimsoll_runtime_last_error();
    EXPECT_STREQ(plimsoll_runtime_last_error(), "");

    const plimsoll_mass none = plimsoll_bundle_mass(nullptr);
    EXPECT_EQ(none.mass, 0.0);
    EXPECT_STREQ(plimsoll_runtime_last_error(), "plimsoll_bundle_mass: bundle is NULL");
    EXPECT_GT(plimsoll_bundle_sample_count(boat), 0u);
    EXPECT_STREQ(plimsoll_runtime_last_error(), "");  // a success clears it

    const std::size_t nodes = plimsoll_graph_node_count(boat);
    ASSERT_GT(nodes, 0u);
    EXPECT_EQ(plimsoll_graph_node_water(boat, nodes), 0.0);
    EXPECT_EQ(std::string(plimsoll_runtime_last_error()),
              "plimsoll_graph_node_water: no such node: " + std::to_string(nodes) + " of " +
                  std::to_string(nodes));

    // A water callback giving NaN is an error, not "no water moved".
    const plimsoll_pose pose = {{0.0, -0.3, 0.0}, {1.0, 0.0, 0.0, 0.0}};
    plimsoll_water water = {0.0, nanHeight, nullptr, nullptr};
    EXPECT_EQ(plimsoll_graph_step(boat, &pose, &water, 0.0, 0.01), -1);
    EXPECT_NE(std::string(plimsoll_runtime_last_error()).find("NaN"), std::string::npos)
        << plimsoll_runtime_last_error();
    water.height = nullptr;
    EXPECT_GE(plimsoll_graph_step(boat, &pose, &water, 0.0, 0.01), 0);
    EXPECT_STREQ(plimsoll_runtime_last_error(), "");
    plimsoll_bundle_destroy(boat);

    // A snapshot through C: saved after 30 frames, restored into a new simulation of a new
    // bundle, the next 30 frames give the same hashes.
    plimsoll_bundle* a = plimsoll_bundle_load(exported(*project).string().c_str(), 1);
    plimsoll_bundle* b = plimsoll_bundle_load(exported(*project).string().c_str(), 1);
    ASSERT_TRUE(a && b);
    plimsoll_simulation* sa = plimsoll_simulation_create(a);
    plimsoll_simulation* sb = plimsoll_simulation_create(b);
    ASSERT_TRUE(sa && sb) << plimsoll_runtime_last_error();
    for (int f = 0; f < 30; ++f) ASSERT_EQ(plimsoll_simulation_advance_frame(sa, nullptr), 1);
    std::size_t size = 0;
    ASSERT_EQ(plimsoll_simulation_save(sa, nullptr, 0, &size), 1);
    std::vector<unsigned char> bytes(size);
    EXPECT_EQ(plimsoll_simulation_save(sa, bytes.data(), size - 1, &size), 0);
    ASSERT_EQ(plimsoll_simulation_save(sa, bytes.data(), size, &size), 1);
    ASSERT_EQ(plimsoll_simulation_restore(sb, bytes.data(), bytes.size()), 1)
        << plimsoll_runtime_last_error();
    for (int f = 0; f < 30; ++f) {
        ASSERT_EQ(plimsoll_simulation_advance_frame(sa, nullptr), 1);
        ASSERT_EQ(plimsoll_simulation_advance_frame(sb, nullptr), 1);
        ASSERT_EQ(plimsoll_simulation_state_hash(sa), plimsoll_simulation_state_hash(sb)) << f;
    }
    EXPECT_EQ(plimsoll_simulation_restore(sb, bytes.data(), 7), 0);
    EXPECT_NE(std::string(plimsoll_runtime_last_error()).find("too short"), std::string::npos);
    EXPECT_EQ(plimsoll_simulation_create(nullptr), nullptr);
    EXPECT_STREQ(plimsoll_runtime_last_error(), "plimsoll_simulation_create: bundle is NULL");
    plimsoll_simulation_destroy(sa);
    plimsoll_simulation_destroy(sb);
    plimsoll_bundle_destroy(a);
    plimsoll_bundle_destroy(b);
}

/// `float_body BUNDLE SECONDS --csv FILE`: the columns of `plimsoll simulate --out`, the rows of
/// the World's run.
TEST_F(RuntimeTrajectory, FloatBodyWritesTheSimulateColumns) {
    Result<Project> project = loadProject(root() / "projects" / "damaged_boat.plim.json");
    ASSERT_TRUE(project.ok()) << project.error().message;
    const fs::path folder = root() / "out" / "csv_boat";
    ASSERT_TRUE(writeBodyBundle(*project, 0, folder).ok());
    const fs::path csv = root() / "boat.csv";
    const std::string command =
        std::string(PLIMSOLL_FLOAT_BODY) + " " + folder.string() + " 20 --csv " + csv.string();
    ASSERT_EQ(std::system(command.c_str()), 0) << command;
    std::ifstream in(csv);
    std::string header;
    std::getline(in, header);
    EXPECT_EQ(header,
              "time,body,x,y,z,qw,qx,qy,qz,vx,vy,vz,wx,wy,wz,submerged_volume,fx,fy,fz,mass,com_x,"
              "com_y,com_z");
    const long frames = static_cast<long>(std::ceil(20.0 / project->simulation.timeStep - 1e-9));
    const std::vector<Frame> world = worldRun(*project, frames);
    std::string line;
    long rows = 0;
    double worst = 0;
    while (std::getline(in, line)) {
        std::stringstream row(line);
        std::string cell;
        std::vector<std::string> cells;
        while (std::getline(row, cell, ',')) cells.push_back(cell);
        ASSERT_EQ(cells.size(), 23u) << line;
        ASSERT_LT(rows, static_cast<long>(world.size()));
        EXPECT_EQ(cells[1], "boat");
        EXPECT_NEAR(std::stod(cells[0]), world[rows].time, 1e-8);
        const Eigen::Vector3d x(std::stod(cells[2]), std::stod(cells[3]), std::stod(cells[4]));
        worst = std::max(worst, (x - world[rows].center).norm());
        // The water inside: the exchange's own differences (about 1e-6 of the flow), which the
        // boat's motion carries on: with the heave stand-in at 0.05 1/s (a radiating body's
        // default) it moves more, and the water follows within 4.7e-5 of the mass (4.7e-5 as
        // well with radiation and linear_damping 0.05 given, 2.6e-5 with radiation off and
        // 0.05 given; 5e-8 with radiation and 0.5 given: the step itself agrees).
        EXPECT_NEAR(std::stod(cells[19]), world[rows].mass, 1e-4 * world[rows].mass);
        ++rows;
    }
    EXPECT_EQ(rows, frames);
    std::printf(
        "  float_body --csv, damaged_boat, %ld rows: centre of mass within %.2e m of the World's\n",
        rows, worst);
    // The flooding bound of EverySampleProjectFollowsTheWorld (2.0e-4 m measured here).
    EXPECT_LE(worst, kFloodingBound);
}

// ---------------------------------------------------------------------------------------
// Instances: one loaded bundle, any number of bodies.

/// The runtime's water model behind the C API's callbacks (user points at the model).
double modelHeight(void* user, double x, double z, double time) {
    return static_cast<const rt::WaterModel*>(user)->height(x, z, time);
}
void modelHeights(void* user, size_t n, const double* x, const double* z, double time,
                  double* out) {
    for (size_t i = 0; i < n; ++i)
        out[i] = static_cast<const rt::WaterModel*>(user)->height(x[i], z[i], time);
}
plimsoll_water cWater(const rt::WaterModel& model) {
    plimsoll_water w{};
    w.level = model.level;
    if (model.kind == rt::WaterModel::Kind::Flat) return w;
    w.height = modelHeight;
    w.heights = modelHeights;
    w.user = const_cast<rt::WaterModel*>(&model);
    w.has_bounds = 1;
    w.min_height = model.minHeight();
    w.max_height = model.maxHeight();
    return w;
}

/// Let go a little above the water with a heel, body i of several a little apart.
plimsoll_body_state startState(double level, int i) {
    const double heel = (4.0 + 3.0 * i) * std::numbers::pi / 180.0;
    return {{{1.5 * i, level + 0.05 + 0.03 * i, -0.7 * i},
             {std::cos(heel / 2), std::sin(heel / 2), 0.0, 0.0}},
            {{0.0, 0.0, 0.0}, {0.0, 0.0, 0.0}}};
}

using BundleHandle = std::unique_ptr<plimsoll_bundle, decltype(&plimsoll_bundle_destroy)>;
using InstanceHandle = std::unique_ptr<plimsoll_instance, decltype(&plimsoll_instance_destroy)>;

BundleHandle loadC(const fs::path& folder) {
    BundleHandle b(plimsoll_bundle_load(folder.string().c_str(), 1), &plimsoll_bundle_destroy);
    EXPECT_TRUE(b) << plimsoll_runtime_last_error();
    return b;
}
InstanceHandle instanceOf(const plimsoll_bundle* bundle) {
    InstanceHandle i(plimsoll_instance_create(bundle), &plimsoll_instance_destroy);
    EXPECT_TRUE(i) << plimsoll_runtime_last_error();
    return i;
}

bool sameBits(const plimsoll_body_state& a, const plimsoll_body_state& b) {
    return std::memcmp(&a, &b, sizeof a) == 0;
}

// Three boats of one bundle step exactly as three boats that were each loaded on their own
// (the 1.x way): the same water in every node, the same loads, bit for bit; and the bundle's
// own water (what the 1.x calls step) stays as exported.
TEST_F(RuntimeTrajectory, InstancesOfOneBundleStepAsSeparateLoadsDid) {
    int flooding = 0;
    for (const Project& project : cases()) {
        const fs::path folder = exported(project);
        const BundleHandle shared = loadC(folder);
        ASSERT_TRUE(shared);
        const std::size_t nodes = plimsoll_graph_node_count(shared.get());
        if (nodes == 0) continue;
        SCOPED_TRACE(project.fileStem);
        ++flooding;
        std::string error;
        const std::unique_ptr<rt::Bundle> cpp = rt::loadBundle(folder.string(), error);
        ASSERT_TRUE(cpp) << error;
        const plimsoll_water water = cWater(cpp->world().water);
        const plimsoll_fluid fluid = plimsoll_bundle_default_fluid(shared.get());
        std::vector<InstanceHandle> instances;
        std::vector<BundleHandle> alone;
        for (int i = 0; i < 3; ++i) {
            instances.push_back(instanceOf(shared.get()));
            alone.push_back(loadC(folder));
        }
        const double dt = 1.0 / 60.0;
        double moved = 0;
        for (int step = 0; step < 240; ++step) {
            const double t = step * dt;
            for (int i = 0; i < 3; ++i) {
                plimsoll_pose pose = startState(cpp->world().water.level, i).pose;
                pose.position[1] -= 0.1 * (1 + i) + 0.05 * std::sin(2.0 * t + i);
                const plimsoll_velocity velocity = {{0.0, -0.1 * std::cos(2.0 * t + i), 0.0},
                                                    {0.0, 0.0, 0.0}};
                ASSERT_GE(plimsoll_instance_graph_step(instances[i].get(), &pose, &water, t, dt), 0)
                    << plimsoll_runtime_last_error();
                ASSERT_GE(plimsoll_graph_step(alone[i].get(), &pose, &water, t, dt), 0)
                    << plimsoll_runtime_last_error();
                plimsoll_load a{}, b{};
                ASSERT_EQ(plimsoll_instance_water_load(instances[i].get(), &pose, &velocity, &water,
                                                       &fluid, t, dt, &a),
                          1)
                    << plimsoll_runtime_last_error();
                ASSERT_EQ(plimsoll_bundle_water_load(alone[i].get(), &pose, &velocity, &water,
                                                     &fluid, t, dt, &b),
                          1);
                ASSERT_EQ(std::memcmp(&a, &b, sizeof a), 0) << "body " << i << ", step " << step;
                for (std::size_t n = 0; n < nodes; ++n) {
                    double mine = -1;
                    ASSERT_EQ(plimsoll_instance_node_water(instances[i].get(), n, &mine), 1);
                    ASSERT_EQ(mine, plimsoll_graph_node_water(alone[i].get(), n))
                        << "body " << i << ", node " << n;
                    moved = std::max(moved, mine);
                }
            }
        }
        // Water did come in, and the shared bundle's own water did not move.
        EXPECT_GT(moved, 0.0);
        for (std::size_t n = 0; n < nodes; ++n)
            EXPECT_EQ(plimsoll_graph_node_water(shared.get(), n), cpp->graph()->nodes()[n].water)
                << n;
    }
    EXPECT_GE(flooding, 2);
}

// An instance's snapshot (its water, random sequence and radiation memory) with the body's
// state, taken at a random step k and restored into an instance of a bundle loaded again,
// continues bit for bit: the same state hash and the same body state every step after, for
// every sample project.
TEST_F(RuntimeTrajectory, AnInstanceRestoredAtARandomStepContinuesBitForBit) {
    std::mt19937 rng(20261206);
    const int steps = 240;
    for (const Project& project : cases()) {
        SCOPED_TRACE(project.fileStem);
        const fs::path folder = exported(project);
        std::string error;
        const std::unique_ptr<rt::Bundle> cpp = rt::loadBundle(folder.string(), error);
        ASSERT_TRUE(cpp) << error;
        const plimsoll_water water = cWater(cpp->world().water);
        const BundleHandle first = loadC(folder), second = loadC(folder);
        ASSERT_TRUE(first && second);
        const plimsoll_fluid fluid = plimsoll_bundle_default_fluid(first.get());
        const InstanceHandle a = instanceOf(first.get()), b = instanceOf(second.get());
        const double dt = 1.0 / 120.0;
        const int k = std::uniform_int_distribution<int>(1, steps - 1)(rng);
        plimsoll_body_state state = startState(cpp->world().water.level, 0), saved{};
        std::vector<std::uint64_t> hashes;
        std::vector<plimsoll_body_state> states;
        std::vector<std::uint8_t> snapshot;
        for (int step = 0; step < steps; ++step) {
            if (step == k) {
                std::size_t size = 0;
                ASSERT_EQ(plimsoll_instance_save(a.get(), nullptr, 0, &size), 1);
                snapshot.resize(size);
                ASSERT_EQ(plimsoll_instance_save(a.get(), snapshot.data(), size, &size), 1);
                saved = state;
            }
            ASSERT_EQ(plimsoll_instance_step(a.get(), &state, &water, &fluid, step * dt, dt), 1)
                << plimsoll_runtime_last_error();
            hashes.push_back(plimsoll_instance_state_hash(a.get()));
            states.push_back(state);
        }
        if (plimsoll_graph_node_count(first.get()) > 0) EXPECT_NE(hashes[k], hashes.back());
        ASSERT_EQ(plimsoll_instance_restore(b.get(), snapshot.data(), snapshot.size()), 1)
            << plimsoll_runtime_last_error();
        for (int step = k; step < steps; ++step) {
            ASSERT_EQ(plimsoll_instance_step(b.get(), &saved, &water, &fluid, step * dt, dt), 1);
            ASSERT_EQ(plimsoll_instance_state_hash(b.get()), hashes[step])
                << "step " << step << " after k = " << k;
            ASSERT_TRUE(sameBits(saved, states[step])) << "step " << step << " after k = " << k;
        }
        // A cut snapshot is refused and changes nothing.
        const std::uint64_t before = plimsoll_instance_state_hash(b.get());
        EXPECT_EQ(plimsoll_instance_restore(b.get(), snapshot.data(), snapshot.size() - 1), 0);
        EXPECT_CONTAINS(plimsoll_runtime_last_error(), "plimsoll_instance_restore: snapshot:");
        EXPECT_EQ(plimsoll_instance_state_hash(b.get()), before);
    }
}

// Sleeping instances: stepped by the batch, damped boxes at rest on calm water fall asleep, cost
// a look at the water a step and leave their states alone; a velocity the game gives, a pose it
// sets, the water rising or plimsoll_instance_wake wake one; the sleep state is in the snapshot.
TEST_F(RuntimeTrajectory, InstancesSleepAtRestAndWakeOnTheGamesPushOrTheWater) {
    const Project project = dampedBox();
    const BundleHandle bundle = loadC(exported(project));
    ASSERT_TRUE(bundle);
    constexpr int kBodies = 3;
    std::vector<InstanceHandle> owned;
    std::vector<plimsoll_instance*> instances;
    std::vector<plimsoll_body_state> states;
    for (int i = 0; i < kBodies; ++i) {
        owned.push_back(instanceOf(bundle.get()));
        instances.push_back(owned.back().get());
        states.push_back(startState(0.0, i));
    }
    plimsoll_batch* batch = plimsoll_batch_create(nullptr);
    ASSERT_TRUE(batch);
    plimsoll_water water{};
    const double dt = 1.0 / 120.0;
    double t = 0;
    auto step = [&](const plimsoll_water& w) {
        ASSERT_EQ(plimsoll_batch_instance_step(batch, kBodies, instances.data(), states.data(), &w,
                                               nullptr, t, dt),
                  1)
            << plimsoll_runtime_last_error();
        t += dt;
    };
    for (int s = 0;
         s < 120 * 20 && !std::all_of(instances.begin(), instances.end(),
                                      [](auto* i) { return plimsoll_instance_asleep(i) == 1; });
         ++s)
        step(water);
    for (plimsoll_instance* i : instances) ASSERT_EQ(plimsoll_instance_asleep(i), 1);
    // Asleep: the states stay, bit for bit, and the velocities are zero.
    const std::vector<plimsoll_body_state> rest = states;
    for (int s = 0; s < 60; ++s) step(water);
    for (int i = 0; i < kBodies; ++i) {
        EXPECT_TRUE(sameBits(states[i], rest[i])) << i;
        EXPECT_EQ(states[i].velocity.linear[1], 0.0);
    }
    // Snapshot of a sleeping instance: restored into a fresh one, it sleeps too.
    std::vector<std::uint8_t> bytes(4096);
    std::size_t size = 0;
    ASSERT_EQ(plimsoll_instance_save(instances[0], bytes.data(), bytes.size(), &size), 1);
    const InstanceHandle copy = instanceOf(bundle.get());
    ASSERT_EQ(plimsoll_instance_restore(copy.get(), bytes.data(), size), 1);
    EXPECT_EQ(plimsoll_instance_asleep(copy.get()), 1);
    EXPECT_EQ(plimsoll_instance_state_hash(copy.get()), plimsoll_instance_state_hash(instances[0]));
    // The game pushes body 0 (a velocity), moves body 1 (a pose): both wake; body 2 sleeps on.
    states[0].velocity.linear[0] = 0.5;
    states[1].pose.position[0] += 2.0;
    step(water);
    EXPECT_EQ(plimsoll_instance_asleep(instances[0]), 0);
    EXPECT_EQ(plimsoll_instance_asleep(instances[1]), 0);
    EXPECT_EQ(plimsoll_instance_asleep(instances[2]), 1);
    EXPECT_GT(states[0].pose.position[0], rest[0].pose.position[0]);
    // The water rising 1 cm wakes body 2; and plimsoll_instance_wake wakes a sleeping copy.
    plimsoll_water raised{};
    raised.level = 0.01;
    step(raised);
    EXPECT_EQ(plimsoll_instance_asleep(instances[2]), 0);
    EXPECT_EQ(plimsoll_instance_wake(copy.get()), 1);
    EXPECT_EQ(plimsoll_instance_asleep(copy.get()), 0);
    EXPECT_EQ(plimsoll_instance_asleep(nullptr), 0);
    EXPECT_NE(std::string(plimsoll_runtime_last_error()).find("NULL"), std::string::npos);
    plimsoll_batch_destroy(batch);
}

// A batch steps its instances with the same bits whatever its thread count and the order of
// the instances in the call: each body's step reads only its own state and the shared bundle.
TEST_F(RuntimeTrajectory, ABatchGivesTheSameBitsWhateverItsThreadsAndOrder) {
    Result<Project> boatProject = loadProject(root() / "projects" / "damaged_boat.plim.json");
    Result<Project> buoyProject = loadProject(root() / "projects" / "buoy.plim.json");
    ASSERT_TRUE(boatProject.ok() && buoyProject.ok());
    const BundleHandle boat = loadC(exported(*boatProject)), buoy = loadC(exported(*buoyProject));
    ASSERT_TRUE(boat && buoy);
    rt::WaterModel waves;
    waves.kind = rt::WaterModel::Kind::Gerstner;
    waves.waves.resize(2);
    waves.waves[1].amplitude = 0.05;
    waves.waves[1].wavelength = 4.0;
    waves.waves[1].direction[1] = 1.0;
    const plimsoll_water water = cWater(waves);
    struct Run {
        std::vector<std::uint64_t> hashes;
        std::vector<plimsoll_body_state> states;
    };
    constexpr int kBodies = 9;
    auto run = [&](int threads, bool reversed) {
        plimsoll_batch_desc desc{
            sizeof(plimsoll_batch_desc), threads, nullptr, nullptr, nullptr, 0};
        std::unique_ptr<plimsoll_batch, decltype(&plimsoll_batch_destroy)> batch(
            plimsoll_batch_create(&desc), &plimsoll_batch_destroy);
        EXPECT_TRUE(batch);
        std::vector<InstanceHandle> owned;
        std::vector<plimsoll_body_state> states;
        for (int i = 0; i < kBodies; ++i) {
            owned.push_back(instanceOf(i % 3 == 2 ? buoy.get() : boat.get()));
            states.push_back(startState(0.0, i));
        }
        std::vector<int> order(kBodies);
        for (int i = 0; i < kBodies; ++i) order[i] = reversed ? kBodies - 1 - i : i;
        std::vector<plimsoll_instance*> call(kBodies);
        std::vector<plimsoll_body_state> callStates(kBodies);
        for (int step = 0; step < 180; ++step) {
            for (int i = 0; i < kBodies; ++i) {
                call[i] = owned[order[i]].get();
                callStates[i] = states[order[i]];
            }
            EXPECT_EQ(
                plimsoll_batch_instance_step(batch.get(), kBodies, call.data(), callStates.data(),
                                             &water, nullptr, step / 120.0, 1.0 / 120.0),
                1)
                << plimsoll_runtime_last_error();
            for (int i = 0; i < kBodies; ++i) states[order[i]] = callStates[i];
        }
        Run r;
        for (int i = 0; i < kBodies; ++i)
            r.hashes.push_back(plimsoll_instance_state_hash(owned[i].get()));
        r.states = states;
        return r;
    };
    const Run serial = run(1, false), parallel = run(4, false), backwards = run(3, true);
    for (int i = 0; i < kBodies; ++i) {
        EXPECT_EQ(parallel.hashes[i], serial.hashes[i]) << i;
        EXPECT_EQ(backwards.hashes[i], serial.hashes[i]) << i;
        EXPECT_TRUE(sameBits(parallel.states[i], serial.states[i])) << i;
        EXPECT_TRUE(sameBits(backwards.states[i], serial.states[i])) << i;
    }
    // The boats took water and the bodies moved: the comparison is not of untouched states.
    EXPECT_NE(serial.hashes[0], serial.hashes[1]);
    EXPECT_NE(serial.states[0].pose.position[1], startState(0.0, 0).pose.position[1]);
    // One instance twice in one call would race on its state: refused.
    plimsoll_batch* batch = plimsoll_batch_create(nullptr);
    const InstanceHandle one = instanceOf(boat.get());
    plimsoll_instance* twice[2] = {one.get(), one.get()};
    plimsoll_body_state two[2] = {startState(0, 0), startState(0, 1)};
    EXPECT_EQ(plimsoll_batch_instance_step(batch, 2, twice, two, &water, nullptr, 0.0, 0.01), 0);
    EXPECT_CONTAINS(plimsoll_runtime_last_error(), "an instance appears twice");
    plimsoll_batch_destroy(batch);
}

// A hundred flooding boats of one bundle hold a tenth or less of what a hundred loads held:
// the bundle's samples, tiles and graph layout once, each boat only its water.
TEST_F(RuntimeTrajectory, AHundredFloodingBoatsShareOneBundle) {
    Result<Project> project = loadProject(root() / "projects" / "damaged_boat.plim.json");
    ASSERT_TRUE(project.ok());
    const BundleHandle boat = loadC(exported(*project));
    ASSERT_TRUE(boat);
    // One evaluation builds the tiles, which the bundle then holds too.
    const plimsoll_pose pose = {{0.0, -0.2, 0.0}, {1.0, 0.0, 0.0, 0.0}};
    const plimsoll_fluid fluid = plimsoll_bundle_default_fluid(boat.get());
    plimsoll_forces forces{};
    ASSERT_EQ(plimsoll_bundle_evaluate(boat.get(), &pose, nullptr, nullptr, &fluid, 0.0, &forces),
              1);
    plimsoll_bundle_size size{sizeof(plimsoll_bundle_size)};
    ASSERT_EQ(plimsoll_bundle_size_query(boat.get(), &size), 1);
    std::vector<InstanceHandle> fleet;
    std::uint64_t instances = 0;
    for (int i = 0; i < 100; ++i) {
        fleet.push_back(instanceOf(boat.get()));
        instances += plimsoll_instance_memory_bytes(fleet.back().get());
    }
    const std::uint64_t shared = size.memory_bytes + instances, separate = 100 * size.memory_bytes;
    std::printf(
        "  100 flooding boats: one bundle %.0f kB + 100 instances %.1f kB = %.0f kB; 100 loads "
        "%.0f kB\n",
        size.memory_bytes / 1024.0, instances / 1024.0, shared / 1024.0, separate / 1024.0);
    EXPECT_GT(instances, 0u);
    EXPECT_LE(10 * shared, separate);
}

// The instruction set does not change a bit: every sample project replayed by float_body
// --csv (the rows, and the final state's hash over every bit of it) with the AVX2 build of the
// evaluation and with the baseline build forced (PLIMSOLL_ISA=baseline) writes the same file. On a
// processor without AVX2 both runs take the baseline, and the test says so.
// scripts/test-determinism.sh compares clang and an aarch64 build under qemu the same way.
TEST_F(RuntimeTrajectory, TheInstructionSetChangesNoBit) {
    const bool avx2 = __builtin_cpu_supports("avx2");
    if (!avx2) std::printf("  this processor has no AVX2: both runs take the baseline build\n");
    int compared = 0;
    for (const Project& project : cases()) {
        SCOPED_TRACE(project.fileStem);
        const fs::path folder = exported(project);
        std::string files[2];
        const char* isa[2] = {"", "PLIMSOLL_ISA=baseline "};
        for (int i = 0; i < 2; ++i) {
            const fs::path csv = root() / ("isa-" + std::to_string(i) + ".csv");
            const fs::path hash = root() / ("isa-" + std::to_string(i) + ".txt");
            const std::string command = std::string(isa[i]) + PLIMSOLL_FLOAT_BODY + " " +
                                        folder.string() + (test::kSanitizedBuild ? " 2" : " 10") +
                                        " --csv " + csv.string() + " >" + hash.string();
            ASSERT_EQ(std::system(command.c_str()), 0) << command;
            files[i] = test::readFile(csv) + test::readFile(hash);
        }
        ASSERT_GT(files[0].size(), 1000u);
        EXPECT_CONTAINS(files[0], "state hash ");
        EXPECT_TRUE(files[0] == files[1]) << "the AVX2 and baseline builds differ";
        ++compared;
    }
    EXPECT_GE(compared, 8);
}

/// A current varying over the water: what drag sees.
void currentAt(const double p[3], double v[3]) {
    v[0] = 0.3 + 0.05 * p[2];
    v[1] = 0.0;
    v[2] = 0.1 * std::sin(p[0]);
}
void currentOne(void*, const double point[3], double, double velocity[3]) {
    currentAt(point, velocity);
}
void currentMany(void*, size_t n, const double* x, const double* y, const double* z, double,
                 double* out) {
    for (size_t i = 0; i < n; ++i) {
        const double p[3] = {x[i], y[i], z[i]};
        currentAt(p, out + 3 * i);
    }
}

// The quaternion order is named, and the engines' x, y, z, w converts both ways, in place too;
// a pose converted from an engine's quaternion evaluates as the same pose written w-first.
TEST_F(RuntimeTrajectory, QuaternionsConvertFromAndToTheEnginesOrder) {
    static_assert(PLIMSOLL_RUNTIME_QUATERNION_WXYZ == 1);
    const double engine[4] = {0.1, 0.2, 0.3, 0.9273618495495703};  // x, y, z, w
    double q[4];
    plimsoll_quaternion_from_xyzw(engine, q);
    EXPECT_EQ(q[0], engine[3]);
    EXPECT_EQ(q[1], engine[0]);
    EXPECT_EQ(q[3], engine[2]);
    double back[4] = {q[0], q[1], q[2], q[3]};
    plimsoll_quaternion_to_xyzw(back, back);  // in place
    for (int i = 0; i < 4; ++i) EXPECT_EQ(back[i], engine[i]) << i;
    plimsoll_quaternion_to_xyzw(nullptr, back);
    EXPECT_STREQ(plimsoll_runtime_last_error(), "plimsoll_quaternion_to_xyzw: an argument is NULL");

    Result<Project> project = loadProject(root() / "projects" / "buoy.plim.json");
    ASSERT_TRUE(project.ok());
    const BundleHandle buoy = loadC(exported(*project));
    ASSERT_TRUE(buoy);
    const plimsoll_fluid fluid = plimsoll_bundle_default_fluid(buoy.get());
    plimsoll_pose written = {{0.0, -0.1, 0.0}, {engine[3], engine[0], engine[1], engine[2]}};
    plimsoll_pose converted = {{0.0, -0.1, 0.0}, {0, 0, 0, 0}};
    plimsoll_quaternion_from_xyzw(engine, converted.orientation);
    plimsoll_forces a{}, b{};
    ASSERT_EQ(plimsoll_bundle_evaluate(buoy.get(), &written, nullptr, nullptr, &fluid, 0.0, &a), 1);
    ASSERT_EQ(plimsoll_bundle_evaluate(buoy.get(), &converted, nullptr, nullptr, &fluid, 0.0, &b),
              1);
    EXPECT_EQ(std::memcmp(&a, &b, sizeof a), 0);
    EXPECT_GT(a.submerged_volume, 0.0);
}

// The C ABI's batched water velocity (plimsoll_water.velocities, 2.0) gives the forces of the
// per-point callback bit for bit: the same points asked, in one call.
TEST_F(RuntimeTrajectory, TheBatchedWaterVelocityGivesThePerPointForces) {
    Result<Project> project = loadProject(root() / "projects" / "buoy.plim.json");
    ASSERT_TRUE(project.ok());
    const BundleHandle buoy = loadC(exported(*project));
    ASSERT_TRUE(buoy);
    const plimsoll_fluid fluid = plimsoll_bundle_default_fluid(buoy.get());
    plimsoll_water one{}, many{}, still{};
    one.velocity = currentOne;
    many.velocities = currentMany;
    const plimsoll_pose pose = {{0.4, -0.2, -0.3},
                                {0.9950041652780258, 0.09983341664682815, 0.0, 0.0}};
    const plimsoll_velocity moving = {{0.5, -0.1, 0.2}, {0.1, 0.3, 0.0}};
    plimsoll_forces a{}, b{}, c{};
    ASSERT_EQ(plimsoll_bundle_evaluate(buoy.get(), &pose, &moving, &one, &fluid, 0.0, &a), 1);
    ASSERT_EQ(plimsoll_bundle_evaluate(buoy.get(), &pose, &moving, &many, &fluid, 0.0, &b), 1);
    ASSERT_EQ(plimsoll_bundle_evaluate(buoy.get(), &pose, &moving, &still, &fluid, 0.0, &c), 1);
    EXPECT_EQ(std::memcmp(&a, &b, sizeof a), 0);
    EXPECT_NE(a.drag_force[0], c.drag_force[0]);  // the current changes the drag
}

}  // namespace
}  // namespace test_runtime_trajectory
}  // namespace plimsoll
