// plimsoll buoyancy MESH [--size N | --exact] --water-level H --position=X,Y,Z
//                   --rotation-deg=RX,RY,RZ [--velocity=VX,VY,VZ] [--angular-velocity=WX,WY,WZ]
//                   [--device cpu|gpu|N|reference] [--fluid-density RHO]
//                   [--drag-coefficient CD] [--friction-coefficient CF] [--compare-exact]
//                   --json
#include "cli/commands.h"

#include "cli/common.h"
#include "plimsoll/physics/buoyancy.h"
#include "plimsoll/compute/compute.h"
#include "plimsoll/physics/massprops.h"
#include "plimsoll/physics/volume_check.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <charconv>
#include <chrono>
#include <cmath>
#include <iostream>
#include <memory>
#include <optional>
#include <string>
#include <system_error>

namespace plimsoll::cli {

namespace {
struct BuoyancyOptions {
    std::string mesh;
    BakeOptions bake;
    bool exact = false;
    std::string device;
    double waterLevel = 0.0;
    Eigen::Vector3d position = Eigen::Vector3d::Zero();
    Eigen::Vector3d rotationDegrees = Eigen::Vector3d::Zero();
    Motion motion;
    FluidSettings fluid;
    bool compareExact = false;
    bool json = false;
};

std::optional<BuoyancyResult> evaluateTexture(const BuoyancyOptions& o, const BodyFrame& frame,
                                              std::string& deviceName, double& frameMs,
                                              std::optional<SubmergedVolumeCheck>& check) {
    // The device first: a bad --device fails before the mesh work, which can take a while.
    std::string notice;
    Result<std::unique_ptr<BuoyancyBackend>> backend = createBuoyancyBackend(o.device, &notice);
    if (!backend) {
        std::cerr << "error: " << backend.error().message << "\n";
        return std::nullopt;
    }
    if (!notice.empty()) std::cerr << "note: " << notice << "\n";
    std::optional<BakeableMesh> mesh = loadMeshForBake(o.mesh, o.bake);
    if (!mesh) return std::nullopt;
    std::optional<SurfaceTextures> textures = bakeWithProgress(mesh->mesh, o.bake);
    if (!textures) return std::nullopt;
    // The centre of mass from the same textures, so that torques match what a simulation
    // running on this bake would apply. Any density gives the same centre.
    const Eigen::Vector3d centerOfMass = textureSolidMassProperties(*textures, 1.0).centerOfMass;
    BuoyancyBackend& engine = **backend;
    const BodyRequest request{engine.addBody(*textures, centerOfMass), frame, o.fluid};
    BuoyancyResult result;
    for (int pass = 0; pass < 2; ++pass) {
        const Status s = engine.evaluate({&request, 1}, WaterModel::flat(o.waterLevel),
                                         {&result, 1});
        if (!s) {
            std::cerr << "error: " << s.error().message << "\n";
            return std::nullopt;
        }
    }
    deviceName = engine.deviceName();
    frameMs = engine.lastTimings().totalMs;
    if (o.compareExact) {
        // The same function as the editor's live preview readout (volume_check.h).
        std::optional<TriangleMesh> closed = loadClosedMesh(o.mesh);
        if (!closed) return std::nullopt;
        BodyFrame at = frame;
        at.centerOfMass = centerOfMass;
        Result<SubmergedVolumeCheck> checked =
            checkSubmergedVolume(engine, request.body, *closed, at, o.waterLevel, o.fluid);
        if (!checked) {
            std::cerr << "error: " << checked.error().message << "\n";
            return std::nullopt;
        }
        check = *checked;
    }
    return result;
}

std::optional<BuoyancyResult> evaluateExact(const BuoyancyOptions& o, BodyFrame frame,
                                            double& frameMs) {
    std::optional<TriangleMesh> mesh = loadClosedMesh(o.mesh);
    if (!mesh) return std::nullopt;
    frame.centerOfMass = exactSolidMassProperties(*mesh, 1.0).centerOfMass;
    const auto start = std::chrono::steady_clock::now();
    BuoyancyResult result = evaluateBuoyancyExact(*mesh, frame, o.waterLevel, o.fluid);
    frameMs =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    return result;
}

int runBuoyancy(const BuoyancyOptions& o) {
    BodyFrame frame;
    frame.pose = Pose::fromEulerDegrees(o.position, o.rotationDegrees);
    frame.motion = o.motion;
    std::string deviceName = "exact";
    double frameMs = 0;
    std::optional<SubmergedVolumeCheck> check;
    std::optional<BuoyancyResult> evaluated =
        o.exact ? evaluateExact(o, frame, frameMs)
                : evaluateTexture(o, frame, deviceName, frameMs, check);
    if (!evaluated) return kExitFailure;
    const BuoyancyResult& r = *evaluated;

    nlohmann::json out;
    out["mesh"] = o.mesh;
    out["method"] = o.exact ? "exact" : "texture";
    out["texture_size"] = o.exact ? nlohmann::json(nullptr) : nlohmann::json(o.bake.size);
    out["device"] = deviceName;
    out["submerged_volume"] = r.submergedVolume;
    out["center_of_buoyancy"] = vectorJson(r.centerOfBuoyancy);
    out["force"] = vectorJson(r.force);
    out["torque"] = vectorJson(r.torque);
    out["pressure_force"] = vectorJson(r.pressureForce);
    out["pressure_torque"] = vectorJson(r.pressureTorque);
    out["drag_force"] = vectorJson(r.dragForce);
    out["drag_torque"] = vectorJson(r.dragTorque);
    out["wetted_area"] = r.wettedArea;
    // The exact clip has no texel entries to count.
    out["submerged_samples"] =
        o.exact ? nlohmann::json(nullptr) : nlohmann::json(r.submergedSamples);
    out["timing_ms"] = frameMs;
    if (check) {
        out["exact_submerged_volume"] = check->exact;
        out["submerged_volume_error"] = check->error;
        out["submerged_volume_relative_error"] = check->relativeError;
    }
    if (o.json) {
        std::cout << reportJson(out) << "\n";
        return kExitOk;
    }
    std::cout << o.mesh << " ("
              << (o.exact ? std::string("exact")
                          : "texture " + std::to_string(o.bake.size) + "^2, " + deviceName)
              << ")\n"
              << "  submerged volume    " << r.submergedVolume << " m^3\n"
              << "  centre of buoyancy  " << r.centerOfBuoyancy.transpose() << " m\n"
              << "  force               " << r.force.transpose() << " N\n"
              << "  torque              " << r.torque.transpose() << " N m\n"
              << "  pressure force      " << r.pressureForce.transpose() << " N\n"
              << "  pressure torque     " << r.pressureTorque.transpose() << " N m\n"
              << "  drag force          " << r.dragForce.transpose() << " N\n"
              << "  drag torque         " << r.dragTorque.transpose() << " N m\n"
              << "  wetted area         " << r.wettedArea << " m^2\n";
    if (!o.exact) std::cout << "  submerged samples   " << r.submergedSamples << "\n";
    if (check) {
        std::cout << "  exact volume        " << check->exact << " m^3\n"
                  << "  volume error        " << check->error << " m^3 ("
                  << 100.0 * check->relativeError << " %)\n";
    }
    std::cout << "  time per frame      " << frameMs << " ms\n"
              << "  (world axes; torques about the centre of mass)\n";
    return kExitOk;
}
}  // namespace

void addBuoyancyCommand(CLI::App& root, CommandRunner& selected) {
    auto o = std::make_shared<BuoyancyOptions>();
    CLI::App* cmd = root.add_subcommand(
        "buoyancy",
        "Buoyancy and drag of a body at one pose in flat water.\n"
        "The pose maps an object-space point p to R p + t in the world: t = --position, "
        "R = Rz(rz) Ry(ry) Rx(rx) from --rotation-deg (about fixed x, then y, then z). "
        "y is up; the water fills y < --water-level. Forces are in world axes, torques about "
        "the body's centre of mass (of the bake, or exact with --exact).\n"
        "A vector is one argument, X,Y,Z; give negative values with '=' (--position=-1,2,-3, "
        "--water-level=-0.5), which is never mistaken for an option.");
    cmd->add_option("MESH", o->mesh, "Closed mesh file")->required();
    CLI::Option* size = addBakeOptions(*cmd, o->bake);
    CLI::Option* exact =
        cmd->add_flag("--exact", o->exact,
                      "Clip the mesh exactly against the water plane (no textures, no drag)")
            ->excludes(size);
    cmd->add_option("--device", o->device,
                    "Compute device for the texture path: fast (the fast CPU path), cpu, gpu, an "
                    "OpenCL device index, or reference (C++); default: $PLIMSOLL_OPENCL_DEVICE, "
                    "else the first GPU, else the fast CPU path")
        ->excludes(exact);
    cmd->add_option("--water-level", o->waterLevel, "Height of the flat water surface, m")
        ->check(kFiniteNumber)
        ->required();
    addVectorOption(*cmd, "--position", o->position, "World position t of the object origin, m")
        ->type_name("X,Y,Z")
        ->required();
    addVectorOption(*cmd, "--rotation-deg", o->rotationDegrees,
                    "Rotation about fixed x, then y, then z axes, degrees")
        ->type_name("RX,RY,RZ")
        ->required();
    addVectorOption(*cmd, "--velocity", o->motion.linear,
                    "Linear velocity of the centre of mass, world axes, m/s (default 0)")
        ->type_name("VX,VY,VZ");
    addVectorOption(*cmd, "--angular-velocity", o->motion.angular,
                    "Angular velocity, world axes, rad/s (default 0)")
        ->type_name("WX,WY,WZ");
    cmd->add_option("--fluid-density", o->fluid.density, "Fluid density, kg/m^3")
        ->check(kFinitePositive)
        ->capture_default_str();
    cmd->add_option("--drag-coefficient", o->fluid.dragCoefficient,
                    "Pressure drag coefficient C_d")
        ->check(kFiniteNonNegative)
        ->capture_default_str();
    cmd->add_option("--friction-coefficient", o->fluid.frictionCoefficient,
                    "Skin friction coefficient C_f (0 = off)")
        ->check(kFiniteNonNegative)
        ->capture_default_str();
    cmd->add_flag("--compare-exact", o->compareExact,
                  "Also clip the mesh exactly at the same pose and print the texture's "
                  "submerged-volume error (the editor's live preview shows the same figure)")
        ->excludes(exact);
    cmd->add_flag("--json", o->json, "Print one JSON object");
    cmd->callback([o, &selected] { selected = [o] { return runBuoyancy(*o); }; });
}

}  // namespace plimsoll::cli
