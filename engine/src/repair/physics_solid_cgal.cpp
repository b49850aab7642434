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

#include <CGAL/AABB_face_graph_triangle_primitive.h>
#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/Polygon_mesh_processing/border.h>
#include <CGAL/Polygon_mesh_processing/compute_normal.h>
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
#include <memory>
#include <numeric>
#include <optional>
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
    return {soup.points[f[first]], soup.points[f[(first + 1) % 3]],
            soup.points[f[(first + 2) % 3]]};
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
/// in): each hole filled (triangulate_hole), the part kept when the patches are at most
/// `maxPatchShare` of its area: closed when it then bounds a volume and does not intersect
/// itself, else broken (wrapped). A sail's or an open shell's opening is most of its area, and
/// stays open. Returns the holes filled and the volume the parts kept closed add.
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
            for (Mesh::Halfedge_index h : borders)
                PMP::triangulate_hole(part, h, std::back_inserter(patch));
        } catch (const std::exception&) {
            ok = false;
        }
        double patchArea = 0;
        for (Mesh::Face_index f : patch) patchArea += PMP::face_area(f, part);
        ok = ok && CGAL::is_closed(part) && patchArea <= maxPatchShare * area;
        if (!ok) {
            ++it;
            continue;
        }
        if (PMP::does_self_intersect(part) || !PMP::does_bound_a_volume(part)) {
            // Closed but for small holes, yet not sound as it is (a hull whose masts and
            // deckhouse, in the same surface, cut through its deck): a hull all the same, not a
            // sheet; it is wrapped like a closed part that intersects itself.
            parts.broken.push_back(std::move(part));
            it = parts.open.erase(it);
            continue;
        }
        filled += borders.size();
        added += std::abs(volumeOf(part));
        parts.closed.push_back(std::move(part));
        it = parts.open.erase(it);
    }
    return {filled, added};
}

/// Which parts each open part's boundary lies on (within `tolerance`): its `share` of the boundary
/// length that lies on other parts' faces (1 for a piece of a closed solid whose other pieces are
/// elsewhere in the surface, 0 for a sheet whose edges are free) and the other open parts it
/// touches (indices into parts.open).
struct Attachment {
    double share = 0;
    std::vector<std::size_t> openNeighbours;
};

std::vector<Attachment> attachments(const Parts& parts, double tolerance) {
    using Primitive = CGAL::AABB_face_graph_triangle_primitive<Mesh>;
    using Tree = CGAL::AABB_tree<CGAL::AABB_traits<Kernel, Primitive>>;
    std::vector<const Mesh*> all;
    for (const std::vector<Mesh>* group : {&parts.open, &parts.closed, &parts.broken})
        for (const Mesh& part : *group) all.push_back(&part);
    std::vector<std::unique_ptr<Tree>> trees;
    for (const Mesh* part : all) {
        trees.push_back(std::make_unique<Tree>(faces(*part).first, faces(*part).second, *part));
        if (!part->is_empty()) trees.back()->accelerate_distance_queries();
    }
    std::vector<Attachment> out(parts.open.size());
    for (std::size_t i = 0; i < parts.open.size(); ++i) {
        const Mesh& part = parts.open[i];
        double length = 0, attached = 0;
        for (Mesh::Halfedge_index h : part.halfedges()) {
            if (!part.is_border(h)) continue;
            const Point& a = part.point(part.source(h));
            const Point& b = part.point(part.target(h));
            const double l = std::sqrt(CGAL::squared_distance(a, b));
            length += l;
            const Point middle = CGAL::midpoint(a, b);
            bool on = false;
            for (std::size_t j = 0; j < all.size(); ++j) {
                if (j == i || all[j]->is_empty()) continue;
                if (trees[j]->squared_distance(middle) <= tolerance * tolerance) {
                    on = true;
                    if (j < parts.open.size() &&
                        std::find(out[i].openNeighbours.begin(), out[i].openNeighbours.end(), j) ==
                            out[i].openNeighbours.end())
                        out[i].openNeighbours.push_back(j);
                }
            }
            if (on) attached += l;
        }
        out[i].share = length > 0 ? attached / length : 0;
    }
    return out;
}

/// What an open part would enclose with its holes filled (triangulate_hole): the volume
/// (absolute), the patches' area and their outward area vector (the way its openings face).
/// None when the holes cannot be filled into a closed surface.
struct Filled {
    double volume = 0, patchArea = 0;
    Kernel::Vector_3 opening{0, 0, 0};
};

std::optional<Filled> filled(const Mesh& open) {
    Mesh part = open;
    std::vector<Mesh::Halfedge_index> borders;
    PMP::extract_boundary_cycles(part, std::back_inserter(borders));
    std::vector<Mesh::Face_index> patch;
    try {
        for (Mesh::Halfedge_index h : borders)
            PMP::triangulate_hole(part, h, std::back_inserter(patch));
    } catch (const std::exception&) {
        return std::nullopt;
    }
    if (patch.empty() || !CGAL::is_closed(part)) return std::nullopt;
    Filled out;
    out.volume = volumeOf(part);
    for (Mesh::Face_index f : patch) {
        out.opening = out.opening + PMP::compute_face_normal(f, part) * PMP::face_area(f, part);
        out.patchArea += PMP::face_area(f, part);
    }
    // Outward: the filled part's volume is positive when its faces face out.
    if (out.volume < 0) {
        out.volume = -out.volume;
        out.opening = -out.opening;
    }
    return out;
}

/// Sorts out the open parts that are not sheets. A part encloses enough when, its holes filled,
/// it holds at least `minShare` of that volume and `otherVolume` (the closed and broken parts'),
/// so a plank glued on a box, an eye on a head and a flat sheet are not enough.
/// - Pieces of a closed solid: open parts whose edges lie on other parts (90% of their length),
///   joined through the open parts they touch into groups. A group with a piece that encloses
///   enough is a closed solid torn into pieces where merging its points and faces with a solid
///   that coincides with it (a visible hull and a buoyancy hull at one place) left non-manifold
///   edges: its pieces go to `broken`, to be wrapped together into the solid they bound.
/// - Open hulls: open parts with free edges that enclose enough and whose openings face up
///   (their outward area vector within 45 degrees of object y): a hull or container modelled as
///   one surface without thickness, which holds water poured in from above. They are returned,
///   to be kept as thin walls (their wrap) that the openings step caps at the rim. A sail, a flag
///   or a half hull cut at its mirror plane opens sideways and stays a sheet.
std::vector<Mesh> takeHullsAndPieces(Parts& parts, double minShare, double otherVolume,
                                     double tolerance) {
    const std::vector<Attachment> attached = attachments(parts, tolerance);
    const std::size_t n = parts.open.size();
    std::vector<std::optional<Filled>> fill;
    std::vector<bool> enough(n), piece(n);
    std::vector<std::size_t> group(n);
    std::iota(group.begin(), group.end(), std::size_t(0));
    auto find = [&](std::size_t x) {
        while (group[x] != x) x = group[x] = group[group[x]];
        return x;
    };
    for (std::size_t i = 0; i < n; ++i) {
        fill.push_back(filled(parts.open[i]));
        enough[i] = fill[i] && fill[i]->volume >= minShare * (fill[i]->volume + otherVolume);
        piece[i] = attached[i].share >= 0.9;
    }
    for (std::size_t i = 0; i < n; ++i)
        for (std::size_t j : attached[i].openNeighbours)
            if (piece[i] && piece[j]) group[find(i)] = find(j);
    std::vector<bool> solidGroup(n, false);
    for (std::size_t i = 0; i < n; ++i)
        if (piece[i] && enough[i]) solidGroup[find(i)] = true;
    std::vector<Mesh> hulls, open;
    for (std::size_t i = 0; i < n; ++i) {
        Mesh& part = parts.open[i];
        if (piece[i] && solidGroup[find(i)])
            parts.broken.push_back(std::move(part));
        else if (!piece[i] && enough[i] &&
                 fill[i]->opening.y() >= std::sqrt(0.5) * fill[i]->patchArea)
            hulls.push_back(std::move(part));
        else
            open.push_back(std::move(part));
    }
    parts.open = std::move(open);
    return hulls;
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
    for (const Eigen::Vector3d& p : surface.positions)
        soup.points.emplace_back(p.x(), p.y(), p.z());
    for (const Triangle& t : surface.triangles) soup.polygons.push_back({t[0], t[1], t[2]});
    return soup;
}

/// The length of the surface's bounding box diagonal, or why no solid can be made of it.
Result<double> usableDiagonal(const TriangleMesh& surface) {
    const std::string& name = surface.source;
    if (surface.triangles.empty())
        return makeError(ErrorKind::invalidArgument, name + ": no triangles: no solid can be made");
    for (const Eigen::Vector3d& p : surface.positions)
        if (!p.allFinite())
            return makeError(ErrorKind::invalidArgument,
                             name + ": NaN or infinite coordinates: no solid can be made");
    const double diagonal = computeBounds(surface).diagonal();
    if (!(diagonal > 0))
        return makeError(ErrorKind::invalidArgument,
                         name + ": every vertex at one point: no solid can be made");
    return diagonal;
}

/// The surface as a soup of faces with area, welded, without repeats, oriented consistently
/// where it can be; `flipped` counts the faces the orientation turned. `report(kind, count,
/// volume change, detail)` records each repair.
template <class Report>
Result<Soup> cleanSoup(const TriangleMesh& surface, double weldDistance, Report& report,
                       std::size_t& flipped) {
    Soup soup = soupOf(surface);
    const std::size_t welded = weld(soup, weldDistance);
    report(
        "weld", welded, 0,
        std::to_string(welded) + " vertices within " + describeNumber(weldDistance) + " m joined");
    const std::size_t degenerate = dropDegenerate(soup);
    report("degenerate-faces", degenerate, 0,
           std::to_string(degenerate) + " faces without area dropped");
    const std::size_t duplicates = PMP::merge_duplicate_polygons_in_polygon_soup(
        soup.points, soup.polygons,
        CGAL::parameters::erase_all_duplicates(false).require_same_orientation(false));
    report("duplicate-faces", duplicates, 0,
           std::to_string(duplicates) + " repeated or back-to-back faces dropped");
    PMP::remove_isolated_points_in_polygon_soup(soup.points, soup.polygons);
    if (soup.polygons.empty())
        return makeError(ErrorKind::invalidArgument,
                         surface.source + ": no face with area: no solid can be made");
    std::vector<std::array<Point, 3>> before;
    for (const Polygon& f : soup.polygons) before.push_back(corners(soup, f));
    PMP::orient_polygon_soup(soup.points, soup.polygons);
    flipped = 0;
    for (std::size_t i = 0; i < soup.polygons.size(); ++i)
        if (corners(soup, soup.polygons[i]) != before[i]) ++flipped;
    return soup;
}

/// Records the open parts: hulls kept as thin walls, sheets left out.
template <class Report>
void reportOpenParts(const std::vector<Mesh>& hulls, const Parts& parts, Report& report) {
    if (!hulls.empty()) {
        std::size_t faces = 0;
        for (const Mesh& part : hulls) faces += part.number_of_faces();
        report("open-hulls", hulls.size(), 0,
               std::to_string(hulls.size()) + " open parts (" + std::to_string(faces) +
                   " faces) that hold water poured in from above, hulls or containers without "
                   "thickness, kept as thin walls (their wrap)");
    }
    if (!parts.open.empty()) {
        std::size_t faces = 0;
        for (const Mesh& part : parts.open) faces += part.number_of_faces();
        report("open-sheets", parts.open.size(), 0,
               std::to_string(parts.open.size()) + " open parts (" + std::to_string(faces) +
                   " faces: sails, planks, eyes, open shells) left out of the volume");
    }
}

/// Where nothing closed and sound remains (broken parts, open hulls, or a surface all open: a
/// thin shell, a single sheet), `result` (the union of the closed parts) joined with the alpha
/// wrap of those parts; `volume` becomes the result's.
template <class Report>
Mesh addWrapOfWhatIsNotSound(Mesh result, std::size_t closedCount, const Parts& parts,
                             const std::vector<Mesh>& hulls, std::size_t pieces,
                             const RepairSettings& settings, double diagonal, double& volume,
                             Report& report) {
    if (parts.broken.empty() && hulls.empty() && !(closedCount == 0 && !parts.open.empty()))
        return result;
    std::vector<const Mesh*> toWrap;
    for (const Mesh& part : parts.broken) toWrap.push_back(&part);
    for (const Mesh& part : hulls) toWrap.push_back(&part);
    if (closedCount == 0 && parts.broken.empty() && hulls.empty())
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
            for (const Mesh& part : hulls) all.push_back(&part);
            joined = wrap(all, settings.wrapAlpha * diagonal, settings.wrapOffset * diagonal);
        }
        result = std::move(joined);
    }
    const double after = volumeOf(result);
    report(
        "wrap", wrappedParts, after - volume,
        std::to_string(wrappedParts) +
            " parts that are not closed sound solids replaced by their alpha wrap (" +
            describeNumber(wrappedVolume) + " m^3" +
            (pieces > 0 ? ", " + std::to_string(pieces) + " of them open pieces of one closed solid"
                        : "") +
            (hulls.empty() ? "" : ", " + std::to_string(hulls.size()) + " of them open hulls") +
            ")");
    volume = after;
    return result;
}

}  // namespace

bool repairAvailable() { return true; }

Result<PhysicsSolid> buildPhysicsSolid(const TriangleMesh& surface,
                                       const RepairSettings& settings) {
    const std::string& name = surface.source;
    const Result<double> usable = usableDiagonal(surface);
    if (!usable) return usable.error();
    const double diagonal = *usable;

    PhysicsSolid solid;
    auto report = [&](const char* kind, std::size_t count, double volumeChange,
                      std::string detail) {
        if (count > 0) solid.repairs.push_back({kind, count, volumeChange, std::move(detail)});
    };
    std::size_t flipped = 0;
    Result<Soup> soup = cleanSoup(surface, settings.weldTolerance * diagonal, report, flipped);
    if (!soup) return soup.error();

    Mesh whole = soupMesh(*soup);
    const std::size_t stitched = PMP::stitch_borders(whole);
    report("stitch", stitched, 0, std::to_string(stitched) + " border edge pairs stitched");
    Parts parts = splitParts(whole);
    const auto [holes, holeVolume] = fillSmallHoles(parts, 0.05);
    report("fill-holes", holes, holeVolume,
           std::to_string(holes) +
               " small holes of nearly closed parts filled; those parts count in the volume");

    std::size_t outward = 0;
    for (Mesh& part : parts.closed) {
        if (volumeOf(part) < 0) {
            outward += part.number_of_faces();
            PMP::reverse_face_orientations(part);
        }
    }
    report("orient", flipped + outward, 0,
           std::to_string(flipped + outward) +
               " faces turned to agree with their neighbours and face out");
    double otherVolume = 0;
    for (const std::vector<Mesh>* group : {&parts.closed, &parts.broken})
        for (const Mesh& part : *group) otherVolume += std::abs(volumeOf(part));
    const std::size_t brokenBefore = parts.broken.size();
    const std::vector<Mesh> hulls =
        takeHullsAndPieces(parts, settings.basins.minVolumeShare, otherVolume,
                           1e3 * settings.weldTolerance * diagonal);
    const std::size_t pieces = parts.broken.size() - brokenBefore;
    reportOpenParts(hulls, parts, report);

    double partsVolume = 0;
    for (const Mesh& part : parts.closed) partsVolume += volumeOf(part);
    const std::size_t closedCount = parts.closed.size();
    auto [united, overlapping] =
        unite(parts.closed, parts.broken, 1e-9 * diagonal * diagonal * diagonal);
    double volume = closedCount > 0 ? volumeOf(united) : 0;
    report("union", overlapping, volume - partsVolume,
           std::to_string(overlapping) + " overlapping closed parts joined; their overlap, " +
               describeNumber(partsVolume - volume) + " m^3, counts once");
    const Mesh result = addWrapOfWhatIsNotSound(std::move(united), closedCount, parts, hulls,
                                                pieces, settings, diagonal, volume, report);
    if (result.is_empty() || !(volume > 0))
        return makeError(
            ErrorKind::invalidArgument,
            name +
                ": no closed solid could be made from the surface (every part open or "
                "without volume): close the hull or give it thickness in the modelling tool");

    solid.mesh = toTriangleMesh(result, name);
    const ValidationReport check = validateSurface(solid.mesh);
    if (!check.closedSolid())
        return makeError(
            ErrorKind::invalidArgument,
            name + ": the repaired solid is still not closed and oriented: " + check.format());
    solid.materialVolume = volume;
    solid.displacementVolume = volume;
    return solid;
}

}  // namespace plimsoll
