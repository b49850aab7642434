/* float_body: loads a Plimsoll runtime bundle through the C API and floats one instance of the
 * body on flat water with the runtime's own integrator (plimsoll_instance_step: semi-implicit
 * Euler with gravity, buoyancy, drag, the manifest's damping, a water graph's water as extra
 * weight and, for a bundle exported with it, radiation),
 * printing the height and heel of the centre of mass and, at the end, the wall time per step.
 * With --csv it replays the project instead (plimsoll_simulation: the bundle's own water, start
 * and step settings, as `plimsoll simulate` steps them) and writes the columns of
 * `plimsoll simulate --out` to FILE, one row per frame, and prints the final state's hash.
 * Exits 1 on a load error or any non-finite value, 2 on a usage error.
 *   float_body BUNDLE_FOLDER [SECONDS] [--csv FILE] */
#include "plimsoll_runtime.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

static double now_seconds(void) {
    struct timespec ts;
    timespec_get(&ts, TIME_UTC);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* World height of the centre of mass and the heel (angle of the object's y axis from up). */
static void describe(const plimsoll_body_state* s, const plimsoll_mass* m, double* height,
                     double* heel) {
    const double w = s->pose.orientation[0], x = s->pose.orientation[1], y = s->pose.orientation[2],
                 z = s->pose.orientation[3];
    const double* c = m->center_of_mass;
    /* Row 1 of the rotation matrix gives the world y of an object-space vector. */
    const double r10 = 2 * (x * y + w * z), r11 = 1 - 2 * (x * x + z * z),
                 r12 = 2 * (y * z - w * x);
    *height = s->pose.position[1] + r10 * c[0] + r11 * c[1] + r12 * c[2];
    *heel = acos(fmin(1.0, fmax(-1.0, r11))) * 180.0 / 3.14159265358979323846;
}

/* The project's own run: one CSV row per frame, the columns of `plimsoll simulate --out`. */
static int replay(plimsoll_bundle* bundle, double seconds, const char* path) {
    plimsoll_simulation* simulation = plimsoll_simulation_create(bundle);
    if (!simulation) {
        fprintf(stderr, "float_body: %s\n", plimsoll_runtime_last_error());
        return 1;
    }
    FILE* out = fopen(path, "w");
    if (!out) {
        fprintf(stderr, "float_body: %s: cannot open for writing\n", path);
        plimsoll_simulation_destroy(simulation);
        return 1;
    }
    fprintf(out,
            "time,body,x,y,z,qw,qx,qy,qz,vx,vy,vz,wx,wy,wz,submerged_volume,fx,fy,fz,mass,com_x,"
            "com_y,com_z\n");
    plimsoll_simulation_state s;
    plimsoll_simulation_state_query(simulation, &s);
    /* As plimsoll simulate counts its frames: ceil(seconds / time_step), less a hair. */
    const long frames = (long)ceil(seconds / s.frame_time - 1e-9);
    int status = 0;
    for (long frame = 0; frame < frames; ++frame) {
        if (!plimsoll_simulation_advance_frame(simulation, NULL)) {
            fprintf(stderr, "float_body: %s\n", plimsoll_runtime_last_error());
            status = 1;
            break;
        }
        plimsoll_simulation_state_query(simulation, &s);
        fprintf(out,
                "%.10g,%s,%.10g,%.10g,%.10g,%.10g,%.10g,%.10g,%.10g,%.10g,%.10g,%.10g,%.10g,%.10g,%"
                ".10g,"
                "%.10g,%.10g,%.10g,%.10g,%.10g,%.10g,%.10g,%.10g\n",
                s.time, plimsoll_bundle_body(bundle), s.center_of_mass[0], s.center_of_mass[1],
                s.center_of_mass[2], s.orientation[0], s.orientation[1], s.orientation[2],
                s.orientation[3], s.velocity[0], s.velocity[1], s.velocity[2],
                s.angular_velocity[0], s.angular_velocity[1], s.angular_velocity[2],
                s.submerged_volume, s.buoyant_force[0], s.buoyant_force[1], s.buoyant_force[2],
                s.mass, s.local_center_of_mass[0], s.local_center_of_mass[1],
                s.local_center_of_mass[2]);
    }
    if (fclose(out) != 0 && status == 0) {
        fprintf(stderr, "float_body: %s: write error\n", path);
        status = 1;
    }
    /* The whole state's hash: equal on two machines or builds exactly when their states are. */
    if (status == 0)
        printf("state hash %016llx\n",
               (unsigned long long)plimsoll_simulation_state_hash(simulation));
    plimsoll_simulation_destroy(simulation);
    return status;
}

int main(int argc, char** argv) {
    const char* csv = NULL;
    const char* positional[2] = {NULL, NULL};
    int count = 0;
    for (int i = 1; i < argc; ++i) {
        if (strcmp(argv[i], "--csv") == 0 && i + 1 < argc) {
            csv = argv[++i];
        } else if (count < 2 && argv[i][0] != '-') {
            positional[count++] = argv[i];
        } else {
            count = -1;
            break;
        }
    }
    if (count < 1) {
        fprintf(stderr, "usage: float_body BUNDLE_FOLDER [SECONDS] [--csv FILE]\n");
        return 2;
    }
    const double seconds = count > 1 ? atof(positional[1]) : 10.0;
    plimsoll_bundle* bundle = plimsoll_bundle_load(positional[0], 1);
    if (!bundle) {
        fprintf(stderr, "float_body: %s\n", plimsoll_runtime_last_error());
        return 1;
    }
    if (csv) {
        const int status = replay(bundle, seconds, csv);
        plimsoll_bundle_destroy(bundle);
        return status;
    }
    int major = 0, minor = 0, patch = 0;
    plimsoll_runtime_version(&major, &minor, &patch);
    const plimsoll_mass body = plimsoll_bundle_mass(bundle);
    const plimsoll_fluid fluid = plimsoll_bundle_default_fluid(bundle);
    plimsoll_bundle_size size = {sizeof(plimsoll_bundle_size)};
    plimsoll_bundle_size_query(bundle, &size);
    printf(
        "runtime %d.%d.%d, bundle schema %s; body '%s': %zu samples, %.0f kB shipped, mass %.3f "
        "kg, "
        "volume %.4f m^3, %zu water graph nodes\n",
        major, minor, patch, plimsoll_runtime_schema_version(), plimsoll_bundle_body(bundle),
        size.samples, size.file_bytes / 1024.0, body.mass, body.volume, size.graph_nodes);

    /* Let go with the object origin on the water and a 10 degree heel about z. */
    const double heel0 = 10.0 * 3.14159265358979323846 / 180.0;
    plimsoll_body_state state = {{{0, 0, 0}, {cos(heel0 / 2), 0, 0, sin(heel0 / 2)}},
                                 {{0, 0, 0}, {0, 0, 0}}};
    const plimsoll_water water = {0.0, NULL, NULL, NULL};
    const double dt = 1.0 / 240.0;
    const int steps = (int)(seconds / dt + 0.5);
    plimsoll_instance* instance = plimsoll_instance_create(bundle);
    if (!instance) {
        fprintf(stderr, "float_body: %s\n", plimsoll_runtime_last_error());
        plimsoll_bundle_destroy(bundle);
        return 1;
    }
    double stepSeconds = 0;
    for (int step = 0; step <= steps; ++step) {
        double height, heel;
        describe(&state, &body, &height, &heel);
        if (!isfinite(height) || !isfinite(heel)) {
            fprintf(stderr, "float_body: non-finite state at t = %.3f s\n", step * dt);
            plimsoll_instance_destroy(instance);
            plimsoll_bundle_destroy(bundle);
            return 1;
        }
        if (step % 120 == 0)
            printf("t %6.2f s  height %+.4f m  heel %6.2f deg\n", step * dt, height, heel);
        if (step == steps) break;
        const double before = now_seconds();
        if (!plimsoll_instance_step(instance, &state, &water, &fluid, step * dt, dt)) {
            fprintf(stderr, "float_body: %s\n", plimsoll_runtime_last_error());
            plimsoll_instance_destroy(instance);
            plimsoll_bundle_destroy(bundle);
            return 1;
        }
        stepSeconds += now_seconds() - before;
    }
    /* Wall clock, for orientation only (plimsoll bench is where speed is measured). */
    printf("step: %.1f us wall per call over %d calls (%zu samples)\n",
           1e6 * stepSeconds / (steps > 0 ? steps : 1), steps, size.samples);
    plimsoll_instance_destroy(instance);
    plimsoll_bundle_destroy(bundle);
    return 0;
}
