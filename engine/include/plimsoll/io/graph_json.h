// The water graph's JSON file (`graph.json`, docs/formats.md): reading with every problem
// named by its JSON path, validation on load, and writing.
#pragma once

#include "plimsoll/graph/graph.h"
#include "plimsoll/core/result.h"

#include <filesystem>
#include <string>

namespace plimsoll {

// JSON (`graph.json`, docs/formats.md): {"schema_version": 1, "nodes": [{"id", "name",
// "position": [x, y, z], "capacity", "water", "sealed", "box"}], "pipes": [{"a", "b",
// "radius", "length", "open"}]}

/// Parses graph JSON: every structural problem reported with its JSON path. The result is
/// not yet validated (validateGraph).
Result<WaterGraph> parseGraph(const std::string& text, const std::string& source);
/// Reads, parses and validates: errors refuse the graph (the report's lines); warnings go to
/// `warnings` when given.
Result<WaterGraph> loadGraph(const std::filesystem::path& path, const TriangleMesh* mesh = nullptr,
                             std::string* warnings = nullptr);
std::string graphToJson(const WaterGraph& graph);
Status saveGraph(const WaterGraph& graph, const std::filesystem::path& path);

}  // namespace plimsoll
