#include "plimsoll/samples/primitives.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <cassert>
#include <cmath>
#include <numbers>
#include <utility>

namespace plimsoll {

namespace {

constexpr double kGutter = kGeneratedChartGutter;
constexpr double kMargin = kGeneratedChartMargin;

/// cos and sin of 2 pi k / n. The angle is folded into the first octant before calling the
/// library, so mirror-symmetric angles give bit-identical magnitudes and quarter turns give
/// exact 0 and +-1: the meshes come out exactly symmetric and seams weld exactly.
Eigen::Vector2d unitCircle(long k, long n) {
    assert(n > 0);
    k %= n;
    if (k < 0) k += n;
    // Work in units of 1/(8n) turn, so octant boundaries fall on integers.
    long a = 8 * k;
    double signCos = 1.0;
    double signSin = 1.0;
    bool swapped = false;
    if (a > 4 * n) {  // lower half-plane: mirror in the x axis
        a = 8 * n - a;
        signSin = -1.0;
    }
    if (a > 2 * n) {  // left quadrant: mirror in the y axis
        a = 4 * n - a;
        signCos = -1.0;
    }
    if (a > n) {  // above the diagonal: mirror in it, exchanging cos and sin
        a = 2 * n - a;
        swapped = true;
    }
    const double angle = 0.25 * std::numbers::pi * static_cast<double>(a) / static_cast<double>(n);
    double c = std::cos(angle);
    double s = std::sin(angle);
    if (swapped) std::swap(c, s);
    // + 0.0 turns -0 into +0, so no "-0" reaches an OBJ file.
    return {signCos * c + 0.0, signSin * s + 0.0};
}

/// Point at `angle` (as cos, sin) on the circle of radius r about the y axis at height y. The
/// angle runs from +x towards -z, which makes (d/d angle) x (d/d y) point outward.
Eigen::Vector3d onCircle(double r, double y, const Eigen::Vector2d& cs) {
    return {r * cs.x() + 0.0, y, 0.0 - r * cs.y()};
}

std::uint32_t addVertex(TriangleMesh& mesh, const Eigen::Vector3d& p, const Eigen::Vector2d& uv) {
    mesh.positions.push_back(p);
    mesh.uvs.push_back(uv);
    return static_cast<std::uint32_t>(mesh.positions.size() - 1);
}

/// Appends profile points on an arc about (cr, cy) of radius `radius` (m), from `fromDeg` to
/// `toDeg` (whole degrees, counter-clockwise in the (r, y) plane) in `stepDeg` steps.
void appendArc(std::vector<ProfilePoint>& profile, double cr, double cy, double radius, int fromDeg,
               int toDeg, int stepDeg) {
    for (int deg = fromDeg; deg <= toDeg; deg += stepDeg) {
        const Eigen::Vector2d cs = unitCircle(deg, 360);
        profile.push_back({cr + radius * cs.x(), cy + radius * cs.y()});
    }
}

}  // namespace

TriangleMesh makeLathe(const std::vector<ProfilePoint>& profile, int segments) {
    assert(segments >= 3);
    assert(profile.size() >= 3);
    assert(profile.front().radius == 0.0 && profile.back().radius == 0.0);

    TriangleMesh mesh;
    mesh.source = "generated:lathe";

    // v = arc length along the profile / total, so texels are square along the profile at the
    // radius where the circumference equals the profile length.
    const std::size_t n = profile.size();
    std::vector<double> arc(n, 0.0);
    for (std::size_t i = 1; i < n; ++i) {
        arc[i] = arc[i - 1] + std::hypot(profile[i].radius - profile[i - 1].radius,
                                         profile[i].y - profile[i - 1].y);
    }
    const double total = arc.back();
    assert(total > 0.0);

    std::vector<Eigen::Vector2d> circle(segments);
    for (int j = 0; j < segments; ++j) circle[j] = unitCircle(j, segments);
    const double du = 1.0 / segments;

    // rowStart[i]: first vertex of profile point i. Poles have `segments` vertices (one per
    // segment, at its mid-u, so the pole triangles have UV area); rings have segments + 1, the
    // last a copy of the first's position with u = 1 (the seam).
    std::vector<std::uint32_t> rowStart(n);
    for (std::size_t i = 0; i < n; ++i) {
        const ProfilePoint& p = profile[i];
        const double v = arc[i] / total;
        rowStart[i] = static_cast<std::uint32_t>(mesh.positions.size());
        if (i == 0 || i + 1 == n) {
            const Eigen::Vector3d pole(0.0, p.y, 0.0);
            for (int j = 0; j < segments; ++j) addVertex(mesh, pole, {(j + 0.5) * du, v});
        } else {
            assert(p.radius > 0.0);
            for (int j = 0; j < segments; ++j) {
                addVertex(mesh, onCircle(p.radius, p.y, circle[j]), {j * du, v});
            }
            const Eigen::Vector3d seam = mesh.positions[rowStart[i]];
            addVertex(mesh, seam, {1.0, v});
        }
    }

    // u follows the angle and v climbs the profile, and the (u, v) -> 3D map keeps
    // orientation, so triangles counter-clockwise in UV face outward.
    for (std::size_t i = 0; i + 1 < n; ++i) {
        const std::uint32_t lo = rowStart[i];
        const std::uint32_t hi = rowStart[i + 1];
        for (std::uint32_t j = 0; j < static_cast<std::uint32_t>(segments); ++j) {
            if (i == 0) {
                mesh.triangles.push_back({lo + j, hi + j + 1, hi + j});
            } else if (i + 2 == n) {
                mesh.triangles.push_back({lo + j, lo + j + 1, hi + j});
            } else {
                mesh.triangles.push_back({lo + j, lo + j + 1, hi + j + 1});
                mesh.triangles.push_back({lo + j, hi + j + 1, hi + j});
            }
        }
    }
    return mesh;
}

TriangleMesh makeUvSphere(double radius, int segments, int rings) {
    assert(rings >= 2);
    // Semicircle from the south pole to the north pole: latitude pi i / rings - pi / 2, which
    // is (2 i - rings) / (4 rings) of a turn.
    std::vector<ProfilePoint> profile;
    for (int i = 0; i <= rings; ++i) {
        const Eigen::Vector2d cs = unitCircle(2 * i - rings, 4L * rings);
        profile.push_back({radius * cs.x(), radius * cs.y()});
    }
    TriangleMesh mesh = makeLathe(profile, segments);
    mesh.source = "generated:uv-sphere";
    return mesh;
}

TriangleMesh makeCylinder(double radius, double height, int segments) {
    assert(segments >= 3 && radius > 0.0 && height > 0.0);
    const double top = 0.5 * height;
    const double bottom = -top;
    std::vector<Eigen::Vector2d> circle(segments);
    for (int j = 0; j < segments; ++j) circle[j] = unitCircle(j, segments);

    // Layout: the unrolled side (prism perimeter x height) along the top, the two caps
    // (polygons inscribed in a circle of `radius`, in 2r x 2r cells) side by side below it.
    const double perimeter = segments * 2.0 * radius * std::sin(std::numbers::pi / segments);
    const double diameter = 2.0 * radius;
    const double usable = 1.0 - 2.0 * kMargin;
    const double scale = std::min({usable / perimeter, (usable - kGutter) / (2.0 * diameter),
                                   (usable - kGutter) / (height + diameter)});
    const double sideBottom = 1.0 - kMargin - scale * height;
    const double chord = perimeter / segments;

    TriangleMesh mesh;
    mesh.source = "generated:cylinder";

    // Side: two rows of segments + 1 vertices; the last column repeats the first's positions.
    const std::uint32_t lo = static_cast<std::uint32_t>(mesh.positions.size());
    for (int row = 0; row < 2; ++row) {
        const double y = row == 0 ? bottom : top;
        const double v = row == 0 ? sideBottom : 1.0 - kMargin;
        for (int j = 0; j <= segments; ++j) {
            const Eigen::Vector2d uv(kMargin + scale * chord * j, v);
            addVertex(mesh, onCircle(radius, y, circle[j % segments]), uv);
        }
    }
    const std::uint32_t hi = lo + static_cast<std::uint32_t>(segments) + 1;
    for (std::uint32_t j = 0; j < static_cast<std::uint32_t>(segments); ++j) {
        mesh.triangles.push_back({lo + j, lo + j + 1, hi + j + 1});
        mesh.triangles.push_back({lo + j, hi + j + 1, hi + j});
    }

    // Caps: fans around a centre vertex. Seen from outside, the top cap maps (x, -z) to UV and
    // the bottom cap (x, z), so both are counter-clockwise in UV.
    for (int cap = 0; cap < 2; ++cap) {
        const bool isTop = cap == 1;
        const double y = isTop ? top : bottom;
        const Eigen::Vector2d centreUv(kMargin + scale * (radius + cap * diameter) + cap * kGutter,
                                       kMargin + scale * radius);
        const std::uint32_t centre = addVertex(mesh, {0.0, y, 0.0}, centreUv);
        for (int j = 0; j < segments; ++j) {
            const Eigen::Vector2d& cs = circle[j];
            const Eigen::Vector2d offset(cs.x(), isTop ? cs.y() : -cs.y());
            addVertex(mesh, onCircle(radius, y, cs), centreUv + scale * radius * offset);
        }
        for (std::uint32_t j = 0; j < static_cast<std::uint32_t>(segments); ++j) {
            const std::uint32_t a = centre + 1 + j;
            const std::uint32_t b = centre + 1 + (j + 1) % static_cast<std::uint32_t>(segments);
            if (isTop) {
                mesh.triangles.push_back({centre, a, b});
            } else {
                mesh.triangles.push_back({centre, b, a});
            }
        }
    }
    return mesh;
}

TriangleMesh makeBuoy() {
    // Profile (m), bottom to top; y = 0 is the design waterline, a little above mid-can.
    std::vector<ProfilePoint> profile;
    // Ballast bulb: sphere of radius 0.13 m hanging 0.62 m below the waterline.
    appendArc(profile, 0.0, -0.62, 0.13, -90, 60, 10);
    // Stem up to the can.
    profile.push_back({0.05, -0.47});
    profile.push_back({0.05, -0.40});
    // Can: flat bottom, rounded edges (radius 0.04 m), cylindrical body of radius 0.4 m.
    appendArc(profile, 0.36, -0.36, 0.04, -90, 0, 15);
    appendArc(profile, 0.36, 0.28, 0.04, 0, 90, 15);
    // Deck, mast, and the conical top mark (base radius 0.2 m, apex 1.6 m above the keel).
    profile.push_back({0.04, 0.32});
    profile.push_back({0.04, 0.50});
    profile.push_back({0.20, 0.50});
    profile.push_back({0.0, 0.85});
    TriangleMesh mesh = makeLathe(profile, 48);
    mesh.source = "generated:buoy";
    return mesh;
}

double hullHalfBeam(const HullShape& shape, double z) {
    const double half = 0.5 * shape.beam;
    if (z <= 0) return half;
    const double f = z / (0.5 * shape.length);
    return half * (1.0 - 0.8 * f * f);
}

TriangleMesh makeHull(const HullShape& shape) {
    assert(shape.stations >= 2 && shape.sectionSegments >= 4 && shape.sectionSegments % 2 == 0);
    TriangleMesh mesh;
    mesh.source = "generated:hull";
    const int S = shape.stations, M = shape.sectionSegments, K = 4;  // K: deck segments
    const double deck = 0.5 * shape.depth;
    auto zAt = [&](int i) { return -0.5 * shape.length + shape.length * i / S; };
    // Section point j of station i: right deck edge (j = 0), keel (M / 2), left edge (M).
    auto sectionPoint = [&](int i, int j) {
        const double z = zAt(i), w = hullHalfBeam(shape, z);
        const Eigen::Vector2d cs = unitCircle(j, 2 * M);  // angle pi j / M
        const double x = w * (cs.x() < 0 ? -1.0 : 1.0) * std::sqrt(std::abs(cs.x()));
        return Eigen::Vector3d(x, deck - shape.depth * std::sqrt(std::abs(cs.y())), z);
    };
    // Deck point k of station i, from the left edge (k = 0) to the right (K).
    auto deckPoint = [&](int i, int k) {
        const double z = zAt(i), w = hullHalfBeam(shape, z);
        return Eigen::Vector3d(k == 0 ? -w : k == K ? w : w * (2.0 * k / K - 1.0), deck, z);
    };
    struct Chart {
        Eigen::Vector2d lo, hi;
        std::size_t firstTriangle;
    };
    std::vector<Chart> charts;
    auto addVertex = [&](const Eigen::Vector3d& p, const Eigen::Vector2d& uv) {
        mesh.positions.push_back(p);
        mesh.uvs.push_back(uv);
        return static_cast<std::uint32_t>(mesh.positions.size() - 1);
    };
    // Adds a triangle turned so that its normal points along `outward`.
    auto addTriangle = [&](std::uint32_t a, std::uint32_t b, std::uint32_t c,
                           const Eigen::Vector3d& outward) {
        const Eigen::Vector3d n =
            (mesh.positions[b] - mesh.positions[a]).cross(mesh.positions[c] - mesh.positions[a]);
        if (n.dot(outward) < 0) std::swap(b, c);
        mesh.triangles.push_back({a, b, c});
    };
    auto lerp = [](double a, double b, double t) { return a + (b - a) * t; };

    // Bottom and sides: a grid over (section parameter, station).
    charts.push_back({{0.015, 0.015}, {0.455, 0.985}, mesh.triangles.size()});
    {
        const Chart& c = charts.back();
        const auto first = static_cast<std::uint32_t>(mesh.positions.size());
        for (int i = 0; i <= S; ++i) {
            for (int j = 0; j <= M; ++j) {
                addVertex(sectionPoint(i, j), {lerp(c.lo.x(), c.hi.x(), double(j) / M),
                                               lerp(c.lo.y(), c.hi.y(), double(i) / S)});
            }
        }
        for (int i = 0; i < S; ++i) {
            for (int j = 0; j < M; ++j) {
                const std::uint32_t a = first + i * (M + 1) + j, b = a + 1, d = a + (M + 1),
                                    e = d + 1;
                const Eigen::Vector3d mid = 0.25 * (mesh.positions[a] + mesh.positions[b] +
                                                    mesh.positions[d] + mesh.positions[e]);
                const Eigen::Vector3d out(mid.x(), mid.y() - (deck - 0.5 * shape.depth), 0.0);
                addTriangle(a, b, e, out);
                addTriangle(a, e, d, out);
            }
        }
    }
    // Deck.
    charts.push_back({{0.485, 0.015}, {0.70, 0.985}, mesh.triangles.size()});
    {
        const Chart& c = charts.back();
        const auto first = static_cast<std::uint32_t>(mesh.positions.size());
        for (int i = 0; i <= S; ++i) {
            for (int k = 0; k <= K; ++k) {
                addVertex(deckPoint(i, k), {lerp(c.lo.x(), c.hi.x(), double(k) / K),
                                            lerp(c.lo.y(), c.hi.y(), double(i) / S)});
            }
        }
        for (int i = 0; i < S; ++i) {
            for (int k = 0; k < K; ++k) {
                const std::uint32_t a = first + i * (K + 1) + k, b = a + 1, d = a + (K + 1),
                                    e = d + 1;
                addTriangle(a, b, e, Eigen::Vector3d::UnitY());
                addTriangle(a, e, d, Eigen::Vector3d::UnitY());
            }
        }
    }
    // Transom (stern, i = 0) and bow (i = S): the section's ring fanned from a centre point,
    // UVs the (x, y) projection.
    for (const int i : {0, S}) {
        charts.push_back(i == 0 ? Chart{{0.73, 0.015}, {0.985, 0.30}, mesh.triangles.size()}
                                : Chart{{0.73, 0.33}, {0.985, 0.60}, mesh.triangles.size()});
        const Chart& c = charts.back();
        const double w = hullHalfBeam(shape, zAt(i));
        auto uvOf = [&](const Eigen::Vector3d& p) {
            return Eigen::Vector2d(lerp(c.lo.x(), c.hi.x(), (p.x() + w) / (2 * w)),
                                   lerp(c.lo.y(), c.hi.y(), (p.y() + deck) / shape.depth));
        };
        std::vector<Eigen::Vector3d> ring;
        for (int j = 0; j <= M; ++j) ring.push_back(sectionPoint(i, j));
        for (int k = 1; k < K; ++k) ring.push_back(deckPoint(i, k));
        const Eigen::Vector3d centre(0.0, deck - 0.45 * shape.depth, zAt(i));
        const std::uint32_t hub = addVertex(centre, uvOf(centre));
        const auto first = static_cast<std::uint32_t>(mesh.positions.size());
        for (const Eigen::Vector3d& p : ring) addVertex(p, uvOf(p));
        const Eigen::Vector3d out(0, 0, i == 0 ? -1.0 : 1.0);
        const auto n = static_cast<std::uint32_t>(ring.size());
        for (std::uint32_t r = 0; r < n; ++r) addTriangle(hub, first + r, first + (r + 1) % n, out);
    }
    // Every chart counter-clockwise in UV (not mirrored): mirror a chart's u where needed.
    for (std::size_t k = 0; k < charts.size(); ++k) {
        const std::size_t end =
            k + 1 < charts.size() ? charts[k + 1].firstTriangle : mesh.triangles.size();
        if (triangleUvArea(mesh, mesh.triangles[charts[k].firstTriangle]) > 0) continue;
        std::vector<char> flipped(mesh.positions.size(), 0);
        for (std::size_t t = charts[k].firstTriangle; t < end; ++t) {
            for (std::uint32_t v : mesh.triangles[t]) {
                if (flipped[v]) continue;
                flipped[v] = 1;
                mesh.uvs[v].x() = charts[k].lo.x() + charts[k].hi.x() - mesh.uvs[v].x();
            }
        }
    }
    return mesh;
}

TriangleMesh makePlush() {
    // Profile (m), bottom to top: a body of radius 0.3 m, a neck, a head of radius 0.2 m.
    std::vector<ProfilePoint> profile;
    appendArc(profile, 0.0, 0.3, 0.3, -90, 60, 10);
    appendArc(profile, 0.0, 0.72, 0.2, -50, 90, 10);
    profile.front().radius = 0.0;
    profile.back().radius = 0.0;
    TriangleMesh mesh = makeLathe(profile, 48);
    mesh.source = "generated:plush";
    return mesh;
}

}  // namespace plimsoll
