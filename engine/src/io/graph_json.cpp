// graph.json (graph.h, docs/formats.md): JSON text <-> WaterGraph. Reading reports every
// structural problem with its JSON path; the graph's own rules (dangling pipes, capacities,
// ...) are validateGraph's, applied by loadGraph.
#include "plimsoll/graph/graph.h"
#include "plimsoll/io/graph_json.h"

#include "plimsoll/io/file_util.h"
#include "plimsoll/core/limits.h"

#include "io/json_reader.h"

#include <nlohmann/json.hpp>

#include <cmath>
#include <fstream>
#include <iterator>
#include <string_view>

namespace plimsoll {

namespace {

using detail::find;
using detail::Json;
using detail::Limit;
using detail::member;
using detail::Presence;

class GraphReader : public detail::JsonReader {
public:
    explicit GraphReader(std::string source) : JsonReader(std::move(source)) {}

    Result<WaterGraph> read(const Json& root) {
        WaterGraph graph;
        if (!root.is_object()) {
            return makeError(ErrorKind::schema, source() + ": must be a JSON object");
        }
        if (const Json* v = find(root, "schema_version")) {
            if (!v->is_number_integer() || v->get<long long>() < 1) {
                problem("schema_version", "must be an integer >= 1");
            } else if (v->get<long long>() > kGraphSchemaVersion) {
                return makeError(ErrorKind::unsupported,
                                 source() +
                                     ": schema_version: " + std::to_string(v->get<long long>()) +
                                     " is newer than this Plimsoll reads (" +
                                     std::to_string(kGraphSchemaVersion) + ")");
            }
        } else {
            problem("schema_version", "required");
        }
        expectObject(root, "", {"schema_version", "name", "nodes", "pipes"});
        const Json* nodes = find(root, "nodes");
        if (!nodes) {
            problem("nodes", "required");
        } else if (!nodes->is_array()) {
            problem("nodes", "must be an array");
        } else if (nodes->size() > kMaxGraphNodes) {
            return makeError(ErrorKind::limit, source() +
                                                   ": nodes: " + std::to_string(nodes->size()) +
                                                   ", more than the limit kMaxGraphNodes = " +
                                                   std::to_string(kMaxGraphNodes) + " (limits.h)");
        } else {
            for (std::size_t i = 0; i < nodes->size(); ++i) {
                readNode((*nodes)[i], detail::element("nodes", i), graph.nodes.emplace_back());
            }
        }
        if (const Json* pipes = find(root, "pipes")) {
            if (!pipes->is_array()) {
                problem("pipes", "must be an array");
            } else if (pipes->size() > kMaxGraphPipes) {
                return makeError(ErrorKind::limit,
                                 source() + ": pipes: " + std::to_string(pipes->size()) +
                                     ", more than the limit kMaxGraphPipes = " +
                                     std::to_string(kMaxGraphPipes) + " (limits.h)");
            } else {
                for (std::size_t i = 0; i < pipes->size(); ++i) {
                    readPipe((*pipes)[i], detail::element("pipes", i), graph.pipes.emplace_back());
                }
            }
        }
        if (hasProblems()) return problems();
        return graph;
    }

private:
    /// Ids are strings; integers are accepted and kept as their decimal text.
    void id(const Json& object, const std::string& path, const char* key, std::string& out) {
        const Json* v = find(object, key);
        if (!v) {
            problem(member(path, key), "required");
        } else if (v->is_string()) {
            out = v->get<std::string>();
        } else if (v->is_number_integer()) {
            out = std::to_string(v->get<long long>());
        } else {
            problem(member(path, key), "must be a string (or an integer)");
        }
    }

    void readNode(const Json& value, const std::string& path, GraphNode& node) {
        if (!expectObject(value, path,
                          {"id", "name", "position", "capacity", "water", "sealed", "box"})) {
            return;
        }
        id(value, path, "id", node.id);
        string(value, path, "name", node.name);
        vector(value, path, "position", node.position, Presence::Required);
        number(value, path, "capacity", node.capacity, Limit::Any, Presence::Required);
        number(value, path, "water", node.water);
        boolean(value, path, "sealed", node.sealed);
        vector(value, path, "box", node.boxSize);
    }

    void readPipe(const Json& value, const std::string& path, GraphPipe& pipe) {
        if (!expectObject(value, path, {"a", "b", "radius", "length", "open"})) return;
        id(value, path, "a", pipe.a);
        id(value, path, "b", pipe.b);
        number(value, path, "radius", pipe.radius, Limit::Any, Presence::Required);
        number(value, path, "length", pipe.length);
        boolean(value, path, "open", pipe.open);
    }
};

Json array3(const Eigen::Vector3d& v) { return Json::array({v.x(), v.y(), v.z()}); }

}  // namespace

Result<WaterGraph> parseGraph(const std::string& text, const std::string& source) {
    Result<Json> root = detail::parseJson(text, source);
    if (!root) return root.error();
    return GraphReader(source).read(*root);
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
