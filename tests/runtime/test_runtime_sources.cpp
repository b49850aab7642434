// What a game engine needs of the runtime beyond a folder (docs/c-abi.md, docs/bundle.md
// "Runtime library"): a bundle loaded from memory or through file callbacks (a pak file) gives
// byte-identical results to the folder, and a damaged bundle fails with the same message on
// each path; versions; the size a body costs; many bodies evaluated and stepped in one call,
// on the library's pool or the caller's task system, equal to one call per body bit for bit.
#include "test_support.h"

#include "plimsoll/export/bundle.h"
#include "plimsoll/project/project.h"

#include "plimsoll_runtime.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <Eigen/Geometry>

#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfInputFile.h>
#include <ImfOutputFile.h>

#include <cmath>
#include <cstring>
#include <fstream>
#include <map>
#include <set>
#include <thread>
#include <atomic>
#include <csignal>
#include <cstdio>
#include <functional>
#include <mutex>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

namespace plimsoll {
namespace test_runtime_sources {
namespace {

namespace fs = std::filesystem;

/// Every file under `folder`, by its path inside it.
std::map<std::string, std::string> readTree(const fs::path& folder) {
    std::map<std::string, std::string> files;
    for (const auto& entry : fs::recursive_directory_iterator(folder)) {
        if (entry.is_regular_file())
            files[fs::relative(entry.path(), folder).generic_string()] =
                test::readFile(entry.path());
    }
    return files;
}

/// A pak file's view of a bundle: the files in memory behind the C callbacks, with every
/// path asked for and every handle still open recorded.
struct Pak {
    std::map<std::string, std::string> files;
    std::vector<std::string> asked;
    std::set<void*> open;
    long long reportedSize = -1;  ///< when >= 0, what size() claims for every file

    struct Handle {
        const std::string* bytes;
    };
    plimsoll_file_callbacks callbacks() {
        plimsoll_file_callbacks c{};
        c.struct_size = sizeof(c);
        c.user = this;
        c.open = [](void* user, const char* path) -> void* {
            Pak& pak = *static_cast<Pak*>(user);
            pak.asked.push_back(path);
            const auto found = pak.files.find(path);
            if (found == pak.files.end()) return nullptr;
            void* h = new Handle{&found->second};
            pak.open.insert(h);
            return h;
        };
        c.size = [](void* user, void* file) -> int64_t {
            const Pak& pak = *static_cast<Pak*>(user);
            return pak.reportedSize >= 0
                       ? pak.reportedSize
                       : static_cast<int64_t>(static_cast<Handle*>(file)->bytes->size());
        };
        // Small reads (at most 4096 bytes), as a streaming archive gives them.
        c.read = [](void*, void* file, uint64_t offset, void* buffer, size_t bytes) -> int64_t {
            const std::string& data = *static_cast<Handle*>(file)->bytes;
            if (offset >= data.size()) return 0;
            const size_t n = std::min<size_t>({bytes, data.size() - offset, 4096});
            std::memcpy(buffer, data.data() + offset, n);
            return static_cast<int64_t>(n);
        };
        c.close = [](void* user, void* file) {
            static_cast<Pak*>(user)->open.erase(file);
            delete static_cast<Handle*>(file);
        };
        return c;
    }
};

std::vector<plimsoll_memory_file> memoryList(const std::map<std::string, std::string>& files) {
    std::vector<plimsoll_memory_file> list;
    for (const auto& [path, bytes] : files)
        list.push_back({path.c_str(), bytes.data(), bytes.size()});
    return list;
}

/// The three ways in: folder, memory and callbacks. `name` = the folder, so messages match.
struct Loaded {
    plimsoll_bundle* folder = nullptr;
    plimsoll_bundle* memory = nullptr;
    plimsoll_bundle* callbacks = nullptr;
    std::string folderError, memoryError, callbacksError;
    Pak pak;
    ~Loaded() {
        plimsoll_bundle_free(folder);
        plimsoll_bundle_free(memory);
        plimsoll_bundle_free(callbacks);
    }
};

void loadThreeWays(const fs::path& dir, int verify, Loaded& out) {
    const std::string name = dir.string();
    out.folder = plimsoll_bundle_load(name.c_str(), verify);
    out.folderError = plimsoll_runtime_last_error();
    const std::map<std::string, std::string> files = readTree(dir);
    const std::vector<plimsoll_memory_file> list = memoryList(files);
    out.memory = plimsoll_bundle_load_memory(list.data(), list.size(), name.c_str(), verify);
    out.memoryError = plimsoll_runtime_last_error();
    out.pak.files = files;
    const plimsoll_file_callbacks c = out.pak.callbacks();
    out.callbacks = plimsoll_bundle_load_callbacks(&c, name.c_str(), verify);
    out.callbacksError = plimsoll_runtime_last_error();
    EXPECT_TRUE(out.pak.open.empty()) << "the loader left " << out.pak.open.size() << " files open";
}

class RuntimeSources : public testing::Test {
protected:
    static void SetUpTestSuite() {
        root_ = new fs::path(test::scratchFolder("runtime_sources"));
        const fs::path source = fs::path(PLIMSOLL_SOURCE_DIR);
        fs::remove_all(*root_ / "assets");
        fs::remove_all(*root_ / "projects");
        fs::copy(source / "assets", *root_ / "assets", fs::copy_options::recursive);
        fs::copy(source / "projects", *root_ / "projects", fs::copy_options::recursive);
        // The damaged boat has every kind of file: water graph, permeability map, texel nodes.
        for (const char* name : {"damaged_boat", "buoy"}) {
            Result<Project> project =
                loadProject(*root_ / "projects" / (std::string(name) + ".plim.json"));
            ASSERT_TRUE(project.ok()) << project.error().message;
            Result<BundleReport> report = writeBodyBundle(*project, 0, *root_ / name);
            ASSERT_TRUE(report.ok()) << report.error().message;
            Result<BundleReport> compact = writeBodyBundle(
                *project, 0, *root_ / (std::string(name) + "_compact"), {}, BundleOptions{true});
            ASSERT_TRUE(compact.ok()) << compact.error().message;
        }
    }
    static void TearDownTestSuite() {
        fs::remove_all(*root_);
        delete root_;
    }
    static fs::path boat() { return *root_ / "damaged_boat"; }
    static fs::path buoy() { return *root_ / "buoy"; }
    static fs::path damaged(const std::string& name) {
        const fs::path to = *root_ / "bad" / name;
        fs::remove_all(to);
        fs::create_directories(to.parent_path());
        fs::copy(boat(), to, fs::copy_options::recursive);
        return to;
    }
    static fs::path* root_;
};
fs::path* RuntimeSources::root_ = nullptr;

// Measured bounds of the compact bundle's error and saving (see the test below).
// Measured (damaged boat, buoy): volume 4.5e-4 / 1.8e-4 V, force 4.5e-4 / 1.8e-4 rho g V,
// torque 1.6e-4 / 7.6e-5 rho g V L; 53% / 55% fewer bytes shipped.
constexpr double kCompactVolumeError = 1e-3;
constexpr double kCompactForceError = 1e-3;
constexpr double kCompactTorqueError = 4e-4;
constexpr double kCompactSaving = 0.45;

void expectSameForces(const plimsoll_forces& a, const plimsoll_forces& b,
                      const std::string& where) {
    // Bit for bit: the same bytes decoded the same way.
    EXPECT_EQ(std::memcmp(&a, &b, sizeof(a)), 0)
        << where << ": V " << a.submerged_volume << " vs " << b.submerged_volume;
}

TEST_F(RuntimeSources, MemoryAndCallbacksGiveTheFolderResultsBitForBit) {
    Loaded l;
    loadThreeWays(boat(), 1, l);
    ASSERT_NE(l.folder, nullptr) << l.folderError;
    ASSERT_NE(l.memory, nullptr) << l.memoryError;
    ASSERT_NE(l.callbacks, nullptr) << l.callbacksError;
    for (const std::string& path : l.pak.asked) {
        EXPECT_EQ(path.find(".."), std::string::npos) << path;
        EXPECT_NE(path.front(), '/') << path;
    }
    // The manifest, the graph, the sample list, the map, texel nodes: every decoded file asked.
    EXPECT_GE(l.pak.asked.size(), 5u);

    const plimsoll_mass m = plimsoll_bundle_mass(l.folder);
    plimsoll_bundle* three[] = {l.folder, l.memory, l.callbacks};
    for (plimsoll_bundle* b : three) {
        EXPECT_EQ(plimsoll_bundle_sample_count(b), plimsoll_bundle_sample_count(l.folder));
        const plimsoll_mass mb = plimsoll_bundle_mass(b);
        EXPECT_EQ(std::memcmp(&m, &mb, sizeof(m)), 0);
        EXPECT_EQ(plimsoll_graph_node_count(b), plimsoll_graph_node_count(l.folder));
    }
    ASSERT_GT(plimsoll_graph_node_count(l.folder), 0u);
    const plimsoll_fluid fluid = plimsoll_bundle_default_fluid(l.folder);
    const plimsoll_water water = {0.05, nullptr, nullptr, nullptr};
    for (int i = 0; i < 40; ++i) {
        const double a = 0.07 * i, s = std::sin(0.5 * a), c = std::cos(0.5 * a);
        const plimsoll_pose pose = {{0.01 * i, -0.3 + 0.015 * i, -0.02 * i},
                                    {c, s * 0.6, s * 0.0, s * 0.8}};
        const plimsoll_velocity v = {{0.2, -0.1 * i, 0.05}, {0.1, 0.02 * i, -0.3}};
        plimsoll_forces f[3];
        for (int k = 0; k < 3; ++k)
            ASSERT_EQ(
                plimsoll_bundle_evaluate(three[k], &pose, &v, &water, &fluid, 0.01 * i, &f[k]), 1)
                << plimsoll_runtime_last_error();
        expectSameForces(f[0], f[1], "memory, pose " + std::to_string(i));
        expectSameForces(f[0], f[2], "callbacks, pose " + std::to_string(i));
        for (plimsoll_bundle* b : three)
            ASSERT_GE(plimsoll_graph_step(b, &pose, &water, 0.01 * i, 0.01), 0)
                << plimsoll_runtime_last_error();
    }
    double flooded = 0;
    for (std::size_t n = 0; n < plimsoll_graph_node_count(l.folder); ++n) {
        flooded += plimsoll_graph_node_water(l.folder, n);
        EXPECT_EQ(plimsoll_graph_node_water(l.memory, n), plimsoll_graph_node_water(l.folder, n))
            << n;
        EXPECT_EQ(plimsoll_graph_node_water(l.callbacks, n), plimsoll_graph_node_water(l.folder, n))
            << n;
    }
    EXPECT_GT(flooded, 0.0) << "the boat took no water: the graph comparison proved nothing";
}

TEST_F(RuntimeSources, ADamagedBundleFailsTheSameWayOnEachPath) {
    struct Damage {
        std::string name, expected;
        std::function<void(const fs::path&)> apply;
        int verify = 1;
    };
    auto truncate = [](const fs::path& file) {
        const std::string bytes = test::readFile(file);
        std::ofstream(file, std::ios::binary | std::ios::trunc)
            << bytes.substr(0, bytes.size() / 2);
    };
    auto editManifest = [](const fs::path& dir, const std::function<void(nlohmann::json&)>& edit) {
        nlohmann::json m = nlohmann::json::parse(test::readFile(dir / "manifest.json"));
        edit(m);
        std::ofstream(dir / "manifest.json", std::ios::binary | std::ios::trunc) << m.dump(2);
    };
    // One sample's position NaN: every channel of samples.exr read and written back as it was.
    auto nanSample = [](const fs::path& dir) {
        const std::string file = (dir / "samples.exr").string();
        std::vector<std::string> names;
        std::vector<std::vector<float>> channels;
        int width = 0, height = 0;
        {
            Imf::InputFile in(file.c_str());
            const Imath::Box2i w = in.header().dataWindow();
            width = w.max.x + 1;
            height = w.max.y + 1;
            Imf::FrameBuffer frame;
            for (auto c = in.header().channels().begin(); c != in.header().channels().end(); ++c) {
                names.push_back(c.name());
                channels.emplace_back(std::size_t(width) * height);
            }
            for (std::size_t c = 0; c < names.size(); ++c)
                frame.insert(names[c],
                             Imf::Slice(Imf::FLOAT, reinterpret_cast<char*>(channels[c].data()),
                                        sizeof(float), sizeof(float) * width));
            in.setFrameBuffer(frame);
            in.readPixels(0, height - 1);
        }
        const std::size_t py = std::find(names.begin(), names.end(), "py") - names.begin();
        ASSERT_LT(py, names.size());
        channels[py][2] = std::nanf("");
        Imf::Header header(width, height);
        header.compression() = Imf::ZIP_COMPRESSION;
        Imf::FrameBuffer frame;
        for (std::size_t c = 0; c < names.size(); ++c) {
            header.channels().insert(names[c], Imf::Channel(Imf::FLOAT));
            frame.insert(names[c],
                         Imf::Slice(Imf::FLOAT, reinterpret_cast<char*>(channels[c].data()),
                                    sizeof(float), sizeof(float) * width));
        }
        Imf::OutputFile out(file.c_str(), header);
        out.setFrameBuffer(frame);
        out.writePixels(height);
    };
    const std::vector<Damage> damages = {
        {"truncated", "samples.exr: ", [&](const fs::path& d) { truncate(d / "samples.exr"); }},
        {"truncated_unverified", "samples.exr: cannot read EXR",
         [&](const fs::path& d) { truncate(d / "samples.exr"); }, 0},
        {"missing", "graph.json: missing", [](const fs::path& d) { fs::remove(d / "graph.json"); }},
        {"checksum", "does not match the manifest's",
         [](const fs::path& d) {
             std::string bytes = test::readFile(d / "graph.json");
             bytes[bytes.size() / 2] ^= 0x20;
             std::ofstream(d / "graph.json", std::ios::binary | std::ios::trunc) << bytes;
         }},
        {"escaping_graph", "leaves the bundle",
         [&](const fs::path& d) {
             editManifest(d, [](nlohmann::json& m) {
                 m["water_graph"]["path"] = "../damaged_boat/graph.json";
             });
         },
         0},
        {"absolute_map", "leaves the bundle",
         [&](const fs::path& d) {
             editManifest(d, [](nlohmann::json& m) {
                 m["painted_maps"]["permeability"]["path"] = "/etc/passwd";
             });
         },
         0},
        {"newer_major", "is newer than this reader's 1.x",
         [&](const fs::path& d) {
             editManifest(d, [](nlohmann::json& m) { m["schema_version"] = 2; });
         }},
        {"nan_sample", "samples.exr: sample 2 has a non-finite position", nanSample, 0},
        {"deep_manifest", "nested more than 128 deep, more than the limit kMaxJsonDepth",
         [&](const fs::path& d) {
             editManifest(d, [](nlohmann::json& m) {
                 nlohmann::json deep = nlohmann::json::array();
                 for (int i = 0; i < 200; ++i) deep = nlohmann::json::array({deep});
                 m["extra"] = deep;
             });
         }},
        // One file listed 2000 times was read and hashed 2000 times; spelled "./graph.json" it
        // is the same file.
        {"repeated_file", "\"graph.json\" is listed twice (also $.files[",
         [&](const fs::path& d) {
             editManifest(d, [](nlohmann::json& m) {
                 nlohmann::json entry;
                 for (const nlohmann::json& f : m["files"])
                     if (f["path"] == "graph.json") entry = f;
                 for (int i = 0; i < 2000; ++i) m["files"].push_back(entry);
             });
         }},
        {"respelled_file", "\"./graph.json\" is listed twice (also $.files[",
         [&](const fs::path& d) {
             editManifest(d, [](nlohmann::json& m) {
                 for (const nlohmann::json& f : m["files"])
                     if (f["path"] == "graph.json") {
                         nlohmann::json again = f;
                         again["path"] = "./graph.json";
                         m["files"].push_back(again);
                         break;
                     }
             });
         },
         0},
    };
    for (const Damage& damage : damages) {
        const fs::path dir = damaged(damage.name);
        damage.apply(dir);
        Loaded l;
        loadThreeWays(dir, damage.verify, l);
        EXPECT_EQ(l.folder, nullptr) << damage.name;
        EXPECT_EQ(l.memory, nullptr) << damage.name;
        EXPECT_EQ(l.callbacks, nullptr) << damage.name;
        EXPECT_CONTAINS(l.folderError, damage.expected);
        EXPECT_EQ(l.memoryError, l.folderError) << damage.name;
        EXPECT_EQ(l.callbacksError, l.folderError) << damage.name;
        for (const std::string& path : l.pak.asked)
            EXPECT_EQ(path.find(".."), std::string::npos) << path;
        EXPECT_EQ(std::count(l.pak.asked.begin(), l.pak.asked.end(), "/etc/passwd"), 0);
    }
}

TEST_F(RuntimeSources, MemoryAndCallbackArgumentsAreChecked) {
    const std::map<std::string, std::string> files = readTree(boat());
    std::vector<plimsoll_memory_file> list = memoryList(files);
    const auto refused = [](plimsoll_bundle* b, const std::string& expected) {
        EXPECT_EQ(b, nullptr);
        plimsoll_bundle_free(b);
        EXPECT_CONTAINS(plimsoll_runtime_last_error(), expected);
    };
    // A truncated memory buffer: the manifest's size and checksum catch it; unchecked, the
    // EXR reader does.
    auto samples = std::find_if(list.begin(), list.end(), [](const plimsoll_memory_file& f) {
        return std::string(f.path) == "samples.exr";
    });
    ASSERT_NE(samples, list.end());
    const size_t full = samples->size;
    samples->size = full / 3;
    refused(plimsoll_bundle_load_memory(list.data(), list.size(), "pak", 1),
            "pak/samples.exr: " + std::to_string(full / 3) + " bytes, the manifest says " +
                std::to_string(full));
    refused(plimsoll_bundle_load_memory(list.data(), list.size(), "pak", 0),
            "pak/samples.exr: cannot read EXR");
    samples->size = full;
    samples->data = nullptr;
    refused(plimsoll_bundle_load_memory(list.data(), list.size(), "pak", 0),
            "no bytes (data is null)");
    samples->data = files.at("samples.exr").data();

    for (const char* bad : {"../samples.exr", "/samples.exr", "maps\\x.png", ""}) {
        std::vector<plimsoll_memory_file> withBad = list;
        withBad.push_back({bad, "x", 1});
        refused(plimsoll_bundle_load_memory(withBad.data(), withBad.size(), "pak", 1),
                "the path leaves the bundle");
    }
    std::vector<plimsoll_memory_file> twice = list;
    twice.push_back(list.front());
    refused(plimsoll_bundle_load_memory(twice.data(), twice.size(), "pak", 1),
            "the path comes twice");
    std::vector<plimsoll_memory_file> nullPath = list;
    nullPath[0].path = nullptr;
    refused(plimsoll_bundle_load_memory(nullPath.data(), nullPath.size(), "pak", 1),
            "file 0: path is NULL");
    refused(plimsoll_bundle_load_memory(nullptr, 3, "pak", 1), "files is NULL");
    refused(plimsoll_bundle_load_memory(list.data(), 0, nullptr, 1),
            "memory/manifest.json: missing");

    // Callbacks: a size the limits refuse is refused before anything is allocated.
    Pak pak;
    pak.files = files;
    pak.reportedSize = 1ll << 40;
    plimsoll_file_callbacks c = pak.callbacks();
    refused(plimsoll_bundle_load_callbacks(&c, "pak", 1),
            "pak/manifest.json: 1099511627776 bytes, more than the");
    EXPECT_TRUE(pak.open.empty());
    pak.reportedSize = -1;
    c.struct_size = sizeof(c) - 8;
    refused(plimsoll_bundle_load_callbacks(&c, "pak", 1), "struct_size");
    c = pak.callbacks();
    c.read = nullptr;
    refused(plimsoll_bundle_load_callbacks(&c, "pak", 1), "open, size, read or close is NULL");
    refused(plimsoll_bundle_load_callbacks(nullptr, "pak", 1), "callbacks is NULL");
    // A read error and a file that ends before its size are reported, and the file is closed.
    c = pak.callbacks();
    c.read = [](void*, void*, uint64_t, void*, size_t) -> int64_t { return -1; };
    refused(plimsoll_bundle_load_callbacks(&c, "pak", 1),
            "pak/manifest.json: the file callbacks report a read error");
    c.read = [](void*, void*, uint64_t, void*, size_t) -> int64_t { return 0; };
    refused(plimsoll_bundle_load_callbacks(&c, "pak", 1),
            "pak/manifest.json: read error (the file shrank");
    EXPECT_TRUE(pak.open.empty());
}

TEST_F(RuntimeSources, VersionsAndTheSizeOfABody) {
    int major = -1, minor = -1, patch = -1;
    plimsoll_runtime_version(&major, &minor, &patch);
    // The header's version macros are the library's version (one source, CMake reads them).
    EXPECT_EQ(major, PLIMSOLL_RUNTIME_VERSION_MAJOR);
    EXPECT_EQ(minor, PLIMSOLL_RUNTIME_VERSION_MINOR);
    EXPECT_EQ(patch, PLIMSOLL_RUNTIME_VERSION_PATCH);
    EXPECT_GE(major, 2);
    plimsoll_runtime_version(nullptr, nullptr, nullptr);
    // The schema this reader reads is the one the exporter writes.
    const nlohmann::json manifest = nlohmann::json::parse(test::readFile(boat() / "manifest.json"));
    int schemaMajor = -1, schemaMinor = -1;
    plimsoll_runtime_bundle_schema(&schemaMajor, &schemaMinor);
    EXPECT_EQ(schemaMajor, manifest["schema_version"].get<int>());
    EXPECT_EQ(schemaMinor, manifest["schema_minor"].get<int>());
    EXPECT_EQ(std::string(plimsoll_runtime_schema_version()),
              std::to_string(schemaMajor) + "." + std::to_string(schemaMinor));

    for (const fs::path& dir : {boat(), buoy()}) {
        plimsoll_bundle* b = plimsoll_bundle_load(dir.string().c_str(), 1);
        ASSERT_NE(b, nullptr) << plimsoll_runtime_last_error();
        // What ships: the manifest and the files it lists, as the file system counts them.
        const nlohmann::json m = nlohmann::json::parse(test::readFile(dir / "manifest.json"));
        std::uint64_t shipped = fs::file_size(dir / "manifest.json");
        for (const auto& f : m["files"])
            shipped += fs::file_size(dir / f["path"].get<std::string>());
        plimsoll_bundle_size size{};
        size.struct_size = sizeof(size);
        ASSERT_EQ(plimsoll_bundle_size_query(b, &size), 1) << plimsoll_runtime_last_error();
        EXPECT_EQ(size.file_bytes, shipped) << dir;
        EXPECT_EQ(size.samples, m["texel_samples"].get<size_t>());
        EXPECT_EQ(size.graph_nodes, plimsoll_graph_node_count(b));
        // At least the sample list itself (texel, position, area vector, area, coverage).
        EXPECT_GE(size.memory_bytes, size.samples * (4 + 8 * 8));
        EXPECT_LE(size.memory_bytes, size.samples * 200 + (1u << 20));
        std::printf("[ size     ] %s: %zu samples, %llu bytes shipped, %llu bytes in memory\n",
                    dir.filename().c_str(), size.samples,
                    static_cast<unsigned long long>(size.file_bytes),
                    static_cast<unsigned long long>(size.memory_bytes));
        size.struct_size = 4;
        EXPECT_EQ(plimsoll_bundle_size_query(b, &size), 0);
        EXPECT_CONTAINS(plimsoll_runtime_last_error(), "struct_size");
        plimsoll_bundle_free(b);
    }
}

// A compact bundle (half floats over a per-body origin and scales, docs/bundle.md "Compact
// bundles") against the float32 bundle of the same body over 100 poses from out of the water
// to fully under, tilted every way: the submerged volume against the body's volume V, the
// Archimedes force against rho g V and its torque against rho g V L (L = the cube root of V).
// The bounds are what was measured (docs/bundle.md) with a margin of about 2.
TEST_F(RuntimeSources, CompactBundleIsSmallerAndKeepsForcesWithinItsStatedError) {
    for (const fs::path& full : {boat(), buoy()}) {
        const fs::path compact = full.string() + "_compact";
        plimsoll_bundle* f = plimsoll_bundle_load(full.string().c_str(), 1);
        ASSERT_NE(f, nullptr) << plimsoll_runtime_last_error();
        plimsoll_bundle* c = plimsoll_bundle_load(compact.string().c_str(), 1);
        ASSERT_NE(c, nullptr) << plimsoll_runtime_last_error();
        plimsoll_bundle_size fullSize{}, compactSize{};
        fullSize.struct_size = compactSize.struct_size = sizeof(plimsoll_bundle_size);
        ASSERT_EQ(plimsoll_bundle_size_query(f, &fullSize), 1);
        ASSERT_EQ(plimsoll_bundle_size_query(c, &compactSize), 1);
        EXPECT_EQ(compactSize.samples, fullSize.samples);

        const plimsoll_mass mass = plimsoll_bundle_mass(f);
        const plimsoll_fluid fluid = plimsoll_bundle_default_fluid(f);
        const double V = mass.volume, L = std::cbrt(V), weight = fluid.density * fluid.gravity * V;
        const plimsoll_water water = {0.0, nullptr, nullptr, nullptr};
        const plimsoll_velocity still = {{0, 0, 0}, {0, 0, 0}};
        double volumeError = 0, forceError = 0, torqueError = 0;
        int partly = 0;
        for (int i = 0; i < 100; ++i) {
            // The centre of mass from 1.2 L above the water to 1.2 L below, axes all round.
            const double depth = L * (1.2 - 2.4 * i / 99.0), angle = 0.37 * i;
            const double s = std::sin(0.5 * angle), k = std::cos(0.5 * angle);
            const Eigen::Vector3d axis =
                Eigen::Vector3d(std::sin(1.3 * i), 1.0, std::cos(0.7 * i)).normalized();
            const Eigen::Quaterniond q(k, s * axis.x(), s * axis.y(), s * axis.z());
            const Eigen::Vector3d com(mass.center_of_mass[0], mass.center_of_mass[1],
                                      mass.center_of_mass[2]);
            const Eigen::Vector3d origin = Eigen::Vector3d(0.05 * L * i / 99.0, depth, 0) - q * com;
            const plimsoll_pose pose = {{origin.x(), origin.y(), origin.z()},
                                        {q.w(), q.x(), q.y(), q.z()}};
            plimsoll_forces a{}, b{};
            ASSERT_EQ(plimsoll_bundle_evaluate(f, &pose, &still, &water, &fluid, 0.0, &a), 1);
            ASSERT_EQ(plimsoll_bundle_evaluate(c, &pose, &still, &water, &fluid, 0.0, &b), 1);
            if (a.submerged_volume > 0.01 * V && a.submerged_volume < 0.99 * V) ++partly;
            volumeError =
                std::max(volumeError, std::abs(a.submerged_volume - b.submerged_volume) / V);
            double dF = 0, dT = 0;
            for (int j = 0; j < 3; ++j) {
                dF += (a.force[j] - b.force[j]) * (a.force[j] - b.force[j]);
                dT += (a.torque[j] - b.torque[j]) * (a.torque[j] - b.torque[j]);
            }
            forceError = std::max(forceError, std::sqrt(dF) / weight);
            torqueError = std::max(torqueError, std::sqrt(dT) / (weight * L));
        }
        // The poses cross the waterline: most of them cut the body, none is trivially equal.
        EXPECT_GE(partly, 40) << full;
        const double saving = 1.0 - double(compactSize.file_bytes) / double(fullSize.file_bytes);
        std::printf(
            "[ compact  ] %s: %llu -> %llu bytes shipped (%.1f%% smaller); largest error over "
            "100 poses: volume %.2e V, force %.2e rho g V, torque %.2e rho g V L\n",
            full.filename().c_str(), static_cast<unsigned long long>(fullSize.file_bytes),
            static_cast<unsigned long long>(compactSize.file_bytes), 100 * saving, volumeError,
            forceError, torqueError);
        EXPECT_LE(volumeError, kCompactVolumeError) << full;
        EXPECT_LE(forceError, kCompactForceError) << full;
        EXPECT_LE(torqueError, kCompactTorqueError) << full;
        EXPECT_GE(saving, kCompactSaving) << full;
        plimsoll_bundle_free(f);
        plimsoll_bundle_free(c);
    }
}

// The water as many heights per call and with known bounds: the same forces bit for bit as one
// height per call; a body wholly above the bounds asks nothing; NaN and bad bounds refused.
TEST_F(RuntimeSources, WaterHeightsInOneCallAndBoundsGiveTheSameForces) {
    plimsoll_bundle* b = plimsoll_bundle_load(boat().string().c_str(), 1);
    ASSERT_NE(b, nullptr) << plimsoll_runtime_last_error();
    struct Calls {
        int single = 0, batched = 0;
        std::size_t points = 0;
    } calls;
    plimsoll_water one{};
    one.user = &calls;
    one.height = [](void* user, double x, double z, double t) {
        ++static_cast<Calls*>(user)->single;
        return 0.15 * std::sin(0.9 * x - 0.4 * z + t);
    };
    plimsoll_water many{};
    many.user = &calls;
    many.heights = [](void* user, size_t n, const double* x, const double* z, double t,
                      double* out) {
        auto& c = *static_cast<Calls*>(user);
        ++c.batched;
        c.points += n;
        for (size_t i = 0; i < n; ++i) out[i] = 0.15 * std::sin(0.9 * x[i] - 0.4 * z[i] + t);
    };
    const plimsoll_fluid fluid = plimsoll_bundle_default_fluid(b);
    const plimsoll_pose pose = {{0.3, -0.1, 0.2}, {0.98, 0.1, 0.1, std::sqrt(1 - 0.9604 - 0.02)}};
    plimsoll_forces a{}, c{};
    ASSERT_EQ(plimsoll_bundle_evaluate(b, &pose, nullptr, &one, &fluid, 0.7, &a), 1)
        << plimsoll_runtime_last_error();
    const int singleCalls = calls.single;
    ASSERT_EQ(plimsoll_bundle_evaluate(b, &pose, nullptr, &many, &fluid, 0.7, &c), 1)
        << plimsoll_runtime_last_error();
    EXPECT_GT(a.submerged_volume, 0.0);
    expectSameForces(a, c, "heights in one call");
    EXPECT_EQ(calls.single, singleCalls)
        << "the per-point callback was used although heights was given";
    EXPECT_GT(calls.batched, 0);
    EXPECT_GE(calls.points, std::size_t(calls.batched));

    // Far above bounded water: nothing asked, nothing submerged.
    many.has_bounds = 1;
    many.min_height = -0.15;
    many.max_height = 0.15;
    const int batchedBefore = calls.batched;
    const plimsoll_pose high = {{0.0, 50.0, 0.0}, {1.0, 0.0, 0.0, 0.0}};
    ASSERT_EQ(plimsoll_bundle_evaluate(b, &high, nullptr, &many, &fluid, 0.7, &c), 1);
    EXPECT_EQ(c.submerged_volume, 0.0);
    EXPECT_EQ(calls.batched, batchedBefore);
    // Bounds that hold the surface do not change a result.
    ASSERT_EQ(plimsoll_bundle_evaluate(b, &pose, nullptr, &many, &fluid, 0.7, &c), 1);
    expectSameForces(a, c, "bounded heights");

    many.min_height = 1.0;
    EXPECT_EQ(plimsoll_bundle_evaluate(b, &pose, nullptr, &many, &fluid, 0.7, &c), 0);
    EXPECT_CONTAINS(plimsoll_runtime_last_error(), "min_height <= max_height");
    many.has_bounds = 0;
    many.heights = [](void*, size_t n, const double*, const double*, double, double* out) {
        for (size_t i = 0; i < n; ++i) out[i] = i == n / 2 ? std::nan("") : 0.0;
    };
    EXPECT_EQ(plimsoll_bundle_evaluate(b, &pose, nullptr, &many, &fluid, 0.7, &c), 0);
    EXPECT_CONTAINS(plimsoll_runtime_last_error(), "callback returned NaN or Inf");
    plimsoll_bundle_free(b);
}

// --- motion -------------------------------------------------------------------------------

Eigen::Quaterniond quat(const double q[4]) { return Eigen::Quaterniond(q[0], q[1], q[2], q[3]); }

/// World angular momentum R I R^T w of the body.
Eigen::Vector3d angularMomentum(const plimsoll_mass& m, const plimsoll_body_state& s) {
    Eigen::Matrix3d I;
    for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c) I(r, c) = m.inertia[r][c];
    const Eigen::Matrix3d R = quat(s.pose.orientation).toRotationMatrix();
    return R * I * R.transpose() *
           Eigen::Vector3d(s.velocity.angular[0], s.velocity.angular[1], s.velocity.angular[2]);
}

// plimsoll_body_step far above the water: no load, so the centre of mass falls exactly as
// semi-implicit Euler under gravity does (v_n = -g n dt, y_n = y_0 - g dt^2 n (n + 1) / 2), and
// a body tumbling about no principal axis keeps its angular momentum (the integrator carries
// L, not w) while w itself moves.
TEST_F(RuntimeSources, BodyStepFallsAndKeepsAngularMomentumInTheAir) {
    plimsoll_bundle* b = plimsoll_bundle_load(boat().string().c_str(), 1);
    ASSERT_NE(b, nullptr) << plimsoll_runtime_last_error();
    const plimsoll_mass m = plimsoll_bundle_mass(b);
    const plimsoll_fluid fluid = plimsoll_bundle_default_fluid(b);
    const plimsoll_water water = {0.0, nullptr, nullptr, nullptr};
    plimsoll_body_state s = {{{0.0, 500.0, 0.0}, {1.0, 0.0, 0.0, 0.0}},
                             {{0.0, 0.0, 0.0}, {0.9, 0.4, -1.3}}};
    const double dt = 1.0 / 240.0, g = fluid.gravity;
    const Eigen::Vector3d L0 = angularMomentum(m, s);
    auto comHeight = [&] {
        return (quat(s.pose.orientation) *
                Eigen::Vector3d(m.center_of_mass[0], m.center_of_mass[1], m.center_of_mass[2]))
                   .y() +
               s.pose.position[1];
    };
    const double y0 = comHeight();
    double worstL = 0, turned = 0;
    const int n = 480;
    for (int i = 0; i < n; ++i) {
        ASSERT_EQ(plimsoll_body_step(b, &s, &water, &fluid, i * dt, dt), 1)
            << plimsoll_runtime_last_error();
        worstL = std::max(worstL, (angularMomentum(m, s) - L0).norm() / L0.norm());
        turned = std::max(turned,
                          quat(s.pose.orientation).angularDistance(Eigen::Quaterniond::Identity()));
    }
    EXPECT_NEAR(s.velocity.linear[1], -g * n * dt, 1e-9);
    EXPECT_NEAR(comHeight(), y0 - g * dt * dt * n * (n + 1) / 2.0, 1e-7);
    std::printf("[ motion   ] in the air: angular momentum drift %.1e relative, turned %.2f rad\n",
                worstL, turned);
    EXPECT_LT(worstL, 1e-12) << "angular momentum drifted";
    EXPECT_GT(turned, 1.0) << "the body hardly turned: the check proved nothing";
    EXPECT_EQ(plimsoll_graph_node_water(b, 0), 0.0);  // in the air it takes no water

    // Bad arguments are refused and leave the state as it was.
    const plimsoll_body_state kept = s;
    plimsoll_body_state bad = s;
    bad.velocity.linear[0] = std::nan("");
    EXPECT_EQ(plimsoll_body_step(b, &bad, &water, &fluid, 0.0, dt), 0);
    EXPECT_CONTAINS(plimsoll_runtime_last_error(), "plimsoll_body_step: velocity has a NaN");
    EXPECT_EQ(plimsoll_body_step(b, &s, &water, &fluid, 0.0, 0.0), 0);
    EXPECT_CONTAINS(plimsoll_runtime_last_error(), "dt must be finite and > 0");
    EXPECT_EQ(plimsoll_body_step(b, nullptr, &water, &fluid, 0.0, dt), 0);
    EXPECT_EQ(std::memcmp(&kept, &s, sizeof(s)), 0);
    plimsoll_load load{};
    EXPECT_EQ(plimsoll_bundle_water_load(b, &s.pose, &s.velocity, &water, nullptr, 0.0, dt, &load),
              0);
    EXPECT_CONTAINS(plimsoll_runtime_last_error(), "NULL");
    double lo[3], hi[3];
    ASSERT_EQ(plimsoll_bundle_bounds(b, lo, hi), 1);
    EXPECT_EQ(plimsoll_bundle_bounds(b, nullptr, hi), 0);
    for (int k = 0; k < 3; ++k) EXPECT_LT(lo[k], hi[k]);
    plimsoll_bundle_free(b);
}

// The buoy let go 0.2 m above its equilibrium settles where the water it displaces weighs what
// it weighs: the submerged volume of the load equals m / rho (within 0.5%, the heave left after
// 20 s) once the motion has died down.
TEST_F(RuntimeSources, BodyStepSettlesAtArchimedesEquilibrium) {
    plimsoll_bundle* b = plimsoll_bundle_load(buoy().string().c_str(), 1);
    ASSERT_NE(b, nullptr) << plimsoll_runtime_last_error();
    const plimsoll_mass m = plimsoll_bundle_mass(b);
    const plimsoll_fluid fluid = plimsoll_bundle_default_fluid(b);
    const plimsoll_water water = {0.0, nullptr, nullptr, nullptr};
    plimsoll_body_state s = {{{0.0, 0.2, 0.0}, {1.0, 0.0, 0.0, 0.0}},
                             {{0.0, 0.0, 0.0}, {0.0, 0.0, 0.0}}};
    const double dt = 1.0 / 240.0;
    double volume = 0;
    const int n = 20 * 240, last = 2 * 240;
    for (int i = 0; i < n; ++i) {
        ASSERT_EQ(plimsoll_body_step(b, &s, &water, &fluid, i * dt, dt), 1)
            << plimsoll_runtime_last_error();
        if (i >= n - last) {
            plimsoll_forces f{};
            ASSERT_EQ(plimsoll_bundle_evaluate(b, &s.pose, &s.velocity, &water, &fluid, i * dt, &f),
                      1);
            volume += f.submerged_volume / last;
        }
    }
    std::printf("[ motion   ] buoy at rest: submerged %.6f m^3, m / rho %.6f m^3\n", volume,
                m.mass / fluid.density);
    EXPECT_NEAR(volume, m.mass / fluid.density, 5e-3 * m.mass / fluid.density);
    plimsoll_bundle_free(b);
}

// --- many bodies in one call ---------------------------------------------------------------

/// A caller task system as a game engine has one: each enqueue runs the ranges on threads of
/// its own and finish joins them.
struct CallerTasks {
    int enqueued = 0;
    struct Job {
        std::vector<std::thread> threads;
    };
    static void* enqueue(plimsoll_task_fn* task, int count, int minRange, void* taskContext,
                         void* user) {
        auto* self = static_cast<CallerTasks*>(user);
        ++self->enqueued;
        auto* job = new Job;
        const int range = std::max(minRange, (count + 2) / 3);
        uint32_t worker = 0;
        for (int begin = 0; begin < count; begin += range)
            job->threads.emplace_back(task, begin, std::min(count, begin + range), worker++,
                                      taskContext);
        return job;
    }
    static void finish(void* userTask, void*) {
        auto* job = static_cast<Job*>(userTask);
        for (std::thread& t : job->threads) t.join();
        delete job;
    }
};

TEST_F(RuntimeSources, BatchEvaluationEqualsOneCallPerBody) {
    plimsoll_bundle* boatB = plimsoll_bundle_load(boat().string().c_str(), 1);
    plimsoll_bundle* buoyB = plimsoll_bundle_load(buoy().string().c_str(), 1);
    ASSERT_TRUE(boatB && buoyB) << plimsoll_runtime_last_error();
    constexpr std::size_t kBodies = 50;
    std::vector<const plimsoll_bundle*> bodies(kBodies);
    std::vector<plimsoll_pose> poses(kBodies);
    std::vector<plimsoll_velocity> velocities(kBodies);
    for (std::size_t i = 0; i < kBodies; ++i) {
        bodies[i] = i % 3 == 0 ? boatB : buoyB;  // the same bundle many times
        const double a = 0.13 * i, s = std::sin(0.5 * a), c = std::cos(0.5 * a);
        poses[i] = {{10.0 * i, -0.4 + 0.02 * i, 1.0}, {c, 0.0, s * 0.6, s * 0.8}};
        velocities[i] = {{0.1 * i, -0.2, 0.0}, {0.0, 0.3, -0.01 * i}};
    }
    // A wave, called from several threads at once: it must be (and is) thread-safe.
    const plimsoll_water water = {
        0.0,
        [](void*, double x, double z, double t) { return 0.1 * std::sin(0.7 * x + 0.3 * z - t); },
        nullptr, nullptr};
    std::vector<plimsoll_forces> single(kBodies);
    for (std::size_t i = 0; i < kBodies; ++i) {
        const plimsoll_fluid fluid = plimsoll_bundle_default_fluid(bodies[i]);
        ASSERT_EQ(plimsoll_bundle_evaluate(bodies[i], &poses[i], &velocities[i], &water, &fluid,
                                           0.5, &single[i]),
                  1);
    }
    EXPECT_GT(single[0].submerged_volume, 0.0);

    CallerTasks caller;
    plimsoll_batch_desc own{};
    own.struct_size = sizeof(own);
    own.thread_count = 3;
    plimsoll_batch_desc tasks = own;
    tasks.enqueue = CallerTasks::enqueue;
    tasks.finish = CallerTasks::finish;
    tasks.user_context = &caller;
    tasks.worker_count = 3;
    plimsoll_batch_desc* descs[] = {nullptr, &own, &tasks};
    for (plimsoll_batch_desc* desc : descs) {
        plimsoll_batch* batch = plimsoll_batch_create(desc);
        ASSERT_NE(batch, nullptr) << plimsoll_runtime_last_error();
        std::vector<plimsoll_forces> out(kBodies);
        ASSERT_EQ(plimsoll_batch_evaluate(batch, kBodies, bodies.data(), poses.data(),
                                          velocities.data(), &water, nullptr, 0.5, out.data()),
                  1)
            << plimsoll_runtime_last_error();
        for (std::size_t i = 0; i < kBodies; ++i)
            expectSameForces(out[i], single[i], "body " + std::to_string(i));

        // Every argument checked before the work, the first bad body named.
        std::vector<plimsoll_pose> bad = poses;
        bad[7].orientation[0] = std::nan("");
        bad[9].position[0] = HUGE_VAL;
        EXPECT_EQ(plimsoll_batch_evaluate(batch, kBodies, bodies.data(), bad.data(), nullptr,
                                          &water, nullptr, 0.5, out.data()),
                  0);
        EXPECT_CONTAINS(plimsoll_runtime_last_error(),
                        "plimsoll_batch_evaluate: body 7: orientation has a NaN");
        std::vector<const plimsoll_bundle*> withNull = bodies;
        withNull[4] = nullptr;
        EXPECT_EQ(plimsoll_batch_evaluate(batch, kBodies, withNull.data(), poses.data(), nullptr,
                                          &water, nullptr, 0.5, out.data()),
                  0);
        EXPECT_CONTAINS(plimsoll_runtime_last_error(), "body 4: bundle is NULL");
        EXPECT_EQ(plimsoll_batch_evaluate(batch, kBodies, bodies.data(), poses.data(), nullptr,
                                          &water, nullptr, 0.5, nullptr),
                  0);
        EXPECT_CONTAINS(plimsoll_runtime_last_error(), "is NULL");
        EXPECT_EQ(plimsoll_batch_evaluate(batch, kBodies, bodies.data(), poses.data(), nullptr,
                                          &water, nullptr, std::nan(""), out.data()),
                  0);
        EXPECT_CONTAINS(plimsoll_runtime_last_error(), "time is NaN");
        // A water callback that fails for some bodies only (x > 205 m: body 21 on, the bodies
        // being 10 m apart and smaller): the first of them named.
        const plimsoll_water partly = {
            0.0, [](void*, double x, double, double) { return x > 205.0 ? std::nan("") : 0.0; },
            nullptr, nullptr};
        EXPECT_EQ(plimsoll_batch_evaluate(batch, kBodies, bodies.data(), poses.data(), nullptr,
                                          &partly, nullptr, 0.5, out.data()),
                  0);
        EXPECT_CONTAINS(plimsoll_runtime_last_error(),
                        "body 21: the water height or velocity callback");
        EXPECT_EQ(plimsoll_batch_evaluate(batch, 0, nullptr, nullptr, nullptr, nullptr, nullptr,
                                          0.0, nullptr),
                  1);

        // The loads a physics engine applies, in one call, equal plimsoll_bundle_water_load's.
        std::vector<plimsoll_load> loads(kBodies);
        ASSERT_EQ(plimsoll_batch_water_load(batch, kBodies, bodies.data(), poses.data(),
                                            velocities.data(), &water, nullptr, 0.5, 1.0 / 240.0,
                                            loads.data()),
                  1)
            << plimsoll_runtime_last_error();
        for (std::size_t i = 0; i < kBodies; ++i) {
            const plimsoll_fluid fluid = plimsoll_bundle_default_fluid(bodies[i]);
            plimsoll_load one{};
            ASSERT_EQ(plimsoll_bundle_water_load(bodies[i], &poses[i], &velocities[i], &water,
                                                 &fluid, 0.5, 1.0 / 240.0, &one),
                      1);
            EXPECT_EQ(std::memcmp(&one, &loads[i], sizeof(one)), 0) << "body " << i;
            expectSameForces(loads[i].forces, single[i], "load of body " + std::to_string(i));
        }
        EXPECT_EQ(plimsoll_batch_water_load(batch, kBodies, bodies.data(), poses.data(), nullptr,
                                            &water, nullptr, 0.5, 0.0, loads.data()),
                  0);
        EXPECT_CONTAINS(plimsoll_runtime_last_error(), "dt must be finite and > 0");
        plimsoll_batch_free(batch);
    }
    EXPECT_GE(caller.enqueued, 3) << "the caller's task system was not used";
    plimsoll_batch_desc half = tasks;
    half.finish = nullptr;
    EXPECT_EQ(plimsoll_batch_create(&half), nullptr);
    EXPECT_CONTAINS(plimsoll_runtime_last_error(), "both enqueue and finish");
    plimsoll_bundle_free(boatB);
    plimsoll_bundle_free(buoyB);
}

/// Runs `body` in a child process, ended by SIGALRM after `seconds` (a deadlock or a hang
/// fails the test instead of stopping the suite): its exit status, or 128 + the signal.
int inChild(const std::function<int()>& body, unsigned seconds) {
    const pid_t child = ::fork();
    if (child == 0) {
        ::alarm(seconds);
        ::_exit(body());
    }
    int status = 0;
    ::waitpid(child, &status, 0);
    return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
}

/// A water callback that, on its first call, evaluates one body through `target` (with the
/// water `targetWater`) and keeps the error of a refused call.
struct Reentry {
    plimsoll_batch* target = nullptr;
    const plimsoll_water* targetWater = nullptr;
    const plimsoll_bundle* body = nullptr;
    std::atomic<int> calls{0}, refused{0};
    std::mutex mutex;
    std::string error;

    static double height(void* user, double, double, double) {
        Reentry& r = *static_cast<Reentry*>(user);
        if (r.calls++ == 0) {
            const plimsoll_pose pose = {{0.0, 0.0, 0.0}, {1.0, 0.0, 0.0, 0.0}};
            plimsoll_forces out{};
            if (plimsoll_batch_evaluate(r.target, 1, &r.body, &pose, nullptr, r.targetWater,
                                        nullptr, 0.0, &out) == 0) {
                ++r.refused;
                std::lock_guard<std::mutex> lock(r.mutex);
                r.error = plimsoll_runtime_last_error();
            }
        }
        return 0.0;
    }
};

// A batch runs one call at a time: a water callback evaluating the batch it runs in (directly,
// or through a second batch whose work calls the first) waited for itself forever. Refused with
// an error instead, on the library's pool, on the caller's task system and on the calling
// thread alone; the outer call goes on.
TEST_F(RuntimeSources, ABatchCalledFromItsOwnWorkIsRefusedNotDeadlocked) {
    plimsoll_bundle* boatB = plimsoll_bundle_load(boat().string().c_str(), 0);
    ASSERT_NE(boatB, nullptr) << plimsoll_runtime_last_error();
    const int status = inChild(
        [&] {
            CallerTasks caller;
            plimsoll_batch_desc alone{}, own{}, tasks{};
            alone.struct_size = own.struct_size = tasks.struct_size = sizeof(plimsoll_batch_desc);
            alone.thread_count = 1;
            own.thread_count = 3;
            tasks.enqueue = CallerTasks::enqueue;
            tasks.finish = CallerTasks::finish;
            tasks.user_context = &caller;
            tasks.worker_count = 3;
            const plimsoll_pose pose = {{0.0, 0.0, 0.0}, {1.0, 0.0, 0.0, 0.0}};
            const plimsoll_bundle* body = boatB;
            int failures = 0;
            auto check = [&](bool ok, const std::string& what) {
                if (!ok) {
                    std::fprintf(stderr, "%s\n", what.c_str());
                    ++failures;
                }
            };
            for (plimsoll_batch_desc* desc : {&alone, &own, &tasks}) {
                plimsoll_batch* a = plimsoll_batch_create(desc);
                plimsoll_batch* b = plimsoll_batch_create(desc);
                // Directly: a's callback calls a.
                Reentry direct;
                direct.target = a;
                direct.body = body;
                plimsoll_water water{};
                water.height = Reentry::height;
                water.user = &direct;
                direct.targetWater = &water;
                plimsoll_forces out{};
                check(plimsoll_batch_evaluate(a, 1, &body, &pose, nullptr, &water, nullptr, 0.0,
                                              &out) == 1,
                      std::string("the outer call failed: ") + plimsoll_runtime_last_error());
                check(direct.refused == 1, "the call from a's own work was not refused");
                check(direct.error.find(
                          "plimsoll_batch_evaluate: the batch is busy with the call this one "
                          "was made from") != std::string::npos,
                      "message: " + direct.error);
                // Through b: a's callback calls b, whose callback calls a.
                Reentry toB, toA;
                plimsoll_water waterA{}, waterB{};
                waterA.height = waterB.height = Reentry::height;
                waterA.user = &toB;
                waterB.user = &toA;
                toB.target = b;
                toB.targetWater = &waterB;
                toA.target = a;
                toA.targetWater = &waterA;
                toA.body = toB.body = body;
                check(plimsoll_batch_evaluate(a, 1, &body, &pose, nullptr, &waterA, nullptr, 0.0,
                                              &out) == 1,
                      std::string("the outer call failed: ") + plimsoll_runtime_last_error());
                check(toB.refused == 0, "a's work could not call b");
                check(toA.refused == 1, "b's work, inside a's, could call a");
                plimsoll_batch_destroy(a);
                plimsoll_batch_destroy(b);
            }
            return failures == 0 ? 0 : 1;
        },
        60);
    EXPECT_EQ(status, 0) << (status == 128 + SIGALRM ? "deadlocked" : "failed (see the output)");
    plimsoll_bundle_free(boatB);
}

// A batch asking for more threads than the system gives: plimsoll_batch_create fails saying
// so, after stopping the threads it started (a std::thread left running ended the process).
// The address space is limited in a child so that the thread stacks cannot all be mapped
// (root ignores RLIMIT_NPROC).
TEST(RuntimeBatch, AThreadTheSystemRefusesFailsTheCreationWithAMessage) {
#ifdef PLIMSOLL_SANITIZED_BUILD
    GTEST_SKIP() << "AddressSanitizer cannot run under an address-space limit";
#endif
    const int status = inChild(
        [] {
            long pages = 0;
            std::ifstream("/proc/self/statm") >> pages;
            const rlim_t now =
                static_cast<rlim_t>(pages) * static_cast<rlim_t>(::sysconf(_SC_PAGESIZE));
            const rlimit limit{now + (256ull << 20), now + (256ull << 20)};  // ~30 stacks of 8 MB
            if (::setrlimit(RLIMIT_AS, &limit) != 0) return 2;
            plimsoll_batch_desc desc{};
            desc.struct_size = sizeof(desc);
            desc.thread_count = 300;
            if (plimsoll_batch_create(&desc) != nullptr) return 3;
            const std::string error = plimsoll_runtime_last_error();
            std::fprintf(stderr, "%s\n", error.c_str());
            if (error.find("plimsoll_batch_create: cannot start thread ") == std::string::npos ||
                error.find(" of 300: ") == std::string::npos)
                return 4;
            // The threads it started were stopped: a small batch still starts and works.
            desc.thread_count = 2;
            plimsoll_batch* small = plimsoll_batch_create(&desc);
            if (!small) return 5;
            plimsoll_batch_destroy(small);
            return 0;
        },
        60);
    EXPECT_EQ(status, 0) << (status == 128 + SIGALRM ? "hung"
                                                     : "exit or signal " + std::to_string(status));
}

TEST_F(RuntimeSources, BatchGraphStepEqualsOneStepPerBody) {
    constexpr int kBoats = 4;
    std::vector<plimsoll_bundle*> batched, alone;
    std::vector<plimsoll_pose> poses;
    for (int i = 0; i < kBoats; ++i) {
        batched.push_back(plimsoll_bundle_load(boat().string().c_str(), 0));
        alone.push_back(plimsoll_bundle_load(boat().string().c_str(), 0));
        ASSERT_TRUE(batched.back() && alone.back()) << plimsoll_runtime_last_error();
        const double a = 0.2 * i;
        poses.push_back({{0.0, -0.2 - 0.1 * i, 0.0}, {std::cos(a / 2), std::sin(a / 2), 0.0, 0.0}});
    }
    const plimsoll_water water = {0.0, nullptr, nullptr, nullptr};
    plimsoll_batch* batch = plimsoll_batch_create(nullptr);
    ASSERT_NE(batch, nullptr);
    std::vector<int> moved(kBoats, -1);
    for (int step = 0; step < 50; ++step) {
        ASSERT_EQ(plimsoll_batch_graph_step(batch, kBoats, batched.data(), poses.data(), &water,
                                            0.02 * step, 0.02, moved.data()),
                  1)
            << plimsoll_runtime_last_error();
        for (int i = 0; i < kBoats; ++i) {
            const int one = plimsoll_graph_step(alone[i], &poses[i], &water, 0.02 * step, 0.02);
            EXPECT_EQ(moved[i], one) << "boat " << i << ", step " << step;
        }
    }
    double water0 = 0;
    for (int i = 0; i < kBoats; ++i) {
        for (std::size_t n = 0; n < plimsoll_graph_node_count(alone[i]); ++n) {
            EXPECT_EQ(plimsoll_graph_node_water(batched[i], n),
                      plimsoll_graph_node_water(alone[i], n));
            water0 += plimsoll_graph_node_water(alone[i], n);
        }
    }
    EXPECT_GT(water0, 0.0);
    std::vector<plimsoll_bundle*> twice = {batched[0], batched[1], batched[0]};
    EXPECT_EQ(
        plimsoll_batch_graph_step(batch, 3, twice.data(), poses.data(), &water, 0.0, 0.02, nullptr),
        0);
    EXPECT_CONTAINS(plimsoll_runtime_last_error(), "a bundle appears twice");
    EXPECT_EQ(plimsoll_batch_graph_step(batch, 2, batched.data(), poses.data(), &water, 0.0, -1.0,
                                        nullptr),
              0);
    EXPECT_CONTAINS(plimsoll_runtime_last_error(), "dt must be finite");
    plimsoll_batch_free(batch);
    for (int i = 0; i < kBoats; ++i) {
        plimsoll_bundle_free(batched[i]);
        plimsoll_bundle_free(alone[i]);
    }
}

}  // namespace
}  // namespace test_runtime_sources
}  // namespace plimsoll
