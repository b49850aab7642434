// Import through assimp, welding, and the OBJ writer's round trip.
#include "plimsoll/io/mesh_io.h"
#include "plimsoll/samples/primitives.h"

#include "test_support.h"

#include <fstream>
#include <set>

namespace plimsoll {
namespace test_mesh_io {
namespace {

namespace fs = std::filesystem;

fs::path scratch(const std::string& name) {
    fs::path dir = fs::temp_directory_path() / "plimsoll_tests";
    fs::create_directories(dir);
    return dir / name;
}

TEST(MeshIo, ObjRoundTripKeepsEveryDouble) {
    const TriangleMesh box = makeBox(Eigen::Vector3d(1.0, 0.5, 0.25));
    const fs::path path = scratch("roundtrip_box.obj");
    ASSERT_TRUE(writeObj(box, path).ok());
    Result<TriangleMesh> loaded = loadMesh(path);
    ASSERT_TRUE(loaded.ok()) << loaded.error().message;
    EXPECT_EQ(loaded->triangleCount(), box.triangleCount());
    ASSERT_TRUE(loaded->hasUvs());
    // assimp reads floats: positions come back to float precision, triangle by triangle.
    for (std::size_t t = 0; t < box.triangles.size(); ++t) {
        for (int k = 0; k < 3; ++k) {
            const auto& a = box.positions[box.triangles[t][k]];
            const auto& b = loaded->positions[loaded->triangles[t][k]];
            EXPECT_LT((a - b).norm(), 1e-7);
            EXPECT_LT((box.uvs[box.triangles[t][k]] - loaded->uvs[loaded->triangles[t][k]]).norm(),
                      1e-7);
        }
    }
}

TEST(MeshIo, WeldJoinsSeamVertices) {
    const TriangleMesh sphere = makeUvSphere(0.5, 16, 8);
    const auto ids = weldByPosition(sphere);
    std::set<std::uint32_t> unique(ids.begin(), ids.end());
    // 16 x 7 ring vertices plus two poles.
    EXPECT_EQ(unique.size(), 16u * 7u + 2u);
}

TEST(MeshIo, MissingFileIsNamed) {
    Result<TriangleMesh> r = loadMesh("/nonexistent/dir/thing.obj");
    ASSERT_FALSE(r.ok());
    EXPECT_NE(r.error().message.find("/nonexistent/dir/thing.obj"), std::string::npos);
    EXPECT_NE(r.error().message.find("no such file"), std::string::npos);
}

TEST(MeshIo, GarbageFileIsAnErrorNotACrash) {
    const fs::path path = scratch("garbage.obj");
    std::ofstream(path) << "this is not\x01\x02 a mesh\nf 1 2 3\n";
    Result<TriangleMesh> r = loadMesh(path);
    ASSERT_FALSE(r.ok());
    EXPECT_NE(r.error().message.find(path.string()), std::string::npos);
}

TEST(MeshIo, FailedWriteKeepsThePreviousFile) {
    const fs::path path = scratch("kept.obj");
    const TriangleMesh box = makeBox(Eigen::Vector3d::Ones());
    ASSERT_TRUE(writeObj(box, path).ok());
    const auto before = fs::file_size(path);
    // A target inside a missing folder cannot be written; a folder in the way cannot be
    // replaced: in both cases nothing is destroyed.
    EXPECT_FALSE(writeObj(box, scratch("missing_dir") / "x" / "y.obj").ok());
    const fs::path blocked = scratch("blocked");
    fs::create_directories(blocked / "inner");
    EXPECT_FALSE(writeObj(box, blocked).ok());
    EXPECT_TRUE(fs::is_directory(blocked / "inner"));
    EXPECT_EQ(fs::file_size(path), before);
}

TEST(ObjWriter, WritesFacesWithoutUvsAndFullPrecision) {
    TriangleMesh mesh;
    mesh.positions = {{0.1, 0.0, 0.0}, {1.0, 1.0 / 3.0, 0.0}, {0.0, 0.0, -1e-300 / 3.0}};
    mesh.triangles = {{0, 1, 2}};
    const fs::path path = test::scratchFolder("plimsoll_test_primitives") / "no_uvs.obj";
    ASSERT_TRUE(writeObj(mesh, path).ok());
    EXPECT_EQ(test::readFile(path),
              "# written by Plimsoll\n"
              "v 0.10000000000000001 0 0\n"
              "v 1 0.33333333333333331 0\n"
              "v 0 0 -3.3333333333333334e-301\n"
              "f 1 2 3\n");
}

TEST(ObjWriter, FailsForAMissingFolder) {
    const TriangleMesh box = makeBox({1.0, 1.0, 1.0});
    const Status written = writeObj(
        box, test::scratchFolder("plimsoll_test_primitives") / "no such folder" / "box.obj");
    ASSERT_FALSE(written.ok());
    EXPECT_NE(written.error().message.find("box.obj"), std::string::npos);
}
}  // namespace
}  // namespace test_mesh_io
}  // namespace plimsoll
