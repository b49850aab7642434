// Hostile input and faults (the attacker's view of every loader and writer): files that are not
// regular files, paths that leave their folder, inputs that crashed or exhausted assimp, the PNG
// readers or the runtime, saves killed at every step or stopped by a full disk, and non-finite
// arguments to the C API. Each test reproduces one class of the fault and checks the clear
// error (naming the file and the problem) or the preserved files that replace it.
#include "cli_runner.h"
#include "test_support.h"

#include "document/command.h"
#include "document/document.h"

#include "plimsoll/bake/bake.h"
#include "plimsoll/io/painted_map_io.h"
#include "plimsoll/io/graph_json.h"
#include "plimsoll/surface/painted_map.h"
#include "plimsoll/core/limits.h"
#include "plimsoll/graph/graph.h"
#include "plimsoll/io/bake_io.h"
#include "plimsoll/export/bundle.h"
#include "plimsoll/io/file_util.h"

#include "io/exr_io.h"
#include "io/test_hooks.h"
#include "plimsoll/io/mesh_io.h"
#include "plimsoll/project/project.h"

#include "plimsoll_runtime.h"
#include "plimsoll_runtime/runtime.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfInputFile.h>
#include <ImfOutputFile.h>
#include <Imath/half.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <limits>
#include <tuple>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

namespace plimsoll {
namespace test_hostile_input {
namespace {

namespace fs = std::filesystem;

// --- non-regular files ------------------------------------------------------------------------

TEST(HostileFiles, AFifoIsRefusedByEveryLoaderWithoutBlocking) {
    const fs::path dir = test::freshFolder("hostile", "fifo");
    const auto start = std::chrono::steady_clock::now();
    for (const char* name : {"mesh.obj", "mesh.ply", "p.plim.json", "g.graph.json", "map.png"}) {
        const fs::path fifo = dir / name;
        ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
        std::string message;
        const std::string n(name);
        if (n.starts_with("mesh"))
            message = test::messageOf(loadMesh(fifo));
        else if (n.ends_with(".plim.json"))
            message = test::messageOf(loadProject(fifo));
        else if (n.ends_with(".graph.json"))
            message = test::messageOf(loadGraph(fifo));
        else
            message = test::messageOf(loadPaintedMap(fifo));
        EXPECT_CONTAINS(message, fifo.string() + ": is a FIFO, not a regular file");
    }
    // A FIFO with no writer blocks an ordinary open forever: these returned at once.
    EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(), 5.0);
    // Through the commands: a project's mesh and an edit script (a hang is killed at 10 s).
    ASSERT_EQ(::mkfifo((dir / "fifo_mesh.obj").c_str(), 0600), 0);
    ASSERT_EQ(::mkfifo((dir / "script.json").c_str(), 0600), 0);
    std::ofstream(dir / "uses_fifo.plim.json")
        << R"({"schema_version": 1, "name": "fifo", "bodies": [{"name": "b", "mesh": "fifo_mesh.obj",)"
        << R"( "texture_size": 16, "material": {"density": 500}}]})";
    fs::copy_file(test::assetPath("box.obj"), dir / "box.obj");
    std::ofstream(dir / "box.plim.json")
        << R"({"schema_version": 1, "name": "box", "bodies": [{"name": "b", "mesh": "box.obj",)"
        << R"( "texture_size": 16, "material": {"density": 500}}]})";
    const std::pair<std::string, std::string> commands[] = {
        {"simulate '" + (dir / "uses_fifo.plim.json").string() + "' --seconds 0.1",
         "fifo_mesh.obj: is a FIFO"},
        {"edit '" + (dir / "box.plim.json").string() + "' --script '" +
             (dir / "script.json").string() + "' --no-save",
         "script.json: is a FIFO"},
    };
    for (const auto& [args, message] : commands) {
        const test::CommandOutput run = test::runPlimsoll(args, "timeout -s KILL 10");
        EXPECT_EQ(run.exitCode, 1) << args << "\n" << run.err;
        EXPECT_CONTAINS(run.err, message);
    }
}

TEST(HostileFiles, ALinkToADeviceIsRefusedAndAPathWithANulByteIsNotCutShort) {
    const fs::path dir = test::freshFolder("hostile", "device");
    fs::create_symlink("/dev/zero", dir / "zero.stl");
    EXPECT_CONTAINS(test::messageOf(loadMesh(dir / "zero.stl")),
                    "is a character device, not a regular file");
    EXPECT_CONTAINS(test::messageOf(readWholeFile(dir / "zero.stl", 1000, "kTest")),
                    "character device");
    // "a.obj\0b": a C open would read a.obj.
    test::writeFile(dir / "a.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
    const std::string withNul = (dir / "a.obj").string() + std::string(1, '\0') + "b";
    EXPECT_CONTAINS(test::messageOf(loadMesh(fs::path(withNul))), "the path holds a NUL byte");
    // A regular file larger than the limit is refused before it is read.
    test::writeFile(dir / "big.json", std::string(2000, ' '));
    EXPECT_CONTAINS(test::messageOf(readWholeFile(dir / "big.json", 1000, "kTest")),
                    "more than the limit kTest");
}

// --- paths that leave their folder ---------------------------------------------------------------

TEST(HostilePaths, SafeFileNamesAndPathsInsideNeverLeaveTheirFolder) {
    for (const std::string name :
         {"", ".", "..", "...", "../x", "a/b", "/etc", ".hidden", "a\\b", "é"}) {
        const std::string safe = safeFileName(name, "body0");
        SCOPED_TRACE("'" + name + "' -> '" + safe + "'");
        EXPECT_FALSE(safe.empty());
        EXPECT_NE(safe.front(), '.');
        EXPECT_EQ(safe.find('/'), std::string::npos);
        EXPECT_EQ(safe.find('\\'), std::string::npos);
        EXPECT_EQ((fs::path("/out") / safe).lexically_normal().parent_path(), fs::path("/out"));
    }
    EXPECT_EQ(safeFileName("hull-2.v1", "body0"), "hull-2.v1");  // a plain name stays as it is
    EXPECT_EQ(safeFileName("..", "project"), "project..");
    EXPECT_EQ(*pathInside("/b", "frames/000/a.exr", "file"), fs::path("/b/frames/000/a.exr"));
    for (const std::string& bad : std::vector<std::string>{"../x", "a/../../x", "/etc/passwd", "",
                                                           "a\\..\\x", std::string("a\0b", 3)}) {
        EXPECT_FALSE(pathInside("/b", bad, "file").ok()) << bad;
    }
    EXPECT_CONTAINS(test::messageOf(pathInside("/b", "../x", "manifest.json: file path")),
                    "manifest.json: file path \"../x\" leaves the folder /b (a '..' component)");
}

/// A one-body project on the box asset, named `file` in `dir`.
fs::path writeBoxProjectAs(const fs::path& dir, const std::string& file) {
    const fs::path path = dir / file;
    std::ofstream(path)
        << R"({"schema_version": 1, "name": "box", "bodies": [{"name": "../../box", "mesh": ")"
        << test::assetPath("box.obj").string()
        << R"(", "texture_size": 16, "material": {"density": 500}}]})";
    return path;
}

TEST(HostilePaths, ExportOfAProjectNamedDotDotStaysInsideOut) {
    const fs::path dir = test::freshFolder("hostile", "export_stem");
    const fs::path out = dir / "out";
    fs::create_directories(out);
    fs::create_directories(dir / "keep");
    test::writeFile(dir / "keep" / "precious.txt", "do not delete");
    // "...plim.json" has the stem "..": it used to export to OUT/.. and swap away the folders
    // beside OUT. The body is named "../../box" too.
    const fs::path project = writeBoxProjectAs(dir, "...plim.json");
    const test::CommandOutput run =
        test::runPlimsoll("export '" + project.string() + "' --out '" + out.string() + "' --quiet");
    ASSERT_EQ(run.exitCode, 0) << run.err;
    EXPECT_EQ(test::readFile(dir / "keep" / "precious.txt"), "do not delete");
    std::vector<fs::path> bundles;
    for (const auto& entry : fs::recursive_directory_iterator(out)) {
        if (entry.path().filename() == "manifest.json")
            bundles.push_back(entry.path().parent_path());
    }
    ASSERT_EQ(bundles.size(), 1u);
    EXPECT_EQ(bundles[0].parent_path().parent_path(), out);  // OUT/<project>/<body>
    EXPECT_TRUE(verifyBundle(bundles[0]).ok());
}

/// A glTF of one triangle whose buffer has the URI `uri` (the buffer itself is `bin`).
std::string triangleGltf(const std::string& uri) {
    return R"({"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}],
      "nodes": [{"mesh": 0}], "meshes": [{"primitives": [{"attributes": {"POSITION": 0}}]}],
      "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3",
                     "min": [0, 0, 0], "max": [1, 1, 0]}],
      "bufferViews": [{"buffer": 0, "byteLength": 36}],
      "buffers": [{"uri": ")" +
           uri + R"(", "byteLength": 36}]})";
}
std::string triangleBin() {
    const float p[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
    return std::string(reinterpret_cast<const char*>(p), sizeof p);
}

TEST(HostilePaths, GltfBufferUrisCannotLeaveTheMeshFolder) {
    const fs::path dir = test::freshFolder("hostile", "gltf_uri");
    fs::create_directories(dir / "mesh");
    test::writeFile(dir / "outside.bin", triangleBin());
    test::writeFile(dir / "mesh" / "inside.bin", triangleBin());
    test::writeFile(dir / "mesh" / "ok.gltf", triangleGltf("inside.bin"));
    Result<TriangleMesh> ok = loadMesh(dir / "mesh" / "ok.gltf");
    ASSERT_TRUE(ok.ok()) << ok.error().message;
    EXPECT_EQ(ok->triangles.size(), 1u);
    const std::pair<const char*, const char*> cases[] = {
        {"../outside.bin", "a '..' component"},
        {"/dev/zero", "an absolute path"},
    };
    for (const auto& [uri, why] : cases) {
        const fs::path file = dir / "mesh" / "escape.gltf";
        test::writeFile(file, triangleGltf(uri));
        const std::string message = test::messageOf(loadMesh(file));
        EXPECT_CONTAINS(message, file.string());
        EXPECT_CONTAINS(message, std::string("leaves the folder"));
        EXPECT_CONTAINS(message, why);
    }
    // Links are never followed, whatever they name (a device, a file outside, a folder on the
    // way), and a FIFO inside the folder is not a regular file.
    fs::create_symlink("/dev/zero", dir / "mesh" / "zero.bin");
    fs::create_symlink(dir / "outside.bin", dir / "mesh" / "out.bin");
    fs::create_directory_symlink(dir, dir / "mesh" / "up");
    ASSERT_EQ(::mkfifo((dir / "mesh" / "fifo.bin").c_str(), 0600), 0);
    const std::pair<const char*, const char*> refused[] = {
        {"zero.bin", "zero.bin: is (or passes through) a symbolic link, which is not followed"},
        {"out.bin", "out.bin: is (or passes through) a symbolic link, which is not followed"},
        {"up/outside.bin", "up/outside.bin: is (or passes through) a symbolic link"},
        {"fifo.bin", "fifo.bin: not a regular file"},
    };
    for (const auto& [uri, why] : refused) {
        test::writeFile(dir / "mesh" / "linked.gltf", triangleGltf(uri));
        const std::string message = test::messageOf(loadMesh(dir / "mesh" / "linked.gltf"));
        EXPECT_CONTAINS(message, "linked.gltf: a file it refers to: ");
        EXPECT_CONTAINS(message, why);
    }
    // From memory nothing is opened at all.
    EXPECT_FALSE(loadMeshFromMemory(triangleGltf("inside.bin"), "gltf", "memory.gltf").ok());
}

// --- inputs that crashed assimp ------------------------------------------------------------------

const char* kPlyHeader =
    "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\n"
    "property float z\nelement face %d\nproperty list uchar int vertex_indices\nend_header\n"
    "0 0 0\n1 0 0\n0 1 0\n0 0 1\n";

std::string asciiPly(const std::string& faces, int count) {
    char header[512];
    std::snprintf(header, sizeof header, kPlyHeader, count);
    return header + faces;
}

/// A binary little-endian PLY of the 4 vertices above and faces of int indices.
std::string binaryPly(const std::vector<std::vector<std::int32_t>>& faces) {
    std::string s =
        "ply\nformat binary_little_endian 1.0\nelement vertex 4\nproperty float x\n"
        "property float y\nproperty float z\nelement face " +
        std::to_string(faces.size()) + "\nproperty list uchar int vertex_indices\nend_header\n";
    const float v[12] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1};
    s.append(reinterpret_cast<const char*>(v), sizeof v);
    for (const auto& f : faces) {
        s += static_cast<char>(f.size());
        s.append(reinterpret_cast<const char*>(f.data()), f.size() * sizeof(std::int32_t));
    }
    return s;
}

TEST(AssimpGuards, PlyFacesAreCheckedBeforeAssimpReadsThem) {
    const fs::path dir = test::freshFolder("hostile", "ply");
    const std::string tetra = "3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n";
    test::writeFile(dir / "ok.ply", asciiPly(tetra, 4));
    Result<TriangleMesh> ok = loadMesh(dir / "ok.ply");
    ASSERT_TRUE(ok.ok()) << ok.error().message;
    EXPECT_EQ(ok->triangles.size(), 4u);
    test::writeFile(dir / "ok_binary.ply", binaryPly({{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}}));
    Result<TriangleMesh> okBinary = loadMesh(dir / "ok_binary.ply");
    ASSERT_TRUE(okBinary.ok()) << okBinary.error().message;
    EXPECT_EQ(okBinary->triangles.size(), 4u);

    const std::pair<std::string, std::string> cases[] = {
        // Each of these crashed assimp (SIGSEGV or an abort in its triangulation).
        {asciiPly("3 0 2 1\n3 0 1 9\n", 2),
         "PLY face 1 (line 15): vertex index 9 out of range (the file declares 4 vertices)"},
        {asciiPly("3 0 2 -1\n", 1), "vertex index -1 out of range"},
        {binaryPly({{0, 2, 1}, {0, 1, 1000000}}), "PLY face 1: vertex index 1000000 out of range"},
        {binaryPly({{0, 2, -7}}), "vertex index -7 out of range"},
        // A list count of 255 read silently across the following lines.
        {asciiPly("255 0 1 2\n3 0 1 3\n", 2), "fewer values than its properties declare"},
        {asciiPly("3 0 1 2 3\n", 1), "more values than its properties declare ('3')"},
        {asciiPly("3 0 1 x\n", 1), "'x' is not an integer"},
    };
    for (const auto& [bytes, expected] : cases) {
        test::writeFile(dir / "bad.ply", bytes);
        const std::string message = test::messageOf(loadMesh(dir / "bad.ply"));
        EXPECT_CONTAINS(message, (dir / "bad.ply").string());
        EXPECT_CONTAINS(message, expected);
    }
}

/// A big-endian scalar of a binary PLY body.
template <class T>
void appendBigEndian(std::string& out, T value) {
    char bytes[sizeof(T)];
    std::memcpy(bytes, &value, sizeof(T));
    for (std::size_t b = sizeof(T); b-- > 0;) out += bytes[b];
}

TEST(AssimpGuards, APlyReachesAssimpOnlyAsTheCanonicalPlyItsReaderWrites) {
    const fs::path dir = test::freshFolder("hostile", "ply_canonical");
    // A unit square of two quads (a 2 x 1 strip) with colours, normals and texture
    // coordinates named s, t, written three ways: ASCII, big-endian doubles with the faces
    // before the vertices, and with an edge element and a face property besides the corners.
    const double xyz[6][3] = {{0, 0, 0}, {0.5, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0.5, 1, 0}, {1, 1, 0}};
    const double st[6][2] = {{0, 0}, {0.25, 0}, {0.5, 0}, {0, 0.75}, {0.25, 0.75}, {0.5, 0.75}};
    const int quads[2][4] = {{0, 1, 4, 3}, {1, 2, 5, 4}};

    std::string ascii =
        "ply\nformat ascii 1.0\ncomment made by hand\nelement vertex 6\n"
        "property float x\nproperty float y\nproperty float z\nproperty uchar red\n"
        "property float nx\nproperty float s\nproperty float t\nelement edge 1\n"
        "property int vertex1\nproperty int vertex2\nelement face 2\n"
        "property uchar flags\nproperty list uchar int vertex_indices\nend_header\n";
    for (int v = 0; v < 6; ++v)
        ascii += std::to_string(xyz[v][0]) + " " + std::to_string(xyz[v][1]) + " 0 200 1 " +
                 std::to_string(st[v][0]) + " " + std::to_string(st[v][1]) + "\n";
    ascii += "0 1\n";
    for (const auto& q : quads)
        ascii += "7 4 " + std::to_string(q[0]) + " " + std::to_string(q[1]) + " " +
                 std::to_string(q[2]) + " " + std::to_string(q[3]) + "\n";

    std::string big =
        "ply\nformat binary_big_endian 1.0\nelement face 2\n"
        "property list ushort uint vertex_index\nelement vertex 6\nproperty double x\n"
        "property double y\nproperty double z\nproperty list uchar float extra\n"
        "property double texture_u\nproperty double texture_v\nend_header\n";
    for (const auto& q : quads) {
        appendBigEndian<std::uint16_t>(big, 4);
        for (int c : q) appendBigEndian<std::uint32_t>(big, static_cast<std::uint32_t>(c));
    }
    for (int v = 0; v < 6; ++v) {
        for (double c : xyz[v]) appendBigEndian(big, c);
        big += '\x01';
        appendBigEndian(big, 9.0f);
        appendBigEndian(big, st[v][0]);
        appendBigEndian(big, st[v][1]);
    }

    for (const auto& [name, bytes] :
         {std::pair<std::string, std::string>{"ascii.ply", ascii}, {"big.ply", big}}) {
        test::writeFile(dir / name, bytes);
        Result<TriangleMesh> mesh = loadMesh(dir / name, {.joinIdenticalVertices = false});
        ASSERT_TRUE(mesh.ok()) << mesh.error().message;
        ASSERT_EQ(mesh->positions.size(), 6u) << name;
        ASSERT_EQ(mesh->uvs.size(), 6u) << name;
        ASSERT_EQ(mesh->triangles.size(), 4u) << name;
        for (int v = 0; v < 6; ++v) {
            EXPECT_EQ(mesh->positions[v], Eigen::Vector3d(xyz[v][0], xyz[v][1], xyz[v][2]))
                << name << " " << v;
            EXPECT_EQ(mesh->uvs[v], Eigen::Vector2d(st[v][0], st[v][1])) << name << " " << v;
        }
        // The quads' triangles cover the square once: their areas add up to 1.
        double area = 0;
        for (const Triangle& t : mesh->triangles)
            area += 0.5 * (mesh->positions[t[1]] - mesh->positions[t[0]])
                              .cross(mesh->positions[t[2]] - mesh->positions[t[0]])
                              .norm();
        EXPECT_DOUBLE_EQ(area, 1.0) << name;
    }

    const std::pair<std::string, std::string> refused[] = {
        // The PLY fuzzer's eighth finding: no vertex element, a corner list under another
        // name; assimp allocated 15 GB for it.
        {"ply\nformat ascii 1.0\nelement vex 3\nproperty float x\nproperty float y\nproperty float "
         "z\n"
         "element face 1\nproperty list uint uint vertex_i~dices\nend_header\n0 0 0\n1 0 0\n0 1 "
         "0\n3 0 1 2\n",
         "PLY header has no vertex element"},
        {asciiPly("", 0), "PLY file has no faces (a point cloud is not a surface)"},
        {"ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty "
         "float z\n"
         "element face 1\nproperty list uchar int corners\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 "
         "2\n",
         "PLY face element has no vertex_indices list"},
        {"ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty "
         "float z\n"
         "element tristrips 1\nproperty list int int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 "
         "0\n3 0 1 2\n",
         "triangle strips (element tristrips) are not read"},
        {"ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\nproperty "
         "float z\n"
         "element vertex 1\nproperty float x\nend_header\n0 0 0\n0\n",
         "a second vertex element"},
    };
    for (const auto& [bytes, expected] : refused) {
        test::writeFile(dir / "bad.ply", bytes);
        const std::string message = test::messageOf(loadMesh(dir / "bad.ply"));
        EXPECT_CONTAINS(message, (dir / "bad.ply").string());
        EXPECT_CONTAINS(message, expected);
    }
}

TEST(AssimpGuards, AGlbWithoutItsMagicNeverReachesAssimp) {
    // The GLB fuzzer's first finding: OBJ-like bytes named .glb overflowed a buffer in assimp.
    const fs::path dir = test::freshFolder("hostile", "glb_magic");
    test::writeFile(dir / "not.glb", std::string("gusemtllTF\x02\0\0\0JSON{\"asset\": {}}", 30));
    Result<TriangleMesh> loaded = loadMesh(dir / "not.glb");
    ASSERT_FALSE(loaded.ok());
    EXPECT_EQ(loaded.error().kind, ErrorKind::format);
    EXPECT_CONTAINS(loaded.error().message, "not.glb");
    EXPECT_CONTAINS(loaded.error().message, "named .glb but its content is not that format's");
}

TEST(AssimpGuards, ObjVertexLinesHoldOnlyNumbers) {
    // The OBJ fuzzer's third finding: text after a vertex's number overflowed a buffer in assimp.
    const fs::path dir = test::freshFolder("hostile", "obj_numbers");
    test::writeFile(dir / "text.obj", "v 0.5mtllib missi n\nv 0 0 0\nv 1 0 0\nf 1 2 3\n");
    EXPECT_CONTAINS(test::messageOf(loadMesh(dir / "text.obj")),
                    "line 1: '0.5mtllib' is not a number");
    test::writeFile(dir / "short.obj", "v 0 0\nv 0 0 0\nv 1 0 0\nf 1 2 3\n");
    EXPECT_CONTAINS(test::messageOf(loadMesh(dir / "short.obj")), "line 1: 'v' with 2 numbers");
    test::writeFile(dir / "ok.obj", "v 0 0 0\nv 1e0 0 0\nv 0 1 0\nf 1 2 3\n");
    Result<TriangleMesh> ok = loadMesh(dir / "ok.obj");
    ASSERT_TRUE(ok.ok()) << ok.error().message;
    EXPECT_EQ(ok->triangles.size(), 1u);
}

TEST(AssimpGuards, PolygonsBeyondTheCornerLimitAreRefusedInObjAndPly) {
    const fs::path dir = test::freshFolder("hostile", "corners");
    std::string obj;
    const int n = static_cast<int>(kMaxFaceCorners) + 1;
    for (int i = 0; i < n; ++i)
        obj += "v " + std::to_string(std::cos(i * 0.001)) + " " +
               std::to_string(std::sin(i * 0.001)) + " 0\n";
    obj += "f";
    for (int i = 1; i <= n; ++i) obj += " " + std::to_string(i);
    test::writeFile(dir / "fan.obj", obj + "\n");
    EXPECT_CONTAINS(test::messageOf(loadMesh(dir / "fan.obj")), "kMaxFaceCorners");
    std::string face = std::to_string(n);
    for (int i = 0; i < n; ++i) face += " " + std::to_string(i % 4);
    test::writeFile(dir / "fan.ply", asciiPly(face + "\n", 1));
    EXPECT_CONTAINS(test::messageOf(loadMesh(dir / "fan.ply")), "kMaxFaceCorners");
}

TEST(AssimpGuards, DeepOrCyclicGltfNodeTreesAreRefused) {
    const fs::path dir = test::freshFolder("hostile", "gltf_nodes");
    test::writeFile(dir / "inside.bin", triangleBin());
    auto withNodes = [&](const nlohmann::json& nodes) {
        nlohmann::json g = nlohmann::json::parse(triangleGltf("inside.bin"));
        g["nodes"] = nodes;
        return g.dump();
    };
    auto chain = [](int depth) {
        nlohmann::json nodes = nlohmann::json::array();
        for (int i = 0; i < depth; ++i) {
            nlohmann::json node = nlohmann::json::object();
            if (i + 1 < depth)
                node["children"] = {i + 1};
            else
                node["mesh"] = 0;
            nodes.push_back(node);
        }
        return nodes;
    };
    test::writeFile(dir / "shallow.gltf", withNodes(chain(20)));
    Result<TriangleMesh> shallow = loadMesh(dir / "shallow.gltf");
    ASSERT_TRUE(shallow.ok()) << shallow.error().message;
    EXPECT_EQ(shallow->triangles.size(), 1u);
    // 20000 nested nodes overflowed assimp's stack.
    test::writeFile(dir / "deep.gltf", withNodes(chain(20000)));
    EXPECT_CONTAINS(test::messageOf(loadMesh(dir / "deep.gltf")), "kMaxGltfNodeDepth");
    test::writeFile(
        dir / "cycle.gltf",
        withNodes(nlohmann::json::parse(
            R"([{"children": [1]}, {"children": [2], "mesh": 0}, {"children": [1]}])")));
    EXPECT_CONTAINS(test::messageOf(loadMesh(dir / "cycle.gltf")), "is its own ancestor");
    test::writeFile(dir / "dangling.gltf",
                    withNodes(nlohmann::json::parse(R"([{"children": [7], "mesh": 0}])")));
    EXPECT_CONTAINS(test::messageOf(loadMesh(dir / "dangling.gltf")),
                    "names child 7, not a node of the file");
}

/// A GLB: header, a JSON chunk with `declared` as its length, the JSON itself.
std::string glb(const std::string& json, std::uint32_t declared) {
    std::string s = "glTF";
    auto u32 = [&](std::uint32_t v) { s.append(reinterpret_cast<const char*>(&v), 4); };
    u32(2);
    u32(static_cast<std::uint32_t>(12 + 8 + json.size()));
    u32(declared);
    u32(0x4E4F534Au);
    return s + json;
}

TEST(AssimpGuards, GlbChunksLongerThanTheFileAreRefusedBeforeAllocating) {
    const fs::path dir = test::freshFolder("hostile", "glb");
    const std::string json = R"({"asset": {"version": "2.0"}})";
    test::writeFile(dir / "bomb.glb", glb(json, 0xFFFFFFF0u));  // a 4 GB JSON chunk in 60 bytes
    const auto start = std::chrono::steady_clock::now();
    const std::string message = test::messageOf(loadMesh(dir / "bomb.glb"));
    EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(), 2.0);
    EXPECT_CONTAINS(message, "bomb.glb: GLB chunk at byte 12 says 4294967280 bytes, the file has " +
                                 std::to_string(json.size()) + " after it");
}

TEST(AssimpGuards, AnObjByteOrderMarkDoesNotEatTheFirstVertex) {
    const fs::path dir = test::freshFolder("hostile", "bom");
    test::writeFile(dir / "bom.obj", "\xEF\xBB\xBFv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
    Result<TriangleMesh> mesh = loadMesh(dir / "bom.obj");
    ASSERT_TRUE(mesh.ok()) << mesh.error().message;
    ASSERT_EQ(mesh->positions.size(), 3u);
    EXPECT_EQ(mesh->positions[0], Eigen::Vector3d(0, 0, 0));
}

// --- messages that said too little ---------------------------------------------------------------

// Each once printed something a user could not act on: "cannot replace file: Success" (errno
// read after a call that reset it), nlohmann's raw "[json.exception.type_error.302] type must
// be number" without the field, and a cut PNG end chunk named "IEN".
TEST(ClearMessages, FailuresNameTheFileTheFieldAndTheRealCause) {
    const fs::path dir = test::freshFolder("hostile", "messages");
    fs::create_directories(dir / "taken");
    const std::string replaced = test::messageOf(
        writeFileAtomically(dir / "taken", [](std::ostream& out) { return bool(out << "x"); }));
    EXPECT_CONTAINS(replaced, "taken: is a folder, not a regular file: not replaced");
    EXPECT_EQ(replaced.find("Success"), std::string::npos) << replaced;

    const SurfaceTextures baked = [] {
        BakeSettings settings;
        settings.size = 16;
        Result<TriangleMesh> box = loadMesh(test::assetPath("box.obj"));
        EXPECT_TRUE(box.ok());
        return *bakeSurfaceTextures(*box, settings);
    }();
    ASSERT_TRUE(writeBakedTextures(baked, dir / "bake", "box.obj").ok());
    nlohmann::json manifest = nlohmann::json::parse(test::readFile(dir / "bake" / "manifest.json"));
    manifest["texture_size"] = "sixteen";
    test::writeFile(dir / "bake" / "manifest.json", manifest.dump());
    const std::string typed = test::messageOf(readBakedTextures(dir / "bake"));
    EXPECT_CONTAINS(typed, "manifest.json: texture_size: type must be number");
    EXPECT_EQ(typed.find("json.exception"), std::string::npos) << typed;

    // Memory running out: a clear error and exit 1, not "std::bad_alloc" alone nor, in a bake's
    // worker thread, the abort an exception leaving a thread causes.
    // Not in the sanitized build: AddressSanitizer's operator new reports and aborts where the
    // normal one throws std::bad_alloc, so there is no exception to turn into the message.
    if (!test::kSanitizedBuild) {
        const test::CommandOutput starved =
            test::runPlimsoll("bake '" + test::assetPath("box.obj").string() +
                                  "' --size 4096 --out '" + (dir / "big").string() + "'",
                              test::memoryCap(300ull << 20));
        EXPECT_EQ(starved.exitCode, 1) << starved.err;
        EXPECT_CONTAINS(starved.err, "out of memory");
    }

    // The painted map's PNG cut inside its end chunk.
    std::string png = encodePaintedMapPng16(PaintedMap{16, 16, std::vector<float>(256, 0.5f)});
    png.resize(png.size() - 6);
    test::writeFile(dir / "cut.png", png);
    const std::string cut = test::messageOf(loadPaintedMap(dir / "cut.png"));
    EXPECT_CONTAINS(cut, "cut.png: ");
    EXPECT_EQ(cut.find("IEN "), std::string::npos) << cut;
    EXPECT_EQ(cut.find("IEN\""), std::string::npos) << cut;
}

// --- work at the documented limits
// ------------------------------------------------------------------

// A graph of kMaxGraphNodes nodes in a chain: each id was looked up by a scan of every node, for
// every node and pipe (minutes); by hash it validates at once. The duplicate of node 0 is found.
TEST(Limits, AGraphOfTheMaximumNodeCountValidates) {
    WaterGraph graph;
    const std::size_t n = kMaxGraphNodes;
    for (std::size_t i = 0; i < n; ++i) {
        GraphNode node;
        node.id = i + 1 == n ? "n0" : "n" + std::to_string(i);
        node.position = Eigen::Vector3d(double(i), 0, 0);
        node.capacity = 1;
        graph.nodes.push_back(node);
        if (i > 0) graph.pipes.push_back({"n" + std::to_string(i - 1), node.id, 0.01, 0, true});
    }
    const GraphReport report = validateGraph(graph);
    ASSERT_TRUE(report.has(GraphProblemKind::DuplicateId)) << report.format();
    EXPECT_CONTAINS(report.format(), "node 99999 'n0': id already used by node 0");
    EXPECT_FALSE(report.has(GraphProblemKind::DanglingPipe)) << report.format();
    // The last pipe names "n0", node 0: the duplicate itself is left alone, one group of two.
    EXPECT_CONTAINS(report.format(), "2 groups of nodes that no open pipe joins");
}

// The same limit through every stage that reads a graph: the project's load (validation
// against the mesh), the export (the texel map: a scan of every node per texel entry) and the
// runtime's load (ids to indices, the node of every shared texel). Each was quadratic in the
// nodes; at kMaxGraphNodes it took minutes, now seconds. Nodes at pseudo-random points inside
// the box asset, every third a box compartment, in a chain of pipes.
TEST(Limits, AGraphOfTheMaximumNodeCountExportsAndLoadsInTheRuntime) {
    const fs::path dir = test::freshFolder("hostile", "big_graph");
    fs::copy_file(test::assetPath("box.obj"), dir / "box.obj");
    WaterGraph graph;
    std::uint64_t state = 7;
    auto uniform = [&](double lo, double hi) {
        state = state * 6364136223846793005ull + 1442695040888963407ull;
        return lo + (hi - lo) * (static_cast<double>(state >> 11) / 9007199254740992.0);
    };
    for (std::size_t i = 0; i < kMaxGraphNodes; ++i) {
        GraphNode node;
        node.id = "n" + std::to_string(i);
        node.position = {uniform(-0.45, 0.45), uniform(-0.2, 0.2), uniform(-0.1, 0.1)};
        node.capacity = 1e-6;
        if (i % 3 == 0) node.boxSize = Eigen::Vector3d::Constant(0.01);
        graph.nodes.push_back(node);
        if (i > 0) graph.pipes.push_back({"n" + std::to_string(i - 1), node.id, 0.001, 0, true});
    }
    ASSERT_TRUE(saveGraph(graph, dir / "big.graph.json").ok());
    ASSERT_TRUE(
        savePaintedMap(PaintedMap{16, 16, std::vector<float>(256, 1.0f)}, dir / "perm.png").ok());
    std::ofstream(dir / "big.plim.json")
        << R"({"schema_version": 1, "name": "big graph", "bodies": [{"name": "box", "mesh": "box.obj",)"
        << R"( "texture_size": 64, "material": {"density": 500}, "permeability_map": "perm.png",)"
        << R"( "water_graph": {"graph": "big.graph.json"}}]})";
    Result<Project> project = loadProject(dir / "big.plim.json");
    ASSERT_TRUE(project.ok()) << project.error().message;
    Result<BundleReport> report = writeBodyBundle(*project, 0, dir / "bundle");
    ASSERT_TRUE(report.ok()) << report.error().message;

    std::string error;
    auto bundle = plimsoll_runtime::loadBundle((dir / "bundle").string(), error);
    ASSERT_TRUE(bundle) << error;
    ASSERT_TRUE(bundle->graph());
    const plimsoll_runtime::GraphLayout& loaded = *bundle->graph();
    ASSERT_EQ(loaded.nodes().size(), kMaxGraphNodes);
    ASSERT_EQ(loaded.pipes().size(), kMaxGraphNodes - 1);
    EXPECT_EQ(loaded.pipes().back().nodeA, int(kMaxGraphNodes) - 2);
    EXPECT_EQ(loaded.pipes().back().nodeB, int(kMaxGraphNodes) - 1);
    // Every sample feeds the node a scan of every node names for its point (texel_nodes.exr
    // for texels with one sample, the runtime's tree for shared ones), checked on a spread.
    const std::vector<plimsoll_runtime::Sample>& samples = bundle->samples();
    ASSERT_EQ(loaded.sampleNodes().size(), samples.size());
    ASSERT_GT(samples.size(), 1000u);
    for (std::size_t i = 0; i < samples.size(); i += 97) {
        const plimsoll_runtime::Vec3& p = samples[i].position;
        EXPECT_EQ(loaded.sampleNodes()[i], nearestNode(graph, {p.x, p.y, p.z})) << "sample " << i;
    }
}

// --- decompression bombs
// --------------------------------------------------------------------------

std::uint32_t crc32(const std::string& bytes) {
    std::uint32_t c = 0xFFFFFFFFu;
    for (unsigned char b : bytes) {
        c ^= b;
        for (int k = 0; k < 8; ++k) c = (c & 1) ? 0xEDB88320u ^ (c >> 1) : c >> 1;
    }
    return c ^ 0xFFFFFFFFu;
}

/// A small real PNG whose IHDR claims `side` x `side` pixels (its CRC made right again).
std::string pngDeclaring(std::uint32_t side) {
    PaintedMap map{16, 16, std::vector<float>(256, 0.5f)};
    std::string png = encodePaintedMapPng16(map);
    for (int k = 0; k < 2; ++k) {
        for (int b = 0; b < 4; ++b)
            png[16 + 4 * k + b] = static_cast<char>((side >> (24 - 8 * b)) & 0xFF);
    }
    const std::uint32_t crc = crc32(png.substr(12, 17));
    for (int b = 0; b < 4; ++b) png[29 + b] = static_cast<char>((crc >> (24 - 8 * b)) & 0xFF);
    return png;
}

TEST(Bombs, APaintedMapDeclaringAHugeImageIsRefusedBeforeDecoding) {
    const fs::path dir = test::freshFolder("hostile", "png_bomb");
    test::writeFile(dir / "bomb.png", pngDeclaring(16384));
    const auto start = std::chrono::steady_clock::now();
    const std::string message = test::messageOf(loadPaintedMap(dir / "bomb.png"));
    EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(), 2.0);
    EXPECT_CONTAINS(message,
                    "bomb.png: painted map declares 16384 x 16384 pixels, outside 1..8192 "
                    "(kMaxPaintedMapSide");
    // The real image still decodes.
    test::writeFile(dir / "ok.png", pngDeclaring(16));
    Result<PaintedMap> ok = loadPaintedMap(dir / "ok.png");
    ASSERT_TRUE(ok.ok()) << ok.error().message;
    EXPECT_NEAR(ok->values[0], 0.5f, 1e-4);
}

// --- saves: temporaries, kills at every step, a full disk
// -----------------------------------------

TEST(AtomicSaves, PlantedLinksAtTemporaryNamesAreNeverFollowed) {
    const fs::path dir = test::freshFolder("hostile", "planted");
    const fs::path outside = dir / "outside.txt", target = dir / "project" / "map.png";
    fs::create_directories(target.parent_path());
    test::writeFile(outside, "someone else's file");
    // The names the writers used to take (".NAME.tmp<pid>"), each a link to the file elsewhere.
    for (const std::string& suffix :
         std::vector<std::string>{".tmp" + std::to_string(::getpid()), ".tmp-XXXXXX"})
        fs::create_symlink(outside, target.parent_path() / (".map.png" + suffix));
    ASSERT_TRUE(
        writeFileAtomically(target, [](std::ostream& out) { return bool(out << "new"); }).ok());
    ASSERT_TRUE(replaceFilesTogether({bytesFileWriter(target, "newer")}).ok());
    EXPECT_EQ(test::readFile(outside), "someone else's file");
    EXPECT_EQ(test::readFile(target), "newer");
    EXPECT_FALSE(fs::is_symlink(target));
    // Each temporary is a new file with a name of its own.
    Result<fs::path> a = createTemporaryFor(target), b = createTemporaryFor(target);
    ASSERT_TRUE(a.ok() && b.ok());
    EXPECT_NE(*a, *b);
    EXPECT_EQ(a->parent_path(), target.parent_path());
    struct stat st {};
    ASSERT_EQ(::lstat(a->c_str(), &st), 0);
    EXPECT_TRUE(S_ISREG(st.st_mode));
    fs::remove(*a);
    fs::remove(*b);
}

// OpenEXR wrote the bake's images by opening the temporary by name itself: a link (or a hard
// link) swapped in at that name after mkstemp made it sent the image into another file. Now
// the temporary is opened without following links, refused if it has another name, and
// OpenEXR writes through the descriptor.
TEST(AtomicSaves, ExrImagesAreWrittenThroughTheTemporaryNeverAFileSwappedIn) {
    const fs::path dir = test::freshFolder("hostile", "exr_swap");
    const fs::path outside = dir / "outside.txt", target = dir / "bake" / "position.exr";
    fs::create_directories(target.parent_path());
    test::writeFile(outside, "someone else's file");
    const detail::FloatImage image{4, 2, {"R"}, {0, 1, 2, 3, 4, 5, 6, 7}};
    for (const bool hard : {false, true}) {
        Result<fs::path> temp = createTemporaryFor(target);
        ASSERT_TRUE(temp.ok());
        fs::remove(*temp);
        if (hard)
            fs::create_hard_link(outside, *temp);
        else
            fs::create_symlink(outside, *temp);
        EXPECT_CONTAINS(test::messageOf(detail::writeExrFile(*temp, image, target)),
                        "position.exr: ");
        EXPECT_EQ(test::readFile(outside), "someone else's file")
            << (hard ? "hard link" : "symlink");
        fs::remove(*temp);
    }
    ASSERT_TRUE(detail::writeExr(target, image).ok());
    Result<detail::FloatImage> back = detail::readExr(target, {"R"});
    ASSERT_TRUE(back.ok()) << back.error().message;
    EXPECT_EQ(back->pixels, image.pixels);
    const detail::UintImage ids{2, 2, "node", {1, 2, 3, 4}};
    ASSERT_TRUE(detail::writeExr(dir / "bake" / "nodes.exr", ids).ok());
    Result<detail::UintImage> idsBack = detail::readExrUint(dir / "bake" / "nodes.exr", "node");
    ASSERT_TRUE(idsBack.ok()) << idsBack.error().message;
    EXPECT_EQ(idsBack->pixels, ids.pixels);
}

/// A project with a painted map beside it (the box asset, 16^2 texture).
fs::path writeMappedProject(const fs::path& dir) {
    const fs::path path = dir / "box.plim.json";
    std::ofstream(path)
        << R"({"schema_version": 1, "name": "before", "bodies": [{"name": "box", "mesh": ")"
        << test::assetPath("box.obj").string()
        << R"(", "texture_size": 16, "permeability_map": "perm.png", "material": {"density": 500}}]})";
    EXPECT_TRUE(
        savePaintedMap(PaintedMap{16, 16, std::vector<float>(256, 0.25f)}, dir / "perm.png").ok());
    return path;
}

TEST(AtomicSaves, AProjectSaveKilledAtAnyStepLoadsTheOldOrTheNewSetNeverAMix) {
    const fs::path dir = test::freshFolder("hostile", "kill");
    const fs::path path = writeMappedProject(dir);
    const std::string oldProject = test::readFile(path), oldMap = test::readFile(dir / "perm.png");
    int outcomes[2] = {0, 0};  // old set, new set
    int k = 1;
    for (; k < 100; ++k) {
        test::writeFile(path, oldProject);
        test::writeFile(dir / "perm.png", oldMap);
        const pid_t child = ::fork();
        ASSERT_GE(child, 0);
        if (child == 0) {
            // The save, killed at its k-th file step (a crash or a power cut there).
            auto d = editor::Document::open(path);
            if (!d) ::_exit(3);
            auto fill = editor::makeFillAllCommand(**d, 0, editor::MapChannel::Permeability, 1.0);
            auto rename = editor::makeSetPropertyCommand(**d, "/name", "after");
            if (!fill || !rename || !(*d)->execute(std::move(fill).value()).ok() ||
                !(*d)->execute(std::move(rename).value()).ok())
                ::_exit(4);
            int steps = 0;
            setFileStepHookForTesting([&](const char*, const fs::path&) {
                if (++steps == k) ::_exit(9);
            });
            ::_exit((*d)->save().ok() ? 0 : 5);
        }
        int status = 0;
        ::waitpid(child, &status, 0);
        ASSERT_TRUE(WIFEXITED(status));
        const int code = WEXITSTATUS(status);
        ASSERT_TRUE(code == 0 || code == 9) << "child exit " << code;
        SCOPED_TRACE("killed at step " + std::to_string(k));
        Result<Project> loaded = loadProject(path);  // completes a committed save
        ASSERT_TRUE(loaded.ok()) << loaded.error().message;
        Result<PaintedMap> map = loadPaintedMap(dir / "perm.png");
        ASSERT_TRUE(map.ok()) << map.error().message;
        const bool isNew = loaded->name == "after";
        EXPECT_NEAR(map->values[0], isNew ? 1.0f : 0.25f, 1e-4)
            << "project and map of different saves";
        ++outcomes[isNew];
        if (code == 0) break;  // the save ran to its end: every step was interrupted once
    }
    EXPECT_LT(k, 100);
    EXPECT_GE(outcomes[0], 3);  // killed before the commit: writing map, project, journal
    EXPECT_GE(outcomes[1], 2);  // killed after it, and the run that went through
    EXPECT_FALSE(fs::exists(dir / ".box.plim.json.journal"));
}

TEST(AtomicSaves, AFullDiskFailsTheSaveAndKeepsThePreviousFile) {
    const fs::path dir = test::freshFolder("hostile", "disk_full");
    const fs::path target = dir / "trajectory.csv";
    test::writeFile(target, "previous");
    const pid_t child = ::fork();
    ASSERT_GE(child, 0);
    if (child == 0) {
        // The file size limit stands in for a full disk: write() fails with EFBIG.
        std::signal(SIGXFSZ, SIG_IGN);
        rlimit limit{4096, 4096};
        ::setrlimit(RLIMIT_FSIZE, &limit);
        const Status s = writeFileAtomically(target, [](std::ostream& out) {
            for (int i = 0; i < 10000; ++i) out << "a row of a long trajectory\n";
            return true;
        });
        // The message names the file and the cause the system gave.
        ::_exit(!s.ok() && s.error().message.find("trajectory.csv: write failed: File too large") !=
                               std::string::npos
                    ? 0
                    : 1);
    }
    int status = 0;
    ::waitpid(child, &status, 0);
    ASSERT_TRUE(WIFEXITED(status));
    EXPECT_EQ(WEXITSTATUS(status), 0) << "the save did not fail naming the file and the cause";
    EXPECT_EQ(test::readFile(target), "previous");
    for (const auto& entry : fs::directory_iterator(dir))
        EXPECT_EQ(entry.path().filename(), "trajectory.csv") << "left behind: " << entry.path();
}

/// A project of one body, "box", whose mesh box.obj lies beside it in `dir`; its path.
fs::path writeBoxProject(const fs::path& dir) {
    fs::copy_file(test::assetPath("box.obj"), dir / "box.obj");
    const fs::path path = dir / "box.plim.json";
    std::ofstream(path)
        << R"({"schema_version": 1, "name": "box", "bodies": [{"name": "box",)"
        << R"( "mesh": "box.obj", "texture_size": 16, "material": {"density": 500}}]})";
    return path;
}

TEST(AtomicSaves, SaveAsNeverReplacesAFileTheProjectReadsAndOthersOnlyWhenForced) {
    const fs::path dir = test::freshFolder("hostile", "save_as");
    const fs::path path = writeBoxProject(dir);
    auto d = editor::Document::open(path);
    ASSERT_TRUE(d.ok()) << d.error().message;
    const std::string mesh = test::readFile(dir / "box.obj");
    // Saving the project over its own mesh left a project that could not be opened.
    EXPECT_CONTAINS(test::messageOf((*d)->saveAs(dir / "box.obj", true)),
                    "box.obj: is the mesh of body 'box': saving over it would lose it");
    EXPECT_EQ(test::readFile(dir / "box.obj"), mesh);
    // What the editor's Save As asks about first: nothing for a new name, the existing file
    // for another, and a file the project reads is refused before asking.
    EXPECT_CONTAINS(test::messageOf((*d)->replacedBySaveAs(dir / "box.obj")),
                    "box.obj: is the mesh of body 'box'");
    Result<std::vector<fs::path>> newName = (*d)->replacedBySaveAs(dir / "new.plim.json");
    ASSERT_TRUE(newName.ok()) << newName.error().message;
    EXPECT_TRUE(newName->empty());
    test::writeFile(dir / "other.plim.json", "someone's project");
    Result<std::vector<fs::path>> replaced = (*d)->replacedBySaveAs(dir / "other.plim.json");
    ASSERT_TRUE(replaced.ok()) << replaced.error().message;
    ASSERT_EQ(replaced->size(), 1u);
    EXPECT_EQ(replaced->front().filename(), "other.plim.json");
    EXPECT_CONTAINS(test::messageOf((*d)->saveAs(dir / "other.plim.json")),
                    "other.plim.json: already exists");
    EXPECT_EQ(test::readFile(dir / "other.plim.json"), "someone's project");
    ASSERT_TRUE((*d)->saveAs(dir / "other.plim.json", true).ok());
    EXPECT_TRUE(loadProject(dir / "other.plim.json").ok());
    // Its own file again: no force needed.
    EXPECT_TRUE((*d)->saveAs(dir / "other.plim.json").ok());
}

// The headless paths to the same refusal: the edit script's save_as op needs "force", the
// command line's --save-as needs --force, and neither replaces the project's mesh even forced.
TEST(AtomicSaves, ScriptAndCommandLineSaveAsNeedForceToReplaceAFile) {
    const fs::path dir = test::freshFolder("hostile", "save_as_cli");
    const fs::path path = writeBoxProject(dir);
    const std::string mesh = test::readFile(dir / "box.obj");
    test::writeFile(dir / "other.plim.json", "someone's project");
    int scripts = 0;  // each case its own script file: the cases are all written up front
    auto script = [&](const std::string& ops) {
        const fs::path file = dir / ("script" + std::to_string(scripts++) + ".json");
        test::writeFile(file, ops);
        return "edit '" + path.string() + "' --script '" + file.string() + "'";
    };
    const std::string other = (dir / "other.plim.json").string();
    const std::pair<std::string, std::string> refused[] = {
        {script(R"([{"op": "save_as", "path": ")" + other + R"("}])") + " --no-save",
         "other.plim.json: already exists"},
        {script("[]") + " --save-as '" + other + "'", "other.plim.json: already exists"},
        {script("[]") + " --save-as '" + (dir / "box.obj").string() + "' --force",
         "box.obj: is the mesh of body 'box'"},
        {script(R"([{"op": "save_as", "path": ")" + (dir / "box.obj").string() +
                R"(", "force": true}])") +
             " --no-save",
         "box.obj: is the mesh of body 'box'"},
    };
    for (const auto& [args, message] : refused) {
        const test::CommandOutput run = test::runPlimsoll(args);
        EXPECT_EQ(run.exitCode, 1) << args << "\n" << run.err;
        EXPECT_CONTAINS(run.err, message);
        EXPECT_EQ(test::readFile(dir / "other.plim.json"), "someone's project");
        EXPECT_EQ(test::readFile(dir / "box.obj"), mesh);
    }
    const test::CommandOutput forced =
        test::runPlimsoll(script("[]") + " --save-as '" + other + "' --force");
    EXPECT_EQ(forced.exitCode, 0) << forced.err;
    EXPECT_TRUE(loadProject(dir / "other.plim.json").ok());
}

TEST(HostileScripts, EditScriptValuesOutsideTheirRangeAreRefused) {
    const fs::path dir = test::freshFolder("hostile", "script");
    const fs::path path = writeMappedProject(dir);
    const std::pair<const char*, const char*> cases[] = {
        {R"([{"op": "fill_all", "channel": "permeability", "value": 7}])",
         "value must be in 0..1, not 7"},
        {R"([{"op": "fill_all", "channel": "permeability", "value": -1e308}])",
         "value must be in 0..1"},
        {R"([{"op": "new_map", "channel": "permeability", "size": 100000}])",
         "is outside 1..kMaxPaintedMapSide = 8192"},
    };
    for (const auto& [script, expected] : cases) {
        test::writeFile(dir / "script.json", script);
        const test::CommandOutput run =
            test::runPlimsoll("edit '" + path.string() + "' --script '" +
                              (dir / "script.json").string() + "' --no-save");
        EXPECT_EQ(run.exitCode, 1) << script << "\n" << run.err;
        EXPECT_CONTAINS(run.err, "script.json");
        EXPECT_CONTAINS(run.err, expected);
    }
    // A script that is a FIFO is refused, not waited on.
    ASSERT_EQ(::mkfifo((dir / "fifo.json").c_str(), 0600), 0);
    const test::CommandOutput fifo = test::runPlimsoll(
        "edit '" + path.string() + "' --script '" + (dir / "fifo.json").string() + "' --no-save");
    EXPECT_EQ(fifo.exitCode, 1);
    EXPECT_CONTAINS(fifo.err, "fifo.json: is a FIFO, not a regular file");
}

// --- the runtime
// ------------------------------------------------------------------------------------

namespace rt = plimsoll_runtime;

/// The damaged boat (a water graph and a permeability map) exported once for these tests.
class HostileBundle : public testing::Test {
protected:
    static void SetUpTestSuite() {
        root_ = new fs::path(test::freshFolder("hostile", "bundle"));
        const fs::path source = fs::path(PLIMSOLL_SOURCE_DIR);
        fs::copy(source / "assets", *root_ / "assets", fs::copy_options::recursive);
        fs::copy(source / "projects", *root_ / "projects", fs::copy_options::recursive);
        Result<Project> project = loadProject(*root_ / "projects" / "damaged_boat.plim.json");
        ASSERT_TRUE(project.ok()) << project.error().message;
        Result<BundleReport> report = writeBodyBundle(*project, 0, *root_ / "good");
        ASSERT_TRUE(report.ok()) << report.error().message;
    }
    static void TearDownTestSuite() {
        fs::remove_all(*root_);
        delete root_;
    }
    static fs::path copy(const std::string& name) {
        const fs::path to = *root_ / name;
        fs::remove_all(to);
        fs::copy(*root_ / "good", to, fs::copy_options::recursive);
        return to;
    }
    static std::string loadError(const fs::path& folder, bool verify) {
        std::string error;
        rt::LoadOptions options;
        options.verifyChecksums = verify;
        EXPECT_FALSE(rt::loadBundle(folder.string(), error, options)) << folder;
        return error;
    }
    static void editManifest(const fs::path& folder,
                             const std::function<void(nlohmann::json&)>& edit) {
        nlohmann::json m = nlohmann::json::parse(test::readFile(folder / "manifest.json"));
        edit(m);
        test::writeFile(folder / "manifest.json", m.dump(2));
    }
    static fs::path* root_;
};
fs::path* HostileBundle::root_ = nullptr;

TEST_F(HostileBundle, ManifestPathsStayInsideTheBundleAndLinksOrFifosAreRefused) {
    {
        std::string error;
        ASSERT_TRUE(rt::loadBundle((*root_ / "good").string(), error)) << error;
    }
    for (const char* path : {"../good/graph.json", "/etc/passwd", "/dev/zero"}) {
        const fs::path b = copy("graph_path");
        editManifest(b, [&](nlohmann::json& m) { m["water_graph"]["path"] = path; });
        EXPECT_CONTAINS(loadError(b, false), "leaves the bundle");
    }
    {
        const fs::path b = copy("map_path");
        editManifest(b, [](nlohmann::json& m) {
            m["painted_maps"]["permeability"]["path"] = "../../x.png";
        });
        EXPECT_CONTAINS(loadError(b, false), "leaves the bundle");
    }
    for (const bool verify : {true, false}) {
        const fs::path b = copy("linked");
        fs::copy_file(b / "samples.exr", *root_ / "samples_elsewhere.exr",
                      fs::copy_options::overwrite_existing);
        fs::remove(b / "samples.exr");
        fs::create_symlink(*root_ / "samples_elsewhere.exr", b / "samples.exr");
        EXPECT_CONTAINS(loadError(b, verify),
                        "samples.exr: is (or passes through) a symbolic link");
        fs::remove(b / "samples.exr");
        ASSERT_EQ(::mkfifo((b / "samples.exr").c_str(), 0600), 0);
        EXPECT_CONTAINS(loadError(b, verify), "samples.exr: not a regular file");
    }
}

// The runtime's JSON reader looked for a repeated member name by a scan of the members read so
// far: one object of 300000 members (6 MB, far inside the size limit) cost 4.5e10 string
// comparisons. Now the repeat at its end is found at once.
TEST_F(HostileBundle, AManifestObjectOfManyMembersIsReadInLinearTime) {
    const fs::path b = copy("many_members");
    std::string text = test::readFile(b / "manifest.json");
    std::string padding = "\"padding\": {";
    for (int i = 0; i < 300000; ++i) padding += "\"k" + std::to_string(i) + "\": 0, ";
    padding += "\"k0\": 1}, ";
    text.insert(text.find('{') + 1, padding);
    test::writeFile(b / "manifest.json", text);
    EXPECT_CONTAINS(loadError(b, false), "duplicate member \"k0\"");
}

// The runtime's PNG reader named a cut end chunk "IEN" (the type read past the bytes left).
TEST_F(HostileBundle, APaintedMapCutInItsEndChunkSaysTruncated) {
    const fs::path b = copy("cut_png");
    std::string file;
    editManifest(b, [&](nlohmann::json& m) { file = m["painted_maps"]["permeability"]["path"]; });
    std::string png = encodePaintedMapPng16(PaintedMap{16, 16, std::vector<float>(256, 0.5f)});
    png.resize(png.size() - 6);
    test::writeFile(b / file, png);
    const std::string message = loadError(b, false);
    EXPECT_CONTAINS(message, file + ": cannot read painted map: ");
    EXPECT_CONTAINS(message, "truncated");
    EXPECT_EQ(message.find("IEN "), std::string::npos) << message;
}

/// Rewrites samples.exr of `folder` after `edit` changed its float pixels (10 channels); with
/// `compact`, the compact encoding's channels, all but x and y stored as HALF.
void editSamples(const fs::path& folder, const std::function<void(std::vector<float>&)>& edit,
                 bool compact = false) {
    const fs::path file = folder / "samples.exr";
    static const std::vector<std::string> kFloat = {"x",  "y",  "px", "py",   "pz",
                                                    "ax", "ay", "az", "area", "coverage"};
    static const std::vector<std::string> kCompact = {"x",   "y",   "hpx", "hpy",   "hpz",
                                                      "hax", "hay", "haz", "harea", "coverage"};
    const std::vector<std::string>& kChannels = compact ? kCompact : kFloat;
    int width = 0, height = 0;
    std::vector<float> pixels;
    auto frame = [&] {
        Imf::FrameBuffer buffer;
        const std::size_t stride = sizeof(float) * kChannels.size();
        for (std::size_t c = 0; c < kChannels.size(); ++c)
            buffer.insert(kChannels[c],
                          Imf::Slice(Imf::FLOAT, reinterpret_cast<char*>(pixels.data() + c), stride,
                                     stride * width));
        return buffer;
    };
    {
        Imf::InputFile in(file.c_str());
        const Imath::Box2i w = in.header().dataWindow();
        width = w.max.x + 1;
        height = w.max.y + 1;
        pixels.assign(std::size_t(width) * height * kChannels.size(), 0.0f);
        in.setFrameBuffer(frame());
        in.readPixels(0, height - 1);
    }
    edit(pixels);
    Imf::Header header(width, height);
    header.compression() = Imf::ZIP_COMPRESSION;
    for (std::size_t c = 0; c < kChannels.size(); ++c)
        header.channels().insert(kChannels[c],
                                 Imf::Channel(compact && c >= 2 ? Imf::HALF : Imf::FLOAT));
    Imf::OutputFile out(file.c_str(), header);
    // OpenEXR converts only when reading: HALF channels are written from half pixels.
    Imf::FrameBuffer buffer = frame();
    std::vector<std::vector<Imath::half>> halves(kChannels.size());
    for (std::size_t c = 2; compact && c < kChannels.size(); ++c) {
        for (std::size_t i = 0; i < std::size_t(width) * height; ++i)
            halves[c].push_back(Imath::half(pixels[i * kChannels.size() + c]));
        buffer[kChannels[c]] = Imf::Slice(Imf::HALF, reinterpret_cast<char*>(halves[c].data()),
                                          sizeof(Imath::half), sizeof(Imath::half) * width);
    }
    out.setFrameBuffer(buffer);
    out.writePixels(height);
}

// A compact bundle (export --compact): NaN or infinite halves, a scale or origin that is not
// finite and positive are refused, each named; a reader that knows only float32 samples.exr
// (as 1.2 runtimes) finds no channel "px" and refuses the file rather than misread it.
TEST_F(HostileBundle, CompactSamplesWithNonFiniteHalvesOrScalesAreRefused) {
    const fs::path good = *root_ / "compact";
    if (!fs::exists(good)) {
        Result<Project> project = loadProject(*root_ / "projects" / "damaged_boat.plim.json");
        ASSERT_TRUE(project.ok()) << project.error().message;
        ASSERT_TRUE(writeBodyBundle(*project, 0, good, {}, BundleOptions{true}).ok());
    }
    auto copyCompact = [&](const std::string& name) {
        const fs::path to = *root_ / name;
        fs::remove_all(to);
        fs::copy(good, to, fs::copy_options::recursive);
        return to;
    };
    {
        std::string error;
        ASSERT_TRUE(rt::loadBundle(good.string(), error)) << error;
    }
    const float nan = std::numeric_limits<float>::quiet_NaN(),
                inf = std::numeric_limits<float>::infinity();
    const std::pair<int, float> halves[] = {{2, nan}, {4, inf}, {6, -inf}, {8, nan}};
    for (const auto& [channel, value] : halves) {
        const fs::path b = copyCompact("compact_nonfinite");
        editSamples(
            b, [&](std::vector<float>& p) { p[10 * 5 + channel] = value; }, true);
        EXPECT_CONTAINS(loadError(b, false), "samples.exr: sample 5 holds a NaN or infinite half");
    }
    // Scales: zero, negative, overflowing to infinity (1e999 in the JSON text).
    for (const char* key : {"position_scale", "area_scale"}) {
        for (const char* value : {"0", "-2", "1e999"}) {
            const fs::path b = copyCompact("compact_scale");
            std::string text = test::readFile(b / "manifest.json");
            const std::size_t at = text.find(std::string("\"") + key + "\": ");
            ASSERT_NE(at, std::string::npos);
            const std::size_t begin = text.find(": ", at) + 2,
                              end = text.find_first_of(",\n", begin);
            text.replace(begin, end - begin, value);
            test::writeFile(b / "manifest.json", text);
            const std::string error = loadError(b, false);
            EXPECT_CONTAINS(error, "manifest.json");
            EXPECT_TRUE(error.find(std::string("sample_encoding.") + key +
                                   ": must be finite and > 0") != std::string::npos ||
                        error.find("malformed manifest") != std::string::npos)
                << error;
        }
    }
    {
        const fs::path b = copyCompact("compact_type");
        editManifest(b, [](nlohmann::json& m) { m["sample_encoding"]["type"] = "bfloat16"; });
        EXPECT_CONTAINS(loadError(b, false), "unknown sample encoding \"bfloat16\"");
    }
    {
        // Without the manifest's sample_encoding (what a 1.2 reader sees of it): refused.
        const fs::path b = copyCompact("compact_unknown");
        editManifest(b, [](nlohmann::json& m) { m.erase("sample_encoding"); });
        EXPECT_CONTAINS(loadError(b, false), "samples.exr: EXR has no channel 'px'");
    }
}

TEST_F(HostileBundle, NonFiniteOrNegativeSampleDataAndBombsAreRefused) {
    const float nan = std::numeric_limits<float>::quiet_NaN(),
                inf = std::numeric_limits<float>::infinity();
    const std::pair<int, float> cases[] = {{2, nan}, {6, inf}, {8, -1.0f}, {8, nan}};
    for (const auto& [channel, value] : cases) {
        const fs::path b = copy("nonfinite");
        editSamples(b, [&](std::vector<float>& p) { p[10 * 3 + channel] = value; });
        EXPECT_CONTAINS(
            loadError(b, false),
            "samples.exr: sample 3 has a non-finite position or area vector, a negative area");
    }
    {
        const fs::path b = copy("png_bomb");
        std::string file;
        editManifest(b,
                     [&](nlohmann::json& m) { file = m["painted_maps"]["permeability"]["path"]; });
        test::writeFile(b / file, pngDeclaring(8192));  // within the side limit, but 1 KB of data
        EXPECT_CONTAINS(loadError(b, false), "more than its");
        test::writeFile(b / file, pngDeclaring(16384));
        EXPECT_CONTAINS(loadError(b, false), "at most 8192 x 8192");
    }
}

TEST_F(HostileBundle, EveryCApiCallRefusesNonFiniteAndNullArguments) {
    plimsoll_bundle* b = plimsoll_bundle_load((*root_ / "good").string().c_str(), 1);
    ASSERT_NE(b, nullptr) << plimsoll_runtime_last_error();
    const double nan = std::nan(""), inf = HUGE_VAL;
    const plimsoll_pose pose = {{0, 0, 0}, {1, 0, 0, 0}};
    const plimsoll_water water = {0.0, nullptr, nullptr, nullptr};
    const plimsoll_fluid fluid = plimsoll_bundle_default_fluid(b);
    plimsoll_forces f{};
    ASSERT_EQ(plimsoll_bundle_evaluate(b, &pose, nullptr, &water, &fluid, 0.0, &f), 1)
        << plimsoll_runtime_last_error();
    auto refused = [&](int result, int failure, const std::string& expected) {
        EXPECT_EQ(result, failure);
        EXPECT_CONTAINS(plimsoll_runtime_last_error(), expected);
    };
    plimsoll_pose bad = pose;
    bad.position[1] = nan;
    refused(plimsoll_bundle_evaluate(b, &bad, nullptr, &water, &fluid, 0.0, &f), 0,
            "pose position has a NaN or Inf");
    bad = pose;
    bad.orientation[0] = 0;
    refused(plimsoll_bundle_evaluate(b, &bad, nullptr, &water, &fluid, 0.0, &f), 0,
            "zero quaternion");
    bad = pose;
    bad.orientation[2] = inf;
    refused(plimsoll_bundle_evaluate(b, &bad, nullptr, &water, &fluid, 0.0, &f), 0,
            "orientation has a NaN or Inf");
    const plimsoll_water nanWater = {nan, nullptr, nullptr, nullptr};
    refused(plimsoll_bundle_evaluate(b, &pose, nullptr, &nanWater, &fluid, 0.0, &f), 0,
            "water level");
    refused(plimsoll_bundle_evaluate(b, &pose, nullptr, &water, &fluid, inf, &f), 0,
            "time is NaN or Inf");
    plimsoll_fluid badFluid = fluid;
    badFluid.density = nan;
    refused(plimsoll_bundle_evaluate(b, &pose, nullptr, &water, &badFluid, 0.0, &f), 0,
            "density must be finite");
    const plimsoll_velocity nanVelocity = {{0, nan, 0}, {0, 0, 0}};
    refused(plimsoll_bundle_evaluate(b, &pose, &nanVelocity, &water, &fluid, 0.0, &f), 0,
            "velocity");
    refused(plimsoll_bundle_evaluate(b, nullptr, nullptr, &water, &fluid, 0.0, &f), 0, "NULL");
    refused(plimsoll_bundle_evaluate(b, &pose, nullptr, &water, &fluid, 0.0, nullptr), 0, "NULL");
    // A height callback that returns NaN: the result is refused, not passed on as success.
    const plimsoll_water nanHeight = {
        0.0, [](void*, double, double, double) { return std::nan(""); }, nullptr, nullptr};
    refused(plimsoll_bundle_evaluate(b, &pose, nullptr, &nanHeight, &fluid, 0.0, &f), 0,
            "the water height or velocity callback returned NaN or Inf");

    ASSERT_GT(plimsoll_graph_node_count(b), 0u);
    refused(plimsoll_graph_set_node_water(b, 0, nan), 0, "water must be in 0..");
    refused(plimsoll_graph_set_node_water(b, 0, -1), 0, "water must be in 0..");
    refused(plimsoll_graph_set_node_water(b, 99999, 0), 0, "no such node");
    refused(plimsoll_graph_set_medium(b, nan, 1e-3, 9.81), 0, "density and viscosity");
    refused(plimsoll_graph_set_medium(b, 1000, inf, 9.81), 0, "density and viscosity");
    bad = pose;
    bad.orientation[0] = nan;
    refused(plimsoll_graph_step(b, &bad, &water, 0.0, 0.01), -1, "orientation");
    refused(plimsoll_graph_step(b, &pose, &water, 0.0, nan), -1, "dt not finite");
    refused(plimsoll_graph_inflow(b, &bad, &water, 0.0, nullptr, nullptr), 0, "orientation");
    const double zero[4] = {0, 0, 0, 0};
    plimsoll_graph_water_mass(b, zero);
    EXPECT_CONTAINS(plimsoll_runtime_last_error(), "zero quaternion");
    EXPECT_EQ(plimsoll_graph_step(b, &pose, &water, 0.0, 0.01) >= 0, true)
        << plimsoll_runtime_last_error();
    plimsoll_bundle_free(b);
    EXPECT_STREQ(plimsoll_bundle_body(nullptr), "");
}

// --- the command line ---------------------------------------------------------------------------

TEST(HostileCli, NonFiniteNumbersAndOverflowingDurationsAreRefused) {
    const std::string mesh = test::assetPath("box.obj").string();
    for (const std::string args : {"simulate --mesh '" + mesh + "' --density nan",
                                   "simulate --mesh '" + mesh + "' --density inf",
                                   "simulate --mesh '" + mesh + "' --water-level nan",
                                   "massprops '" + mesh + "' --density=-nan"}) {
        const test::CommandOutput run = test::runPlimsoll(args);
        EXPECT_EQ(run.exitCode, 2) << args << "\n" << run.err;  // a usage error, not CLI11's 105
        EXPECT_CONTAINS(run.err, "is not a finite number");
    }
    const test::CommandOutput empty = test::runPlimsoll("bake '" + mesh + "' --size 16 --out ''");
    EXPECT_EQ(empty.exitCode, 2) << empty.err;
    EXPECT_CONTAINS(empty.err, "an empty path");
    const test::CommandOutput run =
        test::runPlimsoll("simulate --mesh '" + mesh + "' --size 16 --seconds 1e300");
    EXPECT_EQ(run.exitCode, 1) << run.err;
    EXPECT_CONTAINS(run.err, "more than the limit kMaxSimulationFrames");
}

// simulate kept every frame until the end (a 1e7 s run reached 8 GB in a minute with nothing
// written). The run, stopped after a few seconds under a 512 MB address-space limit, has
// already streamed its rows into the trajectory's temporary; the target itself only appears
// when a run completes. Without radiation: its panel solve at load takes most of those seconds
// in the sanitized build, and what is measured here is the run after it.
TEST(HostileCli, ALongSimulationStreamsItsTrajectoryInBoundedMemory) {
    const fs::path dir = test::freshFolder("hostile", "streamed");
    const std::string mesh = test::assetPath("box.obj").string();
    const test::CommandOutput run = test::runPlimsoll(
        "simulate --mesh '" + mesh + "' --size 16 --no-radiation --seconds 1e6 --out '" +
            (dir / "t.csv").string() + "'",
        "timeout -s KILL 4 " + test::memoryCap(512ull << 20));
    EXPECT_EQ(run.exitCode, 137) << "not stopped by the timeout: " << run.err;
    EXPECT_FALSE(fs::exists(dir / "t.csv"));
    std::size_t rows = 0;
    for (const auto& entry : fs::directory_iterator(dir)) {
        const std::string text = test::readFile(entry.path());
        rows += static_cast<std::size_t>(std::count(text.begin(), text.end(), '\n'));
    }
    EXPECT_GT(rows, 100u) << "the frames were not written as they were computed";
}

// A body no affordable step resolves: one 1e-40 m across (hydrostatic frequency ~1e21 rad/s)
// or one spun to 1e50 or 1e6 rad/s. Its sub-steps were clamped to kMaxSubSteps and the run
// ended in NaN, or (at 1e6 rad/s) its spin silently vanished with exit 0. Refused before the
// run, naming the body and why; a spin a step can follow still runs.
TEST(HostileCli, ABodyNoStepCanResolveIsRefusedBeforeItRuns) {
    const fs::path dir = test::freshFolder("hostile", "unresolvable");
    std::ifstream box(test::assetPath("box.obj"));
    std::ofstream tiny(dir / "tiny.obj");
    for (std::string line; std::getline(box, line);) {
        double x, y, z;
        if (std::sscanf(line.c_str(), "v %lf %lf %lf", &x, &y, &z) == 3) {
            char scaled[128];
            std::snprintf(scaled, sizeof scaled, "v %.17g %.17g %.17g", x * 1e-40, y * 1e-40,
                          z * 1e-40);
            line = scaled;
        }
        tiny << line << "\n";
    }
    tiny.close();
    fs::copy_file(test::assetPath("box.obj"), dir / "box.obj");
    int written = 0;
    auto project = [&](const std::string& mesh, const std::string& spin) {
        const fs::path path = dir / ("spun" + std::to_string(written++) + ".plim.json");
        std::ofstream(path)
            << R"({"schema_version": 1, "name": "spun", "bodies": [{"name": "b", "mesh": ")" << mesh
            << R"(.obj", "texture_size": 16, "material": {"density": 500},)"
            << R"( "angular_velocity": [0, )" << spin << "]}]}";
        return path.string();
    };
    for (const auto& [mesh, spin, why] : {std::tuple{"tiny", "1e50", "spin 1e+50 rad/s"},
                                          std::tuple{"tiny", "0", "hydrostatic frequency"},
                                          std::tuple{"box", "1e50", "spin 1e+50 rad/s"},
                                          std::tuple{"box", "1e6", "spin 1e+06 rad/s"}}) {
        const fs::path out = dir / "trajectory.csv";
        const test::CommandOutput run =
            test::runPlimsoll("simulate '" + project(mesh, std::string("0, ") + spin) +
                              "' --seconds 0.1 --out '" + out.string() + "'");
        EXPECT_EQ(run.exitCode, 1) << mesh << " " << spin << "\n" << run.err;
        EXPECT_CONTAINS(run.err, "body 'b': a stable step needs");
        EXPECT_CONTAINS(run.err, "more than the limit World::kMaxSubSteps = 20000");
        EXPECT_CONTAINS(run.err, why);
        EXPECT_FALSE(fs::exists(out));
    }
    const test::CommandOutput ok =
        test::runPlimsoll("simulate '" + project("box", "0, 300") + "' --seconds 0.1");
    EXPECT_EQ(ok.exitCode, 0) << ok.err;
}

}  // namespace
}  // namespace test_hostile_input
}  // namespace plimsoll
