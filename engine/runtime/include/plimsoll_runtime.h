/* Plimsoll runtime, C API: load a bundle exported by `plimsoll export`, evaluate buoyancy,
 * pressure and drag for a pose, step the body's water graph (docs/bundle.md "Runtime
 * library"). Opaque handles; no C++ exception crosses this boundary: a function that can fail
 * returns 0 (or NULL) and plimsoll_runtime_last_error() says why (per thread).
 *
 * Conventions: SI units, +y up, right-handed. A pose is the world position of the object's
 * origin and a unit quaternion (w, x, y, z), object -> world. Velocities are of the centre of
 * mass, world axes. Forces in world axes, torques about the centre of mass. */
#ifndef PLIMSOLL_RUNTIME_H
#define PLIMSOLL_RUNTIME_H

#include <stddef.h>

#ifdef __cplusplus
extern "C" {
#endif

typedef struct plimsoll_bundle plimsoll_bundle;

typedef struct plimsoll_pose {
    double position[3];     /* world position of the object's origin, m */
    double orientation[4];  /* unit quaternion w, x, y, z */
} plimsoll_pose;

typedef struct plimsoll_velocity {
    double linear[3];       /* of the centre of mass, m/s */
    double angular[3];      /* rad/s */
} plimsoll_velocity;

/* Water height y at world (x, z) and time t (s). */
typedef double (*plimsoll_height_fn)(void* user, double x, double z, double time);
/* Water velocity at a world point (optional; for drag). */
typedef void (*plimsoll_water_velocity_fn)(void* user, const double point[3], double time,
                                           double velocity[3]);

typedef struct plimsoll_water {
    double level;                        /* flat water height when height is NULL, m */
    plimsoll_height_fn height;           /* may be NULL */
    plimsoll_water_velocity_fn velocity; /* may be NULL: still water */
    void* user;                          /* passed to both callbacks */
} plimsoll_water;

typedef struct plimsoll_fluid {
    double density;                /* kg/m^3 */
    double gravity;                /* m/s^2, along -y */
    double drag_coefficient;       /* C_d */
    double friction_coefficient;   /* C_f, 0 = off */
} plimsoll_fluid;

typedef struct plimsoll_forces {
    double submerged_volume;       /* m^3 */
    double center_of_buoyancy[3];  /* world, m */
    double force[3];               /* Archimedes, N */
    double torque[3];              /* about the centre of mass, N m */
    double pressure_force[3];
    double pressure_torque[3];
    double drag_force[3];
    double drag_torque[3];
    double wetted_area;            /* m^2 */
    size_t submerged_samples;
} plimsoll_forces;

typedef struct plimsoll_mass {
    double mass;                   /* kg */
    double volume;                 /* m^3 */
    double center_of_mass[3];      /* object space, m */
    double inertia[3][3];          /* about the centre of mass, object axes, kg m^2 */
} plimsoll_mass;

/* The message of the last failure on this thread ("" when none). */
const char* plimsoll_runtime_last_error(void);
/* "major.minor" of the bundle schema this runtime reads. */
const char* plimsoll_runtime_schema_version(void);

/* Loads a bundle folder, checking every file's size and SHA-256 when verify_checksums != 0.
 * NULL on failure. */
plimsoll_bundle* plimsoll_bundle_load(const char* folder, int verify_checksums);
void plimsoll_bundle_free(plimsoll_bundle* bundle);

const char* plimsoll_bundle_body(const plimsoll_bundle* bundle);
size_t plimsoll_bundle_sample_count(const plimsoll_bundle* bundle);
/* mass_properties.texture of the manifest. */
plimsoll_mass plimsoll_bundle_mass(const plimsoll_bundle* bundle);
/* Density 1000, gravity 9.81 and the manifest's drag and friction coefficients. */
plimsoll_fluid plimsoll_bundle_default_fluid(const plimsoll_bundle* bundle);
/* The manifest's linear and angular damping (1/s at full submersion). */
void plimsoll_bundle_damping(const plimsoll_bundle* bundle, double* linear, double* angular);

/* Buoyancy, pressure and drag. Returns 0 on bad arguments. */
int plimsoll_bundle_evaluate(const plimsoll_bundle* bundle, const plimsoll_pose* pose,
                             const plimsoll_velocity* velocity, const plimsoll_water* water,
                             const plimsoll_fluid* fluid, double time, plimsoll_forces* out);

/* Water graph (all return 0 / do nothing for a body without one). */
size_t plimsoll_graph_node_count(const plimsoll_bundle* bundle);
double plimsoll_graph_node_water(const plimsoll_bundle* bundle, size_t node);
double plimsoll_graph_node_capacity(const plimsoll_bundle* bundle, size_t node);
int plimsoll_graph_set_node_water(plimsoll_bundle* bundle, size_t node, double water);
/* The medium inside the body: density (kg/m^3), viscosity (Pa s), gravity (m/s^2). */
int plimsoll_graph_set_medium(plimsoll_bundle* bundle, double density, double viscosity,
                              double gravity);
/* Inflow and outflow (m^3/s) of each node through the permeable surface at this pose;
 * `inflow` and `outflow` hold node_count values each (either may be NULL). */
int plimsoll_graph_inflow(const plimsoll_bundle* bundle, const plimsoll_pose* pose,
                          const plimsoll_water* water, double time, double* inflow,
                          double* outflow);
/* One step of dt seconds: exchange with the water outside, then flow between nodes. Returns
 * 1 when water moved, 0 when not, -1 on error. */
int plimsoll_graph_step(plimsoll_bundle* bundle, const plimsoll_pose* pose,
                        const plimsoll_water* water, double time, double dt);
/* The water's mass properties at this orientation (w, x, y, z). */
plimsoll_mass plimsoll_graph_water_mass(const plimsoll_bundle* bundle, const double orientation[4]);

#ifdef __cplusplus
}
#endif

#endif /* PLIMSOLL_RUNTIME_H */
