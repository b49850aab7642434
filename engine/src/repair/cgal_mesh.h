// The CGAL types the repair's translation units share, the conversions between CGAL's
// Surface_mesh and Plimsoll's TriangleMesh, the alpha wrap, and how repair details print numbers.
// Included only by the repair's CGAL files.
#pragma once

#include "plimsoll/geometry/mesh.h"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/polygon_soup_to_polygon_mesh.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/alpha_wrap_3.h>

#include <cstdint>
#include <array>
#include <map>
#include <sstream>
#include <string>
#include <vector>

namespace plimsoll::repair_cgal {

namespace PMP = CGAL::Polygon_mesh_processing;
using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = Kernel::Point_3;
using Mesh = CGAL::Surface_mesh<Point>;

/// A volume or length in a repair's detail: four significant digits.
inline std::string describeNumber(double value) {
    std::ostringstream text;
    text.precision(4);
    text << value;
    return text.str();
}

/// The mesh's faces as triangles (a polygon fanned from its first corner), no UVs.
inline TriangleMesh toTriangleMesh(const Mesh& mesh, const std::string& source) {
    TriangleMesh out;
    out.source = source;
    std::map<Mesh::Vertex_index, std::uint32_t> of;
    for (Mesh::Vertex_index v : mesh.vertices()) {
        const Point& p = mesh.point(v);
        of[v] = static_cast<std::uint32_t>(out.positions.size());
        out.positions.emplace_back(p.x(), p.y(), p.z());
    }
    for (Mesh::Face_index f : mesh.faces()) {
        std::vector<std::uint32_t> ring;
        for (Mesh::Vertex_index v : CGAL::vertices_around_face(mesh.halfedge(f), mesh))
            ring.push_back(of[v]);
        for (std::size_t k = 1; k + 1 < ring.size(); ++k)
            out.triangles.push_back({ring[0], ring[k], ring[k + 1]});
    }
    return out;
}

/// A closed TriangleMesh as a Surface_mesh: vertices at one position (split at UV seams) are
/// one vertex.
inline Mesh toCgalMesh(const TriangleMesh& mesh) {
    const std::vector<std::uint32_t> id = weldByPosition(mesh);
    std::vector<Point> points;
    std::vector<std::size_t> index(mesh.positions.size());
    for (std::size_t v = 0; v < mesh.positions.size(); ++v) {
        if (id[v] == v) {
            index[v] = points.size();
            points.emplace_back(mesh.positions[v].x(), mesh.positions[v].y(),
                                mesh.positions[v].z());
        }
    }
    std::vector<std::vector<std::size_t>> polygons;
    polygons.reserve(mesh.triangles.size());
    for (const Triangle& t : mesh.triangles)
        polygons.push_back({index[id[t[0]]], index[id[t[1]]], index[id[t[2]]]});
    Mesh out;
    PMP::polygon_soup_to_polygon_mesh(points, polygons, out);
    return out;
}

/// The 3D alpha wrap (CGAL::alpha_wrap_3) of the meshes' triangles together: a closed, outward
/// solid around them, with balls of size `alpha` kept out and the surface `offset` outside them.
inline Mesh wrap(const std::vector<const Mesh*>& meshes, double alpha, double offset) {
    std::vector<Point> points;
    std::vector<std::array<std::size_t, 3>> triangles;
    for (const Mesh* mesh : meshes) {
        std::map<Mesh::Vertex_index, std::size_t> of;
        for (Mesh::Vertex_index v : mesh->vertices()) {
            of[v] = points.size();
            points.push_back(mesh->point(v));
        }
        for (Mesh::Face_index f : mesh->faces()) {
            std::vector<std::size_t> ring;
            for (Mesh::Vertex_index v : CGAL::vertices_around_face(mesh->halfedge(f), *mesh))
                ring.push_back(of[v]);
            for (std::size_t k = 1; k + 1 < ring.size(); ++k)
                triangles.push_back({ring[0], ring[k], ring[k + 1]});
        }
    }
    Mesh wrapped;
    CGAL::alpha_wrap_3(points, triangles, alpha, offset, wrapped);
    return wrapped;
}

}  // namespace plimsoll::repair_cgal
