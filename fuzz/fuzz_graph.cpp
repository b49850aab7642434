// libFuzzer target: water-graph JSON text (parseGraph, then validateGraph as loadGraph does).
// A graph that parses must survive graphToJson and parse back to the same JSON.
#include "plimsoll/graph/graph.h"
#include "plimsoll/io/graph_json.h"

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::string text(reinterpret_cast<const char*>(data), size);
    plimsoll::Result<plimsoll::WaterGraph> graph = plimsoll::parseGraph(text, "fuzz.graph.json");
    if (!graph) {
        if (graph.error().message.empty()) std::abort();
        return 0;
    }
    const plimsoll::GraphReport report =
        plimsoll::validateGraph(*graph, nullptr, "fuzz.graph.json");
    (void)report.format();
    const std::string saved = plimsoll::graphToJson(*graph);
    plimsoll::Result<plimsoll::WaterGraph> again = plimsoll::parseGraph(saved, "saved.graph.json");
    if (!again || plimsoll::graphToJson(*again) != saved) {
        std::fprintf(stderr, "saved graph does not load back the same: %s\n%s\n",
                     again ? "different" : again.error().message.c_str(), saved.c_str());
        std::abort();
    }
    return 0;
}
