// The water graph's JSON form (graph_json.h): exact round trips, every structural problem named
// with its JSON path, and a load that refuses an invalid graph with the problem's class.
#include "plimsoll/io/graph_json.h"

#include "plimsoll/graph/graph.h"

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
    EXPECT_NE(m.find("bad.json: nodes[0].position: must be an array of 3 numbers"),
              std::string::npos)
        << m;
    EXPECT_NE(m.find("nodes[0].capacity: must be a number"), std::string::npos) << m;
    EXPECT_NE(m.find("nodes[1].colour: unknown key"), std::string::npos) << m;
    EXPECT_NE(m.find("pipes[0].b: required"), std::string::npos) << m;
    EXPECT_FALSE(parseGraph(R"({"nodes": []})", "v.json").ok());  // no schema_version
    Result<WaterGraph> newer = parseGraph(R"({"schema_version": 99, "nodes": []})", "v.json");
    ASSERT_FALSE(newer.ok());
    EXPECT_NE(newer.error().message.find("newer"), std::string::npos);
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
