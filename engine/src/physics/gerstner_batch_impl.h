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

/// Waves whose phases a block keeps between the steps of its search (the phases of any
/// further ones are formed again at each step).
constexpr std::size_t kKeptWaves = 16;

/// Each wave's phase at the block's points, k D.x + phase0, formed and reduced to [-pi, pi] in
/// double (by the nearest multiple of 2 pi; the magic constant 1.5 * 2^52 rounds to an integer
/// without a library call; exact while |theta| < 2^51 * 2 pi; beyond that, a point some 1e15 m
/// away, the angle is meaningless anyway and the clamp to [-4, 4] keeps it convertible to
/// single precision). In double batches: written as a loop over the block's points, GCC
/// unrolled it into scalar code with branches.
inline void basePhases(const GerstnerBatchWave& w, const double* x, const double* z, float* out) {
    using Doubles = xsimd::batch<double>;
    alignas(64) double reduced[kBlock];
    const Doubles kdx(w.k * w.dx), kdz(w.k * w.dz), phase0(w.phase0);
    for (std::size_t l = 0; l < kBlock; l += Doubles::size) {
        const Doubles theta = xsimd::fma(kdx, Doubles::load_aligned(x + l),
                                         xsimd::fma(kdz, Doubles::load_aligned(z + l), phase0));
        const Doubles turns =
            (theta * Doubles(0.15915494309189533576888376337251) + Doubles(6755399441055744.0)) -
            Doubles(6755399441055744.0);
        const Doubles angle = xsimd::fnma(turns, Doubles(6.283185307179586476925286766559), theta);
        xsimd::min(Doubles(4.0), xsimd::max(Doubles(-4.0), angle)).store_aligned(reduced + l);
    }
    for (std::size_t l = 0; l < kBlock; ++l) out[l] = static_cast<float>(reduced[l]);
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

    /// Wave i's phase at the undisplaced points.
    Lanes angleAt(const GerstnerBatch& g, std::size_t i, const double* x, const double* z) {
        const GerstnerBatchWave& w = g.waves[i];
        if (i >= kKeptWaves) basePhases(w, x, z, spare);
        const float* phase = i < kKeptWaves ? base[i] : spare;
        const Lanes kdx(static_cast<float>(w.k * w.dx)), kdz(static_cast<float>(w.k * w.dz));
        return xsimd::fma(kdx, Lanes::load_aligned(sx),
                          xsimd::fma(kdz, Lanes::load_aligned(sz), Lanes::load_aligned(phase)));
    }
};

/// The undisplaced points of a block (WaterModel's undisplaced: three fixed-point steps
/// x0 <- x + sum Q A D sin(theta(x0))).
inline void undisplacedBlock(const GerstnerBatch& g, const double* x, const double* z,
                             BlockSearch& search) {
    for (std::size_t i = 0; i < std::min(g.count, kKeptWaves); ++i)
        basePhases(g.waves[i], x, z, search.base[i]);
    Lanes(0.0f).store_aligned(search.sx);
    Lanes(0.0f).store_aligned(search.sz);
    for (int iteration = 0; iteration < 3; ++iteration) {
        Lanes sx(0.0f), sz(0.0f);
        for (std::size_t i = 0; i < g.count; ++i) {
            const GerstnerBatchWave& w = g.waves[i];
            const Lanes sine = FoldedPhase(search.angleAt(g, i, x, z)).sin();
            sx = xsimd::fma(Lanes(static_cast<float>(w.qa * w.dx)), sine, sx);
            sz = xsimd::fma(Lanes(static_cast<float>(w.qa * w.dz)), sine, sz);
        }
        sx.store_aligned(search.sx);
        sz.store_aligned(search.sz);
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

inline void heightsImpl(const GerstnerBatch& g, std::size_t n, const double* x, const double* z,
                        double* out) {
    forBlocks(n, x, nullptr, z,
              [&](std::size_t first, std::size_t count, const double* bx, const double*,
                  const double* bz) {
                  BlockSearch search;
                  undisplacedBlock(g, bx, bz, search);
                  // The height about the level in single precision (the waves' sum, a few metres at
                  // most, to 1e-7 of it), the level added in double.
                  Lanes height(0.0f);
                  alignas(64) float above[kBlock];
                  for (std::size_t i = 0; i < g.count; ++i)
                      height = xsimd::fma(Lanes(static_cast<float>(g.waves[i].amplitude)),
                                          FoldedPhase(search.angleAt(g, i, bx, bz)).cos(), height);
                  height.store_aligned(above);
                  for (std::size_t l = 0; l < count; ++l) out[first + l] = g.level + above[l];
              });
}

inline void velocitiesImpl(const GerstnerBatch& g, std::size_t n, const double* x, const double* y,
                           const double* z, double* out) {
    forBlocks(
        n, x, y, z,
        [&](std::size_t first, std::size_t count, const double* bx, const double* by,
            const double* bz) {
            BlockSearch search;
            undisplacedBlock(g, bx, bz, search);
            // The depth below the level (none above it), in single precision: clamped first, as a
            // point far below would not fit a float (e^(k d) is 0 in single precision long before).
            alignas(64) float depth[kBlock];
            for (std::size_t l = 0; l < kBlock; ++l)
                depth[l] = static_cast<float>(std::max(-1e6, std::min(0.0, by[l] - g.level)));
            const Lanes below = Lanes::load_aligned(depth);
            // The velocity in single precision (the waves' sum, a few m/s, to 1e-7 of it).
            Lanes vx(0.0f), vy(0.0f), vz(0.0f);
            for (std::size_t i = 0; i < g.count; ++i) {
                const GerstnerBatchWave& w = g.waves[i];
                const FoldedPhase phase(search.angleAt(g, i, bx, bz));  // folded once for both
                // Orbital motion decays as e^(k d) below the mean level.
                const Lanes decay =
                    xsimd::exp(xsimd::max(Lanes(-80.0f), Lanes(static_cast<float>(w.k)) * below));
                const Lanes horizontal =
                    Lanes(static_cast<float>(w.qa * w.omega)) * phase.cos() * decay;
                vx = xsimd::fma(horizontal, Lanes(static_cast<float>(w.dx)), vx);
                vy = xsimd::fma(Lanes(static_cast<float>(w.amplitude * w.omega)) * phase.sin(),
                                decay, vy);
                vz = xsimd::fma(horizontal, Lanes(static_cast<float>(w.dz)), vz);
            }
            alignas(64) float v[3][kBlock];
            vx.store_aligned(v[0]);
            vy.store_aligned(v[1]);
            vz.store_aligned(v[2]);
            for (std::size_t l = 0; l < count; ++l)
                for (int c = 0; c < 3; ++c) out[3 * (first + l) + c] = v[c][l];
        });
}

}  // namespace

/// The exported entry points of one build (Suffix: Baseline or Avx2), outside the anonymous
/// namespace the body above lives in.
#define PLIMSOLL_GERSTNER_BATCH_ENTRY_POINTS(Suffix)                                        \
    void gerstnerHeights##Suffix(const GerstnerBatch& g, std::size_t n, const double* x,    \
                                 const double* z, double* out) {                            \
        heightsImpl(g, n, x, z, out);                                                       \
    }                                                                                       \
    void gerstnerVelocities##Suffix(const GerstnerBatch& g, std::size_t n, const double* x, \
                                    const double* y, const double* z, double* out) {        \
        velocitiesImpl(g, n, x, y, z, out);                                                 \
    }
