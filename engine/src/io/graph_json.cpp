// graph.json (graph.h, docs/formats.md): JSON text <-> WaterGraph. Reading is the runtime's
// reader of the format (readGraphJson) in its authoring form: every problem of form with its
// JSON path; the graph's own rules (dangling pipes, capacities, ...) are validateGraph's,
// applied by loadGraph.
#include "plimsoll/graph/graph.h"
#include "plimsoll/io/graph_json.h"

#include "plimsoll/io/file_util.h"
#include "plimsoll/core/limits.h"

#include "io/json_reader.h"
#include "plimsoll_runtime/runtime.hpp"

#include <nlohmann/json.hpp>

#include <vector>

namespace plimsoll {

namespace {

using detail::Json;

ErrorKind errorKindOf(plimsoll_runtime::GraphJsonProblem problem) {
    using Problem = plimsoll_runtime::GraphJsonProblem;
    switch (problem) {
        case Problem::Syntax:
            return ErrorKind::format;
        case Problem::Limit:
            return ErrorKind::limit;
        case Problem::NewerSchema:
            return ErrorKind::unsupported;
        default:
            return ErrorKind::schema;
    }
}

Eigen::Vector3d eigen(const plimsoll_runtime::Vec3& v) { return {v.x, v.y, v.z}; }

Json array3(const Eigen::Vector3d& v) { return Json::array({v.x(), v.y(), v.z()}); }

}  // namespace

Result<WaterGraph> parseGraph(const std::string& text, const std::string& source) {
    // The runtime's reader of the format, in the form people's files need: every problem, no
    // unknown member; the graph's own rules are validateGraph's, each with its class.
    std::vector<plimsoll_runtime::GraphNode> nodes;
    std::vector<plimsoll_runtime::GraphPipe> pipes;
    plimsoll_runtime::GraphJsonProblem problem{};
    std::string error;
    if (!plimsoll_runtime::readGraphJson(source, text, plimsoll_runtime::GraphJsonMode::Authoring,
                                         nodes, pipes, problem, error)) {
        return makeError(errorKindOf(problem), error);
    }
    WaterGraph graph;
    graph.nodes.reserve(nodes.size());
    for (const plimsoll_runtime::GraphNode& n : nodes) {
        graph.nodes.push_back({.id = n.id,
                               .name = n.name,
                               .position = eigen(n.position),
                               .capacity = n.capacity,
                               .water = n.water,
                               .sealed = n.sealed,
                               .boxSize = eigen(n.box)});
    }
    graph.pipes.reserve(pipes.size());
    for (const plimsoll_runtime::GraphPipe& p : pipes) {
        graph.pipes.push_back(
            {.a = p.a, .b = p.b, .radius = p.radius, .length = p.length, .open = p.open});
    }
    return graph;
}

Result<WaterGraph> loadGraph(const std::filesystem::path& path, const TriangleMesh* mesh,
                             std::string* warnings) {
    Result<std::string> text = readWholeFile(path, kMaxJsonFileBytes, "kMaxJsonFileBytes");
    if (!text) return text.error();
    Result<WaterGraph> graph = parseGraph(*text, path.string());
    if (!graph) return graph;
    const GraphReport report = validateGraph(*graph, mesh, path.string());
    if (report.hasErrors()) return makeError(ErrorKind::schema, report.format());
    if (warnings) *warnings = report.format();
    return graph;
}

std::string graphToJson(const WaterGraph& graph) {
    // One node or pipe a line: graphs are read and edited by people.
    std::string out =
        "{\n  \"schema_version\": " + std::to_string(kGraphSchemaVersion) + ",\n  \"nodes\": [";
    for (std::size_t i = 0; i < graph.nodes.size(); ++i) {
        const GraphNode& n = graph.nodes[i];
        Json j;
        j["id"] = n.id;
        j["name"] = n.name;
        j["position"] = array3(n.position);
        j["capacity"] = n.capacity;
        j["water"] = n.water;
        if (n.sealed) j["sealed"] = true;
        if (!n.boxSize.isZero(0.0)) j["box"] = array3(n.boxSize);
        out += std::string(i ? "," : "") + "\n    " + j.dump(-1, ' ', false);
    }
    out += graph.nodes.empty() ? "],\n  \"pipes\": [" : "\n  ],\n  \"pipes\": [";
    for (std::size_t i = 0; i < graph.pipes.size(); ++i) {
        const GraphPipe& p = graph.pipes[i];
        Json j;
        j["a"] = p.a;
        j["b"] = p.b;
        j["radius"] = p.radius;
        j["length"] = p.length;
        j["open"] = p.open;
        out += std::string(i ? "," : "") + "\n    " + j.dump(-1, ' ', false);
    }
    out += graph.pipes.empty() ? "]\n}\n" : "\n  ]\n}\n";
    // dump(-1) writes no spaces after separators; put them in for readability.
    std::string spaced;
    spaced.reserve(out.size() + out.size() / 8);
    bool inString = false;
    for (std::size_t i = 0; i < out.size(); ++i) {
        const char c = out[i];
        spaced += c;
        if (c == '"' && (i == 0 || out[i - 1] != '\\')) inString = !inString;
        if (!inString && (c == ',' || c == ':') && i + 1 < out.size() && out[i + 1] != '\n' &&
            out[i + 1] != ' ') {
            spaced += ' ';
        }
    }
    return spaced;
}

Status saveGraph(const WaterGraph& graph, const std::filesystem::path& path) {
    const std::string text = graphToJson(graph);
    return writeFileAtomically(path, [&](std::ostream& out) {
        out << text;
        return true;
    });
}

}  // namespace plimsoll
