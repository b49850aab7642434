// Water models (water.h). The Gerstner evaluation mirrors kernels/buoyancy.cl line for line:
// the kernels are tested against this file.
#include "plimsoll/physics/water.h"

#include "gerstner_batch.h"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace plimsoll {

namespace {

/// Per-wave constants: wavenumber k, angular frequency omega (deep water: omega^2 = g k) and
/// the horizontal displacement factor Q_i = steepness / (k A n), which keeps the summed
/// surface free of loops for steepness <= 1 (GPU Gems 1, ch. 1).
struct WaveTerms {
    double k, omega, q;
    Eigen::Vector2d direction;
};

WaveTerms termsOf(const GerstnerWave& w, double gravity, std::size_t count) {
    WaveTerms t;
    t.k = 2.0 * std::numbers::pi / w.wavelength;
    t.omega = std::sqrt(gravity * t.k);
    t.q = w.amplitude > 0 ? w.steepness / (t.k * w.amplitude * static_cast<double>(count)) : 0.0;
    const double n = w.direction.norm();
    t.direction = n > 0 ? Eigen::Vector2d(w.direction / n) : Eigen::Vector2d(1.0, 0.0);
    return t;
}

/// One value per wave without allocating for up to kMaxGerstnerWaves waves (a query's tables).
template <class T>
class PerWave {
public:
    explicit PerWave(std::size_t count) : count_(count) {
        if (count_ > kMaxGerstnerWaves) spill_.resize(count_);  // more waves than the kernels take
    }
    T* data() { return count_ > kMaxGerstnerWaves ? spill_.data() : inline_; }
    const T* data() const { return count_ > kMaxGerstnerWaves ? spill_.data() : inline_; }
    std::size_t size() const { return count_; }

private:
    std::size_t count_;
    T inline_[kMaxGerstnerWaves];
    std::vector<T> spill_;
};

/// Every wave's constants (termsOf), worked out once per query rather than once per wave and
/// fixed-point step: the same values, so the same heights.
class WaveTable {
public:
    explicit WaveTable(const WaterModel& water) : terms_(water.waves.size()) {
        for (std::size_t i = 0; i < terms_.size(); ++i)
            terms_.data()[i] = termsOf(water.waves[i], water.gravity, terms_.size());
    }
    const WaveTerms& operator[](std::size_t i) const { return terms_.data()[i]; }

private:
    PerWave<WaveTerms> terms_;
};

/// The undisplaced horizontal position whose Gerstner surface point lies above (x, z): three
/// fixed-point steps x0 <- x + sum Q A D sin(theta(x0)) (contracting for steepness < 1).
Eigen::Vector2d undisplaced(const WaterModel& water, const WaveTable& terms, const Eigen::Vector2d& xz,
                            double time) {
    Eigen::Vector2d x0 = xz;
    for (int iteration = 0; iteration < 3; ++iteration) {
        Eigen::Vector2d shift = Eigen::Vector2d::Zero();
        for (std::size_t i = 0; i < water.waves.size(); ++i) {
            const GerstnerWave& w = water.waves[i];
            const WaveTerms& t = terms[i];
            const double theta = t.k * t.direction.dot(x0) - t.omega * time + w.phase;
            shift += t.q * w.amplitude * std::sin(theta) * t.direction;
        }
        x0 = xz + shift;
    }
    return x0;
}

double gridHeight(const HeightGrid& grid, double x, double z) {
    if (grid.countX == 0 || grid.countZ == 0) return 0.0;
    const double gx = (x - grid.origin.x()) / grid.spacing;
    const double gz = (z - grid.origin.y()) / grid.spacing;
    const double fx = gx - std::floor(gx), fz = gz - std::floor(gz);
    auto at = [&](double i, double j) {
        const int ci = std::clamp(static_cast<int>(i), 0, grid.countX - 1);
        const int cj = std::clamp(static_cast<int>(j), 0, grid.countZ - 1);
        return static_cast<double>(grid.heights[static_cast<std::size_t>(cj) * grid.countX + ci]);
    };
    // Clamp the cell index in floating point first: far outside the grid the edge value holds.
    const double i0 = std::clamp(std::floor(gx), -1.0, static_cast<double>(grid.countX));
    const double j0 = std::clamp(std::floor(gz), -1.0, static_cast<double>(grid.countZ));
    return (1 - fz) * ((1 - fx) * at(i0, j0) + fx * at(i0 + 1, j0)) +
           fz * ((1 - fx) * at(i0, j0 + 1) + fx * at(i0 + 1, j0 + 1));
}

}  // namespace

double WaterModel::height(double x, double z, double time) const {
    switch (kind) {
        case Kind::Flat:
            return level;
        case Kind::HeightField:
            return level + gridHeight(grid, x, z);
        case Kind::Gerstner: {
            const WaveTable terms(*this);
            const Eigen::Vector2d x0 = undisplaced(*this, terms, {x, z}, time);
            double y = level;
            for (std::size_t i = 0; i < waves.size(); ++i) {
                const GerstnerWave& w = waves[i];
                const WaveTerms& t = terms[i];
                y += w.amplitude * std::cos(t.k * t.direction.dot(x0) - t.omega * time + w.phase);
            }
            return y;
        }
    }
    return level;
}

Eigen::Vector3d WaterModel::velocity(const Eigen::Vector3d& point, double time) const {
    if (kind != Kind::Gerstner) return Eigen::Vector3d::Zero();
    const WaveTable terms(*this);
    const Eigen::Vector2d x0 = undisplaced(*this, terms, {point.x(), point.z()}, time);
    Eigen::Vector3d v = Eigen::Vector3d::Zero();
    for (std::size_t i = 0; i < waves.size(); ++i) {
        const GerstnerWave& w = waves[i];
        const WaveTerms& t = terms[i];
        const double theta = t.k * t.direction.dot(x0) - t.omega * time + w.phase;
        // Orbital motion of deep-water waves decays as e^(k d) below the mean level.
        const double decay = std::exp(t.k * std::min(0.0, point.y() - level));
        const double horizontal = t.q * w.amplitude * t.omega * std::cos(theta) * decay;
        v += Eigen::Vector3d(horizontal * t.direction.x(),
                             w.amplitude * t.omega * std::sin(theta) * decay,
                             horizontal * t.direction.y());
    }
    return v;
}

namespace {

/// The waves' constants for one batched call at `time` (gerstner_batch.h); no allocation for
/// up to kMaxGerstnerWaves waves.
class BatchWaves {
public:
    BatchWaves(const WaterModel& water, double time) : waves_(water.waves.size()) {
        const WaveTable terms(water);
        for (std::size_t i = 0; i < waves_.size(); ++i) {
            const WaveTerms& t = terms[i];
            const GerstnerWave& w = water.waves[i];
            // phase - omega t to [-pi, pi] in double: the single-precision sines see small angles.
            const double phase0 = std::remainder(w.phase - t.omega * time, 2.0 * std::numbers::pi);
            waves_.data()[i] = {w.amplitude, t.k, t.omega, t.q * w.amplitude, t.direction.x(), t.direction.y(), phase0};
        }
    }
    detail::GerstnerBatch batch(double level) const { return {waves_.data(), waves_.size(), level}; }

private:
    PerWave<detail::GerstnerBatchWave> waves_;
};

}  // namespace

void WaterModel::heights(std::size_t n, const double* x, const double* z, double time, double* out) const {
    if (kind != Kind::Gerstner || waves.empty()) {
        for (std::size_t i = 0; i < n; ++i) out[i] = height(x[i], z[i], time);
        return;
    }
    const BatchWaves w(*this, time);
    const detail::GerstnerBatch batch = w.batch(level);
    detail::gerstnerBatchBuild().heights(batch, n, x, z, out);
}

void WaterModel::velocities(std::size_t n, const double* x, const double* y, const double* z, double time,
                            double* out) const {
    if (kind != Kind::Gerstner || waves.empty()) {
        for (std::size_t i = 0; i < 3 * n; ++i) out[i] = 0.0;
        return;
    }
    const BatchWaves w(*this, time);
    const detail::GerstnerBatch batch = w.batch(level);
    detail::gerstnerBatchBuild().velocities(batch, n, x, y, z, out);
}

double WaterModel::maxHeight() const {
    switch (kind) {
        case Kind::Flat:
            return level;
        case Kind::Gerstner: {
            double sum = 0;
            for (const GerstnerWave& w : waves) sum += std::abs(w.amplitude);
            return level + sum;
        }
        case Kind::HeightField:
            return grid.heights.empty()
                       ? level
                       : level + *std::max_element(grid.heights.begin(), grid.heights.end());
    }
    return level;
}

double WaterModel::minHeight() const {
    switch (kind) {
        case Kind::Flat:
            return level;
        case Kind::Gerstner:
            return 2.0 * level - maxHeight();
        case Kind::HeightField:
            return grid.heights.empty()
                       ? level
                       : level + *std::min_element(grid.heights.begin(), grid.heights.end());
    }
    return level;
}

}  // namespace plimsoll
