// The water graph's JSON form (graph_json.h): exact round trips, every structural problem named
// with its JSON path, and a load that refuses an invalid graph with the problem's class.
#include "plimsoll/io/graph_json.h"

#include "plimsoll/graph/graph.h"
#include "plimsoll_runtime/runtime.hpp"

#include "graph_support.h"
#include "test_support.h"

#include <filesystem>

namespace plimsoll {
namespace test_graph_json {
namespace {

using test::node;
using test::pipe;
using test::threeNodes;

TEST(GraphJson, RoundTripsExactly) {
    WaterGraph g = threeNodes();
    g.nodes[0].position = {0.1, 1.0 / 3.0, -2e-7};
    g.nodes[1].sealed = true;
    g.nodes[2].boxSize = {1.0, 0.5, 2.0};
    g.pipes[0].length = 1.25;
    g.pipes[1].open = false;
    const std::string text = graphToJson(g);
    EXPECT_NE(text.find("\"schema_version\": 1"), std::string::npos) << text;
    Result<WaterGraph> back = parseGraph(text, "g.json");
    ASSERT_TRUE(back.ok()) << back.error().message;
    EXPECT_TRUE(*back == g) << text;
    EXPECT_EQ(graphToJson(*back), text);
}

TEST(GraphJson, ReportsEveryStructuralProblemWithItsPath) {
    const std::string text = R"({"schema_version": 1,
        "nodes": [{"id": "a", "position": [0, 1], "capacity": "big"},
                  {"id": 7, "position": [0, 0, 0], "capacity": 1, "colour": "red"}],
        "pipes": [{"a": "a", "radius": 0.1}]})";
    Result<WaterGraph> g = parseGraph(text, "bad.json");
    ASSERT_FALSE(g.ok());
    const std::string& m = g.error().message;
    EXPECT_NE(m.find("bad.json: $.nodes[0].position: expected an array of 3 numbers"),
              std::string::npos)
        << m;
    EXPECT_NE(m.find("bad.json: $.nodes[0].capacity: expected a number"), std::string::npos) << m;
    EXPECT_NE(m.find("bad.json: $.nodes[1].colour: unknown member"), std::string::npos) << m;
    EXPECT_NE(m.find("bad.json: $.pipes[0]: missing required member \"b\""), std::string::npos)
        << m;
    EXPECT_EQ(g.error().kind, ErrorKind::schema);
    EXPECT_FALSE(parseGraph(R"({"nodes": []})", "v.json").ok());  // no schema_version
    Result<WaterGraph> newer = parseGraph(R"({"schema_version": 99, "nodes": []})", "v.json");
    ASSERT_FALSE(newer.ok());
    EXPECT_NE(newer.error().message.find("newer"), std::string::npos);
    EXPECT_EQ(newer.error().kind, ErrorKind::unsupported);
}

// JSON text is UTF-8: names in any script load and save back unchanged; a byte sequence that is
// not UTF-8 (a stray Latin-1 byte, an overlong form, an encoded surrogate) is refused by the
// reader with its position, since a graph that loaded could not be written again.
TEST(GraphJson, NamesAreUtf8AndMalformedBytesAreRefused) {
    WaterGraph g = threeNodes();
    g.nodes[0].name =
        "K\xc3\xbc"
        "che \xe8\x88\xb9\xe5\xba\x95 \xf0\x9f\x9a\xa2";  // Küche 船底 🚢
    const std::string text = graphToJson(g);
    Result<WaterGraph> back = parseGraph(text, "g.json");
    ASSERT_TRUE(back.ok()) << back.error().message;
    EXPECT_EQ(back->nodes[0].name, g.nodes[0].name);
    for (const std::string bad :
         {"\xe9"
          "t"
          "\xe9",
          "\xc0\xaf", "\xed\xa0\x80", "\xf4\x90\x80\x80", "\xe8\x88", "\x80"}) {
        std::string mutated = text;
        const std::size_t at = mutated.find(g.nodes[0].name);
        ASSERT_NE(at, std::string::npos);
        mutated.replace(at, g.nodes[0].name.size(), bad);
        Result<WaterGraph> refused = parseGraph(mutated, "latin1.json");
        ASSERT_FALSE(refused.ok()) << "accepted " << bad.size() << " bytes";
        EXPECT_NE(refused.error().message.find("latin1.json"), std::string::npos);
        EXPECT_NE(refused.error().message.find("invalid UTF-8"), std::string::npos)
            << refused.error().message;
    }
}

// One reader reads the format for projects and bundles (plimsoll_runtime::readGraphJson); its
// two forms differ only where the docs say.
TEST(GraphJson, TheBundleFormIsTheSameReaderWithTheGraphsRules) {
    using plimsoll_runtime::GraphJsonMode;
    using plimsoll_runtime::GraphJsonProblem;
    const auto read = [](const std::string& text, GraphJsonMode mode, std::string& error) {
        std::vector<plimsoll_runtime::GraphNode> nodes;
        std::vector<plimsoll_runtime::GraphPipe> pipes;
        GraphJsonProblem problem{};
        const bool ok =
            plimsoll_runtime::readGraphJson("g.json", text, mode, nodes, pipes, problem, error);
        EXPECT_EQ(ok, problem == GraphJsonProblem::None);
        return std::make_pair(ok, nodes.size() + pipes.size());
    };
    std::string error;
    // What the engine writes reads back whole in both forms.
    const std::string written = graphToJson(threeNodes());
    EXPECT_EQ(read(written, GraphJsonMode::Bundle, error), std::make_pair(true, std::size_t{5}))
        << error;
    EXPECT_EQ(read(written, GraphJsonMode::Authoring, error), std::make_pair(true, std::size_t{5}))
        << error;
    // A member neither knows: ignored in a bundle (a newer minor's), refused from a person.
    const std::string extra =
        R"({"schema_version": 1, "nodes": [{"id": "a", "position": [0, 0, 0], "capacity": 1,
            "colour": "red"}], "pipes": []})";
    EXPECT_TRUE(read(extra, GraphJsonMode::Bundle, error).first) << error;
    EXPECT_FALSE(read(extra, GraphJsonMode::Authoring, error).first);
    EXPECT_NE(error.find("g.json: $.nodes[0].colour: unknown member"), std::string::npos) << error;
    // The graph's rules: the bundle form checks them itself, the first problem only; the
    // authoring form leaves them to validateGraph, which names each with its class.
    const std::string twice =
        R"({"schema_version": 1, "nodes": [{"id": "a", "position": [0, 0, 0], "capacity": 1},
            {"id": "a", "position": [1, 0, 0], "capacity": -1}], "pipes": []})";
    EXPECT_FALSE(read(twice, GraphJsonMode::Bundle, error).first);
    EXPECT_EQ(error, "g.json: $.nodes[1].capacity: must be > 0");
    EXPECT_TRUE(read(twice, GraphJsonMode::Authoring, error).first) << error;
    Result<WaterGraph> parsed = parseGraph(twice, "g.json");
    ASSERT_TRUE(parsed.ok()) << parsed.error().message;
    const std::string report = validateGraph(*parsed).format();
    EXPECT_NE(report.find("[duplicate-id]"), std::string::npos) << report;
    EXPECT_NE(report.find("[bad-capacity]"), std::string::npos) << report;
}

TEST(GraphJson, LoadRefusesAnInvalidGraphWithTheClass) {
    WaterGraph g = threeNodes();
    g.pipes[0].b = "ghost";
    const std::filesystem::path file = test::scratchFolder("plimsoll_test_graph") / "dangling.json";
    ASSERT_TRUE(saveGraph(g, file).ok());
    Result<WaterGraph> loaded = loadGraph(file);
    ASSERT_FALSE(loaded.ok());
    EXPECT_NE(loaded.error().message.find("[dangling-pipe]"), std::string::npos)
        << loaded.error().message;
    EXPECT_NE(loaded.error().message.find("dangling.json"), std::string::npos);
}

}  // namespace
}  // namespace test_graph_json
}  // namespace plimsoll
