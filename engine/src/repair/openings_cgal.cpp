// Exact caps for the basins of a closed solid (close_openings.h), with CGAL's corefinement.
#include "close_openings.h"

#include "cgal_mesh.h"

#include "plimsoll/geometry/validate.h"

#include <CGAL/Polygon_mesh_processing/connected_components.h>
#include <CGAL/Polygon_mesh_processing/corefinement.h>
#include <CGAL/Polygon_mesh_processing/measure.h>
#include <CGAL/Polygon_mesh_processing/orientation.h>
#include <CGAL/Side_of_triangle_mesh.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <array>
#include <map>
#include <set>

#include <cmath>
#include <limits>
#include <optional>
#include <sstream>

namespace plimsoll {

using namespace repair_cgal;

namespace {

/// The box [lo, hi] as a closed, outward mesh of twelve triangles.
Mesh boxMesh(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi) {
    std::vector<Point> points;
    for (int k = 0; k < 8; ++k)
        points.emplace_back(k & 1 ? hi.x() : lo.x(), k & 2 ? hi.y() : lo.y(),
                            k & 4 ? hi.z() : lo.z());
    const std::vector<std::vector<std::size_t>> faces{
        {0, 2, 3}, {0, 3, 1}, {4, 5, 7}, {4, 7, 6},   // z = lo, z = hi
        {0, 1, 5}, {0, 5, 4}, {2, 6, 7}, {2, 7, 3},   // y = lo, y = hi
        {0, 4, 6}, {0, 6, 2}, {1, 3, 7}, {1, 7, 5}};  // x = lo, x = hi
    Mesh box;
    PMP::polygon_soup_to_polygon_mesh(points, faces, box);
    if (PMP::volume(box) < 0) PMP::reverse_face_orientations(box);
    return box;
}

bool inside(const Mesh& mesh, const Eigen::Vector3d& p) {
    CGAL::Side_of_triangle_mesh<Mesh, Kernel> side(mesh);
    return side(Point(p.x(), p.y(), p.z())) == CGAL::ON_BOUNDED_SIDE;
}

/// The space that holds water below height h, and the solid cut where it meets it: the part of
/// a box around the solid (reaching past it on every side and below the basin, up to h) that is not
/// in the solid, the piece of it around `seed`, when that piece touches neither the box's sides
/// nor its floor (water there cannot leave below h). The piece and the solid share the points
/// where they meet (one corefinement made both). None when the piece touches (h is above the
/// rim) or when CGAL refuses.
struct Cavity {
    Mesh space;  ///< closed, outward; its level top at h is the cap
    Mesh walls;  ///< the solid, its faces split where the space meets them
    double height = 0;
    double rim = 0, bottom = 0;  ///< Opening::rimHeight, bottomHeight
};

Eigen::Vector3d vec(const Point& p) { return {p.x(), p.y(), p.z()}; }
bool levelUpFace(const Mesh& mesh, Mesh::Face_index f, double h, double tolerance);

/// A point just under the first face of `piece` that is level at h and looks up (its cap), or
/// none when it has no such face (a void the solid encloses).
std::optional<Eigen::Vector3d> underItsCap(const Mesh& piece, double h, double diagonal) {
    for (Mesh::Face_index f : piece.faces()) {
        if (!levelUpFace(piece, f, h, 1e-9 * diagonal)) continue;
        Eigen::Vector3d centre = Eigen::Vector3d::Zero();
        int n = 0;
        for (Mesh::Vertex_index v : CGAL::vertices_around_face(piece.halfedge(f), piece)) {
            centre += vec(piece.point(v));
            ++n;
        }
        return centre / n - Eigen::Vector3d(0, 1e-6 * diagonal, 0);
    }
    return std::nullopt;
}

/// With `within` (the space behind the cap at the rim): the space below a lower cap is that
/// space's part below h, which may be several pools (a hull's bottom divided by its frames);
/// every piece whose cap lies in `within` is taken, joined into one mesh.
std::optional<Cavity> cavityBelow(const Mesh& solid, const Bounds3& bounds, const Basin& basin,
                                  double h, double diagonal, const Mesh* within = nullptr) {
    // Across the whole solid: the space may reach further out at its rim than the basin's cells
    // below the grid's spill height do (a flared hull).
    const double margin = 2 * basin.cellSize;
    Eigen::Vector3d lo = bounds.min - Eigen::Vector3d::Constant(margin);
    lo.y() = basin.boundsMin.y() - margin;
    Eigen::Vector3d hi = bounds.max + Eigen::Vector3d::Constant(margin);
    hi.y() = h;
    Cavity cavity;
    cavity.walls = solid;
    cavity.height = h;
    Mesh box = boxMesh(lo, hi), difference;
    try {
        if (!PMP::corefine_and_compute_difference(box, cavity.walls, difference))
            return std::nullopt;
    } catch (const std::exception&) {
        return std::nullopt;
    }
    std::vector<Mesh> pieces;
    PMP::split_connected_components(difference, pieces);
    const double touch = 1e-9 * diagonal;
    const auto touches = [&](const Mesh& piece) {
        for (Mesh::Vertex_index v : piece.vertices()) {
            const Point& p = piece.point(v);
            if (p.x() <= lo.x() + touch || p.x() >= hi.x() - touch || p.z() <= lo.z() + touch ||
                p.z() >= hi.z() - touch || p.y() <= lo.y() + touch)
                return true;
        }
        return false;
    };
    if (within) {
        CGAL::Side_of_triangle_mesh<Mesh, Kernel> side(*within);
        bool any = false;
        for (Mesh& piece : pieces) {
            const std::optional<Eigen::Vector3d> under = underItsCap(piece, h, diagonal);
            if (!under || side(Point(under->x(), under->y(), under->z())) != CGAL::ON_BOUNDED_SIDE)
                continue;
            if (touches(piece)) return std::nullopt;
            cavity.space.join(piece);
            any = true;
        }
        if (!any) return std::nullopt;
        return cavity;
    }
    for (Mesh& piece : pieces) {
        if (!inside(piece, basin.seed)) continue;
        for (Mesh::Vertex_index v : piece.vertices()) {
            const Point& p = piece.point(v);
            if (p.x() <= lo.x() + touch || p.x() >= hi.x() - touch || p.z() <= lo.z() + touch ||
                p.z() >= hi.z() - touch || p.y() <= lo.y() + touch)
                return std::nullopt;
        }
        cavity.space = std::move(piece);
        return cavity;
    }
    return std::nullopt;
}

/// Whether face f of `mesh` is level at height h (every corner within `tolerance`) and looks up.
bool levelUpFace(const Mesh& mesh, Mesh::Face_index f, double h, double tolerance) {
    std::vector<Eigen::Vector3d> corners;
    for (Mesh::Vertex_index v : CGAL::vertices_around_face(mesh.halfedge(f), mesh))
        corners.push_back(vec(mesh.point(v)));
    for (const Eigen::Vector3d& c : corners)
        if (std::abs(c.y() - h) > tolerance) return false;
    Eigen::Vector3d normal = Eigen::Vector3d::Zero();
    for (std::size_t k = 1; k + 1 < corners.size(); ++k)
        normal += (corners[k] - corners[0]).cross(corners[k + 1] - corners[0]);
    return normal.y() > 0.9 * normal.norm();
}

/// A face by its corners' coordinates, in sorted order: the same face in two meshes made by
/// one corefinement, whatever its orientation.
using FaceKey = std::array<std::array<double, 3>, 3>;

FaceKey faceKey(const Mesh& mesh, Mesh::Face_index f) {
    FaceKey key{};
    std::size_t k = 0;
    for (Mesh::Vertex_index v : CGAL::vertices_around_face(mesh.halfedge(f), mesh)) {
        if (k == 3) return {};
        const Point& p = mesh.point(v);
        key[k++] = {p.x(), p.y(), p.z()};
    }
    std::sort(key.begin(), key.end());
    return key;
}

/// The solid with the space joined, by surgery: the space's faces other than its cap are the
/// solid's own faces where the two meet (one corefinement made both, point for point), so the
/// solid's copies of them are dropped and the cap is put in their place. Exact (no new points),
/// where a boolean union of two solids that share faces is fragile.
TriangleMesh sealedBy(const Cavity& cavity, const std::string& source, double diagonal) {
    TriangleMesh out;
    out.source = source;
    std::map<std::array<double, 3>, std::uint32_t> index;
    const auto vertex = [&](const Point& p) {
        const auto [it, added] = index.try_emplace(
            {p.x(), p.y(), p.z()}, static_cast<std::uint32_t>(out.positions.size()));
        if (added) out.positions.emplace_back(p.x(), p.y(), p.z());
        return it->second;
    };
    const auto addFace = [&](const Mesh& mesh, Mesh::Face_index f) {
        std::vector<std::uint32_t> ring;
        for (Mesh::Vertex_index v : CGAL::vertices_around_face(mesh.halfedge(f), mesh))
            ring.push_back(vertex(mesh.point(v)));
        for (std::size_t k = 1; k + 1 < ring.size(); ++k)
            out.triangles.push_back({ring[0], ring[k], ring[k + 1]});
    };
    std::vector<Mesh::Face_index> cap;
    std::set<FaceKey> shared;
    for (Mesh::Face_index f : cavity.space.faces()) {
        if (levelUpFace(cavity.space, f, cavity.height, 1e-9 * diagonal))
            cap.push_back(f);
        else
            shared.insert(faceKey(cavity.space, f));
    }
    for (Mesh::Face_index f : cavity.walls.faces())
        if (!shared.count(faceKey(cavity.walls, f))) addFace(cavity.walls, f);
    for (Mesh::Face_index f : cap) addFace(cavity.space, f);
    return out;
}

/// A cap the project moved to `h` (RepairSettings::capHeights[index]): below the rim and above
/// the bottom, `cavity` becomes the part of its space below it; else an error naming the
/// opening and both heights.
Status moveCap(Cavity& cavity, const Mesh& current, const Bounds3& bounds, const Basin& basin,
               double diagonal, std::size_t index, double h, const std::string& source) {
    const std::string which = source + ": the cap of opening " + std::to_string(index + 1) +
                              " (caps[" + std::to_string(index) +
                              "].height) at y = " + describeNumber(h) + " m";
    if (!std::isfinite(h) || h > cavity.rim)
        return makeError(
            ErrorKind::schema,
            which + " is above the lowest point of its rim (y = " + describeNumber(cavity.rim) +
                " m), where the water spills before it reaches the cap");
    if (h <= cavity.bottom)
        return makeError(ErrorKind::schema,
                         which + " is not above the bottom of the space behind it (y = " +
                             describeNumber(cavity.bottom) + " m)");
    if (h < cavity.height) {
        const Mesh full = cavity.space;
        std::optional<Cavity> lowered = cavityBelow(current, bounds, basin, h, diagonal, &full);
        if (!lowered)
            return makeError(ErrorKind::schema,
                             which + " cannot be cut there (try a height a little above or below)");
        lowered->rim = cavity.rim;
        lowered->bottom = cavity.bottom;
        cavity = std::move(*lowered);
    }
    return Ok{};
}

}  // namespace

Status closeOpenings(PhysicsSolid& solid, const std::vector<Basin>& basins,
                     const RepairSettings& settings) {
    if (basins.empty()) return Ok{};
    const Bounds3 bounds = computeBounds(solid.mesh);
    const double diagonal = bounds.diagonal();
    const Mesh walls = toCgalMesh(solid.mesh);
    const double before = solid.displacementVolume;  // no openings closed yet

    // One basin after the other, each closed on the solid the ones before it left.
    TriangleMesh sealed = solid.mesh;
    sealed.uvs.clear();
    std::vector<Cavity> found;
    bool surgery = true;
    for (const Basin& basin : basins) {
        const Mesh current = toCgalMesh(sealed);
        const double cell = basin.cellSize;
        // The grid's spill height is within a cell or two of the rim's lowest point. Water
        // finds its way out first at a height where the surface has a vertex (a saddle of the
        // height on the surface), so the rim's lowest point is found exactly by bisection over
        // the vertex heights between a height that holds water and one that spills.
        double holds = std::max(basin.spillHeight - 2 * cell, basin.seed.y() + 0.25 * cell);
        std::optional<Cavity> cavity = cavityBelow(current, bounds, basin, holds, diagonal);
        if (!cavity) continue;
        double spills = basin.spillHeight + 2 * cell;
        while (spills < bounds.max.y() + 2 * cell) {
            std::optional<Cavity> higher = cavityBelow(current, bounds, basin, spills, diagonal);
            if (!higher) break;
            cavity = std::move(higher);
            holds = spills;
            spills += 2 * cell;
        }
        std::vector<double> heights;
        for (Mesh::Vertex_index v : current.vertices())
            if (current.point(v).y() > holds && current.point(v).y() <= spills)
                heights.push_back(current.point(v).y());
        std::sort(heights.begin(), heights.end());
        heights.erase(std::unique(heights.begin(), heights.end()), heights.end());
        // Between two neighbouring vertex heights nothing changes: test in the middle of each
        // gap (never at a vertex, where the cut would be degenerate). Gap 0 starts at `holds`
        // (holds water), the last ends at `spills` (spills); find the first that spills.
        const auto middle = [&](std::size_t gap) {
            const double from = gap == 0 ? holds : heights[gap - 1];
            const double to = gap == heights.size() ? spills : heights[gap];
            return 0.5 * (from + to);
        };
        std::size_t low = 0, high = heights.size();
        while (high - low > 1) {
            const std::size_t mid = (low + high) / 2;
            if (cavityBelow(current, bounds, basin, middle(mid), diagonal))
                low = mid;
            else
                high = mid;
        }
        // The rim's lowest point is the vertex height between the two: the cap goes just under it.
        double rim = spills;
        if (high > 0) {
            rim = heights[high - 1];
            const double at = std::max(middle(low), rim - 1e-4 * cell);
            if (std::optional<Cavity> capped = cavityBelow(current, bounds, basin, at, diagonal))
                cavity = std::move(capped);
        }
        cavity->rim = rim;
        cavity->bottom = std::numeric_limits<double>::max();
        for (Mesh::Vertex_index v : cavity->space.vertices())
            cavity->bottom = std::min(cavity->bottom, cavity->space.point(v).y());
        const std::size_t index = found.size();
        if (index < settings.capHeights.size() && settings.capHeights[index]) {
            if (Status s = moveCap(*cavity, current, bounds, basin, diagonal, index,
                                   *settings.capHeights[index], solid.mesh.source);
                !s)
                return s;
        }
        TriangleMesh joined = sealedBy(*cavity, solid.mesh.source, diagonal);
        if (validateSurface(joined).closedSolid())
            sealed = std::move(joined);
        else
            surgery = false;
        found.push_back(std::move(*cavity));
    }
    if (found.empty()) return Ok{};

    // The cap's faces: level at the cap's height (within the wrap's offset when wrapped).
    double capTolerance = 1e-9 * diagonal;
    double after = exactSolidMassProperties(sealed, 1.0).volume;
    if (!surgery) {
        // The surgery left a seam open (a solid that touches itself along the rim): the solid
        // and the spaces wrapped together instead.
        std::vector<const Mesh*> parts{&walls};
        for (const Cavity& c : found) parts.push_back(&c.space);
        const double offset = settings.wrapOffset * diagonal;
        sealed =
            toTriangleMesh(wrap(parts, settings.wrapAlpha * diagonal, offset), solid.mesh.source);
        if (!validateSurface(sealed).closedSolid())
            return makeError(
                ErrorKind::invalidArgument,
                solid.mesh.source + ": the caps of its openings could not be joined to the solid");
        capTolerance = 3 * offset;
        after = exactSolidMassProperties(sealed, 1.0).volume;
        solid.repairs.push_back(
            {"wrap", 1 + found.size(), after - before,
             "the solid and the spaces behind its caps wrapped together (the caps "
             "could not be joined to it exactly)"});
    }

    std::vector<Opening> openings;
    std::ostringstream heights;
    double behind = 0;
    for (const Cavity& c : found) {
        Opening opening;
        opening.capHeight = c.height;
        opening.rimHeight = c.rim;
        opening.bottomHeight = c.bottom;
        const TriangleMesh space = toTriangleMesh(c.space, solid.mesh.source);
        opening.cavity = exactSolidMassProperties(space, 1.0);
        const Bounds3 box = computeBounds(space);
        opening.boundsMin = box.min;
        opening.boundsMax = box.max;
        CGAL::Side_of_triangle_mesh<Mesh, Kernel> side(c.space);
        for (std::uint32_t t = 0; t < sealed.triangles.size(); ++t) {
            const Triangle& tri = sealed.triangles[t];
            bool level = true;
            for (std::uint32_t v : tri)
                level = level && std::abs(sealed.positions[v].y() - c.height) <= capTolerance;
            const Eigen::Vector3d area = triangleAreaVector(sealed, tri);
            if (!level || !(area.y() > 0.9 * area.norm())) continue;
            const Eigen::Vector3d below =
                (sealed.positions[tri[0]] + sealed.positions[tri[1]] + sealed.positions[tri[2]]) /
                    3.0 -
                Eigen::Vector3d(0, 1e-6 * diagonal + capTolerance, 0);
            if (side(Point(below.x(), below.y(), below.z())) != CGAL::ON_BOUNDED_SIDE) continue;
            opening.capTriangles.push_back(t);
            opening.capArea += area.norm();
        }
        behind += opening.cavity.volume;
        heights << (openings.empty() ? "" : ", ") << describeNumber(c.height);
        openings.push_back(std::move(opening));
    }
    solid.repairs.push_back({"cap", openings.size(), after - before,
                             std::to_string(openings.size()) +
                                 (openings.size() == 1 ? " opening" : " openings") +
                                 " closed by a level cap (y = " + heights.str() +
                                 " m; the rim's lowest point unless moved), " +
                                 describeNumber(behind) + " m^3 behind the caps"});
    solid.mesh = std::move(sealed);
    solid.displacementVolume = after;
    solid.openings = std::move(openings);
    return Ok{};
}

}  // namespace plimsoll
