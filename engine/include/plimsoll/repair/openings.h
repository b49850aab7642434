// Openings of open hulls and containers: the spaces outside a closed solid that hold water
// poured in from above (the inside of a dinghy, a bucket, a barrel's recessed lid), found the
// way hydrology fills the depressions of a terrain (Priority-Flood; Barnes, Lehman and Mulla,
// Computers & Geosciences 62, 2014), here on a voxel grid of the solid instead of a height map.
// Object space, y up (Plimsoll's axes): a basin is water that cannot drain downhill to the
// outside, and its water stands at its spill height, the lowest point of its rim.
#pragma once

#include "plimsoll/geometry/mesh.h"

#include <Eigen/Core>

#include <cstddef>
#include <vector>

namespace plimsoll {

/// A basin as the voxel grid sees it: its height and volume are the grid's (within about a cell);
/// the physics solid's exact cap (physics_solid.h) starts from it.
struct Basin {
    /// Height of the lowest point of its rim, object y, m (within about a cell).
    double spillHeight = 0;
    /// Volume of water it holds, m^3 (its cells).
    double volume = 0;
    /// A point well inside it, below spillHeight - 2 cells.
    Eigen::Vector3d seed = Eigen::Vector3d::Zero();
    /// Box of its cells, m.
    Eigen::Vector3d boundsMin = Eigen::Vector3d::Zero(), boundsMax = Eigen::Vector3d::Zero();
    double cellSize = 0;  ///< m
};

struct BasinSettings {
    /// Cells along the longest side of the solid's box (the grid has at most maxCells cells).
    int resolution = 128;
    std::size_t maxCells = 4'000'000;
    /// A basin counts when it holds at least this share of the solid's own volume: a crate's
    /// gaps between planks and a barrel's shallow lid are not containers.
    double minVolumeShare = 0.05;
    /// ... and is at least this many cells deep.
    int minDepthCells = 4;
};

/// The basins of a closed, outward-oriented solid of volume `solidVolume` (m^3), largest
/// first (equal volumes by their seeds' x, then z, then y: an order of the mesh alone). Walls are
/// the cells inside the solid and every cell its surface passes through, so thin walls hold water
/// too. Enclosed voids (not reachable from outside) are not basins.
std::vector<Basin> findBasins(const TriangleMesh& solid, double solidVolume,
                              const BasinSettings& settings = {});

}  // namespace plimsoll
