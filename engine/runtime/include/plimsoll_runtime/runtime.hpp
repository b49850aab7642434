// Plimsoll runtime: what a game engine embeds to float a body exported by `plimsoll export`
// (docs/bundle.md, "Runtime library"). Depends only on the C++17 standard library, OpenEXR
// (the bundle's float images) and zlib (OpenEXR's own dependency; the 16-bit PNG painted maps).
//
// Conventions are the bundle's: SI units, object space of the source mesh, +y up,
// right-handed. A pose maps an object-space point p to R(q) p + position (position is the
// object's origin, not its centre of mass). Velocities are those of the centre of mass, world
// axes. Forces are world axes; torques about the centre of mass.
//
// Errors: functions that can fail return bool and fill an std::string; nothing throws.
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

namespace plimsoll_runtime {

inline constexpr int kSchemaMajor = 1;   ///< bundle schema this reader knows
inline constexpr int kSchemaMinor = 1;   ///< newest minor it was written for (older: read too)

struct Vec3 {
    double x = 0, y = 0, z = 0;
};

/// Unit quaternion (w, x, y, z), object -> world.
struct Quat {
    double w = 1, x = 0, y = 0, z = 0;
};

struct Pose {
    Vec3 position;        ///< world position of the object's origin, m
    Quat orientation;
};

/// Velocity of the body's centre of mass and its angular velocity, world axes.
struct Velocity {
    Vec3 linear;          ///< m/s
    Vec3 angular;         ///< rad/s
};

/// The water surface y = height(x, z, t) and, optionally, the water's own velocity at a point
/// (for drag; zero when empty). Without a height function the water is flat at `level`.
struct Water {
    double level = 0.0;
    std::function<double(double x, double z, double time)> height;
    std::function<Vec3(const Vec3& point, double time)> velocity;

    double heightAt(double x, double z, double time) const {
        return height ? height(x, z, time) : level;
    }
};

/// The fluid and the drag model's coefficients. loadBundle fills dragCoefficient and
/// frictionCoefficient from the manifest's `hydrodynamics`; the rest is the caller's world.
struct Fluid {
    double density = 1000.0;             ///< kg/m^3
    double gravity = 9.81;               ///< m/s^2, along -y
    double dragCoefficient = 1.0;        ///< C_d of pressure drag
    double frictionCoefficient = 0.0;    ///< C_f of skin friction (0 = off)
};

/// What evaluate() returns: the engine's BuoyancyResult (plimsoll/buoyancy.h).
struct Forces {
    double submergedVolume = 0;          ///< m^3
    Vec3 centerOfBuoyancy;               ///< world, m (the centre of mass when dry)
    Vec3 force;                          ///< Archimedes: (0, rho g V, 0), N
    Vec3 torque;                         ///< (C_B - c) x force, N m
    Vec3 pressureForce;                  ///< -sum p_i A_i, N
    Vec3 pressureTorque;                 ///< N m
    Vec3 dragForce;                      ///< N
    Vec3 dragTorque;                     ///< N m
    double wettedArea = 0;               ///< m^2
    std::size_t submergedSamples = 0;
};

/// Mass properties (about the centre of mass, object axes; products of inertia with the minus
/// sign: I = integral of (r.r Id - r r^T) dm).
struct MassProperties {
    double mass = 0;                     ///< kg
    double volume = 0;                   ///< m^3
    Vec3 centerOfMass;                   ///< object space, m
    double inertia[3][3] = {{0, 0, 0}, {0, 0, 0}, {0, 0, 0}};  ///< kg m^2
};

/// One entry of samples.exr: the list every sum runs over.
struct Sample {
    std::uint32_t texel = 0;             ///< y * N + x
    Vec3 position;                       ///< object space, m
    Vec3 areaVector;                     ///< outward, m^2
    double area = 0;                     ///< m^2
    double coverage = 0;
};

// ---------------------------------------------------------------------------------------
// Water graph

struct GraphNode {
    std::string id, name;
    Vec3 position;                       ///< object space, m
    double capacity = 0;                 ///< m^3
    double water = 0;                    ///< m^3
    bool sealed = false;
    Vec3 box;                            ///< box edges (m); all zero: a sphere of the capacity
    bool isBox() const { return box.x > 0 && box.y > 0 && box.z > 0; }
};

struct GraphPipe {
    std::string a, b;
    int nodeA = -1, nodeB = -1;          ///< indices of a and b
    double radius = 0.01;                ///< m
    double length = 0;                   ///< m; 0 = distance between the nodes
    bool open = true;
};

/// The simulation's settings: the manifest's `water_graph` (inflow, flow, seed, ...); the
/// medium (density, viscosity, gravity) is the caller's world, as for Fluid.
struct GraphSettings {
    bool torricelli = false;             ///< inflow model: false = linear
    double inflowRate = 1.0;             ///< linear: 1/s
    double dischargeCoefficient = 0.6;   ///< Torricelli: C_d
    bool diffusion = false;              ///< flow model: false = Poiseuille
    double diffusionPressure = 1000.0;   ///< Pa
    bool freeSurface = false;
    std::uint64_t seed = 1;
    double permeability = 1.0;           ///< scale of the permeability map
    double density = 1000.0;             ///< kg/m^3
    double viscosity = 1.0e-3;           ///< Pa s
    double gravity = 9.81;               ///< m/s^2
};

/// Per-node water flow through the surface for one pose (m^3/s), before any limiting.
struct NodeInflow {
    std::vector<double> inflow;
    std::vector<double> outflow;
    std::vector<double> outsideTop;      ///< highest outside surface feeding in (-inf: none)
};

class Bundle;

/// The water graph of one body and its state (the engine's WaterGraphSimulation).
class WaterGraph {
public:
    const std::vector<GraphNode>& nodes() const { return nodes_; }
    const std::vector<GraphPipe>& pipes() const { return pipes_; }
    GraphSettings& settings() { return settings_; }
    const GraphSettings& settings() const { return settings_; }
    /// Index of the node fed by each sample of the bundle (-1: none).
    const std::vector<int>& sampleNodes() const { return sampleNodes_; }
    std::size_t permeableSamples() const { return exchange_.size(); }

    /// Water flowing in and out of each node through the permeable surface at this pose.
    NodeInflow inflow(const Pose& pose, const Water& water, double time) const;
    /// One step: exchange with the water outside, then flow between nodes. Returns whether any
    /// water moved.
    bool step(const Pose& pose, const Water& water, double time, double dt);
    /// The two halves of step().
    bool exchange(const Pose& pose, const Water& water, double time, double dt);
    bool flowInside(const Quat& orientation, double dt);

    void setWater(std::size_t node, double water);
    double storedWater() const;
    double entered() const { return entered_; }
    double left() const { return left_; }
    /// The water's mass properties (point masses rho v at the nodes, or with freeSurface at
    /// the water's centroid) at this orientation, object space.
    MassProperties waterMass(const Quat& orientation) const;
    /// Level of node i's water: world height above its position for the body at `orientation`.
    double levelOffset(std::size_t node, double water, const Quat& orientation) const;

private:
    friend class Bundle;
    friend bool loadBundleImpl(const std::string&, Bundle&, std::string&, bool);
    struct Exchange {
        Vec3 position;
        double weight = 0;
        std::uint32_t node = 0;
    };
    struct Link {
        std::uint32_t node, pipe;
    };
    struct Path {
        int node = -1;
        double radius = 0, length = 0;
    };
    void prepare();
    double pipeLength(const GraphPipe& pipe) const;
    double nodeHeight(std::size_t node, const double R[3][3]) const;
    double level(std::size_t node, const double R[3][3]) const;
    double volumeAtLevel(std::size_t node, double offset, const double R[3][3]) const;
    double levelOffsetR(std::size_t node, double water, const double R[3][3]) const;
    void levelRange(std::size_t node, const double R[3][3], double& lo, double& hi) const;
    Vec3 waterCentroid(std::size_t node, double water, const double R[3][3]) const;
    NodeInflow inflowAt(const Pose& pose, const Water& water, double time,
                        const std::vector<double>& surface) const;
    bool applyExchange(const Pose& pose, double dt, const NodeInflow& rates);
    Path findPath(int source, const double R[3][3], const std::vector<double>& levels,
                  double sourceLevel);
    bool flowPoiseuille(const double R[3][3], double dt);
    bool flowDiffusion(double dt);
    std::uint64_t random();
    std::uint64_t randomBelow(std::uint64_t n) { return random() % n; }

    std::vector<GraphNode> nodes_;
    std::vector<GraphPipe> pipes_;
    GraphSettings settings_;
    std::vector<int> sampleNodes_;
    std::vector<Exchange> exchange_;
    std::vector<std::vector<Link>> links_;
    std::vector<double> radius_;
    std::vector<Vec3> scaledBox_;
    double entered_ = 0, left_ = 0, initial_ = 0;
    std::uint64_t rng_ = 1;
};

// ---------------------------------------------------------------------------------------
// Bundle

struct LoadOptions {
    /// Check every file's size and SHA-256 against the manifest (a few ms per MB).
    bool verifyChecksums = true;
};

class Bundle {
public:
    const std::string& folder() const { return folder_; }
    const std::string& body() const { return body_; }
    int schemaMajor() const { return schemaMajor_; }
    int schemaMinor() const { return schemaMinor_; }
    int textureSize() const { return textureSize_; }
    const std::vector<Sample>& samples() const { return samples_; }
    /// mass_properties.texture: what the engine simulates with.
    const MassProperties& mass() const { return mass_; }
    /// The manifest's hydrodynamics (drag/friction coefficients in fluid(); damping in 1/s).
    const Fluid& fluid() const { return fluid_; }
    double linearDamping() const { return linearDamping_; }
    double angularDamping() const { return angularDamping_; }
    /// The body's water graph, or null.
    WaterGraph* graph() { return graph_.get(); }
    const WaterGraph* graph() const { return graph_.get(); }
    /// Whether the node of each sample came from texel_nodes.exr (else computed).
    bool texelNodesFromFile() const { return texelNodesFromFile_; }

    /// Buoyancy, pressure and drag for the body at `pose` moving with `velocity` (the engine's
    /// evaluateBuoyancyReference, summed over samples.exr).
    Forces evaluate(const Pose& pose, const Velocity& velocity, const Water& water,
                    const Fluid& fluid, double time = 0.0) const;

private:
    friend bool loadBundleImpl(const std::string&, Bundle&, std::string&, bool);
    std::string folder_, body_;
    int schemaMajor_ = 0, schemaMinor_ = 0, textureSize_ = 0;
    std::vector<Sample> samples_;
    MassProperties mass_;
    Fluid fluid_;
    double linearDamping_ = 0, angularDamping_ = 0;
    std::unique_ptr<WaterGraph> graph_;
    bool texelNodesFromFile_ = false;
};

/// Loads and checks a bundle folder: the manifest (format, schema major = kSchemaMajor, any
/// minor), every listed file's size and SHA-256, samples.exr, graph.json, the permeability map
/// and texel_nodes.exr when present. On failure returns null and sets `error` to a message
/// naming the file and the problem.
std::unique_ptr<Bundle> loadBundle(const std::string& folder, std::string& error,
                                   const LoadOptions& options = {});

/// SHA-256 of `size` bytes as 64 lowercase hex digits (FIPS 180-4).
std::string sha256Hex(const void* data, std::size_t size);

/// Rotation matrix of a unit quaternion (the same formula as Eigen's toRotationMatrix).
void rotationMatrix(const Quat& q, double R[3][3]);

}  // namespace plimsoll_runtime
