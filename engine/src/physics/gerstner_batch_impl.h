// The body of the batched Gerstner evaluation (gerstner_batch.h), compiled once per
// instruction set: gerstner_batch_baseline.cpp and gerstner_batch_avx2.cpp include it inside
// namespace plimsoll::detail; its helpers are in an anonymous namespace, so that nothing
// compiled here for AVX2 can be linked into baseline code. Included only by those two files.
namespace {

/// Points per block: one single-precision batch of this build's widest registers.
using Lanes = xsimd::batch<float>;
constexpr std::size_t kBlock = Lanes::size;

/// theta reduced to [-pi, pi] (by the nearest multiple of 2 pi; the magic constant rounds to
/// an integer without a library call, so that the loop vectorises; exact while
/// |theta| < 2^51 * 2 pi).
inline double reducedPhase(double theta) {
    constexpr double kTwoPi = 6.283185307179586476925286766559;
    constexpr double kInverseTwoPi = 0.15915494309189533576888376337251;
    constexpr double kRound = 6755399441055744.0;  // 1.5 * 2^52
    const double turns = (theta * kInverseTwoPi + kRound) - kRound;
    // Beyond that range (a point some 1e15 m away) the angle is meaningless anyway; the clamp
    // keeps it convertible to single precision.
    return std::clamp(theta - turns * kTwoPi, -4.0, 4.0);
}

/// sin and cos (as requested) of each wave's phase at the block's undisplaced points.
struct BlockPhases {
    alignas(64) float angle[kBlock];
    alignas(64) float sine[kBlock];
    alignas(64) float cosine[kBlock];
};

inline void phasesOf(const GerstnerBatchWave& w, const double* x0, const double* z0, BlockPhases& p) {
    for (std::size_t l = 0; l < kBlock; ++l)
        p.angle[l] = static_cast<float>(reducedPhase(w.k * (w.dx * x0[l] + w.dz * z0[l]) + w.phase0));
}

/// The undisplaced points of a block (WaterModel's undisplaced: three fixed-point steps).
inline void undisplacedBlock(const GerstnerBatch& g, const double* x, const double* z, double* x0, double* z0) {
    for (std::size_t l = 0; l < kBlock; ++l) {
        x0[l] = x[l];
        z0[l] = z[l];
    }
    BlockPhases p;
    for (int iteration = 0; iteration < 3; ++iteration) {
        alignas(64) double sx[kBlock] = {}, sz[kBlock] = {};
        for (std::size_t i = 0; i < g.count; ++i) {
            const GerstnerBatchWave& w = g.waves[i];
            phasesOf(w, x0, z0, p);
            xsimd::sin(Lanes::load_aligned(p.angle)).store_aligned(p.sine);
            for (std::size_t l = 0; l < kBlock; ++l) {
                sx[l] += w.qa * p.sine[l] * w.dx;
                sz[l] += w.qa * p.sine[l] * w.dz;
            }
        }
        for (std::size_t l = 0; l < kBlock; ++l) {
            x0[l] = x[l] + sx[l];
            z0[l] = z[l] + sz[l];
        }
    }
}

/// Runs `block(first, count, x, y, z)` over whole blocks, padding the last one with its final
/// point (padded lanes are computed and dropped).
template <class Block>
void forBlocks(std::size_t n, const double* x, const double* y, const double* z, Block block) {
    alignas(64) double bx[kBlock], by[kBlock], bz[kBlock];
    for (std::size_t first = 0; first < n; first += kBlock) {
        const std::size_t count = std::min(kBlock, n - first);
        for (std::size_t l = 0; l < kBlock; ++l) {
            const std::size_t i = first + std::min(l, count - 1);
            bx[l] = x[i];
            by[l] = y ? y[i] : 0.0;
            bz[l] = z[i];
        }
        block(first, count, bx, by, bz);
    }
}

inline void heightsImpl(const GerstnerBatch& g, std::size_t n, const double* x, const double* z, double* out) {
    forBlocks(n, x, nullptr, z, [&](std::size_t first, std::size_t count, const double* bx, const double*,
                                    const double* bz) {
        alignas(64) double x0[kBlock], z0[kBlock], height[kBlock];
        undisplacedBlock(g, bx, bz, x0, z0);
        for (std::size_t l = 0; l < kBlock; ++l) height[l] = g.level;
        BlockPhases p;
        for (std::size_t i = 0; i < g.count; ++i) {
            const GerstnerBatchWave& w = g.waves[i];
            phasesOf(w, x0, z0, p);
            xsimd::cos(Lanes::load_aligned(p.angle)).store_aligned(p.cosine);
            for (std::size_t l = 0; l < kBlock; ++l) height[l] += w.amplitude * p.cosine[l];
        }
        for (std::size_t l = 0; l < count; ++l) out[first + l] = height[l];
    });
}

inline void velocitiesImpl(const GerstnerBatch& g, std::size_t n, const double* x, const double* y,
                           const double* z, double* out) {
    forBlocks(n, x, y, z, [&](std::size_t first, std::size_t count, const double* bx, const double* by,
                              const double* bz) {
        alignas(64) double x0[kBlock], z0[kBlock], v[3][kBlock] = {};
        undisplacedBlock(g, bx, bz, x0, z0);
        BlockPhases p;
        alignas(64) float depthScale[kBlock], decay[kBlock];
        for (std::size_t i = 0; i < g.count; ++i) {
            const GerstnerBatchWave& w = g.waves[i];
            phasesOf(w, x0, z0, p);
            const auto [sine, cosine] = xsimd::sincos(Lanes::load_aligned(p.angle));
            sine.store_aligned(p.sine);
            cosine.store_aligned(p.cosine);
            // Orbital motion decays as e^(k d) below the mean level (none above it).
            // (Clamped before the conversion: e^-80 is already 0 in single precision, and a
            // point far below would not fit a float.)
            for (std::size_t l = 0; l < kBlock; ++l)
                depthScale[l] = static_cast<float>(std::max(-80.0, w.k * std::min(0.0, by[l] - g.level)));
            xsimd::exp(Lanes::load_aligned(depthScale)).store_aligned(decay);
            for (std::size_t l = 0; l < kBlock; ++l) {
                const double horizontal = w.qa * w.omega * p.cosine[l] * decay[l];
                v[0][l] += horizontal * w.dx;
                v[1][l] += w.amplitude * w.omega * p.sine[l] * decay[l];
                v[2][l] += horizontal * w.dz;
            }
        }
        for (std::size_t l = 0; l < count; ++l)
            for (int c = 0; c < 3; ++c) out[3 * (first + l) + c] = v[c][l];
    });
}

}  // namespace

/// The exported entry points of one build (Suffix: Baseline or Avx2), outside the anonymous
/// namespace the body above lives in.
#define PLIMSOLL_GERSTNER_BATCH_ENTRY_POINTS(Suffix)                                                     \
    void gerstnerHeights##Suffix(const GerstnerBatch& g, std::size_t n, const double* x, const double* z, \
                                 double* out) {                                                         \
        heightsImpl(g, n, x, z, out);                                                                   \
    }                                                                                                   \
    void gerstnerVelocities##Suffix(const GerstnerBatch& g, std::size_t n, const double* x,              \
                                    const double* y, const double* z, double* out) {                    \
        velocitiesImpl(g, n, x, y, z, out);                                                             \
    }
