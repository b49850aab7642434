// Mesh validation: everything that would make a texture-space result wrong (errors) or is
// merely worth knowing (warnings), with counts and the share of the surface affected.
#pragma once

#include "plimsoll/geometry/mesh.h"

#include <cstddef>
#include <string>
#include <vector>

namespace plimsoll {

enum class Severity { Warning, Error };

/// One class of problem. Stable: tests and scripts match on these, and problemCode() gives the
/// kebab-case name printed in reports.
enum class ProblemKind {
    EmptyMesh,                ///< no triangles                                        (error)
    NonFinite,                ///< NaN or Inf in a position or UV                      (error)
    MissingUvs,               ///< no texture coordinates                              (error)
    DegenerateTriangle,       ///< zero 3D area: contributes nothing                   (warning)
    DegenerateUvTriangle,     ///< positive 3D area but zero UV area: area is lost     (error)
    OpenSurface,              ///< boundary edges (used by one face), after welding    (error)
    NonManifoldEdge,          ///< edges used by more than two faces, after welding    (error)
    InconsistentOrientation,  ///< an edge used twice in the same direction            (error)
    InwardNormals,            ///< closed, consistent, but negative signed volume      (error)
    UvOutOfRange,             ///< UVs outside [0,1]: remapped into the texture        (warning)
    UvOverlap,                ///< UV triangles overlap: the map is not bijective      (error)
    UvMirrored,               ///< UV islands with flipped orientation (no overlap)    (warning)
    UvMultipleTiles,          ///< UVs spread over several unit tiles (UDIM-like)       (warning)
    UvDistortion,     ///< world area per UV area varies more than kMaxUvAreaSpread (warning)
    IndexOutOfRange,  ///< a triangle names a vertex the mesh does not have    (error)
};

/// Texel world-area spread above this is reported: a texel then stands for up to this many
/// times the surface of another, and accuracy follows the coarsest texels.
inline constexpr double kMaxUvAreaSpread = 4.0;

const char* problemCode(ProblemKind kind);

/// Problems of the UV map only (they matter to the bake, not to the exact mesh integrals).
bool isUvProblem(ProblemKind kind);

struct Problem {
    ProblemKind kind;
    Severity severity;
    std::size_t count = 0;       ///< how many elements (triangles, edges, islands) are affected
    double surfaceFraction = 0;  ///< share of the 3D surface area affected, 0..1 (0 if n/a)
    std::string message;         ///< one line, no file name (the report adds it)
};

struct ValidationReport {
    std::string source;  ///< the mesh's file, named in every formatted line
    std::vector<Problem> problems;
    /// UV-area distortion of the mesh's own UVs: world area per UV area, 99th over 1st
    /// percentile over the surface (area-weighted, so 1% of the surface at either extreme is
    /// ignored). 1 for a map without distortion; 0 when there are no usable UVs.
    double uvAreaSpread = 0;
    /// Share of the surface (area) whose UVs are mirrored relative to the majority orientation.
    double mirroredSurfaceFraction = 0;

    bool has(ProblemKind kind) const;
    bool hasErrors() const;
    /// Closed, consistently oriented, finite: exact mass properties are meaningful.
    bool closedSolid() const;
    /// No errors at all: the mesh's own UVs can be baked.
    bool usableForTexture() const { return !hasErrors(); }
    /// "file: error [code]: message" lines, errors first.
    std::string format() const;
};

ValidationReport validateMesh(const TriangleMesh& mesh);

/// validateMesh without the checks of the UV map: enough to know whether the mesh is a closed
/// solid (ValidationReport::closedSolid), e.g. to draw only its front faces.
ValidationReport validateSurface(const TriangleMesh& mesh);

}  // namespace plimsoll
