// The box mesh (box.h).
#include "plimsoll/geometry/box.h"

#include <algorithm>
#include <utility>

namespace plimsoll {

TriangleMesh makeBox(const Eigen::Vector3d& size) {
    const Eigen::Vector3d half = 0.5 * size;

    // Per face: outward normal axis and the 3D directions of u and v (u x v = normal), so each
    // chart is counter-clockwise in UV seen from outside.
    struct Face {
        Eigen::Vector3d normal, u, v;
    };
    const Eigen::Vector3d X = Eigen::Vector3d::UnitX();
    const Eigen::Vector3d Y = Eigen::Vector3d::UnitY();
    const Eigen::Vector3d Z = Eigen::Vector3d::UnitZ();
    // Top row of the grid: +x, +y, +z; bottom row: -x, -y, -z. A column holds one axis, so its
    // two faces have the same size.
    const Face faces[6] = {{X, -Z, Y}, {Y, X, -Z}, {Z, X, Y}, {-X, Z, Y}, {-Y, X, Z}, {-Z, -X, Y}};

    // One scale (UV units per metre) for all faces: uniform texel density.
    double columnWidth[3];
    double columnHeight[3];
    double widthSum = 0.0;
    double heightMax = 0.0;
    for (int c = 0; c < 3; ++c) {
        columnWidth[c] = faces[c].u.cwiseAbs().dot(size);
        columnHeight[c] = faces[c].v.cwiseAbs().dot(size);
        widthSum += columnWidth[c];
        heightMax = std::max(heightMax, columnHeight[c]);
    }
    const double scale =
        std::min((1.0 - 2.0 * kGeneratedChartMargin - 2.0 * kGeneratedChartGutter) / widthSum,
                 (1.0 - 2.0 * kGeneratedChartMargin - kGeneratedChartGutter) / (2.0 * heightMax));

    // Chart corners in (u, v) order, counter-clockwise.
    constexpr std::pair<int, int> kCorners[4] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
    TriangleMesh mesh;
    mesh.source = "generated:box";
    double columnLeft = kGeneratedChartMargin;
    for (int c = 0; c < 3; ++c) {
        for (int row = 0; row < 2; ++row) {
            const Face& f = faces[c + 3 * row];
            const Eigen::Vector2d origin(
                columnLeft, row == 0 ? 1.0 - kGeneratedChartMargin - scale * columnHeight[c]
                                     : kGeneratedChartMargin);
            const std::uint32_t first = static_cast<std::uint32_t>(mesh.positions.size());
            for (const auto& [a, b] : kCorners) {
                // Each coordinate is exactly +-half: corners shared by three faces weld.
                const Eigen::Vector3d p =
                    (f.normal + (2.0 * a - 1.0) * f.u + (2.0 * b - 1.0) * f.v).cwiseProduct(half);
                const Eigen::Vector2d uv =
                    origin + scale * Eigen::Vector2d(a * columnWidth[c], b * columnHeight[c]);
                mesh.positions.push_back(p);
                mesh.uvs.push_back(uv);
            }
            mesh.triangles.push_back({first, first + 1, first + 2});
            mesh.triangles.push_back({first, first + 2, first + 3});
        }
        columnLeft += scale * columnWidth[c] + kGeneratedChartGutter;
    }
    return mesh;
}

}  // namespace plimsoll
