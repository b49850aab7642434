// graph.json (graph.h, docs/formats.md): JSON text <-> WaterGraph. Reading reports every
// structural problem with its JSON path; the graph's own rules (dangling pipes, capacities,
// ...) are validateGraph's, applied by loadGraph.
#include "plimsoll/graph.h"

#include "plimsoll/file_util.h"
#include "plimsoll/limits.h"

#include <nlohmann/json.hpp>

#include <cmath>
#include <fstream>
#include <iterator>
#include <string_view>

namespace plimsoll {

namespace {

using Json = nlohmann::ordered_json;

class GraphReader {
public:
    explicit GraphReader(std::string source) : source_(std::move(source)) {}

    Result<WaterGraph> read(const Json& root) {
        WaterGraph graph;
        if (!root.is_object()) return makeError(source_ + ": must be a JSON object");
        if (const auto v = root.find("schema_version"); v != root.end()) {
            if (!v->is_number_integer() || v->get<long long>() < 1) {
                problem("schema_version", "must be an integer >= 1");
            } else if (v->get<long long>() > kGraphSchemaVersion) {
                return makeError(source_ + ": schema_version: " +
                                 std::to_string(v->get<long long>()) +
                                 " is newer than this Plimsoll reads (" +
                                 std::to_string(kGraphSchemaVersion) + ")");
            }
        } else {
            problem("schema_version", "required");
        }
        known(root, "", {"schema_version", "name", "nodes", "pipes"});
        const auto nodes = root.find("nodes");
        if (nodes == root.end()) {
            problem("nodes", "required");
        } else if (!nodes->is_array()) {
            problem("nodes", "must be an array");
        } else if (nodes->size() > kMaxGraphNodes) {
            return makeError(source_ + ": nodes: " + std::to_string(nodes->size()) +
                             ", more than the limit kMaxGraphNodes = " +
                             std::to_string(kMaxGraphNodes) + " (limits.h)");
        } else {
            for (std::size_t i = 0; i < nodes->size(); ++i) {
                readNode((*nodes)[i], "nodes[" + std::to_string(i) + "]", graph.nodes.emplace_back());
            }
        }
        if (const auto pipes = root.find("pipes"); pipes != root.end()) {
            if (!pipes->is_array()) {
                problem("pipes", "must be an array");
            } else if (pipes->size() > kMaxGraphPipes) {
                return makeError(source_ + ": pipes: " + std::to_string(pipes->size()) +
                                 ", more than the limit kMaxGraphPipes = " +
                                 std::to_string(kMaxGraphPipes) + " (limits.h)");
            } else {
                for (std::size_t i = 0; i < pipes->size(); ++i) {
                    readPipe((*pipes)[i], "pipes[" + std::to_string(i) + "]",
                             graph.pipes.emplace_back());
                }
            }
        }
        if (problems_.empty()) return graph;
        std::string message;
        for (const std::string& line : problems_) message += (message.empty() ? "" : "\n") + line;
        return makeError(message);
    }

private:
    void problem(const std::string& path, const std::string& message) {
        problems_.push_back(source_ + ": " + path + ": " + message);
    }

    bool known(const Json& object, const std::string& path,
               std::initializer_list<std::string_view> keys) {
        if (!object.is_object()) {
            problem(path, "must be an object");
            return false;
        }
        for (const auto& item : object.items()) {
            bool ok = false;
            for (std::string_view k : keys) ok = ok || item.key() == k;
            if (!ok) problem((path.empty() ? "" : path + ".") + item.key(), "unknown key");
        }
        return true;
    }

    void number(const Json& object, const std::string& path, const char* key, double& out,
                bool required) {
        const auto v = object.find(key);
        if (v == object.end()) {
            if (required) problem(path + "." + key, "required");
            return;
        }
        if (!v->is_number()) {
            problem(path + "." + key, "must be a number");
            return;
        }
        out = v->get<double>();
    }

    void boolean(const Json& object, const std::string& path, const char* key, bool& out) {
        const auto v = object.find(key);
        if (v == object.end()) return;
        if (!v->is_boolean()) {
            problem(path + "." + key, "must be true or false");
            return;
        }
        out = v->get<bool>();
    }

    /// Ids are strings; integers are accepted and kept as their decimal text.
    void id(const Json& object, const std::string& path, const char* key, std::string& out) {
        const auto v = object.find(key);
        if (v == object.end()) {
            problem(path + "." + key, "required");
        } else if (v->is_string()) {
            out = v->get<std::string>();
        } else if (v->is_number_integer()) {
            out = std::to_string(v->get<long long>());
        } else {
            problem(path + "." + key, "must be a string (or an integer)");
        }
    }

    void vector3(const Json& object, const std::string& path, const char* key,
                 Eigen::Vector3d& out, bool required) {
        const auto v = object.find(key);
        if (v == object.end()) {
            if (required) problem(path + "." + key, "required");
            return;
        }
        if (!v->is_array() || v->size() != 3 ||
            !std::all_of(v->begin(), v->end(), [](const Json& x) { return x.is_number(); })) {
            problem(path + "." + key, "must be an array of 3 numbers");
            return;
        }
        for (int i = 0; i < 3; ++i) out[i] = (*v)[i].get<double>();
    }

    void readNode(const Json& value, const std::string& path, GraphNode& node) {
        if (!known(value, path,
                   {"id", "name", "position", "capacity", "water", "sealed", "box"})) {
            return;
        }
        id(value, path, "id", node.id);
        if (const auto v = value.find("name"); v != value.end()) {
            if (v->is_string()) node.name = v->get<std::string>();
            else problem(path + ".name", "must be a string");
        }
        vector3(value, path, "position", node.position, true);
        number(value, path, "capacity", node.capacity, true);
        number(value, path, "water", node.water, false);
        boolean(value, path, "sealed", node.sealed);
        vector3(value, path, "box", node.boxSize, false);
    }

    void readPipe(const Json& value, const std::string& path, GraphPipe& pipe) {
        if (!known(value, path, {"a", "b", "radius", "length", "open"})) return;
        id(value, path, "a", pipe.a);
        id(value, path, "b", pipe.b);
        number(value, path, "radius", pipe.radius, true);
        number(value, path, "length", pipe.length, false);
        boolean(value, path, "open", pipe.open);
    }

    std::string source_;
    std::vector<std::string> problems_;
};

Json array3(const Eigen::Vector3d& v) { return Json::array({v.x(), v.y(), v.z()}); }

}  // namespace

Result<WaterGraph> parseGraph(const std::string& text, const std::string& source) {
    Json root;
    try {
        root = Json::parse(text);
    } catch (const Json::exception& e) {
        std::string what = e.what();
        const std::size_t tag = what.find("] ");
        return makeError(source + ": " + (tag == std::string::npos ? what : what.substr(tag + 2)));
    }
    return GraphReader(source).read(root);
}

Result<WaterGraph> loadGraph(const std::filesystem::path& path, const TriangleMesh* mesh,
                             std::string* warnings) {
    Result<std::string> text = readWholeFile(path, kMaxJsonFileBytes, "kMaxJsonFileBytes");
    if (!text) return text.error();
    Result<WaterGraph> graph = parseGraph(*text, path.string());
    if (!graph) return graph;
    const GraphReport report = validateGraph(*graph, mesh, path.string());
    if (report.hasErrors()) return makeError(report.format());
    if (warnings) *warnings = report.format();
    return graph;
}

std::string graphToJson(const WaterGraph& graph) {
    // One node or pipe a line: graphs are read and edited by people.
    std::string out = "{\n  \"schema_version\": " + std::to_string(kGraphSchemaVersion) +
                      ",\n  \"nodes\": [";
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
