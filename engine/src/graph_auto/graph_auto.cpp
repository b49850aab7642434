// Automatic water graphs (graph.h buildAutomaticGraph; paper section 4.1): segments from the
// SDF segmentation (sdf_segmentation.cpp, the only CGAL code), merged to the k the user asked
// for, one node per segment, capacities from the segments' shares of the enclosed volume,
// pipes between adjacent segments.
#include "plimsoll/graph/graph.h"
#include "plimsoll/graph_auto/graph_auto.h"
#include "plimsoll/geometry/validate.h"

#include <Eigen/Dense>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <map>
#include <numbers>

namespace plimsoll {

int defaultSegmentCount(const TriangleMesh& mesh) {
    const double t = std::max<double>(1.0, static_cast<double>(mesh.triangleCount()));
    return std::clamp(static_cast<int>(std::lround(2.0 + std::log2(std::max(1.0, t / 1000.0)))), 2,
                      8);
}

namespace {

using Border = std::map<std::pair<int, int>, double>;  // (a < b) -> shared edge length, m

/// Length of the boundary between every pair of segments (edges after welding).
Border segmentBorders(const TriangleMesh& mesh, const std::vector<std::uint32_t>& weld,
                      const std::vector<int>& segment) {
    std::map<std::pair<std::uint32_t, std::uint32_t>, int> firstFace;
    Border border;
    for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
        for (int e = 0; e < 3; ++e) {
            std::uint32_t a = weld[mesh.triangles[t][e]], b = weld[mesh.triangles[t][(e + 1) % 3]];
            if (a > b) std::swap(a, b);
            const auto [it, inserted] = firstFace.emplace(std::pair{a, b}, static_cast<int>(t));
            if (inserted) continue;
            const int sa = segment[it->second], sb = segment[t];
            if (sa == sb) continue;
            border[{std::min(sa, sb), std::max(sa, sb)}] +=
                (mesh.positions[a] - mesh.positions[b]).norm();
        }
    }
    return border;
}

/// Merges the smallest segment (by area) into the neighbour it shares the longest border
/// with, until `target` remain; relabels 0..target-1.
void mergeSegments(const TriangleMesh& mesh, const std::vector<std::uint32_t>& weld,
                   MeshSegmentation& s, int target) {
    std::vector<double> area(s.segmentCount, 0.0);
    for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
        area[s.triangleSegment[t]] += triangleAreaVector(mesh, mesh.triangles[t]).norm();
    }
    Border border = segmentBorders(mesh, weld, s.triangleSegment);
    std::vector<int> into(s.segmentCount);
    for (int i = 0; i < s.segmentCount; ++i) into[i] = i;
    int alive = s.segmentCount;
    while (alive > target) {
        int smallest = -1;
        for (int i = 0; i < s.segmentCount; ++i) {
            if (into[i] == i && (smallest < 0 || area[i] < area[smallest])) smallest = i;
        }
        int best = -1;
        double longest = -1;
        for (const auto& [pair, length] : border) {
            if (pair.first != smallest && pair.second != smallest) continue;
            const int other = pair.first == smallest ? pair.second : pair.first;
            if (length > longest) longest = length, best = other;
        }
        if (best < 0) {  // a separate piece of the mesh: into the largest other segment
            for (int i = 0; i < s.segmentCount; ++i) {
                if (into[i] == i && i != smallest && (best < 0 || area[i] > area[best])) best = i;
            }
        }
        into[smallest] = best;
        area[best] += area[smallest];
        Border merged;
        for (const auto& [pair, length] : border) {
            int a = pair.first == smallest ? best : pair.first;
            int b = pair.second == smallest ? best : pair.second;
            if (a == b) continue;
            merged[{std::min(a, b), std::max(a, b)}] += length;
        }
        border = std::move(merged);
        --alive;
    }
    std::vector<int> label(s.segmentCount, -1);
    int next = 0;
    for (int i = 0; i < s.segmentCount; ++i) {
        if (into[i] == i) label[i] = next++;
    }
    for (int& seg : s.triangleSegment) {
        int r = seg;
        while (into[r] != r) r = into[r];
        seg = label[r];
    }
    s.segmentCount = next;
}

/// Cuts the largest segment (by area) in two across its longest axis (the plane through its
/// area centroid normal to the principal direction of its triangle centroids), until `target`
/// segments exist: for shapes whose SDF is one value everywhere (a sphere) or has fewer
/// clusters than asked.
void splitSegments(const TriangleMesh& mesh, MeshSegmentation& s, int target) {
    const std::size_t count = mesh.triangles.size();
    std::vector<Eigen::Vector3d> centre(count);
    std::vector<double> area(count);
    for (std::size_t t = 0; t < count; ++t) {
        const Triangle& tri = mesh.triangles[t];
        centre[t] =
            (mesh.positions[tri[0]] + mesh.positions[tri[1]] + mesh.positions[tri[2]]) / 3.0;
        area[t] = triangleAreaVector(mesh, tri).norm();
    }
    while (s.segmentCount < target) {
        std::vector<double> segArea(s.segmentCount, 0.0);
        for (std::size_t t = 0; t < count; ++t) segArea[s.triangleSegment[t]] += area[t];
        const int largest =
            static_cast<int>(std::max_element(segArea.begin(), segArea.end()) - segArea.begin());
        Eigen::Vector3d mean = Eigen::Vector3d::Zero();
        std::size_t members = 0;
        for (std::size_t t = 0; t < count; ++t) {
            if (s.triangleSegment[t] != largest) continue;
            mean += area[t] * centre[t];
            ++members;
        }
        if (members < 2) break;
        mean /= segArea[largest];
        Eigen::Matrix3d spread = Eigen::Matrix3d::Zero();
        for (std::size_t t = 0; t < count; ++t) {
            if (s.triangleSegment[t] != largest) continue;
            const Eigen::Vector3d d = centre[t] - mean;
            spread += area[t] * d * d.transpose();
        }
        const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(spread);
        const Eigen::Vector3d axis = eig.eigenvectors().col(2);
        for (std::size_t t = 0; t < count; ++t) {
            if (s.triangleSegment[t] == largest && (centre[t] - mean).dot(axis) > 0) {
                s.triangleSegment[t] = s.segmentCount;
            }
        }
        ++s.segmentCount;
    }
}

/// Grid points inside the closed mesh: columns along y, crossings by parity.
std::vector<Eigen::Vector3d> interiorPoints(const TriangleMesh& mesh, int samples,
                                            double& cellVolume) {
    const Bounds3 b = computeBounds(mesh);
    const Eigen::Vector3d extent = b.max - b.min;
    const double h = extent.maxCoeff() / samples;
    cellVolume = h * h * h;
    const int nx = std::max(1, static_cast<int>(std::ceil(extent.x() / h)));
    const int ny = std::max(1, static_cast<int>(std::ceil(extent.y() / h)));
    const int nz = std::max(1, static_cast<int>(std::ceil(extent.z() / h)));
    // Triangles by the columns their xz bounds cover.
    std::vector<std::vector<std::uint32_t>> columns(static_cast<std::size_t>(nx) * nz);
    auto cell = [&](double v, double lo, int n) {
        return std::clamp(static_cast<int>(std::floor((v - lo) / h - 0.5)), 0, n - 1);
    };
    for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
        double x0 = 1e300, x1 = -1e300, z0 = 1e300, z1 = -1e300;
        for (std::uint32_t v : mesh.triangles[t]) {
            x0 = std::min(x0, mesh.positions[v].x()), x1 = std::max(x1, mesh.positions[v].x());
            z0 = std::min(z0, mesh.positions[v].z()), z1 = std::max(z1, mesh.positions[v].z());
        }
        for (int i = cell(x0, b.min.x(), nx); i <= std::min(nx - 1, cell(x1, b.min.x(), nx) + 1);
             ++i) {
            for (int k = cell(z0, b.min.z(), nz);
                 k <= std::min(nz - 1, cell(z1, b.min.z(), nz) + 1); ++k) {
                columns[static_cast<std::size_t>(k) * nx + i].push_back(
                    static_cast<std::uint32_t>(t));
            }
        }
    }
    std::vector<Eigen::Vector3d> points;
    std::vector<double> crossings;
    for (int k = 0; k < nz; ++k) {
        for (int i = 0; i < nx; ++i) {
            // Cell centres, nudged off any symmetric placement so rays miss edges.
            const double x = b.min.x() + (i + 0.5) * h + 1.3e-7 * h;
            const double z = b.min.z() + (k + 0.5) * h + 0.7e-7 * h;
            crossings.clear();
            for (std::uint32_t t : columns[static_cast<std::size_t>(k) * nx + i]) {
                const Eigen::Vector3d& p0 = mesh.positions[mesh.triangles[t][0]];
                const Eigen::Vector3d& p1 = mesh.positions[mesh.triangles[t][1]];
                const Eigen::Vector3d& p2 = mesh.positions[mesh.triangles[t][2]];
                // Barycentric coordinates of (x, z) in the triangle's xz projection.
                const double d =
                    (p1.x() - p0.x()) * (p2.z() - p0.z()) - (p2.x() - p0.x()) * (p1.z() - p0.z());
                if (d == 0) continue;
                const double u =
                    ((x - p0.x()) * (p2.z() - p0.z()) - (p2.x() - p0.x()) * (z - p0.z())) / d;
                const double v =
                    ((p1.x() - p0.x()) * (z - p0.z()) - (x - p0.x()) * (p1.z() - p0.z())) / d;
                if (u < 0 || v < 0 || u + v > 1) continue;
                crossings.push_back(p0.y() + u * (p1.y() - p0.y()) + v * (p2.y() - p0.y()));
            }
            std::sort(crossings.begin(), crossings.end());
            for (int j = 0; j < ny; ++j) {
                const double y = b.min.y() + (j + 0.5) * h;
                const auto below =
                    std::lower_bound(crossings.begin(), crossings.end(), y) - crossings.begin();
                if (below % 2 == 1) points.emplace_back(x, y, z);
            }
        }
    }
    return points;
}

/// Centre of the sphere that best fits the points (algebraic least squares:
/// |p|^2 = 2 c.p + (r^2 - |c|^2)).
Eigen::Vector3d leastSquaresSphereCentre(const std::vector<Eigen::Vector3d>& points,
                                         const Eigen::Vector3d& reference) {
    Eigen::MatrixXd a(points.size(), 4);
    Eigen::VectorXd rhs(points.size());
    for (std::size_t i = 0; i < points.size(); ++i) {
        const Eigen::Vector3d p = points[i] - reference;
        a.row(static_cast<Eigen::Index>(i)) << 2 * p.x(), 2 * p.y(), 2 * p.z(), 1.0;
        rhs[static_cast<Eigen::Index>(i)] = p.squaredNorm();
    }
    const Eigen::Vector4d x = a.colPivHouseholderQr().solve(rhs);
    return reference + x.head<3>();
}

}  // namespace

Result<WaterGraph> buildAutomaticGraph(const TriangleMesh& mesh, const AutoGraphSettings& settings,
                                       AutoGraphReport* report) {
    const auto start = std::chrono::steady_clock::now();
    const ValidationReport validation = validateMesh(mesh);
    if (!validation.closedSolid()) {
        return makeError(ErrorKind::invalidArgument,
                         mesh.source +
                             ": an automatic graph needs a closed, outward-oriented "
                             "mesh:\n" +
                             validation.format());
    }
    const int k = settings.segments > 0 ? settings.segments : defaultSegmentCount(mesh);
    auto stage = [&](double from, double to) {
        return [&settings, from, to](double f) {
            if (settings.progress) settings.progress(from + (to - from) * f);
        };
    };
    Result<MeshSegmentation> segmented = segmentMeshSdf(mesh, k, stage(0.0, 0.7));
    if (!segmented) return segmented.error();
    MeshSegmentation seg = std::move(*segmented);
    const std::vector<std::uint32_t> weld = weldByPosition(mesh);
    if (seg.segmentCount > k) mergeSegments(mesh, weld, seg, k);
    if (seg.segmentCount < k) splitSegments(mesh, seg, k);
    if (settings.progress) settings.progress(0.75);

    const double enclosed = exactSolidMassProperties(mesh, 1.0).volume;
    if (!(enclosed > 0)) {
        return makeError(ErrorKind::invalidArgument,
                         mesh.source + ": the mesh encloses no volume (open, or inside out)");
    }
    double surface = 0;
    for (const Triangle& t : mesh.triangles) surface += triangleAreaVector(mesh, t).norm();
    const double water = enclosed - settings.shellThickness * surface;
    if (!(water > 0)) {
        return makeError(ErrorKind::invalidArgument, mesh.source + ": a shell of " +
                                                         std::to_string(settings.shellThickness) +
                                                         " m leaves no room inside");
    }

    // Each interior grid point goes to the segment of the nearest triangle centroid.
    double cellVolume = 0;
    const std::vector<Eigen::Vector3d> inside =
        interiorPoints(mesh, std::max(8, settings.volumeSamples), cellVolume);
    std::vector<Eigen::Vector3d> centroid(mesh.triangles.size());
    for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
        const Triangle& tri = mesh.triangles[t];
        centroid[t] =
            (mesh.positions[tri[0]] + mesh.positions[tri[1]] + mesh.positions[tri[2]]) / 3.0;
    }
    const int n = seg.segmentCount;
    std::vector<double> cells(n, 0.0);
    std::vector<Eigen::Vector3d> cellSum(n, Eigen::Vector3d::Zero());
    for (std::size_t i = 0; i < inside.size(); ++i) {
        std::size_t nearest = 0;
        double best = std::numeric_limits<double>::infinity();
        for (std::size_t t = 0; t < centroid.size(); ++t) {
            const double d = (centroid[t] - inside[i]).squaredNorm();
            if (d < best) best = d, nearest = t;
        }
        const int s = seg.triangleSegment[nearest];
        cells[s] += 1;
        cellSum[s] += inside[i];
        if (settings.progress && i % 4096 == 0) {
            settings.progress(0.75 + 0.2 * static_cast<double>(i) / inside.size());
        }
    }
    // A segment too thin to own a grid point still gets a (small) share.
    double totalCells = 0;
    for (double& c : cells) totalCells += (c = std::max(c, 0.5));

    // Vertices of each segment (welded, once each).
    std::vector<std::vector<Eigen::Vector3d>> vertices(n);
    std::vector<int> vertexSegment(mesh.positions.size(), -1);
    for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
        for (std::uint32_t v : mesh.triangles[t]) {
            const std::uint32_t w = weld[v];
            if (vertexSegment[w] == seg.triangleSegment[t]) continue;
            vertexSegment[w] = seg.triangleSegment[t];
            vertices[seg.triangleSegment[t]].push_back(mesh.positions[w]);
        }
    }

    WaterGraph graph;
    double assigned = 0;
    for (int s = 0; s < n; ++s) {
        GraphNode node;
        node.id = "s" + std::to_string(s);
        node.name = "segment " + std::to_string(s);
        Eigen::Vector3d mean = Eigen::Vector3d::Zero();
        for (const Eigen::Vector3d& p : vertices[s]) mean += p;
        mean /= std::max<std::size_t>(1, vertices[s].size());
        const Eigen::Vector3d fallback =
            cellSum[s].isZero(0.0) ? mean : Eigen::Vector3d(cellSum[s] / cells[s]);
        node.position =
            vertices[s].size() >= 4 ? leastSquaresSphereCentre(vertices[s], mean) : fallback;
        // A flat patch fits a huge sphere whose centre lies far outside: use the centroid of
        // the segment's share of the volume instead.
        if (!node.position.allFinite() || windingNumber(mesh, node.position) < 0.5) {
            node.position = fallback;
        }
        node.capacity = s + 1 < n ? water * cells[s] / totalCells : water - assigned;
        assigned += node.capacity;
        graph.nodes.push_back(std::move(node));
    }
    for (const auto& [pair, length] : segmentBorders(mesh, weld, seg.triangleSegment)) {
        GraphPipe pipe;
        pipe.a = graph.nodes[pair.first].id;
        pipe.b = graph.nodes[pair.second].id;
        pipe.radius = length / (2.0 * std::numbers::pi);  // the border as a circle's rim
        graph.pipes.push_back(std::move(pipe));
    }
    if (settings.progress) settings.progress(1.0);
    if (report) {
        report->segmentation = seg;
        report->enclosedVolume = enclosed;
        report->sampledVolume = static_cast<double>(inside.size()) * cellVolume;
        report->totalSeconds =
            std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    }
    return graph;
}

}  // namespace plimsoll
