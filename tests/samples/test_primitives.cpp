// Generated meshes: closed, outward, non-overlapping UVs with gutters, exact volumes, and the
// committed assets/ are byte for byte what the generator writes.
#include "plimsoll/io/mesh_io.h"
#include "plimsoll/samples/primitives.h"

#include "test_support.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <numbers>
#include <numbers>
#include <numeric>
#include <set>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

namespace plimsoll {
namespace test_primitives {
namespace {

namespace fs = std::filesystem;

constexpr double kPi = std::numbers::pi;

double signedVolume(const TriangleMesh& mesh) {
    double sum = 0.0;
    for (const Triangle& t : mesh.triangles) {
        sum += mesh.positions[t[0]].dot(mesh.positions[t[1]].cross(mesh.positions[t[2]]));
    }
    return sum / 6.0;
}

/// Volume of the polyhedron makeLathe builds from `profile`: every slice is a regular polygon
/// of circumradius r(y), linear in y between profile points, and each quad is planar.
double latheVolume(const std::vector<ProfilePoint>& profile, int segments) {
    double integral = 0.0;  // integral of r^2 dy (m^3)
    for (std::size_t i = 1; i < profile.size(); ++i) {
        const double r0 = profile[i - 1].radius;
        const double r1 = profile[i].radius;
        integral += (profile[i].y - profile[i - 1].y) * (r0 * r0 + r0 * r1 + r1 * r1) / 3.0;
    }
    return 0.5 * segments * std::sin(2.0 * kPi / segments) * integral;
}

std::vector<ProfilePoint> sphereProfile(double radius, int rings) {
    std::vector<ProfilePoint> profile;
    for (int i = 0; i <= rings; ++i) {
        const double latitude = kPi * i / rings - 0.5 * kPi;
        profile.push_back({i == 0 || i == rings ? 0.0 : radius * std::cos(latitude),
                           radius * std::sin(latitude)});
    }
    return profile;
}

/// Every undirected edge of the position-welded mesh is used exactly twice, once each way.
void expectClosedAndOriented(const TriangleMesh& mesh) {
    const std::vector<std::uint32_t> id = weldByPosition(mesh);
    std::map<std::pair<std::uint32_t, std::uint32_t>, int> directed;
    for (const Triangle& t : mesh.triangles) {
        for (int k = 0; k < 3; ++k) ++directed[{id[t[k]], id[t[(k + 1) % 3]]}];
    }
    int bad = 0;
    for (const auto& [edge, count] : directed) {
        const auto reverse = directed.find({edge.second, edge.first});
        if (count != 1 || reverse == directed.end() || reverse->second != 1) ++bad;
    }
    EXPECT_EQ(bad, 0) << mesh.source << ": edges not used exactly once in each direction";
}

void expectNoDegenerateTriangles(const TriangleMesh& mesh) {
    const double scale = computeBounds(mesh).diagonal();
    int degenerate = 0;
    for (const Triangle& t : mesh.triangles) {
        if (triangleAreaVector(mesh, t).norm() <= 1e-9 * scale * scale) ++degenerate;
    }
    EXPECT_EQ(degenerate, 0) << mesh.source;
}

void expectUvsInUnitSquareAndPositive(const TriangleMesh& mesh) {
    ASSERT_TRUE(mesh.hasUvs()) << mesh.source;
    for (const Eigen::Vector2d& uv : mesh.uvs) {
        ASSERT_TRUE(uv.x() >= 0.0 && uv.x() <= 1.0 && uv.y() >= 0.0 && uv.y() <= 1.0)
            << mesh.source << ": uv " << uv.transpose();
    }
    int nonPositive = 0;
    for (const Triangle& t : mesh.triangles) {
        if (!(triangleUvArea(mesh, t) > 1e-9)) ++nonPositive;
    }
    EXPECT_EQ(nonPositive, 0) << mesh.source << ": UV triangles not counter-clockwise";
}

using Polygon = std::vector<Eigen::Vector2d>;

double polygonArea(const Polygon& p) {
    double twice = 0.0;
    for (std::size_t i = 0; i < p.size(); ++i) {
        const Eigen::Vector2d& a = p[i];
        const Eigen::Vector2d& b = p[(i + 1) % p.size()];
        twice += a.x() * b.y() - a.y() * b.x();
    }
    return 0.5 * twice;
}

/// Area of the intersection of two counter-clockwise triangles (Sutherland-Hodgman).
double intersectionArea(Polygon subject, const Polygon& clip) {
    for (std::size_t e = 0; e < 3 && !subject.empty(); ++e) {
        const Eigen::Vector2d& a = clip[e];
        const Eigen::Vector2d edge = clip[(e + 1) % 3] - a;
        const auto side = [&](const Eigen::Vector2d& p) {
            const Eigen::Vector2d d = p - a;
            return edge.x() * d.y() - edge.y() * d.x();  // > 0: inside (left of the edge)
        };
        Polygon kept;
        for (std::size_t i = 0; i < subject.size(); ++i) {
            const Eigen::Vector2d& p = subject[i];
            const Eigen::Vector2d& q = subject[(i + 1) % subject.size()];
            const double sp = side(p);
            const double sq = side(q);
            if (sp >= 0.0) kept.push_back(p);
            if ((sp >= 0.0) != (sq >= 0.0)) kept.push_back(p + (sp / (sp - sq)) * (q - p));
        }
        subject = std::move(kept);
    }
    return subject.size() < 3 ? 0.0 : polygonArea(subject);
}

/// Pairs of UV triangles sharing more than a sliver of area; bounding boxes sorted by u prune
/// the pairs.
int countUvOverlaps(const TriangleMesh& mesh) {
    const std::size_t n = mesh.triangles.size();
    std::vector<Eigen::AlignedBox2d> box(n);
    std::vector<Polygon> tri(n);
    for (std::size_t i = 0; i < n; ++i) {
        for (std::uint32_t v : mesh.triangles[i]) {
            tri[i].push_back(mesh.uvs[v]);
            box[i].extend(mesh.uvs[v]);
        }
    }
    std::vector<std::size_t> order(n);
    std::iota(order.begin(), order.end(), 0);
    std::sort(order.begin(), order.end(),
              [&](std::size_t a, std::size_t b) { return box[a].min().x() < box[b].min().x(); });
    int overlaps = 0;
    for (std::size_t oi = 0; oi < n; ++oi) {
        const std::size_t i = order[oi];
        for (std::size_t oj = oi + 1; oj < n; ++oj) {
            const std::size_t j = order[oj];
            if (box[j].min().x() >= box[i].max().x()) break;
            if (box[j].min().y() >= box[i].max().y() || box[i].min().y() >= box[j].max().y()) {
                continue;
            }
            const double smaller = std::min(polygonArea(tri[i]), polygonArea(tri[j]));
            if (intersectionArea(tri[i], tri[j]) > 1e-9 * smaller) ++overlaps;
        }
    }
    return overlaps;
}

/// UV bounding boxes of the charts (triangles connected through shared vertex indices).
std::vector<Eigen::AlignedBox2d> chartBounds(const TriangleMesh& mesh) {
    std::vector<std::uint32_t> parent(mesh.vertexCount());
    std::iota(parent.begin(), parent.end(), 0u);
    const auto find = [&](std::uint32_t v) {
        while (parent[v] != v) v = parent[v] = parent[parent[v]];
        return v;
    };
    for (const Triangle& t : mesh.triangles) {
        parent[find(t[1])] = find(t[0]);
        parent[find(t[2])] = find(t[0]);
    }
    std::map<std::uint32_t, Eigen::AlignedBox2d> charts;
    for (const Triangle& t : mesh.triangles) {
        for (std::uint32_t v : t) charts[find(v)].extend(mesh.uvs[v]);
    }
    std::vector<Eigen::AlignedBox2d> result;
    for (const auto& [root, box] : charts) result.push_back(box);
    return result;
}

/// Charts' bounding boxes are at least `gutter` apart along u or v.
void expectGutters(const TriangleMesh& mesh, std::size_t expectedCharts, double gutter) {
    const std::vector<Eigen::AlignedBox2d> charts = chartBounds(mesh);
    EXPECT_EQ(charts.size(), expectedCharts) << mesh.source;
    for (std::size_t i = 0; i < charts.size(); ++i) {
        for (std::size_t j = i + 1; j < charts.size(); ++j) {
            const Eigen::Vector2d gapLow = charts[j].min() - charts[i].max();
            const Eigen::Vector2d gapHigh = charts[i].min() - charts[j].max();
            EXPECT_GE(gapLow.cwiseMax(gapHigh).maxCoeff(), gutter)
                << mesh.source << ": charts " << i << " and " << j;
        }
    }
}

void expectWellFormed(const TriangleMesh& mesh) {
    expectClosedAndOriented(mesh);
    expectNoDegenerateTriangles(mesh);
    expectUvsInUnitSquareAndPositive(mesh);
    EXPECT_EQ(countUvOverlaps(mesh), 0) << mesh.source;
    EXPECT_GT(signedVolume(mesh), 0.0) << mesh.source << ": normals point inward";
}

/// The committed asset equals what writeObj makes of the generated mesh, byte for byte.
void expectMatchesAsset(const TriangleMesh& mesh, const std::string& file) {
    const fs::path written = test::scratchFolder("plimsoll_test_primitives") / file;
    ASSERT_TRUE(writeObj(mesh, written).ok());
    const std::string expected = test::readFile(fs::path(PLIMSOLL_ASSETS_DIR) / file);
    ASSERT_FALSE(expected.empty()) << PLIMSOLL_ASSETS_DIR << "/" << file << " missing";
    EXPECT_TRUE(test::readFile(written) == expected)
        << file << " differs from the generator: run `plimsoll samples --out assets`";
}

TEST(Primitives, SphereIsWellFormedAndSymmetric) {
    const TriangleMesh sphere = makeUvSphere(0.5, 64, 32);
    EXPECT_EQ(sphere.triangleCount(), 2u * 64 * 31);
    expectWellFormed(sphere);
    expectGutters(sphere, 1, 0.0);
    // Exactly symmetric: mirroring any vertex in y or z gives another vertex's position.
    const std::set<std::array<double, 3>> positions = [&] {
        std::set<std::array<double, 3>> s;
        for (const auto& p : sphere.positions) s.insert({p.x(), p.y(), p.z()});
        return s;
    }();
    for (const auto& p : sphere.positions) {
        EXPECT_TRUE(positions.count({p.x(), -p.y() + 0.0, p.z()})) << p.transpose();
        EXPECT_TRUE(positions.count({p.x(), p.y(), -p.z() + 0.0})) << p.transpose();
    }
}

TEST(Primitives, SphereVolumeIsThePolyhedronsAndConverges) {
    const double radius = 0.5;
    const double ball = 4.0 / 3.0 * kPi * radius * radius * radius;
    const double coarse = signedVolume(makeUvSphere(radius, 64, 32));
    const double fine = signedVolume(makeUvSphere(radius, 128, 64));
    EXPECT_NEAR(coarse, latheVolume(sphereProfile(radius, 32), 64), 1e-12 * ball);
    EXPECT_NEAR(fine, latheVolume(sphereProfile(radius, 64), 128), 1e-12 * ball);
    // An inscribed polyhedron: below the ball, with second-order convergence.
    EXPECT_LT(coarse, ball);
    EXPECT_LT(fine, ball);
    EXPECT_LT((ball - coarse) / ball, 1e-2);
    EXPECT_LT(ball - fine, 0.3 * (ball - coarse));
}

TEST(Primitives, LatheCoversTheUnitSquareWithExactVolume) {
    // Two cones joined by a frustum: four profile points, two of them poles.
    const std::vector<ProfilePoint> profile = {{0.0, -1.0}, {0.5, -0.25}, {0.3, 0.5}, {0.0, 1.0}};
    const TriangleMesh lathe = makeLathe(profile, 7);
    expectWellFormed(lathe);
    const std::vector<Eigen::AlignedBox2d> charts = chartBounds(lathe);
    ASSERT_EQ(charts.size(), 1u);
    EXPECT_EQ(charts[0].min(), Eigen::Vector2d(0.0, 0.0));
    EXPECT_EQ(charts[0].max(), Eigen::Vector2d(1.0, 1.0));
    const double exact = latheVolume(profile, 7);
    EXPECT_NEAR(signedVolume(lathe), exact, 1e-12 * exact);
}

TEST(Primitives, BoxHasSixChartsAndExactVolume) {
    const Eigen::Vector3d size(1.0, 0.5, 0.25);
    const TriangleMesh box = makeBox(size);
    EXPECT_EQ(box.vertexCount(), 24u);
    EXPECT_EQ(box.triangleCount(), 12u);
    expectWellFormed(box);
    expectGutters(box, 6, 0.02);
    EXPECT_NEAR(signedVolume(box), size.prod(), 1e-12 * size.prod());
    const Bounds3 bounds = computeBounds(box);
    EXPECT_EQ(bounds.min, -0.5 * size);
    EXPECT_EQ(bounds.max, 0.5 * size);
    // One texel density: UV area / 3D area is the same for every triangle.
    const auto density = [&](const Triangle& t) {
        return triangleUvArea(box, t) / triangleAreaVector(box, t).norm();
    };
    const double ratio = density(box.triangles[0]);
    for (const Triangle& t : box.triangles) {
        EXPECT_NEAR(density(t), ratio, 1e-12 * ratio);
    }
}

TEST(Primitives, CylinderIsAnExactPrism) {
    const double radius = 0.3;
    const double height = 1.0;
    for (int segments : {3, 5, 64}) {
        const TriangleMesh cylinder = makeCylinder(radius, height, segments);
        EXPECT_EQ(cylinder.triangleCount(), 4u * segments);
        expectWellFormed(cylinder);
        expectGutters(cylinder, 3, 0.02);
        const double prism =
            0.5 * segments * radius * radius * std::sin(2.0 * kPi / segments) * height;
        EXPECT_NEAR(signedVolume(cylinder), prism, 1e-12 * prism) << segments << " segments";
    }
}

TEST(Primitives, BuoyIsAClosedLatheAboutOnePointSixMetresTall) {
    const TriangleMesh buoy = makeBuoy();
    expectWellFormed(buoy);
    expectGutters(buoy, 1, 0.0);
    const Bounds3 bounds = computeBounds(buoy);
    EXPECT_NEAR(bounds.max.y() - bounds.min.y(), 1.6, 0.05);
    EXPECT_NEAR(bounds.max.x(), 0.4, 1e-12);  // the can body
    EXPECT_LT(bounds.min.y(), -0.5);          // keel well below the waterline y = 0
    EXPECT_GT(bounds.max.y(), 0.5);           // top mark well above it
}

TEST(Primitives, HullIsAClosedBoatWithADeckAndFourCharts) {
    const HullShape shape;
    const TriangleMesh hull = makeHull(shape);
    expectWellFormed(hull);
    expectGutters(hull, 4, 0.029);
    const Bounds3 b = computeBounds(hull);
    EXPECT_NEAR(b.min.x(), -1.0, 1e-12);
    EXPECT_NEAR(b.max.x(), 1.0, 1e-12);
    EXPECT_NEAR(b.min.y(), -0.5, 1e-12);
    EXPECT_NEAR(b.max.y(), 0.5, 1e-12);
    EXPECT_NEAR(b.min.z(), -3.0, 1e-12);
    EXPECT_NEAR(b.max.z(), 3.0, 1e-12);
    // Volume: the section (deck line over the curve x = w sqrt|cos t|, y = 0.5 - sqrt(sin t))
    // scales with the half-beam, so station areas are w_i A_1; aft of amidships the hull is
    // a prism (exact), forward the trapezoid rule over the stations is close.
    double a1 = 0;
    std::vector<Eigen::Vector2d> ring;
    for (int j = 0; j <= shape.sectionSegments; ++j) {
        const double t = std::numbers::pi * j / shape.sectionSegments;
        const double c = std::cos(t), sn = std::max(0.0, std::sin(t));
        ring.emplace_back(std::copysign(std::sqrt(std::abs(c)), c), 0.5 - std::sqrt(sn));
    }
    for (std::size_t i = 0; i < ring.size(); ++i) {
        const Eigen::Vector2d& p = ring[i];
        const Eigen::Vector2d& q = ring[(i + 1) % ring.size()];
        a1 += 0.5 * (q.x() * p.y() - p.x() * q.y());
    }
    double volume = 0;
    const double dz = shape.length / shape.stations;
    for (int i = 0; i < shape.stations; ++i) {
        const double z0 = -0.5 * shape.length + i * dz;
        volume += 0.5 * (hullHalfBeam(shape, z0) + hullHalfBeam(shape, z0 + dz)) * a1 * dz;
    }
    EXPECT_NEAR(signedVolume(hull), volume, 2e-3 * volume);
}

TEST(Primitives, PlushIsAClosedLathe) {
    const TriangleMesh plush = makePlush();
    expectWellFormed(plush);
    const Bounds3 b = computeBounds(plush);
    EXPECT_NEAR(b.min.y(), 0.0, 1e-12);
    EXPECT_NEAR(b.max.y(), 0.92, 1e-12);
    EXPECT_NEAR(b.max.x(), 0.3, 1e-3);
}

TEST(Primitives, GenerationIsDeterministic) {
    const TriangleMesh a = makeBuoy();
    const TriangleMesh b = makeBuoy();
    EXPECT_EQ(a.positions, b.positions);
    EXPECT_EQ(a.uvs, b.uvs);
    EXPECT_EQ(a.triangles, b.triangles);
}

TEST(Assets, CommittedSamplesAreExactlyTheGeneratorsOutput) {
    expectMatchesAsset(makeUvSphere(0.5, 64, 32), "sphere.obj");
    expectMatchesAsset(makeBox({1.0, 0.5, 0.25}), "box.obj");
    expectMatchesAsset(makeCylinder(0.3, 1.0, 64), "cylinder.obj");
    expectMatchesAsset(makeBuoy(), "buoy.obj");
    expectMatchesAsset(makeHull(), "hull.obj");
    expectMatchesAsset(makePlush(), "plush.obj");
}

TEST(Assets, SamplesHaveUvsAndNoNegativeZero) {
    for (const char* file :
         {"sphere.obj", "box.obj", "cylinder.obj", "buoy.obj", "hull.obj", "plush.obj"}) {
        const std::string text = test::readFile(fs::path(PLIMSOLL_ASSETS_DIR) / file);
        EXPECT_NE(text.find("\nvt "), std::string::npos) << file;
        EXPECT_EQ(text.find(" -0 "), std::string::npos) << file;
        EXPECT_EQ(text.find(" -0\n"), std::string::npos) << file;
    }
}

}  // namespace
}  // namespace test_primitives
}  // namespace plimsoll
