// Hostile glTF and GLB files: the numbers assimp's glTF 2 reader trusts (offsets that wrap, sparse
// accessors without data or with indices past their accessor, Draco-compressed attributes, data
// URIs with long headers, nodes with two parents, instancing and zeros that ask for gigabytes).
// Each test builds the file in a folder of its own and checks that the import refuses it with a
// message naming the file and the value's JSON path; valid files, the shared real assets among
// them, still import.
#include "test_support.h"

#include "plimsoll/core/limits.h"
#include "plimsoll/io/mesh_io.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cctype>
#include <chrono>
#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

namespace plimsoll {
namespace test_hostile_gltf {
namespace {

namespace fs = std::filesystem;
using json = nlohmann::json;

std::string floats(const std::vector<float>& values) {
    return std::string(reinterpret_cast<const char*>(values.data()), values.size() * sizeof(float));
}
template <class T>
std::string integers(const std::vector<T>& values) {
    return std::string(reinterpret_cast<const char*>(values.data()), values.size() * sizeof(T));
}

/// One triangle's positions (36 bytes).
std::string triangleBytes() { return floats({0, 0, 0, 1, 0, 0, 0, 1, 0}); }

/// A glTF of one triangle: buffer 0 holds its positions (bufferView 0, accessor 0); `uri` is the
/// buffer's URI (none for a GLB).
json triangle(const std::string& uri = "") {
    json g = json::parse(R"({"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}],
      "nodes": [{"mesh": 0}], "meshes": [{"primitives": [{"attributes": {"POSITION": 0}}]}],
      "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3",
                     "min": [0, 0, 0], "max": [1, 1, 0]}],
      "bufferViews": [{"buffer": 0, "byteLength": 36}],
      "buffers": [{"byteLength": 36}]})");
    if (!uri.empty()) g["buffers"][0]["uri"] = uri;
    return g;
}

/// A GLB of `gltf` and `bin` (the BIN chunk, padded to 4 bytes).
std::string glb(const json& gltf, std::string bin) {
    std::string text = gltf.dump();
    while (text.size() % 4) text += ' ';
    while (bin.size() % 4) bin += '\0';
    std::string s = "glTF";
    auto u32 = [&](std::uint32_t v) { s.append(reinterpret_cast<const char*>(&v), 4); };
    u32(2);
    u32(static_cast<std::uint32_t>(12 + 8 + text.size() + 8 + bin.size()));
    u32(static_cast<std::uint32_t>(text.size()));
    u32(0x4E4F534Au);
    s += text;
    u32(static_cast<std::uint32_t>(bin.size()));
    u32(0x004E4942u);
    return s + bin;
}

/// Writes `gltf` as NAME.gltf (its buffer as NAME.bin beside it, holding `bin`) and NAME.glb,
/// loads both, and returns both messages ("" where one loaded).
struct Messages {
    std::string gltf, glb;
};
Messages loadBoth(const fs::path& dir, const std::string& name, json gltf, const std::string& bin) {
    json external = gltf;
    external["buffers"][0]["uri"] = name + ".bin";
    test::writeFile(dir / (name + ".bin"), bin);
    test::writeFile(dir / (name + ".gltf"), external.dump());
    test::writeFile(dir / (name + ".glb"), glb(gltf, bin));
    return {test::messageOf(loadMesh(dir / (name + ".gltf"))),
            test::messageOf(loadMesh(dir / (name + ".glb")))};
}

/// Both forms refused, naming the file and containing every part of `parts`.
void expectRefused(const fs::path& dir, const std::string& name, const json& gltf,
                   const std::string& bin, const std::vector<std::string>& parts) {
    const Messages m = loadBoth(dir, name, gltf, bin);
    for (const auto& [message, file] :
         {std::pair{m.gltf, name + ".gltf"}, std::pair{m.glb, name + ".glb"}}) {
        SCOPED_TRACE(file);
        EXPECT_CONTAINS(message, (dir / file).string() + ": glTF ");
        for (const std::string& part : parts) EXPECT_CONTAINS(message, part);
    }
}

TEST(HostileGltf, TheTriangleItselfLoadsInEveryForm) {
    const fs::path dir = test::freshFolder("hostile_gltf", "triangle");
    const Messages m = loadBoth(dir, "ok", triangle(), triangleBytes());
    EXPECT_EQ(m.gltf, "");
    EXPECT_EQ(m.glb, "");
    // Embedded as a base64 data URI.
    test::writeFile(dir / "embedded.gltf",
                    triangle("data:application/octet-stream;base64,"
                             "AAAAAAAAAAAAAAAAAACAPwAAAAAAAAAAAAAAAAAAgD8AAAAA")
                        .dump());
    Result<TriangleMesh> embedded = loadMesh(dir / "embedded.gltf");
    ASSERT_TRUE(embedded.ok()) << embedded.error().message;
    EXPECT_EQ(embedded->triangles.size(), 1u);
}

// bufferView.byteOffset + byteLength wrapped assimp's bounds check (2^64 - 16 + 36 = 20) and
// it read 16 bytes before the buffer.
TEST(HostileGltf, OffsetsThatWrapAroundAreRefused) {
    const fs::path dir = test::freshFolder("hostile_gltf", "wrap");
    json view = triangle();
    view["bufferViews"][0]["byteOffset"] = 18446744073709551600ull;  // 2^64 - 16
    expectRefused(dir, "view", view, triangleBytes(),
                  {"bufferViews[0]: byteOffset 18446744073709551600 and byteLength 36 reach past "
                   "the end of buffers[0] (36 bytes)"});
    json accessor = triangle();
    accessor["accessors"][0]["byteOffset"] = 18446744073709551600ull;
    expectRefused(dir, "accessor", accessor, triangleBytes(),
                  {"accessors[0]: 3 elements of 12 bytes", "bufferViews[0] has 0 from there"});
    // An accessor one float longer than its view.
    json longer = triangle();
    longer["accessors"][0]["byteOffset"] = 4;
    expectRefused(dir, "longer", longer, triangleBytes(), {"accessors[0]: 3 elements of 12 bytes"});
    // A view longer than its buffer, and a buffer longer than its data.
    json view2 = triangle();
    view2["bufferViews"][0]["byteLength"] = 40;
    expectRefused(dir, "view_long", view2, triangleBytes(), {"bufferViews[0]: byteOffset 0"});
    json buffer = triangle();
    buffer["buffers"][0]["byteLength"] = 1000;
    const Messages m = loadBoth(dir, "buffer_long", buffer, triangleBytes());
    EXPECT_CONTAINS(m.gltf,
                    "buffers[0].byteLength: 1000 bytes, the file \"buffer_long.bin\" has 36");
    EXPECT_CONTAINS(m.glb, "buffers[0].byteLength: 1000 bytes, the GLB's BIN chunk holds 36");
    test::writeFile(dir / "uri_long.gltf", [&] {
        json g = triangle("data:application/octet-stream;base64,AAAA");
        return g.dump();
    }());
    EXPECT_CONTAINS(test::messageOf(loadMesh(dir / "uri_long.gltf")),
                    "buffers[0].byteLength: 36 bytes, its data URI holds 3");
    // byteStride outside 4..252 or not a multiple of 4.
    for (int stride : {2, 13, 256}) {
        json g = triangle();
        g["bufferViews"][0]["byteStride"] = stride;
        expectRefused(dir, "stride" + std::to_string(stride), g, triangleBytes(),
                      {"bufferViews[0].byteStride: " + std::to_string(stride) +
                       " (glTF: 4 to 252, a multiple of 4)"});
    }
}

// Assimp looks for the BIN chunk after the JSON chunk padded to 4 bytes and allocates its
// stated length before reading it; a chunk walk without the padding found an empty chunk there
// and let a 4 GB BIN chunk through.
TEST(HostileGltf, TheBinChunkIsCheckedWhereAssimpFindsIt) {
    const fs::path dir = test::freshFolder("hostile_gltf", "bin");
    std::string text = triangle().dump();
    while (text.size() % 4 != 1) text += ' ';
    std::string body;
    auto u32 = [&](std::uint32_t v) { body.append(reinterpret_cast<const char*>(&v), 4); };
    u32(static_cast<std::uint32_t>(text.size()));
    u32(0x4E4F534Au);
    body += text + std::string(3, '\0');  // padding to 4 bytes
    u32(0xFFFFFF00u);                     // BIN: 4 GB stated, 4 bytes there
    u32(0x004E4942u);
    body += std::string(4, '\0');
    std::string file = "glTF";
    const std::uint32_t header[2] = {2, static_cast<std::uint32_t>(12 + body.size())};
    file.append(reinterpret_cast<const char*>(header), 8);
    test::writeFile(dir / "bin.glb", file + body);
    const std::string message = test::messageOf(loadMesh(dir / "bin.glb"));
    EXPECT_CONTAINS(message, (dir / "bin.glb").string() + ": GLB BIN chunk at byte " +
                                 std::to_string(20 + text.size() + 3) +
                                 " says 4294967040 bytes, the file has 4 after it");
}

// A Draco-compressed POSITION of 16 components overflowed the 4-element array assimp decodes
// each point into, on the stack: Draco-compressed primitives are refused.
TEST(HostileGltf, DracoCompressedPrimitivesAreRefused) {
    const fs::path dir = test::freshFolder("hostile_gltf", "draco");
    json g = triangle();
    g["extensionsUsed"] = {"KHR_draco_mesh_compression"};
    g["extensionsRequired"] = {"KHR_draco_mesh_compression"};
    g["meshes"][0]["primitives"][0]["extensions"]["KHR_draco_mesh_compression"] = {
        {"bufferView", 0}, {"attributes", {{"POSITION", 0}}}};
    expectRefused(dir, "draco", g, triangleBytes(),
                  {"meshes[0].primitives[0].extensions.KHR_draco_mesh_compression: "
                   "Draco-compressed geometry is not read"});
}

/// The triangle with accessor 1, a sparse VEC3 accessor of `count` elements whose `sparse` is
/// given, and the buffer's bytes after the triangle: indices at 36, values at 36 + 4 * n.
json withSparse(std::uint64_t count, const json& sparse, bool view = true) {
    json g = triangle();
    json accessor = {
        {"componentType", 5126}, {"count", count}, {"type", "VEC3"}, {"sparse", sparse}};
    if (view) accessor["bufferView"] = 0;
    g["accessors"].push_back(accessor);
    // Used as a morph target, so that assimp reads it.
    g["meshes"][0]["primitives"][0]["targets"] = json::array({{{"POSITION", 1}}});
    return g;
}

TEST(HostileGltf, SparseAccessorsAreCheckedBeforeAssimpPatchesThem) {
    const fs::path dir = test::freshFolder("hostile_gltf", "sparse");
    // One index (uint32) and one value after the triangle: views 1 (indices) and 2 (values).
    const std::string bin = triangleBytes() + integers<std::uint32_t>({2}) + floats({0, 0, 1});
    auto views = [](json g) {
        g["bufferViews"].push_back({{"buffer", 0}, {"byteOffset", 36}, {"byteLength", 4}});
        g["bufferViews"].push_back({{"buffer", 0}, {"byteOffset", 40}, {"byteLength", 12}});
        g["buffers"][0]["byteLength"] = 52;
        return g;
    };
    const json good = {{"count", 1},
                       {"componentType", 5125},
                       {"indices", {{"bufferView", 1}, {"componentType", 5125}}},
                       {"values", {{"bufferView", 2}}}};
    const Messages ok = loadBoth(dir, "ok", views(withSparse(3, good)), bin);
    EXPECT_EQ(ok.gltf, "");
    EXPECT_EQ(ok.glb, "");

    // Without indices.bufferView assimp dereferenced null.
    json noView = good;
    noView["indices"].erase("bufferView");
    expectRefused(dir, "no_view", views(withSparse(3, noView)), bin,
                  {"accessors[1].sparse.indices.bufferView: missing"});
    json noValues = good;
    noValues.erase("values");
    expectRefused(dir, "no_values", views(withSparse(3, noValues)), bin,
                  {"accessors[1].sparse.values: missing"});
    // An unchecked byte offset: a wild read.
    json wild = good;
    wild["indices"]["byteOffset"] = 18446744073709551600ull;
    expectRefused(dir, "wild", views(withSparse(3, wild)), bin,
                  {"accessors[1].sparse.indices: 1 elements of 4 bytes"});
    json wildValues = good;
    wildValues["values"]["byteOffset"] = 1ull << 40;
    expectRefused(dir, "wild_values", views(withSparse(3, wildValues)), bin,
                  {"accessors[1].sparse.values: 1 elements of 12 bytes"});
    // An index past the accessor: assimp wrote the value outside its array.
    const std::string far = triangleBytes() + integers<std::uint32_t>({100000}) + floats({0, 0, 1});
    expectRefused(dir, "far", views(withSparse(3, good)), far,
                  {"accessors[1].sparse.indices: index 0 is 100000", "past the accessor's 3"});
    // More sparse elements than the accessor has, and an index type that is not one.
    json many = good;
    many["count"] = 4;
    expectRefused(dir, "many", views(withSparse(3, many)), bin,
                  {"accessors[1].sparse.count: 4 (1 to the accessor's count, 3)"});
    // On a strided view: assimp copies the elements packed and reads the copy strided.
    json strided = views(withSparse(3, good));
    strided["bufferViews"][0]["byteStride"] = 16;
    strided["bufferViews"][0]["byteLength"] = 36;
    strided["accessors"][0]["count"] = 2;
    strided["accessors"][1]["count"] = 2;
    expectRefused(dir, "strided", strided, bin,
                  {"accessors[1]: a sparse accessor on bufferViews[0], whose byteStride 16"});
    json floatIndices = good;
    floatIndices["indices"]["componentType"] = 5126;
    expectRefused(dir, "float_indices", views(withSparse(3, floatIndices)), bin,
                  {"accessors[1].sparse.indices.componentType: 5126 is not an index type"});
    // Assimp reads the indices with the sparse object's componentType (unsigned short when it
    // has none): a wider one than the indices' own reads past their view.
    json wider = good;
    wider["indices"]["componentType"] = 5121;
    json oneByte = views(withSparse(3, wider));
    oneByte["bufferViews"][1]["byteLength"] = 1;
    expectRefused(dir, "wider", oneByte, bin,
                  {"accessors[1].sparse.indices: 1 elements of 4 bytes"});
}

// A sparse accessor without a bufferView is zeros that assimp allocates whole: 1.2 GB from a
// 1.7 KB file.
TEST(HostileGltf, ZerosAskingForGigabytesAreRefusedBeforeAllocating) {
    const fs::path dir = test::freshFolder("hostile_gltf", "zeros");
    const std::string bin = triangleBytes() + integers<std::uint32_t>({2}) + floats({0, 0, 1});
    auto build = [](std::uint64_t count) {
        json g = withSparse(count,
                            {{"count", 1},
                             {"indices", {{"bufferView", 1}, {"componentType", 5125}}},
                             {"values", {{"bufferView", 2}}}},
                            false);
        g["bufferViews"].push_back({{"buffer", 0}, {"byteOffset", 36}, {"byteLength", 4}});
        g["bufferViews"].push_back({{"buffer", 0}, {"byteOffset", 40}, {"byteLength", 12}});
        g["buffers"][0]["byteLength"] = 52;
        g["accessors"][1]["sparse"]["componentType"] = 5125;
        return g;
    };
    const auto start = std::chrono::steady_clock::now();
    expectRefused(dir, "huge", build(100'000'000), bin,
                  {"accessors[1].count: elements: 100000000, more than the limit kMaxVertices"});
    expectRefused(dir, "large", build(30'000'000), bin,
                  {"accessors[1]: accessors without a bufferView (zeros) need bytes: 360000000",
                   "kMaxGltfZeroFilledBytes"});
    EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(), 5.0);
}

// Assimp copies a mesh once per node that shows it (the file's vertices times its instances),
// and imports a node once per path to it: a node with two parents at each of 64 levels is 2^64
// imports, a hang.
TEST(HostileGltf, InstancesAndSharedNodesAreCountedBeforeAssimpCopiesThem) {
    const fs::path dir = test::freshFolder("hostile_gltf", "instances");
    json shared = triangle();
    json nodes = json::array();
    for (int level = 0; level < 64; ++level)
        nodes.push_back({{"children", {level + 1, level + 1}}});
    nodes.push_back({{"mesh", 0}});
    shared["nodes"] = nodes;
    const auto start = std::chrono::steady_clock::now();
    expectRefused(dir, "shared", shared, triangleBytes(),
                  {"nodes[1]: the child of 2 nodes (a glTF node has at most one parent)"});
    EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(), 5.0);
    json twice = triangle();
    twice["scenes"][0]["nodes"] = {0, 0};
    expectRefused(dir, "twice", twice, triangleBytes(),
                  {"scenes[0].nodes[1]: node 0 is listed twice"});
    // A mesh of 20M vertices (zeros, 240 MB) shown by four nodes: 80M vertices.
    json many = triangle();
    many["accessors"][0].erase("bufferView");
    many["accessors"][0]["count"] = 20'000'000;
    many["scenes"][0]["nodes"] = {0, 1, 2, 3};
    many["nodes"] = json::array({{{"mesh", 0}}, {{"mesh", 0}}, {{"mesh", 0}}, {{"mesh", 0}}});
    expectRefused(
        dir, "many", many, triangleBytes(),
        {"meshes: vertices over every instance and morph target: 80000000", "kMaxVertices"});
}

// A triangle fan or strip of 2 indices made assimp write a face into an array of none.
TEST(HostileGltf, PrimitivesWithTooFewElementsForTheirModeAreRefused) {
    const fs::path dir = test::freshFolder("hostile_gltf", "modes");
    const std::string bin = triangleBytes() + integers<std::uint16_t>({0, 1});
    for (int mode : {1, 2, 3, 4, 5, 6}) {
        json g = triangle();
        g["bufferViews"].push_back({{"buffer", 0}, {"byteOffset", 36}, {"byteLength", 4}});
        g["buffers"][0]["byteLength"] = 40;
        g["accessors"].push_back({{"bufferView", 1},
                                  {"componentType", 5123},
                                  {"count", mode <= 3 ? 1 : 2},
                                  {"type", "SCALAR"}});
        g["meshes"][0]["primitives"][0]["indices"] = 1;
        g["meshes"][0]["primitives"][0]["mode"] = mode;
        expectRefused(dir, "mode" + std::to_string(mode), g, bin,
                      {"meshes[0].primitives[0]: ", "vertices for mode " + std::to_string(mode)});
    }
    // Assimp resizes a list to the number after a target's attribute name and writes there.
    for (const char* name : {"POSITION_-1", "NORMAL_2000000000"}) {
        json target = triangle();
        target["meshes"][0]["primitives"][0]["targets"] = json::array({{{name, 0}}});
        expectRefused(dir, "target", target, triangleBytes(),
                      {std::string("meshes[0].primitives[0].targets[0].") + name +
                       ": a morph target attribute named after"});
    }
    // No POSITION: assimp counts no vertices, and a fan of no vertices has 2^32 - 2 faces (the
    // glTF fuzzer's first finding).
    json unnamed = triangle();
    unnamed["meshes"][0]["primitives"][0]["attributes"] = {{"NORMAL", 0}};
    unnamed["meshes"][0]["primitives"][0]["mode"] = 6;
    expectRefused(dir, "unnamed", unnamed, triangleBytes(),
                  {"meshes[0].primitives[0].attributes.POSITION: missing"});
    json bad = triangle();
    bad["meshes"][0]["primitives"][0]["mode"] = 7;
    expectRefused(dir, "mode7", bad, triangleBytes(),
                  {"meshes[0].primitives[0].mode: 7 is not a glTF mode"});
    json missing = triangle();
    missing["meshes"][0]["primitives"][0]["attributes"]["NORMAL"] = 5;
    expectRefused(dir, "missing", missing, triangleBytes(),
                  {"meshes[0].primitives[0].attributes.NORMAL: 5 names no element of accessors"});
}

// Assimp logs an index past a primitive's vertices and leaves that face unwritten; its line
// loops and strips then read the face before the first through a null pointer (the GLB
// fuzzer's finding: a crate whose indices were mutated, drawn as a line loop). Every index is
// checked against the vertices, in every mode; the indices in range still load.
TEST(HostileGltf, IndicesPastTheVerticesAreRefused) {
    const fs::path dir = test::freshFolder("hostile_gltf", "indices");
    for (const std::uint16_t past : {std::uint16_t{3}, std::uint16_t{65535}}) {
        for (int mode : {2, 3, 4}) {
            json g = triangle();
            g["bufferViews"].push_back({{"buffer", 0}, {"byteOffset", 36}, {"byteLength", 6}});
            g["buffers"][0]["byteLength"] = 42;
            g["accessors"].push_back(
                {{"bufferView", 1}, {"componentType", 5123}, {"count", 3}, {"type", "SCALAR"}});
            g["meshes"][0]["primitives"][0]["indices"] = 1;
            g["meshes"][0]["primitives"][0]["mode"] = mode;
            expectRefused(dir, "past" + std::to_string(mode), g,
                          triangleBytes() + integers<std::uint16_t>({past, 1, 2}),
                          {"meshes[0].primitives[0].indices: index 0 is " + std::to_string(past) +
                           ", past the primitive's 3 vertices"});
            const Messages fine = loadBoth(dir, "fine" + std::to_string(mode), g,
                                           triangleBytes() + integers<std::uint16_t>({2, 1, 0}));
            if (mode == 4) EXPECT_EQ(fine.gltf + fine.glb, "");
        }
    }
}

// Assimp keeps the offsets of a data URI's header in a signed char: past 127 bytes they are
// negative and it read before the string.
TEST(HostileGltf, DataUrisWithLongHeadersOrBadBase64AreRefused) {
    const fs::path dir = test::freshFolder("hostile_gltf", "data_uri");
    const std::string data = ";base64,AAAAAAAAAAAAAAAAAACAPwAAAAAAAAAAAAAAAAAAgD8AAAAA";
    test::writeFile(dir / "long.gltf", triangle("data:" + std::string(200, 'a') + data).dump());
    const std::string message = test::messageOf(loadMesh(dir / "long.gltf"));
    EXPECT_CONTAINS(message, (dir / "long.gltf").string() +
                                 ": glTF buffers[0].uri: a data URI "
                                 "whose header (before its comma) is 212 "
                                 "bytes, more than 120");
    EXPECT_LT(message.size(), 400u);  // the URI quoted as an excerpt
    json image = triangle("data:" + data);
    image["images"] = json::array({{{"uri", "data:" + std::string(200, 'a') + data}}});
    test::writeFile(dir / "image.gltf", image.dump());
    EXPECT_CONTAINS(test::messageOf(loadMesh(dir / "image.gltf")),
                    "images[0].uri: a data URI whose");
    // A URI starting with byte 0x10 is one assimp believes it has parsed already.
    test::writeFile(dir / "parsed.gltf",
                    triangle(std::string("\x10\x01\x01\x01") + "\xC2\x80" + data).dump());
    EXPECT_CONTAINS(test::messageOf(loadMesh(dir / "parsed.gltf")),
                    "buffers[0].uri: a URI with a control character");
    test::writeFile(dir / "base64.gltf", triangle("data:;base64,AA=A").dump());
    EXPECT_CONTAINS(test::messageOf(loadMesh(dir / "base64.gltf")),
                    "buffers[0].uri: a data URI whose base64 data is not well formed");
}

// Assimp reads two elements of a texture transform's offset and scale whatever their size.
TEST(HostileGltf, TextureTransformsHoldTwoNumbers) {
    const fs::path dir = test::freshFolder("hostile_gltf", "transform");
    json g = triangle();
    g["extensionsUsed"] = {"KHR_texture_transform"};
    g["materials"] = json::parse(R"([{"pbrMetallicRoughness": {"baseColorTexture": {"index": 0,
        "extensions": {"KHR_texture_transform": {"offset": [], "scale": [1, 1]}}}}}])");
    g["meshes"][0]["primitives"][0]["material"] = 0;
    expectRefused(dir, "transform", g, triangleBytes(),
                  {"materials[0].pbrMetallicRoughness.baseColorTexture.extensions."
                   "KHR_texture_transform.offset: not two numbers: []"});
}

// Assimp reads an output element for each key of an animation's input (three for a cubic
// spline) without comparing the counts: a read past the output's copy.
TEST(HostileGltf, AnimationOutputsHoldAnElementForEveryKey) {
    const fs::path dir = test::freshFolder("hostile_gltf", "animation");
    json g = triangle();
    // Accessor 1: 3 key times (the triangle's x coordinates as floats); accessor 2: 1 VEC3.
    g["accessors"].push_back(
        {{"bufferView", 0}, {"componentType", 5126}, {"count", 3}, {"type", "SCALAR"}});
    g["accessors"].push_back(
        {{"bufferView", 0}, {"componentType", 5126}, {"count", 1}, {"type", "VEC3"}});
    g["animations"] = json::parse(R"([{"samplers": [{"input": 1, "output": 2}],
        "channels": [{"sampler": 0, "target": {"node": 0, "path": "translation"}}]}])");
    expectRefused(dir, "short", g, triangleBytes(),
                  {"animations[0].samplers[0].output: accessors[2] has 1 elements, fewer than 1 "
                   "for each of the input's 3 keys"});
    g["accessors"][2]["count"] = 3;
    g["animations"][0]["samplers"][0]["interpolation"] = "CUBICSPLINE";
    expectRefused(dir, "cubic", g, triangleBytes(),
                  {"fewer than 3 for each of the input's 3 keys"});
    g["animations"][0]["channels"][0]["sampler"] = 1;
    g["animations"][0]["samplers"][0].erase("interpolation");
    expectRefused(dir, "sampler", g, triangleBytes(),
                  {"animations[0].channels[0].sampler: 1 names no element of samplers"});
}

// nlohmann keeps the last of two members of one name, assimp's reader the first: the checked
// value and the one read could differ. Bytes that are not UTF-8 (a name in Latin-1) are read.
TEST(HostileGltf, RepeatedNamesAreRefusedAndNamesNotInUtf8AreRead) {
    const fs::path dir = test::freshFolder("hostile_gltf", "names");
    test::writeFile(dir / "ok.bin", triangleBytes());
    std::string text = triangle("ok.bin").dump();
    const std::string view = "\"byteLength\":36";
    text.replace(text.find(view), view.size(),
                 "\"byteOffset\":18446744073709551600,\"byteLength\":36,\"byteOffset\":0");
    test::writeFile(dir / "twice.gltf", text);
    EXPECT_CONTAINS(test::messageOf(loadMesh(dir / "twice.gltf")),
                    "twice.gltf: glTF JSON names \"byteOffset\" twice in one object");
    json latin = triangle("ok.bin");
    latin["nodes"][0]["name"] = "x";
    std::string latinText = latin.dump();
    latinText.replace(latinText.find("\"x\""), 3, "\"Ni\xF1o\"");
    test::writeFile(dir / "latin.gltf", latinText);
    Result<TriangleMesh> mesh = loadMesh(dir / "latin.gltf");
    EXPECT_TRUE(mesh.ok()) << mesh.error().message;
}

// Every glTF and GLB of the shared meshes and real assets is valid, and still imports.
TEST(HostileGltf, EverySharedGltfAndGlbStillImports) {
    int found = 0;
    for (const fs::path& root : {fs::path(PLIMSOLL_SHARED_DIR) / "meshes", test::realAssetsDir()}) {
        if (!fs::is_directory(root)) continue;
        for (const auto& entry : fs::recursive_directory_iterator(root)) {
            std::string extension = entry.path().extension().string();
            for (char& c : extension)
                c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
            if (extension != ".gltf" && extension != ".glb") continue;
            ++found;
            Result<TriangleMesh> mesh = loadMesh(entry.path());
            EXPECT_TRUE(mesh.ok()) << entry.path() << ": " << mesh.error().message;
            if (mesh) EXPECT_GT(mesh->triangles.size(), 0u) << entry.path();
        }
    }
    if (found == 0) GTEST_SKIP() << "no glTF or GLB under " << PLIMSOLL_SHARED_DIR;
    // The corpus's valid samples too.
    for (const char* sample :
         {"fuzz/corpus/mesh_glb/tetra.glb", "fuzz/corpus/mesh_gltf/tetra_embedded.gltf"}) {
        Result<TriangleMesh> mesh = loadMesh(fs::path(PLIMSOLL_SOURCE_DIR) / sample);
        EXPECT_TRUE(mesh.ok()) << sample << ": " << mesh.error().message;
    }
}

}  // namespace
}  // namespace test_hostile_gltf
}  // namespace plimsoll
