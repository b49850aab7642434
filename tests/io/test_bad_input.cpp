// The bad-input corpus (tests/data/bad, listed with the expected outcomes in expected.json):
// every file goes to the loader it is meant for, which must refuse it (or, for meshes that load,
// validation must report the problem) with a message naming the file; mesh files also go
// through `plimsoll validate`, which must exit with 1, not a signal. Then every command that
// reads such a file walks the corpus under a time and a memory limit.
#include "cli_runner.h"

#include "test_support.h"

#include "plimsoll/surface/painted_map.h"
#include "plimsoll/io/painted_map_io.h"
#include "plimsoll/io/graph_json.h"
#include "plimsoll/io/bake_io.h"
#include "plimsoll/export/bundle.h"
#include "plimsoll/graph/graph.h"
#include "plimsoll/io/mesh_io.h"
#include "plimsoll/project/project.h"
#include "plimsoll/geometry/validate.h"

#include "plimsoll_runtime/runtime.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <filesystem>
#include <fstream>
#include <map>
#include <set>

namespace plimsoll {
namespace test_bad_input {
namespace {

namespace fs = std::filesystem;

const fs::path kCorpus = fs::path(PLIMSOLL_SOURCE_DIR) / "tests" / "data" / "bad";

struct Case {
    std::string file, loader, kind, contains;
};

std::vector<Case> corpusCases() {
    std::ifstream in(kCorpus / "expected.json");
    const nlohmann::json index = nlohmann::json::parse(in);
    std::vector<Case> cases;
    for (const auto& c : index.at("cases")) {
        cases.push_back({c.at("file").get<std::string>(), c.at("loader").get<std::string>(),
                         c.at("class").get<std::string>(), c.value("contains", std::string())});
    }
    return cases;
}

/// The loader's error message, or "" when it accepted the file.
std::string loaderError(const Case& c, const fs::path& path) {
    auto messageOf = [](const auto& result) {
        return result.ok() ? std::string() : result.error().message;
    };
    if (c.loader == "mesh") return messageOf(loadMesh(path));
    if (c.loader == "project") return messageOf(loadProject(path));
    if (c.loader == "graph") return messageOf(loadGraph(path));
    if (c.loader == "bundle") return messageOf(verifyBundle(path));
    if (c.loader == "bake") return messageOf(readBakedTextures(path));
    if (c.loader == "map") return messageOf(loadPaintedMap(path));
    if (c.loader == "simulate") {
        // Loads, but no simulation of it can run: plimsoll simulate must refuse it.
        if (Result<Project> project = loadProject(path); !project) return project.error().message;
        const test::CommandOutput run =
            test::runPlimsoll("simulate '" + path.string() + "' --seconds 0.1");
        return run.exitCode == 1 ? run.err : std::string();
    }
    if (c.loader == "runtime") {
        std::string error;
        return plimsoll_runtime::loadBundle(path.string(), error) ? std::string() : error;
    }
    ADD_FAILURE() << c.file << ": unknown loader " << c.loader;
    return {};
}

TEST(BadInput, EveryCorpusFileIsRefusedWithItsClassAndName) {
    const std::vector<Case> cases = corpusCases();
    ASSERT_GE(cases.size(), 40u);
    std::set<std::string> listed;
    for (const Case& c : cases) {
        SCOPED_TRACE(c.file + " (" + c.loader + ", " + c.kind + ")");
        listed.insert(c.file);
        const fs::path path = kCorpus / c.file;
        ASSERT_TRUE(fs::exists(path));
        const std::string name = path.filename().string();

        if (c.loader == "validate") {
            Result<TriangleMesh> mesh = loadMesh(path);
            ASSERT_TRUE(mesh.ok()) << mesh.error().message;
            const ValidationReport report = validateMesh(*mesh);
            bool found = false;
            for (const Problem& p : report.problems) found = found || problemCode(p.kind) == c.kind;
            EXPECT_TRUE(found) << report.format();
            EXPECT_NE(report.format().find(name + ": "), std::string::npos) << report.format();
            EXPECT_NE(report.format().find("[" + c.kind + "]"), std::string::npos)
                << report.format();
        } else {
            const std::string message = loaderError(c, path);
            ASSERT_FALSE(message.empty()) << "accepted";
            EXPECT_NE(message.find(name), std::string::npos) << message;
            EXPECT_NE(message.find(c.contains), std::string::npos) << message;
            if (c.kind == "limit") EXPECT_NE(message.find("limit"), std::string::npos) << message;
        }

        // The CLI is how users meet these files: a clean exit 1, never a crash.
        if (c.loader == "mesh" || c.loader == "validate") {
            const test::CommandOutput run = test::runPlimsoll("validate '" + path.string() + "'");
            const std::string all = run.out + run.err;
            // A mesh with problems a generated atlas or a physics solid gets round is usable
            // (exit 0, saying how); one that loads or solidifies not at all is refused (exit 1).
            if (c.loader == "mesh")
                EXPECT_EQ(run.exitCode, 1) << all;
            else
                EXPECT_TRUE(run.exitCode == 1 ||
                            (run.exitCode == 0 && all.find("usable through") != std::string::npos))
                    << all;
            EXPECT_NE(all.find(name), std::string::npos) << all;
            EXPECT_NE(all.find(c.loader == "mesh" ? c.contains : c.kind), std::string::npos) << all;
        }
    }
    // Every file of the corpus is listed (the script and the index excepted).
    for (const auto& entry : fs::directory_iterator(kCorpus)) {
        const std::string name = entry.path().filename().string();
        if (name == "expected.json" || name == "make_binary.py") continue;
        EXPECT_TRUE(listed.count(name)) << name << " is not in expected.json";
    }
}

/// Every regular file under `dir` (relative path -> bytes), `skip` (a folder under it) excepted.
std::map<std::string, std::string> snapshot(const fs::path& dir, const fs::path& skip = {}) {
    std::map<std::string, std::string> files;
    for (auto it = fs::recursive_directory_iterator(dir); it != fs::recursive_directory_iterator();
         ++it) {
        if (!skip.empty() && it->path() == skip) {
            it.disable_recursion_pending();
            continue;
        }
        if (it->is_regular_file())
            files[fs::relative(it->path(), dir).string()] = test::readFile(it->path());
    }
    return files;
}

// Every command that reads a file of the corpus, on each such file, at most 10 s and 1 GB of
// memory (the limits the issue sets): exit 1 or 2 (never a signal, a timeout or 0), a message
// naming the file and its problem, and no file changed outside the command's output folder.
TEST(BadInput, EveryCommandOverTheCorpusFailsCleanlyWithinTimeAndMemory) {
    const fs::path work = test::scratchFolder("bad_input_walk");
    const fs::path out = work / "out";
    const std::map<std::string, std::string> corpusBefore = snapshot(kCorpus);
    // timeout kills a hang; prlimit caps the address space a loader may take. The reference
    // backend: no OpenCL driver reserving address space of its own.
    const std::string limits =
        "PLIMSOLL_OPENCL_DEVICE=reference timeout -k 2 10 " + test::memoryCap(1ull << 30);
    int runs = 0;
    for (const Case& c : corpusCases()) {
        const std::string file = "'" + (kCorpus / c.file).string() + "'";
        std::vector<std::string> commands;
        if (c.loader == "mesh") {
            for (const std::string command :
                 {"validate " + file, "massprops " + file + " --size 16",
                  "buoyancy " + file +
                      " --exact --water-level 0 --position 0,0,0 --rotation-deg 0,0,0",
                  "bake " + file + " --size 16 --out '" + out.string() + "'",
                  "graph auto " + file + " --out '" + (out / "g.graph.json").string() + "'",
                  "simulate --mesh " + file + " --size 16 --seconds 0.1",
                  "atlas generate " + file + " --out '" + (out / "a.obj").string() + "'"})
                commands.push_back(command);
        } else if (c.loader == "project") {
            commands = {"simulate " + file + " --seconds 0.1",
                        "export " + file + " --out '" + out.string() + "' --quiet"};
        } else if (c.loader == "simulate") {
            commands = {"simulate " + file + " --seconds 0.1",
                        "simulate " + file + " --seconds 0.1 --integrator rk4"};
        } else if (c.loader == "graph") {
            commands = {"graph validate " + file};
        } else if (c.loader == "map") {
            const std::string box = "'" + test::assetPath("box.obj").string() + "'";
            commands = {"atlas transfer-map " + file + " --from " + box + " --to " + box +
                        " --out '" + (out / "m.png").string() + "'"};
        }
        for (const std::string& command : commands) {
            SCOPED_TRACE(command);
            fs::remove_all(out);
            fs::create_directories(out);
            const std::map<std::string, std::string> workBefore = snapshot(work, out);
            const test::CommandOutput run = test::runPlimsoll(command, limits);
            ++runs;
            const std::string all = run.out + run.err;
            EXPECT_TRUE(run.exitCode == 1 || run.exitCode == 2) << "exit " << run.exitCode << "\n"
                                                                << all;
            EXPECT_NE(all.find(c.file), std::string::npos) << all;
            EXPECT_NE(all.find(c.contains), std::string::npos) << all;
            EXPECT_TRUE(snapshot(work, out) == workBefore) << "a file beside the output changed";
        }
    }
    EXPECT_GE(runs, 100);
    EXPECT_TRUE(snapshot(kCorpus) == corpusBefore) << "the command changed the corpus";
}

}  // namespace
}  // namespace test_bad_input
}  // namespace plimsoll
