// The one translation unit of the repair that includes CGAL (physics_solid.h). The steps are
// CGAL's Polygon Mesh Processing on the artist's polygon soup: weld, drop degenerate and
// duplicate faces (repair_polygon_soup), orient (orient_polygon_soup), make a mesh and stitch
// its borders, split it into parts, leave open sheets out, orient each closed part to bound a
// volume, join the closed parts (corefine_and_compute_union) and wrap what stays broken (3D
// Alpha Wrapping). Only the welding within a tolerance is Plimsoll's own: CGAL 5.5 merges
// exactly equal points only.
#include "plimsoll/repair/physics_solid.h"

#include "cgal_mesh.h"

#include "plimsoll/geometry/validate.h"

#include <CGAL/Polygon_mesh_processing/border.h>
#include <CGAL/Polygon_mesh_processing/connected_components.h>
#include <CGAL/Polygon_mesh_processing/corefinement.h>
#include <CGAL/Polygon_mesh_processing/measure.h>
#include <CGAL/Polygon_mesh_processing/orient_polygon_soup.h>
#include <CGAL/Polygon_mesh_processing/orientation.h>
#include <CGAL/Polygon_mesh_processing/polygon_soup_to_polygon_mesh.h>
#include <CGAL/Polygon_mesh_processing/repair_polygon_soup.h>
#include <CGAL/Polygon_mesh_processing/self_intersections.h>
#include <CGAL/Polygon_mesh_processing/stitch_borders.h>
#include <CGAL/Polygon_mesh_processing/triangulate_hole.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <numeric>
#include <sstream>
#include <tuple>

namespace plimsoll {

using namespace repair_cgal;

namespace {

using Polygon = std::vector<std::size_t>;

struct Soup {
    std::vector<Point> points;
    std::vector<Polygon> polygons;
};

/// Joins points closer than `tolerance` (cells of that size, each point compared with the
/// points of its 27 neighbouring cells) and returns how many points moved that were not
/// already exactly equal to the point they joined: UV seams split vertices at equal positions,
/// which is no repair.
std::size_t weld(Soup& soup, double tolerance) {
    std::map<std::array<long long, 3>, std::vector<std::size_t>> cells;
    std::vector<std::size_t> target(soup.points.size());
    std::size_t moved = 0;
    for (std::size_t i = 0; i < soup.points.size(); ++i) {
        const Point& p = soup.points[i];
        const std::array<long long, 3> cell{std::llround(p.x() / tolerance),
                                            std::llround(p.y() / tolerance),
                                            std::llround(p.z() / tolerance)};
        target[i] = i;
        for (long long dx = -1; dx <= 1 && target[i] == i; ++dx)
            for (long long dy = -1; dy <= 1 && target[i] == i; ++dy)
                for (long long dz = -1; dz <= 1 && target[i] == i; ++dz) {
                    auto found = cells.find({cell[0] + dx, cell[1] + dy, cell[2] + dz});
                    if (found == cells.end()) continue;
                    for (std::size_t j : found->second) {
                        if (CGAL::squared_distance(p, soup.points[j]) <= tolerance * tolerance) {
                            target[i] = j;
                            if (p != soup.points[j]) ++moved;
                            break;
                        }
                    }
                }
        if (target[i] == i) cells[cell].push_back(i);
    }
    for (Polygon& polygon : soup.polygons)
        for (std::size_t& v : polygon) v = target[v];
    return moved;
}

/// Faces whose corners are not three distinct points, or whose corners are collinear.
std::size_t dropDegenerate(Soup& soup) {
    const std::size_t before = soup.polygons.size();
    std::erase_if(soup.polygons, [&](const Polygon& f) {
        if (f[0] == f[1] || f[1] == f[2] || f[0] == f[2]) return true;
        return CGAL::collinear(soup.points[f[0]], soup.points[f[1]], soup.points[f[2]]);
    });
    return before - soup.polygons.size();
}

/// The cyclic order of a triangle's corners as positions, smallest index first, to tell
/// whether orienting reversed it (orienting may duplicate points, not move them).
std::array<Point, 3> corners(const Soup& soup, const Polygon& f) {
    std::size_t first = 0;
    for (std::size_t k = 1; k < 3; ++k)
        if (soup.points[f[k]] < soup.points[f[first]]) first = k;
    return {soup.points[f[first]], soup.points[f[(first + 1) % 3]], soup.points[f[(first + 2) % 3]]};
}

double volumeOf(const Mesh& mesh) { return PMP::volume(mesh); }

Mesh soupMesh(const Soup& soup) {
    Mesh mesh;
    PMP::polygon_soup_to_polygon_mesh(soup.points, soup.polygons, mesh);
    return mesh;
}

/// The closed and open parts of the oriented mesh. A closed part that intersects itself or
/// bounds no volume goes to `broken` (it is wrapped).
struct Parts {
    std::vector<Mesh> closed, open, broken;
};

Parts splitParts(const Mesh& whole) {
    std::vector<Mesh> pieces;
    PMP::split_connected_components(whole, pieces);
    Parts parts;
    for (Mesh& piece : pieces) {
        if (!CGAL::is_closed(piece)) {
            parts.open.push_back(std::move(piece));
        } else if (PMP::does_self_intersect(piece) || !PMP::does_bound_a_volume(piece)) {
            parts.broken.push_back(std::move(piece));
        } else {
            parts.closed.push_back(std::move(piece));
        }
    }
    return parts;
}

/// Open parts that are closed solids but for small holes (a hull with a gap where a mast went
/// in): each hole filled (triangulate_hole), the part kept when it then bounds a volume and the
/// patches are at most `maxPatchShare` of its area. A sail's or an open shell's opening is
/// most of its area, and stays open. Returns the holes filled and the volume the parts add.
std::pair<std::size_t, double> fillSmallHoles(Parts& parts, double maxPatchShare) {
    std::size_t filled = 0;
    double added = 0;
    for (auto it = parts.open.begin(); it != parts.open.end();) {
        Mesh part = *it;
        const double area = PMP::area(part);
        std::vector<Mesh::Halfedge_index> borders;
        PMP::extract_boundary_cycles(part, std::back_inserter(borders));
        std::vector<Mesh::Face_index> patch;
        bool ok = true;
        try {
            for (Mesh::Halfedge_index h : borders) PMP::triangulate_hole(part, h, std::back_inserter(patch));
        } catch (const std::exception&) {
            ok = false;
        }
        double patchArea = 0;
        for (Mesh::Face_index f : patch) patchArea += PMP::face_area(f, part);
        ok = ok && CGAL::is_closed(part) && patchArea <= maxPatchShare * area && !PMP::does_self_intersect(part) &&
             PMP::does_bound_a_volume(part);
        if (!ok) {
            ++it;
            continue;
        }
        filled += borders.size();
        added += std::abs(volumeOf(part));
        parts.closed.push_back(std::move(part));
        it = parts.open.erase(it);
    }
    return {filled, added};
}

/// The union of the closed parts, biggest first; a part the union refuses goes to `broken`.
/// Returns the union and how many parts overlapped what was joined before them.
std::pair<Mesh, std::size_t> unite(std::vector<Mesh>& closed, std::vector<Mesh>& broken,
                                   double tolerance) {
    std::sort(closed.begin(), closed.end(),
              [](const Mesh& a, const Mesh& b) { return volumeOf(a) > volumeOf(b); });
    Mesh result;
    std::size_t overlapping = 0;
    bool first = true;
    for (Mesh& part : closed) {
        if (first) {
            result = part;
            first = false;
            continue;
        }
        const double before = volumeOf(result) + volumeOf(part);
        Mesh joined;
        Mesh left = result, right = part;
        bool ok = false;
        try {
            ok = PMP::corefine_and_compute_union(left, right, joined);
        } catch (const std::exception&) {
            ok = false;
        }
        if (!ok) {
            broken.push_back(std::move(part));
            continue;
        }
        if (volumeOf(joined) < before - tolerance) ++overlapping;
        result = std::move(joined);
    }
    return {std::move(result), overlapping};
}

/// The soup of the artist's surface, with exactly equal points joined (UV seams).
Soup soupOf(const TriangleMesh& surface) {
    Soup soup;
    for (const Eigen::Vector3d& p : surface.positions) soup.points.emplace_back(p.x(), p.y(), p.z());
    for (const Triangle& t : surface.triangles) soup.polygons.push_back({t[0], t[1], t[2]});
    return soup;
}

}  // namespace

bool repairAvailable() { return true; }

Result<PhysicsSolid> buildPhysicsSolid(const TriangleMesh& surface, const RepairSettings& settings) {
    const std::string& name = surface.source;
    if (surface.triangles.empty())
        return makeError(ErrorKind::invalidArgument, name + ": no triangles: no solid can be made");
    for (const Eigen::Vector3d& p : surface.positions)
        if (!p.allFinite())
            return makeError(ErrorKind::invalidArgument,
                             name + ": NaN or infinite coordinates: no solid can be made");
    const double diagonal = computeBounds(surface).diagonal();
    if (!(diagonal > 0))
        return makeError(ErrorKind::invalidArgument, name + ": every vertex at one point: no solid can be made");

    PhysicsSolid solid;
    auto report = [&](const char* kind, std::size_t count, double volumeChange, std::string detail) {
        if (count > 0) solid.repairs.push_back({kind, count, volumeChange, std::move(detail)});
    };

    Soup soup = soupOf(surface);
    const std::size_t welded = weld(soup, settings.weldTolerance * diagonal);
    report("weld", welded, 0, std::to_string(welded) + " vertices within " +
                                  describeNumber(settings.weldTolerance * diagonal) + " m joined");
    const std::size_t degenerate = dropDegenerate(soup);
    report("degenerate-faces", degenerate, 0, std::to_string(degenerate) + " faces without area dropped");
    const std::size_t duplicates = PMP::merge_duplicate_polygons_in_polygon_soup(
        soup.points, soup.polygons,
        CGAL::parameters::erase_all_duplicates(false).require_same_orientation(false));
    report("duplicate-faces", duplicates, 0,
           std::to_string(duplicates) + " repeated or back-to-back faces dropped");
    PMP::remove_isolated_points_in_polygon_soup(soup.points, soup.polygons);
    if (soup.polygons.empty())
        return makeError(ErrorKind::invalidArgument, name + ": no face with area: no solid can be made");

    std::vector<std::array<Point, 3>> before;
    for (const Polygon& f : soup.polygons) before.push_back(corners(soup, f));
    PMP::orient_polygon_soup(soup.points, soup.polygons);
    std::size_t flipped = 0;
    for (std::size_t i = 0; i < soup.polygons.size(); ++i)
        if (corners(soup, soup.polygons[i]) != before[i]) ++flipped;

    Mesh whole = soupMesh(soup);
    const std::size_t stitched = PMP::stitch_borders(whole);
    report("stitch", stitched, 0, std::to_string(stitched) + " border edge pairs stitched");
    Parts parts = splitParts(whole);
    const auto [holes, holeVolume] = fillSmallHoles(parts, 0.05);
    report("fill-holes", holes, holeVolume,
           std::to_string(holes) + " small holes of nearly closed parts filled; those parts count in the volume");

    std::size_t outward = 0;
    for (Mesh& part : parts.closed) {
        if (volumeOf(part) < 0) {
            outward += part.number_of_faces();
            PMP::reverse_face_orientations(part);
        }
    }
    report("orient", flipped + outward, 0,
           std::to_string(flipped + outward) + " faces turned to agree with their neighbours and face out");
    if (!parts.open.empty()) {
        std::size_t faces = 0;
        for (const Mesh& part : parts.open) faces += part.number_of_faces();
        report("open-sheets", parts.open.size(), 0,
               std::to_string(parts.open.size()) + " open parts (" + std::to_string(faces) +
                   " faces: sails, planks, eyes, open shells) left out of the volume");
    }

    double partsVolume = 0;
    for (const Mesh& part : parts.closed) partsVolume += volumeOf(part);
    const std::size_t closedCount = parts.closed.size();
    auto [united, overlapping] =
        unite(parts.closed, parts.broken, 1e-9 * diagonal * diagonal * diagonal);
    double volume = closedCount > 0 ? volumeOf(united) : 0;
    report("union", overlapping, volume - partsVolume,
           std::to_string(overlapping) + " overlapping closed parts joined; their overlap, " +
               describeNumber(partsVolume - volume) + " m^3, counts once");

    Mesh result = std::move(united);
    if (!parts.broken.empty() || (closedCount == 0 && !parts.open.empty())) {
        // Nothing closed and sound: the wrap of the broken parts, or of everything when the
        // surface is all open (a thin shell, a single sheet).
        std::vector<const Mesh*> toWrap;
        for (const Mesh& part : parts.broken) toWrap.push_back(&part);
        if (closedCount == 0 && parts.broken.empty())
            for (const Mesh& part : parts.open) toWrap.push_back(&part);
        const std::size_t wrappedParts = toWrap.size();
        Mesh wrapped = wrap(toWrap, settings.wrapAlpha * diagonal, settings.wrapOffset * diagonal);
        const double wrappedVolume = volumeOf(wrapped);
        if (closedCount == 0 || result.is_empty()) {
            result = std::move(wrapped);
        } else {
            Mesh joined, left = result;
            bool ok = false;
            try {
                ok = PMP::corefine_and_compute_union(left, wrapped, joined);
            } catch (const std::exception&) {
                ok = false;
            }
            if (!ok) {
                std::vector<const Mesh*> all{&result};
                for (const Mesh& part : parts.broken) all.push_back(&part);
                joined = wrap(all, settings.wrapAlpha * diagonal, settings.wrapOffset * diagonal);
            }
            result = std::move(joined);
        }
        const double after = volumeOf(result);
        report("wrap", wrappedParts, after - volume,
               std::to_string(wrappedParts) + " parts that are not closed sound solids replaced by their alpha wrap (" +
                   describeNumber(wrappedVolume) + " m^3)");
        volume = after;
    }
    if (result.is_empty() || !(volume > 0))
        return makeError(ErrorKind::invalidArgument,
                         name + ": no closed solid could be made from the surface (every part open or "
                                "without volume): close the hull or give it thickness in the modelling tool");

    solid.mesh = toTriangleMesh(result, name);
    const ValidationReport check = validateSurface(solid.mesh);
    if (!check.closedSolid())
        return makeError(ErrorKind::invalidArgument,
                         name + ": the repaired solid is still not closed and oriented: " + check.format());
    solid.materialVolume = volume;
    solid.displacementVolume = volume;
    return solid;
}

}  // namespace plimsoll
