// Texture bake by exact clipping (DESIGN.md, "The textures").
//
// Every UV triangle is cut into the pieces that fall into each texel square: first into row
// strips, then each strip into cells, by splitting convex polygons along grid lines. The map
// from UV to the surface is affine on a triangle, so a piece covering a share f of the
// triangle's UV area carries exactly f times the triangle's area vector, and its 3D centroid is
// the image of its UV centroid. Summed per texel this gives AVT (sum of area vectors), PT (area
// centroid) and coverage; the area vectors of a closed surface then sum to zero up to rounding.
//
// The texture is processed in bands of rows, one band per task on a pool of threads; each task
// owns a dense accumulator for its rows only (bounded memory at 8192^2), and bands are joined in
// order, so the result does not depend on the thread count.
#include "plimsoll/bake.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <array>
#include <atomic>
#include <cassert>
#include <cmath>
#include <mutex>
#include <string>
#include <thread>

namespace plimsoll {

namespace {

using Vec2 = Eigen::Vector2d;

/// A convex polygon in texel coordinates. A triangle cut by two pairs of grid lines has at
/// most 7 vertices; the capacity leaves room for points duplicated on the cut lines.
struct Polygon {
    std::array<Vec2, 16> v;
    int n = 0;
    void push(const Vec2& p) {
        assert(n < static_cast<int>(v.size()));
        v[n++] = p;
    }
};

/// Splits `in` along the line coordinate[axis] == value into its parts below and above.
/// Intersection points are placed exactly on the line so neighbouring cells share them.
void splitPolygon(const Polygon& in, int axis, double value, Polygon& below, Polygon& above) {
    below.n = above.n = 0;
    for (int i = 0; i < in.n; ++i) {
        const Vec2& a = in.v[i];
        const Vec2& b = in.v[(i + 1) % in.n];
        const double da = a[axis] - value;
        const double db = b[axis] - value;
        if (da <= 0) below.push(a);
        if (da >= 0) above.push(a);
        if ((da < 0 && db > 0) || (da > 0 && db < 0)) {
            Vec2 p = a + (da / (da - db)) * (b - a);
            p[axis] = value;
            below.push(p);
            above.push(p);
        }
    }
}

/// Twice the signed area and the centroid of a polygon (shoelace, relative to vertex 0).
struct AreaCentroid {
    double twiceArea = 0;
    Vec2 centroid = Vec2::Zero();
};
AreaCentroid areaAndCentroid(const Polygon& poly) {
    AreaCentroid out;
    if (poly.n < 3) return out;
    const Vec2 origin = poly.v[0];
    Vec2 weighted = Vec2::Zero();
    for (int i = 1; i + 1 < poly.n; ++i) {
        const Vec2 a = poly.v[i] - origin;
        const Vec2 b = poly.v[i + 1] - origin;
        const double cross = a.x() * b.y() - a.y() * b.x();
        out.twiceArea += cross;
        weighted += cross * (a + b);
    }
    out.centroid = out.twiceArea != 0 ? Vec2(origin + weighted / (3.0 * out.twiceArea)) : origin;
    return out;
}

/// A triangle prepared for clipping: texel-space corners and the affine map back to 3D.
struct PreparedTriangle {
    std::array<Vec2, 3> corner;     ///< texel coordinates (uv * N)
    Vec2 edge1, edge2;              ///< corner[1] - corner[0], corner[2] - corner[0]
    double twiceUvArea = 0;         ///< signed, texel units
    Eigen::Vector3d origin, side1, side2;  ///< p0, p1 - p0, p2 - p0
    Eigen::Vector3d areaVector;     ///< m^2
    double area = 0;                ///< m^2
    int rowLo = 0, rowHi = -1;      ///< rows touched, clamped to the texture

    Eigen::Vector3d surfacePoint(const Vec2& q) const {
        const Vec2 d = q - corner[0];
        const double b1 = (d.x() * edge2.y() - d.y() * edge2.x()) / twiceUvArea;
        const double b2 = (edge1.x() * d.y() - edge1.y() * d.x()) / twiceUvArea;
        return origin + b1 * side1 + b2 * side2;
    }
};

struct TexelAccumulator {
    Eigen::Vector3d areaVector = Eigen::Vector3d::Zero();
    Eigen::Vector3d weightedPosition = Eigen::Vector3d::Zero();  ///< sum of area * centroid
    double area = 0;
    double coverage = 0;  ///< texel units: 1 = the whole texel square
};

/// Compact output of one band, joined in band order.
struct BandResult {
    std::vector<std::uint32_t> texelIndex;
    std::vector<Eigen::Vector3d> position, areaVector;
    std::vector<double> area, coverage;
};

class BandBaker {
public:
    BandBaker(int size, int bandRows)
        : size_(size), cells_(static_cast<std::size_t>(size) * bandRows), touched_(cells_.size()) {}

    BandResult bake(const std::vector<PreparedTriangle>& triangles,
                    const std::vector<std::uint32_t>& ids, int rowBegin, int rowEnd) {
        rowBegin_ = rowBegin;
        for (std::uint32_t id : ids) clipTriangle(triangles[id], rowBegin, rowEnd);
        return collect();
    }

private:
    void clipTriangle(const PreparedTriangle& tri, int rowBegin, int rowEnd) {
        Polygon rest, row, above;
        for (const Vec2& c : tri.corner) rest.push(c);
        const int first = std::max(tri.rowLo, rowBegin);
        const int last = std::min(tri.rowHi, rowEnd - 1);
        if (first > tri.rowLo) {  // drop what belongs to earlier bands
            splitPolygon(rest, 1, first, row, above);
            rest = above;
        }
        for (int r = first; r <= last; ++r) {
            if (r < tri.rowHi) {
                splitPolygon(rest, 1, r + 1, row, above);
                rest = above;
            } else {
                row = rest;
            }
            clipRow(tri, row, r);
        }
    }

    void clipRow(const PreparedTriangle& tri, const Polygon& row, int r) {
        if (row.n < 3) return;
        double xLo = row.v[0].x(), xHi = xLo;
        for (int i = 1; i < row.n; ++i) {
            xLo = std::min(xLo, row.v[i].x());
            xHi = std::max(xHi, row.v[i].x());
        }
        const int colLo = std::clamp(static_cast<int>(std::floor(xLo)), 0, size_ - 1);
        const int colHi = std::clamp(static_cast<int>(std::floor(xHi)), 0, size_ - 1);
        Polygon rest = row, cell, right;
        for (int c = colLo; c <= colHi; ++c) {
            if (c < colHi) {
                splitPolygon(rest, 0, c + 1, cell, right);
                rest = right;
            } else {
                cell = rest;
            }
            addPiece(tri, cell, r, c);
        }
    }

    void addPiece(const PreparedTriangle& tri, const Polygon& cell, int r, int c) {
        const AreaCentroid piece = areaAndCentroid(cell);
        if (piece.twiceArea == 0) return;
        // Share of the triangle: both areas carry the triangle's UV orientation, so the ratio is
        // positive for mirrored triangles too.
        const double share = piece.twiceArea / tri.twiceUvArea;
        const std::size_t local = static_cast<std::size_t>(r - rowBegin_) * size_ + c;
        TexelAccumulator& acc = cells_[local];
        if (!touched_[local]) {
            touched_[local] = 1;
            touchedList_.push_back(static_cast<std::uint32_t>(local));
        }
        const double pieceArea = share * tri.area;
        acc.areaVector += share * tri.areaVector;
        acc.area += pieceArea;
        acc.weightedPosition += pieceArea * tri.surfacePoint(piece.centroid);
        acc.coverage += 0.5 * std::abs(piece.twiceArea);
    }

    BandResult collect() {
        std::sort(touchedList_.begin(), touchedList_.end());
        BandResult out;
        for (std::uint32_t local : touchedList_) {
            TexelAccumulator& acc = cells_[local];
            if (acc.area > 0) {
                out.texelIndex.push_back(static_cast<std::uint32_t>(
                    static_cast<std::size_t>(rowBegin_) * size_ + local));
                out.position.push_back(acc.weightedPosition / acc.area);
                out.areaVector.push_back(acc.areaVector);
                out.area.push_back(acc.area);
                out.coverage.push_back(acc.coverage);
            }
            acc = TexelAccumulator{};
            touched_[local] = 0;
        }
        touchedList_.clear();
        return out;
    }

    int size_;
    int rowBegin_ = 0;
    std::vector<TexelAccumulator> cells_;
    std::vector<std::uint8_t> touched_;
    std::vector<std::uint32_t> touchedList_;
};

std::vector<PreparedTriangle> prepareTriangles(const TriangleMesh& mesh,
                                               const UvPlacement& placement, int size) {
    std::vector<PreparedTriangle> prepared;
    prepared.reserve(mesh.triangles.size());
    for (const Triangle& t : mesh.triangles) {
        PreparedTriangle tri;
        for (int k = 0; k < 3; ++k) tri.corner[k] = placement.apply(mesh.uvs[t[k]]) * size;
        tri.edge1 = tri.corner[1] - tri.corner[0];
        tri.edge2 = tri.corner[2] - tri.corner[0];
        tri.twiceUvArea = tri.edge1.x() * tri.edge2.y() - tri.edge1.y() * tri.edge2.x();
        tri.origin = mesh.positions[t[0]];
        tri.side1 = mesh.positions[t[1]] - tri.origin;
        tri.side2 = mesh.positions[t[2]] - tri.origin;
        tri.areaVector = 0.5 * tri.side1.cross(tri.side2);
        tri.area = tri.areaVector.norm();
        // A triangle without UV area maps to nothing (validation reports it as an error).
        if (tri.twiceUvArea != 0 && std::isfinite(tri.twiceUvArea)) {
            const double yLo = std::min({tri.corner[0].y(), tri.corner[1].y(), tri.corner[2].y()});
            const double yHi = std::max({tri.corner[0].y(), tri.corner[1].y(), tri.corner[2].y()});
            tri.rowLo = std::clamp(static_cast<int>(std::floor(yLo)), 0, size - 1);
            tri.rowHi = std::clamp(static_cast<int>(std::floor(yHi)), 0, size - 1);
        }
        prepared.push_back(tri);
    }
    return prepared;
}

}  // namespace

double SurfaceTextures::uvCoverage() const {
    double covered = 0;
    for (double c : coverage) covered += c;
    return covered / (static_cast<double>(size) * size);
}

double SurfaceTextures::surfaceArea() const {
    double total = 0;
    for (double a : area) total += a;
    return total;
}

double SurfaceTextures::closureError() const {
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    double magnitude = 0;
    for (const auto& a : areaVector) {
        sum += a;
        magnitude += a.norm();
    }
    return magnitude > 0 ? sum.norm() / magnitude : 0.0;
}

Eigen::Vector3d SurfaceTextures::areaCentroid() const {
    Eigen::Vector3d weighted = Eigen::Vector3d::Zero();
    double total = 0;
    for (std::size_t i = 0; i < area.size(); ++i) {
        weighted += area[i] * position[i];
        total += area[i];
    }
    return total > 0 ? Eigen::Vector3d(weighted / total) : Eigen::Vector3d::Zero();
}

Result<SurfaceTextures> bakeSurfaceTextures(const TriangleMesh& mesh,
                                            const BakeSettings& settings) {
    const int size = settings.size;
    if (size < kMinTextureSize || size > kMaxTextureSize) {
        return makeError(mesh.source + ": texture size " + std::to_string(size) +
                         " is outside " + std::to_string(kMinTextureSize) + ".." +
                         std::to_string(kMaxTextureSize));
    }
    if (!mesh.hasUvs()) {
        return makeError(mesh.source + ": the mesh has no texture coordinates to bake");
    }

    SurfaceTextures out;
    out.size = size;
    out.placement = fitUvsIntoUnitSquare(mesh);
    const std::vector<PreparedTriangle> triangles = prepareTriangles(mesh, out.placement, size);

    const unsigned threads = std::max(1u, settings.threads ? settings.threads
                                                           : std::thread::hardware_concurrency());
    // Enough bands to balance the threads, few enough rows that a band's accumulator stays
    // near 64 MB at the largest size.
    const int maxRowsForMemory = std::max(1, (1 << 20) / size);
    const int rowsForBalance = (size + 4 * static_cast<int>(threads) - 1) / (4 * threads);
    const int bandRows = std::max(1, std::min(maxRowsForMemory, rowsForBalance));
    const int bandCount = (size + bandRows - 1) / bandRows;

    std::vector<std::vector<std::uint32_t>> bandTriangles(bandCount);
    for (std::uint32_t id = 0; id < triangles.size(); ++id) {
        const PreparedTriangle& tri = triangles[id];
        for (int b = tri.rowLo / bandRows; tri.rowLo <= tri.rowHi && b <= tri.rowHi / bandRows; ++b)
            bandTriangles[b].push_back(id);
    }

    std::vector<BandResult> bands(bandCount);
    std::atomic<int> nextBand{0};
    std::atomic<int> bandsDone{0};
    std::mutex progressMutex;
    auto worker = [&] {
        BandBaker baker(size, bandRows);
        for (int b = nextBand++; b < bandCount; b = nextBand++) {
            bands[b] = baker.bake(triangles, bandTriangles[b], b * bandRows,
                                  std::min(size, (b + 1) * bandRows));
            const int done = ++bandsDone;
            if (settings.progress) {
                std::lock_guard<std::mutex> lock(progressMutex);
                settings.progress(static_cast<double>(done) / bandCount);
            }
        }
    };
    std::vector<std::thread> pool;
    for (unsigned t = 1; t < std::min<unsigned>(threads, bandCount); ++t) pool.emplace_back(worker);
    worker();
    for (auto& t : pool) t.join();

    std::size_t total = 0;
    for (const auto& band : bands) total += band.texelIndex.size();
    out.texelIndex.reserve(total);
    out.position.reserve(total);
    out.areaVector.reserve(total);
    out.area.reserve(total);
    out.coverage.reserve(total);
    for (auto& band : bands) {
        out.texelIndex.insert(out.texelIndex.end(), band.texelIndex.begin(), band.texelIndex.end());
        out.position.insert(out.position.end(), band.position.begin(), band.position.end());
        out.areaVector.insert(out.areaVector.end(), band.areaVector.begin(), band.areaVector.end());
        out.area.insert(out.area.end(), band.area.begin(), band.area.end());
        out.coverage.insert(out.coverage.end(), band.coverage.begin(), band.coverage.end());
        band = BandResult{};
    }
    return out;
}

}  // namespace plimsoll
