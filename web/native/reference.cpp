// plimsoll_web_reference BUNDLE_FOLDER: the native runtime's forces for the web package's tests.
// With --steps N instead: a body from the world's start stepped N times by 1/240 s on the
// bundle's own water (stepBody; step i at time i/240), then one line: its state (13 numbers:
// position, orientation w x y z, velocity, angular velocity), the water load a step would apply
// there (31: forces, water mass, force, torque) and the body's state hash (16 hex digits).
// Otherwise it reads lines "water t x y z qw qx qy qz vx vy vz wx wy wz" from stdin (water: "own"
// for the bundle's own water, a number for flat water at that level) and prints, per line, the 24
// numbers of plimsoll_web.cpp's putForces with 17 significant digits (enough to give back the
// very double), or "error MESSAGE". Exits 1 when the bundle does not load.
#include "plimsoll_runtime/runtime.hpp"

#include <array>
#include <cstdio>
#include <cstdlib>
#include <iostream>
#include <sstream>
#include <string>

namespace rt = plimsoll_runtime;

namespace {

/// The 24 numbers of plimsoll_web.cpp's putForces, in its order.
std::array<double, 24> forceValues(const rt::Forces& f) {
    return {f.submergedVolume,
            f.centerOfBuoyancy.x,
            f.centerOfBuoyancy.y,
            f.centerOfBuoyancy.z,
            f.force.x,
            f.force.y,
            f.force.z,
            f.torque.x,
            f.torque.y,
            f.torque.z,
            f.pressureForce.x,
            f.pressureForce.y,
            f.pressureForce.z,
            f.pressureTorque.x,
            f.pressureTorque.y,
            f.pressureTorque.z,
            f.dragForce.x,
            f.dragForce.y,
            f.dragForce.z,
            f.dragTorque.x,
            f.dragTorque.y,
            f.dragTorque.z,
            f.wettedArea,
            static_cast<double>(f.submergedSamples)};
}

}  // namespace

int main(int argc, char** argv) {
    if (argc != 2 && argc != 4) {
        std::fprintf(stderr, "usage: plimsoll_web_reference BUNDLE_FOLDER [--steps N] < poses\n");
        return 2;
    }
    std::string error;
    auto bundle = rt::loadBundle(argv[1], error);
    if (!bundle) {
        std::fprintf(stderr, "plimsoll_web_reference: %s\n", error.c_str());
        return 1;
    }
    const rt::Water own = bundle->world().water.water();
    // The bundle's fluid already carries its world's density and gravity (as index.js reads it).
    const rt::Fluid fluid = bundle->fluid();
    if (argc == 4 && std::string(argv[2]) == "--steps") {
        const int steps = std::atoi(argv[3]);
        const double dt = 1.0 / 240.0;
        rt::Body body(*bundle);
        rt::BodyState state;
        state.pose = bundle->world().startPose;
        for (int i = 0; i < steps; ++i) rt::stepBody(body, state, own, fluid, i * dt, dt);
        const rt::WaterLoad load =
            rt::waterLoad(body, state.pose, state.velocity, own, fluid, steps * dt, dt);
        const rt::Forces& f = load.forces;
        const double state13[] = {
            state.pose.position.x,    state.pose.position.y,    state.pose.position.z,
            state.pose.orientation.w, state.pose.orientation.x, state.pose.orientation.y,
            state.pose.orientation.z, state.velocity.linear.x,  state.velocity.linear.y,
            state.velocity.linear.z,  state.velocity.angular.x, state.velocity.angular.y,
            state.velocity.angular.z};
        const double load7[] = {load.waterMass, load.force.x,  load.force.y, load.force.z,
                                load.torque.x,  load.torque.y, load.torque.z};
        for (double v : state13) std::printf("%.17g ", v);
        for (double v : forceValues(f)) std::printf("%.17g ", v);
        for (double v : load7) std::printf("%.17g ", v);
        std::printf("%016llx\n", static_cast<unsigned long long>(body.stateHash()));
        return 0;
    }
    std::string line;
    while (std::getline(std::cin, line)) {
        std::istringstream in(line);
        std::string water;
        double v[14];
        in >> water;
        for (double& x : v) in >> x;
        if (!in) {
            std::printf("error bad line\n");
            continue;
        }
        rt::Water flat;
        if (water != "own") flat.level = std::stod(water);
        rt::Pose pose;
        pose.position = {v[1], v[2], v[3]};
        pose.orientation = {v[4], v[5], v[6], v[7]};
        rt::Velocity velocity;
        velocity.linear = {v[8], v[9], v[10]};
        velocity.angular = {v[11], v[12], v[13]};
        const rt::Forces f =
            bundle->evaluate(pose, velocity, water == "own" ? own : flat, fluid, v[0]);
        const std::array<double, 24> out = forceValues(f);
        for (int i = 0; i < 24; ++i) std::printf(i ? " %.17g" : "%.17g", out[i]);
        std::printf("\n");
    }
    return 0;
}
