// The Bullet adapter (plimsoll_bullet.hpp).
#include "plimsoll_bullet.hpp"

#include <algorithm>
#include <mutex>
#include <unordered_map>

namespace plimsoll_bullet {

namespace {

btVector3 vec(const double v[3]) {
    return btVector3(btScalar(v[0]), btScalar(v[1]), btScalar(v[2]));
}

/// The centre of mass and the principal axes of inertia (a proper rotation) in object space,
/// and the principal moments.
btTransform principalFrame(const plimsoll_mass& m, btVector3& moments) {
    btMatrix3x3 inertia(
        btScalar(m.inertia[0][0]), btScalar(m.inertia[0][1]), btScalar(m.inertia[0][2]),
        btScalar(m.inertia[1][0]), btScalar(m.inertia[1][1]), btScalar(m.inertia[1][2]),
        btScalar(m.inertia[2][0]), btScalar(m.inertia[2][1]), btScalar(m.inertia[2][2]));
    btMatrix3x3 axes;
    // inertia becomes diag(moments) with original = axes * diag * axes^T.
    inertia.diagonalize(axes, btScalar(1e-12), 32);
    if (axes.determinant() < 0) {
        for (int row = 0; row < 3; ++row) axes[row][2] = -axes[row][2];
    }
    moments = btVector3(inertia[0][0], inertia[1][1], inertia[2][2]);
    return btTransform(axes, vec(m.center_of_mass));
}

/// The world's pre-tick callback, which btDynamicsWorld keeps protected and gives no getter
/// for: a pointer to the member, formed in a derived class, reads it on any world.
struct PreTickPeek : btDynamicsWorld {
    static btInternalTickCallback of(const btDynamicsWorld& world) {
        constexpr btInternalTickCallback btDynamicsWorld::*member =
            &PreTickPeek::m_internalPreTickCallback;
        return world.*member;
    }
};

/// The Harbour of each world: the world's user info stays the game's (its own callbacks read
/// it), so the pre-tick callback finds its Harbour here.
std::mutex harboursMutex;
std::unordered_map<const btDynamicsWorld*, Harbour*>& harbours() {
    static std::unordered_map<const btDynamicsWorld*, Harbour*> map;
    return map;
}

}  // namespace

FloatingBody::FloatingBody(const plimsoll_bundle* bundle, const btTransform& objectPose,
                           btCollisionShape* objectShape)
    : bundle_(bundle), instance_(plimsoll_instance_create(bundle)) {
    const plimsoll_mass m = plimsoll_bundle_mass(bundle);
    btVector3 moments;
    bodyInObject_ = principalFrame(m, moments);
    if (!objectShape) {
        double lo[3] = {0, 0, 0}, hi[3] = {0, 0, 0};
        plimsoll_bundle_bounds(bundle, lo, hi);
        const double half[3] = {0.5 * (hi[0] - lo[0]), 0.5 * (hi[1] - lo[1]),
                                0.5 * (hi[2] - lo[2])};
        const double mid[3] = {0.5 * (hi[0] + lo[0]), 0.5 * (hi[1] + lo[1]), 0.5 * (hi[2] + lo[2])};
        defaultShape_ = std::make_unique<btBoxShape>(vec(half));
        defaultShape_->setMargin(0);
        objectShape = defaultShape_.get();
        // The box's own frame sits at its middle.
        shape_ = std::make_unique<btCompoundShape>();
        shape_->addChildShape(
            bodyInObject_.inverse() * btTransform(btMatrix3x3::getIdentity(), vec(mid)),
            objectShape);
    } else {
        shape_ = std::make_unique<btCompoundShape>();
        shape_->addChildShape(bodyInObject_.inverse(), objectShape);
    }
    motion_ = std::make_unique<btDefaultMotionState>(objectPose * bodyInObject_);
    btRigidBody::btRigidBodyConstructionInfo info(btScalar(m.mass), motion_.get(), shape_.get(),
                                                  moments);
    body_ = std::make_unique<btRigidBody>(info);
    // Angular momentum, not angular velocity, is what a free body keeps.
    body_->setFlags(body_->getFlags() | BT_ENABLE_GYROSCOPIC_FORCE_IMPLICIT_BODY);
    // A body may sleep once at rest on calm water: below these speeds for Bullet's 2 s. Bullet's
    // default thresholds (0.8 m/s, 1 rad/s) would freeze a gently rolling body; the Harbour wakes
    // a sleeping one on waves and while water moves in or out of it.
    body_->setSleepingThresholds(0.005f, 0.005f);
}

FloatingBody::~FloatingBody() {
    if (harbour_) harbour_->remove(this);
    plimsoll_instance_destroy(instance_);
}

plimsoll_pose FloatingBody::pose() const {
    const btTransform object = body_->getCenterOfMassTransform() * bodyInObject_.inverse();
    const btQuaternion q = object.getRotation();
    const btVector3& p = object.getOrigin();
    return {{p.x(), p.y(), p.z()}, {q.w(), q.x(), q.y(), q.z()}};
}

plimsoll_velocity FloatingBody::velocity() const {
    const btVector3& v = body_->getLinearVelocity();
    const btVector3& w = body_->getAngularVelocity();
    return {{v.x(), v.y(), v.z()}, {w.x(), w.y(), w.z()}};
}

Harbour::Harbour(btDiscreteDynamicsWorld* world, const plimsoll_water& water,
                 const plimsoll_fluid& fluid, const plimsoll_batch_desc* batch)
    : world_(world), water_(water), fluid_(fluid), batch_(plimsoll_batch_create(batch)) {
    if (!batch_) error_ = plimsoll_runtime_last_error();
    {
        std::lock_guard<std::mutex> lock(harboursMutex);
        harbours()[world_] = this;
    }
    // Chained, not replaced: the game's own pre-tick callback (set before the Harbour) is
    // still called, first, with the world's user info left as the game set it.
    previous_ = PreTickPeek::of(*world_);
    world_->setInternalTickCallback(&Harbour::preTick, world_->getWorldUserInfo(), true);
}

Harbour::~Harbour() {
    world_->setInternalTickCallback(previous_, world_->getWorldUserInfo(), true);
    {
        std::lock_guard<std::mutex> lock(harboursMutex);
        harbours().erase(world_);
    }
    for (FloatingBody* body : bodies_) {
        world_->removeRigidBody(body->rigidBody());
        body->harbour_ = nullptr;
    }
    plimsoll_batch_destroy(batch_);
}

void Harbour::setPreTickCallback(btInternalTickCallback callback) { previous_ = callback; }

void Harbour::add(FloatingBody* body) {
    if (body->harbour_) body->harbour_->remove(body);
    world_->addRigidBody(body->rigidBody());
    bodies_.push_back(body);
    body->harbour_ = this;
}

void Harbour::remove(FloatingBody* body) {
    const auto found = std::find(bodies_.begin(), bodies_.end(), body);
    if (found == bodies_.end()) return;
    world_->removeRigidBody(body->rigidBody());
    bodies_.erase(found);
    body->harbour_ = nullptr;
}

void Harbour::preTick(btDynamicsWorld* world, btScalar step) {
    Harbour* harbour = nullptr;
    {
        std::lock_guard<std::mutex> lock(harboursMutex);
        const auto found = harbours().find(world);
        if (found != harbours().end()) harbour = found->second;
    }
    if (!harbour) return;
    if (harbour->previous_) harbour->previous_(world, step);
    harbour->applyLoads(step);
}

void Harbour::applyLoads(double dt) {
    auto failed = [this] {
        if (error_.empty()) error_ = plimsoll_runtime_last_error();
    };
    const bool wavy = water_.height || water_.heights;
    // Every flooding body's water steps, asleep or not: water still coming in or going out
    // wakes it (its weight changes).
    flooding_.clear();
    floodingPoses_.clear();
    floodingBodies_.clear();
    for (FloatingBody* body : bodies_) {
        if (plimsoll_graph_node_count(body->bundle()) == 0) continue;
        flooding_.push_back(body->instance());
        floodingPoses_.push_back(body->pose());
        floodingBodies_.push_back(body);
    }
    moved_.assign(flooding_.size(), 0);
    if (batch_ && !flooding_.empty() &&
        !plimsoll_batch_instance_graph_step(batch_, flooding_.size(), flooding_.data(),
                                            floodingPoses_.data(), &water_, time_, dt,
                                            moved_.data()))
        failed();
    for (std::size_t j = 0; j < flooding_.size(); ++j) {
        if (moved_[j]) floodingBodies_[j]->rigidBody()->activate();
    }
    // Loads for the awake bodies only: on calm water a body at rest sleeps (Bullet's thresholds,
    // set by FloatingBody) and costs nothing; waves wake every body.
    awake_.clear();
    instances_.clear();
    poses_.clear();
    velocities_.clear();
    for (FloatingBody* body : bodies_) {
        btRigidBody* rb = body->rigidBody();
        if (wavy && !rb->isActive()) rb->activate();
        if (!rb->isActive()) {
            body->load_ = plimsoll_load{};
            continue;
        }
        awake_.push_back(body);
        instances_.push_back(body->instance());
        poses_.push_back(body->pose());
        velocities_.push_back(body->velocity());
    }
    const std::size_t n = awake_.size();
    loads_.assign(n, plimsoll_load{});
    if (batch_ && n > 0 &&
        !plimsoll_batch_instance_water_load(batch_, n, instances_.data(), poses_.data(),
                                            velocities_.data(), &water_, &fluid_, time_, dt,
                                            loads_.data())) {
        failed();
        loads_.assign(n, plimsoll_load{});
    }
    for (std::size_t i = 0; i < n; ++i) {
        btRigidBody* rb = awake_[i]->rigidBody();
        awake_[i]->load_ = loads_[i];
        // As impulses of this substep: Bullet adds a body's total force to its velocity at
        // the step (v += F dt / m), so F dt now is the same push, and the game's own forces
        // (a thruster's applyCentralForce), gravity and callbacks stay as they are. Bullet
        // clears forces only after its last substep, so a force set here would stay for
        // the substeps that follow.
        rb->applyCentralImpulse(vec(loads_[i].force) * btScalar(dt));
        rb->applyTorqueImpulse(vec(loads_[i].torque) * btScalar(dt));
    }
    time_ += dt;
}

}  // namespace plimsoll_bullet
