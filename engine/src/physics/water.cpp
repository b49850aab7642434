// Water models (water.h). The one-point formulas are the evaluation core's
// (plimsoll_eval/water.hpp, which the runtime compiles too); kernels/buoyancy.cl mirrors them
// line for line and is tested against this file, and the vectorised batch (gerstner_batch.h)
// is held to them within its stated bound (tests/physics/test_water.cpp).
#include "plimsoll/physics/water.h"

#include "gerstner_batch.h"

#include "plimsoll_eval/water.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace plimsoll {

namespace {

namespace ev = plimsoll_eval;

/// Every wave's constants (plimsoll_eval::water_detail::termsOf), worked out once per query
/// rather than once per wave and fixed-point step; no allocation for up to 16 waves.
ev::WaveTable waveTable(const WaterModel& water) {
    return ev::WaveTable(water.waves, water.gravity,
                         [](const GerstnerWave& w, double& x, double& z) {
                             x = w.direction.x();
                             z = w.direction.y();
                         });
}

/// One value per wave without allocating for up to kMaxGerstnerWaves waves (a batch's tables).
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

}  // namespace

// The scalar models are the evaluation core's formulas (plimsoll_eval/water.hpp), the ones the
// runtime compiles: one reference for both.

double WaterModel::height(double x, double z, double time) const {
    switch (kind) {
        case Kind::Flat:
            return level;
        case Kind::HeightField:
            return level + ev::water_detail::gridHeight(grid.heights.data(), grid.countX,
                                                        grid.countZ, grid.spacing, grid.origin.x(),
                                                        grid.origin.y(), x, z);
        case Kind::Gerstner: {
            const ev::WaveTable terms = waveTable(*this);
            return ev::water_detail::gerstnerHeight(terms.data(), terms.size(), level, x, z, time);
        }
    }
    return level;
}

Eigen::Vector3d WaterModel::velocity(const Eigen::Vector3d& point, double time) const {
    if (kind != Kind::Gerstner) return Eigen::Vector3d::Zero();
    const ev::WaveTable terms = waveTable(*this);
    Eigen::Vector3d v;
    ev::water_detail::gerstnerVelocity(terms.data(), terms.size(), level, point.x(), point.y(),
                                       point.z(), time, v.data());
    return v;
}

namespace {

/// The waves' constants for one batched call at `time` (gerstner_batch.h); no allocation for
/// up to kMaxGerstnerWaves waves.
class BatchWaves {
public:
    BatchWaves(const WaterModel& water, double time) : waves_(water.waves.size()) {
        const ev::WaveTable terms = waveTable(water);
        for (std::size_t i = 0; i < waves_.size(); ++i) {
            const ev::water_detail::WaveTerms& t = terms[i];
            // phase - omega t to [-pi, pi] in double: the single-precision sines see small angles.
            const double phase0 = std::remainder(t.phase - t.omega * time, 2.0 * std::numbers::pi);
            waves_.data()[i] = {t.amplitude, t.k, t.omega, t.q * t.amplitude, t.dx, t.dz, phase0};
        }
    }
    detail::GerstnerBatch batch(double level) const {
        return {waves_.data(), waves_.size(), level};
    }

private:
    PerWave<detail::GerstnerBatchWave> waves_;
};

}  // namespace

void WaterModel::heights(std::size_t n, const double* x, const double* z, double time,
                         double* out) const {
    if (kind != Kind::Gerstner || waves.empty()) {
        for (std::size_t i = 0; i < n; ++i) out[i] = height(x[i], z[i], time);
        return;
    }
    const BatchWaves w(*this, time);
    const detail::GerstnerBatch batch = w.batch(level);
    detail::gerstnerBatchBuild().heights(batch, n, x, z, out);
}

void WaterModel::velocities(std::size_t n, const double* x, const double* y, const double* z,
                            double time, double* out) const {
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
        case Kind::Gerstner:
            return level + ev::water_detail::amplitudeSum(waves);
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
