// Small water graphs the graph and graph-JSON tests build: a node, a pipe, and three nodes
// stacked in a column with water in the top two.
#pragma once

#include "plimsoll/graph/graph.h"

#include <Eigen/Core>

#include <string>

namespace plimsoll::test {

inline GraphNode node(const std::string& id, const Eigen::Vector3d& position, double capacity,
                      double water = 0) {
    GraphNode n;
    n.id = id;
    n.name = id;
    n.position = position;
    n.capacity = capacity;
    n.water = water;
    return n;
}

inline GraphPipe pipe(const std::string& a, const std::string& b, double radius,
                      double length = 0) {
    GraphPipe p;
    p.a = a;
    p.b = b;
    p.radius = radius;
    p.length = length;
    return p;
}

inline WaterGraph threeNodes() {
    WaterGraph g;
    g.nodes = {node("a", {0, 4, 0}, 1.0, 0.5), node("b", {0, 2, 0}, 1.0, 1.0),
               node("c", {0, 0, 0}, 1.0, 0.0)};
    g.pipes = {pipe("a", "b", 0.05), pipe("b", "c", 0.05)};
    return g;
}

}  // namespace plimsoll::test
