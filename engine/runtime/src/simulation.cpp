// One body stepped as the editor's World steps it (runtime.hpp, Simulation): the same order of
// operations as World::advanceFrame, World::wrenchOf, the semi-implicit Euler step with the
// energy-conserving rotation (engine/src/physics/rigid_body.cpp) and World::stepWaterGraphs,
// written over the evaluation core's vectors. tests/runtime/test_runtime_trajectory.cpp runs
// both side by side on every sample project.
#include "plimsoll_runtime/runtime.hpp"

#include "bytes.hpp"
#include "motion.hpp"
#include "vec.hpp"

#include "plimsoll_eval/levels.hpp"
#include "plimsoll_eval/portable_math.hpp"
#include "plimsoll_eval/cummins.hpp"
#include "plimsoll_eval/sleep.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <memory>

namespace plimsoll_runtime {

namespace {

constexpr double kPi = 3.14159265358979323846;
/// World::kMaxSubSteps: beyond it the World refuses the body.
constexpr int kMaxSubSteps = 1000;

Quat conjugate(const Quat& q) { return {q.w, -q.x, -q.y, -q.z}; }

/// q v q*, as Eigen's Quaternion * Vector3 forms it.
Vec3 rotate(const Quat& q, const Vec3& v) {
    const Vec3 u{q.x, q.y, q.z};
    Vec3 uv = cross(u, v);
    uv = uv + uv;
    return v + q.w * uv + cross(u, uv);
}

Quat multiply(const Quat& a, const Quat& b) {
    return {a.w * b.w - a.x * b.x - a.y * b.y - a.z * b.z,
            a.w * b.x + a.x * b.w + a.y * b.z - a.z * b.y,
            a.w * b.y + a.y * b.w + a.z * b.x - a.x * b.z,
            a.w * b.z + a.z * b.w + a.x * b.y - a.y * b.x};
}

Quat normalized(const Quat& q) {
    const double n = std::sqrt(q.w * q.w + q.x * q.x + q.y * q.y + q.z * q.z);
    return {q.w / n, q.x / n, q.y / n, q.z / n};
}

/// The quaternion of a rotation matrix (Eigen's Quaternion(Matrix3) algorithm), normalised:
/// what RigidBodyState::orientation becomes when the World rebuilds a state from a pose.
Quat fromMatrix(const double m[3][3]) {
    Quat q;
    const double t = m[0][0] + m[1][1] + m[2][2];
    if (t > 0) {
        double s = std::sqrt(t + 1.0);
        q.w = 0.5 * s;
        s = 0.5 / s;
        q.x = (m[2][1] - m[1][2]) * s;
        q.y = (m[0][2] - m[2][0]) * s;
        q.z = (m[1][0] - m[0][1]) * s;
    } else {
        int i = 0;
        if (m[1][1] > m[0][0]) i = 1;
        if (m[2][2] > m[i][i]) i = 2;
        const int j = (i + 1) % 3, k = (j + 1) % 3;
        double s = std::sqrt(m[i][i] - m[j][j] - m[k][k] + 1.0);
        double v[3];
        v[i] = 0.5 * s;
        s = 0.5 / s;
        q.w = (m[k][j] - m[j][k]) * s;
        v[j] = (m[j][i] + m[i][j]) * s;
        v[k] = (m[k][i] + m[i][k]) * s;
        q.x = v[0], q.y = v[1], q.z = v[2];
    }
    return normalized(q);
}

Vec3 times(const double I[3][3], const Vec3& v) {
    return {I[0][0] * v.x + I[0][1] * v.y + I[0][2] * v.z,
            I[1][0] * v.x + I[1][1] * v.y + I[1][2] * v.z,
            I[2][0] * v.x + I[2][1] * v.y + I[2][2] * v.z};
}

/// I^-1 v for a symmetric positive definite I (Cholesky; zero when not positive definite).
Vec3 solve(const double I[3][3], const Vec3& v) {
    const double l00 = std::sqrt(I[0][0]);
    const double l10 = I[1][0] / l00, l20 = I[2][0] / l00;
    const double l11 = std::sqrt(I[1][1] - l10 * l10);
    const double l21 = (I[2][1] - l20 * l10) / l11;
    const double l22 = std::sqrt(I[2][2] - l20 * l20 - l21 * l21);
    if (!(l00 > 0) || !(l11 > 0) || !(l22 > 0)) return {};
    const double y0 = v.x / l00, y1 = (v.y - l10 * y0) / l11,
                 y2 = (v.z - l20 * y0 - l21 * y1) / l22;
    const double x2 = y2 / l22, x1 = (y1 - l21 * x2) / l11, x0 = (y0 - l10 * x1 - l20 * x2) / l00;
    return {x0, x1, x2};
}

/// exp(w dt / 2): the rotation by |w| dt about w (Eigen's AngleAxis to Quaternion).
Quat rotationBy(const Vec3& w, double dt) {
    const double rate = norm(w);
    if (rate == 0) return {};
    const double half = 0.5 * (rate * dt), s = plimsoll_eval::math::sin(half);
    return {plimsoll_eval::math::cos(half), s * (w.x / rate), s * (w.y / rate), s * (w.z / rate)};
}

/// The orientation after dt with the world angular momentum L fixed: the implicit midpoint
/// rule for Euler's equations, as rigid_body.cpp's energyConservingRotation.
Quat energyConservingRotation(const Quat& q, const Vec3& angularMomentum, const double I[3][3],
                              double dt) {
    constexpr int kMaxIterations = 16;
    constexpr double kTolerance = 1e-15;
    const Vec3 before = rotate(conjugate(q), angularMomentum);
    Vec3 w = solve(I, before);
    for (int iteration = 0; iteration < kMaxIterations; ++iteration) {
        const Vec3 after = rotate(conjugate(rotationBy(w, dt)), before);
        const Vec3 next = solve(I, 0.5 * (before + after));
        const bool converged = norm(next - w) <= kTolerance * norm(next);
        w = next;
        if (converged) break;
    }
    return multiply(q, rotationBy(w, dt));
}

/// Smallest eigenvalue of a symmetric 3x3 matrix (the trigonometric closed form).
double smallestEigenvalue(const double A[3][3]) {
    const double p1 = A[0][1] * A[0][1] + A[0][2] * A[0][2] + A[1][2] * A[1][2];
    if (p1 == 0) return std::min({A[0][0], A[1][1], A[2][2]});
    const double q = (A[0][0] + A[1][1] + A[2][2]) / 3.0;
    const double p2 = (A[0][0] - q) * (A[0][0] - q) + (A[1][1] - q) * (A[1][1] - q) +
                      (A[2][2] - q) * (A[2][2] - q) + 2.0 * p1;
    const double p = std::sqrt(p2 / 6.0);
    double B[3][3];
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) B[i][j] = (A[i][j] - (i == j ? q : 0.0)) / p;
    const double det = B[0][0] * (B[1][1] * B[2][2] - B[1][2] * B[2][1]) -
                       B[0][1] * (B[1][0] * B[2][2] - B[1][2] * B[2][0]) +
                       B[0][2] * (B[1][0] * B[2][1] - B[1][1] * B[2][0]);
    const double phi = std::acos(std::clamp(det / 2.0, -1.0, 1.0)) / 3.0;
    return q + 2.0 * p * std::cos(phi + 2.0 * kPi / 3.0);
}

/// a + b by the parallel-axis theorem (the engine's MassProperties operator+).
MassProperties combined(const MassProperties& a, const MassProperties& b) {
    MassProperties sum;
    sum.mass = a.mass + b.mass;
    sum.volume = std::max(a.volume, b.volume);
    if (sum.mass == 0.0) {
        sum.centerOfMass = 0.5 * (a.centerOfMass + b.centerOfMass);
        return sum;
    }
    const Vec3 weighted = a.mass * a.centerOfMass + b.mass * b.centerOfMass;
    sum.centerOfMass = {weighted.x / sum.mass, weighted.y / sum.mass, weighted.z / sum.mass};
    auto add = [&](const MassProperties& part) {
        const Vec3 d = part.centerOfMass - sum.centerOfMass;
        const double dd = dot(d, d), dv[3] = {d.x, d.y, d.z};
        for (int i = 0; i < 3; ++i)
            for (int j = 0; j < 3; ++j)
                sum.inertia[i][j] +=
                    part.inertia[i][j] + part.mass * ((i == j ? dd : 0.0) - dv[i] * dv[j]);
    };
    add(a);
    add(b);
    return sum;
}

bool isApprox(const double a[3][3], const double b[3][3], double precision) {
    double diff = 0, na = 0, nb = 0;
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) {
            diff += (a[i][j] - b[i][j]) * (a[i][j] - b[i][j]);
            na += a[i][j] * a[i][j];
            nb += b[i][j] * b[i][j];
        }
    return diff <= precision * precision * std::min(na, nb);
}

bool wavy(const Water& water) {
    return static_cast<bool>(water.height) || static_cast<bool>(water.heights);
}
double highest(const Water& water) { return wavy(water) ? water.maxHeight : water.level; }

/// f += w d, field by field (what a level's blend adds).
void addScaled(Forces& f, const Forces& d, double w) {
    f.submergedVolume += w * d.submergedVolume;
    f.centerOfBuoyancy += w * d.centerOfBuoyancy;
    f.force += w * d.force;
    f.torque += w * d.torque;
    f.pressureForce += w * d.pressureForce;
    f.pressureTorque += w * d.pressureTorque;
    f.dragForce += w * d.dragForce;
    f.dragTorque += w * d.dragTorque;
    f.wettedArea += w * d.wettedArea;
}

/// At most what stops `momentum` within dt.
Vec3 limited(const Vec3& loss, const Vec3& momentum, double dt) {
    const double impulse = norm(loss) * dt, cap = norm(momentum);
    return impulse > cap && impulse > 0 ? (cap / impulse) * loss : loss;
}

}  // namespace

Simulation::Simulation(const Bundle& bundle) : bundle_(bundle), body_(bundle) {}

std::unique_ptr<Simulation> Simulation::create(const Bundle& bundle, std::string& error) {
    const BundleWorld& world = bundle.world();
    if (world.integrator != "semi-implicit-euler") {
        error = bundle.folder() + ": integrator " + world.integrator +
                ": the runtime's Simulation steps semi-implicit-euler only";
        return nullptr;
    }
    if (!(bundle.mass().mass > 0)) {
        error = bundle.folder() + ": the body has no mass";
        return nullptr;
    }
    std::unique_ptr<Simulation> s(new Simulation(bundle));
    s->fluid_ = bundle.fluid();
    s->hull_ = bundle.mass();
    for (const Sample& sample : bundle.samples()) {
        // Half a texel's extent beyond its centroid: the surface it stands for.
        s->hullRadius_ = std::max(s->hullRadius_, norm(sample.position - s->hull_.centerOfMass) +
                                                      0.5 * std::sqrt(sample.area));
    }
    s->boundingRadius_ = s->hullRadius_;
    s->mass_ = s->hull_;
    const Pose& start = world.startPose;
    s->lod_.level = static_cast<int>(bundle.levels().size()) - 1;  // the finest until a policy says
    s->lod_.framesHeld = std::numeric_limits<int>::max() / 2;      // free to switch at once
    s->orientation_ = start.orientation;
    s->composedAt_ = start.orientation;
    if (const WaterGraph* graph = s->body_.graph()) {
        const MassProperties water = graph->waterMass(start.orientation);
        if (water.mass > 0) s->mass_ = combined(s->hull_, water);
        s->boundingRadius_ += norm(s->mass_.centerOfMass - s->hull_.centerOfMass);
    }
    double R[3][3];
    rotationMatrix(s->orientation_, R);
    s->position_ = mul(R, s->mass_.centerOfMass) + start.position;
    s->linearMomentum_ = s->mass_.mass * world.startVelocity.linear;
    s->angularMomentum_ = mul(R, times(s->mass_.inertia, mulT(R, world.startVelocity.angular)));
    if (const Radiation* radiation = bundle.radiation()) {
        // The added mass it starts with (World::addBody: the submerged volume at the start pose
        // on the project's water, at rest), so that it starts with the velocities asked for.
        const Water water = world.water.water();
        double submerged = 0;
        if (!(s->position_.y - s->boundingRadius_ > highest(water)))
            submerged = bundle.evaluate(start, Velocity{}, water, s->fluid_, 0.0).submergedVolume;
        s->applyAddedMass(plimsoll_eval::entrainedShare(submerged, radiation->restVolume));
        const Vec3 v = world.startVelocity.linear, w = world.startVelocity.angular;
        s->linearMomentum_ = s->mass_.mass * v + mul(R, times(s->addedMass_, mulT(R, v)));
        s->angularMomentum_ = mul(R, times(s->mass_.inertia, mulT(R, w))) +
                              mul(R, times(s->addedInertia_, mulT(R, w)));
    }
    return s;
}

void Simulation::rotationalInertia(double I[3][3]) const {
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) I[i][j] = mass_.inertia[i][j] + addedInertia_[i][j];
}

void Simulation::applyAddedMass(double share) {
    const Radiation* radiation = bundle_.radiation();
    if (!radiation) return;
    share = std::clamp(share, 0.0, 1.0);
    double T[3][3], Rr[3][3];
    radiation->sharedAddedMass(share, T, Rr);
    bool same = true;
    double traceNew = 0, traceOld = 0;
    for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 3; ++j) {
            same = same && T[i][j] == addedMass_[i][j] && Rr[i][j] == addedInertia_[i][j];
        }
        traceNew += T[i][i] + Rr[i][i];
        traceOld += addedMass_[i][i] + addedInertia_[i][i];
    }
    if (same) return;
    const Vec3 v = linearVelocity(), w = angularVelocity();
    added_ = false;
    for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 3; ++j) {
            addedMass_[i][j] = T[i][j];
            addedInertia_[i][j] = Rr[i][j];
            added_ = added_ || T[i][j] != 0;
        }
    }
    // Less water entrained: the velocities stay (the kinetic energy falls); more: the momenta
    // stay (the body drags the water along).
    if (traceNew < traceOld) {
        double R[3][3], I[3][3];
        rotationMatrix(orientation_, R);
        rotationalInertia(I);
        linearMomentum_ = mass_.mass * v + mul(R, times(addedMass_, mulT(R, v)));
        angularMomentum_ = mul(R, times(I, mulT(R, w)));
    }
}

void Simulation::startRadiation(double submergedVolume) {
    RadiationMemory* memory = body_.radiation();
    if (!memory) return;
    Pose pose;
    pose.orientation = orientation_;
    const RadiationLoad load = memory->begin(pose, submergedVolume);
    applyAddedMass(load.share);
    memoryForce_ = load.force;
    memoryTorque_ = load.torque;
}

void Simulation::finishRadiation(double dt) {
    RadiationMemory* memory = body_.radiation();
    if (!memory) return;
    Pose pose;
    pose.orientation = orientation_;
    memory->advance(pose, Velocity{linearVelocity(), angularVelocity()}, dt);
}

Vec3 Simulation::linearVelocity() const {
    if (!added_) return (1.0 / mass_.mass) * linearMomentum_;
    // In object axes the translational mass is m + A, constant.
    double M[3][3];
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) M[i][j] = (i == j ? mass_.mass : 0.0) + addedMass_[i][j];
    return rotate(orientation_, solve(M, rotate(conjugate(orientation_), linearMomentum_)));
}

Vec3 Simulation::angularVelocity() const {
    double I[3][3];
    rotationalInertia(I);
    return rotate(orientation_, solve(I, rotate(conjugate(orientation_), angularMomentum_)));
}

double Simulation::stiffestFrequency() const {
    const double rhoG = fluid_.density * fluid_.gravity;
    const double R = boundingRadius_;
    const double heave = rhoG * kPi * R * R / mass_.mass;
    const double roll = rhoG * kPi * std::pow(R, 4) / 4.0 / smallestEigenvalue(mass_.inertia);
    return std::sqrt(std::max(heave, roll));
}

int Simulation::stableSteps(double frameTime) const {
    const double spin = norm(angularVelocity());
    const double needed =
        std::ceil(std::max(stiffestFrequency(), spin) * frameTime / bundle_.world().maxPhaseStep);
    return needed <= kMaxSubSteps ? static_cast<int>(needed) : -1;
}

Forces Simulation::forcesAt(std::size_t level, const Water& water) const {
    double R[3][3];
    rotationMatrix(orientation_, R);
    Pose pose;
    pose.orientation = orientation_;
    pose.position = position_ - mul(R, mass_.centerOfMass);
    Velocity velocity{linearVelocity(), angularVelocity()};
    // The evaluation's centre is the hull's centre of mass: its velocity, and the torques
    // moved back to the centre of mass of the body with its water.
    const Vec3 r = mul(R, hull_.centerOfMass - mass_.centerOfMass);
    const bool shifted = hull_.centerOfMass.x != mass_.centerOfMass.x ||
                         hull_.centerOfMass.y != mass_.centerOfMass.y ||
                         hull_.centerOfMass.z != mass_.centerOfMass.z;
    if (shifted) velocity.linear += cross(velocity.angular, r);
    Forces f = bundle_.evaluateLevel(level, pose, velocity, water, fluid_, time_);
    if (shifted) {
        f.torque += cross(r, f.force);
        f.pressureTorque += cross(r, f.pressureForce);
        f.dragTorque += cross(r, f.dragForce);
    }
    return f;
}

void Simulation::evaluate(const Water& water, double dt) {
    if (position_.y - boundingRadius_ > highest(water)) {
        forces_ = Forces{};
        forces_.centerOfBuoyancy = position_;
    } else {
        forces_ = forcesAt(level(), water);
        if (lod_.blendLeft > 0)
            addScaled(forces_, lod_.offset, static_cast<double>(lod_.blendLeft) / lod_.blendSteps);
    }
    // The added mass of this submerged volume before the damping acts on the momenta.
    startRadiation(forces_.submergedVolume);
    // On flat water Archimedes' form (exactly vertical); on waves the pressure integral, which
    // carries their horizontal push (World::wrenchOf).
    const bool flat = !wavy(water);
    const BundleWorld& world = bundle_.world();
    Wrench w;
    w.force = mass_.mass * world.gravity + (flat ? forces_.force : forces_.pressureForce);
    w.torque = flat ? forces_.torque : forces_.pressureTorque;
    const double wet =
        hull_.volume > 0 ? std::clamp(forces_.submergedVolume / hull_.volume, 0.0, 1.0) : 0.0;
    Vec3 loss = forces_.dragForce - (wet * bundle_.linearDamping()) * linearMomentum_;
    if (bundle_.verticalDamping() != bundle_.linearDamping()) {
        // Along gravity its own rate (radiation damps a radiating body's heave).
        const double g = norm(world.gravity);
        const Vec3 up = g > 0 ? (-1.0 / g) * world.gravity : Vec3{0, 1, 0};
        loss = loss - (wet * (bundle_.verticalDamping() - bundle_.linearDamping()) *
                       dot(up, linearMomentum_)) *
                          up;
    }
    w.force += limited(loss, linearMomentum_, dt);
    w.torque += limited(forces_.dragTorque - (wet * bundle_.angularDamping()) * angularMomentum_,
                        angularMomentum_, dt);
    // The radiation memory is passive by construction: not capped either.
    if (body_.radiation()) {
        w.force += memoryForce_;
        w.torque += memoryTorque_;
    }
    wrench_ = w;
}

void Simulation::step(double dt) {
    // Kick, then drift with the new momenta (rigid_body.cpp's semiImplicitEulerStep).
    const Quat before = orientation_;
    linearMomentum_ += dt * wrench_.force;
    angularMomentum_ += dt * wrench_.torque;
    position_ += dt * linearVelocity();
    double I[3][3];
    rotationalInertia(I);
    orientation_ = energyConservingRotation(before, angularMomentum_, I, dt);
}

void Simulation::setMass(const MassProperties& mass) {
    // The pose and the velocities stay (the water moves with the body): the new centre of mass
    // moves with v + w x (c_new - c_old) (World::replaceMass).
    double R[3][3];
    rotationMatrix(orientation_, R);
    const Vec3 origin = position_ - mul(R, mass_.centerOfMass);
    Vec3 linear = linearVelocity();
    const Vec3 angular = angularVelocity();
    const Vec3 oldCenter = position_;
    mass_ = mass;
    const Vec3 newCenter = mul(R, mass_.centerOfMass) + origin;
    linear += cross(angular, newCenter - oldCenter);
    orientation_ = fromMatrix(R);
    rotationMatrix(orientation_, R);
    position_ = mul(R, mass_.centerOfMass) + origin;
    // The added mass stays: the water around the body did not change.
    linearMomentum_ = mass_.mass * linear;
    angularMomentum_ = mul(R, times(mass_.inertia, mulT(R, angular)));
    if (body_.radiation()) {
        linearMomentum_ += mul(R, times(addedMass_, mulT(R, linear)));
        angularMomentum_ += mul(R, times(addedInertia_, mulT(R, angular)));
    }
}

bool Simulation::stepGraph(const Water& water, double frameTime) {
    WaterGraph* graph = body_.graph();
    if (!graph) return false;
    double R[3][3];
    rotationMatrix(orientation_, R);
    Pose pose;
    pose.orientation = orientation_;
    pose.position = position_ - mul(R, mass_.centerOfMass);
    bool moved = graph->exchange(pose, water, time_, frameTime);
    moved = graph->flowInside(orientation_, frameTime) || moved;
    double C[3][3];
    rotationMatrix(composedAt_, C);
    const bool turned =
        graph->settings().freeSurface && graph->storedWater() > 0 && !isApprox(R, C, 1e-12);
    if (moved || turned) composeWater(orientation_);
    return moved;
}

void Simulation::composeWater(const Quat& at) {
    const MassProperties water = body_.graph()->waterMass(at);
    composedAt_ = at;
    setMass(water.mass > 0 ? combined(hull_, water) : hull_);
    boundingRadius_ = hullRadius_ + norm(mass_.centerOfMass - hull_.centerOfMass);
}

bool Simulation::setLevelPolicy(const LevelPolicy& policy, std::string& error) {
    const auto refuse = [&](const char* what) {
        error = bundle_.folder() + ": level policy: " + what;
        return false;
    };
    if (!finite(policy.pointOfInterest)) return refuse("the point of interest is not finite");
    if (!(policy.nearDistance > 0) || !std::isfinite(policy.nearDistance))
        return refuse("nearDistance must be a positive distance (m)");
    if (!(policy.margin >= 0) || !std::isfinite(policy.margin))
        return refuse("margin must be 0 or more");
    if (!(policy.importance >= 0) || !(policy.importance <= 1))
        return refuse("importance is outside 0..1");
    if (policy.holdFrames < 0) return refuse("holdFrames must be 0 or more");
    if (policy.blendFrames < 1) return refuse("blendFrames must be at least 1");
    levelPolicy_ = policy;
    return true;
}

void Simulation::chooseLevel(const Water& water) {
    const std::size_t count = bundle_.levels().size();
    if (count < 2) return;
    const LevelPolicy& p = levelPolicy_;
    plimsoll_eval::LevelSwitch sw{lod_.level, lod_.framesHeld, lod_.blendSteps, lod_.blendLeft};
    const bool free = sw.countFrame(p.holdFrames);
    lod_.framesHeld = sw.framesHeld;
    // Asleep the body keeps the level it fell asleep with.
    if (!free || asleep_) return;
    const int finest = static_cast<int>(count) - 1;
    int target = finest;
    switch (p.kind) {
        case LevelPolicy::Kind::finest:
            break;
        case LevelPolicy::Kind::distance:
            target = plimsoll_eval::levelAtDistance(norm(position_ - p.pointOfInterest),
                                                    p.nearDistance, p.margin, sw.level, finest);
            break;
        case LevelPolicy::Kind::importance:
            target = plimsoll_eval::levelOfImportance(p.importance, p.nearDistance, p.margin,
                                                      sw.level, finest);
            break;
        case LevelPolicy::Kind::fixed:
            target = static_cast<int>(std::min<std::size_t>(p.level, count - 1));
            break;
    }
    if (target == sw.level) return;
    const std::size_t from = static_cast<std::size_t>(sw.level);
    const double carried = sw.switchTo(target);
    ++lod_.switches;
    if (!(position_.y - boundingRadius_ > highest(water))) {
        // Both levels at the same state: their difference (and what was left of a running
        // blend) is faded out from here.
        Forces offset;
        offset.centerOfBuoyancy = {0, 0, 0};
        if (carried > 0) addScaled(offset, lod_.offset, carried);
        addScaled(offset, forcesAt(from, water), 1.0);
        addScaled(offset, forcesAt(static_cast<std::size_t>(sw.level), water), -1.0);
        lod_.offset = offset;
        sw.startBlend(p.blendFrames, subSteps_);
    }
    lod_.level = sw.level;
    lod_.framesHeld = sw.framesHeld;
    lod_.blendSteps = sw.blendSteps;
    lod_.blendLeft = sw.blendLeft;
}

void Simulation::wake() {
    asleep_ = false;
    restedFor_ = 0;
}

bool Simulation::advanceFrame(const Water& water, std::string& error) {
    const double frameTime = bundle_.world().timeStep;
    const plimsoll_eval::SleepSettings sleep = sleepSettingsOf(bundle_.world().sleep);
    plimsoll_eval::SleepState rest{asleep_, restedFor_, sleepHeight_};
    if (asleep_) {
        double height = 0, speed = 0;
        surfaceAbove(water, position_, time_, height, speed);
        if (plimsoll_eval::mustWake(rest, sleep, speed, height, false)) {
            wake();
        } else {
            // The World's clock runs on through a sleeping body's frame in the same sub-steps.
            chooseLevel(water);  // counts the frame only
            subSteps_ = bundle_.world().subSteps;
            const double dt = frameTime / subSteps_;
            for (int sub = 0; sub < subSteps_; ++sub) time_ += dt;
            return true;
        }
    }
    const Vec3 startLinear = linearVelocity(), startAngular = angularVelocity();
    const int stable = stableSteps(frameTime);
    if (stable < 0) {
        error = bundle_.folder() + ": a stable step needs more than 1000 sub-steps a frame";
        return false;
    }
    subSteps_ = std::max(bundle_.world().subSteps, stable);
    chooseLevel(water);
    const int stride = plimsoll_eval::stepStride(levelPolicy_.fewerStepsWhenCoarser, subSteps_,
                                                 bundle_.world().subSteps, stable, lod_.level,
                                                 static_cast<int>(bundle_.levels().size()) - 1);
    const double dt = frameTime / subSteps_;
    const double bodyDt = dt * stride;
    for (int sub = 0; sub < subSteps_; ++sub) {
        // The World's sub-steps, the body's steps on every stride-th of them.
        if (sub % stride == 0) {
            evaluate(water, bodyDt);
            step(bodyDt);
            finishRadiation(bodyDt);
        }
        if (lod_.blendLeft > 0) --lod_.blendLeft;
        time_ += dt;
    }
    const bool changed = stepGraph(water, frameTime);
    if (!finite(position_) || !finite(linearMomentum_) || !finite(angularMomentum_) ||
        !std::isfinite(orientation_.w + orientation_.x + orientation_.y + orientation_.z)) {
        error = bundle_.folder() +
                ": the body left the finite numbers at t = " + std::to_string(time_) + " s";
        return false;
    }
    plimsoll_eval::RestSample sample;
    const Vec3 linear = linearVelocity(), angular = angularVelocity();
    sample.speed = norm(linear);
    sample.spin = norm(angular);
    sample.acceleration = norm(linear - startLinear) / frameTime;
    sample.angularAcceleration = norm(angular - startAngular) / frameTime;
    plimsoll_eval::sampleWaterIfStill(sleep, sample, [&](double& height, double& speed) {
        surfaceAbove(water, position_, time_, height, speed);
    });
    sample.changing = changed;
    rest = {false, restedFor_, sleepHeight_};
    if (plimsoll_eval::countRest(rest, sleep, sample, frameTime)) {
        linearMomentum_ = {0, 0, 0};
        angularMomentum_ = {0, 0, 0};
        // The little the radiation memory still holds after this long at rest is let go, so
        // that the body wakes without an old push (World::sleepWhereRested).
        if (RadiationMemory* memory = body_.radiation())
            *memory = RadiationMemory(bundle_.radiation());
        memoryForce_ = {0, 0, 0};
        memoryTorque_ = {0, 0, 0};
    }
    asleep_ = rest.asleep;
    restedFor_ = rest.restedFor;
    sleepHeight_ = rest.waterHeight;
    return true;
}

namespace {

constexpr std::uint64_t kSnapshotMagic = 0x324D49534C4C4D50ull;  // "PMLLSIM2"

}  // namespace

std::vector<std::uint8_t> Simulation::save() const {
    std::vector<std::uint8_t> out;
    putBytes(out, kSnapshotMagic);
    putBytes(out, static_cast<std::uint64_t>(bundle_.samples().size()));
    const MassProperties& m = mass_;
    for (double v : {time_,
                     position_.x,
                     position_.y,
                     position_.z,
                     orientation_.w,
                     orientation_.x,
                     orientation_.y,
                     orientation_.z,
                     linearMomentum_.x,
                     linearMomentum_.y,
                     linearMomentum_.z,
                     angularMomentum_.x,
                     angularMomentum_.y,
                     angularMomentum_.z,
                     m.mass,
                     m.volume,
                     m.centerOfMass.x,
                     m.centerOfMass.y,
                     m.centerOfMass.z,
                     m.inertia[0][0],
                     m.inertia[0][1],
                     m.inertia[0][2],
                     m.inertia[1][0],
                     m.inertia[1][1],
                     m.inertia[1][2],
                     m.inertia[2][0],
                     m.inertia[2][1],
                     m.inertia[2][2],
                     boundingRadius_,
                     composedAt_.w,
                     composedAt_.x,
                     composedAt_.y,
                     composedAt_.z,
                     asleep_ ? 1.0 : 0.0,
                     restedFor_,
                     sleepHeight_})
        putBytes(out, v);
    // The level in use and its blend, for a bundle with levels only: a snapshot of a body with
    // one level is what it always was.
    if (bundle_.levels().size() > 1) {
        for (int v : {lod_.level, lod_.framesHeld, lod_.blendSteps, lod_.blendLeft})
            putBytes(out, static_cast<std::int32_t>(v));
        putBytes(out, static_cast<std::uint64_t>(lod_.switches));
        const Forces& f = lod_.offset;
        putBytes(out, f.submergedVolume);
        for (const Vec3* v : {&f.centerOfBuoyancy, &f.force, &f.torque, &f.pressureForce,
                              &f.pressureTorque, &f.dragForce, &f.dragTorque}) {
            putBytes(out, v->x);
            putBytes(out, v->y);
            putBytes(out, v->z);
        }
        putBytes(out, f.wettedArea);
    }
    if (const WaterGraph* graph = body_.graph()) graph->saveState(out);
    if (const RadiationMemory* memory = body_.radiation()) {
        for (int i = 0; i < 3; ++i)
            for (int j = 0; j < 3; ++j) putBytes(out, addedMass_[i][j]);
        for (int i = 0; i < 3; ++i)
            for (int j = 0; j < 3; ++j) putBytes(out, addedInertia_[i][j]);
        memory->saveState(out);
    }
    return out;
}

bool Simulation::restore(const std::vector<std::uint8_t>& bytes, std::string& error) {
    std::uint64_t magic = 0, samples = 0;
    if (bytes.size() < 2 * sizeof(std::uint64_t)) {
        error = "snapshot: " + std::to_string(bytes.size()) + " bytes, too short";
        return false;
    }
    std::memcpy(&magic, bytes.data(), sizeof(magic));
    std::memcpy(&samples, bytes.data() + sizeof(magic), sizeof(samples));
    if (magic != kSnapshotMagic || samples != bundle_.samples().size()) {
        error = "snapshot: not a snapshot of this body (" + bundle_.folder() + ")";
        return false;
    }
    std::size_t at = 2 * sizeof(std::uint64_t);
    double v[36];
    for (double& d : v) {
        if (!takeBytes(bytes, at, d) || !std::isfinite(d)) {
            error = "snapshot: truncated or not finite";
            return false;
        }
    }
    LevelState lod = lod_;
    if (bundle_.levels().size() > 1) {
        std::int32_t n[4];
        std::uint64_t switches = 0;
        double o[23];
        bool ok = true;
        for (std::int32_t& k : n) ok = ok && takeBytes(bytes, at, k);
        ok = ok && takeBytes(bytes, at, switches);
        for (double& d : o) ok = ok && takeBytes(bytes, at, d) && std::isfinite(d);
        if (!ok || n[0] < 0 || static_cast<std::size_t>(n[0]) >= bundle_.levels().size() ||
            n[1] < 0 || n[2] < 0 || n[3] < 0 || n[3] > n[2]) {
            error = "snapshot: the level of detail's state does not fit this body";
            return false;
        }
        lod = {n[0], n[1], n[2], n[3], static_cast<std::size_t>(switches), Forces{}};
        lod.offset.submergedVolume = o[0];
        Vec3* fields[] = {&lod.offset.centerOfBuoyancy, &lod.offset.force,
                          &lod.offset.torque,           &lod.offset.pressureForce,
                          &lod.offset.pressureTorque,   &lod.offset.dragForce,
                          &lod.offset.dragTorque};
        for (int k = 0; k < 7; ++k) *fields[k] = {o[1 + 3 * k], o[2 + 3 * k], o[3 + 3 * k]};
        lod.offset.wettedArea = o[22];
    }
    // The graph and the radiation first: they are the parts that can still refuse, and nothing
    // may change then.
    WaterGraph* graph = body_.graph();
    std::vector<std::uint8_t> graphBefore;
    if (graph) graph->saveState(graphBefore);
    auto undoGraph = [&] {
        std::size_t back = 0;
        if (graph) graph->restoreState(graphBefore, back);
    };
    if (graph && !graph->restoreState(bytes, at)) {
        error = "snapshot: the water graph's state does not fit this body";
        return false;
    }
    double added[18] = {};
    RadiationMemory* memory = body_.radiation();
    std::unique_ptr<RadiationMemory> restored;
    if (memory) {
        bool fits = true;
        for (double& d : added) fits = fits && takeBytes(bytes, at, d) && std::isfinite(d);
        restored = std::make_unique<RadiationMemory>(*memory);
        if (!fits || !restored->restoreState(bytes, at)) {
            undoGraph();
            error = "snapshot: the radiation state does not fit this body";
            return false;
        }
    }
    if (at != bytes.size()) {
        undoGraph();
        error = "snapshot: " + std::to_string(bytes.size() - at) + " bytes too many";
        return false;
    }
    if (memory) {
        *memory = *restored;
        added_ = false;
        for (int i = 0; i < 3; ++i) {
            for (int j = 0; j < 3; ++j) {
                addedMass_[i][j] = added[3 * i + j];
                addedInertia_[i][j] = added[9 + 3 * i + j];
                added_ = added_ || addedMass_[i][j] != 0;
            }
        }
    }
    time_ = v[0];
    position_ = {v[1], v[2], v[3]};
    orientation_ = {v[4], v[5], v[6], v[7]};
    linearMomentum_ = {v[8], v[9], v[10]};
    angularMomentum_ = {v[11], v[12], v[13]};
    mass_.mass = v[14];
    mass_.volume = v[15];
    mass_.centerOfMass = {v[16], v[17], v[18]};
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) mass_.inertia[i][j] = v[19 + 3 * i + j];
    boundingRadius_ = v[28];
    composedAt_ = {v[29], v[30], v[31], v[32]};
    asleep_ = v[33] != 0;
    restedFor_ = v[34];
    sleepHeight_ = v[35];
    lod_ = lod;
    return true;
}

std::uint64_t Simulation::stateHash() const { return fnv1a(save()); }

}  // namespace plimsoll_runtime
