// Automatic water graphs (paper 4.1): the mesh segmented by CGAL's Shape Diameter Function,
// one node per segment, capacities from each segment's share of the enclosed volume.
#pragma once

#include "plimsoll/graph/graph.h"
#include "plimsoll/geometry/mesh.h"
#include "plimsoll/core/result.h"

#include <functional>
#include <vector>

namespace plimsoll {

/// Per-triangle segment of a mesh (Shape Diameter Function + graph cut, CGAL); all CGAL code
/// lives in sdf_segmentation.cpp.
struct MeshSegmentation {
    std::vector<int> triangleSegment;  ///< per triangle of the input mesh, 0..segmentCount-1
    int segmentCount = 0;
    double sdfSeconds = 0;  ///< time spent in CGAL
};

/// Segments a closed mesh into at most `clusters` SDF clusters, then connected segments;
/// progress gets 0..1 at the stages.
Result<MeshSegmentation> segmentMeshSdf(const TriangleMesh& mesh, int clusters,
                                        const std::function<void(double)>& progress = {});

/// False in a build configured without CGAL (PLIMSOLL_WITH_CGAL=OFF): segmentMeshSdf and
/// buildAutomaticGraph then fail with ErrorKind::unsupported, saying so.
bool meshSegmentationAvailable();

struct AutoGraphSettings {
    int segments = 0;  ///< k nodes; 0 = chosen from the mesh (defaultSegmentCount)
    /// Shell thickness (m): the capacities sum to the enclosed volume minus the shell's own
    /// volume (area x thickness). 0 = the whole enclosed volume.
    double shellThickness = 0;
    int volumeSamples = 48;  ///< grid cells along the longest side for the volume shares
    std::function<void(double)> progress;
};

/// k for a mesh when the user gives none: 2 + one per doubling of triangles above 1000, at
/// most 8.
int defaultSegmentCount(const TriangleMesh& mesh);

/// What automatic construction made, beside the graph.
struct AutoGraphReport {
    MeshSegmentation segmentation;  ///< after merging to k segments
    double enclosedVolume = 0;      ///< m^3 (exact, divergence theorem)
    /// The interior grid points' volume (cells x cell volume), m^3: how well the grid that
    /// shares the volume out covers it (an independent check of the inside test).
    double sampledVolume = 0;
    double totalSeconds = 0;
};

/// Paper 4.1: segments (k of them: SDF segments merged, smallest into its longest-bordering
/// neighbour, until k remain; where the SDF gives fewer, the largest cut in two across its
/// longest axis until k), one node per segment at the least-squares sphere centre of its
/// vertices (the centroid of its share of the volume when that centre lies outside the
/// mesh), capacities from each segment's share of the enclosed volume (interior grid points
/// go to the segment of their nearest vertex; the shares are scaled to sum to the enclosed
/// volume), pipes between adjacent segments with radius = shared boundary length / 2 pi.
Result<WaterGraph> buildAutomaticGraph(const TriangleMesh& mesh, const AutoGraphSettings& settings,
                                       AutoGraphReport* report = nullptr);

}  // namespace plimsoll
