// Hydrostatics and stability from the buoyancy evaluations (docs/hydrostatics.md). Everything
// is worked out in a frame centred on the centre of gravity G: the body turned by R (object ->
// world axes), the water a plane at height h above G. One evaluation gives the displaced
// volume V and the centre of buoyancy B; the equilibrium, the GZ curve and, through
// derivatives, the waterplane and the metacentric heights all follow from that one function,
// so the texel sums and the exact clip are compared on exactly the same terms.
#include "plimsoll/physics/hydrostatics.h"

#include "plimsoll/bake/bake.h"
#include "plimsoll/graph/graph.h"
#include "plimsoll/physics/buoyancy.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <functional>
#include <numbers>
#include <string>

namespace plimsoll {

namespace {

constexpr double kDegree = std::numbers::pi / 180.0;

/// The water the body displaces at one attitude.
struct Displaced {
    double volume = 0;                                  ///< m^3
    Eigen::Vector3d offset = Eigen::Vector3d::Zero();   ///< B - G, world axes, m
};

/// Integrals over the waterplane, world axes relative to G, m^2, m^3 and m^4.
struct Waterplane {
    double area = 0;
    Eigen::Vector2d moment = Eigen::Vector2d::Zero();  ///< of x and of z
    double xx = 0, zz = 0;                             ///< of x^2 and of z^2
};

/// One method's view of the body: the displaced water at (R, h), and the points that bound
/// the body (mesh vertices or texel centroids) relative to G, object axes.
struct DisplacementMeasure {
    std::function<Displaced(const Eigen::Matrix3d& rotation, double waterHeight)> displaced;
    std::vector<Eigen::Vector3d> points;
    /// The waterplane's integrals at (R, h) where the method has them directly (the
    /// textures); empty: from the derivatives of `displaced` (the exact clip).
    std::function<Waterplane(const Eigen::Matrix3d& rotation, double waterHeight)> waterplane;
};

double lowestPoint(const DisplacementMeasure& m, const Eigen::Matrix3d& rotation) {
    double lowest = INFINITY;
    for (const Eigen::Vector3d& p : m.points) lowest = std::min(lowest, rotation.row(1).dot(p));
    return lowest;
}

double highestPoint(const DisplacementMeasure& m, const Eigen::Matrix3d& rotation) {
    double highest = -INFINITY;
    for (const Eigen::Vector3d& p : m.points) highest = std::max(highest, rotation.row(1).dot(p));
    return highest;
}

/// Heel phi about x, then trim theta about z (the same fixed-axes order as
/// Pose::fromEulerDegrees), radians.
Eigen::Matrix3d attitude(double heel, double trim) {
    return (Eigen::AngleAxisd(trim, Eigen::Vector3d::UnitZ()) *
            Eigen::AngleAxisd(heel, Eigen::Vector3d::UnitX()))
        .toRotationMatrix();
}

/// The body floating at a fixed attitude: the water height that displaces the target volume.
struct Floating {
    double waterHeight = 0;  ///< above G, m
    Displaced water;
};

class Solver {
public:
    Solver(DisplacementMeasure measure, double displacement)
        : m_(std::move(measure)), target_(displacement) {
        for (const Eigen::Vector3d& p : m_.points) reach_ = std::max(reach_, p.norm());
    }

    double reach() const { return reach_; }
    const DisplacementMeasure& measure() const { return m_; }

    /// The largest volume the body can displace (fully under water), m^3.
    double fullVolume() const {
        const Eigen::Matrix3d upright = Eigen::Matrix3d::Identity();
        return m_.displaced(upright, highestPoint(m_, upright) + 1e-9 * reach_).volume;
    }

    /// Sinks the body at `rotation` until it displaces the target volume. V(h) rises
    /// monotonically from 0 at the lowest point to the full volume at the highest: the
    /// Illinois variant of false position keeps a bracket and converges superlinearly on the
    /// smooth exact curve as on the piecewise linear texel sums.
    Floating floatAt(const Eigen::Matrix3d& rotation) const {
        double lo = lowestPoint(m_, rotation), hi = highestPoint(m_, rotation);
        double fLo = -target_, fHi = m_.displaced(rotation, hi).volume - target_;
        Floating best{hi, m_.displaced(rotation, hi)};
        int side = 0;
        for (int i = 0; i < 200 && hi - lo > 1e-15 * reach_; ++i) {
            const double h = (fHi - fLo) > 0 ? lo + (hi - lo) * (-fLo) / (fHi - fLo)
                                             : 0.5 * (lo + hi);
            const Displaced d = m_.displaced(rotation, h);
            const double f = d.volume - target_;
            best = {h, d};
            if (std::abs(f) <= 1e-15 * target_) break;
            if (f < 0) {
                lo = h, fLo = f;
                if (side == -1) fHi *= 0.5;
                side = -1;
            } else {
                hi = h, fHi = f;
                if (side == 1) fLo *= 0.5;
                side = 1;
            }
        }
        return best;
    }

    /// The free trim at `heel`: the trim at which B lies straight below or above G along x
    /// (no pitching moment), by the secant method from `trimGuess` (radians).
    std::pair<double, Floating> trimmedAt(double heel, double trimGuess) const {
        auto pitchArm = [&](double trim) { return floatAt(attitude(heel, trim)); };
        double t0 = trimGuess, t1 = trimGuess + kDegree;
        Floating f0 = pitchArm(t0), f1 = pitchArm(t1);
        for (int i = 0; i < 60; ++i) {
            if (std::abs(f1.water.offset.x()) < std::abs(f0.water.offset.x()))
                std::swap(t0, t1), std::swap(f0, f1);
            if (std::abs(f0.water.offset.x()) <= 1e-13 * reach_) break;
            const double slope = (f1.water.offset.x() - f0.water.offset.x()) / (t1 - t0);
            if (!(std::abs(slope) > 0)) break;
            const double step = std::clamp(-f0.water.offset.x() / slope, -20 * kDegree,
                                           20 * kDegree);
            if (std::abs(step) < 1e-14) break;
            t1 = t0 + step;
            f1 = pitchArm(t1);
        }
        return {t0, f0};
    }

    /// Heel and trim at which B lies straight below or above G: Newton's method on the two
    /// lever arms, the Jacobian by differences, steps limited to 10 degrees.
    Eigen::Vector2d equilibrium() const {
        Eigen::Vector2d angles = Eigen::Vector2d::Zero();  // heel, trim (rad)
        auto arms = [&](const Eigen::Vector2d& a) {
            const Displaced d = floatAt(attitude(a[0], a[1])).water;
            return Eigen::Vector2d(d.offset.z(), d.offset.x());
        };
        Eigen::Vector2d r = arms(angles);
        for (int i = 0; i < 60 && r.norm() > 1e-13 * reach_; ++i) {
            const double step = 1e-3;
            Eigen::Matrix2d jacobian;
            for (int k = 0; k < 2; ++k) {
                Eigen::Vector2d a = angles;
                a[k] += step;
                Eigen::Vector2d b = angles;
                b[k] -= step;
                jacobian.col(k) = (arms(a) - arms(b)) / (2 * step);
            }
            Eigen::Vector2d delta = -jacobian.fullPivLu().solve(r);
            if (!delta.allFinite()) break;
            const double largest = delta.cwiseAbs().maxCoeff();
            if (largest > 10 * kDegree) delta *= 10 * kDegree / largest;
            const Eigen::Vector2d next = angles + delta;
            const Eigen::Vector2d rNext = arms(next);
            if (rNext.norm() >= r.norm() && largest < 1e-12) break;
            angles = next, r = rNext;
        }
        return angles;
    }

private:
    DisplacementMeasure m_;
    double target_ = 0;
    double reach_ = 0;
};

/// Metacentric height about the world axis `axis` (x: transverse, z: longitudinal) at the
/// equilibrium attitude: the slope of the righting arm at constant displacement, by central
/// differences over delta and 2 delta combined by Richardson's extrapolation.
double metacentricHeight(const Solver& solver, const Eigen::Matrix3d& equilibrium,
                         const Eigen::Vector3d& axis, double delta) {
    auto arm = [&](double angle) {
        const Eigen::Matrix3d r = Eigen::AngleAxisd(angle, axis).toRotationMatrix() * equilibrium;
        const Eigen::Vector3d offset = solver.floatAt(r).water.offset;
        // Positive rights the body: B goes to the side the turn pushes down.
        return axis.x() != 0 ? offset.z() : -offset.x();
    };
    auto slope = [&](double d) { return (arm(d) - arm(-d)) / (2 * std::sin(d)); };
    return (4 * slope(delta) - slope(2 * delta)) / 3;
}

/// The first heel above the equilibrium heel where GZ turns from righting to capsizing,
/// refined by bisection on the free-trim arm. The equilibrium heel itself when the first arm
/// beyond it capsizes (negative GM) or none rights (neutral); 180 when it rights to the end.
double vanishingAngle(const Solver& solver, const std::vector<RightingArm>& gz,
                      double equilibriumDegrees) {
    const double tolerance = 1e-7 * solver.reach();
    std::size_t righting = gz.size();  // last sample seen righting
    for (std::size_t i = 0; i < gz.size(); ++i) {
        if (gz[i].heelDegrees <= equilibriumDegrees + 1e-9) continue;
        if (gz[i].arm > tolerance) {
            righting = i;
            continue;
        }
        if (gz[i].arm >= -tolerance) continue;
        if (righting == gz.size()) return std::max(0.0, equilibriumDegrees);
        double lo = gz[righting].heelDegrees, hi = gz[i].heelDegrees;
        double trim = gz[righting].trimDegrees * kDegree;
        for (int k = 0; k < 40; ++k) {
            const double mid = 0.5 * (lo + hi);
            const auto [t, f] = solver.trimmedAt(mid * kDegree, trim);
            trim = t;
            (f.water.offset.z() > 0 ? lo : hi) = mid;
        }
        return 0.5 * (lo + hi);
    }
    return righting == gz.size() ? std::max(0.0, equilibriumDegrees) : 180.0;
}

Result<HydrostaticsResult> solveHydrostatics(DisplacementMeasure measure,
                                             const HydrostaticBody& body,
                                             const HydrostaticsSettings& settings,
                                             HydrostaticsMethod method) {
    const auto refuse = [](const std::string& what) {
        return makeError(ErrorKind::invalidArgument, "hydrostatics: " + what);
    };
    if (!(body.mass > 0) || !std::isfinite(body.mass)) return refuse("the mass must be positive");
    if (!body.centerOfMass.allFinite()) return refuse("the centre of mass is not finite");
    if (!(settings.density > 0) || !std::isfinite(settings.density))
        return refuse("the water density must be positive");
    if (!(settings.gzStepDegrees > 0) || !(settings.gzStepDegrees <= 90))
        return refuse("the GZ step must lie in (0, 90] degrees");
    if (!(settings.derivativeStepDegrees > 0) || !(settings.derivativeStepDegrees <= 10))
        return refuse("the derivative step must lie in (0, 10] degrees");
    if (measure.points.empty()) return refuse("the body has no surface");

    const double displacement = body.mass / settings.density;
    const Solver solver(std::move(measure), displacement);
    const double full = solver.fullVolume();
    if (!(full > 0)) return refuse("the body encloses no volume");
    if (displacement >= full) {
        return refuse("the body sinks: its mass needs " + std::to_string(displacement) +
                      " m^3 of water, and it displaces at most " + std::to_string(full) + " m^3");
    }

    HydrostaticsResult r;
    r.method = method;
    const Eigen::Vector2d angles = solver.equilibrium();
    const Eigen::Matrix3d upright = attitude(angles[0], angles[1]);
    const Floating rest = solver.floatAt(upright);
    r.heelDegrees = angles[0] / kDegree;
    r.trimDegrees = angles[1] / kDegree;
    r.displacement = rest.water.volume;
    const double keel = lowestPoint(solver.measure(), upright);  // below G, m
    r.draft = rest.waterHeight - keel;
    r.kb = rest.water.offset.y() - keel;
    r.kg = -keel;

    Eigen::Vector2d flotation = Eigen::Vector2d::Zero();  // x, z relative to G, world axes
    if (solver.measure().waterplane) {
        // Directly: A_wp, x_F and I = integral of (z - z_F)^2 over the waterplane.
        const Waterplane w = solver.measure().waterplane(upright, rest.waterHeight);
        r.waterplaneArea = w.area;
        if (w.area > 0) flotation = w.moment / w.area;
        r.bmTransverse = (w.zz - w.area * flotation.y() * flotation.y()) / r.displacement;
        r.bmLongitudinal = (w.xx - w.area * flotation.x() * flotation.x()) / r.displacement;
        r.gmTransverse = r.kb + r.bmTransverse - r.kg;
        r.gmLongitudinal = r.kb + r.bmLongitudinal - r.kg;
    } else {
        // From derivatives: dV/dh and d(V B)/dh by central differences, GM from the slope of
        // the righting arm.
        const double dh = 1e-5 * solver.reach();
        const Displaced above = solver.measure().displaced(upright, rest.waterHeight + dh);
        const Displaced below = solver.measure().displaced(upright, rest.waterHeight - dh);
        r.waterplaneArea = (above.volume - below.volume) / (2 * dh);
        const Eigen::Vector3d moment =
            (above.volume * above.offset - below.volume * below.offset) / (2 * dh);
        if (r.waterplaneArea > 0) flotation = Eigen::Vector2d(moment.x(), moment.z()) / r.waterplaneArea;
        const double delta = settings.derivativeStepDegrees * kDegree;
        r.gmTransverse = metacentricHeight(solver, upright, Eigen::Vector3d::UnitX(), delta);
        r.gmLongitudinal = metacentricHeight(solver, upright, Eigen::Vector3d::UnitZ(), delta);
        r.bmTransverse = r.gmTransverse + r.kg - r.kb;
        r.bmLongitudinal = r.gmLongitudinal + r.kg - r.kb;
    }
    r.centerOfFlotation =
        upright.transpose() * Eigen::Vector3d(flotation.x(), rest.waterHeight, flotation.y()) +
        body.centerOfMass;
    const double displacedMass = settings.density * displacement;  // kg
    for (const FreeSurface& s : body.freeSurfaces) {
        r.freeSurfaceLossTransverse += s.density * s.inertiaAboutX / displacedMass;
        r.freeSurfaceLossLongitudinal += s.density * s.inertiaAboutZ / displacedMass;
    }

    const int steps = static_cast<int>(std::ceil(180.0 / settings.gzStepDegrees - 1e-9));
    double trim = angles[1];
    for (int i = 0; i <= steps; ++i) {
        const double heel = std::min(180.0, i * settings.gzStepDegrees);
        const auto [t, f] = solver.trimmedAt(heel * kDegree, trim);
        trim = t;
        r.gz.push_back({heel, f.water.offset.z(), t / kDegree});
    }
    r.vanishingStabilityDegrees = vanishingAngle(solver, r.gz, r.heelDegrees);
    return r;
}

/// The waterplane from the texel entries: a field g(x, z) e_y has no divergence, so over the
/// submerged body's closed surface (wetted part and waterplane cap) its flux vanishes and the
/// cap's integral of g is minus the wetted surface's, -sum A_y g(p). An entry across the
/// waterline counts with its share under water (linear across its height, as the drag's
/// wetted share), and each entry adds its own second moment, a^2 / 12 for a square of
/// projected area a: the error of the midpoint rule the point samples make.
Waterplane textureWaterplane(const SurfaceTextures& textures, const Eigen::Matrix3d& rotation,
                             const Eigen::Vector3d& centerOfMass, double h) {
    Waterplane w;
    for (std::size_t i = 0; i < textures.coveredCount(); ++i) {
        const Eigen::Vector3d p = rotation * (textures.position[i] - centerOfMass);
        const Eigen::Vector3d a = rotation * textures.areaVector[i];
        const double tilt = std::max(0.0, 1.0 - a.y() * a.y() / std::max(a.squaredNorm(), 1e-300));
        const double height = std::sqrt(textures.area[i] * tilt);  // vertical extent, m
        const double depth = h - p.y();
        const double wet = height > 0 ? std::clamp(0.5 + depth / height, 0.0, 1.0)
                                      : (depth > 0 ? 1.0 : 0.0);
        if (wet <= 0) continue;
        const double projected = -wet * a.y();  // share of the cap under this entry, m^2
        const double own = projected * std::abs(projected) / 12;
        w.area += projected;
        w.moment += projected * Eigen::Vector2d(p.x(), p.z());
        w.xx += projected * p.x() * p.x() + own;
        w.zz += projected * p.z() * p.z() + own;
    }
    return w;
}

/// Relative to G, object axes.
std::vector<Eigen::Vector3d> relativeTo(const std::vector<Eigen::Vector3d>& points,
                                        const Eigen::Vector3d& center) {
    std::vector<Eigen::Vector3d> out;
    out.reserve(points.size());
    for (const Eigen::Vector3d& p : points) out.push_back(p - center);
    return out;
}

/// The body with G at the world origin, turned by `rotation`.
BodyFrame frameAt(const Eigen::Matrix3d& rotation, const Eigen::Vector3d& centerOfMass) {
    BodyFrame frame;
    frame.pose.rotation = rotation;
    frame.pose.translation = -rotation * centerOfMass;
    frame.centerOfMass = centerOfMass;
    return frame;
}

Displaced displacedOf(const BuoyancyResult& b) {
    if (!(b.submergedVolume > 0)) return {};
    return {b.submergedVolume, b.centerOfBuoyancy};
}

}  // namespace

const char* hydrostaticsMethodName(HydrostaticsMethod method) {
    return method == HydrostaticsMethod::Exact ? "exact" : "textures";
}

Result<HydrostaticsResult> hydrostaticsFromTextures(const SurfaceTextures& textures,
                                                    const HydrostaticBody& body,
                                                    const HydrostaticsSettings& settings) {
    const FluidSettings fluid{settings.density, settings.gravity, 0.0, 0.0};
    DisplacementMeasure measure;
    measure.points = relativeTo(textures.position, body.centerOfMass);
    measure.displaced = [&textures, &body, fluid](const Eigen::Matrix3d& rotation, double h) {
        return displacedOf(evaluateBuoyancyReference(
            textures, frameAt(rotation, body.centerOfMass), WaterModel::flat(h), fluid));
    };
    measure.waterplane = [&textures, &body](const Eigen::Matrix3d& rotation, double h) {
        return textureWaterplane(textures, rotation, body.centerOfMass, h);
    };
    return solveHydrostatics(std::move(measure), body, settings, HydrostaticsMethod::Textures);
}

Result<HydrostaticsResult> hydrostaticsExact(const TriangleMesh& mesh, const HydrostaticBody& body,
                                             const HydrostaticsSettings& settings) {
    const FluidSettings fluid{settings.density, settings.gravity, 0.0, 0.0};
    DisplacementMeasure measure;
    measure.points = relativeTo(mesh.positions, body.centerOfMass);
    measure.displaced = [&mesh, &body, fluid](const Eigen::Matrix3d& rotation, double h) {
        return displacedOf(
            evaluateBuoyancyExact(mesh, frameAt(rotation, body.centerOfMass), h, fluid));
    };
    return solveHydrostatics(std::move(measure), body, settings, HydrostaticsMethod::Exact);
}

std::vector<FreeSurface> graphFreeSurfaces(const WaterGraph& graph, double density) {
    std::vector<FreeSurface> surfaces;
    for (const GraphNode& node : graph.nodes) {
        const bool partlyFilled =
            node.water > 1e-12 * node.capacity && node.water < (1 - 1e-12) * node.capacity;
        if (!partlyFilled) continue;
        FreeSurface s;
        s.density = density;
        if (node.isBox()) {
            // The box scaled to the capacity (graph.h): its horizontal section, upright.
            const double scale = std::cbrt(node.capacity / node.boxSize.prod());
            const double x = scale * node.boxSize.x(), z = scale * node.boxSize.z();
            s.inertiaAboutX = x * z * z * z / 12;
            s.inertiaAboutZ = z * x * x * x / 12;
        } else {
            // A sphere of the capacity: the water's depth a from the cap volume
            // pi a^2 (3 r - a) / 3 (monotone in a), the surface a circle of radius^2
            // a (2 r - a).
            const double radius = std::cbrt(3 * node.capacity / (4 * std::numbers::pi));
            double lo = 0, hi = 2 * radius;
            for (int i = 0; i < 100; ++i) {
                const double a = 0.5 * (lo + hi);
                const double cap = std::numbers::pi * a * a * (3 * radius - a) / 3;
                (cap < node.water ? lo : hi) = a;
            }
            const double a = 0.5 * (lo + hi);
            const double circle2 = a * (2 * radius - a);
            s.inertiaAboutX = s.inertiaAboutZ = std::numbers::pi * circle2 * circle2 / 4;
        }
        surfaces.push_back(s);
    }
    return surfaces;
}

}  // namespace plimsoll
