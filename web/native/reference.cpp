// plimsoll_web_reference BUNDLE_FOLDER: the native runtime's forces for the web package's tests.
// Reads lines "water t x y z qw qx qy qz vx vy vz wx wy wz" from stdin (water: "own" for the
// bundle's own water, a number for flat water at that level) and prints, per line, the 24
// numbers of plimsoll_web.cpp's putForces with 17 significant digits (enough to give back the
// very double), or "error MESSAGE". Exits 1 when the bundle does not load.
#include "plimsoll_runtime/runtime.hpp"

#include <cstdio>
#include <iostream>
#include <sstream>
#include <string>

namespace rt = plimsoll_runtime;

int main(int argc, char** argv) {
    if (argc != 2) {
        std::fprintf(stderr, "usage: plimsoll_web_reference BUNDLE_FOLDER < poses\n");
        return 2;
    }
    std::string error;
    auto bundle = rt::loadBundle(argv[1], error);
    if (!bundle) {
        std::fprintf(stderr, "plimsoll_web_reference: %s\n", error.c_str());
        return 1;
    }
    const rt::Water own = bundle->world().water.water();
    rt::Fluid fluid = bundle->fluid();
    fluid.density = bundle->world().density;
    fluid.gravity = -bundle->world().gravity.y;
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
        const rt::Forces f = bundle->evaluate(pose, velocity, water == "own" ? own : flat, fluid, v[0]);
        const double out[24] = {f.submergedVolume, f.centerOfBuoyancy.x, f.centerOfBuoyancy.y, f.centerOfBuoyancy.z,
                                f.force.x, f.force.y, f.force.z, f.torque.x, f.torque.y, f.torque.z,
                                f.pressureForce.x, f.pressureForce.y, f.pressureForce.z,
                                f.pressureTorque.x, f.pressureTorque.y, f.pressureTorque.z,
                                f.dragForce.x, f.dragForce.y, f.dragForce.z,
                                f.dragTorque.x, f.dragTorque.y, f.dragTorque.z,
                                f.wettedArea, static_cast<double>(f.submergedSamples)};
        for (int i = 0; i < 24; ++i) std::printf(i ? " %.17g" : "%.17g", out[i]);
        std::printf("\n");
    }
    return 0;
}
