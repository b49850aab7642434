// The physics solid: a watertight, consistently oriented solid built from any artist's surface,
// for the bake and the exact integrals, when the surface is not one closed solid as it is. The
// artist's mesh stays as it is (for painting and display); only the solid is baked. Every change
// is reported by kind, with counts and its effect on the volume, and nothing is repaired
// silently. CGAL's Polygon Mesh Processing and 3D Alpha Wrapping do the geometry; a build
// without CGAL (PLIMSOLL_WITH_CGAL=OFF) reports that repair is unavailable.
#pragma once

#include "plimsoll/core/result.h"
#include "plimsoll/geometry/mesh.h"
#include "plimsoll/geometry/validate.h"
#include "plimsoll/physics/massprops.h"
#include "plimsoll/repair/openings.h"

#include <Eigen/Core>

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace plimsoll {

/// One kind of repair and what it did. `kind` is stable (scripts match on it):
///   "weld"              vertices closer than the tolerance joined (count: vertices removed)
///   "degenerate-faces"  faces without area dropped (count: faces)
///   "duplicate-faces"   faces repeated, in either orientation, dropped (count: faces)
///   "orient"            faces turned to agree with their neighbours and face out (count: faces)
///   "fill-holes"        small holes of nearly closed parts filled (count: holes; the volume
///                       change is those parts' volume)
///   "open-sheets"       open parts (sails, planks, eyes) left out of the volume (count: parts)
///   "open-hulls"        open parts that hold water poured in from above (a hull or container
///                       modelled as one surface without thickness) kept as thin walls, their
///                       wrap, for the openings step to cap (count: parts; wrapped with "wrap")
///   "union"             overlapping closed parts joined (count: parts joined)
///   "wrap"              what stays broken replaced by its alpha wrap (count: parts wrapped)
///   "cap"               openings of open hulls and containers closed at their rims (count:
///                       openings; the volume change is the space behind the caps)
struct Repair {
    std::string kind;
    std::size_t count = 0;
    /// Volume after minus volume before this step (m^3): the volume the step adds (a wrap) or
    /// removes (overlap counted once by a union); 0 where it has no effect on the volume.
    double volumeChange = 0;
    std::string detail;  ///< one line for people
};

/// An opening of an open hull or container, closed by a cap at its rim: the cap is part of the
/// solid (so the sealed body displaces the space behind it), and that space is a compartment
/// the cap lets water into (the scene makes it a node of the body's water graph) unless it is
/// sealed. The cap is level, by default at the height of the lowest point of the rim, so the
/// compartment holds what the container holds before it spills; a cap moved lower
/// (RepairSettings::capHeights) holds less.
struct Opening {
    double capHeight = 0;  ///< object y of the cap's plane, m
    /// Object y of the lowest point of the rim (where water spills; the default cap is just
    /// under it) and of the bottom of the space behind the cap, m: a cap may move between them.
    double rimHeight = 0, bottomHeight = 0;
    /// The space behind the cap at density 1 (mass = volume, m^3; centre; inertia), object space.
    MassProperties cavity;
    /// The box of that space, m.
    Eigen::Vector3d boundsMin = Eigen::Vector3d::Zero(), boundsMax = Eigen::Vector3d::Zero();
    /// The cap's triangles in PhysicsSolid::mesh, and their area (m^2).
    std::vector<std::uint32_t> capTriangles;
    double capArea = 0;
};

/// The space behind the caps of all `openings` (density 1: mass = volume, m^3): what a solid
/// material does not fill (BodyParts::hollow, withoutHollow). No mass without openings.
MassProperties hollowSpace(const std::vector<Opening>& openings);

struct PhysicsSolid {
    /// The solid, closed and outward: no UVs (a generated atlas lays it out).
    TriangleMesh mesh;
    std::vector<Repair> repairs;
    /// Volume of the solid material (m^3).
    double materialVolume = 0;
    /// Volume the sealed body displaces when fully submerged (m^3): the material volume plus
    /// the space behind the caps of its openings.
    double displacementVolume = 0;
    /// The openings closed by caps, largest first.
    std::vector<Opening> openings;
};

/// Whether this build can repair (built with CGAL).
bool repairAvailable();

/// Tuning of the repair; the defaults suit game assets.
struct RepairSettings {
    /// Vertices closer than this share of the bounding-box diagonal are welded.
    double weldTolerance = 1e-6;
    /// Alpha wrap: ball size and offset as shares of the bounding-box diagonal.
    double wrapAlpha = 1.0 / 100.0;
    double wrapOffset = 1.0 / 3000.0;
    /// Whether openings of open hulls and containers (basins that hold water poured in from
    /// above, object y up) are closed by caps; off, the body floods as the surface is.
    bool closeOpenings = true;
    /// Heights of the caps (object y, m) by opening index; unset or past the end: just under
    /// the rim's lowest point. A height above the rim, or at or below the bottom of the space
    /// behind the cap, is refused (the error names the opening and both heights).
    std::vector<std::optional<double>> capHeights;
    BasinSettings basins;
};

/// Builds the physics solid of `surface` (positions only; UVs are ignored). Fails, naming the
/// mesh and saying why, when no solid can be made (no triangles, no area, everything open and
/// nothing to wrap) or when the build has no CGAL.
Result<PhysicsSolid> buildPhysicsSolid(const TriangleMesh& surface,
                                       const RepairSettings& settings = {});

/// The solid to bake for a validated surface: the surface itself, UVs and all, with no repairs,
/// when its report shows a closed solid (UV problems aside; a mesh that needs no repair is
/// baked exactly as it is), else buildPhysicsSolid's; then, with settings.closeOpenings, its
/// openings closed by caps (findBasins, then exact caps: the solid has no UVs then). The
/// volumes are the exact ones. Openings are closed only in builds with CGAL.
Result<PhysicsSolid> physicsSolidFor(const TriangleMesh& surface, const ValidationReport& report,
                                     const RepairSettings& settings = {});

/// "weld 3, orient 2 (...)": the repairs in one line, "none" without any.
std::string describeRepairs(const std::vector<Repair>& repairs);

}  // namespace plimsoll
