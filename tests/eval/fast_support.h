// Bodies, random frames and the buoy's waves that the fast path's tests and the fast backend's
// share.
#pragma once

#include "plimsoll/bake/bake.h"
#include "plimsoll/compute/fast_backend.h"
#include "plimsoll/physics/buoyancy.h"
#include "plimsoll/physics/massprops.h"

#include "test_support.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <random>

namespace plimsoll::fast_test {

namespace ev = plimsoll_eval;

struct Body {
    SurfaceTextures textures;
    MassProperties props;
    double radius = 0;  ///< largest distance of an entry from the centre of mass
    ev::FastBody fast;
};

inline Body makeBody(const TriangleMesh& mesh, int size) {
    Body b;
    b.textures = test::bakeOrFail(mesh, size);
    b.props = textureSolidMassProperties(b.textures, 1.0);
    for (const auto& p : b.textures.position)
        b.radius = std::max(b.radius, (p - b.props.centerOfMass).norm());
    b.fast = makeFastBody(b.textures, b.props.centerOfMass);
    return b;
}

inline BodyFrame randomFrame(std::mt19937& random, const Body& body, int kind) {
    std::uniform_real_distribution<double> unit(-1.0, 1.0);
    BodyFrame frame;
    frame.centerOfMass = body.props.centerOfMass;
    frame.pose = Pose::fromEulerDegrees(
        {2 * unit(random), 1.2 * body.radius * unit(random), 2 * unit(random)},
        {180 * unit(random), 90 * unit(random), 180 * unit(random)});
    if (kind >= 1) frame.motion.linear = {unit(random), 0.5 * unit(random), unit(random)};
    if (kind >= 2) frame.motion.angular = {2 * unit(random), 2 * unit(random), unit(random)};
    frame.time = 5.0 * (1.0 + unit(random));
    return frame;
}

inline WaterModel buoyWaves() {  // projects/buoy.plim.json
    WaterModel water;
    water.kind = WaterModel::Kind::Gerstner;
    water.waves = {{0.12, 9.0, {1.0, 0.2}, 0.5, 0.0}, {0.05, 4.0, {0.3, 1.0}, 0.4, 1.3}};
    return water;
}

}  // namespace plimsoll::fast_test
