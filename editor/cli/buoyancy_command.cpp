// plimsoll buoyancy MESH [--size N | --exact] --water-level H --position=X,Y,Z
//                   --rotation-deg=RX,RY,RZ [--velocity=VX,VY,VZ] [--angular-velocity=WX,WY,WZ]
//                   [--device cpu|gpu|N|reference] [--fluid-density RHO]
//                   [--drag-coefficient CD] [--friction-coefficient CF] [--compare-exact]
//                   --json
#include "cli/commands.h"

#include "cli/common.h"
#include "cli/jobs.h"
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
    BuoyancyJob job;
    bool json = false;
};

Result<BuoyancyResult> evaluateTexture(const BuoyancyJob& o, const BodyFrame& frame,
                                       BuoyancyOutcome& outcome, const Reporter& reporter) {
    // The device first: a bad --device fails before the mesh work, which can take a while.
    std::string notice;
    Result<std::unique_ptr<BuoyancyBackend>> backend = createBuoyancyBackend(o.device, &notice);
    if (!backend) return backend.error();
    if (!notice.empty()) reporter.note("note: " + notice + "\n");
    Result<BakeableMesh> mesh = bakeableMeshOf(o.mesh, o.bake, reporter);
    if (!mesh) return mesh.error();
    Result<SurfaceTextures> textures = bakeTextures(mesh->mesh, o.bake, reporter);
    if (!textures) return textures.error();
    // The centre of mass from the same textures, so that torques match what a simulation
    // running on this bake would apply. Any density gives the same centre.
    const Eigen::Vector3d centerOfMass = textureSolidMassProperties(*textures, 1.0).centerOfMass;
    BuoyancyBackend& engine = **backend;
    const BodyRequest request{engine.addBody(*textures, centerOfMass), frame, o.fluid};
    BuoyancyResult result;
    for (int pass = 0; pass < 2; ++pass) {
        const Status s =
            engine.evaluate({&request, 1}, WaterModel::flat(o.waterLevel), {&result, 1});
        if (!s) return s.error();
    }
    outcome.deviceName = engine.deviceName();
    outcome.frameMs = engine.lastTimings().totalMs;
    if (o.compareExact) {
        // The same function as the editor's live preview readout (volume_check.h).
        Result<TriangleMesh> closed = closedMeshOf(o.mesh, 0, nullptr, reporter);
        if (!closed) return closed.error();
        BodyFrame at = frame;
        at.centerOfMass = centerOfMass;
        Result<SubmergedVolumeCheck> checked =
            checkSubmergedVolume(engine, request.body, *closed, at, o.waterLevel, o.fluid);
        if (!checked) return checked.error();
        outcome.check = *checked;
    }
    return result;
}

Result<BuoyancyResult> evaluateExact(const BuoyancyJob& o, BodyFrame frame,
                                     BuoyancyOutcome& outcome, const Reporter& reporter) {
    Result<TriangleMesh> mesh = closedMeshOf(o.mesh, 0, nullptr, reporter);
    if (!mesh) return mesh.error();
    frame.centerOfMass = exactSolidMassProperties(*mesh, 1.0).centerOfMass;
    const auto start = std::chrono::steady_clock::now();
    BuoyancyResult result = evaluateBuoyancyExact(*mesh, frame, o.waterLevel, o.fluid);
    outcome.frameMs =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    return result;
}

int runBuoyancy(const BuoyancyOptions& options) {
    Result<BuoyancyOutcome> outcome = buoyancyJob(options.job, stderrReporter());
    if (!outcome) {
        std::cerr << "error: " << outcome.error().message << "\n";
        return kExitFailure;
    }
    if (options.json) {
        std::cout << reportJson(outcome->json) << "\n";
        return kExitOk;
    }
    const BuoyancyJob& o = options.job;
    const BuoyancyResult& r = outcome->result;
    const std::optional<SubmergedVolumeCheck>& check = outcome->check;
    std::cout << o.mesh << " ("
              << (o.exact ? std::string("exact")
                          : "texture " + std::to_string(o.bake.size) + "^2, " + outcome->deviceName)
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
    std::cout << "  time per frame      " << outcome->frameMs << " ms\n"
              << "  (world axes; torques about the centre of mass)\n";
    return kExitOk;
}
}  // namespace

Result<BuoyancyOutcome> buoyancyJob(const BuoyancyJob& o, const Reporter& reporter) {
    BodyFrame frame;
    frame.pose = Pose::fromEulerDegrees(o.position, o.rotationDegrees);
    frame.motion = o.motion;
    BuoyancyOutcome outcome;
    Result<BuoyancyResult> evaluated = o.exact ? evaluateExact(o, frame, outcome, reporter)
                                               : evaluateTexture(o, frame, outcome, reporter);
    if (!evaluated) return evaluated.error();
    const BuoyancyResult& r = outcome.result = *evaluated;

    nlohmann::json& out = outcome.json;
    out["mesh"] = o.mesh;
    out["method"] = o.exact ? "exact" : "texture";
    out["texture_size"] = o.exact ? nlohmann::json(nullptr) : nlohmann::json(o.bake.size);
    out["device"] = outcome.deviceName;
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
    out["timing_ms"] = outcome.frameMs;
    if (outcome.check) {
        out["exact_submerged_volume"] = outcome.check->exact;
        out["submerged_volume_error"] = outcome.check->error;
        out["submerged_volume_relative_error"] = outcome.check->relativeError;
    }
    return outcome;
}

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
    cmd->add_option("MESH", o->job.mesh, "Closed mesh file")->required();
    CLI::Option* size = addBakeOptions(*cmd, o->job.bake);
    CLI::Option* exact =
        cmd->add_flag("--exact", o->job.exact,
                      "Clip the mesh exactly against the water plane (no textures, no drag)")
            ->excludes(size);
    cmd->add_option("--device", o->job.device,
                    "Compute device for the texture path: fast (the fast CPU path), cpu, gpu, an "
                    "OpenCL device index, or reference (C++); default: $PLIMSOLL_OPENCL_DEVICE, "
                    "else the first GPU, else the fast CPU path")
        ->excludes(exact);
    cmd->add_option("--water-level", o->job.waterLevel, "Height of the flat water surface, m")
        ->check(kFiniteNumber)
        ->required();
    addVectorOption(*cmd, "--position", o->job.position, "World position t of the object origin, m")
        ->type_name("X,Y,Z")
        ->required();
    addVectorOption(*cmd, "--rotation-deg", o->job.rotationDegrees,
                    "Rotation about fixed x, then y, then z axes, degrees")
        ->type_name("RX,RY,RZ")
        ->required();
    addVectorOption(*cmd, "--velocity", o->job.motion.linear,
                    "Linear velocity of the centre of mass, world axes, m/s (default 0)")
        ->type_name("VX,VY,VZ");
    addVectorOption(*cmd, "--angular-velocity", o->job.motion.angular,
                    "Angular velocity, world axes, rad/s (default 0)")
        ->type_name("WX,WY,WZ");
    cmd->add_option("--fluid-density", o->job.fluid.density, "Fluid density, kg/m^3")
        ->check(kFinitePositive)
        ->capture_default_str();
    cmd->add_option("--drag-coefficient", o->job.fluid.dragCoefficient,
                    "Pressure drag coefficient C_d")
        ->check(kFiniteNonNegative)
        ->capture_default_str();
    cmd->add_option("--friction-coefficient", o->job.fluid.frictionCoefficient,
                    "Skin friction coefficient C_f (0 = off)")
        ->check(kFiniteNonNegative)
        ->capture_default_str();
    cmd->add_flag("--compare-exact", o->job.compareExact,
                  "Also clip the mesh exactly at the same pose and print the texture's "
                  "submerged-volume error (the editor's live preview shows the same figure)")
        ->excludes(exact);
    cmd->add_flag("--json", o->json, "Print one JSON object");
    cmd->callback([o, &selected] { selected = [o] { return runBuoyancy(*o); }; });
}

}  // namespace plimsoll::cli
