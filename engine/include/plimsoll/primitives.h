// Generated closed meshes with non-overlapping UVs: the sample assets in assets/ and the
// analytic solids the tests hold results against. Deterministic: the same arguments give the
// same mesh, bit for bit.
#pragma once

#include "plimsoll/mesh.h"

#include <Eigen/Core>

#include <vector>

namespace plimsoll {

/// A profile point of a surface of revolution about the y axis: radius r >= 0 (m), height y (m).
struct ProfilePoint {
    double radius;
    double y;
};

/// Surface of revolution of a profile that starts and ends on the axis (radius 0), from the
/// bottom pole to the top pole. UVs: u = angle / 2 pi, v = normalised arc length, one chart
/// covering the unit square with a seam at u = 0|1; poles get one vertex per segment.
TriangleMesh makeLathe(const std::vector<ProfilePoint>& profile, int segments);

/// UV sphere of the given radius (m) centred at the origin.
TriangleMesh makeUvSphere(double radius, int segments, int rings);

/// Axis-aligned box centred at the origin with the given edge lengths (m); six UV charts.
TriangleMesh makeBox(const Eigen::Vector3d& size);

/// Closed cylinder about the y axis centred at the origin (regular prism of `segments` sides).
TriangleMesh makeCylinder(double radius, double height, int segments);

/// A navigation buoy (can body, ballast keel, conical top mark), about 1.6 m tall.
TriangleMesh makeBuoy();

}  // namespace plimsoll
