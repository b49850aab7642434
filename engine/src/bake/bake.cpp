// Texture bake by exact clipping (docs/design.md, "The textures").
//
// Every UV triangle is cut into the pieces that fall into each texel square: first into row
// strips, then each strip into cells, by splitting convex polygons along grid lines. The map
// from UV to the surface is affine on a triangle, so a piece covering a share f of the
// triangle's UV area carries exactly f times the triangle's area vector, and its 3D centroid is
// the image of its UV centroid. Summed per texel this gives AVT (sum of area vectors), PT (area
// centroid) and coverage; the area vectors of a closed surface then sum to zero up to rounding.
//
// A texel on the border between two UV islands can hold surface from both, and those pieces
// may lie far apart on the body: one centroid cannot stand for them (the volume sum would use a
// point between them, an error that does not shrink with N). Such a texel gets one entry per
// island ("shared texels"), so every entry describes one connected piece of surface.
//
// On request the bake also records every piece (triangle, barycentric centroid, share) with the
// entry it went into, so a deforming mesh can regather the textures without clipping again
// (deform.h).
//
// The texture is processed in bands of rows, one band per task on a pool of threads; each task
// owns a dense accumulator for its rows only (bounded memory at 8192^2), and bands are joined in
// order, so the result does not depend on the thread count.
#include "plimsoll/bake/bake.h"
#include "plimsoll/bake/cancellable_bake.h"

#include <Eigen/Geometry>
#include <Eigen/LU>

#include <algorithm>
#include <array>
#include <atomic>
#include <cassert>
#include <cmath>
#include <limits>
#include <map>
#include <mutex>
#include <new>
#include <string>
#include <thread>
#include <tuple>

namespace plimsoll {

namespace {

using Vec2 = Eigen::Vector2d;

/// Finest grid: this many cells per texel side.
constexpr int kMaxSubdivision = 64;

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

/// A triangle prepared for clipping: grid-space corners and the affine map back to 3D. The
/// grid is the texel grid, or a finer one (`subdivision` cells per texel side) for a triangle
/// whose texels would span too much surface.
struct PreparedTriangle {
    std::array<Vec2, 3> corner;            ///< grid coordinates (uv * N * subdivision)
    Vec2 edge1, edge2;                     ///< corner[1] - corner[0], corner[2] - corner[0]
    double twiceUvArea = 0;                ///< signed, grid units
    Eigen::Vector3d origin, side1, side2;  ///< p0, p1 - p0, p2 - p0
    Eigen::Vector3d areaVector;            ///< m^2
    double area = 0;                       ///< m^2
    int rowLo = 0, rowHi = -1;             ///< grid rows touched, clamped to the texture
    std::uint32_t island = 0;              ///< UV island (see uvIslands)
    std::uint32_t index = 0;               ///< in the mesh's triangles
    int subdivision = 1;                   ///< grid cells per texel side

    /// (b1, b2) of grid point q: q = corner0 + b1 edge1 + b2 edge2.
    Vec2 barycentric(const Vec2& q) const {
        const Vec2 d = q - corner[0];
        return {(d.x() * edge2.y() - d.y() * edge2.x()) / twiceUvArea,
                (edge1.x() * d.y() - edge1.y() * d.x()) / twiceUvArea};
    }

    /// Same arithmetic as regatherSurface (deform.cpp), which reproduces the bake bit for bit.
    Eigen::Vector3d surfacePoint(const Vec2& b) const {
        return origin + b.x() * side1 + b.y() * side2;
    }

    /// Corners, edges, area and rows scaled from texel units to a grid of `cellsPerTexel`.
    PreparedTriangle onGrid(int cellsPerTexel, int textureSize) const {
        PreparedTriangle fine = *this;
        for (Vec2& c : fine.corner) c *= cellsPerTexel;
        fine.edge1 *= cellsPerTexel;
        fine.edge2 *= cellsPerTexel;
        fine.twiceUvArea *= static_cast<double>(cellsPerTexel) * cellsPerTexel;
        fine.setRows(textureSize * cellsPerTexel);
        return fine;
    }

    void setRows(int gridSize) {
        const double yLo = std::min({corner[0].y(), corner[1].y(), corner[2].y()});
        const double yHi = std::max({corner[0].y(), corner[1].y(), corner[2].y()});
        rowLo = std::clamp(static_cast<int>(std::floor(yLo)), 0, gridSize - 1);
        rowHi = std::clamp(static_cast<int>(std::floor(yHi)), 0, gridSize - 1);
    }
};

struct TexelAccumulator {
    Eigen::Vector3d areaVector = Eigen::Vector3d::Zero();
    Eigen::Vector3d weightedPosition = Eigen::Vector3d::Zero();  ///< sum of area * centroid
    double area = 0;
    double coverage = 0;  ///< texel units: 1 = the whole texel square
    std::uint32_t island = kNoIsland;
    std::uint32_t record = kNone;  ///< id of its recorded pieces, when recording

    static constexpr std::uint32_t kNoIsland = ~0u;
    static constexpr std::uint32_t kNone = ~0u;

    void add(const Eigen::Vector3d& pieceAreaVector, double pieceArea,
             const Eigen::Vector3d& centroid, double pieceCoverage) {
        areaVector += pieceAreaVector;
        area += pieceArea;
        weightedPosition += pieceArea * centroid;
        coverage += pieceCoverage;
    }
};

/// Compact output of one band, joined in band order.
struct BandResult {
    std::vector<std::uint32_t> texelIndex;
    std::vector<Eigen::Vector3d> position, areaVector;
    std::vector<double> area, coverage;
    std::vector<std::uint32_t> pieceCount;  ///< per entry, when recording
    std::vector<SurfacePiece> pieces;       ///< grouped by entry, when recording
};

class BandBaker {
public:
    BandBaker(int size, int bandRows, bool recordPieces)
        : size_(size),
          recordPieces_(recordPieces),
          cells_(static_cast<std::size_t>(size) * bandRows),
          touched_(cells_.size()) {}

    BandResult bake(const std::vector<PreparedTriangle>& triangles,
                    const std::vector<std::uint32_t>& ids, int rowBegin, int rowEnd) {
        rowBegin_ = rowBegin;
        for (std::uint32_t id : ids) {
            const PreparedTriangle& tri = triangles[id];
            const int k = tri.subdivision;
            if (k == 1) {
                clipTriangle(tri, rowBegin, rowEnd);
            } else {
                clipTriangle(tri.onGrid(k, size_), rowBegin * k, rowEnd * k);
            }
        }
        return collect();
    }

private:
    /// Cuts the triangle into grid rows within [rowBegin, rowEnd), then each row into cells.
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
        const int gridSize = size_ * tri.subdivision;
        const int colLo = std::clamp(static_cast<int>(std::floor(xLo)), 0, gridSize - 1);
        const int colHi = std::clamp(static_cast<int>(std::floor(xHi)), 0, gridSize - 1);
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

    void addPiece(const PreparedTriangle& tri, const Polygon& cell, int gridRow, int gridCol) {
        const AreaCentroid piece = areaAndCentroid(cell);
        if (piece.twiceArea == 0) return;
        // Share of the triangle: both areas carry the triangle's UV orientation, so the ratio is
        // positive for mirrored triangles too.
        const double share = piece.twiceArea / tri.twiceUvArea;
        const int k = tri.subdivision;
        const std::uint32_t local = static_cast<std::uint32_t>(
            static_cast<std::size_t>(gridRow / k - rowBegin_) * size_ + gridCol / k);
        TexelAccumulator& dense = cells_[local];
        if (!touched_[local]) {
            touched_[local] = 1;
            touchedList_.push_back(local);
        }
        // The first island to reach a texel at texel resolution owns the dense cell; other
        // islands and sub-texel cells are entries of their own in the side table.
        if (k == 1 && dense.island == TexelAccumulator::kNoIsland) dense.island = tri.island;
        const bool inDense = k == 1 && dense.island == tri.island;
        const std::uint32_t subCell = static_cast<std::uint32_t>((gridRow % k) * k + gridCol % k);
        TexelAccumulator& target =
            inDense ? dense
                    : sideEntries_[{local, tri.island, static_cast<std::uint32_t>(k), subCell}];
        const Vec2 barycentric = tri.barycentric(piece.centroid);
        target.add(share * tri.areaVector, share * tri.area, tri.surfacePoint(barycentric),
                   0.5 * std::abs(piece.twiceArea) / (static_cast<double>(k) * k));
        if (recordPieces_) {
            if (target.record == TexelAccumulator::kNone) target.record = recordCount_++;
            records_.push_back(
                {target.record, {tri.index, {barycentric.x(), barycentric.y()}, share}});
        }
    }

    BandResult collect() {
        std::sort(touchedList_.begin(), touchedList_.end());
        BandResult out;
        if (recordPieces_) recordEntry_.assign(recordCount_, kDropped);
        auto emit = [&](std::uint32_t local, const TexelAccumulator& acc) {
            if (acc.area <= 0) return;
            if (recordPieces_) {
                recordEntry_[acc.record] = static_cast<std::uint32_t>(out.texelIndex.size());
            }
            out.texelIndex.push_back(
                static_cast<std::uint32_t>(static_cast<std::size_t>(rowBegin_) * size_ + local));
            out.position.push_back(acc.weightedPosition / acc.area);
            out.areaVector.push_back(acc.areaVector);
            out.area.push_back(acc.area);
            out.coverage.push_back(acc.coverage);
        };
        auto side = sideEntries_.begin();
        for (std::uint32_t local : touchedList_) {
            emit(local, cells_[local]);
            for (; side != sideEntries_.end() && std::get<0>(side->first) == local; ++side)
                emit(local, side->second);
            cells_[local] = TexelAccumulator{};
            touched_[local] = 0;
        }
        touchedList_.clear();
        sideEntries_.clear();
        if (recordPieces_) collectPieces(out);
        return out;
    }

    /// Groups the band's pieces by entry (a stable counting sort, so each entry keeps its
    /// accumulation order); pieces of dropped entries (no surface area) go.
    void collectPieces(BandResult& out) {
        out.pieceCount.assign(out.texelIndex.size(), 0);
        for (const PieceRecord& r : records_) {
            if (recordEntry_[r.record] != kDropped) ++out.pieceCount[recordEntry_[r.record]];
        }
        cursor_.resize(out.pieceCount.size());
        std::uint32_t next = 0;
        for (std::size_t e = 0; e < cursor_.size(); ++e) {
            cursor_[e] = next;
            next += out.pieceCount[e];
        }
        out.pieces.resize(next);
        for (const PieceRecord& r : records_) {
            const std::uint32_t entry = recordEntry_[r.record];
            if (entry != kDropped) out.pieces[cursor_[entry]++] = r.piece;
        }
        records_.clear();
        recordCount_ = 0;
    }

    struct PieceRecord {
        std::uint32_t record;  ///< TexelAccumulator::record of the entry it went into
        SurfacePiece piece;
    };
    static constexpr std::uint32_t kDropped = ~0u;

    int size_;
    bool recordPieces_;
    int rowBegin_ = 0;
    std::vector<TexelAccumulator> cells_;
    std::vector<std::uint8_t> touched_;
    std::vector<std::uint32_t> touchedList_;
    /// Entries beyond a texel's first island at texel resolution, keyed (local texel, island,
    /// cells per texel side, sub-cell): ordered, so they come out deterministically.
    std::map<std::tuple<std::uint32_t, std::uint32_t, std::uint32_t, std::uint32_t>,
             TexelAccumulator>
        sideEntries_;
    std::vector<PieceRecord> records_;  ///< in accumulation order
    std::uint32_t recordCount_ = 0;
    std::vector<std::uint32_t> recordEntry_;  ///< record -> entry in the band, or kDropped
    std::vector<std::uint32_t> cursor_;
};

/// Length on the surface of the longest texel-sized step in UV on this triangle (m): the
/// largest singular value of the affine map's Jacobian from texel space to object space.
double longestTexelSide(const PreparedTriangle& tri) {
    Eigen::Matrix2d uvEdges;
    uvEdges << tri.edge1, tri.edge2;
    Eigen::Matrix<double, 3, 2> sides;
    sides << tri.side1, tri.side2;
    const Eigen::Matrix<double, 3, 2> jacobian = sides * uvEdges.inverse();
    const Eigen::Matrix2d gram = jacobian.transpose() * jacobian;
    // Largest eigenvalue of a symmetric 2x2 matrix.
    const double mean = 0.5 * gram.trace();
    const double spread = std::sqrt(std::max(0.0, mean * mean - gram.determinant()));
    return std::sqrt(mean + spread);
}

std::vector<PreparedTriangle> prepareTriangles(const TriangleMesh& mesh,
                                               const UvPlacement& placement, int size,
                                               double maxTexelStretch) {
    const std::vector<std::uint32_t> islands = uvIslands(mesh);
    std::vector<PreparedTriangle> prepared;
    prepared.reserve(mesh.triangles.size());
    double totalArea = 0, totalUvArea = 0;
    for (std::size_t id = 0; id < mesh.triangles.size(); ++id) {
        const Triangle& t = mesh.triangles[id];
        PreparedTriangle tri;
        tri.island = islands[id];
        tri.index = static_cast<std::uint32_t>(id);
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
            tri.setRows(size);
            totalArea += tri.area;
            totalUvArea += 0.5 * std::abs(tri.twiceUvArea);
        }
        prepared.push_back(tri);
    }
    // Where the map squeezes surface (a texel of this triangle spans, in its longest
    // direction, more than maxTexelStretch times the mesh's typical texel side), the triangle
    // is cut on a finer grid, so every entry stays a small piece of surface and the sums keep
    // second-order accuracy. Typical UV maps need this on a few triangles; a fin squeezed into
    // one texel needs it badly.
    if (totalUvArea > 0 && maxTexelStretch > 0) {
        const double typicalTexelSide = std::sqrt(totalArea / totalUvArea);  // m
        for (PreparedTriangle& tri : prepared) {
            if (tri.rowHi < tri.rowLo || tri.area == 0) continue;
            const double stretch = longestTexelSide(tri) / typicalTexelSide;
            tri.subdivision = std::clamp(static_cast<int>(std::ceil(stretch / maxTexelStretch)), 1,
                                         kMaxSubdivision);
        }
    }
    return prepared;
}

}  // namespace

std::size_t SurfaceTextures::distinctTexelCount() const {
    std::size_t distinct = 0;
    for (std::size_t i = 0; i < texelIndex.size(); ++i)
        distinct += (i == 0 || texelIndex[i] != texelIndex[i - 1]);
    return distinct;
}

double SurfaceTextures::texelAreaSpread(double tail) const {
    std::vector<double> density;
    density.reserve(area.size());
    for (std::size_t i = 0; i < area.size(); ++i) {
        if (coverage[i] > 0 && area[i] > 0) density.push_back(area[i] / coverage[i]);
    }
    if (density.empty()) return 0;
    const auto at = [&](double q) {
        const auto k = static_cast<std::size_t>(q * static_cast<double>(density.size() - 1) + 0.5);
        std::nth_element(density.begin(), density.begin() + static_cast<std::ptrdiff_t>(k),
                         density.end());
        return density[k];
    };
    const double low = at(tail), high = at(1.0 - tail);
    return high / low;
}

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

Result<SurfaceTextures> bakeSurfaceTextures(const TriangleMesh& mesh, const BakeSettings& settings,
                                            SurfacePieceTable* pieces) {
    return bakeSurfaceTextures(mesh, settings, pieces, CancelRequested{});
}

Result<SurfaceTextures> bakeSurfaceTextures(const TriangleMesh& mesh, const BakeSettings& settings,
                                            SurfacePieceTable* pieces,
                                            const CancelRequested& cancelled) {
    const int size = settings.size;
    if (size < kMinTextureSize || size > kMaxTextureSize) {
        return makeError(ErrorKind::limit, mesh.source + ": texture size " + std::to_string(size) +
                                               " is outside " + std::to_string(kMinTextureSize) +
                                               ".." + std::to_string(kMaxTextureSize));
    }
    if (!mesh.hasUvs()) {
        return makeError(ErrorKind::invalidArgument,
                         mesh.source + ": the mesh has no texture coordinates to bake");
    }

    SurfaceTextures out;
    out.size = size;
    out.placement = fitUvsIntoUnitSquare(mesh);
    const std::vector<PreparedTriangle> triangles =
        prepareTriangles(mesh, out.placement, size, settings.maxTexelStretch);

    const unsigned threads =
        std::max(1u, settings.threads ? settings.threads : std::thread::hardware_concurrency());
    // Sixteen or more bands balance the threads; at most 2^20 texels a band keep an
    // accumulator near 64 MB at the largest size. The split must not depend on the thread
    // count: a triangle cut at a band edge rounds differently, and results are bit-identical
    // on every machine.
    const int maxRowsForMemory = std::max(1, (1 << 20) / size);
    const int bandRows = std::clamp(size / 16, 1, maxRowsForMemory);
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
    // Memory running out in a worker thread would end the process (an exception cannot leave
    // a thread): it stops every worker and the bake fails with a clear error instead. A
    // cancelled bake stops before its next band.
    std::atomic<bool> outOfMemory{false};
    std::atomic<bool> stopped{false};
    auto worker = [&] {
        try {
            BandBaker baker(size, bandRows, pieces != nullptr);
            for (int b = nextBand++; b < bandCount; b = nextBand++) {
                if (stopped || (cancelled && cancelled())) {
                    stopped = true;
                    return;
                }
                bands[b] = baker.bake(triangles, bandTriangles[b], b * bandRows,
                                      std::min(size, (b + 1) * bandRows));
                const int done = ++bandsDone;
                if (settings.progress) {
                    std::lock_guard<std::mutex> lock(progressMutex);
                    settings.progress(static_cast<double>(done) / bandCount);
                }
            }
        } catch (const std::bad_alloc&) {
            outOfMemory = true;
            nextBand = bandCount;
        }
    };
    std::vector<std::thread> pool;
    for (unsigned t = 1; t < std::min<unsigned>(threads, bandCount); ++t) pool.emplace_back(worker);
    worker();
    for (auto& t : pool) t.join();
    if (outOfMemory) {
        return makeError(ErrorKind::limit,
                         mesh.source + ": out of memory baking " + std::to_string(size) +
                             "^2 texels: bake a smaller texture (texture_size, --size)");
    }
    if (stopped)
        return makeError(ErrorKind::invalidArgument, mesh.source + ": " + kBakeCancelledMessage);

    std::size_t total = 0, totalPieces = 0;
    for (const auto& band : bands) {
        total += band.texelIndex.size();
        totalPieces += band.pieces.size();
    }
    if (totalPieces > std::numeric_limits<std::uint32_t>::max()) {
        return makeError(ErrorKind::limit,
                         mesh.source + ": " + std::to_string(totalPieces) +
                             " surface pieces are too many to record; bake a smaller texture");
    }
    if (pieces) {
        pieces->firstPiece.clear();
        pieces->firstPiece.reserve(total + 1);
        pieces->firstPiece.push_back(0);
        pieces->pieces.clear();
        pieces->pieces.reserve(totalPieces);
        pieces->triangleCount = mesh.triangles.size();
    }
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
        if (pieces) {
            for (std::uint32_t count : band.pieceCount)
                pieces->firstPiece.push_back(pieces->firstPiece.back() + count);
            pieces->pieces.insert(pieces->pieces.end(), band.pieces.begin(), band.pieces.end());
        }
        band = BandResult{};
    }
    return out;
}

}  // namespace plimsoll
