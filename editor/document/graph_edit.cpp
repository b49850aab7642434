#include "document/graph_edit.h"

#include <algorithm>
#include <map>
#include <cmath>
#include <set>

namespace plimsoll::editor {

GraphCommand::GraphCommand(std::string name, std::size_t body, std::optional<WaterGraph> before,
                           std::optional<WaterGraph> after, std::optional<Project> projectBefore,
                           std::optional<Project> projectAfter)
    : name_(std::move(name)),
      body_(body),
      before_(std::move(before)),
      after_(std::move(after)),
      projectBefore_(std::move(projectBefore)),
      projectAfter_(std::move(projectAfter)) {}

Status GraphCommand::apply(Document& document) {
    if (body_ >= document.bodyCount())
        return makeError(ErrorKind::invalidArgument, "no body " + std::to_string(body_));
    // The project first: it names the file the graph belongs to.
    if (projectAfter_) document.setProject(*projectAfter_, detached_);
    document.setGraph(body_, after_);
    return Ok{};
}

void GraphCommand::revert(Document& document) {
    document.setGraph(body_, before_);
    if (projectBefore_) document.setProject(*projectBefore_, detached_);
}

namespace {

bool finite(const Eigen::Vector3d& v) { return v.allFinite(); }

/// The body's graph to edit, or why there is none.
Result<WaterGraph> currentGraph(const Document& document, std::size_t body) {
    if (body >= document.bodyCount()) {
        return makeError(ErrorKind::invalidArgument,
                         "no body " + std::to_string(body) + " (the project has " +
                             std::to_string(document.bodyCount()) + ")");
    }
    if (!document.project().bodies[body].waterGraph) {
        return makeError(ErrorKind::invalidArgument,
                         "body " + std::to_string(body) +
                             " has no water graph (create one first: graph_create)");
    }
    const WaterGraph* graph = document.graph(body);
    if (!graph) {
        return makeError(ErrorKind::io,
                         "body " + std::to_string(body) +
                             ": water graph not loaded: " + document.assets(body).graph.error);
    }
    return *graph;
}

Status checkNode(const GraphNode& n) {
    if (!(n.capacity > 0) || !std::isfinite(n.capacity)) {
        return makeError(ErrorKind::invalidArgument,
                         "node " + n.id + ": capacity must be > 0 (m^3)");
    }
    if (!(n.water >= 0) || n.water > n.capacity) {
        return makeError(ErrorKind::invalidArgument,
                         "node " + n.id + ": water must be within 0..capacity (m^3)");
    }
    if (!finite(n.position))
        return makeError(ErrorKind::invalidArgument, "node " + n.id + ": position not finite");
    if (!finite(n.boxSize) || n.boxSize.minCoeff() < 0) {
        return makeError(ErrorKind::invalidArgument,
                         "node " + n.id + ": box size must be >= 0 (m)");
    }
    return Ok{};
}

Status checkPipe(const GraphPipe& p) {
    if (!(p.radius > 0) || !std::isfinite(p.radius)) {
        return makeError(ErrorKind::invalidArgument,
                         "pipe " + p.a + "-" + p.b + ": radius must be > 0 (m)");
    }
    if (!(p.length >= 0) || !std::isfinite(p.length)) {
        return makeError(ErrorKind::invalidArgument,
                         "pipe " + p.a + "-" + p.b + ": length must be >= 0 (m)");
    }
    return Ok{};
}

Status checkIds(const WaterGraph& graph, const std::vector<std::string>& ids) {
    if (ids.empty()) return makeError(ErrorKind::invalidArgument, "no nodes given");
    for (const std::string& id : ids) {
        if (graph.indexOf(id) < 0)
            return makeError(ErrorKind::invalidArgument, "no node \"" + id + "\"");
    }
    return Ok{};
}

Result<std::unique_ptr<Command>> edited(const Document& document, std::size_t body,
                                        std::string name, WaterGraph after) {
    return std::unique_ptr<Command>(std::make_unique<GraphCommand>(
        std::move(name), body, *document.graph(body), std::move(after)));
}

std::string plural(std::size_t n, const char* what) {
    return std::to_string(n) + " " + what + (n == 1 ? "" : "s");
}

}  // namespace

std::string freshNodeId(const WaterGraph& graph) {
    for (std::size_t i = graph.nodes.size() + 1;; ++i) {
        std::string id = "n" + std::to_string(i);
        if (graph.indexOf(id) < 0) return id;
    }
}

int findPipe(const WaterGraph& graph, const std::string& a, const std::string& b) {
    for (std::size_t i = 0; i < graph.pipes.size(); ++i) {
        const GraphPipe& p = graph.pipes[i];
        if ((p.a == a && p.b == b) || (p.a == b && p.b == a)) return static_cast<int>(i);
    }
    return -1;
}

Result<std::unique_ptr<Command>> makeCreateGraphCommand(const Document& document, std::size_t body,
                                                        std::string path) {
    if (body >= document.bodyCount())
        return makeError(ErrorKind::invalidArgument, "no body " + std::to_string(body));
    if (document.project().bodies[body].waterGraph) {
        return makeError(ErrorKind::invalidArgument,
                         "body " + std::to_string(body) + " already has a water graph (" +
                             document.project().bodies[body].waterGraph->graph + ")");
    }
    if (path.empty()) path = document.defaultGraphPath(body);
    Project after = document.project();
    WaterGraphDesc desc;
    desc.graph = path;
    after.bodies[body].waterGraph = desc;
    return std::unique_ptr<Command>(std::make_unique<GraphCommand>(
        "New water graph", body,
        document.graph(body) ? std::optional(*document.graph(body)) : std::nullopt, WaterGraph{},
        document.project(), std::move(after)));
}

Result<std::unique_ptr<Command>> makeReplaceGraphCommand(const Document& document, std::size_t body,
                                                         WaterGraph graph, std::string name) {
    if (body >= document.bodyCount())
        return makeError(ErrorKind::invalidArgument, "no body " + std::to_string(body));
    if (!document.project().bodies[body].waterGraph) {
        return makeError(ErrorKind::invalidArgument,
                         "body " + std::to_string(body) + " has no water graph entry");
    }
    for (const GraphNode& n : graph.nodes) {
        if (Status s = checkNode(n); !s) return s.error();
    }
    for (const GraphPipe& p : graph.pipes) {
        if (Status s = checkPipe(p); !s) return s.error();
    }
    const WaterGraph* before = document.graph(body);
    return std::unique_ptr<Command>(std::make_unique<GraphCommand>(
        std::move(name), body, before ? std::optional(*before) : std::nullopt, std::move(graph)));
}

Result<std::unique_ptr<Command>> makeAddNodeCommand(const Document& document, std::size_t body,
                                                    GraphNode node) {
    Result<WaterGraph> graph = currentGraph(document, body);
    if (!graph) return graph.error();
    if (node.id.empty()) node.id = freshNodeId(*graph);
    if (graph->indexOf(node.id) >= 0)
        return makeError(ErrorKind::invalidArgument, "node id \"" + node.id + "\" is taken");
    if (Status s = checkNode(node); !s) return s.error();
    const std::string name = "Add node " + node.id;
    graph->nodes.push_back(std::move(node));
    return edited(document, body, name, std::move(graph).value());
}

Result<std::unique_ptr<Command>> makeDuplicateNodesCommand(const Document& document,
                                                           std::size_t body,
                                                           const std::vector<std::string>& ids,
                                                           const Eigen::Vector3d& offset) {
    Result<WaterGraph> graph = currentGraph(document, body);
    if (!graph) return graph.error();
    if (Status s = checkIds(*graph, ids); !s) return s.error();
    if (!finite(offset)) return makeError(ErrorKind::invalidArgument, "offset not finite");
    std::map<std::string, std::string> copyOf;
    for (const std::string& id : ids) {
        if (copyOf.count(id)) continue;
        GraphNode copy = graph->nodes[graph->indexOf(id)];
        copy.id = freshNodeId(*graph);
        copy.position += offset;
        copyOf[id] = copy.id;
        graph->nodes.push_back(std::move(copy));
    }
    // Pipes among the duplicated nodes come along, so a duplicated group stays connected.
    const std::size_t pipes = graph->pipes.size();
    for (std::size_t i = 0; i < pipes; ++i) {
        const GraphPipe p = graph->pipes[i];
        if (copyOf.count(p.a) && copyOf.count(p.b)) {
            GraphPipe copy = p;
            copy.a = copyOf[p.a];
            copy.b = copyOf[p.b];
            graph->pipes.push_back(std::move(copy));
        }
    }
    return edited(document, body, "Duplicate " + plural(copyOf.size(), "node"),
                  std::move(graph).value());
}

Result<std::unique_ptr<Command>> makeDeleteNodesCommand(const Document& document, std::size_t body,
                                                        const std::vector<std::string>& ids) {
    Result<WaterGraph> graph = currentGraph(document, body);
    if (!graph) return graph.error();
    if (Status s = checkIds(*graph, ids); !s) return s.error();
    const std::set<std::string> gone(ids.begin(), ids.end());
    std::erase_if(graph->nodes, [&](const GraphNode& n) { return gone.count(n.id) > 0; });
    std::erase_if(graph->pipes,
                  [&](const GraphPipe& p) { return gone.count(p.a) > 0 || gone.count(p.b) > 0; });
    return edited(document, body, "Delete " + plural(gone.size(), "node"),
                  std::move(graph).value());
}

Result<std::unique_ptr<Command>> makeMoveNodesCommand(const Document& document, std::size_t body,
                                                      const std::vector<std::string>& ids,
                                                      const Eigen::Vector3d& offset) {
    Result<WaterGraph> graph = currentGraph(document, body);
    if (!graph) return graph.error();
    if (Status s = checkIds(*graph, ids); !s) return s.error();
    if (!finite(offset)) return makeError(ErrorKind::invalidArgument, "offset not finite");
    const std::set<std::string> moved(ids.begin(), ids.end());
    for (GraphNode& n : graph->nodes) {
        if (moved.count(n.id)) n.position += offset;
    }
    return edited(document, body, "Move " + plural(moved.size(), "node"), std::move(graph).value());
}

Result<std::unique_ptr<Command>> makeSetNodeCommand(const Document& document, std::size_t body,
                                                    const std::string& id, const NodeEdit& edit) {
    return makeSetNodesCommand(document, body, {id}, edit);
}

Result<std::unique_ptr<Command>> makeSetNodesCommand(const Document& document, std::size_t body,
                                                     const std::vector<std::string>& ids,
                                                     const NodeEdit& edit) {
    if (ids.size() > 1 && (edit.name || edit.position)) {
        return makeError(ErrorKind::invalidArgument,
                         "a name or a position is given to one node at a time (" +
                             std::to_string(ids.size()) + " selected)");
    }
    Result<WaterGraph> graph = currentGraph(document, body);
    if (!graph) return graph.error();
    if (Status s = checkIds(*graph, ids); !s) return s.error();
    for (const std::string& id : ids) {
        GraphNode& n = graph->nodes[graph->indexOf(id)];
        if (edit.name) n.name = *edit.name;
        if (edit.position) n.position = *edit.position;
        if (edit.capacity) n.capacity = *edit.capacity;
        if (edit.water) n.water = *edit.water;
        if (edit.sealed) n.sealed = *edit.sealed;
        if (edit.boxSize) n.boxSize = *edit.boxSize;
        if (Status s = checkNode(n); !s) return s.error();
    }
    const std::string name =
        ids.size() == 1 ? "Edit node " + ids[0] : "Edit " + plural(ids.size(), "node");
    return edited(document, body, name, std::move(graph).value());
}

Result<std::unique_ptr<Command>> makeAddPipeCommand(const Document& document, std::size_t body,
                                                    GraphPipe pipe) {
    Result<WaterGraph> graph = currentGraph(document, body);
    if (!graph) return graph.error();
    if (Status s = checkIds(*graph, {pipe.a, pipe.b}); !s) return s.error();
    if (pipe.a == pipe.b)
        return makeError(ErrorKind::invalidArgument,
                         "a pipe joins two different nodes, not " + pipe.a + " to itself");
    if (findPipe(*graph, pipe.a, pipe.b) >= 0) {
        return makeError(ErrorKind::invalidArgument,
                         "nodes " + pipe.a + " and " + pipe.b + " are already connected");
    }
    if (Status s = checkPipe(pipe); !s) return s.error();
    const std::string name = "Connect " + pipe.a + "-" + pipe.b;
    graph->pipes.push_back(std::move(pipe));
    return edited(document, body, name, std::move(graph).value());
}

Result<std::unique_ptr<Command>> makeRemovePipeCommand(const Document& document, std::size_t body,
                                                       const std::string& a, const std::string& b) {
    Result<WaterGraph> graph = currentGraph(document, body);
    if (!graph) return graph.error();
    const int index = findPipe(*graph, a, b);
    if (index < 0)
        return makeError(ErrorKind::invalidArgument, "no pipe between " + a + " and " + b);
    graph->pipes.erase(graph->pipes.begin() + index);
    return edited(document, body, "Disconnect " + a + "-" + b, std::move(graph).value());
}

Result<std::unique_ptr<Command>> makeSetPipeCommand(const Document& document, std::size_t body,
                                                    const std::string& a, const std::string& b,
                                                    const PipeEdit& edit) {
    Result<WaterGraph> graph = currentGraph(document, body);
    if (!graph) return graph.error();
    const int index = findPipe(*graph, a, b);
    if (index < 0)
        return makeError(ErrorKind::invalidArgument, "no pipe between " + a + " and " + b);
    GraphPipe& p = graph->pipes[index];
    if (edit.open) p.open = *edit.open;
    if (edit.radius) p.radius = *edit.radius;
    if (edit.length) p.length = *edit.length;
    if (Status s = checkPipe(p); !s) return s.error();
    const std::string name =
        edit.open && !edit.radius && !edit.length
            ? std::string(*edit.open ? "Open" : "Close") + " pipe " + a + "-" + b
            : "Edit pipe " + a + "-" + b;
    return edited(document, body, name, std::move(graph).value());
}

}  // namespace plimsoll::editor
