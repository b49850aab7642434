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

#include <cstddef>
#include <string>
#include <vector>

namespace plimsoll {

/// One kind of repair and what it did. `kind` is stable (scripts match on it):
///   "weld"              vertices closer than the tolerance joined (count: vertices removed)
///   "degenerate-faces"  faces without area dropped (count: faces)
///   "duplicate-faces"   faces repeated, in either orientation, dropped (count: faces)
///   "orient"            faces turned to agree with their neighbours and face out (count: faces)
///   "open-sheets"       open parts (sails, planks, eyes) left out of the volume (count: parts)
///   "union"             overlapping closed parts joined (count: parts joined)
///   "wrap"              what stays broken replaced by its alpha wrap (count: parts wrapped)
struct Repair {
    std::string kind;
    std::size_t count = 0;
    /// Volume after minus volume before this step (m^3): the volume the step adds (a wrap) or
    /// removes (overlap counted once by a union); 0 where it has no effect on the volume.
    double volumeChange = 0;
    std::string detail;  ///< one line for people
};

struct PhysicsSolid {
    /// The solid, closed and outward: no UVs (a generated atlas lays it out).
    TriangleMesh mesh;
    std::vector<Repair> repairs;
    /// Volume of the solid material (m^3).
    double materialVolume = 0;
    /// Volume the sealed body displaces when fully submerged (m^3): the material volume for a
    /// solid without compartments.
    double displacementVolume = 0;
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
};

/// Builds the physics solid of `surface` (positions only; UVs are ignored). Fails, naming the
/// mesh and saying why, when no solid can be made (no triangles, no area, everything open and
/// nothing to wrap) or when the build has no CGAL.
Result<PhysicsSolid> buildPhysicsSolid(const TriangleMesh& surface, const RepairSettings& settings = {});

/// The solid to bake for a validated surface: the surface itself, UVs and all, with no repairs,
/// when its report shows a closed solid (UV problems aside; a mesh that needs no repair is
/// baked exactly as it is), else buildPhysicsSolid's. The volumes are the exact ones.
Result<PhysicsSolid> physicsSolidFor(const TriangleMesh& surface, const ValidationReport& report,
                                     const RepairSettings& settings = {});

/// "weld 3, orient 2 (...)": the repairs in one line, "none" without any.
std::string describeRepairs(const std::vector<Repair>& repairs);

}  // namespace plimsoll
