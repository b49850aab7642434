#include "view/water_view.h"

#include <algorithm>
#include <cmath>

namespace plimsoll::editor {

WaterView WaterView::of(const WaterModel& water, double time, const Camera& camera) {
    WaterView v;
    v.camera = camera;
    const double half = std::max(10.0, camera.distance * 3.0);
    v.step = 2 * half / kCells;
    v.x0 = camera.target.x() - half;
    v.z0 = camera.target.z() - half;
    constexpr int n = kCells + 1;
    std::vector<double> x(n * n), z(n * n), h(n * n);
    for (int j = 0; j < n; ++j) {
        for (int i = 0; i < n; ++i) {
            x[j * n + i] = v.x0 + i * v.step;
            z[j * n + i] = v.z0 + j * v.step;
        }
    }
    water.heights(h.size(), x.data(), z.data(), time, h.data());
    v.heights.assign(h.begin(), h.end());
    return v;
}

double WaterView::heightAt(double x, double z) const {
    // As waterHeightAt in water_view.frag, in the same single precision for the samples.
    const double gx = std::clamp((x - x0) / step, 0.0, double(kCells));
    const double gz = std::clamp((z - z0) / step, 0.0, double(kCells));
    const int i = std::min(static_cast<int>(std::floor(gx)), kCells - 1);
    const int j = std::min(static_cast<int>(std::floor(gz)), kCells - 1);
    const double fx = gx - i, fz = gz - j;
    auto at = [&](int di, int dj) { return double(heights[(j + dj) * (kCells + 1) + i + di]); };
    if (fx >= fz) return at(0, 0) + fx * (at(1, 0) - at(0, 0)) + fz * (at(1, 1) - at(1, 0));
    return at(0, 0) + fz * (at(0, 1) - at(0, 0)) + fx * (at(1, 1) - at(0, 1));
}

std::vector<Eigen::Vector3f> WaterView::surfaceSegments(float lift) const {
    std::vector<Eigen::Vector3f> points;
    surfaceSegments(lift, points);
    return points;
}

void WaterView::surfaceSegments(float lift, std::vector<Eigen::Vector3f>& points) const {
    constexpr int n = kCells + 1;
    points.clear();
    if (heights.size() != std::size_t(n) * n) return;
    points.reserve(std::size_t(4) * kCells * n);
    auto at = [&](int i, int j) {
        return Eigen::Vector3f(float(x0 + i * step), heights[std::size_t(j) * n + i] + lift,
                               float(z0 + j * step));
    };
    for (int j = 0; j < n; ++j) {
        for (int i = 0; i < kCells; ++i) {
            points.push_back(at(i, j));  // along x
            points.push_back(at(i + 1, j));
            points.push_back(at(j, i));  // along z
            points.push_back(at(j, i + 1));
        }
    }
}

bool WaterView::seenThrough(const Eigen::Vector3d& p) const {
    const Eigen::Vector3d eye = camera.eye();
    const Eigen::Vector3d forward = camera.forward();
    const Eigen::Vector3d start =
        camera.orthographic ? Eigen::Vector3d(p - forward * forward.dot(p - eye)) : eye;
    return below(p) != below(start);
}

bool WaterView::backgroundSeenThrough(const Eigen::Vector3d& origin,
                                      const Eigen::Vector3d& direction) const {
    return below(origin) ? direction.y() > 0 : direction.y() < 0;
}

WaterView::Backdrop WaterView::backdrop(int width, int height) const {
    auto seenThroughAtRow = [&](int row) {
        Eigen::Vector3d origin, direction;
        camera.rayThrough(0.5 * width, row + 0.5, width, height, origin, direction);
        return backgroundSeenThrough(origin, direction);
    };
    Backdrop b;
    b.height = std::max(height, 0);
    b.topSeenThrough = seenThroughAtRow(0);
    // The first row that differs from the top one (one change at most: no roll). Bisection:
    // rows [0, lo) are the top's, rows [hi, height) are not, or hi = height.
    int lo = 1, hi = height;
    if (height <= 0 || seenThroughAtRow(height - 1) == b.topSeenThrough) {
        b.split = std::max(height, 0);
        return b;
    }
    hi = height - 1;
    while (lo < hi) {
        const int mid = lo + (hi - lo) / 2;
        if (seenThroughAtRow(mid) == b.topSeenThrough)
            lo = mid + 1;
        else
            hi = mid;
    }
    b.split = lo;
    return b;
}

}  // namespace plimsoll::editor
