// TriangleMesh: the engine's one mesh representation, as imported (see mesh_io.h) or generated
// (see primitives.h). Vertices are split at UV seams, as in every game asset: two vertices may
// share a position and differ in UV. Topology checks weld them back by position.
#pragma once

#include <Eigen/Core>

#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace plimsoll {

using Triangle = std::array<std::uint32_t, 3>;

struct TriangleMesh {
    /// Where the mesh came from (file path or generator name); every message about it names it.
    std::string source;
    /// Vertex positions, object space, mesh units (metres for Plimsoll's own assets).
    std::vector<Eigen::Vector3d> positions;
    /// Texture coordinates, one per vertex, or empty when the mesh has none. u right, v up;
    /// the unit square [0,1]^2 is the texture.
    std::vector<Eigen::Vector2d> uvs;
    /// Vertex indices, counter-clockwise seen from outside (right-hand rule gives the outward
    /// normal).
    std::vector<Triangle> triangles;

    bool hasUvs() const { return !uvs.empty() && uvs.size() == positions.size(); }
    std::size_t vertexCount() const { return positions.size(); }
    std::size_t triangleCount() const { return triangles.size(); }
};

/// For every vertex, the index of the first vertex with exactly the same position: vertices
/// split at UV (or normal) seams get one id, so edges can be matched for topology checks.
std::vector<std::uint32_t> weldByPosition(const TriangleMesh& mesh);

/// Axis-aligned bounds of the positions; min > max for an empty mesh.
struct Bounds3 {
    Eigen::Vector3d min{Eigen::Vector3d::Constant(1e300)};
    Eigen::Vector3d max{Eigen::Vector3d::Constant(-1e300)};
    Eigen::Vector3d center() const { return 0.5 * (min + max); }
    double diagonal() const { return (max - min).norm(); }
};
Bounds3 computeBounds(const TriangleMesh& mesh);

/// Area vector of triangle t: half the cross product of its edges (m^2, outward normal).
Eigen::Vector3d triangleAreaVector(const TriangleMesh& mesh, const Triangle& t);

/// Signed UV area of triangle t (positive = counter-clockwise in UV, i.e. not mirrored).
double triangleUvArea(const TriangleMesh& mesh, const Triangle& t);

}  // namespace plimsoll
