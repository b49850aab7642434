// Mesh validation: one small broken mesh per problem kind, a clean cube and torus with no
// problems, and the shared public meshes with their known defects.
#include "plimsoll/io/mesh_io.h"
#include "plimsoll/geometry/validate.h"
#include "geometry/uv_clip.h"

#include <gtest/gtest.h>

#include <array>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <iostream>
#include <limits>
#include <numbers>
#include <optional>
#include <string>
#include <vector>

namespace plimsoll {
namespace test_validate {
namespace {

// ---------------------------------------------------------------------------------------------
// Test meshes

// Each UV chart is a 0.2 x 0.2 square in a 3 x 3 grid of cells 0.33 apart (cell 0 at lower
// left), so charts never touch and shifting one by half its width overlaps exactly one other.
constexpr double kChart = 0.2;
Eigen::Vector2d cellOrigin(int cell) {
    return {0.02 + 0.33 * (cell % 3), 0.02 + 0.33 * (cell / 3)};
}

// Appends a quad (corners counter-clockwise seen from outside) as two triangles with its own
// four vertices, its UV chart filling cell `cell`.
void addQuad(TriangleMesh& mesh, const std::array<Eigen::Vector3d, 4>& corners, int cell) {
    const auto base = static_cast<std::uint32_t>(mesh.positions.size());
    const std::array<Eigen::Vector2d, 4> unit{{{0, 0}, {1, 0}, {1, 1}, {0, 1}}};
    for (int k = 0; k < 4; ++k) {
        mesh.positions.push_back(corners[k]);
        mesh.uvs.push_back(cellOrigin(cell) + kChart * unit[k]);
    }
    mesh.triangles.push_back({base, base + 1, base + 2});
    mesh.triangles.push_back({base, base + 2, base + 3});
}

// Unit cube [0,1]^3: six faces of two triangles, four vertices per face (split at every UV
// seam, like a game asset), face f charted in UV cell f.
TriangleMesh makeTestCube() {
    using V = Eigen::Vector3d;
    TriangleMesh mesh;
    mesh.source = "cube";
    addQuad(mesh, {V(0, 0, 0), V(0, 0, 1), V(0, 1, 1), V(0, 1, 0)}, 0);  // -x
    addQuad(mesh, {V(1, 0, 0), V(1, 1, 0), V(1, 1, 1), V(1, 0, 1)}, 1);  // +x
    addQuad(mesh, {V(0, 0, 0), V(1, 0, 0), V(1, 0, 1), V(0, 0, 1)}, 2);  // -y
    addQuad(mesh, {V(0, 1, 0), V(0, 1, 1), V(1, 1, 1), V(1, 1, 0)}, 3);  // +y
    addQuad(mesh, {V(0, 0, 0), V(0, 1, 0), V(1, 1, 0), V(1, 0, 0)}, 4);  // -z
    addQuad(mesh, {V(0, 0, 1), V(1, 0, 1), V(1, 1, 1), V(0, 1, 1)}, 5);  // +z
    return mesh;
}

// The four vertices of cube face f (see addQuad).
std::uint32_t faceVertex(int face, int corner) {
    return static_cast<std::uint32_t>(4 * face + corner);
}

// Maps face f's UVs by `map` (a function of the UV).
template <class Map>
void mapFaceUvs(TriangleMesh& mesh, int face, Map map) {
    for (int k = 0; k < 4; ++k) {
        Eigen::Vector2d& uv = mesh.uvs[faceVertex(face, k)];
        uv = map(uv);
    }
}

// Mirrors face f's chart left to right inside its cell.
void mirrorFaceUvs(TriangleMesh& mesh, int face) {
    const double left = cellOrigin(face).x();
    mapFaceUvs(mesh, face, [&](Eigen::Vector2d uv) {
        return Eigen::Vector2d(2 * left + kChart - uv.x(), uv.y());
    });
}

// Moves face `face`'s chart from its own cell to cell `cell`, plus `offset`.
void moveFaceUvs(TriangleMesh& mesh, int face, int cell, Eigen::Vector2d offset = {0, 0}) {
    const Eigen::Vector2d shift = cellOrigin(cell) - cellOrigin(face) + offset;
    mapFaceUvs(mesh, face, [&](Eigen::Vector2d uv) { return Eigen::Vector2d(uv + shift); });
}

void flipTriangle(Triangle& t) { std::swap(t[1], t[2]); }

// Torus (major radius 1, minor 0.3) of 2 * nu * nv triangles, one UV chart over the unit
// square; the seam vertices repeat positions with other UVs, so the surface closes only after
// welding.
TriangleMesh makeTestTorus(int nu, int nv) {
    TriangleMesh mesh;
    mesh.source = "torus";
    const double twoPi = 2 * std::numbers::pi;
    for (int j = 0; j <= nv; ++j) {
        for (int i = 0; i <= nu; ++i) {
            // Angles from the wrapped index, so the seam copies get bit-identical positions.
            const double theta = twoPi * (i % nu) / nu, phi = twoPi * (j % nv) / nv;
            const double ring = 1 + 0.3 * std::cos(phi);
            mesh.positions.emplace_back(ring * std::cos(theta), 0.3 * std::sin(phi),
                                        -ring * std::sin(theta));
            mesh.uvs.emplace_back(double(i) / nu, double(j) / nv);
        }
    }
    const auto vertex = [&](int i, int j) { return static_cast<std::uint32_t>(j * (nu + 1) + i); };
    for (int j = 0; j < nv; ++j) {
        for (int i = 0; i < nu; ++i) {
            mesh.triangles.push_back({vertex(i, j), vertex(i + 1, j), vertex(i + 1, j + 1)});
            mesh.triangles.push_back({vertex(i, j), vertex(i + 1, j + 1), vertex(i, j + 1)});
        }
    }
    return mesh;
}

std::vector<ProblemKind> kinds(const ValidationReport& report) {
    std::vector<ProblemKind> out;
    for (const Problem& p : report.problems) out.push_back(p.kind);
    return out;
}

// The report's one problem, which must be of `kind`; a copy, as reports are often temporaries.
Problem only(const ValidationReport& report, ProblemKind kind) {
    EXPECT_EQ(kinds(report), std::vector<ProblemKind>{kind}) << report.format();
    return report.problems.empty() ? Problem{kind, Severity::Warning, 0, 0, "none"}
                                   : report.problems.front();
}

// ---------------------------------------------------------------------------------------------
// Clean meshes

TEST(Validate, CleanCubeHasNoProblems) {
    const ValidationReport report = validateMesh(makeTestCube());
    EXPECT_TRUE(report.problems.empty()) << report.format();
    EXPECT_TRUE(report.closedSolid());
    EXPECT_TRUE(report.usableForTexture());
    EXPECT_EQ(report.format(), "");
}

TEST(Validate, CleanTorusWithUvSeamsHasNoProblems) {
    const ValidationReport report = validateMesh(makeTestTorus(24, 12));
    EXPECT_TRUE(report.problems.empty()) << report.format();
}

TEST(Validate, LargeCleanTorusHasNoProblems) {
    const TriangleMesh torus = makeTestTorus(224, 224);  // 100352 triangles
    const auto start = std::chrono::steady_clock::now();
    const ValidationReport report = validateMesh(torus);
    const std::chrono::duration<double> elapsed = std::chrono::steady_clock::now() - start;
    EXPECT_TRUE(report.problems.empty()) << report.format();
    std::cout << "validated " << torus.triangleCount() << " triangles in " << elapsed.count()
              << " s\n";
}

// ---------------------------------------------------------------------------------------------
// One broken mesh per problem kind

TEST(Validate, EmptyMesh) {
    const ValidationReport report = validateMesh(TriangleMesh{});
    EXPECT_EQ(only(report, ProblemKind::EmptyMesh).severity, Severity::Error);
    EXPECT_FALSE(report.closedSolid());
}

TEST(Validate, NaNPositionStopsGeometricChecks) {
    TriangleMesh cube = makeTestCube();
    cube.positions[0].x() = std::numeric_limits<double>::quiet_NaN();
    const ValidationReport report = validateMesh(cube);
    const Problem problem = only(report, ProblemKind::NonFinite);
    EXPECT_EQ(problem.severity, Severity::Error);
    EXPECT_EQ(problem.count, 2u);  // both triangles of face 0
    EXPECT_FALSE(report.closedSolid());
}

// Found by fuzz/fuzz_validate: an index past the last vertex was read out of bounds.
TEST(Validate, IndexPastTheLastVertexIsAnErrorNotARead) {
    TriangleMesh cube = makeTestCube();
    cube.triangles[3][1] = static_cast<std::uint32_t>(cube.positions.size());
    cube.triangles[7][2] = 4000000000u;
    const ValidationReport report = validateMesh(cube);
    const Problem problem = only(report, ProblemKind::IndexOutOfRange);
    EXPECT_EQ(problem.severity, Severity::Error);
    EXPECT_EQ(problem.count, 2u);
    EXPECT_FALSE(report.closedSolid());
    EXPECT_NE(report.format().find("[index-out-of-range]"), std::string::npos) << report.format();
}

// UVs near the double range: their sums and differences overflow to Inf inside the overlap grid
// and the tile count, where converting them to integers was undefined behaviour (caught by
// the sanitizer build and fuzz/fuzz_validate). The map is still checked and reported.
TEST(Validate, UvsNearTheDoubleRangeAreReportedNotUndefined) {
    TriangleMesh cube = makeTestCube();
    for (std::size_t v = 0; v < cube.uvs.size(); ++v) {
        cube.uvs[v] = (v % 2 ? 1.0 : -1.0) * 1.5e308 * Eigen::Vector2d(v % 3 ? 1.0 : -0.5, 1.0);
    }
    const ValidationReport report = validateMesh(cube);
    EXPECT_TRUE(report.has(ProblemKind::UvOutOfRange)) << report.format();
    EXPECT_TRUE(report.closedSolid()) << report.format();  // the geometry is untouched
}

TEST(Validate, InfiniteUv) {
    TriangleMesh cube = makeTestCube();
    cube.uvs[5].y() = std::numeric_limits<double>::infinity();
    EXPECT_EQ(only(validateMesh(cube), ProblemKind::NonFinite).severity, Severity::Error);
}

TEST(Validate, MissingUvs) {
    TriangleMesh cube = makeTestCube();
    cube.uvs.clear();
    const ValidationReport report = validateMesh(cube);
    EXPECT_EQ(only(report, ProblemKind::MissingUvs).severity, Severity::Error);
    EXPECT_TRUE(report.closedSolid());  // the geometry is still fine
}

TEST(Validate, DegenerateTriangleWithRepeatedIndex) {
    TriangleMesh cube = makeTestCube();
    cube.triangles.push_back({0, 0, 1});
    const Problem problem = only(validateMesh(cube), ProblemKind::DegenerateTriangle);
    EXPECT_EQ(problem.severity, Severity::Warning);
    EXPECT_EQ(problem.count, 1u);
}

TEST(Validate, DegenerateUvTriangle) {
    TriangleMesh cube = makeTestCube();
    const Eigen::Vector2d point = cube.uvs[faceVertex(3, 0)];
    mapFaceUvs(cube, 3, [&](Eigen::Vector2d) { return point; });
    const Problem problem = only(validateMesh(cube), ProblemKind::DegenerateUvTriangle);
    EXPECT_EQ(problem.severity, Severity::Error);
    EXPECT_EQ(problem.count, 2u);
    EXPECT_NEAR(problem.surfaceFraction, 1.0 / 6, 1e-12);
}

TEST(Validate, OpenSurface) {
    TriangleMesh cube = makeTestCube();
    cube.triangles.resize(10);  // drop the +z face
    const ValidationReport report = validateMesh(cube);
    const Problem problem = only(report, ProblemKind::OpenSurface);
    EXPECT_EQ(problem.severity, Severity::Error);
    EXPECT_EQ(problem.count, 4u);
    EXPECT_NEAR(problem.surfaceFraction, 2.0 / 5, 1e-12);  // one triangle per side face
    EXPECT_NE(problem.message.find("4 boundary edges"), std::string::npos);
    EXPECT_FALSE(report.closedSolid());
}

TEST(Validate, NonManifoldEdge) {
    // A second copy of face 0 with its own vertices, charted in a free cell: its four sides and
    // its diagonal are then shared by three and four triangles.
    TriangleMesh cube = makeTestCube();
    addQuad(cube, {cube.positions[0], cube.positions[1], cube.positions[2], cube.positions[3]}, 6);
    const Problem problem = only(validateMesh(cube), ProblemKind::NonManifoldEdge);
    EXPECT_EQ(problem.severity, Severity::Error);
    EXPECT_EQ(problem.count, 5u);
}

TEST(Validate, InconsistentOrientation) {
    // Rewinding face 0 makes its four sides run the same way as its neighbours'; mirroring its
    // chart keeps the UV orientation positive, so only the winding is wrong.
    TriangleMesh cube = makeTestCube();
    flipTriangle(cube.triangles[0]);
    flipTriangle(cube.triangles[1]);
    mirrorFaceUvs(cube, 0);
    const ValidationReport report = validateMesh(cube);
    const Problem problem = only(report, ProblemKind::InconsistentOrientation);
    EXPECT_EQ(problem.severity, Severity::Error);
    EXPECT_EQ(problem.count, 4u);
    EXPECT_FALSE(report.closedSolid());
}

TEST(Validate, InwardNormals) {
    TriangleMesh cube = makeTestCube();
    for (Triangle& t : cube.triangles) flipTriangle(t);  // all UVs flip too: none is mirrored
    const ValidationReport report = validateMesh(cube);
    EXPECT_EQ(only(report, ProblemKind::InwardNormals).severity, Severity::Error);
    EXPECT_FALSE(report.closedSolid());
}

TEST(Validate, InwardNormalsFarFromOrigin) {
    TriangleMesh cube = makeTestCube();
    for (Eigen::Vector3d& p : cube.positions) p += Eigen::Vector3d(1e6, -2e6, 3e6);
    EXPECT_TRUE(validateMesh(cube).problems.empty());
    for (Triangle& t : cube.triangles) flipTriangle(t);
    EXPECT_EQ(kinds(validateMesh(cube)), std::vector{ProblemKind::InwardNormals});
}

TEST(Validate, UvOutOfRange) {
    TriangleMesh cube = makeTestCube();
    for (Eigen::Vector2d& uv : cube.uvs) uv.x() += 0.5;  // columns 1 and 2 pass u = 1
    const ValidationReport report = validateMesh(cube);
    // Offset, not tiled: the map is still less than one unit wide.
    const Problem problem = only(report, ProblemKind::UvOutOfRange);
    EXPECT_EQ(problem.severity, Severity::Warning);
    EXPECT_EQ(problem.count, 8u);
    EXPECT_NE(problem.message.find("remapped"), std::string::npos);
    EXPECT_TRUE(report.usableForTexture());
}

TEST(Validate, UvsOverSeveralTilesAreCountedByTile) {
    // Faces 0-2 stay in tile (0,0); faces 3 and 4 move one tile right, face 5 one tile up.
    TriangleMesh cube = makeTestCube();
    for (int face = 3; face < 6; ++face) {
        const Eigen::Vector2d shift = face == 5 ? Eigen::Vector2d(0, 1) : Eigen::Vector2d(1, 0);
        for (int corner = 0; corner < 4; ++corner) cube.uvs[faceVertex(face, corner)] += shift;
    }
    const ValidationReport report = validateMesh(cube);
    ASSERT_TRUE(report.has(ProblemKind::UvMultipleTiles)) << report.format();
    for (const Problem& p : report.problems) {
        if (p.kind != ProblemKind::UvMultipleTiles) continue;
        EXPECT_EQ(p.severity, Severity::Warning);
        EXPECT_EQ(p.count, 3u);                      // tiles (0,0), (1,0), (0,1)
        EXPECT_NEAR(p.surfaceFraction, 0.5, 1e-12);  // 3 of 6 faces outside tile (0,0)
    }
}

TEST(Validate, UvAreaDistortionIsMeasuredAndReportedAboveTheLimit) {
    TriangleMesh cube = makeTestCube();
    EXPECT_NEAR(validateMesh(cube).uvAreaSpread, 1.0, 1e-9);  // every face alike
    // Face 2's UVs shrunk to a fifth about its chart's corner: 25 times the world area per UV
    // area of the other faces, on a sixth of the surface (far more than the 1% ignored).
    for (int corner = 0; corner < 4; ++corner) {
        Eigen::Vector2d& uv = cube.uvs[faceVertex(2, corner)];
        uv = cellOrigin(2) + (uv - cellOrigin(2)) / 5.0;
    }
    const ValidationReport report = validateMesh(cube);
    EXPECT_NEAR(report.uvAreaSpread, 25.0, 1e-6);
    ASSERT_TRUE(report.has(ProblemKind::UvDistortion)) << report.format();
    for (const Problem& p : report.problems) {
        if (p.kind != ProblemKind::UvDistortion) continue;
        EXPECT_EQ(p.count, 2u);  // face 2's two triangles, 25 times the median
        EXPECT_NEAR(p.surfaceFraction, 1.0 / 6.0, 1e-12);
    }
    EXPECT_TRUE(report.usableForTexture());  // a warning: bakeable, less accurate
}

TEST(Validate, UvOverlapOfTwoWholeCharts) {
    TriangleMesh cube = makeTestCube();
    moveFaceUvs(cube, 5, 0);
    const ValidationReport report = validateMesh(cube);
    const Problem problem = only(report, ProblemKind::UvOverlap);
    EXPECT_EQ(problem.severity, Severity::Error);
    EXPECT_EQ(problem.count, 4u);
    EXPECT_NEAR(problem.surfaceFraction, 4.0 / 12, 1e-12);
    EXPECT_NE(problem.message.find("16.7%"), std::string::npos) << problem.message;  // 1 of 6
    EXPECT_FALSE(report.usableForTexture());
}

TEST(Validate, UvOverlapAreaIsExact) {
    // Half a chart over another: the overlap is half a chart's area, 1/12 of the UV area.
    TriangleMesh cube = makeTestCube();
    moveFaceUvs(cube, 5, 0, {kChart / 2, 0});
    const Problem problem = only(validateMesh(cube), ProblemKind::UvOverlap);
    EXPECT_NE(problem.message.find("8.33%"), std::string::npos) << problem.message;
}

TEST(UvClip, CornersWithinRoundingOfAClipLineKeepTheExactArea) {
    // Found by fuzz_validate: two corners of the clip triangle sit at y = 3e-294 and 3e-289,
    // where the orientation products underflow. The clip then crosses the same line several
    // times and the polygon grows past the six vertices that exact arithmetic allows (seven
    // here; it used to write past its array). Its area must be that of the same clip with
    // those y set to exactly 0, the perturbation being far below rounding, either way round.
    const auto triangle = [](Eigen::Vector2d a, Eigen::Vector2d b, Eigen::Vector2d c) {
        uvclip::UvTriangle t;
        t.corners = {a, b, c};
        if (uvclip::orient(a, b, c) < 0) std::swap(t.corners[1], t.corners[2]);
        for (const auto& p : t.corners) t.box.extend(p);
        return t;
    };
    const uvclip::UvTriangle subject = triangle({-1.0, 1.5}, {-0.5, 0.0}, {0.0, 1.0});
    const uvclip::UvTriangle nearlyFlat =
        triangle({0.5, 2.5}, {-0.5, 3.133809643456172e-294}, {-1.0, 2.821876933372013e-289});
    const uvclip::UvTriangle flat = triangle({0.5, 2.5}, {-0.5, 0.0}, {-1.0, 0.0});
    const double reference = uvclip::intersectionArea(subject, flat);
    EXPECT_GT(reference, 0.25);
    EXPECT_NEAR(uvclip::intersectionArea(subject, nearlyFlat), reference, 1e-12);
    EXPECT_NEAR(uvclip::intersectionArea(nearlyFlat, subject), reference, 1e-12);
    EXPECT_NEAR(uvclip::intersectionArea(flat, subject), reference, 1e-12);
}

TEST(Validate, UvFoldOverInsideAnIslandIsOverlapNotMirroring) {
    // Dragging corner 3 of face 1 across the chart's diagonal flips triangle (0, 2, 3) onto
    // triangle (0, 1, 2).
    TriangleMesh cube = makeTestCube();
    cube.uvs[faceVertex(1, 3)] = cellOrigin(1) + Eigen::Vector2d(0.15, 0.05);
    const Problem problem = only(validateMesh(cube), ProblemKind::UvOverlap);
    EXPECT_EQ(problem.severity, Severity::Error);
    EXPECT_EQ(problem.count, 2u);
}

TEST(Validate, NegligibleUvFoldOverIsAWarning) {
    // Corner 3 of face 1 just past the middle of the chart's diagonal: triangle (0, 2, 3) is a
    // flipped sliver of area 1.4e-8 lying on triangle (0, 1, 2).
    TriangleMesh cube = makeTestCube();
    cube.uvs[faceVertex(1, 3)] = cellOrigin(1) + Eigen::Vector2d(0.1 + 1e-7, 0.1 - 1e-7);
    const ValidationReport report = validateMesh(cube);
    // The sliver also squeezes half a face into no UV area: a distortion warning beside it.
    EXPECT_EQ(kinds(report),
              (std::vector<ProblemKind>{ProblemKind::UvOverlap, ProblemKind::UvDistortion}))
        << report.format();
    const Problem& problem = report.problems.front();
    EXPECT_EQ(problem.severity, Severity::Warning);
    EXPECT_EQ(problem.count, 2u);
    EXPECT_TRUE(report.usableForTexture());
}

TEST(Validate, HeavilyOverlappingMapStopsSearchingEarly) {
    // 3000 triangles (an open strip) that all map to the same UV triangle: 4.5 million
    // overlapping pairs, more than the search visits.
    TriangleMesh strip;
    for (std::uint32_t i = 0; i < 3000; ++i) {
        const auto base = static_cast<std::uint32_t>(strip.positions.size());
        strip.positions.insert(strip.positions.end(),
                               {{double(i), 0, 0}, {i + 1.0, 0, 0}, {double(i), 1, 0}});
        strip.uvs.insert(strip.uvs.end(), {{0, 0}, {1, 0}, {0, 1}});
        strip.triangles.push_back({base, base + 1, base + 2});
    }
    const ValidationReport report = validateMesh(strip);
    ASSERT_TRUE(report.has(ProblemKind::UvOverlap)) << report.format();
    for (const Problem& p : report.problems) {
        if (p.kind != ProblemKind::UvOverlap) continue;
        EXPECT_EQ(p.severity, Severity::Error);
        EXPECT_NE(p.message.find("at least"), std::string::npos) << p.message;
    }
}

TEST(Validate, UvMirroredIsland) {
    TriangleMesh cube = makeTestCube();
    mirrorFaceUvs(cube, 2);
    const ValidationReport report = validateMesh(cube);
    const Problem problem = only(report, ProblemKind::UvMirrored);
    EXPECT_EQ(problem.severity, Severity::Warning);
    EXPECT_EQ(problem.count, 1u);
    EXPECT_NE(problem.message.find("2 triangles"), std::string::npos) << problem.message;
    EXPECT_TRUE(report.usableForTexture());
}

// ---------------------------------------------------------------------------------------------
// Report

// validateSurface: validateMesh's problems less the UV map's, on a mesh with both kinds.
TEST(Validate, SurfaceChecksAreTheMeshChecksWithoutTheUvOnes) {
    TriangleMesh cube = makeTestCube();
    moveFaceUvs(cube, 1, 0);    // two charts on each other: uv-overlap
    cube.triangles.resize(10);  // the +z face gone: open-surface
    const ValidationReport all = validateMesh(cube), surface = validateSurface(cube);
    ASSERT_TRUE(all.has(ProblemKind::UvOverlap));
    std::vector<ProblemKind> expected;
    for (const Problem& p : all.problems) {
        if (!isUvProblem(p.kind)) expected.push_back(p.kind);
    }
    EXPECT_EQ(kinds(surface), expected);
    EXPECT_EQ(expected, std::vector<ProblemKind>{ProblemKind::OpenSurface});
    EXPECT_FALSE(surface.closedSolid());
    EXPECT_TRUE(validateSurface(makeTestCube()).closedSolid());
    EXPECT_TRUE(validateSurface(makeTestCube()).problems.empty());
}

TEST(Validate, FormatPutsErrorsFirst) {
    TriangleMesh cube = makeTestCube();
    for (Eigen::Vector2d& uv : cube.uvs) uv.x() += 0.5;
    cube.triangles.resize(10);
    const std::string text = validateMesh(cube).format();
    EXPECT_EQ(text.rfind("cube: error [open-surface]: 4 boundary edges", 0), 0u) << text;
    EXPECT_NE(text.find("\ncube: warning [uv-out-of-range]: "), std::string::npos) << text;
}

TEST(Validate, ProblemCodesAreKebabCase) {
    EXPECT_STREQ(problemCode(ProblemKind::EmptyMesh), "empty-mesh");
    EXPECT_STREQ(problemCode(ProblemKind::NonFinite), "non-finite");
    EXPECT_STREQ(problemCode(ProblemKind::MissingUvs), "missing-uvs");
    EXPECT_STREQ(problemCode(ProblemKind::DegenerateTriangle), "degenerate-triangle");
    EXPECT_STREQ(problemCode(ProblemKind::DegenerateUvTriangle), "degenerate-uv-triangle");
    EXPECT_STREQ(problemCode(ProblemKind::OpenSurface), "open-surface");
    EXPECT_STREQ(problemCode(ProblemKind::NonManifoldEdge), "non-manifold-edge");
    EXPECT_STREQ(problemCode(ProblemKind::InconsistentOrientation), "inconsistent-orientation");
    EXPECT_STREQ(problemCode(ProblemKind::InwardNormals), "inward-normals");
    EXPECT_STREQ(problemCode(ProblemKind::UvOutOfRange), "uv-out-of-range");
    EXPECT_STREQ(problemCode(ProblemKind::UvOverlap), "uv-overlap");
    EXPECT_STREQ(problemCode(ProblemKind::UvMirrored), "uv-mirrored");
    EXPECT_STREQ(problemCode(ProblemKind::IndexOutOfRange), "index-out-of-range");
}

// ---------------------------------------------------------------------------------------------
// Shared public meshes (skipped when the shared folder is absent)

class SharedMeshValidation : public ::testing::Test {
protected:
    // The report for shared mesh `name`, or nothing when the file is absent.
    std::optional<ValidationReport> validateShared(const std::string& name) {
        const auto path = std::filesystem::path(PLIMSOLL_SHARED_DIR) / "meshes" / name;
        if (!std::filesystem::exists(path)) return std::nullopt;
        Result<TriangleMesh> mesh = loadMesh(path);
        EXPECT_TRUE(mesh.ok()) << mesh.error().message;
        if (!mesh.ok()) return std::nullopt;
        ValidationReport report = validateMesh(*mesh);
        std::cout << report.format();
        return report;
    }
};

TEST_F(SharedMeshValidation, BoatUvsAreOutOfRangeAndOverlap) {
    const auto report = validateShared("boat.obj");
    if (!report) GTEST_SKIP() << "boat.obj not found under " PLIMSOLL_SHARED_DIR;
    EXPECT_EQ(kinds(*report), (std::vector{ProblemKind::UvOutOfRange, ProblemKind::UvOverlap}));
    EXPECT_TRUE(report->closedSolid());
}

TEST_F(SharedMeshValidation, SpotHasNoErrors) {
    const auto report = validateShared("spot.obj");
    if (!report) GTEST_SKIP() << "spot.obj not found under " PLIMSOLL_SHARED_DIR;
    EXPECT_FALSE(report->hasErrors()) << report->format();
    EXPECT_TRUE(report->closedSolid());
}

TEST_F(SharedMeshValidation, TeapotIsOpen) {
    const auto report = validateShared("teapot.obj");
    if (!report) GTEST_SKIP() << "teapot.obj not found under " PLIMSOLL_SHARED_DIR;
    EXPECT_EQ(kinds(*report), (std::vector{ProblemKind::MissingUvs, ProblemKind::OpenSurface}));
    for (const Problem& p : report->problems) {
        if (p.kind == ProblemKind::OpenSurface) {
            EXPECT_EQ(p.count, 160u);
        }
    }
}

TEST_F(SharedMeshValidation, MeshesWithoutUvsAreOtherwiseClean) {
    for (const char* name : {"bunny.obj", "sphere.obj", "torus.obj"}) {
        const auto report = validateShared(name);
        if (!report) GTEST_SKIP() << name << " not found under " PLIMSOLL_SHARED_DIR;
        EXPECT_EQ(kinds(*report), std::vector{ProblemKind::MissingUvs}) << name;
        EXPECT_TRUE(report->closedSolid()) << name;
    }
}

TEST_F(SharedMeshValidation, CubeHasNoProblemsAndBlubOnlyItsSqueezedFin) {
    const auto cube = validateShared("cube.obj");
    if (!cube) GTEST_SKIP() << "cube.obj not found under " PLIMSOLL_SHARED_DIR;
    EXPECT_TRUE(cube->problems.empty()) << cube->format();
    // blub's UVs are bijective, but its tail fin is squeezed into about one texel: a
    // distortion warning, nothing else.
    const auto blub = validateShared("blub_triangulated.obj");
    ASSERT_TRUE(blub);
    EXPECT_EQ(kinds(*blub), std::vector{ProblemKind::UvDistortion}) << blub->format();
    EXPECT_GT(blub->uvAreaSpread, kMaxUvAreaSpread);
    EXPECT_TRUE(blub->usableForTexture());
}

}  // namespace
}  // namespace test_validate
}  // namespace plimsoll
