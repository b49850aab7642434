// Paint is exactly what was painted: a fill and a stroke over every shared mesh and real asset
// that loads leave no unpainted pixel inside the painted region of the saved map. The region is
// found from the mesh alone: the pixels whose centre lies in a UV triangle (of the filled
// island; or whose surface point there lies well inside the stroke's reach).
#include "test_support.h"
#include "editor/document_test_support.h"

#include "document/command.h"
#include "document/document.h"
#include "document/paint.h"

#include "plimsoll/geometry/uv_layout.h"
#include "plimsoll/io/painted_map_io.h"
#include "plimsoll/project/project.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <limits>
#include <map>
#include <set>
#include <unistd.h>

namespace plimsoll::editor {
namespace test_editor_paint_coverage {
namespace {

namespace fs = std::filesystem;
using test::executeOrFail;

constexpr int kSide = 512;

/// A pixel whose centre lies in a UV triangle, with the surface point there and the surface's
/// extent over one pixel (how far the pixel's own points can lie from that point).
struct CoveredPixel {
    std::uint32_t pixel;
    std::uint32_t triangle;
    Eigen::Vector3d point;
    double extent;
};

std::vector<CoveredPixel> coveredPixels(const TriangleMesh& mesh, int w, int h) {
    std::vector<CoveredPixel> out;
    for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
        const Triangle& tri = mesh.triangles[t];
        const Eigen::Vector2d a = mesh.uvs[tri[0]], b = mesh.uvs[tri[1]], c = mesh.uvs[tri[2]];
        const double det = (b - a).x() * (c - a).y() - (b - a).y() * (c - a).x();
        if (std::abs(det) < 1e-14) continue;
        const Eigen::Vector3d p0 = mesh.positions[tri[0]];
        const Eigen::Vector3d e1 = mesh.positions[tri[1]] - p0, e2 = mesh.positions[tri[2]] - p0;
        // d point / d uv, for the pixel's extent on the surface.
        const Eigen::Vector3d dPdu = (e1 * (c - a).y() - e2 * (b - a).y()) / det;
        const Eigen::Vector3d dPdv = (e2 * (b - a).x() - e1 * (c - a).x()) / det;
        const double extent = dPdu.norm() / w + dPdv.norm() / h;
        const double u0 = std::min({a.x(), b.x(), c.x()}), u1 = std::max({a.x(), b.x(), c.x()});
        const double v0 = std::min({a.y(), b.y(), c.y()}), v1 = std::max({a.y(), b.y(), c.y()});
        const int x0 = std::max(0, static_cast<int>(std::floor(u0 * w - 0.5)));
        const int x1 = std::min(w - 1, static_cast<int>(std::ceil(u1 * w - 0.5)));
        const int y0 = std::max(0, static_cast<int>(std::floor((1 - v1) * h - 0.5)));
        const int y1 = std::min(h - 1, static_cast<int>(std::ceil((1 - v0) * h - 0.5)));
        for (int y = y0; y <= y1; ++y) {
            for (int x = x0; x <= x1; ++x) {
                const Eigen::Vector2d q = Eigen::Vector2d((x + 0.5) / w, 1.0 - (y + 0.5) / h) - a;
                const double b1 = (q.x() * (c - a).y() - q.y() * (c - a).x()) / det;
                const double b2 = ((b - a).x() * q.y() - (b - a).y() * q.x()) / det;
                if (b1 < 0 || b2 < 0 || b1 + b2 > 1) continue;
                out.push_back({static_cast<std::uint32_t>(y * w + x), static_cast<std::uint32_t>(t),
                               p0 + b1 * e1 + b2 * e2, extent});
            }
        }
    }
    return out;
}

/// Every mesh the check covers: the shared meshes and the real assets.
std::vector<fs::path> meshFiles() {
    std::vector<fs::path> out;
    for (const char* folder : {"meshes", "real-assets"}) {
        const fs::path root = fs::path(PLIMSOLL_SHARED_DIR) / folder;
        if (!fs::exists(root)) continue;
        for (const auto& entry : fs::recursive_directory_iterator(root)) {
            const std::string ext = entry.path().extension().string();
            if (ext != ".obj" && ext != ".fbx" && ext != ".glb" && ext != ".stl") continue;
            // The sanitized build leaves the largest meshes (spot, bunny, blub, the boat: 30k to
            // 100k triangles) to the normal build: the smaller ones run the same paint code.
            if (test::kSanitizedBuild && entry.file_size() > 300'000) continue;
            out.push_back(entry.path());
        }
    }
    std::sort(out.begin(), out.end());
    return out;
}

struct Painted {
    std::unique_ptr<Document> document;
    PaintedMap map;  ///< as saved and read back
};

fs::path freshProject(const fs::path& mesh, const std::string& tag) {
    const fs::path dir = fs::temp_directory_path() / "plimsoll_tests" /
                         ("coverage_" + tag + "_" + std::to_string(::getpid()));
    fs::remove_all(dir);
    fs::create_directories(dir);
    const fs::path path = dir / "p.plim.json";
    std::ofstream(path) << R"({"schema_version": 1, "name": "p", "bodies": [{"name": "b", "mesh": )"
                        << nlohmann::json(fs::absolute(mesh).string()).dump()
                        << R"(, "material": {"density": 500}}]})";
    return path;
}

/// The saved permeability map of the document's project.
std::optional<PaintedMap> savedMap(Document& d) {
    if (Status s = d.save(); !s) {
        ADD_FAILURE() << s.error().message;
        return std::nullopt;
    }
    Result<Project> saved = loadProject(d.path());
    if (!saved) return std::nullopt;
    Result<PaintedMap> map = loadPaintedMap(saved->resolvePath(saved->bodies[0].permeabilityMap));
    if (!map) {
        ADD_FAILURE() << map.error().message;
        return std::nullopt;
    }
    return std::move(map).value();
}

TEST(EditorPaintCoverage, FillAndStrokeLeaveNoUnpaintedPixelInsideThePaintedRegionOfEveryMesh) {
    const std::vector<fs::path> files = meshFiles();
    if (files.empty()) GTEST_SKIP() << "no ../shared/meshes or ../shared/real-assets";
    int checked = 0;
    for (const fs::path& file : files) {
        SCOPED_TRACE(file.string());
        const std::string tag = file.stem().string() + std::to_string(checked);
        Result<std::unique_ptr<Document>> opened = Document::open(freshProject(file, tag));
        if (!opened) continue;  // an asset the project cannot take (no body to paint)
        std::unique_ptr<Document> d = std::move(opened).value();
        const TriangleMesh& mesh = *d->assets(0).mesh;
        if (!mesh.hasUvs()) continue;
        ++checked;
        executeOrFail(*d,
                      makeNewMapCommand(*d, 0, MapChannel::Permeability, kSide, kSide, 0.0, ""));
        const std::vector<CoveredPixel> covered = coveredPixels(mesh, kSide, kSide);
        const std::vector<std::uint32_t> islands = uvIslands(mesh);

        // The fill: the biggest island whose pixels no other island's centres share, so that
        // what it must paint is its own pixels and no neighbour's.
        std::map<std::uint32_t, std::set<std::uint32_t>> islandsOfPixel;
        for (const CoveredPixel& c : covered) islandsOfPixel[c.pixel].insert(islands[c.triangle]);
        std::map<std::uint32_t, std::set<std::uint32_t>> pixelsOfIsland;
        std::set<std::uint32_t> shared;
        for (const auto& [pixel, owners] : islandsOfPixel) {
            for (std::uint32_t island : owners) pixelsOfIsland[island].insert(pixel);
            if (owners.size() > 1) shared.insert(owners.begin(), owners.end());
        }
        std::optional<std::uint32_t> fillIsland;
        for (const auto& [island, pixels] : pixelsOfIsland) {
            if (shared.contains(island) || pixels.size() < 50) continue;
            if (!fillIsland || pixels.size() > pixelsOfIsland[*fillIsland].size())
                fillIsland = island;
        }
        if (fillIsland) {
            // A point inside the island: the surface point of one of its covered pixels that
            // no other island's surface comes near (parts of a model can lie over each other,
            // and a fill names its island by the nearest surface).
            std::vector<const CoveredPixel*> own;
            for (const CoveredPixel& c : covered)
                if (islands[c.triangle] == *fillIsland) own.push_back(&c);
            const CoveredPixel* inside = nullptr;
            double clearance = -1;
            const std::size_t step = std::max<std::size_t>(1, own.size() / 16);
            for (std::size_t k = 0; k < own.size(); k += step) {
                double nearestOther = std::numeric_limits<double>::infinity();
                for (const CoveredPixel& c : covered)
                    if (islands[c.triangle] != *fillIsland)
                        nearestOther = std::min(nearestOther, (c.point - own[k]->point).norm());
                if (nearestOther / std::max(own[k]->extent, 1e-12) > clearance) {
                    clearance = nearestOther / std::max(own[k]->extent, 1e-12);
                    inside = own[k];
                }
            }
            ASSERT_NE(inside, nullptr);
            executeOrFail(*d, makeFillIslandCommand(*d, 0, MapChannel::Permeability, inside->point,
                                                    1.0, false));
            std::optional<PaintedMap> map = savedMap(*d);
            ASSERT_TRUE(map);
            std::size_t holes = 0;
            for (std::uint32_t pixel : pixelsOfIsland[*fillIsland])
                holes += map->values[pixel] != 1.0f;
            EXPECT_EQ(holes, 0u) << "of " << pixelsOfIsland[*fillIsland].size()
                                 << " pixels of the filled island";
            ASSERT_TRUE(d->undo());
        }

        // The stroke: two surface points a few radii apart, a constant brush of 5% of the
        // body's size. Every pixel whose centre's surface point lies within half the radius
        // of the stroke's line is painted: a dab, a quarter radius apart along the line, lies
        // within 0.625 radius of that point, which is on the pixel's own piece of surface.
        Eigen::Vector3d lo = mesh.positions[0], hi = lo;
        for (const Eigen::Vector3d& p : mesh.positions) {
            lo = lo.cwiseMin(p);
            hi = hi.cwiseMax(p);
        }
        Brush brush;
        brush.radius = 0.05 * (hi - lo).norm();
        brush.falloff = Falloff::Constant;
        const Eigen::Vector3d from = covered[covered.size() / 2].point;
        const auto far = std::find_if(covered.begin(), covered.end(), [&](const CoveredPixel& c) {
            return (c.point - from).norm() > 2 * brush.radius &&
                   (c.point - from).norm() < 4 * brush.radius;
        });
        const Eigen::Vector3d to = far != covered.end() ? far->point : from;
        const std::vector<Eigen::Vector3d> points{from, to};
        executeOrFail(*d, makeStrokeCommand(*d, 0, MapChannel::Permeability, brush, points));
        std::optional<PaintedMap> map = savedMap(*d);
        ASSERT_TRUE(map);
        std::size_t region = 0, holes = 0;
        for (const CoveredPixel& c : covered) {
            if (c.extent > brush.radius / 2) continue;  // a pixel stretched over much surface
            const Eigen::Vector3d segment = to - from;
            const double t =
                segment.squaredNorm() > 0
                    ? std::clamp((c.point - from).dot(segment) / segment.squaredNorm(), 0.0, 1.0)
                    : 0.0;
            if ((c.point - (from + t * segment)).norm() > brush.radius / 2) continue;
            ++region;
            holes += map->values[c.pixel] != 1.0f;
        }
        EXPECT_GT(region, 0u);
        EXPECT_EQ(holes, 0u) << "of " << region << " pixels under the stroke";
    }
    std::printf("  %d meshes with UVs checked\n", checked);
    EXPECT_GE(checked, 5) << "too few meshes with UVs loaded";
}

}  // namespace
}  // namespace test_editor_paint_coverage
}  // namespace plimsoll::editor
