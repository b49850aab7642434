// Plimsoll runtime: what a game engine embeds to float a body exported by `plimsoll export`
// (docs/bundle.md, "Runtime library"). Depends only on the C++17 standard library and zlib (the
// bundle's EXR images and 16-bit PNG painted maps). For static linking: the shared library
// exports the C ABI only (plimsoll_runtime.h). It includes one header of the evaluation core,
// plimsoll_eval/graph_settings.hpp (the water graph's settings, the engine's own), installed
// beside it.
//
// Conventions are the bundle's: SI units, object space of the source mesh, +y up,
// right-handed. A pose maps an object-space point p to R(q) p + position (position is the
// object's origin, not its centre of mass). Velocities are those of the centre of mass, world
// axes. Forces are world axes; torques about the centre of mass.
//
// Errors: functions that can fail return bool and fill an std::string; nothing throws.
#pragma once

#include "plimsoll_eval/graph_settings.hpp"

#include <cmath>
#include <cstddef>
#include <atomic>
#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

namespace plimsoll_eval {
class FastBody;
}

namespace plimsoll_runtime {

/// A version: the library's own (semantic versioning: a minor only adds) or the bundle schema's
/// (major: readers refuse any other; minor: the newest this reader knows, older ones are read).
struct Version {
    int major = 0, minor = 0, patch = 0;
};
/// The version of this library (its CMake project version).
Version runtimeVersion();
/// The bundle schema this library reads (plimsoll_eval/format.hpp, the exporter's source).
Version bundleSchemaVersion();

struct Vec3 {
    double x = 0, y = 0, z = 0;
};

/// Unit quaternion (w, x, y, z), object -> world.
struct Quat {
    double w = 1, x = 0, y = 0, z = 0;
};

struct Pose {
    Vec3 position;  ///< world position of the object's origin, m
    Quat orientation;
};

/// Velocity of the body's centre of mass and its angular velocity, world axes.
struct Velocity {
    Vec3 linear;   ///< m/s
    Vec3 angular;  ///< rad/s
};

/// The water surface y = height(x, z, t) and, optionally, the water's own velocity at a point
/// (for drag; zero when empty). Without a height function the water is flat at `level`.
struct Water {
    double level = 0.0;
    std::function<double(double x, double z, double time)> height;
    std::function<Vec3(const Vec3& point, double time)> velocity;
    /// Bounds of `height` (m), if known: a body wholly above maxHeight costs nothing.
    double minHeight = -HUGE_VAL, maxHeight = HUGE_VAL;
    /// Many heights in one call, out[i] = f(x[i], z[i], time): evaluate() asks for a small grid
    /// of points per body at once. When set it is used instead of `height`.
    std::function<void(std::size_t n, const double* x, const double* z, double time, double* out)>
        heights;
    /// Many velocities in one call, out[3 i + 0..2] the water's velocity at (x[i], y[i], z[i]):
    /// evaluate() asks for every point it needs (one per wet tile) at once. When set it is used
    /// instead of `velocity`.
    std::function<void(std::size_t n, const double* x, const double* y, const double* z,
                       double time, double* out)>
        velocities;

    double heightAt(double x, double z, double time) const {
        if (heights) {
            double out = level;
            heights(1, &x, &z, time, &out);
            return out;
        }
        return height ? height(x, z, time) : level;
    }
};

/// The fluid and the drag model's coefficients. loadBundle fills dragCoefficient and
/// frictionCoefficient from the manifest's `hydrodynamics`; the rest is the caller's world.
struct Fluid {
    double density = 1000.0;           ///< kg/m^3
    double gravity = 9.81;             ///< m/s^2, along -y
    double dragCoefficient = 1.0;      ///< C_d of pressure drag
    double frictionCoefficient = 0.0;  ///< C_f of skin friction (0 = off)
};

/// What evaluate() returns: the engine's BuoyancyResult (plimsoll/physics/buoyancy.h).
struct Forces {
    double submergedVolume = 0;  ///< m^3
    Vec3 centerOfBuoyancy;       ///< world, m (the centre of mass when dry)
    Vec3 force;                  ///< Archimedes: (0, rho g V, 0), N
    Vec3 torque;                 ///< (C_B - c) x force, N m
    Vec3 pressureForce;          ///< -sum p_i A_i, N
    Vec3 pressureTorque;         ///< N m
    Vec3 dragForce;              ///< N
    Vec3 dragTorque;             ///< N m
    double wettedArea = 0;       ///< m^2
    std::size_t submergedSamples = 0;
};

/// Mass properties (about the centre of mass, object axes; products of inertia with the minus
/// sign: I = integral of (r.r Id - r r^T) dm).
struct MassProperties {
    double mass = 0;                                           ///< kg
    double volume = 0;                                         ///< m^3
    Vec3 centerOfMass;                                         ///< object space, m
    double inertia[3][3] = {{0, 0, 0}, {0, 0, 0}, {0, 0, 0}};  ///< kg m^2
};

/// One entry of samples.exr: the list every sum runs over.
struct Sample {
    std::uint32_t texel = 0;  ///< y * N + x
    Vec3 position;            ///< object space, m
    Vec3 areaVector;          ///< outward, m^2
    double area = 0;          ///< m^2
    double coverage = 0;
};

// ---------------------------------------------------------------------------------------
// Water graph

struct GraphNode {
    std::string id, name;
    Vec3 position;        ///< object space, m
    double capacity = 0;  ///< m^3
    double water = 0;     ///< m^3
    bool sealed = false;
    Vec3 box;  ///< box edges (m); all zero: a sphere of the capacity
    bool isBox() const { return box.x > 0 && box.y > 0 && box.z > 0; }
};

struct GraphPipe {
    std::string a, b;
    int nodeA = -1, nodeB = -1;  ///< indices of a and b
    double radius = 0.01;        ///< m
    double length = 0;           ///< m; 0 = distance between the nodes
    bool open = true;
};

// ---------------------------------------------------------------------------------------
// Files inside a folder

/// What stopped readFileInside.
enum class FileReadProblem { None, Outside, Missing, Link, NotRegular, TooLarge, Unreadable };

/// Reads the file `relative` names inside `folder` into `bytes`, as every file of a bundle is
/// read (and the engine reads the files a mesh refers to): the path stays inside (not empty,
/// not absolute, no "..", backslash or NUL byte); each component is opened relative to its
/// folder's descriptor without following a link (openat with O_NOFOLLOW: a link could name any
/// file of the system, and a check of the path before opening it could be raced); the file is
/// opened without blocking and read only if it is a regular file (not a FIFO or a device) of at
/// most `maxBytes`. False with `error` naming the file and the problem, `problem` its kind.
bool readFileInside(const std::string& folder, const std::string& relative, std::uint64_t maxBytes,
                    std::string& bytes, std::string& error, FileReadProblem* problem = nullptr);

// ---------------------------------------------------------------------------------------
// graph.json

/// How readGraphJson reads a graph.json (docs/formats.md): the format has one reader, which
/// reads it as each of its two uses needs.
enum class GraphJsonMode {
    /// A bundle's graph, written by the engine: the first problem ends the reading, a member
    /// this reader does not know (a newer minor schema's) is ignored, and the graph's own rules
    /// are checked here: a node at least, ids used once, pipes between two different nodes
    /// that exist, capacities > 0, water in 0..capacity, radii > 0, lengths >= 0.
    Bundle,
    /// A graph as people write and edit it: every problem of form is reported, one a line; a
    /// member this reader does not know is refused (a misspelt key is a mistake); an id may be
    /// an integer (kept as its decimal text); "pipes" may be left out. The graph's own rules
    /// are the caller's (the engine's validateGraph names each with its class).
    Authoring,
};

/// What ended a failed readGraphJson.
enum class GraphJsonProblem {
    None,
    Syntax,       ///< not JSON (the message gives line and column)
    Limit,        ///< nested deeper than JSON may be, or more nodes or pipes than a graph may have
    NewerSchema,  ///< a schema_version newer than this reader knows
    Content,      ///< valid JSON that is not a graph (each problem with its JSON path)
};

/// Reads graph.json's `text` (called `source` in messages) into `nodes` and `pipes`, with each
/// pipe's node indices set where its ids name a node. False on a problem: `problem` says what
/// kind, `error` gives the message(s), each "source: $.json.path: what".
bool readGraphJson(const std::string& source, const std::string& text, GraphJsonMode mode,
                   std::vector<GraphNode>& nodes, std::vector<GraphPipe>& pipes,
                   GraphJsonProblem& problem, std::string& error);

/// The simulation's settings: the manifest's `water_graph` (inflow, flow, seed, ...) and the
/// medium (density, viscosity, gravity: the caller's world, as for Fluid). The engine's own
/// struct (plimsoll_eval/graph_settings.hpp, installed with this header).
using GraphSettings = plimsoll_eval::GraphSettings;
using InflowModel = plimsoll_eval::InflowModel;
using FlowMode = plimsoll_eval::FlowMode;

/// Per-node water flow through the surface for one pose (m^3/s), before any limiting.
struct NodeInflow {
    std::vector<double> inflow;
    std::vector<double> outflow;
    std::vector<double> outsideTop;  ///< highest outside surface feeding in (-inf: none)
};

class Bundle;
class BundleLoader;

/// A body's water graph as the bundle ships it: compartments (with the water they start with),
/// pipes, settings and the permeable surface. Part of the shared, immutable Bundle; each body
/// steps its own WaterGraph over it.
class GraphLayout {
public:
    GraphLayout();
    ~GraphLayout();
    GraphLayout(const GraphLayout&) = delete;
    GraphLayout& operator=(const GraphLayout&) = delete;

    /// The nodes, `water` as exported (what a new WaterGraph starts with).
    const std::vector<GraphNode>& nodes() const { return nodes_; }
    const std::vector<GraphPipe>& pipes() const { return pipes_; }
    /// The manifest's settings, with the project's medium.
    const GraphSettings& settings() const { return settings_; }
    /// Index of the node fed by each sample of the bundle (-1: none).
    const std::vector<int>& sampleNodes() const { return sampleNodes_; }
    /// Samples through which water can pass (permeability > 0, feeding an unsealed node).
    std::size_t permeableSamples() const;
    /// Bytes the layout holds.
    std::uint64_t memoryBytes() const;

private:
    friend class WaterGraph;
    friend class BundleLoader;
    struct Exchange {
        Vec3 position;
        double weight = 0;
        std::uint32_t node = 0;
    };
    /// Hands the loaded nodes, pipes and permeable samples to the step's form (after loading).
    void prepare(std::vector<Exchange> exchange);

    std::vector<GraphNode> nodes_;
    std::vector<GraphPipe> pipes_;
    GraphSettings settings_;
    std::vector<int> sampleNodes_;
    struct Prepared;  ///< the evaluation core's form: exchange points, start state (graph.cpp)
    std::unique_ptr<const Prepared> prepared_;
};

/// The water inside one body: its own state (water per node, the random sequence, the
/// bookkeeping) over a GraphLayout shared by every body of the same bundle. The engine's
/// WaterGraphSimulation, whose step (plimsoll_eval/graph.hpp) this library compiles too.
/// One thread at a time per WaterGraph; any number of them may share a layout.
class WaterGraph {
public:
    /// Starts with the layout's water; the layout must outlive it.
    explicit WaterGraph(const GraphLayout& layout);
    ~WaterGraph();
    WaterGraph(const WaterGraph&);
    WaterGraph& operator=(const WaterGraph&) = delete;

    const GraphLayout& layout() const { return *layout_; }
    std::size_t nodeCount() const { return layout_->nodes().size(); }
    /// Water in node i now, m^3.
    double water(std::size_t node) const;
    /// The medium inside (density, viscosity, gravity) and the layout's models.
    const GraphSettings& settings() const { return settings_; }
    void setMedium(double density, double viscosity, double gravity);

    /// Water flowing in and out of each node through the permeable surface at this pose. The
    /// outside heights are asked once for all permeable samples (Water::heights when set).
    NodeInflow inflow(const Pose& pose, const Water& water, double time) const;
    /// One step: exchange with the water outside, then flow between nodes. Returns whether any
    /// water moved.
    bool step(const Pose& pose, const Water& water, double time, double dt);
    /// The two halves of step().
    bool exchange(const Pose& pose, const Water& water, double time, double dt);
    bool flowInside(const Quat& orientation, double dt);

    /// Sets node i's water (clamped to 0..capacity), booked as initial water.
    void setWater(std::size_t node, double water);
    /// The state the steps change (water per node, the random sequence, the bookkeeping), as
    /// bytes appended to `out`; restoreState reads it back from `in` at `at` (advanced past it)
    /// and continues bit for bit. False (nothing changed) for bytes of another graph.
    void saveState(std::vector<std::uint8_t>& out) const;
    bool restoreState(const std::vector<std::uint8_t>& in, std::size_t& at);
    double storedWater() const;
    double entered() const;
    double left() const;
    /// The water's mass properties (point masses rho v at the nodes, or with freeSurface at
    /// the water's centroid) at this orientation, object space.
    MassProperties waterMass(const Quat& orientation) const;
    /// Level of node i's water: world height above its position for the body at `orientation`.
    double levelOffset(std::size_t node, double water, const Quat& orientation) const;
    /// Bytes this graph's own state holds (not the shared layout).
    std::uint64_t memoryBytes() const;

private:
    const GraphLayout* layout_;
    GraphSettings settings_;
    struct Step;  ///< the evaluation core's state (graph.cpp)
    std::unique_ptr<Step> step_;
};

// ---------------------------------------------------------------------------------------
// Bundle

/// One filter of a mode's radiation memory: the damped oscillator x'' + 2 zeta w x' + w^2 x = v
/// driven by the body's velocity in the mode, pushing back with -gain x'.
struct RadiationTerm {
    double gain = 0;          ///< >= 0 (kg/s^2 for translations, kg m^2/s^2 for rotations)
    double frequency = 0;     ///< w > 0, rad/s
    double dampingRatio = 0;  ///< zeta > 0
};

/// A body's wave radiation (manifest "radiation", schema 1.3; docs/bundle.md "Radiation"):
/// Cummins' equation with the infinite-frequency added mass in the mass matrix and the memory
/// of the radiated waves as filters per mode. Body axes about the centre of mass of mass();
/// modes surge x, heave y, sway z, roll x, yaw y, pitch z.
struct Radiation {
    double restVolume = 0;                ///< displaced at rest, m^3
    double addedMassInfinity[6][6] = {};  ///< kg, kg m, kg m^2 (symmetric)
    std::vector<RadiationTerm> memory[6];

    /// The added mass a body entrains when `share` of its rest volume is under water: share
    /// times addedMassInfinity's translational (kg) and rotational (kg m^2) blocks, body axes.
    void sharedAddedMass(double share, double translational[3][3], double rotational[3][3]) const {
        for (int i = 0; i < 3; ++i) {
            for (int j = 0; j < 3; ++j) {
                translational[i][j] = share * addedMassInfinity[i][j];
                rotational[i][j] = share * addedMassInfinity[i + 3][j + 3];
            }
        }
    }
};

/// A water model the bundle carries (manifest "world.water", schema 1.4): the project's own
/// water, the engine's reference formulas (plimsoll_eval/water.hpp) in double precision.
struct WaterModel {
    enum class Kind { Flat, Gerstner, HeightGrid };
    struct Wave {
        double amplitude = 0.1;            ///< m
        double wavelength = 10.0;          ///< m
        double direction[2] = {1.0, 0.0};  ///< (x, z), normalised on use
        double steepness = 0.5;            ///< 0..1
        double phase = 0.0;                ///< rad
    };
    Kind kind = Kind::Flat;
    double level = 0.0;          ///< mean height, m
    std::vector<Wave> waves;     ///< Gerstner
    int countX = 0, countZ = 0;  ///< HeightGrid: samples along x and z
    double spacing = 1.0, originX = 0.0, originZ = 0.0;
    std::vector<float> heights;  ///< countX * countZ, row = fixed z, relative to level
    double gravity = 9.81;       ///< for the waves' dispersion, m/s^2

    double height(double x, double z, double time) const;
    Vec3 velocity(const Vec3& point, double time) const;
    double maxHeight() const;
    double minHeight() const;
    /// A Water whose callbacks ask this model (which must outlive it), with its bounds.
    Water water() const;
};

/// The world the body was exported from (manifest "world", schema 1.4): what the editor's
/// World simulates it in. `present` is false for a bundle before 1.4 (the defaults below).
struct BundleWorld {
    bool present = false;
    double density = 1000.0;    ///< the medium's, kg/m^3
    double viscosity = 1.0e-3;  ///< Pa s
    Vec3 gravity{0, -9.81, 0};  ///< m/s^2
    WaterModel water;
    double timeStep = 1.0 / 60.0;  ///< s, one frame
    int subSteps = 4;              ///< at least, per frame
    double maxPhaseStep = 0.5;     ///< rad (World's rule for more sub-steps)
    std::string integrator = "semi-implicit-euler";
    Pose startPose;          ///< the object origin's world pose
    Velocity startVelocity;  ///< of the centre of mass (with its water)
    /// When a body at rest on calm water sleeps (manifest "world.simulation.sleep", schema 1.5;
    /// docs/design.md "Sleeping bodies"). Off for a bundle before 1.5, whose editor had no
    /// sleeping bodies.
    struct Sleep {
        bool enabled = false;
        double linearSpeed = 0;          ///< m/s, of the centre of mass and of the water
        double angularSpeed = 0;         ///< rad/s
        double linearAcceleration = 0;   ///< m/s^2, the velocity's change over a frame
        double angularAcceleration = 0;  ///< rad/s^2
        double restTime = 0;             ///< s below them all before it sleeps
        double wakeHeight = 0;           ///< m, a change of the water's height above it
    } sleep;
};

struct LoadOptions {
    /// Check every file's size and SHA-256 against the manifest (a few ms per MB).
    bool verifyChecksums = true;
};

/// One loaded bundle: the shape asset (samples, tiles, mass, graph layout, radiation model).
/// One level of a body's level ladder (bundle schema 1.6, the manifest's "levels";
/// docs/bundle.md): a bake of its own at `size` texels per side, with its stated errors.
struct BundleLevel {
    int size = 0;             ///< texels per side
    std::size_t samples = 0;  ///< entries of its sample list
    /// Its largest |F - F_exact| / (rho g V) over the exporter's test poses (F both Archimedes'
    /// force and the pressure integral, F_exact the exact clip of the mesh); 0: not stated (a
    /// bundle without a ladder).
    double forceError = 0;
    double torqueError = 0;   ///< the same for the torque about the centre of mass, over rho g V R
    double evaluationUs = 0;  ///< microseconds one evaluation took where the bundle was exported
};

/// Immutable after loading and thread-safe: any number of Body instances, Simulations and
/// threads share one (a fleet of one boat loads it once). What changes as a body floats lives
/// in its Body.
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
    /// The linear damping of the horizontal momentum; verticalDamping() of the momentum along
    /// gravity ("vertical_damping", where a radiating body's radiation damps its heave; absent:
    /// the same as linear_damping).
    double linearDamping() const { return linearDamping_; }
    double verticalDamping() const { return verticalDamping_; }
    double angularDamping() const { return angularDamping_; }
    /// The project's world: medium, water, step settings and the body's start (schema 1.4).
    const BundleWorld& world() const { return world_; }
    /// The body's wave radiation, or null (a body exported without it, or a bundle before 1.3).
    const Radiation* radiation() const { return radiation_.get(); }
    /// The body's water graph as shipped, or null. Each Body (or Simulation) steps its own water
    /// over it.
    const GraphLayout* graph() const { return graph_.get(); }
    /// Whether the node of each sample came from texel_nodes.exr (else computed).
    bool texelNodesFromFile() const { return texelNodesFromFile_; }
    /// What the body's bundle ships: the manifest plus every file it lists, in bytes.
    std::uint64_t fileBytes() const { return fileBytes_; }
    /// What the loaded asset holds in memory: the sample list, the water graph's layout and,
    /// once the first evaluate() has built them, the evaluation tiles.
    std::uint64_t memoryBytes() const;

    /// Buoyancy, pressure and drag for the body at `pose` moving with `velocity`: the engine's
    /// fast CPU path over samples.exr (the same code: plimsoll_eval/fast.hpp), whose tiles are
    /// built on the first call. Thread-safe.
    Forces evaluate(const Pose& pose, const Velocity& velocity, const Water& water,
                    const Fluid& fluid, double time = 0.0) const;

    /// The body's levels, coarsest first; the last is the finest (textureSize(), samples()).
    /// One level, its errors 0, for a bundle without a ladder (before 1.6, or exported without).
    const std::vector<BundleLevel>& levels() const { return levels_; }
    /// evaluate() over level `level` of levels() (its own sample list, whose tiles are built on
    /// its first call); the finest is evaluate() itself. Thread-safe.
    Forces evaluateLevel(std::size_t level, const Pose& pose, const Velocity& velocity,
                         const Water& water, const Fluid& fluid, double time = 0.0) const;

private:
    friend class BundleLoader;
    std::string folder_, body_;
    std::uint64_t fileBytes_ = 0;
    int schemaMajor_ = 0, schemaMinor_ = 0, textureSize_ = 0;
    std::vector<Sample> samples_;
    MassProperties mass_;
    Fluid fluid_;
    double linearDamping_ = 0, verticalDamping_ = 0, angularDamping_ = 0;
    std::unique_ptr<const Radiation> radiation_;
    BundleWorld world_;
    std::unique_ptr<const GraphLayout> graph_;
    bool texelNodesFromFile_ = false;
    const plimsoll_eval::FastBody& fastBody() const;
    /// Bytes of the evaluation tiles (0 until the first evaluate() builds them).
    std::uint64_t fastBytes() const;
    mutable std::once_flag fastOnce_;
    mutable std::shared_ptr<const plimsoll_eval::FastBody> fast_;
    mutable std::atomic<bool> fastBuilt_{false};
    std::vector<BundleLevel> levels_;
    /// A level below the finest: its samples and, once evaluated, its tiles.
    struct CoarseLevel {
        std::vector<Sample> samples;
        mutable std::once_flag once;
        mutable std::shared_ptr<const plimsoll_eval::FastBody> fast;
        mutable std::atomic<bool> built{false};
    };
    std::vector<std::unique_ptr<CoarseLevel>> coarse_;  ///< levels_ but the finest, in order
};

/// Loads and checks a bundle folder: the manifest (format, schema major =
/// bundleSchemaVersion().major, any minor), every listed file's size and SHA-256, samples.exr,
/// graph.json, the permeability map and texel_nodes.exr when present. On failure returns null
/// and sets `error` to a message naming the file and the problem.
std::unique_ptr<Bundle> loadBundle(const std::string& folder, std::string& error,
                                   const LoadOptions& options = {});

/// One file of a bundle held in memory: its path inside the bundle ("samples.exr",
/// "maps/permeability.png") and its bytes, which must outlive the load call only.
struct MemoryFile {
    std::string path;
    const void* data = nullptr;
    std::size_t size = 0;
};

/// Loads a bundle whose files are in memory, with the checks of loadBundle: every path inside
/// the bundle, the same size limits, checksums, non-finite data refused. `name` prefixes the
/// messages ("name/samples.exr: missing") as the folder does for loadBundle.
std::unique_ptr<Bundle> loadBundleFromMemory(const std::vector<MemoryFile>& files,
                                             const std::string& name, std::string& error,
                                             const LoadOptions& options = {});

/// A bundle's files read through the caller: a pak file, an archive, the engine's own file
/// system. The loader asks only for paths that stay inside the bundle ('/'-separated, no "..",
/// not absolute) and checks the size before it allocates.
struct FileCallbacks {
    /// Opens `path`; null when there is no such file.
    std::function<void*(const std::string& path)> open;
    /// Size of an open file in bytes; negative when it cannot be known.
    std::function<long long(void* file)> size;
    /// Reads up to `bytes` bytes at `offset` into `buffer`: how many were read, 0 at the end,
    /// negative on an error.
    std::function<long long(void* file, std::uint64_t offset, void* buffer, std::size_t bytes)>
        read;
    /// Closes a file open() returned (called once for each).
    std::function<void(void* file)> close;
};

/// Loads a bundle through `callbacks`, with the checks of loadBundle.
std::unique_ptr<Bundle> loadBundleWithCallbacks(const FileCallbacks& callbacks,
                                                const std::string& name, std::string& error,
                                                const LoadOptions& options = {});

/// What a bundle's manifest says of the bundle as a whole (readBundleManifest).
struct BundleManifest {
    int schemaMajor = 0, schemaMinor = 0;
    std::string body;  ///< "body"; empty when absent
    struct File {
        std::string path;    ///< inside the bundle, as the manifest spells it
        std::string sha256;  ///< as the manifest gives it (lower-case hex)
        std::uint64_t bytes = 0;
    };
    std::vector<File> files;  ///< the manifest's `files`, in its order
};

/// The checks every load begins with (docs/bundle.md, "Reading a bundle"), and nothing else:
/// `folder`/manifest.json read (at most 256 MiB, no link followed) and parsed; its `format`
/// a Plimsoll runtime bundle; its schema major bundleSchemaVersion().major (any minor); every
/// path it names inside the bundle and every file of `files` listed once; then, with
/// `verifyFiles`, each listed file opened inside the folder without following links, with the
/// listed size and SHA-256. On failure returns false and sets `error` to a message naming the
/// file and the problem, as loadBundle would; else fills `out`.
bool readBundleManifest(const std::string& folder, BundleManifest& out, std::string& error,
                        bool verifyFiles = true);

/// The checks of readBundleManifest that need no file but the manifest, on its text;
/// `manifestName` names it in messages ("folder/manifest.json").
bool parseBundleManifest(const std::string& text, const std::string& manifestName,
                         BundleManifest& out, std::string& error);

// ---------------------------------------------------------------------------------------
// Motion: what a physics engine applies each step, and an integrator for a body on its own

/// What the water does to a body in one step, to add to the physics engine's gravity: forces
/// at the centre of mass (world axes) and torques about it.
struct WaterLoad {
    Vec3 force;            ///< buoyancy + drag + damping + the weight of water inside, N
    Vec3 torque;           ///< N m
    Forces forces;         ///< evaluate()'s result the load was made of
    double waterMass = 0;  ///< kg of water inside (its weight is in `force`)
};

/// A body on its own: the world pose of its object origin and the velocity of its centre of mass.
struct BodyState {
    Pose pose;
    Velocity velocity;
};

/// What radiation adds to a step, from RadiationMemory::begin.
struct RadiationLoad {
    /// The share of the equilibrium added mass and memory the body has now: 1 while at least
    /// half its resting displacement is under water, falling to 0 as it leaves the water.
    double share = 0;
    /// The share of the call before (-1 on the first): when the share grows, an integrator
    /// keeps the body's momentum (the body drags the water along); when it shrinks, the
    /// velocity. Either way the kinetic energy can only fall.
    double previousShare = -1;
    double addedMass[3][3] = {};     ///< share x the translational block of A_inf, body axes
    double addedInertia[3][3] = {};  ///< share x the rotational block, body axes
    Vec3 force;                      ///< the memory's force, world axes, N
    Vec3 torque;                     ///< its torque about the centre of mass, N m
};

/// A radiating body's memory between steps: its filters and the share it last had. An engine
/// with its own integrator calls begin() before its step (adds the added mass to the body's
/// mass and inertia, applies force and torque) and advance() after it; stepBody does both for
/// a Body with radiation. One per body; not thread-safe.
class RadiationMemory {
public:
    /// For the bundle's radiation (null: a body without it, which then gets nothing).
    explicit RadiationMemory(const Radiation* radiation);
    /// The share, added mass and memory load at `pose` with `submergedVolume` under water
    /// (evaluate()'s submergedVolume), and remembers the share for advance().
    RadiationLoad begin(const Pose& pose, double submergedVolume);
    /// Advances the filters by dt with the body's velocity after the step (centre of mass,
    /// world axes), scaled by the share begin() found.
    void advance(const Pose& pose, const Velocity& velocity, double dt);
    /// The share begin() found last (0 before the first call).
    double share() const { return share_; }
    /// The energy the filters hold, J (the body's mechanical energy plus this never grows).
    double energy() const;
    /// The filters' state and the share, as bytes appended to `out`; restoreState reads them
    /// back from `in` at `at` (advanced past them). False (nothing changed) for bytes of
    /// another body's memory.
    void saveState(std::vector<std::uint8_t>& out) const;
    bool restoreState(const std::vector<std::uint8_t>& in, std::size_t& at);

private:
    struct Filter {
        double x = 0, rate = 0;
    };
    const Radiation* radiation_;
    std::vector<Filter> filters_[6];
    double share_ = 0;
    bool started_ = false;
};

/// One floating body: a small instance over a shared Bundle. It holds what changes as the body
/// floats (the water in its compartments and the random sequence that spreads it, the
/// radiation memory); the bundle holds everything else. A hundred boats of one bundle are one
/// load and a hundred Bodies. The game's physics engine (or stepBody) holds the pose and the
/// velocity. One thread at a time per Body; any number of Bodies of one bundle on any threads.
class Body {
public:
    /// The bundle must outlive the body. The water starts as exported; the radiation memory
    /// (for a bundle with radiation) at rest.
    explicit Body(const Bundle& bundle);
    Body(const Body& other);
    Body& operator=(const Body&) = delete;
    ~Body();

    const Bundle& bundle() const { return *bundle_; }
    /// The body's own water, or null for a bundle without a water graph.
    WaterGraph* graph() { return graph_.get(); }
    const WaterGraph* graph() const { return graph_.get(); }
    /// The body's own radiation memory, or null for a bundle without radiation.
    RadiationMemory* radiation() { return radiation_.get(); }
    const RadiationMemory* radiation() const { return radiation_.get(); }

    /// Everything the body's next steps depend on beyond its pose and velocity (the graph's
    /// water, random sequence and bookkeeping; the radiation filters), as bytes: restore() on a
    /// Body of the same bundle continues bit for bit. For multiplayer snapshots and rollback.
    std::vector<std::uint8_t> save() const;
    /// save() into `out` (cleared first; its capacity is reused, so a caller that saves every
    /// step allocates nothing after the first).
    void save(std::vector<std::uint8_t>& out) const;
    /// False with `error` (nothing changed) for bytes of another body or damaged ones.
    bool restore(const std::vector<std::uint8_t>& bytes, std::string& error);
    /// FNV-1a (64 bits) of save().
    std::uint64_t stateHash() const;
    /// Bytes the instance holds (not the shared bundle).
    std::uint64_t memoryBytes() const;

    /// Stepped by stepBody, the body sleeps at rest on calm water as the editor's World's
    /// bodies do (the bundle's world().sleep; never for a bundle before 1.5): a step then costs
    /// one look at the water above it and leaves the state as it is. It wakes when that water
    /// moves or rises, when the game changes its pose or gives it a velocity, or on wake().
    /// A game whose own engine integrates (waterLoad) uses the engine's sleeping instead.
    bool asleep() const { return sleep_.asleep; }
    void wake();

private:
    friend void stepBody(Body&, BodyState&, const Water&, const Fluid&, double, double);
    struct Sleep {
        bool asleep = false;
        double restedFor = 0;    ///< s below the thresholds so far
        double waterHeight = 0;  ///< the water's height above the body when it fell asleep
        Pose pose;               ///< where it fell asleep
    };
    const Bundle* bundle_;
    std::unique_ptr<WaterGraph> graph_;
    std::unique_ptr<RadiationMemory> radiation_;
    Sleep sleep_;
};

/// The load on the body at `pose` moving with `velocity`: on flat water (no height callback)
/// Archimedes' force and torque, on waves the pressure integral (which carries their
/// horizontal push), as the engine's World applies them; drag; the manifest's linear and
/// angular damping of the momenta of the body with its water (scaled by the submerged
/// fraction, at most what stops the body within `dt`, as the World limits dissipation); and,
/// for a body with a water graph, the weight of its water at the water's centre of mass. The
/// body's own weight is not in it (the physics engine's gravity gives that), nor radiation
/// (its added mass belongs in the mass matrix: body.radiation()->begin and advance).
WaterLoad waterLoad(const Body& body, const Pose& pose, const Velocity& velocity,
                    const Water& water, const Fluid& fluid, double time, double dt);

/// One semi-implicit Euler step of `dt` for a body with no contacts (gravity along -y of
/// fluid.gravity, then waterLoad; the water graph, if any, steps first): momenta first, then
/// position and orientation with the new velocities (angular momentum integrated, so a
/// tumbling body keeps it). For a body with radiation, the share of the added mass is in the
/// mass matrix (never applied as a force) and the memory's load is added; when the share grows
/// the momentum is kept, when it shrinks the velocity (the kinetic energy can only fall), as the
/// engine's World does. For engines without a physics engine, and the reference the adapters
/// are tested against.
void stepBody(Body& body, BodyState& state, const Water& water, const Fluid& fluid, double time,
              double dt);

/// How a Simulation picks its body's level (Bundle::levels) each frame, by the editor's World's
/// rules (docs/design.md, "Level of detail"): a body switches at most once every holdFrames
/// frames and not while asleep, and at a switch both levels are evaluated at the same state and
/// their difference is faded out over blendFrames frames, so that the acceleration never jumps
/// by more than the two levels' difference over the blend's sub-steps.
struct LevelPolicy {
    enum class Kind {
        finest,      ///< the finest level (textureSize()): the default, as without a ladder
        distance,    ///< by the centre of mass's distance from pointOfInterest
        importance,  ///< by importance: 1 the finest, each halving one level coarser
        fixed,       ///< the level `level` (a caller's own rule: a budget over many bodies)
    };
    Kind kind = Kind::finest;
    Vec3 pointOfInterest;  ///< world, m (a camera)
    /// m: the finest level within it of the point of interest, one level coarser each time the
    /// distance doubles.
    double nearDistance = 50.0;
    /// Hysteresis: the level changes only when the distance is beyond a boundary by this
    /// fraction of it (0.15: 15%).
    double margin = 0.15;
    double importance = 1.0;  ///< in 0..1 (importance policy)
    std::size_t level = 0;    ///< index in levels(), clamped to the finest (fixed policy)
    int holdFrames = 30;      ///< at least this many frames between two switches
    int blendFrames = 8;      ///< frames a switch's force is blended over, >= 1
    /// Temporal level of detail, as the World: the world's sub-steps at the finest level, half
    /// as many at each coarser one, never fewer than a stable step needs. False: every
    /// sub-step at every level.
    bool fewerStepsWhenCoarser = true;
};

/// One body stepped as the editor's World steps it (engine/src/scene/world.cpp), for a game
/// without a physics engine, a server, and the conformance test against `plimsoll simulate`:
/// frames of world().timeStep split into the World's sub-steps (at least world().subSteps, more
/// where the hydrostatic stiffness or the spin needs them; at a coarser level of detail the body
/// steps on every second, fourth... of them, LevelPolicy::fewerStepsWhenCoarser), semi-implicit
/// Euler on the momenta
/// with the energy-conserving rotation, Archimedes' force on flat water and the pressure
/// integral on waves (their horizontal push), drag and damping on the momenta of the body with
/// its water, the water graph stepped once a frame and its water composed into the mass by the
/// parallel-axis theorem. A radiating body (the bundle's radiation()) steps as the World's: the
/// share of the added mass at infinite frequency in the mass matrix, taken each sub-step from
/// the submerged volume, the memory's load added to the wrench and its filters advanced with the
/// velocity after the step. The state is the World's: the centre of mass of the body with its
/// water, the orientation, the linear and angular momenta (with the added mass).
class Simulation {
public:
    /// Starts at the bundle's world() start, a radiating body with the added mass of its
    /// submerged volume there on the bundle's own water (as the World starts it). Null with
    /// `error` for what it does not step: an integrator other than semi-implicit Euler.
    /// The bundle must outlive it; it steps its own water, so any number of Simulations may
    /// share one bundle.
    static std::unique_ptr<Simulation> create(const Bundle& bundle, std::string& error);

    /// One frame of world().timeStep on `water` (the bundle's world().water.water() where the
    /// game has no water of its own); false with `error` when the state leaves the finite numbers.
    bool advanceFrame(const Water& water, std::string& error);

    double time() const { return time_; }
    /// One frame: the project's time step (world().timeStep).
    double frameTime() const { return bundle_.world().timeStep; }
    /// World position of the centre of mass of the body with its water, m.
    const Vec3& centerOfMass() const { return position_; }
    const Quat& orientation() const { return orientation_; }
    Vec3 linearVelocity() const;
    Vec3 angularVelocity() const;
    /// The last sub-step's evaluation, torques about the centre of mass (zero above the water).
    const Forces& forces() const { return forces_; }
    /// The body with its water, object space.
    const MassProperties& mass() const { return mass_; }
    /// Sub-steps the last frame took.
    int subSteps() const { return subSteps_; }
    /// At rest on calm water, the body sleeps as the World's do (world().sleep): a frame then
    /// costs one look at the water above it, until the water wakes it or wake() does.
    bool asleep() const { return asleep_; }
    /// Wakes the body (the game pushed it, or something hit it).
    void wake();
    /// The body's own water (null: the bundle has no water graph).
    const WaterGraph* graph() const { return body_.graph(); }

    /// How the body picks its level of detail from the next frame on (LevelPolicy). False with
    /// `error` for a non-finite point, a nearDistance that is not > 0, a margin below 0, an
    /// importance outside 0..1, holdFrames below 0 or blendFrames below 1. A bundle with one
    /// level evaluates it whatever the policy.
    bool setLevelPolicy(const LevelPolicy& policy, std::string& error);
    const LevelPolicy& levelPolicy() const { return levelPolicy_; }
    /// The index in bundle().levels() of the level evaluated now.
    std::size_t level() const { return static_cast<std::size_t>(lod_.level); }
    /// Times the level changed.
    std::size_t levelSwitches() const { return lod_.switches; }

    /// Everything the next frames depend on (the body's state, its mass with the water, the
    /// water graph's state), as bytes: restore() on a simulation of the same bundle continues
    /// bit for bit as if it had never stopped. For multiplayer snapshots and rollback.
    std::vector<std::uint8_t> save() const;
    /// False with `error` (nothing changed) for bytes of another body or a damaged snapshot.
    bool restore(const std::vector<std::uint8_t>& bytes, std::string& error);
    /// FNV-1a (64 bits) of save(): equal hashes, equal states (compare them across machines,
    /// builds and thread counts each step).
    std::uint64_t stateHash() const;

private:
    explicit Simulation(const Bundle& bundle);
    void evaluate(const Water& water, double dt);
    void step(double dt);
    /// True when water moved in or out of the body or inside it.
    bool stepGraph(const Water& water, double frameTime);
    void composeWater(const Quat& at);
    void setMass(const MassProperties& mass);
    /// Steps a frame a stable step needs (stiffness and spin); -1 beyond kMaxSubSteps. The
    /// frame's sub-steps are at least the world's and these.
    int stableSteps(double frameTime) const;
    double stiffestFrequency() const;
    /// The policy's level for this frame; at a switch evaluates both levels and starts the blend.
    void chooseLevel(const Water& water);
    /// The forces of level `level` at the current state (torques about the centre of mass).
    Forces forcesAt(std::size_t level, const Water& water) const;
    /// The share of the added mass for `submergedVolume`, its memory's load (World's
    /// startRadiationStep); nothing without radiation.
    void startRadiation(double submergedVolume);
    /// The added mass of `share` of A_inf; when it shrinks, the velocities are kept (cummins.h
    /// applyAddedMass).
    void applyAddedMass(double share);
    /// The memory's filters advanced by dt with the velocity after the step.
    void finishRadiation(double dt);
    /// The rotation's inertia: the body's with its water, plus the added inertia.
    void rotationalInertia(double I[3][3]) const;

    const Bundle& bundle_;
    Body body_;
    Fluid fluid_;
    Vec3 position_, linearMomentum_, angularMomentum_;
    Quat orientation_;
    MassProperties mass_, hull_;
    double boundingRadius_ = 0, hullRadius_ = 0;
    Quat composedAt_;
    Forces forces_;
    double time_ = 0;
    int subSteps_ = 0;
    bool asleep_ = false;
    double restedFor_ = 0;    ///< s below the sleep thresholds so far
    double sleepHeight_ = 0;  ///< the water's height above the body when it fell asleep
    /// The share of A_inf's translational and rotational blocks in the mass, body axes (zero
    /// without radiation).
    double addedMass_[3][3] = {}, addedInertia_[3][3] = {};
    bool added_ = false;               ///< whether either is non-zero
    Vec3 memoryForce_, memoryTorque_;  ///< the memory's load this sub-step, world axes
    struct Wrench {
        Vec3 force, torque;
    } wrench_;
    LevelPolicy levelPolicy_;
    /// plimsoll_eval::LevelSwitch's state (simulation.cpp) and the blend's difference.
    struct LevelState {
        int level = 0, framesHeld = 0, blendSteps = 0, blendLeft = 0;
        std::size_t switches = 0;
        Forces offset;  ///< the old level's forces minus the new one's at the switch
    } lod_;
};

/// SHA-256 of `size` bytes as 64 lowercase hex digits (FIPS 180-4).
std::string sha256Hex(const void* data, std::size_t size);

/// Rotation matrix of a unit quaternion (the same formula as Eigen's toRotationMatrix).
void rotationMatrix(const Quat& q, double R[3][3]);

}  // namespace plimsoll_runtime
