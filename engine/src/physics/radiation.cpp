// Radiation panel method (radiation.h). Formulation (docs/radiation.md):
//
//   phi(x) = int_S sigma(s) G(x, s) dS   (the 1/(4 pi) of the source strength folded into sigma)
//   d phi/dn (x_i) = sum_j sigma_j D_ij = n_i . (mode velocity)   at every centroid x_i,
//
// with D_ii carrying the flat panel's own limit -2 pi (seen from the water, the normal pointing
// into it) and G = 1/r + 1/r' + G_wave. Then A and B follow from the pressure -rho d phi/dt
// integrated over the panels: with time dependence e^{i omega t},
//   -(i omega A + B) = i omega rho int phi_j n_k dS.
//
// The wave part (Wehausen & Laitone 1960, eq. 13.17; Newman 1985, J. Eng. Math. 19):
//   G_wave = 2 K PV int_0^inf e^{k (y + eta)} J0(k R) / (k - K) dk - i 2 pi K e^{K (y + eta)} J0(K
//   R),
// the imaginary sign being the outgoing wave for e^{i omega t}. With X = K R, Y = -K (y + eta),
// F(X, Y) = PV int e^{-m Y} J0(m X) / (m - 1) dm obeys dF/dY + F = -1 / sqrt(X^2 + Y^2), so
//   F(X, Y) = -(pi/2) e^{-Y} (H0(X) + Y0(X)) - int_0^Y e^{t - Y} / sqrt(X^2 + t^2) dt
// (the value at Y = 0 is the classical PV int J0(m X) / (m - 1) dm = -(pi/2)(H0 + Y0)), and
//   dF/dX = e^{-Y} ((pi/2)(H1(X) + Y1(X)) - 1) + int_0^Y e^{t - Y} X / (X^2 + t^2)^{3/2} dt.
// Both remaining integrals are smooth and short; they are done by Gauss-Legendre pieces.
#include "plimsoll/physics/radiation.h"

#include <Eigen/Dense>
#include <boost/math/special_functions/bessel.hpp>

#include <algorithm>
#include <atomic>
#include <cassert>
#include <cmath>
#include <cstdint>
#include <limits>
#include <map>
#include <memory>
#include <mutex>
#include <numbers>
#include <thread>
#include <vector>

namespace plimsoll {

namespace {

constexpr double kPi = std::numbers::pi;

// Bessel functions of integer order from Boost.Math (rational approximations), kept in double:
// about ten times faster than std::cyl_bessel_j and std::cyl_neumann, the same to 1e-12. They
// are most of the cost of the wave part.
using DoublePolicy = boost::math::policies::policy<boost::math::policies::promote_double<false>>;
double besselJ(int order, double x) { return boost::math::cyl_bessel_j(order, x, DoublePolicy()); }
double besselY(int order, double x) { return boost::math::cyl_neumann(order, x, DoublePolicy()); }

// 8-point Gauss-Legendre on [-1, 1].
constexpr std::array<double, 8> kGaussNodes = {
    -0.9602898564975363, -0.7966664774136267, -0.5255324099163290, -0.1834346424956498,
    0.1834346424956498,  0.5255324099163290,  0.7966664774136267,  0.9602898564975363};
constexpr std::array<double, 8> kGaussWeights = {
    0.1012285362903763, 0.2223810344533745, 0.3137066458778873, 0.3626837833783620,
    0.3626837833783620, 0.3137066458778873, 0.2223810344533745, 0.1012285362903763};

template <class F>
void gaussPiece(double a, double b, F&& f) {
    const double half = 0.5 * (b - a);
    const double mid = 0.5 * (a + b);
    for (std::size_t q = 0; q < kGaussNodes.size(); ++q)
        f(mid + half * kGaussNodes[q], half * kGaussWeights[q]);
}

// (H_nu - Y_nu)(x) for large x (Abramowitz & Stegun 12.1.29):
// (1/pi) sum_k Gamma(k + 1/2) / Gamma(nu + 1/2 - k) (x/2)^(nu - 2k - 1), stopped at its
// smallest term.
double struveMinusNeumannAsymptotic(int nu, double x) {
    double term = nu == 0 ? 2.0 / x : 2.0;
    double sum = term;
    const double q = 4.0 / (x * x);
    for (int k = 0; k < 40; ++k) {
        const double next = term * (k + 0.5) * (nu - 0.5 - k) * q;
        if (std::abs(next) >= std::abs(term) || std::abs(next) < 1e-17 * std::abs(sum)) break;
        sum += next;
        term = next;
    }
    return sum / kPi;
}

constexpr double kStruveSeriesLimit = 16.0;

double struveSeries(int nu, double x) {
    // H0 = (2/pi) sum (-1)^k x^(2k+1) / ((2k+1)!!)^2 ;
    // H1 = (2/pi) sum (-1)^k x^(2k+2) / ((2k+1)!! (2k+3)!!)   (A&S 12.1.3)
    const double x2 = x * x;
    double term = nu == 0 ? x : x2 / 3.0;
    double sum = term;
    for (int k = 0; k < 200; ++k) {
        term *=
            nu == 0 ? -x2 / ((2.0 * k + 3) * (2.0 * k + 3)) : -x2 / ((2.0 * k + 3) * (2.0 * k + 5));
        sum += term;
        if (std::abs(term) < 1e-17 * std::abs(sum) && k > x) break;
    }
    return 2.0 / kPi * sum;
}

// int_{t0}^{Y} e^{t-Y} / sqrt(X^2 + t^2) dt and int e^{t-Y} X / (X^2 + t^2)^{3/2} dt.
// Below e^{-40} the integrand is dropped; pieces of length 2 in t keep the exponential smooth
// on each, and the first piece near t = 0 goes through t = X sinh u when X is small, which
// takes out the near-singularity 1/sqrt(X^2 + t^2).
void tailIntegrals(double X, double Y, double& t0Integral, double& t1Integral) {
    t0Integral = 0;
    t1Integral = 0;
    if (Y <= 0) return;
    const double start = std::max(0.0, Y - 40.0);
    const double firstEnd = std::min(Y, start + 2.0);
    // The integrands in t, where 1/sqrt(X^2 + t^2) is smooth.
    auto inT = [&](double t, double w) {
        const double e = std::exp(t - Y);
        const double r2 = X * X + t * t;
        const double r = std::sqrt(r2);
        t0Integral += w * e / r;
        t1Integral += w * e * X / (r2 * r);
    };
    if (start == 0.0 && X < firstEnd) {
        const double uEnd = std::asinh(firstEnd / X);
        const int pieces = std::max(1, static_cast<int>(std::ceil(uEnd / 1.5)));
        for (int p = 0; p < pieces; ++p) {
            gaussPiece(uEnd * p / pieces, uEnd * (p + 1) / pieces, [&](double u, double w) {
                const double e = std::exp(X * std::sinh(u) - Y);
                const double c = std::cosh(u);
                t0Integral += w * e;
                t1Integral += w * e / (X * c * c);
            });
        }
    } else {
        gaussPiece(start, firstEnd, inT);
    }
    const int rest = static_cast<int>(std::ceil((Y - firstEnd) / 2.0 - 1e-12));
    for (int p = 0; p < rest; ++p) {
        const double a = firstEnd + (Y - firstEnd) * p / rest;
        const double b = firstEnd + (Y - firstEnd) * (p + 1) / rest;
        gaussPiece(a, b, inT);
    }
}

Eigen::Vector3d mirrored(const Eigen::Vector3d& p) { return {p.x(), -p.y(), p.z()}; }

double longestEdge(const RadiationPanel& panel) {
    const auto& v = panel.vertices;
    return std::max({(v[1] - v[0]).norm(), (v[2] - v[1]).norm(), (v[0] - v[2]).norm()});
}

// Three-point rule (degree 2) on a triangle: points at (2/3, 1/6, 1/6) and permutations.
std::array<Eigen::Vector3d, 3> threePoints(const RadiationPanel& panel) {
    const auto& v = panel.vertices;
    return {(4.0 * v[0] + v[1] + v[2]) / 6.0, (v[0] + 4.0 * v[1] + v[2]) / 6.0,
            (v[0] + v[1] + 4.0 * v[2]) / 6.0};
}

// Calls f(triangle, area) on the 4^levels triangles of a midpoint subdivision.
template <class F>
void subdivide(const std::array<Eigen::Vector3d, 3>& t, int levels, F&& f) {
    if (levels == 0) {
        f(t, 0.5 * (t[1] - t[0]).cross(t[2] - t[0]).norm());
        return;
    }
    const Eigen::Vector3d m01 = 0.5 * (t[0] + t[1]), m12 = 0.5 * (t[1] + t[2]),
                          m20 = 0.5 * (t[2] + t[0]);
    subdivide({t[0], m01, m20}, levels - 1, f);
    subdivide({m01, t[1], m12}, levels - 1, f);
    subdivide({m20, m12, t[2]}, levels - 1, f);
    subdivide({m01, m12, m20}, levels - 1, f);
}

// Calls rowWork(i) for every i in [0, n) on up to settings' threads (0: the hardware's), rows
// handed out one at a time. Each row's results do not depend on which thread computes it, so
// the matrices are bit-identical for any thread count.
template <class F>
void forEachRow(Eigen::Index n, unsigned threads, F&& rowWork) {
    const unsigned available =
        threads ? threads : std::max(1u, std::thread::hardware_concurrency());
    const unsigned count =
        static_cast<unsigned>(std::min<Eigen::Index>(available, std::max<Eigen::Index>(n, 1)));
    std::atomic<Eigen::Index> next{0};
    auto worker = [&] {
        for (Eigen::Index i = next++; i < n; i = next++) rowWork(i);
    };
    std::vector<std::thread> pool;
    for (unsigned t = 1; t < count; ++t) pool.emplace_back(worker);
    worker();
    for (auto& t : pool) t.join();
}

// The part of F that the panel rules and the table cannot follow near the origin (Newman 1985,
// J. Eng. Math. 19: F = -e^{-Y} (ln((rho + Y) / 2) + gamma) - rho + a smooth rest, rho =
// sqrt(X^2 + Y^2)): the logarithm and the cone, with their derivatives. What is left,
// F - waveSingular, is continuous with a bounded gradient (ln 2 - gamma at the origin).
WaveGreen waveSingular(double X, double Y) {
    X = std::max(X, 1e-9);
    const double rho = std::sqrt(X * X + Y * Y);
    const double e = std::exp(-Y);
    const double l = std::log(rho + Y);
    WaveGreen s;
    s.value = -e * l - rho;
    s.dX = -X * (e / (rho * (rho + Y)) + 1.0 / rho);
    s.dY = e * l - (e + Y) / rho;
    return s;
}

// F and its X derivative on a grid in (X, Y), interpolated by cubic Lagrange polynomials on
// 4 x 4 nodes (docs/radiation.md "The wave kernel's table" has the measured error). Two grids:
// 1/16 on [0, 4)^2 holding F - waveSingular (smooth, where F is not), and 1/4 on [0, 96) x
// [0, 48) holding F itself (used where X or Y is at least 3.8: F is smooth there); outside,
// waveGreen itself. Tiles of 16 x 16 cells are filled on first use (a body
// needs a part of the range; each node is one waveGreen, a few microseconds), so the table
// costs only what its bodies touch. A node's value does not depend on the order or the thread
// that fills it: the results are the same for any thread count.
class WaveTable {
public:
    static const WaveTable& instance() {
        static const WaveTable table;
        return table;
    }

    /// F and dF/dX at (X, Y) (dF/dY = -1/rho - F); false outside the grids.
    bool lookup(double X, double Y, double& value, double& dX) const {
        const bool nearOrigin = X < kFineExtent - 3 * kFineStep && Y < kFineExtent - 3 * kFineStep;
        const Grid& g = nearOrigin ? fine_ : coarse_;
        const double u = X / g.step, v = Y / g.step;
        if (!(u < g.tilesX * kTileCells) || !(v < g.tilesY * kTileCells) || !(u >= 0) || !(v >= 0))
            return false;
        const int i0 = std::max(static_cast<int>(u) - 1, 0),
                  j0 = std::max(static_cast<int>(v) - 1, 0);
        const Tile& tile = g.tile(i0 / kTileCells, j0 / kTileCells);
        double wx[4], wy[4];
        lagrangeWeights(u - i0, wx);
        lagrangeWeights(v - j0, wy);
        const int a0 = i0 % kTileCells, b0 = j0 % kTileCells;
        double t = 0, tX = 0;
        for (int b = 0; b < 4; ++b) {
            const double* row =
                &tile.values[static_cast<std::size_t>(2 * ((b0 + b) * kTileNodes + a0))];
            double rt = 0, rX = 0;
            for (int a = 0; a < 4; ++a) {
                rt += wx[a] * row[2 * a];
                rX += wx[a] * row[2 * a + 1];
            }
            t += wy[b] * rt;
            tX += wy[b] * rX;
        }
        if (!nearOrigin) {
            value = t;
            dX = tX;
            return true;
        }
        const WaveGreen s = waveSingular(X, Y);
        value = t + s.value;
        dX = tX + s.dX;
        return true;
    }

    /// J0 and J1 at x (cubic interpolation on 1/32 below the coarse grid's X extent, else
    /// Boost.Math).
    void bessel01(double x, double& j0, double& j1) const {
        const double u = x * kBesselPerUnit;
        if (!(u < static_cast<double>(bessel_.size() / 2 - 3))) {
            j0 = besselJ(0, x);
            j1 = besselJ(1, x);
            return;
        }
        const int i0 = std::max(static_cast<int>(u) - 1, 0);
        double w[4];
        lagrangeWeights(u - i0, w);
        j0 = j1 = 0;
        for (int a = 0; a < 4; ++a) {
            j0 += w[a] * bessel_[static_cast<std::size_t>(2 * (i0 + a))];
            j1 += w[a] * bessel_[static_cast<std::size_t>(2 * (i0 + a) + 1)];
        }
    }

private:
    static constexpr int kTileCells = 16;
    static constexpr int kTileNodes = kTileCells + 3;
    static constexpr double kFineStep = 1.0 / 16, kFineExtent = 4.0;
    static constexpr double kCoarseStep = 0.25, kCoarseExtentX = 96.0, kCoarseExtentY = 48.0;
    static constexpr double kBesselPerUnit = 32.0;

    struct Tile {
        std::once_flag filled;
        std::vector<double> values;  ///< (F (less singular), its d/dX) per node, rows of constant Y
    };
    struct Grid {
        double step = 0;
        int tilesX = 0, tilesY = 0;
        std::unique_ptr<Tile[]> tiles;

        bool lessSingular = false;  ///< F - waveSingular, else F itself (away from the origin)

        Grid(double step_, double extentX, double extentY, bool lessSingular_)
            : step(step_),
              tilesX(static_cast<int>(std::ceil(extentX / step_ / kTileCells))),
              tilesY(static_cast<int>(std::ceil(extentY / step_ / kTileCells))),
              tiles(new Tile[static_cast<std::size_t>(tilesX * tilesY)]),
              lessSingular(lessSingular_) {}

        const Tile& tile(int a, int b) const {
            Tile& t = tiles[static_cast<std::size_t>(b * tilesX + a)];
            std::call_once(t.filled, [&] { fill(t, a, b); });
            return t;
        }

        void fill(Tile& t, int a, int b) const {
            t.values.resize(2 * kTileNodes * kTileNodes);
            for (int j = 0; j < kTileNodes; ++j) {
                for (int i = 0; i < kTileNodes; ++i) {
                    const double X = (a * kTileCells + i) * step, Y = (b * kTileCells + j) * step;
                    double* node = &t.values[static_cast<std::size_t>(2 * (j * kTileNodes + i))];
                    if (X == 0 && Y == 0) {
                        node[0] = std::numbers::ln2 - std::numbers::egamma;
                        node[1] = 0;
                        continue;
                    }
                    const WaveGreen f = waveGreen(X, Y);
                    const WaveGreen s = lessSingular ? waveSingular(X, Y) : WaveGreen{};
                    node[0] = f.value - s.value;
                    // On X = 0 both derivatives vanish by symmetry (waveGreen's dX is not
                    // computed there).
                    node[1] = X == 0 ? 0.0 : f.dX - s.dX;
                }
            }
        }
    };

    WaveTable()
        : fine_(kFineStep, kFineExtent, kFineExtent, true),
          coarse_(kCoarseStep, kCoarseExtentX, kCoarseExtentY, false) {
        const auto count = static_cast<std::size_t>(kCoarseExtentX * kBesselPerUnit) + 4;
        bessel_.resize(2 * count);
        for (std::size_t k = 0; k < count; ++k) {
            const double x = static_cast<double>(k) / kBesselPerUnit;
            bessel_[2 * k] = besselJ(0, x);
            bessel_[2 * k + 1] = besselJ(1, x);
        }
    }

    // Cubic Lagrange weights of nodes 0..3 at t in [0, 3].
    static void lagrangeWeights(double t, double* w) {
        const double a = t, b = t - 1, c = t - 2, d = t - 3;
        w[0] = -b * c * d / 6;
        w[1] = a * c * d / 2;
        w[2] = -a * b * d / 2;
        w[3] = a * b * c / 6;
    }

    Grid fine_, coarse_;
    std::vector<double> bessel_;  ///< (J0, J1) at k / kBesselPerUnit
};

}  // namespace

double struveH0(double x) {
    if (x < kStruveSeriesLimit) return struveSeries(0, x);
    return struveMinusNeumannAsymptotic(0, x) + besselY(0, x);
}

double struveH1(double x) {
    if (x < kStruveSeriesLimit) return struveSeries(1, x);
    return struveMinusNeumannAsymptotic(1, x) + besselY(1, x);
}

WaveGreen waveGreen(double X, double Y) {
    assert(Y >= 0);
    // On the vertical through the source Y0 and the integral both diverge like ln X and cancel;
    // a tiny floor keeps them finite (d/dX vanishes there by symmetry and is not used).
    X = std::max(X, 1e-9);
    const double y0 = besselY(0, X);
    const double y1 = besselY(1, X);
    double hy0, hy1;  // H0 + Y0, H1 + Y1
    if (X < kStruveSeriesLimit) {
        hy0 = struveSeries(0, X) + y0;
        hy1 = struveSeries(1, X) + y1;
    } else {
        hy0 = struveMinusNeumannAsymptotic(0, X) + 2.0 * y0;
        hy1 = struveMinusNeumannAsymptotic(1, X) + 2.0 * y1;
    }
    double t0, t1;
    tailIntegrals(X, Y, t0, t1);
    const double eY = std::exp(-Y);
    WaveGreen g;
    g.value = -0.5 * kPi * eY * hy0 - t0;
    g.dX = eY * (0.5 * kPi * hy1 - 1.0) + t1;
    g.dY = -1.0 / std::sqrt(X * X + Y * Y) - g.value;
    return g;
}

WaveGreen tabulatedWaveGreen(double X, double Y) {
    WaveGreen g;
    if (!WaveTable::instance().lookup(X, Y, g.value, g.dX)) return waveGreen(X, Y);
    g.dY = -1.0 / std::sqrt(X * X + Y * Y) - g.value;
    return g;
}

RankineIntegral rankineTriangle(const std::array<Eigen::Vector3d, 3>& triangle,
                                const Eigen::Vector3d& r) {
    // Wilton, Rao, Glisson, Schaubert, Al-Bundak & Butler (1984), eqs. (4) and (6): per edge,
    // with the point projected onto the plane, s-/s+ the edge ends along the edge, t0 the
    // signed distance to the edge line (positive inside), R-/R+ the distances to the ends.
    const Eigen::Vector3d areaVector = (triangle[1] - triangle[0]).cross(triangle[2] - triangle[0]);
    const Eigen::Vector3d n = areaVector.normalized();
    const double h = (r - triangle[0]).dot(n);
    const Eigen::Vector3d rho = r - h * n;
    const double absH = std::abs(h);
    RankineIntegral out;
    double solidAngle = 0;
    Eigen::Vector3d inPlane = Eigen::Vector3d::Zero();
    for (int e = 0; e < 3; ++e) {
        const Eigen::Vector3d& a = triangle[e];
        const Eigen::Vector3d& b = triangle[(e + 1) % 3];
        const Eigen::Vector3d l = (b - a).normalized();
        const Eigen::Vector3d u = l.cross(n);
        const double sMinus = (a - rho).dot(l);
        const double sPlus = (b - rho).dot(l);
        const double t0 = (a - rho).dot(u);
        const double rMinus = (r - a).norm();
        const double rPlus = (r - b).norm();
        const double r0Squared = t0 * t0 + h * h;
        // ln((R+ + s+)/(R- + s-)) = ln((R- - s-)/(R+ - s+)); take the better-conditioned form.
        const double logTerm = (sMinus + sPlus >= 0)
                                   ? std::log((rPlus + sPlus) / (rMinus + sMinus))
                                   : std::log((rMinus - sMinus) / (rPlus - sPlus));
        // On the edge's line (t0 = 0) the edge subtends no solid angle; the guard keeps a
        // point in the panel's plane (coplanar neighbours) from dividing 0 by 0.
        const double beta = t0 == 0.0 ? 0.0
                                      : std::atan(t0 * sPlus / (r0Squared + absH * rPlus)) -
                                            std::atan(t0 * sMinus / (r0Squared + absH * rMinus));
        out.potential += t0 * logTerm;
        solidAngle += beta;
        inPlane -= u * logTerm;
    }
    out.potential -= absH * solidAngle;
    const double side = h > 0 ? 1.0 : (h < 0 ? -1.0 : 0.0);
    out.gradient = inPlane - side * solidAngle * n;
    return out;
}

std::vector<RadiationPanel> wettedPanels(const TriangleMesh& surface,
                                         const Eigen::Affine3d& toWater, double minArea) {
    std::vector<RadiationPanel> panels;
    auto emit = [&](const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c) {
        const Eigen::Vector3d areaVector = 0.5 * (b - a).cross(c - a);
        const double area = areaVector.norm();
        if (area <= minArea) return;
        panels.push_back({{a, b, c}, (a + b + c) / 3.0, areaVector / area, area});
    };
    // Vertices within rounding of the surface count as on it: no sliver panels at a vertex
    // ring on the waterline.
    std::vector<Eigen::Vector3d> placed(surface.positions.size());
    double extent = 0;
    for (std::size_t k = 0; k < placed.size(); ++k) {
        placed[k] = toWater * surface.positions[k];
        extent = std::max(extent, placed[k].cwiseAbs().maxCoeff());
    }
    for (Eigen::Vector3d& p : placed) {
        if (std::abs(p.y()) <= 1e-12 * extent) p.y() = 0;
    }
    for (const Triangle& t : surface.triangles) {
        const std::array<Eigen::Vector3d, 3> v = {placed[t[0]], placed[t[1]], placed[t[2]]};
        // Sutherland-Hodgman against the half-space y <= 0: at most four vertices come out.
        std::array<Eigen::Vector3d, 4> polygon;
        int count = 0;
        for (int k = 0; k < 3; ++k) {
            const Eigen::Vector3d& p = v[k];
            const Eigen::Vector3d& q = v[(k + 1) % 3];
            const bool pIn = p.y() <= 0;
            const bool qIn = q.y() <= 0;
            if (pIn) polygon[count++] = p;
            if (pIn != qIn) {
                const double s = p.y() / (p.y() - q.y());
                Eigen::Vector3d cut = p + s * (q - p);
                cut.y() = 0;
                polygon[count++] = cut;
            }
        }
        if (count >= 3) emit(polygon[0], polygon[1], polygon[2]);
        if (count == 4) emit(polygon[0], polygon[2], polygon[3]);
    }
    return panels;
}

namespace {

/// How many times refinedPanels halves `p`'s edges for `maxEdge`.
int refinementLevels(const RadiationPanel& p, double maxEdge) {
    const int levels =
        maxEdge > 0 ? std::max(0, static_cast<int>(std::ceil(std::log2(longestEdge(p) / maxEdge))))
                    : 0;
    return std::min(levels, 8);
}

/// refinedPanels(panels, maxEdge).size(), without making them.
double refinedCount(const std::vector<RadiationPanel>& panels, double maxEdge) {
    double count = 0;
    for (const RadiationPanel& p : panels)
        count += std::ldexp(1.0, 2 * refinementLevels(p, maxEdge));
    return count;
}

}  // namespace

std::vector<RadiationPanel> refinedPanels(const std::vector<RadiationPanel>& panels,
                                          double maxEdge) {
    std::vector<RadiationPanel> out;
    for (const RadiationPanel& p : panels) {
        subdivide(p.vertices, refinementLevels(p, maxEdge),
                  [&](const std::array<Eigen::Vector3d, 3>& t, double area) {
                      out.push_back({t, (t[0] + t[1] + t[2]) / 3.0, p.normal, area});
                  });
    }
    return out;
}

std::vector<RadiationPanel> bisectedPanels(const std::vector<RadiationPanel>& panels,
                                           double maxEdge, std::size_t limit) {
    std::vector<RadiationPanel> out;
    std::vector<std::array<Eigen::Vector3d, 3>> pending;
    for (const RadiationPanel& p : panels) {
        pending.push_back(p.vertices);
        while (!pending.empty()) {
            const std::array<Eigen::Vector3d, 3> t = pending.back();
            pending.pop_back();
            int longest = 0;
            double length = 0;
            for (int k = 0; k < 3; ++k) {
                const double l = (t[(k + 1) % 3] - t[k]).norm();
                if (l > length) {
                    length = l;
                    longest = k;
                }
            }
            if (!(maxEdge > 0) || length <= maxEdge) {
                const double area = 0.5 * (t[1] - t[0]).cross(t[2] - t[0]).norm();
                out.push_back({t, (t[0] + t[1] + t[2]) / 3.0, p.normal, area});
                if (out.size() > limit) return out;
                continue;
            }
            // Halves at the longest edge's midpoint, both keeping the orientation.
            const Eigen::Vector3d& a = t[longest];
            const Eigen::Vector3d& b = t[(longest + 1) % 3];
            const Eigen::Vector3d& c = t[(longest + 2) % 3];
            const Eigen::Vector3d m = 0.5 * (a + b);
            pending.push_back({a, m, c});
            pending.push_back({m, b, c});
        }
    }
    return out;
}

TriangleMesh clusteredMesh(const TriangleMesh& mesh, double cell) {
    TriangleMesh out;
    out.source = mesh.source;
    if (!(cell > 0)) {
        out.positions = mesh.positions;
        out.triangles = mesh.triangles;
        return out;
    }
    // Welded by position (a UV seam repeats its vertices), then clustered by grid cell.
    std::map<std::array<std::int64_t, 3>, int> clusterOfCell;
    std::map<std::array<double, 3>, int> clusterOfPosition;
    std::vector<Eigen::Vector3d> sum;
    std::vector<int> count;
    std::vector<int> clusterOfVertex(mesh.positions.size());
    for (std::size_t v = 0; v < mesh.positions.size(); ++v) {
        const Eigen::Vector3d& p = mesh.positions[v];
        auto [at, added] = clusterOfPosition.try_emplace({p.x(), p.y(), p.z()}, 0);
        if (added) {
            const std::array<std::int64_t, 3> key = {
                static_cast<std::int64_t>(std::floor(p.x() / cell)),
                static_cast<std::int64_t>(std::floor(p.y() / cell)),
                static_cast<std::int64_t>(std::floor(p.z() / cell))};
            auto [c, newCluster] = clusterOfCell.try_emplace(key, static_cast<int>(sum.size()));
            if (newCluster) {
                sum.push_back(Eigen::Vector3d::Zero());
                count.push_back(0);
            }
            at->second = c->second;
            sum[static_cast<std::size_t>(c->second)] += p;
            ++count[static_cast<std::size_t>(c->second)];
        }
        clusterOfVertex[v] = at->second;
    }
    // Each cluster at its vertex nearest the mean: on the surface, where the mean of a curved
    // patch lies inside it (the sample sphere's heave A came out 11% low with the means).
    std::vector<double> nearest(sum.size(), std::numeric_limits<double>::infinity());
    out.positions.resize(sum.size());
    for (const auto& [position, c] : clusterOfPosition) {
        const Eigen::Vector3d p(position[0], position[1], position[2]);
        const auto k = static_cast<std::size_t>(c);
        const double d = (p - sum[k] / count[k]).squaredNorm();
        if (d < nearest[k]) {
            nearest[k] = d;
            out.positions[k] = p;
        }
    }
    // Each triangle's clusters, counted with its orientation: two faces that meet the other way
    // round cancel, so the result bounds what the mesh bounded (a closed mesh stays closed:
    // every edge is still met as often each way round), thin parts collapsing to nothing.
    std::map<std::array<int, 3>, int> net;
    std::vector<std::array<int, 3>> order;
    for (const Triangle& t : mesh.triangles) {
        const std::array<int, 3> c = {clusterOfVertex[static_cast<std::size_t>(t[0])],
                                      clusterOfVertex[static_cast<std::size_t>(t[1])],
                                      clusterOfVertex[static_cast<std::size_t>(t[2])]};
        if (c[0] == c[1] || c[1] == c[2] || c[2] == c[0]) continue;  // collapsed
        // Rotated so that the smallest comes first; the orientation is then the order of the rest.
        const int first = static_cast<int>(std::min_element(c.begin(), c.end()) - c.begin());
        const std::array<int, 3> r = {c[static_cast<std::size_t>(first)],
                                      c[static_cast<std::size_t>((first + 1) % 3)],
                                      c[static_cast<std::size_t>((first + 2) % 3)]};
        const bool even = r[1] < r[2];
        const std::array<int, 3> key = even ? r : std::array<int, 3>{r[0], r[2], r[1]};
        auto [it, added] = net.try_emplace(key, 0);
        if (added) order.push_back(key);
        it->second += even ? 1 : -1;
    }
    for (const std::array<int, 3>& key : order) {
        const int n = net[key];
        for (int k = 0; k < std::abs(n); ++k) {
            const auto v = [&](int j) {
                return static_cast<std::uint32_t>(key[static_cast<std::size_t>(j)]);
            };
            out.triangles.push_back(n > 0 ? Triangle{v(0), v(1), v(2)}
                                          : Triangle{v(0), v(2), v(1)});
        }
    }
    return out;
}

namespace {

// Signed area of a closed polygon in the (x, z) plane: positive when it turns from x towards z.
double signedAreaXz(const std::vector<Eigen::Vector3d>& loop) {
    double twice = 0;
    for (std::size_t k = 0; k < loop.size(); ++k) {
        const Eigen::Vector3d& a = loop[k];
        const Eigen::Vector3d& b = loop[(k + 1) % loop.size()];
        twice += a.x() * b.z() - b.x() * a.z();
    }
    return 0.5 * twice;
}

double crossXz(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c) {
    return (b.x() - a.x()) * (c.z() - a.z()) - (b.z() - a.z()) * (c.x() - a.x());
}

// The waterline of the wetted panels as closed loops of points on y = 0: the panel edges with
// both ends on the surface, chained end to start. Ends match within `tolerance` (clipping cuts
// a shared edge from both of its triangles, not always to the same last bit).
std::vector<std::vector<Eigen::Vector3d>> waterlineLoops(const std::vector<RadiationPanel>& wetted,
                                                         double tolerance) {
    std::vector<std::array<Eigen::Vector3d, 2>> edges;
    for (const RadiationPanel& p : wetted) {
        const auto& v = p.vertices;
        if (v[0].y() == 0 && v[1].y() == 0 && v[2].y() == 0) continue;  // a panel in the surface
        for (int e = 0; e < 3; ++e) {
            const Eigen::Vector3d& a = v[e];
            const Eigen::Vector3d& b = v[(e + 1) % 3];
            if (a.y() == 0 && b.y() == 0 && (a - b).norm() > tolerance) edges.push_back({a, b});
        }
    }
    std::vector<bool> used(edges.size(), false);
    std::vector<std::vector<Eigen::Vector3d>> loops;
    for (std::size_t first = 0; first < edges.size(); ++first) {
        if (used[first]) continue;
        used[first] = true;
        std::vector<Eigen::Vector3d> loop = {edges[first][0]};
        Eigen::Vector3d end = edges[first][1];
        bool closed = false;
        while (true) {
            if ((end - loop.front()).norm() <= tolerance) {
                closed = true;
                break;
            }
            std::size_t next = edges.size();
            for (std::size_t e = 0; e < edges.size(); ++e) {
                if (!used[e] && (edges[e][0] - end).norm() <= tolerance) {
                    next = e;
                    break;
                }
            }
            if (next == edges.size()) break;  // an open chain: not a waterline
            used[next] = true;
            loop.push_back(edges[next][0]);
            end = edges[next][1];
        }
        if (closed && loop.size() >= 3) loops.push_back(std::move(loop));
    }
    return loops;
}

// Triangles covering a loop of positive orientation: rings about its centroid when every fan
// triangle from there turns the right way (a star-shaped loop), else ear clipping.
std::vector<std::array<Eigen::Vector3d, 3>> coverLoop(const std::vector<Eigen::Vector3d>& loop,
                                                      double edge, double gap, int maxRings,
                                                      bool& star) {
    const std::size_t m = loop.size();
    const double area = signedAreaXz(loop);
    Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
    for (std::size_t k = 0; k < m; ++k) {
        const Eigen::Vector3d& a = loop[k];
        const Eigen::Vector3d& b = loop[(k + 1) % m];
        centroid += (a + b) * (a.x() * b.z() - b.x() * a.z());
    }
    centroid /= 6.0 * area;
    centroid.y() = 0;
    star = true;
    double reach = 0;
    for (std::size_t k = 0; k < m; ++k) {
        star = star && crossXz(centroid, loop[k], loop[(k + 1) % m]) > 1e-9 * area;
        reach = std::max(reach, (loop[k] - centroid).norm());
    }
    std::vector<std::array<Eigen::Vector3d, 3>> out;
    if (star) {
        const int rings =
            std::clamp(static_cast<int>(std::ceil((reach - gap) / edge)), 1, std::max(1, maxRings));
        // Each ray from the centroid stops `gap` short of the waterline (at most halfway).
        auto ring = [&](int l, std::size_t k) -> Eigen::Vector3d {
            const Eigen::Vector3d ray = loop[k % m] - centroid;
            const double reachHere = std::max(0.5, 1.0 - gap / ray.norm());
            return centroid + reachHere * (static_cast<double>(l) / rings) * ray;
        };
        for (std::size_t k = 0; k < m; ++k) {
            out.push_back({centroid, ring(1, k), ring(1, k + 1)});
            for (int l = 1; l < rings; ++l) {
                out.push_back({ring(l, k), ring(l + 1, k), ring(l + 1, k + 1)});
                out.push_back({ring(l, k), ring(l + 1, k + 1), ring(l, k + 1)});
            }
        }
        return out;
    }
    std::vector<Eigen::Vector3d> rest = loop;
    while (rest.size() > 3) {
        bool clipped = false;
        for (std::size_t k = 0; k < rest.size() && !clipped; ++k) {
            const Eigen::Vector3d& a = rest[(k + rest.size() - 1) % rest.size()];
            const Eigen::Vector3d& b = rest[k];
            const Eigen::Vector3d& c = rest[(k + 1) % rest.size()];
            if (crossXz(a, b, c) <= 0) continue;  // reflex or flat
            bool empty = true;
            for (const Eigen::Vector3d& p : rest) {
                if (&p == &a || &p == &b || &p == &c) continue;
                if (crossXz(a, b, p) >= 0 && crossXz(b, c, p) >= 0 && crossXz(c, a, p) >= 0)
                    empty = false;
            }
            if (!empty) continue;
            out.push_back({a, b, c});
            rest.erase(rest.begin() + static_cast<std::ptrdiff_t>(k));
            clipped = true;
        }
        if (!clipped) break;  // self-intersecting: leave the remainder open
    }
    if (rest.size() == 3) out.push_back({rest[0], rest[1], rest[2]});
    return out;
}

}  // namespace

std::vector<RadiationPanel> waterplaneLid(const std::vector<RadiationPanel>& wetted,
                                          double maxEdge) {
    double extent = 0;
    for (const RadiationPanel& p : wetted) {
        for (const Eigen::Vector3d& v : p.vertices)
            extent = std::max(extent, v.cwiseAbs().maxCoeff());
    }
    const auto loops = waterlineLoops(wetted, 1e-9 * std::max(extent, 1e-300));
    double waterplaneArea = 0;
    for (const auto& loop : loops) waterplaneArea += std::max(0.0, signedAreaXz(loop));
    std::vector<RadiationPanel> lid;
    for (const auto& loop : loops) {
        const double loopArea = signedAreaXz(loop);
        if (loopArea <= 0) continue;  // an opening in the waterplane
        double perimeter = 0;
        for (std::size_t k = 0; k < loop.size(); ++k)
            perimeter += (loop[(k + 1) % loop.size()] - loop[k]).norm();
        const double meanEdge = perimeter / static_cast<double>(loop.size());
        const double edge = maxEdge > 0 ? maxEdge : 1.5 * meanEdge;
        std::vector<RadiationPanel> cover;
        bool star = false;
        // Every ring repeats the loop's vertices (2 rings - 1 triangles per loop edge): at most
        // half as many lid panels as the body has, so that a long, finely cut waterline (a
        // hull's) does not multiply the unknowns.
        const int maxRings =
            static_cast<int>((0.5 * static_cast<double>(wetted.size()) / loop.size() + 1) / 2);
        for (const auto& t : coverLoop(loop, edge, 0.5 * meanEdge, std::min(maxRings, 16), star)) {
            // Reordered so that the normal points up.
            const std::array<Eigen::Vector3d, 3> up = {t[0], t[2], t[1]};
            const double area = 0.5 * (up[1] - up[0]).cross(up[2] - up[0]).norm();
            if (area > 0)
                cover.push_back(
                    {up, (up[0] + up[1] + up[2]) / 3.0, Eigen::Vector3d::UnitY(), area});
        }
        if (!star) {
            // Split to `edge` (the rings are sized already), within the loop's share by area of
            // the rings' bound, half as many panels as the body has: a finely cut waterline that
            // is not star-shaped (a flooded hull's) made 4177 lid panels for 164 on the body, and
            // minutes for every frequency. Coarser splits until it fits; the ear-clipped cover is
            // the coarsest.
            const double budget =
                std::max(1.0, 0.5 * static_cast<double>(wetted.size()) * loopArea / waterplaneArea);
            double splitEdge = edge;
            while (maxEdge <= 0 &&
                   refinedCount(cover, splitEdge) > std::max(budget, double(cover.size())))
                splitEdge *= 2;
            cover = refinedPanels(cover, splitEdge);
        }
        lid.insert(lid.end(), cover.begin(), cover.end());
    }
    return lid;
}

double wettedVolume(const std::vector<RadiationPanel>& panels) {
    double volume = 0;
    for (const RadiationPanel& p : panels) volume += p.centroid.y() * p.normal.y() * p.area;
    return volume;
}

double equilibriumHeight(const TriangleMesh& surface, const Eigen::Affine3d& toWater,
                         double volume) {
    const Bounds3 bounds = [&] {
        Bounds3 b;
        for (const Eigen::Vector3d& p : surface.positions) {
            const Eigen::Vector3d q = toWater * p;
            b.min = b.min.cwiseMin(q);
            b.max = b.max.cwiseMax(q);
        }
        return b;
    }();
    // Raised by `high` the body is out of the water, by `low` under it.
    double high = -bounds.min.y(), low = -bounds.max.y();
    for (int iteration = 0; iteration < 60; ++iteration) {
        const double mid = 0.5 * (low + high);
        const Eigen::Affine3d raised = Eigen::Translation3d(0, mid, 0) * toWater;
        if (wettedVolume(wettedPanels(surface, raised)) > volume)
            low = mid;
        else
            high = mid;
    }
    return 0.5 * (low + high);
}

RadiationSolver::RadiationSolver(std::vector<RadiationPanel> panels,
                                 const Eigen::Vector3d& reference, RadiationSettings settings)
    : panels_(std::move(panels)), settings_(settings) {
    if (settings_.irregularFrequencyLid) lid_ = waterplaneLid(panels_);
    sources_ = panels_;
    sources_.insert(sources_.end(), lid_.begin(), lid_.end());
    const auto bodyCount = static_cast<Eigen::Index>(panels_.size());
    const auto n = static_cast<Eigen::Index>(sources_.size());
    modeNormals_.resize(bodyCount, 6);
    directPotential_.resize(n, n);
    directNormal_.resize(n, n);
    imagePotential_.resize(n, n);
    imageNormal_.resize(n, n);
    for (Eigen::Index j = 0; j < bodyCount; ++j) {
        const RadiationPanel& p = panels_[j];
        modeNormals_.row(j).head<3>() = p.normal.transpose();
        modeNormals_.row(j).tail<3>() = (p.centroid - reference).cross(p.normal).transpose();
    }
    std::vector<std::array<Eigen::Vector3d, 3>> images(sources_.size());
    for (Eigen::Index j = 0; j < n; ++j) {
        const RadiationPanel& p = sources_[j];
        // Mirrored and reordered, so that the image keeps a consistent orientation.
        images[j] = {mirrored(p.vertices[0]), mirrored(p.vertices[2]), mirrored(p.vertices[1])};
    }
    // Averaged over the field panel (three points): the flux through it and its mean potential,
    // where the centroid alone misses the first-order variation across a triangle.
    forEachRow(n, settings_.threads, [&](Eigen::Index i) {
        const Eigen::Vector3d& ni = sources_[i].normal;
        const std::array<Eigen::Vector3d, 3> points = threePoints(sources_[i]);
        for (Eigen::Index j = 0; j < n; ++j) {
            double dp = 0, dn = 0, ip = 0, in = 0;
            for (const Eigen::Vector3d& x : points) {
                const RankineIntegral direct = rankineTriangle(sources_[j].vertices, x);
                const RankineIntegral image = rankineTriangle(images[j], x);
                dp += direct.potential;
                dn += ni.dot(direct.gradient);
                ip += image.potential;
                in += ni.dot(image.gradient);
            }
            directPotential_(i, j) = dp / 3.0;
            // On its own flat panel, seen from the water: the solid-angle limit -2 pi.
            directNormal_(i, j) = i == j ? -2.0 * kPi : dn / 3.0;
            imagePotential_(i, j) = ip / 3.0;
            imageNormal_(i, j) = in / 3.0;
        }
    });
    // The near pairs' singular integrals (at(): the wave part's ln(r' + d) and r', d the depth
    // of field and source point added up, r' the distance to the source's image), on midpoint
    // subdivisions as fine as the image is close: they do not depend on the frequency.
    near_.assign(static_cast<std::size_t>(n), {});
    forEachRow(n, settings_.threads, [&](Eigen::Index i) {
        const Eigen::Vector3d& x = sources_[i].centroid;
        for (Eigen::Index j = 0; j < n; ++j) {
            if (isFar(i, j)) continue;
            const RadiationPanel& source = sources_[j];
            const double size = longestEdge(source);
            const double imageDistance = (x - mirrored(source.centroid)).norm();
            const int levels = std::clamp(static_cast<int>(std::ceil(std::log2(
                                              2.0 * size / std::max(imageDistance, 1e-12 * size)))),
                                          0, 4);
            NearSource near;
            near.source = j;
            subdivide(source.vertices, levels,
                      [&](const std::array<Eigen::Vector3d, 3>& t, double area) {
                          RadiationPanel piece{t, {}, {}, area};
                          for (const Eigen::Vector3d& s : threePoints(piece)) {
                              const double w = area / 3.0;
                              const double dx = x.x() - s.x(), dz = x.z() - s.z();
                              const double d = std::max(0.0, -(x.y() + s.y()));
                              const double r =
                                  std::max(std::sqrt(dx * dx + dz * dz + d * d), 1e-12 * size);
                              const Eigen::Vector3d gradR(dx / r, -d / r, dz / r);
                              near.logIntegral += w * std::log(r + d);
                              near.distanceIntegral += w * r;
                              near.logGradient += w * (gradR - Eigen::Vector3d::UnitY()) / (r + d);
                              near.distanceGradient += w * gradR;
                          }
                      });
            near_[static_cast<std::size_t>(i)].push_back(near);
        }
    });
}

bool RadiationSolver::isFar(Eigen::Index i, Eigen::Index j) const {
    const RadiationPanel& source = sources_[j];
    const Eigen::Vector3d& x = sources_[i].centroid;
    const double size = longestEdge(source);
    return (x - mirrored(source.centroid)).norm() >= settings_.nearFactor * size &&
           (x - source.centroid).norm() >= settings_.nearFactor * size;
}

Eigen::Matrix<std::complex<double>, 6, 6> RadiationSolver::forces(
    const Eigen::MatrixXcd& potential, const Eigen::MatrixXcd& system) const {
    const auto bodyCount = static_cast<Eigen::Index>(panels_.size());
    Eigen::MatrixXcd rhs = Eigen::MatrixXcd::Zero(system.rows(), 6);
    rhs.topRows(bodyCount) = modeNormals_.cast<std::complex<double>>();
    const Eigen::MatrixXcd sources = system.partialPivLu().solve(rhs);
    const Eigen::MatrixXcd phi = potential * sources;  // body panels x 6: potential of each mode
    Eigen::Matrix<double, Eigen::Dynamic, 6> weighted = modeNormals_;
    for (Eigen::Index i = 0; i < weighted.rows(); ++i) weighted.row(i) *= panels_[i].area;
    // F(k, j) = int phi_j n_k dS
    return weighted.cast<std::complex<double>>().transpose() * phi;
}

RadiationCoefficients RadiationSolver::at(double omega) const {
    assert(omega > 0);
    const double K = omega * omega / settings_.gravity;
    const auto bodyCount = static_cast<Eigen::Index>(panels_.size());
    const auto n = static_cast<Eigen::Index>(sources_.size());
    Eigen::MatrixXcd potential = (directPotential_ + imagePotential_).cast<std::complex<double>>();
    Eigen::MatrixXcd system(n, n);
    system.topRows(bodyCount) =
        (directNormal_ + imageNormal_).topRows(bodyCount).cast<std::complex<double>>();
    // The wave part at the field panel's centroid: smooth on the panel's scale there (averaging
    // it over three points, like the Rankine part, changed the hemisphere's A and B by < 0.3%).
    //
    // The wave part between two points, nondimensional: G_wave(x, s) = 2 K (value + i pi e^{-Y}
    // J0(X)) etc. It depends on the pair only through X (horizontal distance) and Y (depths
    // added), both symmetric in x and s; evaluating it (Struve and Bessel functions, the tail
    // integrals) is most of the cost of a frequency.
    // The kernel at (x, s): F and its derivatives (tabulated, WaveTable) and e^{-Y} J0, J1.
    struct Kernel {
        WaveGreen w;
        double decay = 0, j0 = 0, j1 = 0;
    };
    const WaveTable& table = WaveTable::instance();
    const double logK = std::log(K);
    auto coordinates = [&](const Eigen::Vector3d& x, const Eigen::Vector3d& s) {
        const double dx = x.x() - s.x(), dz = x.z() - s.z();
        return std::pair{K * std::sqrt(dx * dx + dz * dz), std::max(0.0, -K * (x.y() + s.y()))};
    };
    auto kernel = [&](const Eigen::Vector3d& x, const Eigen::Vector3d& s) {
        Kernel k;
        const auto [X, Y] = coordinates(x, s);
        k.w = tabulatedWaveGreen(X, Y);
        k.decay = std::exp(-Y);
        table.bessel01(X, k.j0, k.j1);
        return k;
    };
    // Adds `weight` times the kernel at (x, s) to one matrix element's potential `g` and, on a
    // body row, to the gradient at x that its normal-velocity entry takes.
    auto accumulate = [&](const Kernel& k, const Eigen::Vector3d& x, const Eigen::Vector3d& s,
                          double weight, bool onBody, std::complex<double>& g,
                          Eigen::Vector3cd& gradient) {
        g += weight * std::complex<double>(2.0 * K * k.w.value, -2.0 * kPi * K * k.decay * k.j0);
        if (!onBody) return;  // the lid's rows need the potential only
        const double dx = x.x() - s.x();
        const double dz = x.z() - s.z();
        const double horizontal = std::sqrt(dx * dx + dz * dz);
        const std::complex<double> dR(2.0 * K * K * k.w.dX, 2.0 * kPi * K * K * k.decay * k.j1);
        const std::complex<double> dy(-2.0 * K * K * k.w.dY, -2.0 * kPi * K * K * k.decay * k.j0);
        const double ex = horizontal > 0 ? dx / horizontal : 0.0;
        const double ez = horizontal > 0 ? dz / horizontal : 0.0;
        gradient += weight * Eigen::Vector3cd(dR * ex, dy, dR * ez);
    };
    // The wave part is singular like ln r' and 1/r' at the image point (Newman 1985): one point
    // far away; near, the singular part (a logarithm and a cone) integrated once per body on
    // subdivided 3-point rules as the image comes close (near_), and the smooth rest on the
    // panel's own three points.
    auto store = [&](Eigen::Index i, Eigen::Index j, const std::complex<double>& g,
                     const Eigen::Vector3cd& gradient) {
        potential(i, j) += g;
        if (i < bodyCount)
            system(i, j) += sources_[i].normal.cast<std::complex<double>>().dot(gradient);
    };
    // Two far panels use one point each, their centroids, whichever is the field point: the
    // kernel is evaluated once per pair for both elements (i, j) and (j, i), which is exact (X
    // and Y are the same numbers either way). Every element is written by one row only: (j, i)
    // with j < i by row j when both directions are far, else by row i.
    forEachRow(n, settings_.threads, [&](Eigen::Index i) {
        const Eigen::Vector3d& x = sources_[i].centroid;
        const bool onBody = i < bodyCount;
        auto nearSource = near_[static_cast<std::size_t>(i)].begin();
        for (Eigen::Index j = 0; j < n; ++j) {
            const RadiationPanel& source = sources_[j];
            const bool far = isFar(i, j);
            if (far) {
                const bool farBack = j != i && isFar(j, i);
                if (j < i && farBack) continue;  // row j wrote this element
                const bool backOnBody = j < bodyCount;
                const Kernel k = kernel(x, source.centroid);
                std::complex<double> g = 0;
                Eigen::Vector3cd gradient = Eigen::Vector3cd::Zero();
                accumulate(k, x, source.centroid, source.area, onBody, g, gradient);
                store(i, j, g, gradient);
                if (j > i && farBack) {
                    std::complex<double> gBack = 0;
                    Eigen::Vector3cd gradientBack = Eigen::Vector3cd::Zero();
                    accumulate(k, source.centroid, x, sources_[i].area, backOnBody, gBack,
                               gradientBack);
                    store(j, i, gBack, gradientBack);
                }
                continue;
            }
            // The singular part, -e^{-Y_c} ln(rho + Y) - rho (Y_c: at the source's centroid, so
            // that the rest of its integral is the frequency-independent NearSource's), and the
            // rest, F less it, on the source's three points.
            while (nearSource->source < j) ++nearSource;
            const NearSource& near = *nearSource;
            const double decayAtCentroid =
                std::exp(std::min(0.0, K * (x.y() + source.centroid.y())));
            std::complex<double> g = 2.0 * K *
                                     (-decayAtCentroid * (logK * source.area + near.logIntegral) -
                                      K * near.distanceIntegral);
            const Eigen::Vector3d singularGradient =
                2.0 * K * (-decayAtCentroid * near.logGradient - K * near.distanceGradient);
            Eigen::Vector3cd gradient = singularGradient.cast<std::complex<double>>();
            for (const Eigen::Vector3d& s : threePoints(source)) {
                Kernel k = kernel(x, s);
                const auto [X, Y] = coordinates(x, s);
                const double rho = std::max(std::sqrt(X * X + Y * Y), 1e-300);
                k.w.value -= -decayAtCentroid * std::log(rho + Y) - rho;
                k.w.dX -= -X * (decayAtCentroid / (rho * (rho + Y)) + 1.0 / rho);
                k.w.dY -= -(decayAtCentroid + Y) / rho;
                accumulate(k, x, s, source.area / 3.0, onBody, g, gradient);
            }
            store(i, j, g, gradient);
        }
    });
    // The lid's rows: the interior flow has no vertical velocity under the lid,
    // d phi/dy = 4 pi sigma + K phi = 0 (4 pi: the jump of a source layer on the free surface,
    // whose image doubles it; K phi: d G/dy = K G there, the free-surface condition).
    for (Eigen::Index i = bodyCount; i < n; ++i) {
        system.row(i) = K * potential.row(i);
        system(i, i) += 4.0 * kPi;
    }
    const auto f = forces(potential.topRows(bodyCount), system);
    RadiationCoefficients out;
    out.omega = omega;
    out.addedMass = -settings_.density * f.real();
    out.damping = settings_.density * omega * f.imag();
    return out;
}

// Both limits have no irregular frequencies (the interior problem is a Dirichlet problem, or the
// lid's rows degenerate): the body's panels alone.
Matrix6d RadiationSolver::infiniteFrequencyAddedMass() const {
    const auto b = static_cast<Eigen::Index>(panels_.size());
    const auto f = forces(
        (directPotential_ - imagePotential_).topLeftCorner(b, b).cast<std::complex<double>>(),
        (directNormal_ - imageNormal_).topLeftCorner(b, b).cast<std::complex<double>>());
    return -settings_.density * f.real();
}

}  // namespace plimsoll
