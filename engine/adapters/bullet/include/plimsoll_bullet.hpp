// Plimsoll over Bullet (Debian's libbullet-dev): Plimsoll supplies buoyancy, drag, damping and
// flooding, Bullet supplies collisions and integrates. Written against the runtime's C API
// (plimsoll_runtime.h), as any engine's adapter would be (docs/engines/bullet.md).
//
// A FloatingBody is a btRigidBody in the frame Bullet needs (origin at the centre of mass, axes
// the principal axes of inertia) built from a bundle; a Harbour registers Bullet's pre-tick
// callback on a world and, before every internal step, steps the bodies' water graphs and
// computes their water loads in one call each (plimsoll_batch_instance_graph_step,
// plimsoll_batch_instance_water_load), then applies each load as impulses of the substep.
// Each FloatingBody is an instance of a shared bundle: a fleet of one boat loads it once.
#pragma once

#include "plimsoll_runtime.h"

#include <btBulletDynamicsCommon.h>

#include <memory>
#include <string>
#include <vector>

namespace plimsoll_bullet {

class Harbour;

class FloatingBody {
public:
    /// A rigid body for an instance of `bundle` (not owned; it must outlive the body, and any
    /// number of bodies may share it) with its object origin at `objectPose`. `objectShape` is a
    /// collision shape in the bundle's object space (not owned); null: the box around the
    /// bundle's samples.
    FloatingBody(const plimsoll_bundle* bundle, const btTransform& objectPose,
                 btCollisionShape* objectShape = nullptr);
    ~FloatingBody();
    FloatingBody(const FloatingBody&) = delete;
    FloatingBody& operator=(const FloatingBody&) = delete;

    btRigidBody* rigidBody() { return body_.get(); }
    const plimsoll_bundle* bundle() const { return bundle_; }
    /// The body's own water and radiation memory (plimsoll_instance_save for snapshots).
    plimsoll_instance* instance() const { return instance_; }
    /// The object origin's world pose and the centre of mass's velocity, from Bullet's state.
    plimsoll_pose pose() const;
    plimsoll_velocity velocity() const;
    /// The load applied in the last step (zero before the first).
    const plimsoll_load& lastLoad() const { return load_; }
    /// Bullet's frame of the body in object space: the centre of mass and principal axes.
    const btTransform& bodyInObject() const { return bodyInObject_; }

private:
    friend class Harbour;
    Harbour* harbour_ =
        nullptr;  // the one it was added to: it leaves it (and its world) when destroyed
    const plimsoll_bundle* bundle_;
    plimsoll_instance* instance_;
    btTransform bodyInObject_;
    std::unique_ptr<btBoxShape> defaultShape_;
    std::unique_ptr<btCompoundShape> shape_;
    std::unique_ptr<btDefaultMotionState> motion_;
    std::unique_ptr<btRigidBody> body_;
    plimsoll_load load_{};
};

/// The water of a Bullet world. Bullet has one pre-tick callback per world: the Harbour chains
/// it, calling the game's (the one set before the Harbour, or given to setPreTickCallback) first,
/// and puts it back when destroyed; the world's user info stays the game's. The load goes in as
/// impulses of each substep, so the game's own forces and torques are kept. fluid.gravity should
/// be the world's gravity. `batch` (may be null: one of the hardware threads is made) runs the
/// bodies' evaluations.
class Harbour {
public:
    Harbour(btDiscreteDynamicsWorld* world, const plimsoll_water& water,
            const plimsoll_fluid& fluid, const plimsoll_batch_desc* batch = nullptr);
    ~Harbour();
    Harbour(const Harbour&) = delete;
    Harbour& operator=(const Harbour&) = delete;

    /// Adds the body to the world and to the water (not owned). Either may be destroyed first:
    /// a body leaves the world and the water when it goes, the Harbour lets go of its bodies.
    void add(FloatingBody* body);
    void remove(FloatingBody* body);
    /// The game's pre-tick callback, called before the water's load every substep. Use it
    /// instead of btDynamicsWorld::setInternalTickCallback(cb, user, true) once the Harbour
    /// exists: that would replace the Harbour's own.
    void setPreTickCallback(btInternalTickCallback callback);
    /// Simulated time of the water, s.
    double time() const { return time_; }
    /// The first runtime error met in a step ("" when none); the body's load is then zero.
    const std::string& error() const { return error_; }

private:
    static void preTick(btDynamicsWorld* world, btScalar step);
    void applyLoads(double dt);

    btDiscreteDynamicsWorld* world_;
    btInternalTickCallback previous_ = nullptr;
    plimsoll_water water_;
    plimsoll_fluid fluid_;
    std::vector<FloatingBody*> bodies_;
    plimsoll_batch* batch_;
    // Per step, one entry per awake body (per flooding body for the graph step).
    std::vector<const plimsoll_instance*> instances_;
    std::vector<plimsoll_instance*> flooding_;
    std::vector<FloatingBody*> floodingBodies_, awake_;
    std::vector<int> moved_;
    std::vector<plimsoll_pose> poses_, floodingPoses_;
    std::vector<plimsoll_velocity> velocities_;
    std::vector<plimsoll_load> loads_;
    double time_ = 0;
    std::string error_;
};

}  // namespace plimsoll_bullet
