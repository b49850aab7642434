// Plimsoll's water load on Jolt Physics bodies: the code docs/engine-integration.md shows for
// Jolt, compiled and tested against a Jolt checkout by tests/adapters/jolt/test_jolt_guide.cpp
// (configure with JOLT_DIR set). Header-only: a game copies it and compiles it with its own Jolt
// (5.0 or later), against the runtime's C ABI.
//
// Jolt clears a body's accumulated force and torque only after the last collision step of
// PhysicsSystem::Update, so the load goes in as impulses, once per collision step, from a
// PhysicsStepListener: a force added in every OnStep would add up over the collision steps,
// and resetting it in between would erase the game's own forces.
#pragma once

#include <Jolt/Jolt.h>

#include <Jolt/Physics/Body/BodyCreationSettings.h>
#include <Jolt/Physics/Body/BodyLock.h>
#include <Jolt/Physics/Body/BodyLockInterface.h>
#include <Jolt/Physics/Collision/Shape/BoxShape.h>
#include <Jolt/Physics/Collision/Shape/OffsetCenterOfMassShape.h>
#include <Jolt/Physics/Collision/Shape/RotatedTranslatedShape.h>
#include <Jolt/Physics/PhysicsStepListener.h>
#include <Jolt/Physics/PhysicsSystem.h>

#include <plimsoll_runtime.h>

#include <algorithm>
#include <mutex>
#include <string>
#include <vector>

static_assert(JPH_VERSION_MAJOR >= 5,
              "the step listener takes a PhysicsStepListenerContext since Jolt 5");

namespace plimsoll_jolt {

/// Settings for a Jolt body of one bundle, placed with its object origin at `position`:
/// - the body's origin is the object's origin, so Body::GetPosition() and GetRotation() are
///   Plimsoll's pose as they are;
/// - the collider is the box around the bundle's samples (pass the game's own shape, in object
///   space, where it has a better one);
/// - mass and inertia are the bundle's, about its centre of mass (OffsetCenterOfMassShape
///   moves the shape's centre of mass onto it);
/// - Jolt's own damping is off: the load carries the water's;
/// - a body with compartments never sleeps, since it may be filling while it looks at rest.
inline JPH::BodyCreationSettings bodySettings(const plimsoll_bundle* bundle, JPH::RVec3Arg position,
                                              JPH::QuatArg rotation, JPH::ObjectLayer layer,
                                              const JPH::Shape* objectShape = nullptr) {
    const plimsoll_mass m = plimsoll_bundle_mass(bundle);
    const JPH::Vec3 com(float(m.center_of_mass[0]), float(m.center_of_mass[1]),
                        float(m.center_of_mass[2]));
    JPH::RefConst<JPH::Shape> shape = objectShape;
    if (!shape) {
        double lo[3] = {0, 0, 0}, hi[3] = {0, 0, 0};
        plimsoll_bundle_bounds(bundle, lo, hi);
        const JPH::Vec3 half(float(0.5 * (hi[0] - lo[0])), float(0.5 * (hi[1] - lo[1])),
                             float(0.5 * (hi[2] - lo[2])));
        const JPH::Vec3 mid(float(0.5 * (hi[0] + lo[0])), float(0.5 * (hi[1] + lo[1])),
                            float(0.5 * (hi[2] + lo[2])));
        const float radius = std::min(JPH::cDefaultConvexRadius, 0.5f * half.ReduceMin());
        shape = JPH::RotatedTranslatedShapeSettings(mid, JPH::Quat::sIdentity(),
                                                    new JPH::BoxShape(half, radius))
                    .Create()
                    .Get();
    }
    const JPH::RefConst<JPH::Shape> moved =
        JPH::OffsetCenterOfMassShapeSettings(com - shape->GetCenterOfMass(), shape).Create().Get();

    JPH::BodyCreationSettings settings(moved, position, rotation, JPH::EMotionType::Dynamic, layer);
    settings.mOverrideMassProperties = JPH::EOverrideMassProperties::MassAndInertiaProvided;
    settings.mMassPropertiesOverride.mMass = float(m.mass);
    const auto column = [&](int c) {
        return JPH::Vec4(float(m.inertia[0][c]), float(m.inertia[1][c]), float(m.inertia[2][c]),
                         0.0f);
    };
    settings.mMassPropertiesOverride.mInertia =
        JPH::Mat44(column(0), column(1), column(2), JPH::Vec4(0, 0, 0, 1));
    settings.mLinearDamping = 0.0f;
    settings.mAngularDamping = 0.0f;
    settings.mAllowSleeping = plimsoll_graph_node_count(bundle) == 0;
    return settings;
}

/// The water's load on every floating body, once per collision step. Register it with
/// PhysicsSystem::AddStepListener; add each floating body with its instance.
class WaterListener final : public JPH::PhysicsStepListener {
public:
    WaterListener(const plimsoll_water& water, const plimsoll_fluid& fluid)
        : water_(water), fluid_(fluid) {}

    /// A floating body: the Jolt body made from bodySettings() and an instance of its bundle
    /// (which holds the body's water and radiation memory; the caller keeps it alive).
    void add(JPH::BodyID body, plimsoll_instance* instance) { bodies_.push_back({body, instance}); }

    /// The first failure's message ("" while none): the failing body gets no load that step.
    std::string error() const {
        std::lock_guard<std::mutex> lock(errorMutex_);
        return error_;
    }
    /// Seconds of water time stepped so far (the water's clock).
    double time() const { return time_; }

    void OnStep(const JPH::PhysicsStepListenerContext& context) override {
        const double dt = context.mDeltaTime;
        // Bodies are locked for the step: the no-lock interface reads and writes them.
        const JPH::BodyLockInterfaceNoLock& locks =
            context.mPhysicsSystem->GetBodyLockInterfaceNoLock();
        for (const Floating& f : bodies_) {
            JPH::BodyLockWrite lock(locks, f.body);
            if (!lock.Succeeded()) continue;
            JPH::Body& body = lock.GetBody();
            if (!body.IsActive()) continue;  // asleep: at rest on calm water
            plimsoll_pose pose;
            const JPH::RVec3 p = body.GetPosition();
            const JPH::Quat q = body.GetRotation();
            pose.position[0] = double(p.GetX());
            pose.position[1] = double(p.GetY());
            pose.position[2] = double(p.GetZ());
            pose.orientation[0] = q.GetW();  // the C API's quaternions are w, x, y, z
            pose.orientation[1] = q.GetX();
            pose.orientation[2] = q.GetY();
            pose.orientation[3] = q.GetZ();
            plimsoll_velocity velocity;
            const JPH::Vec3 v = body.GetLinearVelocity(), w = body.GetAngularVelocity();
            for (int k = 0; k < 3; ++k) {
                velocity.linear[k] = v[k];
                velocity.angular[k] = w[k];
            }
            const bool flooding =
                plimsoll_graph_node_count(plimsoll_instance_bundle(f.instance)) > 0;
            if (flooding &&
                plimsoll_instance_graph_step(f.instance, &pose, &water_, time_, dt) < 0) {
                fail();
                continue;
            }
            plimsoll_load load;
            if (!plimsoll_instance_water_load(f.instance, &pose, &velocity, &water_, &fluid_, time_,
                                              dt, &load)) {
                fail();
                continue;
            }
            // An impulse over the step changes the velocity before Jolt integrates it, as a
            // force over the step does in Jolt's symplectic Euler; the game's forces stay.
            body.AddImpulse(JPH::Vec3(float(load.force[0] * dt), float(load.force[1] * dt),
                                      float(load.force[2] * dt)));
            body.AddAngularImpulse(JPH::Vec3(float(load.torque[0] * dt), float(load.torque[1] * dt),
                                             float(load.torque[2] * dt)));
        }
        time_ += dt;
    }

private:
    struct Floating {
        JPH::BodyID body;
        plimsoll_instance* instance;
    };
    void fail() {
        std::lock_guard<std::mutex> lock(errorMutex_);
        if (error_.empty()) error_ = plimsoll_runtime_last_error();
    }

    plimsoll_water water_;
    plimsoll_fluid fluid_;
    std::vector<Floating> bodies_;
    double time_ = 0.0;
    mutable std::mutex errorMutex_;
    std::string error_;
};

}  // namespace plimsoll_jolt
