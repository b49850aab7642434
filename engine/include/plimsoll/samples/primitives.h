// Generated closed meshes with non-overlapping UVs: the sample assets in assets/ and the
// analytic solids the tests hold results against. Deterministic: the same arguments give the
// same mesh, bit for bit. The box is geometry's (box.h), which the water graph uses too.
#pragma once

#include "plimsoll/geometry/box.h"
#include "plimsoll/geometry/mesh.h"

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

/// Closed cylinder about the y axis centred at the origin (regular prism of `segments` sides).
TriangleMesh makeCylinder(double radius, double height, int segments);

/// A navigation buoy (can body, ballast keel, conical top mark), about 1.6 m tall.
TriangleMesh makeBuoy();

/// A boat hull closed by a flat deck, bow towards +z, keel at y = -depth/2, deck at
/// y = +depth/2 (m). Sections are a flat deck over a boxy U (x = w sqrt|cos t|,
/// y = deck - depth sqrt(sin t), t in 0..pi);
/// the half-beam w is beam/2 aft of amidships and narrows to a fifth of it at the bow; the
/// stern is a flat transom. Four UV charts: bottom and sides, deck, transom, bow.
struct HullShape {
    double length = 6.0;       ///< m, along z
    double beam = 2.0;         ///< m, along x (aft of amidships)
    double depth = 1.0;        ///< m, keel to deck
    int stations = 48;         ///< sections along the length
    int sectionSegments = 24;  ///< segments of each section's bottom curve
};
TriangleMesh makeHull(const HullShape& shape = {});

/// The hull's half-beam at z (m): the inner width of a compartment there, for graph authoring.
double hullHalfBeam(const HullShape& shape, double z);

/// A plush toy (a round body with a smaller head, about 0.9 m tall): the absorbent sample of
/// the water graph (paper figure 16).
TriangleMesh makePlush();

}  // namespace plimsoll
