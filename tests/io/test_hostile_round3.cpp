// Hostile input, third round: journals that name files elsewhere, outputs that are not regular
// files, readers during a bundle's replacement, and painted maps that are not PNG. Each test
// fails on the code before its defence (docs/security.md lists them).
#include "cli_runner.h"
#include "test_support.h"

#include "plimsoll/export/bundle.h"
#include "plimsoll/io/file_util.h"
#include "plimsoll/io/graph_json.h"
#include "plimsoll/io/json_depth.h"
#include "plimsoll/io/mesh_io.h"
#include "plimsoll/io/painted_map_io.h"
#include "plimsoll/project/project.h"
#include "plimsoll/surface/painted_map.h"

#include "io/mesh_header_check.h"
#include "io/test_hooks.h"

#include "plimsoll_runtime.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <atomic>
#include <fstream>
#include <string>
#include <sys/stat.h>
#include <sys/sysmacros.h>
#include <sys/wait.h>
#include <thread>
#include <unistd.h>

namespace plimsoll {
namespace test_hostile_round3 {
namespace {

namespace fs = std::filesystem;

/// The box asset with a painted map beside it, at `density`.
fs::path writeBoxProject(const fs::path& dir, double density) {
    const fs::path path = dir / "box.plim.json";
    std::ofstream(path)
        << R"({"schema_version": 1, "name": "box", "bodies": [{"name": "box", "mesh": ")"
        << test::assetPath("box.obj").string()
        << R"(", "texture_size": 16, "permeability_map": "perm.png",
                           "material": {"density": )"
        << density << "}}]}";
    EXPECT_TRUE(
        savePaintedMap(PaintedMap{16, 16, std::vector<float>(256, 0.5f)}, dir / "perm.png").ok());
    return path;
}

// --- a journal names only files of its own folder ----------------------------------------------

TEST(HostileJournal, AJournalNamingFilesElsewhereIsRefusedAndMovesNothing) {
    const fs::path dir = test::freshFolder("hostile3", "journal");
    const fs::path project = dir / "proj", other = dir / "other";
    fs::create_directories(project);
    fs::create_directories(other);
    const fs::path path = writeBoxProject(project, 500.0);
    test::writeFile(other / "photo.jpg", "a photograph");
    test::writeFile(other / ".photo.jpg.tmp-abcdef", "the attacker's bytes");
    test::writeFile(other / "notes.txt", "notes");
    test::writeFile(other / ".notes.txt.previous.tmp-123456", "backup");
    // Absolute paths into the other folder, then the same reached through "..".
    for (const std::string& base : {other.string() + "/", std::string("../other/")}) {
        SCOPED_TRACE(base);
        test::writeFile(project / ".box.plim.json.journal",
                        R"({"format": "plimsoll-replace-journal", "files": [{"temp": ")" + base +
                            R"(.photo.jpg.tmp-abcdef", "target": ")" + base +
                            R"(photo.jpg", "backup": ")" + base +
                            R"(.notes.txt.previous.tmp-123456"}]})");
        Result<Project> loaded = loadProject(path);
        ASSERT_FALSE(loaded.ok());
        EXPECT_CONTAINS(loaded.error().message, "journal refused");
        EXPECT_CONTAINS(loaded.error().message, ".box.plim.json.journal");
        EXPECT_EQ(test::readFile(other / "photo.jpg"), "a photograph");
        EXPECT_EQ(test::readFile(other / ".photo.jpg.tmp-abcdef"), "the attacker's bytes");
        EXPECT_TRUE(fs::exists(other / ".notes.txt.previous.tmp-123456"));
    }
    // Through a link in the project folder to the other one.
    fs::create_directory_symlink(other, project / "maps");
    test::writeFile(
        project / ".box.plim.json.journal",
        R"({"format": "plimsoll-replace-journal", "files": [{"temp": "maps/.photo.jpg.tmp-abcdef", "target": "maps/photo.jpg", "backup": ""}]})");
    EXPECT_CONTAINS(test::messageOf(loadProject(path)), "not a folder (a link?)");
    EXPECT_EQ(test::readFile(other / "photo.jpg"), "a photograph");
    // A set of files reaching outside the last one's folder is refused before it is written.
    const Status outside = replaceFilesTogether(
        {bytesFileWriter(other / "photo.jpg", "map"), bytesFileWriter(project / "x.json", "{}")});
    EXPECT_CONTAINS(test::messageOf(outside), "outside");
    EXPECT_EQ(test::readFile(other / "photo.jpg"), "a photograph");
    EXPECT_FALSE(fs::exists(project / "x.json"));
}

// --- an output that is not a regular file is never replaced ------------------------------------

TEST(HostileOutput, ALinkADeviceOrAFifoNamedAsOutputIsNotReplaced) {
    const fs::path dir = test::freshFolder("hostile3", "out");
    test::writeFile(dir / "real.csv", "kept");
    fs::create_symlink(dir / "real.csv", dir / "link.csv");
    fs::create_symlink("/proc/self/fd/1", dir / "stdout.csv");
    ASSERT_EQ(::mkfifo((dir / "fifo.csv").c_str(), 0600), 0);
    std::vector<std::string> names{"link.csv", "stdout.csv", "fifo.csv"};
    // A copy of /dev/null, where the test may make device nodes (as root).
    if (::mknod((dir / "null.csv").c_str(), S_IFCHR | 0666, makedev(1, 3)) == 0)
        names.push_back("null.csv");
    for (const std::string& name : names) {
        SCOPED_TRACE(name);
        struct stat before {};
        ASSERT_EQ(::lstat((dir / name).c_str(), &before), 0);
        const Status s =
            writeFileAtomically(dir / name, [](std::ostream& out) { return bool(out << "t,x\n"); });
        EXPECT_CONTAINS(test::messageOf(s), name + ": is a");
        EXPECT_CONTAINS(test::messageOf(s), "not replaced");
        struct stat after {};
        ASSERT_EQ(::lstat((dir / name).c_str(), &after), 0);
        EXPECT_EQ(before.st_ino, after.st_ino) << "the node itself was replaced";
        EXPECT_EQ(before.st_mode, after.st_mode);
    }
    EXPECT_EQ(test::readFile(dir / "real.csv"), "kept");
    // The CLI says so and exits 1.
    const test::CommandOutput run = test::runPlimsoll(
        "simulate '" +
        (fs::path(PLIMSOLL_SOURCE_DIR) / "projects" / "box_half_draft.plim.json").string() +
        "' --seconds 0.05 --out '" + (dir / "link.csv").string() + "'");
    EXPECT_EQ(run.exitCode, 1) << run.err;
    EXPECT_CONTAINS(run.err, "link.csv: is a symbolic link");
    EXPECT_TRUE(fs::is_symlink(dir / "link.csv"));
}

// --- readers during a re-export ------------------------------------------------------------------

/// 100 re-exports of one bundle while a loader thread loads it without pause through the
/// runtime: every load finds a complete bundle (the exchange is one rename).
TEST(HostileExport, ALoaderDuringReExportsAlwaysFindsACompleteBundle) {
    const fs::path dir = test::freshFolder("hostile3", "readers");
    const fs::path projectDir = dir / "project", out = dir / "export";
    fs::create_directories(projectDir);
    Result<Project> project = loadProject(writeBoxProject(projectDir, 500.0));
    ASSERT_TRUE(project.ok()) << project.error().message;
    ASSERT_TRUE(writeBodyBundle(*project, 0, out / "box").ok());
    std::atomic<bool> done{false};
    std::atomic<int> loads{0}, failures{0};
    std::string firstFailure;
    std::thread loader([&] {
        while (!done) {
            plimsoll_bundle* bundle = plimsoll_bundle_load((out / "box").c_str(), 0);
            if (bundle)
                plimsoll_bundle_free(bundle);
            else if (failures++ == 0)
                firstFailure = plimsoll_runtime_last_error();
            ++loads;
        }
    });
    int exports = 0;
    for (; exports < 100; ++exports) {
        Result<BundleReport> r = writeBodyBundle(*project, 0, out / "box");
        if (!r.ok()) {
            ADD_FAILURE() << r.error().message;
            break;
        }
    }
    done = true;
    loader.join();
    EXPECT_EQ(exports, 100);
    EXPECT_GT(loads.load(), 100);
    EXPECT_EQ(failures.load(), 0) << "of " << loads.load() << " loads; first: " << firstFailure;
    EXPECT_TRUE(verifyBundle(out / "box").ok());
}

/// `export --force` killed at every step, with the exchange and with the fallback of two
/// renames: the bundle at the path is always the old one or the new one, complete (the
/// fallback's kill between its renames is repaired by the next export's check).
TEST(HostileExport, AReExportKilledAtAnyStepLeavesACompleteBundle) {
    for (const bool fallback : {false, true}) {
        SCOPED_TRACE(fallback ? "two renames" : "exchange");
        const fs::path dir =
            test::freshFolder("hostile3", fallback ? "kill_fallback" : "kill_exchange");
        const fs::path projectDir = dir / "project", out = dir / "export";
        fs::create_directories(projectDir);
        Result<Project> a = loadProject(writeBoxProject(projectDir, 500.0));
        ASSERT_TRUE(a.ok()) << a.error().message;
        ASSERT_TRUE(writeBodyBundle(*a, 0, out / "box").ok());
        const std::string oldManifest = test::readFile(out / "box" / "manifest.json");
        Result<Project> b = loadProject(writeBoxProject(projectDir, 700.0));
        ASSERT_TRUE(b.ok());
        int outcomes[2] = {0, 0};
        int k = 1;
        for (; k < 60; ++k) {
            const pid_t child = ::fork();
            ASSERT_GE(child, 0);
            if (child == 0) {
                disableRenameExchangeForTesting(fallback);
                int steps = 0;
                setFileStepHookForTesting([&](const char*, const fs::path&) {
                    if (++steps == k) ::_exit(9);
                });
                ::_exit(writeBodyBundle(*b, 0, out / "box").ok() ? 0 : 5);
            }
            int status = 0;
            ::waitpid(child, &status, 0);
            ASSERT_TRUE(WIFEXITED(status));
            const int code = WEXITSTATUS(status);
            ASSERT_TRUE(code == 0 || code == 9) << "child exit " << code;
            SCOPED_TRACE("killed at step " + std::to_string(k));
            ASSERT_TRUE(restoreInterruptedFolderSwap(out / "box").ok());
            Result<BundleManifestInfo> verified = verifyBundle(out / "box");
            ASSERT_TRUE(verified.ok()) << verified.error().message;
            const bool isNew = test::readFile(out / "box" / "manifest.json") != oldManifest;
            ++outcomes[isNew];
            if (code == 0) break;
            if (isNew) {  // put the old bundle back for the next step
                ASSERT_TRUE(writeBodyBundle(*a, 0, out / "box").ok());
            }
        }
        EXPECT_LT(k, 60);
        EXPECT_GE(outcomes[0], 10);  // killed while the staging folder was written
        EXPECT_GE(outcomes[1], 1);
    }
}

// --- painted maps are PNG by content
// --------------------------------------------------------------

TEST(HostileImages, AMapThatIsNotAPngIsRefusedNamingItsRealType) {
    const std::string png = encodePaintedMapPng16(PaintedMap{4, 3, std::vector<float>(12, 0.25f)});
    Result<PaintedMap> good = decodePaintedMap(png, "perm.png");
    ASSERT_TRUE(good.ok()) << good.error().message;
    EXPECT_EQ(good->width, 4);
    EXPECT_NEAR(good->values[5], 0.25f, 1e-4);
    // A Radiance HDR with a corrupt run-length scanline (the one that looped in stb_image),
    // a progressive JPEG header, a GIF, a PSD, a PNM, a Softimage PIC.
    std::string hdr = "#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 8 +X 8\n";
    hdr += std::string("\x02\x02\x00\x08", 4) + std::string(64, '\x80');
    const std::pair<std::string, std::string> others[] = {
        {hdr, "Radiance HDR"},
        {std::string("\xFF\xD8\xFF\xC2\x00\x11", 6) + std::string(40, '\0'), "JPEG"},
        {"GIF89a" + std::string(40, '\0'), "GIF"},
        {"8BPS" + std::string(40, '\0'), "PSD"},
        {"P5\n8 8\n255\n" + std::string(64, '\0'), "PNM"},
        {std::string("\x53\x80\xF6\x34", 4) + std::string(200, '\0'), "PIC"},
    };
    for (const auto& [bytes, type] : others) {
        Result<PaintedMap> map = decodePaintedMap(bytes, "perm.png");
        EXPECT_CONTAINS(test::messageOf(map), "perm.png: is a");
        EXPECT_CONTAINS(test::messageOf(map), type);
    }
    // A PNG broken in its chunks: refused before decoding, with the reason.
    std::string badCrc = png;
    badCrc[png.size() - 20] ^= 0x40;  // inside the IDAT data
    EXPECT_CONTAINS(test::messageOf(decodePaintedMap(badCrc, "perm.png")), "fails its CRC");
    EXPECT_CONTAINS(test::messageOf(decodePaintedMap(png.substr(0, png.size() - 12), "perm.png")),
                    "no IEND");
    std::string huge = png;  // a declared 8000 x 8000 from a few bytes of IDAT
    huge.replace(16, 8, std::string("\x00\x00\x1f\x40\x00\x00\x1f\x40", 8));
    const std::uint32_t crc = [&] {
        std::uint32_t c = 0xFFFFFFFFu;
        for (std::size_t i = 12; i < 29; ++i) {
            c ^= static_cast<unsigned char>(huge[i]);
            for (int b = 0; b < 8; ++b) c = (c & 1) ? 0xEDB88320u ^ (c >> 1) : c >> 1;
        }
        return ~c;
    }();
    for (int i = 0; i < 4; ++i) huge[29 + i] = static_cast<char>(crc >> (24 - 8 * i));
    EXPECT_CONTAINS(test::messageOf(decodePaintedMap(huge, "perm.png")),
                    "cannot hold the declared image");
}

// --- depth before parsing, formats by content ------------------------------------------------

TEST(HostileJson, DeepNestingIsRefusedBeforeAnyParser) {
    const std::string deep = "{\"a\": " + std::string(200000, '[') + std::string(200000, ']') + "}";
    EXPECT_CONTAINS(test::messageOf(checkJsonDepth(deep, "x.json")),
                    "more than the limit kMaxJsonDepth");
    EXPECT_TRUE(checkJsonDepth("{\"s\": \"[[[[[[[[\"}", "x.json", 2).ok());  // brackets in strings
    const fs::path dir = test::freshFolder("hostile3", "deep");
    test::writeFile(dir / "p.plim.json", deep);
    EXPECT_CONTAINS(test::messageOf(loadProject(dir / "p.plim.json")),
                    "p.plim.json: JSON nested more than 128");
    test::writeFile(dir / "g.gltf", R"({"asset": {"version": "2.0"}, "nodes": [{"extras": )" +
                                        std::string(200000, '[') + std::string(200000, ']') +
                                        "}]}");
    EXPECT_CONTAINS(test::messageOf(loadMesh(dir / "g.gltf")), "JSON nested more than 128");
    EXPECT_EQ(boundedExcerpt(std::string(500, 'x') + "\xff", 10), "xxxxxxxxxx...");
    EXPECT_EQ(boundedExcerpt("a\xff"
                             "b"),
              "a?b");
}

// A value quoted in a message is written only as far as the excerpt goes: dump() recursed
// through every level (a stack overflow on deep values) and wrote every byte of large ones,
// and threw on bytes that are not UTF-8.
TEST(HostileJson, MessagesQuoteBoundedExcerptsOfValues) {
    nlohmann::json big = nlohmann::json::array();
    for (int i = 0; i < 100000; ++i) big.push_back(123456);
    EXPECT_EQ(jsonExcerpt(big, 20), "[123456, 123456, 123...");
    nlohmann::json deep = nlohmann::json::array();
    for (int i = 0; i < 100; ++i) deep = nlohmann::json::array({deep});
    EXPECT_EQ(jsonExcerpt(deep, 10), "[[[[[[[[[[...");
    EXPECT_EQ(jsonExcerpt(nlohmann::json{{"k", std::string("a\xff")}}), "{\"k\": \"a?\"}");
    EXPECT_EQ(validUtf8("a\xff"
                        "b\xc3\xa9"),
              "a\xEF\xBF\xBD"
              "b\xc3\xa9");
    // A glTF child that is not a node index, quoted in the message: an excerpt of it.
    const fs::path dir = test::freshFolder("hostile3", "excerpt");
    test::writeFile(dir / "c.gltf", R"({"asset": {"version": "2.0"}, "nodes": [{"children": [)" +
                                        big.dump() + "]}]}");
    const std::string message = test::messageOf(loadMesh(dir / "c.gltf"));
    EXPECT_CONTAINS(message, "c.gltf: glTF node 0 names child [123456, 123456");
    EXPECT_LT(message.size(), 300u);
}

/// A binary FBX (version 7400: 32-bit offsets) of `depth` node records nested in each other.
std::string nestedBinaryFbx(int depth) {
    std::string bytes = std::string("Kaydara FBX Binary  \0\x1a\0", 23);
    const auto u32 = [&](std::uint32_t v) {
        for (int k = 0; k < 4; ++k) bytes += static_cast<char>(v >> (8 * k));
    };
    u32(7400);
    // A record: end offset, no properties, a one-letter name, the nested record and the null
    // record that ends a list (13 zero bytes); the innermost has nothing nested.
    std::vector<std::uint32_t> ends(depth);
    std::uint32_t size = 14;
    for (int k = depth - 1; k >= 0; --k) {
        ends[k] = 27 + 14 * static_cast<std::uint32_t>(k) + size;
        size += 27;
    }
    for (int k = 0; k < depth; ++k) {
        u32(ends[k]);
        u32(0);
        u32(0);
        bytes +=
            "\x01"
            "A";
    }
    for (int k = 1; k < depth; ++k) bytes += std::string(13, '\0');
    return bytes + std::string(13, '\0');  // the top level's null record
}

// Assimp reads FBX scopes recursively: 50000 nested braces overflowed its stack. Both forms are
// refused past kMaxFbxDepth before it sees them; braces in strings and comments are no scopes.
TEST(HostileFbx, ScopesNestedPastTheLimitAreRefusedBeforeAssimp) {
    const fs::path dir = test::freshFolder("hostile3", "fbx");
    std::string ascii = "; FBX 7.4.0 project file\nFBXHeaderExtension:  {\n}\nObjects:  {\n";
    for (int i = 0; i < 50000; ++i) ascii += "A: {";
    ascii += std::string(50001, '}') + "\n";
    test::writeFile(dir / "deep.fbx", ascii);
    test::writeFile(dir / "deep_binary.fbx", nestedBinaryFbx(200000));  // 5.4 MB
    for (const std::string name : {"deep.fbx", "deep_binary.fbx"}) {
        SCOPED_TRACE(name);
        const std::string message = test::messageOf(loadMesh(dir / name));
        EXPECT_CONTAINS(message, name + ": FBX scopes nested more than 128 deep");
        EXPECT_CONTAINS(message, "kMaxFbxDepth");
        const test::CommandOutput run =
            test::runPlimsoll("validate '" + (dir / name).string() + "'");
        EXPECT_EQ(run.exitCode, 1) << run.err;
        EXPECT_CONTAINS(run.err, name + ": FBX scopes nested more than 128 deep");
    }
    EXPECT_TRUE(detail::checkFbx("b.fbx", nestedBinaryFbx(128)).ok());
    EXPECT_FALSE(detail::checkFbx("b.fbx", nestedBinaryFbx(129)).ok());
    const std::string quoted = "; FBX 7.4.0 {{{{ " + std::string(500, '{') + "\nA: {\n P: \"" +
                               std::string(500, '{') + "\"\n}\n";
    EXPECT_TRUE(detail::checkFbx("q.fbx", quoted).ok());
}

/// The offset of the first zlib-encoded array property of a binary FBX: its type ('f', 'd',
/// 'l', 'i' or 'b'), its count, encoding 1, its stored length, then zlib's header byte 0x78.
std::size_t firstZlibArray(const std::string& fbx) {
    auto u32 = [&](std::size_t at) {
        std::uint32_t v = 0;
        for (int k = 3; k >= 0; --k) v = v << 8 | static_cast<unsigned char>(fbx[at + k]);
        return v;
    };
    for (std::size_t i = 27; i + 14 < fbx.size(); ++i) {
        if (std::string_view("fdlib").find(fbx[i]) != std::string_view::npos && u32(i + 5) == 1 &&
            static_cast<unsigned char>(fbx[i + 13]) == 0x78)
            return i;
    }
    return std::string::npos;
}

// Assimp inflates an FBX array into a buffer of the count the file states and, when the zlib
// data does not fit it, throws between zlib's inflateInit and inflateEnd (the FBX fuzzer's
// first finding, a leak of zlib's state per load); it allocates that count before inflating.
// Every array is checked first: a Blender export of a 50 cm cube (scene in centimetres) reads
// as 0.5 m; a byte changed in its zlib data, or a count of 4 billion, is refused by name.
TEST(HostileFbx, ArraysThatDoNotInflateToTheirCountAreRefusedBeforeAssimp) {
    const fs::path dir = test::freshFolder("hostile3", "fbx_arrays");
    const std::string cube =
        test::readFile(fs::path(PLIMSOLL_SOURCE_DIR) / "fuzz/corpus/mesh_fbx/cube_cm.fbx");
    Result<TriangleMesh> read = loadMeshFromMemory(cube, "fbx", "cube_cm.fbx");
    ASSERT_TRUE(read.ok()) << read.error().message;
    const Bounds3 bounds = computeBounds(*read);
    EXPECT_NEAR(bounds.max.x() - bounds.min.x(), 0.5, 1e-6);
    EXPECT_NEAR(bounds.max.y() - bounds.min.y(), 0.5, 1e-6);
    const std::size_t array = firstZlibArray(cube);
    ASSERT_NE(array, std::string::npos);

    std::string corrupt = cube;
    corrupt[array + 13 + 6] = static_cast<char>(corrupt[array + 13 + 6] ^ 0x5a);
    test::writeFile(dir / "corrupt.fbx", corrupt);
    EXPECT_CONTAINS(test::messageOf(loadMesh(dir / "corrupt.fbx")),
                    "corrupt.fbx: the FBX array at byte " + std::to_string(array));
    EXPECT_CONTAINS(test::messageOf(loadMesh(dir / "corrupt.fbx")), "does not inflate");

    std::string huge = cube;
    for (int k = 0; k < 4; ++k) huge[array + 1 + k] = '\xff';
    test::writeFile(dir / "huge.fbx", huge);
    const test::CommandOutput run =
        test::runPlimsoll("validate '" + (dir / "huge.fbx").string() + "'");
    EXPECT_EQ(run.exitCode, 1) << run.err;
    EXPECT_CONTAINS(run.err, "huge.fbx: the FBX arrays hold more than");
    EXPECT_CONTAINS(run.err, "kMaxFbxInflatedBytes");
}

// Assimp adds a record's 64-bit property length to a pointer before comparing it with the
// record's end: a length near 2^64 wrapped past that check into an assertion (abort; the PLY
// fuzzer's finding, a file whose content was binary FBX). Assimp also reads a file as binary
// FBX from its first 18 bytes, "Kaydara FBX Binary", whatever the two that usually follow.
TEST(HostileFbx, APropertyLengthPastItsRecordIsRefusedBeforeAssimp) {
    const fs::path dir = test::freshFolder("hostile3", "fbx_lengths");
    for (const std::string magic : {std::string("Kaydara FBX Binary  \0\x1a\0", 23),
                                    std::string("Kaydara FBX Binary\xff\xff\xff\xff\xff", 23)}) {
        std::string bytes = magic;
        const auto u64 = [&](std::uint64_t v) {
            for (int k = 0; k < 8; ++k) bytes += static_cast<char>(v >> (8 * k));
        };
        for (int k = 0; k < 4; ++k) bytes += '\xff';  // version 2^32-1: 64-bit fields
        u64(27 + 25 + 1 + 64);                        // the record ends after 64 more bytes
        u64(1);                                       // one property
        u64(~std::uint64_t{0});                       // of 2^64 - 1 bytes
        bytes +=
            "\x01"
            "A";
        bytes += std::string(64, '\0');
        test::writeFile(dir / "wrap.ply", bytes);  // the content decides, not the name
        const std::string message = test::messageOf(loadMesh(dir / "wrap.ply"));
        EXPECT_CONTAINS(message,
                        "wrap.ply: the FBX record at byte 27 declares "
                        "18446744073709551615 bytes of properties, past its end");
        // The same record ending one byte past the file, where assimp's copy has a NUL.
        for (int k = 0; k < 8; ++k)
            bytes[27 + k] = static_cast<char>((bytes.size() + 1) >> (8 * k));
        test::writeFile(dir / "past.ply", bytes);
        EXPECT_CONTAINS(test::messageOf(loadMesh(dir / "past.ply")),
                        "past.ply: the FBX record at byte 27 ends at byte " +
                            std::to_string(bytes.size() + 1) + ", outside the file");
    }
}

// Assimp's FBX converter splits a rotation curve into a key per 180 degrees of change: six bytes
// changed in the values of the shared shark's swim cycle asked for more than 2 GB (the FBX
// fuzzer's finding). Plimsoll reads shapes: animations are not converted, and the changed shark
// reads as the shark.
TEST(HostileFbx, AnimationsAreNotConvertedSoTheirKeysCannotAskForGigabytes) {
    const fs::path shark = test::realAssetsDir() / "quaternius" / "Shark.fbx";
    if (!fs::exists(shark)) GTEST_SKIP() << "../shared/real-assets not present";
    const std::string original = test::readFile(shark);
    // The finding's change, at its place in the first KeyValueFloat array of rotations.
    const std::size_t at = 90775;
    const std::string was("\x3f\xe6\x15\x23\x3f\x72\x14", 7),
        now("\x72\x23\x3f\x15\x3f\x14\xe6", 7);
    if (original.size() != 101804 || original.compare(at, was.size(), was) != 0)
        GTEST_SKIP() << "Shark.fbx is not the version the finding was made on";
    std::string changed = original;
    changed.replace(at, now.size(), now);
    Result<TriangleMesh> a = loadMeshFromMemory(original, "fbx", "Shark.fbx");
    Result<TriangleMesh> b = loadMeshFromMemory(changed, "fbx", "changed.fbx");
    ASSERT_TRUE(a.ok()) << a.error().message;
    ASSERT_TRUE(b.ok()) << b.error().message;
    EXPECT_EQ(a->triangles, b->triangles);
    EXPECT_EQ(a->positions, b->positions);
}

/// A 2 m cube in ASCII FBX 7.4, in metres: one mesh of two materials (three faces each), its
/// model and the materials.
std::string asciiFbxCube() {
    return R"(; FBX 7.4.0 project file
FBXHeaderExtension:  {
	FBXHeaderVersion: 1003
	FBXVersion: 7400
}
GlobalSettings:  {
	Version: 1000
	Properties70:  {
		P: "UnitScaleFactor", "double", "Number", "",100
	}
}
Objects:  {
	Geometry: 1000, "Geometry::cube", "Mesh" {
		Vertices: *24 {
			a: -1,-1,-1,1,-1,-1,1,1,-1,-1,1,-1,-1,-1,1,1,-1,1,1,1,1,-1,1,1
		}
		PolygonVertexIndex: *24 {
			a: 0,3,2,-2,4,5,6,-8,0,1,5,-5,2,3,7,-7,1,2,6,-6,3,0,4,-8
		}
		GeometryVersion: 124
		LayerElementMaterial: 0 {
			Version: 101
			Name: ""
			MappingInformationType: "ByPolygon"
			ReferenceInformationType: "IndexToDirect"
			Materials: *6 {
				a: 0,0,0,1,1,1
			}
		}
		Layer: 0 {
			Version: 100
			LayerElement:  {
				Type: "LayerElementMaterial"
				TypedIndex: 0
			}
		}
	}
	Model: 2000, "Model::cube", "Mesh" {
		Version: 232
	}
	Material: 3000, "Material::steel", "" {
		Version: 102
	}
	Material: 3001, "Material::wood", "" {
		Version: 102
	}
}
Connections:  {
	C: "OO",2000,0
	C: "OO",1000,2000
	C: "OO",3000,2000
	C: "OO",3001,2000
})";
}

std::string replaced(std::string text, const std::string& from, const std::string& to) {
    const std::size_t at = text.find(from);
    EXPECT_NE(at, std::string::npos) << from;
    if (at != std::string::npos) text.replace(at, from.size(), to);
    return text;
}

// What assimp's FBX document and converter read without looking: a layer with no index (read
// from an empty list: SIGSEGV), a negative layer-element index (written before its array), a
// per-polygon material list longer than the polygons under a mapping assimp does not resize
// (the converter walks past the faces: SIGSEGV), and a model that is its own ancestor (endless
// recursion: SIGSEGV), and a material property's name longer than assimp's 1024-byte keys
// (an assertion: SIGABRT). Each is refused, naming the element and its byte.
TEST(HostileFbx, WhatAssimpReadsWithoutLookingIsRefusedBeforeIt) {
    Result<TriangleMesh> cube = loadMeshFromMemory(asciiFbxCube(), "fbx", "cube.fbx");
    ASSERT_TRUE(cube.ok()) << cube.error().message;
    EXPECT_EQ(cube->triangleCount(), 12u);
    const std::pair<std::string, std::string> cases[] = {
        {replaced(asciiFbxCube(), "Layer: 0 {", "Layer: 0: {"), "'Layer' at byte"},
        {replaced(asciiFbxCube(), "TypedIndex: 0", "TypedIndex: -1"), "a negative index"},
        {replaced(asciiFbxCube(), "LayerElementMaterial: 0 {", "LayerElementMaterial: -1 {"),
         "a negative index"},
        {replaced(replaced(replaced(asciiFbxCube(), "Materials: *6 {", "Materials: *9 {"),
                           "a: 0,0,0,1,1,1", "a: 0,0,0,1,1,1,1,1,1"),
                  "\"ByPolygon\"", "\"ByPolygonVertex\""),
         "9 materials for 6 polygons"},
        {replaced(asciiFbxCube(), "C: \"OO\",2000,0", "C: \"OO\",2000,0\n\tC: \"OO\",2000,2000"),
         "model 2000 is its own ancestor"},
        {replaced(asciiFbxCube(), "\t\tVersion: 102\n",
                  "\t\tVersion: 102\n\t\tProperties70:  {\n\t\t\tP: \"" + std::string(600, 'k') +
                      "\", \"double\", \"Number\", \"\",1\n\t\t}\n"),
         "a property name of 600 bytes, more than the limit kMaxFbxPropertyName"},
    };
    for (const auto& [text, expected] : cases) {
        const std::string message = test::messageOf(loadMeshFromMemory(text, "fbx", "mutated.fbx"));
        EXPECT_CONTAINS(message, "mutated.fbx: the FBX ");
        EXPECT_CONTAINS(message, expected);
    }
    EXPECT_CONTAINS(test::messageOf(loadMeshFromMemory(replaced(asciiFbxCube(), "a: -1", "a: \"-1"),
                                                       "fbx", "quote.fbx")),
                    "quote.fbx: not a well-formed FBX file: a quote inside a token");
}

// A chain of models as deep as the limit reads; one deeper is refused before assimp's recursive
// conversion of the tree (a few hundred bytes of stack a model) sees it.
TEST(HostileFbx, ModelChainsPastTheLimitAreRefused) {
    const auto chain = [](std::uint64_t depth) {
        std::string models, links;
        for (std::uint64_t k = 1; k <= depth; ++k) {
            const std::string id = std::to_string(5000 + k);
            models += "\tModel: " + id + ", \"Model::m" + id + "\", \"Null\" {\n\t}\n";
            links +=
                "\tC: \"OO\"," + id + "," + (k == 1 ? "2000" : std::to_string(4999 + k)) + "\n";
        }
        std::string text =
            replaced(asciiFbxCube(), "\tMaterial: 3000,", models + "\tMaterial: 3000,");
        return replaced(text, "\tC: \"OO\",2000,0", "\tC: \"OO\",2000,0\n" + links);
    };
    // The cube's model is the chain's first: depth + 1 models in all.
    const Result<TriangleMesh> deepest =
        loadMeshFromMemory(chain(kMaxFbxModelDepth - 1), "fbx", "ok.fbx");
    ASSERT_TRUE(deepest.ok()) << deepest.error().message;
    EXPECT_EQ(deepest->triangleCount(), 12u);
    const std::string message =
        test::messageOf(loadMeshFromMemory(chain(kMaxFbxModelDepth), "fbx", "deep.fbx"));
    EXPECT_CONTAINS(message, "deep.fbx: FBX models nested more than 1024 deep");
    EXPECT_CONTAINS(message, "kMaxFbxModelDepth");
}

// Plimsoll reads shapes: every object but models, materials and polygon meshes is renamed in
// assimp's copy, so that their converters, which trust their files, never run. A layered
// texture fed by a material (assimp takes every source of a layered texture for a texture and
// read through a null pointer: SIGSEGV) reads as the plain cube.
TEST(HostileFbx, ObjectsPlimsollDoesNotReadAreNotGivenToAssimp) {
    std::string layered = replaced(asciiFbxCube(), "\tMaterial: 3001,",
                                   "\tLayeredTexture: 4000, \"LayeredTexture::layers\", \"\" {\n"
                                   "\t\tLayeredTexture: 100\n\t}\n"
                                   "\tTexture: 4001, \"Texture::t\", \"\" {\n"
                                   "\t\tFileName: \"t.png\"\n\t}\n\tMaterial: 3001,");
    layered = replaced(layered, "C: \"OO\",3001,2000",
                       "C: \"OO\",3001,2000\n\tC: \"OP\",4000,3000, \"DiffuseColor\"\n"
                       "\tC: \"OO\",3001,4000\n\tC: \"OO\",4001,4000");
    std::string forAssimp;
    ASSERT_TRUE(detail::checkFbx("layered.fbx", layered, &forAssimp).ok());
    EXPECT_EQ(forAssimp.size(), layered.size());
    EXPECT_CONTAINS(forAssimp, "LayeredTextur_: 4000");
    EXPECT_CONTAINS(forAssimp, "Textur_: 4001");
    EXPECT_CONTAINS(forAssimp, "Material: 3001");
    Result<TriangleMesh> read = loadMeshFromMemory(layered, "fbx", "layered.fbx");
    Result<TriangleMesh> plain = loadMeshFromMemory(asciiFbxCube(), "fbx", "cube.fbx");
    ASSERT_TRUE(read.ok()) << read.error().message;
    EXPECT_EQ(read->positions, plain->positions);
    EXPECT_EQ(read->triangles, plain->triangles);
}

TEST(HostileMeshFormats, OtherFormatsAreRefusedByContentAndOBJIsReadWhateverItsName) {
    const fs::path dir = test::freshFolder("hostile3", "formats");
    const std::pair<std::string, std::string> refused[] = {
        {"m.dae", R"(<?xml version="1.0"?><COLLADA xmlns="x"></COLLADA>)"},
        {"m.x", "xof 0303txt 0032\n"},
        {"m.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n"},
        {"m.obj", "xof 0303txt 0032\n"},  // an X file named .obj: the content decides
        {"m.3mf", std::string("PK\x03\x04", 4) + std::string(40, '\0')},
        {"m.md5mesh", "MD5Version 10\n"},
    };
    for (const auto& [name, bytes] : refused) {
        test::writeFile(dir / name, bytes);
        const std::string message = test::messageOf(loadMesh(dir / name));
        EXPECT_CONTAINS(message, name + ": is a");
        EXPECT_CONTAINS(message, "OBJ, PLY, STL, FBX, glTF and GLB");
    }
    test::writeFile(dir / "m.bin", std::string(64, '\x01'));
    EXPECT_CONTAINS(test::messageOf(loadMesh(dir / "m.bin")), "content of no allowed format");
    // An OBJ under another name is read, through the OBJ checks.
    fs::copy_file(test::assetPath("box.obj"), dir / "box.OBJ.bak");
    Result<TriangleMesh> box = loadMesh(dir / "box.OBJ.bak");
    ASSERT_TRUE(box.ok()) << box.error().message;
    EXPECT_EQ(box->triangleCount(), loadMesh(test::assetPath("box.obj"))->triangleCount());
}

}  // namespace
}  // namespace test_hostile_round3
}  // namespace plimsoll
