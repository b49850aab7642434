/* Plimsoll runtime, C API: load a bundle exported by `plimsoll export`, evaluate buoyancy,
 * pressure and drag for a pose, float any number of bodies of it (docs/bundle.md "Runtime
 * library"). Opaque handles; no C++ exception crosses this boundary: a function that can fail
 * returns 0 (or NULL) and plimsoll_runtime_last_error() says why (per thread).
 *
 * Asset and instance (since 2.0): a plimsoll_bundle is the loaded shape, immutable and
 * thread-safe, shared by any number of plimsoll_instance bodies, each of which holds only what
 * changes as it floats (the water in its compartments, the random sequence that spreads it,
 * its radiation memory) and can be saved and restored as bytes. The 1.x calls that stepped the
 * water of the bundle itself are kept, deprecated, as wrappers over one instance the bundle
 * holds (docs/c-abi.md, "2.0").
 *
 * The ABI rules (what a minor version may change, struct_size fields, threads) are in
 * docs/c-abi.md.
 *
 * Conventions: SI units, +y up, right-handed. A pose is the world position of the object's
 * origin and a unit quaternion (w, x, y, z), object -> world. Velocities are of the centre of
 * mass, world axes. Forces in world axes, torques about the centre of mass. */
#ifndef PLIMSOLL_RUNTIME_H
#define PLIMSOLL_RUNTIME_H

#include <stddef.h>
#include <stdint.h>

/* The version of this header (semantic versioning, docs/c-abi.md): compare it with
 * plimsoll_runtime_version() to find a library older than the header. CMake's project version
 * is read from these lines: they are the one source. */
#define PLIMSOLL_RUNTIME_VERSION_MAJOR 2
#define PLIMSOLL_RUNTIME_VERSION_MINOR 2
#define PLIMSOLL_RUNTIME_VERSION_PATCH 0

/* Every function is PLIMSOLL_RUNTIME_API: exported from the shared library (built with
 * -DPLIMSOLL_RUNTIME_SHARED=ON, whose CMake package and pkg-config file define
 * PLIMSOLL_RUNTIME_SHARED for its users), plain declarations for the static one. The shared
 * library exports this C ABI and nothing else. */
#if defined(_WIN32) || defined(__CYGWIN__)
#if defined(PLIMSOLL_RUNTIME_BUILDING_SHARED)
#define PLIMSOLL_RUNTIME_API __declspec(dllexport)
#elif defined(PLIMSOLL_RUNTIME_SHARED)
#define PLIMSOLL_RUNTIME_API __declspec(dllimport)
#else
#define PLIMSOLL_RUNTIME_API
#endif
#elif defined(__GNUC__) || defined(__clang__)
#define PLIMSOLL_RUNTIME_API __attribute__((visibility("default")))
#else
#define PLIMSOLL_RUNTIME_API
#endif

/* The 1.x calls 2.0 replaces warn where they are used; define
 * PLIMSOLL_RUNTIME_NO_DEPRECATION_WARNINGS before including this header to silence them. */
#if defined(PLIMSOLL_RUNTIME_NO_DEPRECATION_WARNINGS)
#define PLIMSOLL_RUNTIME_DEPRECATED(replacement)
#elif defined(__GNUC__) || defined(__clang__)
#define PLIMSOLL_RUNTIME_DEPRECATED(replacement) __attribute__((deprecated("use " replacement)))
#elif defined(_MSC_VER)
#define PLIMSOLL_RUNTIME_DEPRECATED(replacement) __declspec(deprecated("use " replacement))
#else
#define PLIMSOLL_RUNTIME_DEPRECATED(replacement)
#endif

#ifdef __cplusplus
extern "C" {
#endif

typedef struct plimsoll_bundle plimsoll_bundle;
typedef struct plimsoll_instance plimsoll_instance;

typedef struct plimsoll_pose {
    double position[3];    /* world position of the object's origin, m */
    double orientation[4]; /* unit quaternion w, x, y, z */
} plimsoll_pose;

typedef struct plimsoll_velocity {
    double linear[3];  /* of the centre of mass, m/s */
    double angular[3]; /* rad/s */
} plimsoll_velocity;

/* Water height y at world (x, z) and time t (s). */
typedef double (*plimsoll_height_fn)(void* user, double x, double z, double time);
/* Water velocity at a world point (optional; for drag). */
typedef void (*plimsoll_water_velocity_fn)(void* user, const double point[3], double time,
                                           double velocity[3]);

/* Many water heights in one call: out[i] = height at (x[i], z[i]) for i < n. */
typedef void (*plimsoll_heights_fn)(void* user, size_t n, const double* x, const double* z,
                                    double time, double* out);
/* Many water velocities in one call: out[3 i + 0..2] = the velocity at (x[i], y[i], z[i]). */
typedef void (*plimsoll_water_velocities_fn)(void* user, size_t n, const double* x, const double* y,
                                             const double* z, double time, double* out);

typedef struct plimsoll_water {
    double level;                        /* flat water height when height is NULL, m */
    plimsoll_height_fn height;           /* may be NULL */
    plimsoll_water_velocity_fn velocity; /* may be NULL: still water */
    void* user;                          /* passed to the callbacks */
    /* Since 1.2 (a zero-initialised tail keeps the 1.1 meaning). An evaluation asks for a small
     * grid of heights per body: `heights` answers them in one call and is used instead of
     * `height` when set. With has_bounds != 0 the surface stays within min_height..max_height
     * and a body wholly above max_height costs nothing. */
    plimsoll_heights_fn heights;
    int has_bounds;
    double min_height, max_height; /* m */
    /* Since 2.0 (zero: as before). Every point one evaluation needs the water's velocity at
     * (one per wet tile, for drag) in one call after its traversal; used instead of `velocity`
     * when set. */
    plimsoll_water_velocities_fn velocities;
} plimsoll_water;

typedef struct plimsoll_fluid {
    double density;              /* kg/m^3 */
    double gravity;              /* m/s^2, along -y */
    double drag_coefficient;     /* C_d */
    double friction_coefficient; /* C_f, 0 = off */
} plimsoll_fluid;

typedef struct plimsoll_forces {
    double submerged_volume;      /* m^3 */
    double center_of_buoyancy[3]; /* world, m */
    double force[3];              /* Archimedes, N */
    double torque[3];             /* about the centre of mass, N m */
    double pressure_force[3];
    double pressure_torque[3];
    double drag_force[3];
    double drag_torque[3];
    double wetted_area; /* m^2 */
    size_t submerged_samples;
} plimsoll_forces;

typedef struct plimsoll_mass {
    double mass;              /* kg */
    double volume;            /* m^3 */
    double center_of_mass[3]; /* object space, m */
    double inertia[3][3];     /* about the centre of mass, object axes, kg m^2 */
} plimsoll_mass;

/* The message of the last failure on this thread: every other call clears it when it succeeds
 * and sets it when it fails ("" after a success), except the _destroy and _free calls, which
 * leave it (a program frees what a failed call returned, then reads why). */
PLIMSOLL_RUNTIME_API const char* plimsoll_runtime_last_error(void);
/* "major.minor" of the bundle schema this runtime reads. */
PLIMSOLL_RUNTIME_API const char* plimsoll_runtime_schema_version(void);

/* Versions. The library's: semantic versioning (docs/c-abi.md). The bundle schema's: a
 * bundle of another major is refused; minor is the newest this library knows (older minors
 * and newer ones, which only add, are read). Any pointer may be NULL. */
PLIMSOLL_RUNTIME_API void plimsoll_runtime_version(int* major, int* minor, int* patch);
PLIMSOLL_RUNTIME_API void plimsoll_runtime_bundle_schema(int* major, int* minor);

/* Quaternion order. Every quaternion of this API (poses, plimsoll_simulation_state,
 * plimsoll_instance_water_mass's orientation) is w, x, y, z: PLIMSOLL_RUNTIME_QUATERNION_WXYZ
 * says so to code that checks it at compile time. glTF, Jolt, Bullet, Unity and Godot store
 * x, y, z, w: convert at the boundary with these two (in place is allowed). */
#define PLIMSOLL_RUNTIME_QUATERNION_WXYZ 1
PLIMSOLL_RUNTIME_API void plimsoll_quaternion_from_xyzw(const double xyzw[4], double wxyz[4]);
PLIMSOLL_RUNTIME_API void plimsoll_quaternion_to_xyzw(const double wxyz[4], double xyzw[4]);

/* Loads a bundle folder, checking every file's size and SHA-256 when verify_checksums != 0.
 * NULL on failure. */
PLIMSOLL_RUNTIME_API plimsoll_bundle* plimsoll_bundle_load(const char* folder,
                                                           int verify_checksums);
/* Frees a bundle (NULL: nothing); its instances and simulations must be destroyed first. */
PLIMSOLL_RUNTIME_API void plimsoll_bundle_destroy(plimsoll_bundle* bundle);
PLIMSOLL_RUNTIME_DEPRECATED("plimsoll_bundle_destroy")
PLIMSOLL_RUNTIME_API void plimsoll_bundle_free(plimsoll_bundle* bundle);

/* One file of a bundle in memory: its path inside the bundle ("samples.exr") and bytes,
 * which need outlive only the load call. */
typedef struct plimsoll_memory_file {
    const char* path;
    const void* data;
    size_t size;
} plimsoll_memory_file;

/* Loads a bundle from `count` files in memory with the checks of plimsoll_bundle_load (paths
 * inside the bundle, size limits, checksums, non-finite data refused). `name` (may be NULL:
 * "memory") prefixes error messages as the folder does. */
PLIMSOLL_RUNTIME_API plimsoll_bundle* plimsoll_bundle_load_memory(const plimsoll_memory_file* files,
                                                                  size_t count, const char* name,
                                                                  int verify_checksums);

/* A bundle's files read through the caller (a pak file, the engine's file system). The
 * loader asks only for paths inside the bundle ('/'-separated, no "..", not absolute), checks
 * the size before it allocates and closes every file it opened. Set struct_size to
 * sizeof(plimsoll_file_callbacks). */
typedef struct plimsoll_file_callbacks {
    size_t struct_size;
    /* A handle for `path`, or NULL when there is no such file. */
    void* (*open)(void* user, const char* path);
    /* Size of an open file in bytes; negative when unknown. */
    int64_t (*size)(void* user, void* file);
    /* Reads up to `bytes` bytes at `offset`: how many were read, 0 at the end, < 0 on error. */
    int64_t (*read)(void* user, void* file, uint64_t offset, void* buffer, size_t bytes);
    void (*close)(void* user, void* file);
    void* user;
} plimsoll_file_callbacks;

PLIMSOLL_RUNTIME_API plimsoll_bundle* plimsoll_bundle_load_callbacks(
    const plimsoll_file_callbacks* callbacks, const char* name, int verify_checksums);

/* What one body costs. Set struct_size to sizeof(plimsoll_bundle_size) before the call. */
typedef struct plimsoll_bundle_size {
    size_t struct_size;
    uint64_t file_bytes;   /* what ships: the manifest and every file it lists */
    uint64_t memory_bytes; /* what the loaded asset holds: sample list, water graph layout and,
                              once the first evaluation built them, the evaluation tiles */
    size_t samples;        /* entries of the sample list */
    size_t graph_nodes;    /* water graph nodes (0: none) */
} plimsoll_bundle_size;

PLIMSOLL_RUNTIME_API int plimsoll_bundle_size_query(const plimsoll_bundle* bundle,
                                                    plimsoll_bundle_size* out);

PLIMSOLL_RUNTIME_API const char* plimsoll_bundle_body(const plimsoll_bundle* bundle);
PLIMSOLL_RUNTIME_API size_t plimsoll_bundle_sample_count(const plimsoll_bundle* bundle);
/* mass_properties.texture of the manifest. */
PLIMSOLL_RUNTIME_API plimsoll_mass plimsoll_bundle_mass(const plimsoll_bundle* bundle);
/* The project's medium density and gravity (bundle schema 1.4; 1000 and 9.81 before) and the
 * manifest's drag and friction coefficients. */
PLIMSOLL_RUNTIME_API plimsoll_fluid plimsoll_bundle_default_fluid(const plimsoll_bundle* bundle);
/* The manifest's linear and angular damping (1/s at full submersion). */
PLIMSOLL_RUNTIME_API void plimsoll_bundle_damping(const plimsoll_bundle* bundle, double* linear,
                                                  double* angular);

/* Buoyancy, pressure and drag. Returns 0 on bad arguments. */
PLIMSOLL_RUNTIME_API int plimsoll_bundle_evaluate(
    const plimsoll_bundle* bundle, const plimsoll_pose* pose, const plimsoll_velocity* velocity,
    const plimsoll_water* water, const plimsoll_fluid* fluid, double time, plimsoll_forces* out);

/* The water graph's layout (0 for a body without one): its nodes and their capacities (m^3). */
PLIMSOLL_RUNTIME_API size_t plimsoll_graph_node_count(const plimsoll_bundle* bundle);
PLIMSOLL_RUNTIME_API double plimsoll_graph_node_capacity(const plimsoll_bundle* bundle,
                                                         size_t node);

/* 1.x: the water of the one instance the bundle holds (plimsoll_instance_node_water and the
 * other plimsoll_instance_ calls below replace them). */
PLIMSOLL_RUNTIME_DEPRECATED("plimsoll_instance_node_water")
PLIMSOLL_RUNTIME_API double plimsoll_graph_node_water(const plimsoll_bundle* bundle, size_t node);
PLIMSOLL_RUNTIME_DEPRECATED("plimsoll_instance_set_node_water")
PLIMSOLL_RUNTIME_API int plimsoll_graph_set_node_water(plimsoll_bundle* bundle, size_t node,
                                                       double water);
PLIMSOLL_RUNTIME_DEPRECATED("plimsoll_instance_set_medium")
PLIMSOLL_RUNTIME_API int plimsoll_graph_set_medium(plimsoll_bundle* bundle, double density,
                                                   double viscosity, double gravity);
PLIMSOLL_RUNTIME_DEPRECATED("plimsoll_instance_graph_inflow")
PLIMSOLL_RUNTIME_API int plimsoll_graph_inflow(const plimsoll_bundle* bundle,
                                               const plimsoll_pose* pose,
                                               const plimsoll_water* water, double time,
                                               double* inflow, double* outflow);
PLIMSOLL_RUNTIME_DEPRECATED("plimsoll_instance_graph_step")
PLIMSOLL_RUNTIME_API int plimsoll_graph_step(plimsoll_bundle* bundle, const plimsoll_pose* pose,
                                             const plimsoll_water* water, double time, double dt);
PLIMSOLL_RUNTIME_DEPRECATED("plimsoll_instance_water_mass")
PLIMSOLL_RUNTIME_API plimsoll_mass plimsoll_graph_water_mass(const plimsoll_bundle* bundle,
                                                             const double orientation[4]);

/* The object-space box around the sample list (a default collider, a broad-phase bound). */
PLIMSOLL_RUNTIME_API int plimsoll_bundle_bounds(const plimsoll_bundle* bundle, double min[3],
                                                double max[3]);

/* ---------------------------------------------------------------------------------------
 * Motion. What a physics engine applies to the body each step, on top of its own gravity:
 * buoyancy and its torque (since 1.5 as the editor's World: Archimedes' force on flat water,
 * the pressure integral with the waves' horizontal push when the water has a height callback),
 * drag, the manifest's damping of the momenta of the body with its water (scaled by the
 * submerged fraction and at most what stops the body within dt) and the weight of the water
 * inside, at the water's centre of mass. Forces at the centre of mass, world axes; torques
 * about it. */
typedef struct plimsoll_load {
    double force[3];        /* N */
    double torque[3];       /* N m */
    double water_mass;      /* kg of water inside (its weight is in force) */
    plimsoll_forces forces; /* the evaluation the load was made of */
} plimsoll_load;

PLIMSOLL_RUNTIME_DEPRECATED("plimsoll_instance_water_load")
PLIMSOLL_RUNTIME_API int plimsoll_bundle_water_load(const plimsoll_bundle* bundle,
                                                    const plimsoll_pose* pose,
                                                    const plimsoll_velocity* velocity,
                                                    const plimsoll_water* water,
                                                    const plimsoll_fluid* fluid, double time,
                                                    double dt, plimsoll_load* out);

/* A body on its own (no contacts). */
typedef struct plimsoll_body_state {
    plimsoll_pose pose;         /* the object origin's world pose */
    plimsoll_velocity velocity; /* of the centre of mass */
} plimsoll_body_state;

/* One semi-implicit Euler step of dt: the water graph steps, then gravity (fluid->gravity
 * along -y) and the water load change the momenta, then position and orientation move with
 * the new velocities (angular momentum is what is integrated). For engines without physics,
 * and the reference the adapters are tested against. */
PLIMSOLL_RUNTIME_DEPRECATED("plimsoll_instance_step")
PLIMSOLL_RUNTIME_API int plimsoll_body_step(plimsoll_bundle* bundle, plimsoll_body_state* state,
                                            const plimsoll_water* water,
                                            const plimsoll_fluid* fluid, double time, double dt);

/* ---------------------------------------------------------------------------------------
 * The editor's simulation, replayed (since 1.5; bundle schema 1.4 carries the project's world:
 * the medium, the water model, the step settings and the body's start). A plimsoll_simulation
 * steps one body exactly as `plimsoll simulate` does: frames of the project's time step in the
 * World's sub-steps, Archimedes' force on flat water and the pressure integral on waves, the
 * water inside in the mass, inertia and damping, the water graph once a frame. For a game
 * without a physics engine, a server, and to check a bundle against the editor. Each simulation
 * steps its own water (since 2.0): any number of them may share a bundle; one thread at a time
 * per simulation. */
typedef struct plimsoll_simulation plimsoll_simulation;

/* NULL (and the last error) for a body it does not step: an integrator other than
 * semi-implicit Euler. A radiating body steps with its added mass and memory, as the World
 * steps it. The bundle must outlive it. */
PLIMSOLL_RUNTIME_API plimsoll_simulation* plimsoll_simulation_create(const plimsoll_bundle* bundle);
PLIMSOLL_RUNTIME_API void plimsoll_simulation_destroy(plimsoll_simulation* simulation);
/* One frame (plimsoll_simulation_state's frame_time). water NULL: the bundle's own water. */
PLIMSOLL_RUNTIME_API int plimsoll_simulation_advance_frame(plimsoll_simulation* simulation,
                                                           const plimsoll_water* water);

/* The columns of `plimsoll simulate --out`. */
typedef struct plimsoll_simulation_state {
    double time;                    /* s */
    double frame_time;              /* s, the project's time_step */
    double center_of_mass[3];       /* world, of the body with its water, m */
    double orientation[4];          /* w, x, y, z */
    double velocity[3];             /* of that centre of mass, m/s */
    double angular_velocity[3];     /* rad/s */
    double submerged_volume;        /* m^3, last sub-step */
    double buoyant_force[3];        /* the pressure integral, N, last sub-step */
    double mass;                    /* kg, with the water inside */
    double local_center_of_mass[3]; /* object space, m */
} plimsoll_simulation_state;
PLIMSOLL_RUNTIME_API int plimsoll_simulation_state_query(const plimsoll_simulation* simulation,
                                                         plimsoll_simulation_state* out);

/* A snapshot of everything the next frames depend on (the body's state, its mass with the
 * water, the water graph's water and random sequence): plimsoll_simulation_restore on a
 * simulation of the same bundle continues bit for bit. With buffer NULL (or capacity too small)
 * only *size is set (and 0 returned when the buffer was too small). */
PLIMSOLL_RUNTIME_API int plimsoll_simulation_save(const plimsoll_simulation* simulation,
                                                  void* buffer, size_t capacity, size_t* size);
PLIMSOLL_RUNTIME_API int plimsoll_simulation_restore(plimsoll_simulation* simulation,
                                                     const void* bytes, size_t size);
/* FNV-1a of the snapshot: equal hashes, equal states (0 and the last error on NULL). */
PLIMSOLL_RUNTIME_API uint64_t plimsoll_simulation_state_hash(const plimsoll_simulation* simulation);

/* ---------------------------------------------------------------------------------------
 * Level of detail (since 2.1; bundle schema 1.6, the manifest's "levels"): a body exported with
 * a level ladder carries a bake of its own at each of a few texture sizes, each with its stated
 * error. plimsoll_bundle_level_count is 1 for a bundle without one. */
typedef struct plimsoll_level_info {
    size_t struct_size;   /* set to sizeof(plimsoll_level_info) */
    int size;             /* texels per side */
    size_t samples;       /* entries of its sample list */
    double force_error;   /* largest |F - F_exact| / (rho g V) (0: not stated) */
    double torque_error;  /* largest |T - T_exact| / (rho g V R) */
    double evaluation_us; /* us per evaluation where the bundle was exported */
} plimsoll_level_info;
/* Levels coarsest first: index count - 1 is the finest (texture_size, samples.exr). */
PLIMSOLL_RUNTIME_API size_t plimsoll_bundle_level_count(const plimsoll_bundle* bundle);
PLIMSOLL_RUNTIME_API int plimsoll_bundle_level_query(const plimsoll_bundle* bundle, size_t level,
                                                     plimsoll_level_info* out);

enum {
    PLIMSOLL_LEVEL_FINEST = 0,     /* the finest level: the default */
    PLIMSOLL_LEVEL_DISTANCE = 1,   /* by the centre of mass's distance from point_of_interest */
    PLIMSOLL_LEVEL_IMPORTANCE = 2, /* by importance in 0..1: 1 the finest, each halving coarser */
    PLIMSOLL_LEVEL_FIXED = 3       /* the level `level` (a caller's own rule, e.g. a budget) */
};
/* How a simulation picks its level each frame, by the editor's World's rules: the finest level
 * within near_distance of the point, one level coarser each time the distance doubles; a level
 * changes only beyond a boundary by `margin` (a fraction), at most once every hold_frames
 * frames, and a switch's force and torque are blended over blend_frames frames, so it never
 * kicks. */
typedef struct plimsoll_level_policy {
    size_t struct_size;          /* set to sizeof(plimsoll_level_policy) */
    int kind;                    /* PLIMSOLL_LEVEL_* */
    double point_of_interest[3]; /* world, m */
    double near_distance;        /* m, > 0 (50) */
    double margin;               /* >= 0 (0.15) */
    double importance;           /* 0..1 */
    size_t level;                /* PLIMSOLL_LEVEL_FIXED: index, clamped to the finest */
    int hold_frames;             /* >= 0 (30) */
    int blend_frames;            /* >= 1 (8) */
    /* 1 (the default): the world's sub-steps at the finest level, half as many at each coarser
     * one, never fewer than a stable step needs; 0: every sub-step at every level. Read only
     * when struct_size covers it (older callers get 1). */
    int fewer_steps_when_coarser;
} plimsoll_level_policy;
/* The defaults above, kind PLIMSOLL_LEVEL_FINEST, struct_size set. */
PLIMSOLL_RUNTIME_API plimsoll_level_policy plimsoll_level_policy_default(void);
/* From the next frame on; 0 (nothing changed) and the last error for a value out of range. */
PLIMSOLL_RUNTIME_API int plimsoll_simulation_set_level_policy(plimsoll_simulation* simulation,
                                                              const plimsoll_level_policy* policy);
/* The index of the level evaluated now (0 and the last error on NULL). */
PLIMSOLL_RUNTIME_API size_t plimsoll_simulation_level(const plimsoll_simulation* simulation);

/* ---------------------------------------------------------------------------------------
 * Wave radiation (bundle schema 1.3; docs/bundle.md "Radiation"): Cummins' equation, the
 * infinite-frequency added mass in the mass matrix and the memory of the radiated waves as
 * filters per mode. Body axes about the centre of mass; modes surge x, heave y, sway z, roll x,
 * yaw y, pitch z. */
typedef struct plimsoll_radiation_info {
    double rest_volume;               /* m^3 displaced at rest */
    double added_mass_infinity[6][6]; /* kg, kg m, kg m^2 */
    int memory_terms[6];              /* filters per mode */
} plimsoll_radiation_info;

/* 1 and `out` filled when the body was exported with radiation; 0 otherwise (the last error
 * says why). */
PLIMSOLL_RUNTIME_API int plimsoll_bundle_radiation(const plimsoll_bundle* bundle,
                                                   plimsoll_radiation_info* out);

/* A radiating body's memory between steps: one per body, used with the bundle it was made for
 * (which must outlive it). NULL when the body has no radiation. */
typedef struct plimsoll_radiation_memory plimsoll_radiation_memory;
PLIMSOLL_RUNTIME_DEPRECATED("plimsoll_instance_create (an instance holds its radiation memory)")
PLIMSOLL_RUNTIME_API plimsoll_radiation_memory* plimsoll_radiation_memory_create(
    const plimsoll_bundle* bundle);
PLIMSOLL_RUNTIME_API void plimsoll_radiation_memory_destroy(plimsoll_radiation_memory* memory);

/* For an engine with its own integrator: before its step, begin() gives the share of the added
 * mass (add added_mass to the body's mass matrix and added_inertia to its inertia, body axes;
 * never apply them as forces) and the memory's force and torque (world axes, about the centre
 * of mass) to apply; when share > previous_share keep the body's momentum across the change,
 * otherwise its velocity. After the step, advance() with the new pose and velocity. */
typedef struct plimsoll_radiation_load {
    double share;               /* 0..1: 1 while half the resting displacement is under water */
    double previous_share;      /* the previous begin()'s share; -1 on the first call */
    double added_mass[3][3];    /* kg, body axes */
    double added_inertia[3][3]; /* kg m^2, body axes */
    double force[3];            /* N, world axes */
    double torque[3];           /* N m, world axes */
} plimsoll_radiation_load;
PLIMSOLL_RUNTIME_DEPRECATED("plimsoll_instance_radiation_begin")
PLIMSOLL_RUNTIME_API int plimsoll_radiation_memory_begin(plimsoll_radiation_memory* memory,
                                                         const plimsoll_pose* pose,
                                                         double submerged_volume,
                                                         plimsoll_radiation_load* out);
PLIMSOLL_RUNTIME_DEPRECATED("plimsoll_instance_radiation_advance")
PLIMSOLL_RUNTIME_API int plimsoll_radiation_memory_advance(plimsoll_radiation_memory* memory,
                                                           const plimsoll_pose* pose,
                                                           const plimsoll_velocity* velocity,
                                                           double dt);
/* Energy the filters hold, J: the body's mechanical energy plus this never grows. */
PLIMSOLL_RUNTIME_DEPRECATED("plimsoll_instance_radiation_energy")
PLIMSOLL_RUNTIME_API double plimsoll_radiation_memory_energy(
    const plimsoll_radiation_memory* memory);

/* plimsoll_body_step with radiation: the added mass in the mass matrix and the memory's load
 * added. */
PLIMSOLL_RUNTIME_DEPRECATED("plimsoll_instance_step")
PLIMSOLL_RUNTIME_API int plimsoll_body_step_radiating(
    plimsoll_bundle* bundle, plimsoll_body_state* state, plimsoll_radiation_memory* memory,
    const plimsoll_water* water, const plimsoll_fluid* fluid, double time, double dt);

/* ---------------------------------------------------------------------------------------
 * Instances (since 2.0): one floating body of a shared bundle. An instance holds the water in
 * its compartments (starting as exported), the random sequence that spreads it and, for a
 * bundle exported with radiation, its radiation memory: a few hundred bytes for a typical
 * graph, where the bundle holds the megabytes. The bundle must outlive its instances. One
 * thread at a time per instance; any number of instances of one bundle on any threads. */
PLIMSOLL_RUNTIME_API plimsoll_instance* plimsoll_instance_create(const plimsoll_bundle* bundle);
PLIMSOLL_RUNTIME_API void plimsoll_instance_destroy(plimsoll_instance* instance);
PLIMSOLL_RUNTIME_API const plimsoll_bundle* plimsoll_instance_bundle(
    const plimsoll_instance* instance);
/* Bytes the instance holds (not its bundle). */
PLIMSOLL_RUNTIME_API uint64_t plimsoll_instance_memory_bytes(const plimsoll_instance* instance);

/* The instance's water: per node (m^3; the node count and capacities are the bundle's,
 * plimsoll_graph_node_count), set one node (0..capacity, booked as initial water), the
 * medium inside (density kg/m^3, viscosity Pa s, gravity m/s^2; the bundle's world by
 * default). All fail (0 and the error) for a bundle without a water graph or a bad node. */
PLIMSOLL_RUNTIME_API int plimsoll_instance_node_water(const plimsoll_instance* instance,
                                                      size_t node, double* water);
PLIMSOLL_RUNTIME_API int plimsoll_instance_set_node_water(plimsoll_instance* instance, size_t node,
                                                          double water);
PLIMSOLL_RUNTIME_API int plimsoll_instance_set_medium(plimsoll_instance* instance, double density,
                                                      double viscosity, double gravity);
/* Inflow and outflow (m^3/s) of each node through the permeable surface at this pose;
 * `inflow` and `outflow` hold node_count values each (either may be NULL). The water's
 * heights are asked once for all permeable points (the `heights` callback when set). */
PLIMSOLL_RUNTIME_API int plimsoll_instance_graph_inflow(const plimsoll_instance* instance,
                                                        const plimsoll_pose* pose,
                                                        const plimsoll_water* water, double time,
                                                        double* inflow, double* outflow);
/* One step of dt seconds: exchange with the water outside, then flow between nodes. Returns
 * 1 when water moved, 0 when not (or the bundle has no water graph), -1 on error. */
PLIMSOLL_RUNTIME_API int plimsoll_instance_graph_step(plimsoll_instance* instance,
                                                      const plimsoll_pose* pose,
                                                      const plimsoll_water* water, double time,
                                                      double dt);
/* The water's mass properties at this orientation (w, x, y, z), object space. */
PLIMSOLL_RUNTIME_API int plimsoll_instance_water_mass(const plimsoll_instance* instance,
                                                      const double orientation[4],
                                                      plimsoll_mass* out);
/* What a physics engine applies to the body (as plimsoll_bundle_water_load describes), with
 * this instance's water inside. */
PLIMSOLL_RUNTIME_API int plimsoll_instance_water_load(const plimsoll_instance* instance,
                                                      const plimsoll_pose* pose,
                                                      const plimsoll_velocity* velocity,
                                                      const plimsoll_water* water,
                                                      const plimsoll_fluid* fluid, double time,
                                                      double dt, plimsoll_load* out);
/* One semi-implicit Euler step of a body on its own (plimsoll_body_step's step), with its
 * radiation when the bundle has it (the added mass in the mass matrix, the memory's load). */
PLIMSOLL_RUNTIME_API int plimsoll_instance_step(plimsoll_instance* instance,
                                                plimsoll_body_state* state,
                                                const plimsoll_water* water,
                                                const plimsoll_fluid* fluid, double time,
                                                double dt);
/* For an engine with its own integrator and a bundle with radiation: before its step, begin()
 * (see plimsoll_radiation_load); after it, advance() with the new pose and velocity. Both fail
 * for a bundle without radiation. energy: J held by the memory (0 without radiation). */
PLIMSOLL_RUNTIME_API int plimsoll_instance_radiation_begin(plimsoll_instance* instance,
                                                           const plimsoll_pose* pose,
                                                           double submerged_volume,
                                                           plimsoll_radiation_load* out);
PLIMSOLL_RUNTIME_API int plimsoll_instance_radiation_advance(plimsoll_instance* instance,
                                                             const plimsoll_pose* pose,
                                                             const plimsoll_velocity* velocity,
                                                             double dt);
PLIMSOLL_RUNTIME_API double plimsoll_instance_radiation_energy(const plimsoll_instance* instance);

/* A snapshot of everything the instance's next steps depend on besides the pose and velocity
 * (which the game's physics holds): plimsoll_instance_restore on an instance of the same
 * bundle continues bit for bit. With buffer NULL (or capacity too small) only *size is set
 * (and 0 returned when the buffer was too small). The hash is FNV-1a of the snapshot. */
PLIMSOLL_RUNTIME_API int plimsoll_instance_save(const plimsoll_instance* instance, void* buffer,
                                                size_t capacity, size_t* size);
PLIMSOLL_RUNTIME_API int plimsoll_instance_restore(plimsoll_instance* instance, const void* bytes,
                                                   size_t size);
PLIMSOLL_RUNTIME_API uint64_t plimsoll_instance_state_hash(const plimsoll_instance* instance);

/* Sleeping (docs/design.md "Sleeping bodies"): stepped by plimsoll_instance_step or
 * plimsoll_batch_instance_step, an instance at rest on calm water sleeps as the editor's bodies
 * do (a bundle of schema 1.5 or later, its world.simulation.sleep): a step then costs one look
 * at the water above it and leaves the state as it is. It wakes when that water moves or rises,
 * when the game changes the pose or gives it a velocity, or on plimsoll_instance_wake. An
 * engine that integrates itself (plimsoll_instance_water_load) uses its own sleeping.
 * asleep: 1 asleep, 0 awake (and 0 with the last error for NULL). The state is part of the
 * snapshot. */
PLIMSOLL_RUNTIME_API int plimsoll_instance_asleep(const plimsoll_instance* instance);
PLIMSOLL_RUNTIME_API int plimsoll_instance_wake(plimsoll_instance* instance);

/* ---------------------------------------------------------------------------------------
 * Many bodies in one call. A plimsoll_batch owns a thread pool, or runs on the caller's task
 * system (as Box2D's enqueueTask / finishTask): enqueue starts `task` over `item_count` items
 * in ranges of at least `min_range` and returns a handle finish() waits on (or runs it at once
 * and returns NULL: finish is then not called). Water callbacks are then called from several
 * threads at once and must be thread-safe. A batch serialises the calls made on it; a call
 * made from inside its own work (a water callback calling the batch it runs in, directly or
 * through another batch) would wait for itself and is refused with an error instead. */
typedef void plimsoll_task_fn(int begin, int end, uint32_t worker, void* task_context);

typedef struct plimsoll_batch_desc {
    size_t struct_size; /* sizeof(plimsoll_batch_desc) */
    int thread_count;   /* own pool: 0 = the machine's hardware threads, 1 = the caller only */
    void* (*enqueue)(plimsoll_task_fn* task, int item_count, int min_range, void* task_context,
                     void* user_context); /* NULL: the own pool */
    void (*finish)(void* user_task, void* user_context);
    void* user_context;
    int worker_count; /* workers the caller's task system may run at once */
} plimsoll_batch_desc;

typedef struct plimsoll_batch plimsoll_batch;

/* desc may be NULL: an own pool of the hardware threads. NULL, with the error, when the system
 * refuses a thread of the pool ("cannot start thread 38 of 300: Resource temporarily
 * unavailable"); the threads already started are stopped. */
PLIMSOLL_RUNTIME_API plimsoll_batch* plimsoll_batch_create(const plimsoll_batch_desc* desc);
PLIMSOLL_RUNTIME_API void plimsoll_batch_destroy(plimsoll_batch* batch);
PLIMSOLL_RUNTIME_DEPRECATED("plimsoll_batch_destroy")
PLIMSOLL_RUNTIME_API void plimsoll_batch_free(plimsoll_batch* batch);

/* plimsoll_bundle_evaluate for bodies[i] at poses[i] into out[i], i < count. velocities may be
 * NULL (all at rest), fluid may be NULL (each body's default fluid); one water for all. Every
 * argument is checked before any work starts; returns 1, or 0 with the error naming the first
 * body that failed ("body 3: ..."). A bundle may appear more than once. */
PLIMSOLL_RUNTIME_API int plimsoll_batch_evaluate(
    plimsoll_batch* batch, size_t count, const plimsoll_bundle* const* bodies,
    const plimsoll_pose* poses, const plimsoll_velocity* velocities, const plimsoll_water* water,
    const plimsoll_fluid* fluid, double time, plimsoll_forces* out);

/* 1.x: plimsoll_bundle_water_load and plimsoll_graph_step for every bundle. */
PLIMSOLL_RUNTIME_DEPRECATED("plimsoll_batch_instance_water_load")
PLIMSOLL_RUNTIME_API int plimsoll_batch_water_load(
    plimsoll_batch* batch, size_t count, const plimsoll_bundle* const* bodies,
    const plimsoll_pose* poses, const plimsoll_velocity* velocities, const plimsoll_water* water,
    const plimsoll_fluid* fluid, double time, double dt, plimsoll_load* out);

PLIMSOLL_RUNTIME_DEPRECATED("plimsoll_batch_instance_graph_step")
PLIMSOLL_RUNTIME_API int plimsoll_batch_graph_step(plimsoll_batch* batch, size_t count,
                                                   plimsoll_bundle* const* bodies,
                                                   const plimsoll_pose* poses,
                                                   const plimsoll_water* water, double time,
                                                   double dt, int* moved);

/* plimsoll_instance_water_load for every instance: what a physics engine applies, for all its
 * floating bodies in one call. Arguments and errors as plimsoll_batch_evaluate (fluid NULL:
 * each bundle's default fluid). */
PLIMSOLL_RUNTIME_API int plimsoll_batch_instance_water_load(
    plimsoll_batch* batch, size_t count, const plimsoll_instance* const* instances,
    const plimsoll_pose* poses, const plimsoll_velocity* velocities, const plimsoll_water* water,
    const plimsoll_fluid* fluid, double time, double dt, plimsoll_load* out);

/* plimsoll_instance_graph_step for every instance (each at most once per call); moved[i] (may
 * be NULL) is 1 where water moved. Instances of bundles without a water graph are skipped. */
PLIMSOLL_RUNTIME_API int plimsoll_batch_instance_graph_step(plimsoll_batch* batch, size_t count,
                                                            plimsoll_instance* const* instances,
                                                            const plimsoll_pose* poses,
                                                            const plimsoll_water* water,
                                                            double time, double dt, int* moved);

/* plimsoll_instance_step for every instance and states[i] (each instance at most once per
 * call); fluid NULL: each bundle's default fluid. A failing body leaves its state as it was. */
PLIMSOLL_RUNTIME_API int plimsoll_batch_instance_step(plimsoll_batch* batch, size_t count,
                                                      plimsoll_instance* const* instances,
                                                      plimsoll_body_state* states,
                                                      const plimsoll_water* water,
                                                      const plimsoll_fluid* fluid, double time,
                                                      double dt);

#ifdef __cplusplus
}
#endif

#endif /* PLIMSOLL_RUNTIME_H */
