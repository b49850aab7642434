// Water-graph edits (graph.h): every change of a body's graph is a GraphCommand holding the
// graph before and after, so undo gives back the graph exactly (graphToJson byte for byte).
// The functions below check what is asked against the current graph and build the command;
// the document executes it. Nodes and pipes are named by node id (a pipe by its two ends, in
// either order), which stays meaningful across undo, unlike indices.
#pragma once

#include "document/document.h"

#include <Eigen/Core>

#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace plimsoll::editor {

/// A change of one body's graph (and, for a new graph, of the project entry naming its file).
class GraphCommand final : public Command {
public:
    GraphCommand(std::string name, std::size_t body, std::optional<WaterGraph> before,
                 std::optional<WaterGraph> after, std::optional<Project> projectBefore = {},
                 std::optional<Project> projectAfter = {});
    std::string name() const override { return name_; }
    Status apply(Document& document) override;
    void revert(Document& document) override;
    std::size_t body() const { return body_; }
    const std::optional<WaterGraph>& after() const { return after_; }

private:
    std::string name_;
    std::size_t body_;
    std::optional<WaterGraph> before_, after_;
    std::optional<Project> projectBefore_, projectAfter_;
    DetachedAssets detached_;  ///< what the project change took out, for the way back
};

/// Fields of a node to change; unset ones stay.
struct NodeEdit {
    std::optional<std::string> name;
    std::optional<Eigen::Vector3d> position;
    std::optional<double> capacity;
    std::optional<double> water;
    std::optional<bool> sealed;
    std::optional<Eigen::Vector3d> boxSize;  ///< zero: a sphere node
};

/// Fields of a pipe to change; unset ones stay.
struct PipeEdit {
    std::optional<bool> open;
    std::optional<double> radius;
    std::optional<double> length;  ///< 0: the distance between the nodes
};

/// An id not used in the graph: "n1", "n2", ...
std::string freshNodeId(const WaterGraph& graph);

/// A new graph (no nodes yet) for a body that has none: the project's water_graph entry names
/// `path` (relative to the project's folder; empty: Document::defaultGraphPath), with the
/// default simulation settings.
Result<std::unique_ptr<Command>> makeCreateGraphCommand(const Document& document, std::size_t body,
                                                        std::string path = {});
/// Replaces the whole graph (an automatically generated one); the body must have a graph entry.
Result<std::unique_ptr<Command>> makeReplaceGraphCommand(const Document& document, std::size_t body,
                                                         WaterGraph graph,
                                                         std::string name = "Replace water graph");
/// Adds a node (empty id: freshNodeId). Capacity > 0, water within 0..capacity, id unused.
Result<std::unique_ptr<Command>> makeAddNodeCommand(const Document& document, std::size_t body,
                                                    GraphNode node);
/// Copies of the nodes (new ids, positions + offset) and of the pipes between them.
Result<std::unique_ptr<Command>> makeDuplicateNodesCommand(const Document& document,
                                                           std::size_t body,
                                                           const std::vector<std::string>& ids,
                                                           const Eigen::Vector3d& offset);
/// Removes the nodes and every pipe that names one of them.
Result<std::unique_ptr<Command>> makeDeleteNodesCommand(const Document& document, std::size_t body,
                                                        const std::vector<std::string>& ids);
/// Moves the nodes by `offset` (object space, m).
Result<std::unique_ptr<Command>> makeMoveNodesCommand(const Document& document, std::size_t body,
                                                      const std::vector<std::string>& ids,
                                                      const Eigen::Vector3d& offset);
Result<std::unique_ptr<Command>> makeSetNodeCommand(const Document& document, std::size_t body,
                                                    const std::string& id, const NodeEdit& edit);
/// The same fields set on several nodes as one step ("Edit 3 nodes"): capacity, water, sealed,
/// box size (a name or a position goes to one node at a time). Every node is checked as one
/// node's edit is; any failure leaves the graph as it was.
Result<std::unique_ptr<Command>> makeSetNodesCommand(const Document& document, std::size_t body,
                                                     const std::vector<std::string>& ids,
                                                     const NodeEdit& edit);
/// Connects two different existing nodes not yet connected (radius > 0, length >= 0).
Result<std::unique_ptr<Command>> makeAddPipeCommand(const Document& document, std::size_t body,
                                                    GraphPipe pipe);
Result<std::unique_ptr<Command>> makeRemovePipeCommand(const Document& document, std::size_t body,
                                                       const std::string& a, const std::string& b);
Result<std::unique_ptr<Command>> makeSetPipeCommand(const Document& document, std::size_t body,
                                                    const std::string& a, const std::string& b,
                                                    const PipeEdit& edit);

/// Index of the pipe joining a and b (either order), or -1.
int findPipe(const WaterGraph& graph, const std::string& a, const std::string& b);

}  // namespace plimsoll::editor
