/* float_body: loads a Plimsoll runtime bundle through the C API and floats the body on flat
 * water with the runtime's own integrator (plimsoll_body_step: semi-implicit Euler with
 * gravity, buoyancy, drag, the manifest's damping and a water graph's water as extra weight),
 * printing the height and heel of the centre of mass and, at the end, the wall time per step.
 * Exits 1 on a load error or any non-finite value.
 *   float_body BUNDLE_FOLDER [SECONDS] */
#include "plimsoll_runtime.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <time.h>

static double now_seconds(void) {
    struct timespec ts;
    timespec_get(&ts, TIME_UTC);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* World height of the centre of mass and the heel (angle of the object's y axis from up). */
static void describe(const plimsoll_body_state* s, const plimsoll_mass* m, double* height, double* heel) {
    const double w = s->pose.orientation[0], x = s->pose.orientation[1], y = s->pose.orientation[2],
                 z = s->pose.orientation[3];
    const double* c = m->center_of_mass;
    /* Row 1 of the rotation matrix gives the world y of an object-space vector. */
    const double r10 = 2 * (x * y + w * z), r11 = 1 - 2 * (x * x + z * z), r12 = 2 * (y * z - w * x);
    *height = s->pose.position[1] + r10 * c[0] + r11 * c[1] + r12 * c[2];
    *heel = acos(fmin(1.0, fmax(-1.0, r11))) * 180.0 / 3.14159265358979323846;
}

int main(int argc, char** argv) {
    if (argc < 2) {
        fprintf(stderr, "usage: float_body BUNDLE_FOLDER [SECONDS]\n");
        return 2;
    }
    const double seconds = argc > 2 ? atof(argv[2]) : 10.0;
    plimsoll_bundle* bundle = plimsoll_bundle_load(argv[1], 1);
    if (!bundle) {
        fprintf(stderr, "float_body: %s\n", plimsoll_runtime_last_error());
        return 1;
    }
    int major = 0, minor = 0, patch = 0;
    plimsoll_runtime_version(&major, &minor, &patch);
    const plimsoll_mass body = plimsoll_bundle_mass(bundle);
    const plimsoll_fluid fluid = plimsoll_bundle_default_fluid(bundle);
    plimsoll_bundle_size size = {sizeof(plimsoll_bundle_size)};
    plimsoll_bundle_size_query(bundle, &size);
    printf("runtime %d.%d.%d, bundle schema %s; body '%s': %zu samples, %.0f kB shipped, mass %.3f kg, "
           "volume %.4f m^3, %zu water graph nodes\n",
           major, minor, patch, plimsoll_runtime_schema_version(), plimsoll_bundle_body(bundle),
           size.samples, size.file_bytes / 1024.0, body.mass, body.volume, size.graph_nodes);

    /* Let go with the object origin on the water and a 10 degree heel about z. */
    const double heel0 = 10.0 * 3.14159265358979323846 / 180.0;
    plimsoll_body_state state = {{{0, 0, 0}, {cos(heel0 / 2), 0, 0, sin(heel0 / 2)}}, {{0, 0, 0}, {0, 0, 0}}};
    const plimsoll_water water = {0.0, NULL, NULL, NULL};
    const double dt = 1.0 / 240.0;
    const int steps = (int)(seconds / dt + 0.5);
    double stepSeconds = 0;
    for (int step = 0; step <= steps; ++step) {
        double height, heel;
        describe(&state, &body, &height, &heel);
        if (!isfinite(height) || !isfinite(heel)) {
            fprintf(stderr, "float_body: non-finite state at t = %.3f s\n", step * dt);
            plimsoll_bundle_free(bundle);
            return 1;
        }
        if (step % 120 == 0) printf("t %6.2f s  height %+.4f m  heel %6.2f deg\n", step * dt, height, heel);
        if (step == steps) break;
        const double before = now_seconds();
        if (!plimsoll_body_step(bundle, &state, &water, &fluid, step * dt, dt)) {
            fprintf(stderr, "float_body: %s\n", plimsoll_runtime_last_error());
            plimsoll_bundle_free(bundle);
            return 1;
        }
        stepSeconds += now_seconds() - before;
    }
    /* Wall clock, for orientation only (plimsoll bench is where speed is measured). */
    printf("step: %.1f us wall per call over %d calls (%zu samples)\n", 1e6 * stepSeconds / (steps > 0 ? steps : 1),
           steps, size.samples);
    plimsoll_bundle_free(bundle);
    return 0;
}
