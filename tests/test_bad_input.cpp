// The bad-input corpus (tests/data/bad, listed with the expected outcomes in expected.json):
// every file goes to the loader it is meant for, which must refuse it (or, for meshes that load,
// validation must report the problem) with a message naming the file; mesh files also go
// through `plimsoll validate`, which must exit with 1, not a signal.
#include "cli_runner.h"

#include "plimsoll/bake_io.h"
#include "plimsoll/bundle.h"
#include "plimsoll/graph.h"
#include "plimsoll/mesh_io.h"
#include "plimsoll/project.h"
#include "plimsoll/validate.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <filesystem>
#include <fstream>
#include <set>

namespace plimsoll {
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
            EXPECT_EQ(run.exitCode, 1) << all;
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

}  // namespace
}  // namespace plimsoll
