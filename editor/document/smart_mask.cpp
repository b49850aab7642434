// Smart masks (smart_mask.h).
#include "document/smart_mask.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <unordered_map>
#include <vector>

namespace plimsoll::editor {

namespace {

/// A crease of the mesh: its end points and its signed dihedral turn (rad).
struct Crease {
    Eigen::Vector3d a, b;
    double turn;
};

/// Every edge shared by exactly two faces that turns (vertices welded by position): the
/// angle between the faces' normals, negative where the second face rises above the first's
/// plane (a concave edge).
std::vector<Crease> creases(const TriangleMesh& mesh) {
    const std::vector<std::uint32_t> id = weldByPosition(mesh);
    struct Faces {
        int count = 0;
        std::uint32_t face[2] = {0, 0};
    };
    std::unordered_map<std::uint64_t, Faces> edges;
    edges.reserve(mesh.triangles.size() * 2);
    for (std::uint32_t f = 0; f < mesh.triangles.size(); ++f) {
        for (int k = 0; k < 3; ++k) {
            const std::uint32_t u = id[mesh.triangles[f][k]],
                                v = id[mesh.triangles[f][(k + 1) % 3]];
            if (u == v) continue;
            Faces& e = edges[(std::uint64_t(std::min(u, v)) << 32) | std::max(u, v)];
            if (e.count < 2) e.face[e.count] = f;
            ++e.count;
        }
    }
    std::vector<Crease> out;
    for (const auto& [key, e] : edges) {
        if (e.count != 2) continue;
        const Eigen::Vector3d a = mesh.positions[key >> 32];
        const Eigen::Vector3d b = mesh.positions[key & 0xffffffffu];
        const Triangle& t1 = mesh.triangles[e.face[0]];
        const Triangle& t2 = mesh.triangles[e.face[1]];
        const Eigen::Vector3d n1 = triangleAreaVector(mesh, t1).normalized();
        const Eigen::Vector3d n2 = triangleAreaVector(mesh, t2).normalized();
        if (!n1.allFinite() || !n2.allFinite()) continue;
        const double angle = std::atan2(n1.cross(n2).norm(), n1.dot(n2));
        if (angle == 0) continue;
        // The second face's vertex off the edge: above the first face's plane, concave.
        double rise = 0;
        for (int k = 0; k < 3; ++k) {
            const double h = n1.dot(mesh.positions[t2[k]] - a);
            if (std::abs(h) > std::abs(rise)) rise = h;
        }
        out.push_back({a, b, rise > 0 ? -angle : angle});
    }
    return out;
}

/// Length of the segment a..b inside the ball of `radius` about p.
double lengthInBall(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& p,
                    double radius) {
    const Eigen::Vector3d d = b - a, m = a - p;
    const double dd = d.squaredNorm();
    if (!(dd > 0)) return 0;
    const double half = d.dot(m) / dd, c = (m.squaredNorm() - radius * radius) / dd;
    const double disc = half * half - c;
    if (disc <= 0) return 0;
    const double root = std::sqrt(disc);
    const double t0 = std::max(0.0, -half - root), t1 = std::min(1.0, -half + root);
    return t1 > t0 ? (t1 - t0) * std::sqrt(dd) : 0.0;
}

/// Creases bucketed on a grid of cells 2 radius wide: a crease sits in the cells of points
/// along it a quarter cell apart, so every crease within `radius` of a point sits in a cell
/// of the 3 x 3 x 3 block around the point's own.
class CreaseGrid {
public:
    CreaseGrid(const std::vector<Crease>& creases, double radius)
        : creases_(creases), cell_(2 * radius), seen_(creases.size(), 0) {
        for (std::uint32_t c = 0; c < creases.size(); ++c) {
            const Eigen::Vector3d d = creases[c].b - creases[c].a;
            const int steps = 1 + static_cast<int>(std::ceil(4 * d.norm() / cell_));
            std::int64_t last = -1;
            for (int s = 0; s <= steps; ++s) {
                const std::int64_t key = keyOf(cellOf(creases[c].a + d * (double(s) / steps)));
                if (key == last) continue;
                std::vector<std::uint32_t>& bucket = cells_[key];
                if (bucket.empty() || bucket.back() != c) bucket.push_back(c);
                last = key;
            }
        }
    }

    /// Calls f(crease) once for every crease that may come within `radius` of p.
    template <class F>
    void near(const Eigen::Vector3d& p, F&& f) {
        ++stamp_;
        const Eigen::Vector3i centre = cellOf(p);
        for (int x = -1; x <= 1; ++x)
            for (int y = -1; y <= 1; ++y)
                for (int z = -1; z <= 1; ++z) {
                    auto it = cells_.find(keyOf(centre + Eigen::Vector3i(x, y, z)));
                    if (it == cells_.end()) continue;
                    for (std::uint32_t c : it->second) {
                        if (seen_[c] == stamp_) continue;
                        seen_[c] = stamp_;
                        f(creases_[c]);
                    }
                }
    }

private:
    Eigen::Vector3i cellOf(const Eigen::Vector3d& p) const {
        return (p / cell_).array().floor().cast<int>();
    }
    static std::int64_t keyOf(const Eigen::Vector3i& c) {
        // 21 bits a coordinate: a body spans far fewer cells than 2^20 at any useful radius.
        auto bits = [](int v) { return std::int64_t(v & 0x1fffff); };
        return (bits(c.x()) << 42) | (bits(c.y()) << 21) | bits(c.z());
    }

    const std::vector<Crease>& creases_;
    double cell_;
    std::unordered_map<std::int64_t, std::vector<std::uint32_t>> cells_;
    std::vector<std::uint64_t> seen_;
    std::uint64_t stamp_ = 0;
};

}  // namespace

std::vector<double> meanCurvatureAt(const TriangleMesh& mesh,
                                    std::span<const Eigen::Vector3f> points, double radius) {
    std::vector<double> out(points.size(), 0.0);
    if (!(radius > 0) || !std::isfinite(radius)) return out;
    const std::vector<Crease> all = creases(mesh);
    CreaseGrid grid(all, radius);
    const double disc = std::numbers::pi * radius * radius;
    for (std::size_t i = 0; i < points.size(); ++i) {
        const Eigen::Vector3d p = points[i].cast<double>();
        double sum = 0;
        grid.near(p, [&](const Crease& c) { sum += c.turn * lengthInBall(c.a, c.b, p, radius); });
        out[i] = 0.5 * sum / disc;
    }
    return out;
}

std::string smartMaskName(SmartMask::Kind kind) {
    switch (kind) {
        case SmartMask::Kind::BelowWaterline:
            return "below the waterline";
        case SmartMask::Kind::Depth:
            return "by depth";
        case SmartMask::Kind::Facing:
            return "facing";
        case SmartMask::Kind::Curvature:
            return "curvature";
        case SmartMask::Kind::Cavity:
            return "cavity";
    }
    return "smart";
}

PaintedMap smartMaskImage(const PaintSurface& surface, const SmartMask& mask,
                          const TriangleMesh* mesh) {
    PaintedMap out;
    out.width = surface.width;
    out.height = surface.height;
    const std::size_t pixels = std::size_t(surface.width) * std::size_t(surface.height);
    std::vector<double> sum(pixels, 0.0);
    std::vector<int> count(pixels, 0);
    const Eigen::Vector3d direction = mask.direction.normalized();
    const bool byCurvature =
        mask.kind == SmartMask::Kind::Curvature || mask.kind == SmartMask::Kind::Cavity;
    std::vector<double> curvature;
    if (byCurvature && mesh) curvature = meanCurvatureAt(*mesh, surface.position, mask.radius);
    const double sign = mask.kind == SmartMask::Kind::Cavity ? -1.0 : 1.0;
    const double full = std::max(mask.fullCurvature, 1e-12);
    for (std::size_t k = 0; k < surface.sampleCount(); ++k) {
        const Eigen::Vector3d p = mask.pose.apply(surface.position[k].cast<double>());
        const double below = mask.waterLevel - p.y();
        double value = 0;
        switch (mask.kind) {
            case SmartMask::Kind::BelowWaterline:
                value = below > 0 ? 1.0 : 0.0;
                break;
            case SmartMask::Kind::Depth:
                value = std::clamp(below / std::max(mask.depth, 1e-9), 0.0, 1.0);
                break;
            case SmartMask::Kind::Facing:
                value = std::max(
                    0.0, (mask.pose.rotation * surface.normal[k].cast<double>()).dot(direction));
                break;
            case SmartMask::Kind::Curvature:
            case SmartMask::Kind::Cavity:
                if (!curvature.empty()) value = std::clamp(sign * curvature[k] / full, 0.0, 1.0);
                break;
        }
        sum[surface.pixel[k]] += value;
        ++count[surface.pixel[k]];
    }
    out.values.resize(pixels, 0.0f);
    for (std::size_t i = 0; i < pixels; ++i) {
        if (count[i] > 0) out.values[i] = static_cast<float>(sum[i] / count[i]);
    }
    return out;
}

}  // namespace plimsoll::editor
