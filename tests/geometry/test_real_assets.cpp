// The shared real game assets (../shared/real-assets): their size in metres against Blender's
// importers reading the same files, and every one of them accepted (as it is or through its
// physics solid).
#include "cli_runner.h"
#include "test_support.h"

#include "plimsoll/geometry/validate.h"
#include "plimsoll/io/mesh_io.h"
#include "plimsoll/repair/physics_solid.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cstdlib>
#include <fstream>
#include <map>
#include <regex>
#include <sstream>

namespace plimsoll {
namespace test_real_assets {
namespace {

namespace fs = std::filesystem;

/// Every model of the folder (the files a README row names; companions such as .mtl aside).
std::vector<fs::path> realAssets() {
    std::vector<fs::path> files;
    if (!fs::exists(test::realAssetsDir())) return files;
    for (const auto& entry : fs::recursive_directory_iterator(test::realAssetsDir())) {
        const std::string ext = entry.path().extension().string();
        if (ext == ".fbx" || ext == ".glb" || ext == ".obj" || ext == ".stl")
            files.push_back(entry.path());
    }
    std::sort(files.begin(), files.end());
    return files;
}

bool isAsciiFbx(const fs::path& file) {
    if (file.extension() != ".fbx") return false;
    std::ifstream in(file, std::ios::binary);
    char head[18] = {};
    in.read(head, sizeof head);
    return std::string(head, sizeof head).rfind("Kaydara FBX Binary", 0) != 0;
}

struct Box {
    Eigen::Vector3d min, max;
};

/// Blender's bounds of every file it can read, from one Blender process for the whole test
/// run (it takes seconds to start): scripts/blender_sizes.py. Empty when Blender is absent.
const std::map<std::string, Box>& blenderBounds() {
    static const std::map<std::string, Box> bounds = [] {
        std::map<std::string, Box> out;
        if (std::system("command -v blender >/dev/null 2>&1") != 0) return out;
        std::string command = "blender -b --factory-startup --python '" +
                              std::string(PLIMSOLL_SOURCE_DIR) + "/scripts/blender_sizes.py' --";
        for (const fs::path& file : realAssets())
            if (!isAsciiFbx(file)) command += " '" + file.string() + "'";
        const fs::path output = test::scratchFolder("blender_sizes") / "bounds.jsonl";
        command += " > '" + output.string() + "' 2>/dev/null";
        if (std::system(command.c_str()) != 0) return out;
        std::ifstream in(output);
        for (std::string line; std::getline(in, line);) {
            if (line.empty() || line[0] != '{') continue;
            const nlohmann::json j = nlohmann::json::parse(line, nullptr, false);
            if (j.is_discarded() || !j.contains("min")) continue;
            Box box;
            for (int a = 0; a < 3; ++a) {
                box.min[a] = j["min"][a].get<double>();
                box.max[a] = j["max"][a].get<double>();
            }
            out[j["file"].get<std::string>()] = box;
        }
        return out;
    }();
    return bounds;
}

/// The UnitScaleFactor an ASCII FBX file writes (centimetres per unit), read from its text.
std::optional<double> asciiUnitScaleFactor(const fs::path& file) {
    const std::string all = test::readFile(file);
    std::smatch match;
    if (!std::regex_search(all, match,
                           std::regex("\"UnitScaleFactor\"[^\\n]*?,\\s*([0-9.eE+-]+)\\s*\\n")))
        return std::nullopt;
    return std::stod(match[1].str());
}

TEST(RealAssets, SizesInMetresMatchBlender) {
    const std::vector<fs::path> files = realAssets();
    if (files.empty()) GTEST_SKIP() << "../shared/real-assets not present";
    EXPECT_GE(files.size(), 25u);
    const std::map<std::string, Box>& blender = blenderBounds();
    if (blender.empty()) GTEST_SKIP() << "blender is not installed (install-deps.sh installs it)";
    int compared = 0;
    for (const fs::path& file : files) {
        SCOPED_TRACE(file.string());
        MeshFileFacts facts;
        Result<TriangleMesh> mesh = loadMesh(file, {}, &facts);
        ASSERT_TRUE(mesh.ok()) << mesh.error().message;
        const Bounds3 ours = computeBounds(*mesh);
        const Eigen::Vector3d size = ours.max - ours.min;
        Eigen::Vector3d reference;
        if (isAsciiFbx(file)) {
            // Blender reads no ASCII FBX: the file's own unit against its raw numbers.
            const std::optional<double> factor = asciiUnitScaleFactor(file);
            ASSERT_TRUE(factor.has_value());
            Result<TriangleMesh> raw = loadMesh(file, MeshLoadOptions{.unitScale = 1.0});
            ASSERT_TRUE(raw.ok());
            const Bounds3 rawBounds = computeBounds(*raw);
            reference = (rawBounds.max - rawBounds.min) * (*factor / 100.0);
            EXPECT_DOUBLE_EQ(facts.unitScale, *factor / 100.0);
        } else {
            auto found = blender.find(file.string());
            ASSERT_NE(found, blender.end()) << "Blender could not read it";
            reference = found->second.max - found->second.min;
        }
        // Each extent within 1% of Blender's (or of a thousandth of the largest, for a flat one).
        const double slack = 1e-3 * reference.maxCoeff();
        for (int a = 0; a < 3; ++a)
            EXPECT_NEAR(size[a], reference[a], std::max(0.01 * reference[a], slack))
                << "axis " << a << ", unit " << facts.unitScale << " (" << facts.unitSource << ")";
        ++compared;
    }
    EXPECT_EQ(compared, int(files.size()));
}

TEST(RealAssets, FbxUnitsAndTheUnitOption) {
    const fs::path boat = test::realAssetsDir() / "quaternius" / "Boat.fbx";
    const fs::path crate = test::realAssetsDir() / "kenney" / "crate.stl";
    if (!fs::exists(boat) || !fs::exists(crate))
        GTEST_SKIP() << "../shared/real-assets not present";
    MeshFileFacts facts;
    Result<TriangleMesh> inFile = loadMesh(boat, {}, &facts);
    ASSERT_TRUE(inFile.ok());
    EXPECT_DOUBLE_EQ(facts.unitScale, 0.01);  // UnitScaleFactor 1: centimetres
    EXPECT_NE(facts.unitSource.find("UnitScaleFactor 1"), std::string::npos) << facts.unitSource;
    Result<TriangleMesh> raw = loadMesh(boat, MeshLoadOptions{.unitScale = 1.0});
    ASSERT_TRUE(raw.ok());
    for (std::size_t i = 0; i < raw->positions.size(); ++i)
        EXPECT_NEAR((inFile->positions[i] - 0.01 * raw->positions[i]).norm(), 0, 1e-12);
    // STL has no unit: metres unless told; "mm" makes it a thousand times smaller.
    MeshFileFacts stlFacts;
    Result<TriangleMesh> metres = loadMesh(crate, {}, &stlFacts);
    Result<TriangleMesh> millimetres =
        loadMesh(crate, MeshLoadOptions{.unitScale = *parseLengthUnit("mm")});
    ASSERT_TRUE(metres.ok() && millimetres.ok());
    EXPECT_EQ(stlFacts.unitScale, 1.0);
    EXPECT_NEAR(computeBounds(*millimetres).diagonal(), 1e-3 * computeBounds(*metres).diagonal(),
                1e-12);
    EXPECT_EQ(parseLengthUnit("cm"), 0.01);
    EXPECT_EQ(parseLengthUnit("0.3048"), 0.3048);
    EXPECT_FALSE(parseLengthUnit("-1").has_value());
    EXPECT_FALSE(parseLengthUnit("nan").has_value());
    EXPECT_FALSE(parseLengthUnit("furlong").has_value());
}

TEST(RealAssets, UvsAreKeptPerPart) {
    // duck.glb: the eyes have UVs, the body and hull shell do not.
    const fs::path duck = test::realAssetsDir() / "dawn-of-the-duck" / "duck.glb";
    if (!fs::exists(duck)) GTEST_SKIP() << "../shared/real-assets not present";
    MeshFileFacts facts;
    Result<TriangleMesh> mesh = loadMesh(duck, {}, &facts);
    ASSERT_TRUE(mesh.ok());
    ASSERT_TRUE(facts.someUvsMissing());
    ASSERT_TRUE(mesh->hasUvs());
    for (const MeshPart& part : facts.parts) {
        double uvArea = 0;
        for (std::size_t t = part.firstTriangle; t < part.firstTriangle + part.triangleCount; ++t)
            uvArea += std::abs(triangleUvArea(*mesh, mesh->triangles[t]));
        if (part.hasUvs)
            EXPECT_GT(uvArea, 0) << part.name;
        else
            EXPECT_EQ(uvArea, 0) << part.name;
    }
}

TEST(RealAssets, EveryModelGivesASolid) {
    const std::vector<fs::path> files = realAssets();
    if (files.empty()) GTEST_SKIP() << "../shared/real-assets not present";
    if (!repairAvailable()) GTEST_SKIP() << "built without CGAL: no mesh repair";
    for (const fs::path& file : files) {
        SCOPED_TRACE(file.string());
        Result<TriangleMesh> mesh = loadMesh(file);
        ASSERT_TRUE(mesh.ok()) << mesh.error().message;
        ValidationReport report = validateMesh(*mesh);
        Result<PhysicsSolid> solid = physicsSolidFor(*mesh, report);
        ASSERT_TRUE(solid.ok()) << solid.error().message;
        EXPECT_TRUE(validateSurface(solid->mesh).closedSolid());
        EXPECT_GT(solid->materialVolume, 0);
        // No bigger than the box around the artist's surface (a wrap adds only its offset).
        const Bounds3 box = computeBounds(*mesh);
        EXPECT_LT(solid->materialVolume, 1.05 * (box.max - box.min).prod());
        std::cout << file.filename().string() << ": " << solid->materialVolume << " m^3, repairs "
                  << describeRepairs(solid->repairs) << "\n";
    }
}

TEST(RealAssets, ValidateSaysUnitBoundsAndHowItIsUsed) {
    const fs::path boat = test::realAssetsDir() / "quaternius" / "Boat.fbx";
    const fs::path spot = test::realAssetsDir() / "keenan-crane" / "spot_triangulated.obj";
    if (!fs::exists(boat)) GTEST_SKIP() << "../shared/real-assets not present";
    const test::CommandOutput run = test::runPlimsoll("validate --json '" + boat.string() + "'");
    const nlohmann::json j = nlohmann::json::parse(run.out);
    EXPECT_DOUBLE_EQ(j.at("unit_scale").get<double>(), 0.01);
    Result<TriangleMesh> mesh = loadMesh(boat);
    ASSERT_TRUE(mesh.ok());
    const Bounds3 bounds = computeBounds(*mesh);
    for (int a = 0; a < 3; ++a) {
        EXPECT_DOUBLE_EQ(j["bounds"]["min"][a].get<double>(), bounds.min[a]);
        EXPECT_DOUBLE_EQ(j["bounds"]["max"][a].get<double>(), bounds.max[a]);
    }
    // About 0.67 m long (Blender: 0.668 m), not 67 m.
    EXPECT_NEAR(bounds.max.z() - bounds.min.z(), 0.668, 0.007);
    if (repairAvailable()) {
        EXPECT_EQ(run.exitCode, 0) << run.out << run.err;
        EXPECT_TRUE(j.at("usable").get<bool>());
        EXPECT_TRUE(j.at("repairs").is_array());
        EXPECT_GT(j.at("material_volume").get<double>(), 0);
    }
    const test::CommandOutput human = test::runPlimsoll("validate '" + boat.string() + "'");
    EXPECT_NE(human.out.find("centimetres"), std::string::npos) << human.out;
    EXPECT_NE(human.out.find(" m (x, y up, z)"), std::string::npos) << human.out;
    if (fs::exists(spot)) {
        const test::CommandOutput asIs = test::runPlimsoll("validate '" + spot.string() + "'");
        EXPECT_EQ(asIs.exitCode, 0);
        EXPECT_NE(asIs.out.find("usable as is"), std::string::npos) << asIs.out;
    }
}

}  // namespace
}  // namespace test_real_assets
}  // namespace plimsoll

namespace plimsoll {
namespace test_real_assets {
namespace {

/// Closed single-part meshes need no repair: what is baked is the mesh as loaded, vertex for
/// vertex (so its bake is byte-identical to a bake of the mesh without the repair step).
TEST(RealAssets, ClosedMeshesAreUsedUnchanged) {
    std::vector<fs::path> files;
    for (const char* name :
         {"box.obj", "buoy.obj", "cylinder.obj", "hull.obj", "plush.obj", "sphere.obj"})
        files.push_back(test::assetPath(name));
    for (const char* name : {"blub_triangulated.obj", "boat.obj", "bunny.obj", "cube.obj",
                             "sphere.obj", "spot.obj", "torus.obj"})
        if (std::optional<fs::path> shared = test::sharedMesh(name)) files.push_back(*shared);
    for (const char* name :
         {"keenan-crane/spot_triangulated.obj", "keenan-crane/blub_triangulated.obj",
          "kenney/crate.glb", "kenney/crate.stl"})
        if (fs::exists(test::realAssetsDir() / name)) files.push_back(test::realAssetsDir() / name);
    for (const fs::path& file : files) {
        SCOPED_TRACE(file.string());
        MeshFileFacts facts;
        Result<TriangleMesh> mesh = loadMesh(file, {}, &facts);
        ASSERT_TRUE(mesh.ok()) << mesh.error().message;
        EXPECT_EQ(facts.unitScale, 1.0);
        ValidationReport report = validateMesh(*mesh);
        Result<PhysicsSolid> solid = physicsSolidFor(*mesh, report);
        ASSERT_TRUE(solid.ok()) << solid.error().message;
        EXPECT_TRUE(solid->repairs.empty()) << describeRepairs(solid->repairs);
        EXPECT_EQ(solid->mesh.positions, mesh->positions);
        EXPECT_EQ(solid->mesh.uvs, mesh->uvs);
        EXPECT_EQ(solid->mesh.triangles, mesh->triangles);
    }
}

}  // namespace
}  // namespace test_real_assets
}  // namespace plimsoll
