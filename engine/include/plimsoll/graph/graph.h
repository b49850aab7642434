// Water graph (paper section 4, docs/design.md, "Water graph"): the water inside a hollow or
// permeable body as nodes (compartments, each with a capacity and the water it holds) joined by
// pipes. The graph is a description (WaterGraph, `graph.json`) plus a simulation of it
// (WaterGraphSimulation): water enters and leaves through the permeable texels of the surface
// (paper 4.2), moves between nodes downhill (findDischargeNode and Poiseuille's law, or
// diffusion for absorbent materials), and its mass properties (paper eqs. 15-17) are composed
// with the body's (paper 4.4). Every volume is in m^3, every position object space in m.
#pragma once

#include "plimsoll/physics/buoyancy_backend.h"
#include "plimsoll/physics/massprops.h"
#include "plimsoll/geometry/mesh.h"
#include "plimsoll/physics/pose.h"
#include "plimsoll/core/result.h"
#include "plimsoll/physics/water.h"

#include "plimsoll_eval/format.hpp"
#include "plimsoll_eval/graph.hpp"
#include "plimsoll_eval/graph_settings.hpp"

#include <Eigen/Core>

#include <cstdint>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

namespace plimsoll {

struct SurfaceTextures;

inline constexpr int kGraphSchemaVersion = plimsoll_eval::kGraphSchemaVersion;

/// A compartment.
struct GraphNode {
    std::string id;    ///< unique within the graph; pipes name nodes by it
    std::string name;  ///< for people (may be empty)
    Eigen::Vector3d position = Eigen::Vector3d::Zero();  ///< object space, m
    double capacity = 0;                                 ///< m^3, > 0
    double water = 0;  ///< m^3, 0..capacity (the starting amount in a file)
    /// A sealed node takes no water from outside and exchanges none through pipes: its water
    /// stays as it is (a sealed room in a damaged boat).
    bool sealed = false;
    /// Shape of the compartment for the water level and the free-surface model: a box with
    /// these edge lengths (m, object axes) centred at `position`, or, when zero, a sphere of
    /// the node's capacity (the paper's picture of a node). A box's volume should be its
    /// capacity; the level is computed on the box scaled to the capacity.
    Eigen::Vector3d boxSize = Eigen::Vector3d::Zero();

    bool isBox() const { return boxSize.minCoeff() > 0; }
    bool operator==(const GraphNode&) const = default;
};

struct GraphPipe {
    std::string a, b;      ///< node ids
    double radius = 0.01;  ///< m, > 0
    double length = 0;     ///< m; 0 = the distance between the two nodes
    bool open = true;      ///< a closed pipe passes nothing

    bool operator==(const GraphPipe&) const = default;
};

struct WaterGraph {
    std::vector<GraphNode> nodes;
    std::vector<GraphPipe> pipes;

    /// Index of the node with this id, or -1.
    int indexOf(const std::string& id) const;
    double totalCapacity() const;
    double totalWater() const;
    /// The pipe's length: its own, or the distance between its nodes when 0.
    double pipeLength(const GraphPipe& pipe) const;
    bool operator==(const WaterGraph&) const = default;
};

// ---------------------------------------------------------------------------------------
// Validation

/// Classes of problems; stable (tests and scripts match on them, graphProblemCode prints them).
enum class GraphProblemKind {
    Empty,            ///< no nodes                                           (error)
    DuplicateId,      ///< two nodes with one id, or an empty id              (error)
    BadCapacity,      ///< capacity <= 0 or not finite                        (error)
    WaterOutOfRange,  ///< starting water < 0 or > capacity                   (error)
    DanglingPipe,     ///< a pipe names a node that does not exist            (error)
    SelfLoop,         ///< a pipe from a node to itself                       (error)
    BadPipe,          ///< radius <= 0, length < 0, or not finite             (error)
    NodeOutsideMesh,  ///< a node's position lies outside the body's surface  (warning)
    Disconnected,     ///< more than one group of nodes joined by open pipes  (warning)
};

const char* graphProblemCode(GraphProblemKind kind);

struct GraphProblem {
    GraphProblemKind kind;
    bool error = true;    ///< false: a warning
    std::string message;  ///< one line naming the node or pipe, no file name
};

struct GraphReport {
    std::string source;  ///< the graph's file, named in every formatted line
    std::vector<GraphProblem> problems;

    bool has(GraphProblemKind kind) const;
    bool hasErrors() const;
    /// "file: error [code]: message" lines, errors first.
    std::string format() const;
};

/// Checks the graph; with a mesh, also warns about nodes outside it (winding number).
GraphReport validateGraph(const WaterGraph& graph, const TriangleMesh* mesh = nullptr,
                          const std::string& source = {});

/// Generalised winding number of a closed mesh about a point: 1 inside, 0 outside.
double windingNumber(const TriangleMesh& mesh, const Eigen::Vector3d& point);

// ---------------------------------------------------------------------------------------
// Simulation

/// The simulation's settings, its models and their names: the evaluation core's
/// (plimsoll_eval/graph_settings.hpp), one struct for the engine, the step and the runtime.
using InflowModel = plimsoll_eval::InflowModel;
using FlowMode = plimsoll_eval::FlowMode;
using GraphSettings = plimsoll_eval::GraphSettings;
using plimsoll_eval::flowModelName;
using plimsoll_eval::inflowModelName;

/// Water bookkeeping since the simulation started (m^3): entered, left, initial (in the nodes
/// at the start) and moved (between nodes, not a balance term). The step's own type: it lives
/// in the evaluation core with the step.
using GraphTotals = plimsoll_eval::GraphFlowTotals;

/// The node each surface point feeds (paper 4.2: a texel exchanges with its nearest node):
/// the index into graph.nodes of the node closest to `point` (distance to a box node's box,
/// else to its centre; ties go to the nearer centre, then the lower index). -1 for an empty
/// graph. Sealed nodes are candidates too: their texels exchange nothing.
int nearestNode(const WaterGraph& graph, const Eigen::Vector3d& point);

/// The texel-to-node map: nearestNode for every texel entry of `textures` (bundle
/// `texel_nodes`, the editor's feed colours, WaterGraphSimulation's samples).
std::vector<std::int32_t> texelNodeMap(const WaterGraph& graph, const SurfaceTextures& textures);

/// The water graph of one body, stepped with the body's pose.
class WaterGraphSimulation {
public:
    /// `permeability` holds one value per texel entry of `textures` (0..1; empty: the body
    /// is impermeable and water moves only between nodes). The graph must be valid.
    static Result<WaterGraphSimulation> create(const WaterGraph& graph,
                                               const SurfaceTextures& textures,
                                               const std::vector<double>& permeability,
                                               const GraphSettings& settings);

    /// One step of dt seconds with the body at `pose` (object -> world): exchange with the
    /// water outside, then flow between nodes. Returns whether any water moved (the body's
    /// mass properties then need composing again).
    bool step(const Pose& pose, const WaterModel& water, double time, double dt);

    /// The two parts of step(): exchange through the surface (the C++ reference pass, then
    /// applyExchange), flow inside.
    bool exchange(const Pose& pose, const WaterModel& water, double time, double dt);
    bool flowInside(const Eigen::Matrix3d& rotation, double dt);

    /// The exchange split for a compute backend (World): the frame to evaluate (each node's
    /// water surface at `pose`; valid until the next call), then the per-node sums of the pass
    /// applied over dt: limited so every node stays in [0, capacity], a full node passing on
    /// what still pushes in, and booked as entered and left.
    ExchangeFrame exchangeFrame(const Pose& pose, double time);
    bool applyExchange(const Pose& pose, double dt, const ExchangeSums& rates);

    /// The paper's findDischargeNode (Algorithm 1) for node `source` at `rotation`: a node
    /// reachable along open pipes, with room, whose water level is below the source's; the
    /// search passes only through full nodes and never through a node higher than the source
    /// (an energy barrier). Neighbours in random order (the simulation's generator). -1: none.
    int findDischargeNode(int source, const Eigen::Matrix3d& rotation);

    /// Level of node i's water surface: world height above the node's position (m; negative
    /// below it), for the body at `rotation`. An empty node's level is its lowest point.
    double levelOffset(std::size_t node, double water, const Eigen::Matrix3d& rotation) const;

    /// Mass properties of the water (paper eqs. 15-17: point masses rho v_n), object space,
    /// at `rotation` (the free-surface model moves each node's water along gravity).
    MassProperties waterMassProperties(const Eigen::Matrix3d& rotation) const;

    /// The body's mass plus the water's, parallel-axis theorem (paper 4.4).
    MassProperties compose(const MassProperties& body, const Eigen::Matrix3d& rotation) const;

    const WaterGraph& graph() const { return graph_; }
    const GraphSettings& settings() const { return settings_; }
    const GraphTotals& totals() const { return flow_.totals(); }
    /// The permeable texel entries (permeability > 0, feeding a node that is not sealed),
    /// each with its nearest node.
    const std::vector<ExchangeSample>& samples() const { return samples_; }
    double storedWater() const;
    /// |entered + initial - left - stored| / max(entered + initial, tiny): should be ~1e-15.
    double conservationError() const;
    /// Sets a node's water (an editor's or a test's starting state); clamped to 0..capacity.
    void setWater(std::size_t node, double water);

    /// Poiseuille's law: m^3/s through a pipe of radius r (m) and length L (m) under a
    /// pressure drop dp (Pa) with viscosity mu (Pa s): pi dp r^4 / (8 mu L).
    static double poiseuilleRate(double dp, double radius, double viscosity, double length);

private:
    WaterGraphSimulation() = default;
    /// Copies the step's water into graph_ after every step (graph() reports it).
    void syncWater();

    WaterGraph graph_;
    GraphSettings settings_;
    plimsoll_eval::GraphFlow flow_;  ///< the state and the step (graph.hpp)
    std::vector<ExchangeSample> samples_;
    ExchangeSums scratchSums_;
    std::vector<double> scratchSurface_;  ///< per node, reused every step
};

}  // namespace plimsoll
