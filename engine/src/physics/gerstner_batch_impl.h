// The body of the batched Gerstner evaluation (gerstner_batch.h), compiled once per
// instruction set: gerstner_batch_baseline.cpp and gerstner_batch_avx2.cpp include it inside
// namespace plimsoll::detail; its helpers are in an anonymous namespace, so that nothing
// compiled here for AVX2 can be linked into baseline code. Included only by those two files.
namespace {

/// Points per block: one single-precision batch of this build's widest registers.
using Lanes = xsimd::batch<float>;
constexpr std::size_t kBlock = Lanes::size;

/// Sines and cosines in single precision for the phases here (already reduced to [-pi, pi] in
/// double, then shifted by k D.s, a few tenths of a radian): one reduction by the nearest
/// multiple of 2 pi, a fold of |x| to [0, pi/2] (sin and -cos of pi - |x| beyond pi/2, pi in
/// two parts so that the fold rounds once), shared by the sine and the cosine of one angle, and
/// a polynomial there (least-squares fits on
/// Chebyshev nodes: sine to x^9 within 4.6e-9, cosine to x^10 within 2.4e-10). xsimd's sin and
/// cos, made for any angle, reduce in three steps and evaluate both polynomials: a third of a
/// batch's time. Over [-8, 8] both are within 1.2e-7 of the double-precision functions,
/// measured on a 1e-5 rad grid.
struct FoldedPhase {
    Lanes y, y2;                             ///< |x| reduced and folded to [0, pi/2], and y^2
    xsimd::batch_bool<float> negative, far;  ///< x < 0 (the sine's sign); |x| > pi/2 (the cosine's)

    explicit FoldedPhase(Lanes x) {
        const Lanes turns = xsimd::nearbyint(x * Lanes(0.159154943f));
        x = xsimd::fnma(turns, Lanes(6.28318548f), x);
        x = xsimd::fnma(turns, Lanes(-1.74845553e-7f), x);  // 2 pi - 6.28318548f
        negative = x < Lanes(0.0f);
        y = xsimd::abs(x);
        far = y > Lanes(1.57079637f);
        // pi - y, pi in two parts: exact up to the one rounding of the sum.
        y = xsimd::select(far, (Lanes(3.14159274f) - y) + Lanes(-8.74227801e-8f), y);
        y2 = y * y;
    }
    Lanes sin() const {
        Lanes p(2.60005397e-6f);
        p = xsimd::fma(p, y2, Lanes(-1.98066148e-4f));
        p = xsimd::fma(p, y2, Lanes(8.33301728e-3f));
        p = xsimd::fma(p, y2, Lanes(-1.66666571e-1f));
        const Lanes sine = xsimd::fma(p * y2, y, y);
        return xsimd::select(negative, -sine, sine);
    }
    Lanes cos() const {
        Lanes p(-2.60771016e-7f);
        p = xsimd::fma(p, y2, Lanes(2.47618860e-5f));
        p = xsimd::fma(p, y2, Lanes(-1.38884035e-3f));
        p = xsimd::fma(p, y2, Lanes(4.16666407e-2f));
        p = xsimd::fma(p, y2, Lanes(-4.99999995e-1f));
        const Lanes cosine = xsimd::fma(p, y2, Lanes(1.0f));
        return xsimd::select(far, -cosine, cosine);
    }
};

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

/// Waves whose phases a block keeps between the steps of its search (the phases of any
/// further ones are formed again at each step).
constexpr std::size_t kKeptWaves = 16;

/// Each wave's phase at the block's points, k D.x + phase0, formed and reduced in double.
inline void basePhases(const GerstnerBatchWave& w, const double* x, const double* z, float* out) {
    for (std::size_t l = 0; l < kBlock; ++l)
        out[l] = static_cast<float>(reducedPhase(w.k * (w.dx * x[l] + w.dz * z[l]) + w.phase0));
}

/// A block's undisplaced points x0 = x + s: the shift s (at most the sum of the waves' Q A, so
/// single precision holds it to 1e-8 m) and each wave's phase at x, from which the phase at x0
/// is that plus k D.s. The double-precision phase, the costly part, is formed once a point
/// rather than once a step.
struct BlockSearch {
    alignas(64) float sx[kBlock];
    alignas(64) float sz[kBlock];
    alignas(64) float base[kKeptWaves][kBlock];
    alignas(64) float spare[kBlock];  // the phase of a wave beyond kKeptWaves, formed when asked

    /// Wave i's phase at the undisplaced points, into `angle`.
    void angleAt(const GerstnerBatch& g, std::size_t i, const double* x, const double* z, float* angle) {
        const GerstnerBatchWave& w = g.waves[i];
        if (i >= kKeptWaves) basePhases(w, x, z, spare);
        const float* phase = i < kKeptWaves ? base[i] : spare;
        const float kdx = static_cast<float>(w.k * w.dx), kdz = static_cast<float>(w.k * w.dz);
        for (std::size_t l = 0; l < kBlock; ++l) angle[l] = phase[l] + kdx * sx[l] + kdz * sz[l];
    }
};

/// The undisplaced points of a block (WaterModel's undisplaced: three fixed-point steps
/// x0 <- x + sum Q A D sin(theta(x0))).
inline void undisplacedBlock(const GerstnerBatch& g, const double* x, const double* z, BlockSearch& search) {
    for (std::size_t i = 0; i < std::min(g.count, kKeptWaves); ++i) basePhases(g.waves[i], x, z, search.base[i]);
    for (std::size_t l = 0; l < kBlock; ++l) search.sx[l] = search.sz[l] = 0.0f;
    alignas(64) float angle[kBlock], sine[kBlock];
    for (int iteration = 0; iteration < 3; ++iteration) {
        alignas(64) float sx[kBlock] = {}, sz[kBlock] = {};
        for (std::size_t i = 0; i < g.count; ++i) {
            const GerstnerBatchWave& w = g.waves[i];
            search.angleAt(g, i, x, z, angle);
            FoldedPhase(Lanes::load_aligned(angle)).sin().store_aligned(sine);
            const float qdx = static_cast<float>(w.qa * w.dx), qdz = static_cast<float>(w.qa * w.dz);
            for (std::size_t l = 0; l < kBlock; ++l) {
                sx[l] += qdx * sine[l];
                sz[l] += qdz * sine[l];
            }
        }
        for (std::size_t l = 0; l < kBlock; ++l) {
            search.sx[l] = sx[l];
            search.sz[l] = sz[l];
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
        BlockSearch search;
        undisplacedBlock(g, bx, bz, search);
        alignas(64) double height[kBlock];
        alignas(64) float angle[kBlock], cosine[kBlock];
        for (std::size_t l = 0; l < kBlock; ++l) height[l] = g.level;
        for (std::size_t i = 0; i < g.count; ++i) {
            search.angleAt(g, i, bx, bz, angle);
            FoldedPhase(Lanes::load_aligned(angle)).cos().store_aligned(cosine);
            for (std::size_t l = 0; l < kBlock; ++l) height[l] += g.waves[i].amplitude * cosine[l];
        }
        for (std::size_t l = 0; l < count; ++l) out[first + l] = height[l];
    });
}

inline void velocitiesImpl(const GerstnerBatch& g, std::size_t n, const double* x, const double* y,
                           const double* z, double* out) {
    forBlocks(n, x, y, z, [&](std::size_t first, std::size_t count, const double* bx, const double* by,
                              const double* bz) {
        BlockSearch search;
        undisplacedBlock(g, bx, bz, search);
        alignas(64) double v[3][kBlock] = {};
        alignas(64) float angle[kBlock], sineOf[kBlock], cosineOf[kBlock];
        alignas(64) float depthScale[kBlock], decay[kBlock];
        for (std::size_t i = 0; i < g.count; ++i) {
            const GerstnerBatchWave& w = g.waves[i];
            search.angleAt(g, i, bx, bz, angle);
            const FoldedPhase phase(Lanes::load_aligned(angle));  // folded once for both
            phase.sin().store_aligned(sineOf);
            phase.cos().store_aligned(cosineOf);
            // Orbital motion decays as e^(k d) below the mean level (none above it).
            // (Clamped before the conversion: e^-80 is already 0 in single precision, and a
            // point far below would not fit a float.)
            for (std::size_t l = 0; l < kBlock; ++l)
                depthScale[l] = static_cast<float>(std::max(-80.0, w.k * std::min(0.0, by[l] - g.level)));
            xsimd::exp(Lanes::load_aligned(depthScale)).store_aligned(decay);
            for (std::size_t l = 0; l < kBlock; ++l) {
                const double horizontal = w.qa * w.omega * cosineOf[l] * decay[l];
                v[0][l] += horizontal * w.dx;
                v[1][l] += w.amplitude * w.omega * sineOf[l] * decay[l];
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
