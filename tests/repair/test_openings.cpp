// Open hulls and containers: their openings found (findBasins), closed by level caps at the
// rim (physicsSolidFor), and the space behind the caps a compartment that floods. Against
// exact volumes (a thick-walled cup, upright and tilted: the exact clip of its hold), an
// independent ray-cast estimate for the shared open boats and bucket, and the order of events
// of a dinghy riding high, swamping and sinking.
#include "cli_runner.h"
#include "document/command.h"
#include "document/document.h"
#include "test_support.h"
#include "repair/repair_support.h"
#include "world_support.h"

#include "plimsoll/geometry/validate.h"
#include "plimsoll/graph/graph.h"  // windingNumber: the independent inside test
#include "plimsoll/geometry/box.h"
#include "plimsoll/io/mesh_io.h"
#include "plimsoll/physics/buoyancy.h"
#include "plimsoll/physics/massprops.h"
#include "plimsoll/repair/openings.h"
#include "plimsoll/repair/physics_solid.h"
#include "plimsoll/samples/primitives.h"

#include <Eigen/Geometry>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <numbers>
#include <random>

namespace plimsoll {
namespace test_openings {
namespace {

namespace fs = std::filesystem;

/// Adds quad p0 p1 p2 p3 (two triangles), turned to face `normal`.
void addQuad(TriangleMesh& mesh, std::array<Eigen::Vector3d, 4> p, const Eigen::Vector3d& normal) {
    if ((p[1] - p[0]).cross(p[2] - p[0]).dot(normal) < 0) std::swap(p[1], p[3]);
    const auto base = static_cast<std::uint32_t>(mesh.positions.size());
    mesh.positions.insert(mesh.positions.end(), p.begin(), p.end());
    mesh.triangles.push_back({base, base + 1, base + 2});
    mesh.triangles.push_back({base, base + 2, base + 3});
}

struct Cup {
    double outer = 0.5, inner = 0.4;   ///< half widths, m
    double height = 0.5, floor = 0.1;  ///< m
    double materialVolume() const {
        return 4 * outer * outer * height - 4 * inner * inner * (height - floor);
    }
};

/// A square cup with thick walls: closed, outward, open at the top (y up).
TriangleMesh makeCup(const Cup& cup) {
    TriangleMesh mesh;
    mesh.source = "cup";
    const auto ring = [](double half, double y) {
        return std::array<Eigen::Vector3d, 4>{
            Eigen::Vector3d(-half, y, -half), Eigen::Vector3d(half, y, -half),
            Eigen::Vector3d(half, y, half), Eigen::Vector3d(-half, y, half)};
    };
    const auto o0 = ring(cup.outer, 0), o1 = ring(cup.outer, cup.height);
    const auto i0 = ring(cup.inner, cup.floor), i1 = ring(cup.inner, cup.height);
    const Eigen::Vector3d up = Eigen::Vector3d::UnitY();
    addQuad(mesh, o0, -up);
    addQuad(mesh, i0, up);
    for (int k = 0; k < 4; ++k) {
        const int n = (k + 1) % 4;
        const Eigen::Vector3d side = Eigen::Vector3d(o0[k] + o0[n]).normalized();
        addQuad(mesh, {o0[k], o0[n], o1[n], o1[k]}, side);
        addQuad(mesh, {o1[k], o1[n], i1[n], i1[k]}, up);
        addQuad(mesh, {i0[k], i0[n], i1[n], i1[k]}, -side);
    }
    return mesh;
}

PhysicsSolid solidOf(const TriangleMesh& mesh, const RepairSettings& settings = {}) {
    Result<PhysicsSolid> solid = physicsSolidFor(mesh, validateSurface(mesh), settings);
    EXPECT_TRUE(solid.ok()) << solid.error().message;
    return solid.ok() ? std::move(*solid) : PhysicsSolid{};
}

TEST(Openings, AThickWalledCupIsCappedAtItsRim) {
    SKIP_WITHOUT_REPAIR();
    const Cup cup;
    const TriangleMesh mesh = makeCup(cup);
    ASSERT_TRUE(validateSurface(mesh).closedSolid());
    ASSERT_NEAR(exactSolidMassProperties(mesh, 1.0).volume, cup.materialVolume(), 1e-12);

    const std::vector<Basin> basins = findBasins(mesh, cup.materialVolume());
    ASSERT_EQ(basins.size(), 1u);
    EXPECT_NEAR(basins[0].spillHeight, cup.height, 2 * basins[0].cellSize);
    EXPECT_NEAR(basins[0].volume, 4 * cup.inner * cup.inner * (cup.height - cup.floor), 0.05);

    const PhysicsSolid solid = solidOf(mesh);
    ASSERT_EQ(solid.openings.size(), 1u);
    const Opening& opening = solid.openings[0];
    // The rim is level at the top: the cap closes the cup there (to the bisection's precision).
    EXPECT_NEAR(opening.capHeight, cup.height, 1e-5);
    const double hold = 4 * cup.inner * cup.inner * (opening.capHeight - cup.floor);
    EXPECT_NEAR(opening.cavity.volume, hold, 1e-9);
    EXPECT_NEAR(opening.cavity.centerOfMass.y(), 0.5 * (cup.floor + opening.capHeight), 1e-9);
    EXPECT_NEAR(opening.capArea, 4 * cup.inner * cup.inner, 1e-9);
    EXPECT_NEAR(solid.materialVolume, cup.materialVolume(), 1e-12);
    EXPECT_NEAR(solid.displacementVolume, cup.materialVolume() + hold, 1e-9);
    ASSERT_FALSE(solid.repairs.empty());
    EXPECT_EQ(solid.repairs.back().kind, "cap");
    EXPECT_EQ(solid.repairs.back().count, 1u);
    EXPECT_NEAR(solid.repairs.back().volumeChange, hold, 1e-9);
    // The sealed solid is closed, and it is what it says.
    EXPECT_TRUE(validateSurface(solid.mesh).closedSolid());
    EXPECT_NEAR(exactSolidMassProperties(solid.mesh, 1.0).volume, solid.displacementVolume, 1e-9);
    // Its walls, the sealed body less the hold, weigh what the artist's cup weighs.
    const MassProperties walls =
        withoutHollow(exactSolidMassProperties(solid.mesh, 700.0), opening.cavity, 700.0);
    const MassProperties artist = exactSolidMassProperties(mesh, 700.0);
    EXPECT_NEAR(walls.mass, artist.mass, 1e-7 * artist.mass);
    EXPECT_LT((walls.centerOfMass - artist.centerOfMass).norm(), 1e-7);
    EXPECT_LT((walls.inertia - artist.inertia).norm(), 1e-6 * artist.inertia.norm());
}

TEST(Openings, ATiltedCupHoldsWaterUpToTheLowestPointOfItsRim) {
    SKIP_WITHOUT_REPAIR();
    const Cup cup;
    const Eigen::Matrix3d tilt =
        Eigen::AngleAxisd(10 * std::numbers::pi / 180, Eigen::Vector3d::UnitX()).matrix();
    TriangleMesh mesh = makeCup(cup);
    for (Eigen::Vector3d& p : mesh.positions) p = tilt * p;
    const PhysicsSolid solid = solidOf(mesh);
    ASSERT_EQ(solid.openings.size(), 1u);
    // Water spills over the inner edge of the rim where it is lowest.
    double spill = 1e300;
    for (double x : {-cup.inner, cup.inner})
        for (double z : {-cup.inner, cup.inner})
            spill = std::min(spill, (tilt * Eigen::Vector3d(x, cup.height, z)).y());
    EXPECT_NEAR(solid.openings[0].capHeight, spill, 1e-5);
    // The hold: the tilted inner box below that level, by the exact clip of a box mesh.
    TriangleMesh hold = makeBox({2 * cup.inner, cup.height - cup.floor, 2 * cup.inner});
    for (Eigen::Vector3d& p : hold.positions)
        p = tilt * (p + Eigen::Vector3d(0, 0.5 * (cup.height + cup.floor), 0));
    BodyFrame frame;
    const double expected =
        evaluateBuoyancyExact(hold, frame, solid.openings[0].capHeight, {}).submergedVolume;
    EXPECT_NEAR(solid.openings[0].cavity.volume, expected, 1e-9);
    EXPECT_NEAR(solid.displacementVolume - solid.materialVolume, expected, 1e-9);
}

TEST(Openings, ClosedSolidsAndShallowDentsHaveNone) {
    SKIP_WITHOUT_REPAIR();
    // A box, a sphere, a torus lying flat (its hole drains), and a cup whose hold is under
    // 5% of its material (a dent, not a container).
    Cup dent;
    dent.floor = 0.48;
    for (const TriangleMesh& mesh :
         {makeBox({1, 2, 3}), makeUvSphere(0.5, 32, 16), makeCup(dent)}) {
        SCOPED_TRACE(mesh.source);
        const PhysicsSolid solid = solidOf(mesh);
        EXPECT_TRUE(solid.openings.empty());
        EXPECT_TRUE(solid.repairs.empty()) << describeRepairs(solid.repairs);
    }
    if (std::optional<fs::path> torus = test::sharedMesh("torus.obj")) {
        Result<TriangleMesh> mesh = loadMesh(*torus);
        ASSERT_TRUE(mesh.ok());
        EXPECT_TRUE(solidOf(*mesh).openings.empty());
    }
    // Openings left open on request: the surface as it is.
    RepairSettings keep;
    keep.closeOpenings = false;
    const TriangleMesh cupMesh = makeCup(Cup{});
    const PhysicsSolid kept = solidOf(cupMesh, keep);
    EXPECT_TRUE(kept.openings.empty());
    EXPECT_EQ(kept.mesh.triangles, cupMesh.triangles);
}

// --- The shared open boats and bucket -------------------------------------------------------

/// Möller-Trumbore: whether the ray from `origin` along `direction` hits triangle (a, b, c).
bool rayHits(const Eigen::Vector3d& origin, const Eigen::Vector3d& direction,
             const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c) {
    const Eigen::Vector3d e1 = b - a, e2 = c - a, p = direction.cross(e2);
    const double det = e1.dot(p);
    if (std::abs(det) < 1e-300) return false;
    const Eigen::Vector3d s = origin - a;
    const double u = s.dot(p) / det;
    if (u < 0 || u > 1) return false;
    const Eigen::Vector3d q = s.cross(e1);
    const double v = direction.dot(q) / det;
    if (v < 0 || u + v > 1) return false;
    return e2.dot(q) / det > 0;
}

/// An independent estimate of the volume the artist's surface displaces sealed at its rim:
/// Monte Carlo over its box, a point counting when it is inside the surface (generalized
/// winding number) or when no ray from it escapes horizontally (16 directions) or downwards
/// (straight down and 8 directions 45 degrees down): water there could not run out.
double sealedVolumeByRayCasting(const TriangleMesh& mesh, int samples) {
    const Bounds3 box = computeBounds(mesh);
    std::vector<Eigen::Vector3d> directions{-Eigen::Vector3d::UnitY()};
    for (int k = 0; k < 16; ++k) {
        const double a = 2 * std::numbers::pi * k / 16;
        directions.emplace_back(std::cos(a), 0, std::sin(a));
        if (k % 2 == 0) directions.emplace_back(std::cos(a), -1, std::sin(a));
    }
    std::mt19937_64 random(7);
    std::uniform_real_distribution<double> unit(0, 1);
    int counted = 0;
    for (int i = 0; i < samples; ++i) {
        const Eigen::Vector3d p =
            box.min + (box.max - box.min)
                          .cwiseProduct(Eigen::Vector3d(unit(random), unit(random), unit(random)));
        if (windingNumber(mesh, p) > 0.5) {
            ++counted;
            continue;
        }
        bool held = true;
        for (const Eigen::Vector3d& d : directions) {
            bool hit = false;
            for (const Triangle& t : mesh.triangles) {
                if (rayHits(p, d, mesh.positions[t[0]], mesh.positions[t[1]],
                            mesh.positions[t[2]])) {
                    hit = true;
                    break;
                }
            }
            if (!hit) {
                held = false;
                break;
            }
        }
        if (held) ++counted;
    }
    return (box.max - box.min).prod() * counted / samples;
}

TEST(Openings, OpenBoatsAndTheBucketDisplaceTheirSealedHull) {
    SKIP_WITHOUT_REPAIR();
    if (!fs::exists(test::realAssetsDir())) GTEST_SKIP() << "../shared/real-assets not present";
    for (const char* name :
         {"quaternius/Boat.fbx", "quaternius/BoatWSail.fbx", "quaternius/Bucket.fbx"}) {
        SCOPED_TRACE(name);
        Result<TriangleMesh> mesh = loadMesh(test::realAssetsDir() / name);
        ASSERT_TRUE(mesh.ok()) << mesh.error().message;
        const PhysicsSolid solid = solidOf(*mesh);
        ASSERT_FALSE(solid.openings.empty());
        EXPECT_FALSE(solid.openings[0].capTriangles.empty());
        EXPECT_GT(solid.openings[0].capArea, 0);
        EXPECT_TRUE(validateSurface(solid.mesh).closedSolid())
            << validateSurface(solid.mesh).format();
        const double estimate = sealedVolumeByRayCasting(*mesh, 6000);
        const double ratio = solid.displacementVolume / solid.materialVolume;
        const double expected = estimate / solid.materialVolume;
        std::cout << name << ": material " << solid.materialVolume << " m^3, displacement "
                  << solid.displacementVolume << " m^3 (ratio " << ratio << "), ray-cast estimate "
                  << estimate << " m^3 (ratio " << expected
                  << "), cap at y = " << solid.openings[0].capHeight << " m, "
                  << describeRepairs(solid.repairs) << "\n";
        EXPECT_NEAR(ratio, expected, 0.15 * expected);
    }
}

TEST(Openings, MasspropsWeighsTheWallsAndReportsBothVolumes) {
    SKIP_WITHOUT_REPAIR();
    const fs::path boat = test::realAssetsDir() / "quaternius" / "Boat.fbx";
    if (!fs::exists(boat)) GTEST_SKIP() << "../shared/real-assets not present";
    const test::CommandOutput run =
        test::runPlimsoll("massprops --exact --json --density 600 '" + boat.string() + "'");
    ASSERT_EQ(run.exitCode, 0) << run.err;
    const nlohmann::json j = nlohmann::json::parse(run.out);
    const double material = j.at("material_volume").get<double>();
    const double displacement = j.at("displacement_volume").get<double>();
    EXPECT_GT(displacement, 2 * material);
    EXPECT_NEAR(j.at("volume").get<double>(), displacement, 1e-9);
    EXPECT_NEAR(j.at("mass").get<double>(), 600 * material, 1e-6 * 600 * material);
    bool capped = false;
    for (const nlohmann::json& r : j.at("repairs"))
        if (r.at("kind") == "cap")
            capped = r.at("count") == 1 && std::abs(r.at("volume_change").get<double>() -
                                                    (displacement - material)) < 1e-9;
    EXPECT_TRUE(capped) << j.at("repairs").dump();
}

TEST(Openings, TheEditorSimulatesWhatAProjectRunSimulates) {
    SKIP_WITHOUT_REPAIR();
    const fs::path boat = test::realAssetsDir() / "quaternius" / "Boat.fbx";
    if (!fs::exists(boat)) GTEST_SKIP() << "../shared/real-assets not present";
    const fs::path folder = test::scratchFolder("openings_editor");
    Project project;
    project.name = "dinghy";
    BodyDesc body;
    body.name = "dinghy";
    body.mesh = boat.string();
    body.textureSize = 32;
    body.material.density = 600;
    project.bodies.push_back(body);
    const fs::path file = folder / "dinghy.plim.json";
    ASSERT_TRUE(saveProject(project, file).ok());
    Result<Project> loaded = loadProject(file);
    ASSERT_TRUE(loaded.ok()) << loaded.error().message;
    const Scene run = test::sceneOrFail(*loaded);
    Result<std::unique_ptr<editor::Document>> document = editor::Document::open(file);
    ASSERT_TRUE(document.ok()) << document.error().message;
    Result<Scene> previewed = (*document)->simulationScene();
    ASSERT_TRUE(previewed.ok()) << previewed.error().message;
    ASSERT_EQ(run.bodies.size(), 1u);
    ASSERT_EQ(previewed->bodies.size(), 1u);
    const SceneBody& a = run.bodies[0];
    const SceneBody& b = previewed->bodies[0];
    EXPECT_EQ(a.textures->position, b.textures->position);
    EXPECT_EQ(a.mass->mass, b.mass->mass);
    ASSERT_TRUE(a.parts.waterGraph && b.parts.waterGraph);
    EXPECT_EQ(*a.parts.waterGraph, *b.parts.waterGraph);
    EXPECT_EQ(b.parts.waterGraph->nodes.size(), 1u);
    ASSERT_TRUE(a.parts.permeabilityMap && b.parts.permeabilityMap);
    EXPECT_EQ(a.parts.permeabilityMap->values, b.parts.permeabilityMap->values);
    // Marked sealed in the editor, undoably: the preview has no compartment then.
    Result<std::unique_ptr<editor::Command>> seal =
        editor::makeSetPropertyCommand(**document, "/bodies/0/openings", "sealed");
    ASSERT_TRUE(seal.ok()) << seal.error().message;
    ASSERT_TRUE((*document)->execute(std::move(*seal)).ok());
    EXPECT_EQ((*document)->project().bodies[0].openings, OpeningsMode::Sealed);
    Result<Scene> decked = (*document)->simulationScene();
    ASSERT_TRUE(decked.ok()) << decked.error().message;
    EXPECT_FALSE(decked->bodies[0].parts.waterGraph);
    EXPECT_TRUE((*document)->undo());
    EXPECT_EQ((*document)->project().bodies[0].openings, OpeningsMode::Open);

    // "sealed": the caps let nothing in, and the walls weigh the same.
    project.bodies[0].openings = OpeningsMode::Sealed;
    ASSERT_TRUE(saveProject(project, file).ok());
    Result<Project> sealedProject = loadProject(file);
    ASSERT_TRUE(sealedProject.ok());
    EXPECT_EQ(sealedProject->bodies[0].openings, OpeningsMode::Sealed);
    const Scene sealed = test::sceneOrFail(*sealedProject);
    ASSERT_EQ(sealed.bodies.size(), 1u);
    EXPECT_FALSE(sealed.bodies[0].parts.waterGraph);
    EXPECT_NEAR(sealed.bodies[0].mass->mass, a.mass->mass, 1e-9 * a.mass->mass);
}

// --- Caps moved and sealed -------------------------------------------------------------------

TEST(Openings, ALoweredCapDisplacesTheInnerAreaTimesTheDropLess) {
    SKIP_WITHOUT_REPAIR();
    const Cup cup;
    const TriangleMesh mesh = makeCup(cup);
    const PhysicsSolid atRim = solidOf(mesh);
    ASSERT_EQ(atRim.openings.size(), 1u);
    EXPECT_NEAR(atRim.openings[0].rimHeight, cup.height, 1e-12);
    EXPECT_NEAR(atRim.openings[0].bottomHeight, cup.floor, 1e-12);
    const double innerArea = 4 * cup.inner * cup.inner;
    for (const double drop : {0.05, 0.2, 0.35}) {
        SCOPED_TRACE(drop);
        RepairSettings settings;
        const double h = cup.height - drop;
        settings.capHeights = {h};
        const PhysicsSolid lowered = solidOf(mesh, settings);
        ASSERT_EQ(lowered.openings.size(), 1u);
        const Opening& opening = lowered.openings[0];
        EXPECT_EQ(opening.capHeight, h);
        EXPECT_NEAR(opening.cavity.volume, innerArea * (h - cup.floor), 1e-9);
        EXPECT_NEAR(opening.capArea, innerArea, 1e-9);
        EXPECT_NEAR(atRim.displacementVolume - lowered.displacementVolume,
                    innerArea * (atRim.openings[0].capHeight - h), 1e-9);
        EXPECT_NEAR(lowered.materialVolume, cup.materialVolume(), 1e-12);
        EXPECT_TRUE(validateSurface(lowered.mesh).closedSolid());
        EXPECT_NEAR(exactSolidMassProperties(lowered.mesh, 1.0).volume, lowered.displacementVolume,
                    1e-9);
    }
    // Above the rim the water spills first; at the floor nothing is behind the cap.
    for (const double h : {cup.height + 0.01, cup.floor, cup.floor - 0.05}) {
        SCOPED_TRACE(h);
        RepairSettings settings;
        settings.capHeights = {h};
        Result<PhysicsSolid> refused = physicsSolidFor(mesh, validateSurface(mesh), settings);
        ASSERT_FALSE(refused.ok());
        EXPECT_NE(refused.error().message.find("caps[0].height"), std::string::npos)
            << refused.error().message;
        EXPECT_NE(refused.error().message.find(h > cup.height ? "above the lowest point of its rim"
                                                              : "not above the bottom"),
                  std::string::npos)
            << refused.error().message;
    }
}

/// Two cups side by side, sharing the wall between them (overlapping closed parts that the
/// repair joins): the left one's hold is the larger, so it is opening 0.
TriangleMesh twinCups(const Cup& left, const Cup& right) {
    TriangleMesh mesh = makeCup(left);
    for (Eigen::Vector3d& p : mesh.positions) p.x() -= left.outer - 0.05;
    TriangleMesh other = makeCup(right);
    const auto base = static_cast<std::uint32_t>(mesh.positions.size());
    for (Eigen::Vector3d p : other.positions)
        mesh.positions.push_back(p + Eigen::Vector3d(right.outer - 0.05, 0, 0));
    for (const Triangle& t : other.triangles)
        mesh.triangles.push_back({t[0] + base, t[1] + base, t[2] + base});
    mesh.source = "twin cups";
    return mesh;
}

/// Tolerance of a figure of a mesh read back from a file: assimp reads positions as floats.
constexpr double kFloatMesh = 1e-6;

/// The project of one body on `mesh` (written as OBJ in a scratch folder).
Project bodyProject(const TriangleMesh& mesh, const std::string& name,
                    const MaterialDesc& material) {
    Project p;
    p.name = name;
    p.fileStem = name;
    p.folder = test::freshFolder("openings_caps", name);
    EXPECT_TRUE(writeObj(mesh, p.folder / (name + ".obj")).ok());
    BodyDesc body;
    body.name = name;
    body.mesh = name + ".obj";
    body.textureSize = 64;
    body.material = material;
    p.bodies.push_back(body);
    p.water = WaterModel::flat(0.0);
    return p;
}

/// bodyProject of a wooden body (600 kg/m^3).
Project woodProject(const TriangleMesh& mesh, const std::string& name) {
    MaterialDesc wood;
    wood.density = 600;
    return bodyProject(mesh, name, wood);
}

TEST(Openings, ASealedCapLetsNoWaterInWhereAnOpenOneFloods) {
    SKIP_WITHOUT_REPAIR();
    Cup left, right;
    right.inner = 0.3;
    right.outer = 0.4;
    const TriangleMesh mesh = twinCups(left, right);
    const PhysicsSolid solid = solidOf(mesh);
    ASSERT_EQ(solid.openings.size(), 2u) << describeRepairs(solid.repairs);
    const double leftHold = 4 * left.inner * left.inner * (left.height - left.floor);
    const double rightHold = 4 * right.inner * right.inner * (right.height - right.floor);
    EXPECT_NEAR(solid.openings[0].cavity.volume, leftHold, 1e-4 * leftHold);
    EXPECT_NEAR(solid.openings[1].cavity.volume, rightHold, 1e-4 * rightHold);
    EXPECT_LT(solid.openings[0].cavity.centerOfMass.x(), 0);

    Project project = woodProject(mesh, "twin");
    project.bodies[0].caps = {
        CapDesc{.mode = OpeningsMode::Sealed}};  // the left one; the right one open
    // Held a metre under for three seconds: the open hold fills, the sealed one stays dry.
    project.bodies[0].position = Eigen::Vector3d(0, -1.5, 0);
    std::unique_ptr<World> world = test::fastWorldOrFail(test::sceneOrFail(project));
    ASSERT_TRUE(world);
    const WaterGraphSimulation* graph = world->waterGraph(0);
    ASSERT_NE(graph, nullptr);
    ASSERT_EQ(graph->graph().nodes.size(), 1u) << "one compartment: the open cap's";
    EXPECT_EQ(graph->graph().nodes[0].id, "opening-2");
    EXPECT_NEAR(graph->graph().nodes[0].capacity, rightHold, 1e-4 * rightHold);
    ASSERT_TRUE(world
                    ->setExternalForce(0,
                                       [](const SimulatedBody& body, const RigidBodyState& state) {
                                           Wrench w;  // a hand that keeps it where it is
                                           w.force = -50.0 * state.linearMomentum;
                                           w.force.y() -=
                                               body.mass.mass * 200.0 * (state.position.y() + 1.5);
                                           return w;
                                       })
                    .ok());
    for (int f = 0; f < 180; ++f) ASSERT_TRUE(world->advanceFrame().ok());
    EXPECT_GT(world->waterGraph(0)->storedWater(), 0.9 * rightHold);

    // Both sealed: no compartment at all, and the body displaces its sealed hull.
    project.bodies[0].caps = {CapDesc{.mode = OpeningsMode::Sealed},
                              CapDesc{.mode = OpeningsMode::Sealed}};
    const Scene decked = test::sceneOrFail(project);
    ASSERT_EQ(decked.bodies.size(), 1u);
    EXPECT_FALSE(decked.bodies[0].parts.waterGraph);
    // And the body-wide default sealed with the left cap open: the left's compartment only.
    project.bodies[0].openings = OpeningsMode::Sealed;
    project.bodies[0].caps = {CapDesc{.mode = OpeningsMode::Open}};
    const Scene leftOpen = test::sceneOrFail(project);
    ASSERT_TRUE(leftOpen.bodies[0].parts.waterGraph);
    ASSERT_EQ(leftOpen.bodies[0].parts.waterGraph->nodes.size(), 1u);
    EXPECT_EQ(leftOpen.bodies[0].parts.waterGraph->nodes[0].id, "opening-1");
}

TEST(Openings, ACapMovedInTheProjectSetsTheCompartmentAndTheDisplacement) {
    SKIP_WITHOUT_REPAIR();
    const Cup cup;
    Project project = woodProject(makeCup(cup), "cup");
    const double h = 0.3;
    project.bodies[0].caps = {CapDesc{.height = h}};
    const Scene scene = test::sceneOrFail(project);
    ASSERT_EQ(scene.bodies.size(), 1u);
    const SceneBody& body = scene.bodies[0];
    ASSERT_TRUE(body.parts.waterGraph);
    ASSERT_EQ(body.parts.waterGraph->nodes.size(), 1u);
    const double hold = 4 * cup.inner * cup.inner * (h - cup.floor);
    EXPECT_NEAR(body.parts.waterGraph->nodes[0].capacity, hold, kFloatMesh * hold);
    // The baked surface encloses walls and hold: V = sum A_y y over the textures (exact).
    double volume = 0;
    for (std::size_t i = 0; i < body.textures->coveredCount(); ++i)
        volume += body.textures->areaVector[i].y() * body.textures->position[i].y();
    EXPECT_NEAR(volume, cup.materialVolume() + hold, kFloatMesh * volume);
    // The walls weigh what the cup weighs, wherever the cap is.
    EXPECT_NEAR(body.mass->mass, 600 * cup.materialVolume(),
                kFloatMesh * 600 * cup.materialVolume());

    // Above the rim: refused, naming the project file, the body and the cap.
    project.bodies[0].caps = {CapDesc{.height = cup.height + 0.1}};
    Result<Scene> refused = loadScene(project);
    ASSERT_FALSE(refused.ok());
    const std::string& message = refused.error().message;
    EXPECT_NE(message.find("cup.plim.json"), std::string::npos) << message;
    EXPECT_NE(message.find("body 'cup'"), std::string::npos) << message;
    EXPECT_NE(message.find("caps[0].height"), std::string::npos) << message;
}

TEST(Openings, TheShellLiesOnTheWallsNotOnTheCap) {
    SKIP_WITHOUT_REPAIR();
    // A thin-walled open box: 1 m square, 0.5 m high, walls and floor 2 cm thick.
    Cup box;
    box.outer = 0.5;
    box.inner = 0.48;
    box.floor = 0.02;
    box.height = 0.5;
    constexpr double kSigma = 12;  // kg/m^2
    MaterialDesc shell;
    shell.shellSurfaceDensity = kSigma;
    for (const OpeningsMode mode : {OpeningsMode::Open, OpeningsMode::Sealed}) {
        SCOPED_TRACE(openingsModeName(mode));
        Project project = bodyProject(makeCup(box), "box", shell);
        project.bodies[0].openings = mode;
        const Scene scene = test::sceneOrFail(project);
        ASSERT_EQ(scene.bodies.size(), 1u);
        const PhysicsSolid solid = solidOf(makeCup(box));
        ASSERT_EQ(solid.openings.size(), 1u);
        const double cap = solid.openings[0].capHeight;
        // The skin of the sealed body less its cap: outside (floor and four sides), the rim's
        // top, and the strip of inner wall above the cap.
        const double a = 2 * box.outer, b = 2 * box.inner;
        const double skin =
            a * a + 4 * a * box.height + (a * a - b * b) + 4 * b * (box.height - cap);
        // (The cap would add kSigma b^2, a third more.)
        EXPECT_NEAR(scene.bodies[0].mass->mass, kSigma * skin, kFloatMesh * kSigma * skin);
        EXPECT_NEAR(scene.bodies[0].mass->centerOfMass.x(), 0, 1e-4);
    }
}

TEST(Openings, TheEditorSealsAndMovesACapUndoablyByteForByte) {
    SKIP_WITHOUT_REPAIR();
    const Cup cup;
    Project project = woodProject(makeCup(cup), "pail");
    const fs::path file = project.folder / "pail.plim.json";
    ASSERT_TRUE(saveProject(project, file).ok());
    const std::string opened = test::readFile(file);
    Result<std::unique_ptr<editor::Document>> document = editor::Document::open(file);
    ASSERT_TRUE(document.ok()) << document.error().message;
    editor::Document& doc = **document;
    const auto text = [&] { return projectToJson(doc.project()); };
    const std::string t0 = text();

    Result<std::unique_ptr<editor::Command>> seal =
        editor::makeSetCapCommand(doc, 0, 0, CapDesc{.mode = OpeningsMode::Sealed});
    ASSERT_TRUE(seal.ok()) << seal.error().message;
    EXPECT_EQ((*seal)->name(), "Seal pail cap 1");
    ASSERT_TRUE(doc.execute(std::move(*seal)).ok());
    const std::string t1 = text();
    EXPECT_EQ(doc.project().bodies[0].capMode(0), OpeningsMode::Sealed);
    Result<Scene> sealed = doc.simulationScene();
    ASSERT_TRUE(sealed.ok()) << sealed.error().message;
    EXPECT_FALSE(sealed->bodies[0].parts.waterGraph) << "a sealed cap lets no water in";

    const double h = 0.3;
    Result<std::unique_ptr<editor::Command>> move =
        editor::makeSetCapCommand(doc, 0, 0, CapDesc{.mode = OpeningsMode::Sealed, .height = h});
    ASSERT_TRUE(move.ok()) << move.error().message;
    EXPECT_EQ((*move)->name(), "Move pail cap 1");
    ASSERT_TRUE(doc.execute(std::move(*move)).ok());
    const std::string t2 = text();
    Result<Scene> moved = doc.simulationScene();
    ASSERT_TRUE(moved.ok()) << moved.error().message;
    double volume = 0;  // what the baked surface encloses: walls and the space under the cap
    for (std::size_t i = 0; i < moved->bodies[0].textures->coveredCount(); ++i)
        volume += moved->bodies[0].textures->areaVector[i].y() *
                  moved->bodies[0].textures->position[i].y();
    EXPECT_NEAR(volume, cup.materialVolume() + 4 * cup.inner * cup.inner * (h - cup.floor),
                kFloatMesh * volume);
    // Nothing to change: no step.
    EXPECT_FALSE(
        editor::makeSetCapCommand(doc, 0, 0, CapDesc{.mode = OpeningsMode::Sealed, .height = h})
            .ok());
    EXPECT_FALSE(editor::makeSetCapCommand(doc, 0, 0, CapDesc{.mode = OpeningsMode::None}).ok());
    EXPECT_FALSE(editor::makeSetCapCommand(doc, 0, 0, CapDesc{.height = std::nan("")}).ok());

    EXPECT_NE(t0, t1);
    EXPECT_NE(t1, t2);
    ASSERT_TRUE(doc.undo());
    EXPECT_EQ(text(), t1);
    ASSERT_TRUE(doc.undo());
    EXPECT_EQ(text(), t0);
    EXPECT_FALSE(doc.dirty());
    ASSERT_TRUE(doc.save().ok());
    EXPECT_EQ(test::readFile(file), opened) << "undone, the file is as it was";
    ASSERT_TRUE(doc.redo());
    EXPECT_EQ(text(), t1);
    ASSERT_TRUE(doc.redo());
    EXPECT_EQ(text(), t2);
    ASSERT_TRUE(doc.save().ok());
    Result<Project> reread = loadProject(file);
    ASSERT_TRUE(reread.ok()) << reread.error().message;
    EXPECT_EQ(reread->bodies[0].caps,
              (std::vector<CapDesc>{CapDesc{.mode = OpeningsMode::Sealed, .height = h}}));
    // Back to the defaults: the list is gone again.
    Result<std::unique_ptr<editor::Command>> reset =
        editor::makeSetCapCommand(doc, 0, 0, CapDesc{});
    ASSERT_TRUE(reset.ok());
    ASSERT_TRUE(doc.execute(std::move(*reset)).ok());
    EXPECT_EQ(text(), t0);
}

/// Where the dinghy's cap is, in world space, and how much water is behind it.
struct Reading {
    double capHeight = 0;  ///< world y of the cap's centre, m
    double fill = 0;       ///< water / capacity of the compartment
    double centerY = 0;    ///< world y of the centre of mass, m
};

Reading read(const World& world, const Eigen::Vector3d& capCentre) {
    Reading r;
    const SimulatedBody& body = world.bodies()[0];
    r.capHeight = body.pose().apply(capCentre).y();
    r.centerY = body.state.position.y();
    const WaterGraphSimulation* graph = world.waterGraph(0);
    if (graph) r.fill = graph->storedWater() / graph->graph().totalCapacity();
    return r;
}

TEST(Openings, TheDinghyRidesHighThenSwampsWhenPushedUnderAndSinksWhenOverloaded) {
    SKIP_WITHOUT_REPAIR();
    const fs::path boat = test::realAssetsDir() / "quaternius" / "Boat.fbx";
    if (!fs::exists(boat)) GTEST_SKIP() << "../shared/real-assets not present";
    Result<TriangleMesh> mesh = loadMesh(boat);
    ASSERT_TRUE(mesh.ok());
    const PhysicsSolid solid = solidOf(*mesh);
    ASSERT_EQ(solid.openings.size(), 1u);
    const Opening& opening = solid.openings[0];
    Eigen::Vector3d capCentre = 0.5 * (opening.boundsMin + opening.boundsMax);
    capCentre.y() = opening.capHeight;
    const Bounds3 bounds = computeBounds(*mesh);
    constexpr double kWood = 600;

    const auto project = [&](double depth) {
        Project p;
        p.folder = test::scratchFolder("openings_dinghy");
        BodyDesc body;
        body.name = "dinghy";
        body.mesh = boat.string();
        body.textureSize = 64;
        body.material.density = kWood;
        body.position = Eigen::Vector3d(0, -bounds.min.y() - depth, 0);
        p.bodies.push_back(body);
        p.water = WaterModel::flat(0.0);
        return p;
    };
    const auto run = [&](std::unique_ptr<World>& world, double seconds, auto&& each) {
        const int frames = static_cast<int>(seconds / world->scene().simulation.timeStep);
        for (int f = 0; f < frames; ++f) {
            ASSERT_TRUE(world->advanceFrame().ok());
            each(f * world->scene().simulation.timeStep, read(*world, capCentre));
        }
    };

    // Set down on the water: it rides high, rim above the water, dry inside.
    std::vector<std::string> log;
    std::unique_ptr<World> calm = test::fastWorldOrFail(
        test::sceneOrFail(project(0.0)), [&](const std::string& l) { log.push_back(l); });
    ASSERT_TRUE(calm);
    ASSERT_NE(calm->waterGraph(0), nullptr) << "the opening is a compartment";
    EXPECT_EQ(calm->waterGraph(0)->graph().nodes.size(), 1u);
    // Walls of wood: the mass is the material's, not the sealed hull's.
    EXPECT_NEAR(calm->bodies()[0].mass.mass, kWood * solid.materialVolume,
                0.02 * kWood * solid.materialVolume);
    Reading afloat;
    run(calm, 10.0, [&](double, const Reading& r) { afloat = r; });
    EXPECT_GT(afloat.capHeight, 0.01) << "freeboard";
    EXPECT_LT(afloat.fill, 0.01);

    // Pushed under and held there for two seconds: the cap goes under first, then the hold
    // fills; let go, the hull comes up full, lower than it rode dry, its wood still afloat.
    std::unique_ptr<World> pushed = test::fastWorldOrFail(test::sceneOrFail(project(0.4)));
    ASSERT_TRUE(pushed);
    bool holding = true;
    const double push = 3 * 1000.0 * solid.displacementVolume * 9.81;
    ASSERT_TRUE(pushed
                    ->setExternalForce(0,
                                       [&](const SimulatedBody& body, const RigidBodyState& state) {
                                           Wrench w;
                                           // A hand on the hull: holds it 0.4 m under, no further.
                                           if (holding)
                                               w.force = Eigen::Vector3d(
                                                   0, state.position.y() > -0.3 ? -push : 0.0, 0);
                                           (void)body;
                                           return w;
                                       })
                    .ok());
    double capUnder = -1, halfFull = -1;
    Reading swamped;
    run(pushed, 20.0, [&](double t, const Reading& r) {
        if (capUnder < 0 && r.capHeight < 0) capUnder = t;
        if (halfFull < 0 && r.fill > 0.5) halfFull = t;
        holding = t < 2.0;
        swamped = r;
    });
    ASSERT_GE(capUnder, 0);
    ASSERT_GE(halfFull, 0) << "the hold never filled";
    EXPECT_LE(capUnder, halfFull);
    EXPECT_GT(swamped.fill, 0.9);
    EXPECT_LT(swamped.capHeight, afloat.capHeight - 0.01) << "a swamped hull floats lower";
    EXPECT_GT(swamped.centerY, -0.5) << "wood walls still float";

    // Loaded past its freeboard (a weight in it): the rim goes under, it floods and sinks.
    std::unique_ptr<World> loaded = test::fastWorldOrFail(test::sceneOrFail(project(0.0)));
    ASSERT_TRUE(loaded);
    const double reserve = 1000.0 * solid.displacementVolume - kWood * solid.materialVolume;  // kg
    const double load = 1.2 * reserve * 9.81;
    ASSERT_TRUE(loaded
                    ->setExternalForce(0,
                                       [load](const SimulatedBody&, const RigidBodyState&) {
                                           Wrench w;
                                           w.force = Eigen::Vector3d(0, -load, 0);
                                           return w;
                                       })
                    .ok());
    capUnder = halfFull = -1;
    Reading sunk;
    run(loaded, 15.0, [&](double t, const Reading& r) {
        if (capUnder < 0 && r.capHeight < 0) capUnder = t;
        if (halfFull < 0 && r.fill > 0.5) halfFull = t;
        sunk = r;
    });
    ASSERT_GE(capUnder, 0);
    ASSERT_GE(halfFull, 0);
    EXPECT_LE(capUnder, halfFull);
    EXPECT_LT(sunk.centerY, -2.0) << "overloaded and flooded, it sinks";
}

}  // namespace
}  // namespace test_openings
}  // namespace plimsoll
