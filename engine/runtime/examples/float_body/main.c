/* float_body: loads a Plimsoll runtime bundle through the C API and floats the body on flat
 * water with semi-implicit Euler (gravity, buoyancy, drag, damping; a water graph's water as
 * extra weight), printing the height and heel of the centre of mass and, at the end, the wall
 * time per evaluate call. Exits 1 on a load error
 * or any non-finite value.
 *   float_body BUNDLE_FOLDER [SECONDS] */
#include "plimsoll_runtime.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <time.h>

static void quat_to_matrix(const double q[4], double R[3][3]) {
    const double w = q[0], x = q[1], y = q[2], z = q[3];
    R[0][0] = 1 - 2 * (y * y + z * z); R[0][1] = 2 * (x * y - w * z);     R[0][2] = 2 * (x * z + w * y);
    R[1][0] = 2 * (x * y + w * z);     R[1][1] = 1 - 2 * (x * x + z * z); R[1][2] = 2 * (y * z - w * x);
    R[2][0] = 2 * (x * z - w * y);     R[2][1] = 2 * (y * z + w * x);     R[2][2] = 1 - 2 * (x * x + y * y);
}

static void mat_vec(double R[3][3], const double v[3], double out[3]) {
    for (int i = 0; i < 3; ++i) out[i] = R[i][0] * v[0] + R[i][1] * v[1] + R[i][2] * v[2];
}

/* inverse of a symmetric positive definite 3 x 3 by cofactors; 0 when singular */
static int invert(double A[3][3], double B[3][3]) {
    const double c00 = A[1][1] * A[2][2] - A[1][2] * A[2][1];
    const double c01 = A[1][2] * A[2][0] - A[1][0] * A[2][2];
    const double c02 = A[1][0] * A[2][1] - A[1][1] * A[2][0];
    const double det = A[0][0] * c00 + A[0][1] * c01 + A[0][2] * c02;
    if (!(fabs(det) > 0)) return 0;
    B[0][0] = c00 / det;
    B[1][0] = c01 / det;
    B[2][0] = c02 / det;
    B[0][1] = (A[0][2] * A[2][1] - A[0][1] * A[2][2]) / det;
    B[1][1] = (A[0][0] * A[2][2] - A[0][2] * A[2][0]) / det;
    B[2][1] = (A[0][1] * A[2][0] - A[0][0] * A[2][1]) / det;
    B[0][2] = (A[0][1] * A[1][2] - A[0][2] * A[1][1]) / det;
    B[1][2] = (A[0][2] * A[1][0] - A[0][0] * A[1][2]) / det;
    B[2][2] = (A[0][0] * A[1][1] - A[0][1] * A[1][0]) / det;
    return 1;
}

static void cross(const double a[3], const double b[3], double out[3]) {
    out[0] = a[1] * b[2] - a[2] * b[1];
    out[1] = a[2] * b[0] - a[0] * b[2];
    out[2] = a[0] * b[1] - a[1] * b[0];
}

static double now_seconds(void) {
    struct timespec ts;
    timespec_get(&ts, TIME_UTC);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static double norm3(const double v[3]) { return sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]); }

/* At most stop the motion within one step (as the engine's World does for dissipation). */
static void limit(double loss[3], const double momentum[3], double dt) {
    const double impulse = norm3(loss) * dt, cap = norm3(momentum);
    if (impulse > cap && impulse > 0)
        for (int k = 0; k < 3; ++k) loss[k] *= cap / impulse;
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
    const plimsoll_mass body = plimsoll_bundle_mass(bundle);
    const plimsoll_fluid fluid = plimsoll_bundle_default_fluid(bundle);
    double linearDamping = 0, angularDamping = 0;
    plimsoll_bundle_damping(bundle, &linearDamping, &angularDamping);
    const size_t nodes = plimsoll_graph_node_count(bundle);
    printf("body '%s': %zu samples, mass %.3f kg, volume %.4f m^3, %zu water graph nodes\n",
           plimsoll_bundle_body(bundle), plimsoll_bundle_sample_count(bundle), body.mass,
           body.volume, nodes);

    /* State: centre of mass x, orientation q (w, x, y, z), momenta P and L (world). Start
     * with the centre of mass on the water and a 10 degree heel about z. */
    double x[3] = {0, 0, 0}, P[3] = {0, 0, 0}, L[3] = {0, 0, 0};
    const double heel0 = 10.0 * 3.14159265358979323846 / 180.0;
    double q[4] = {cos(heel0 / 2), 0, 0, sin(heel0 / 2)};
    plimsoll_water water = {0.0, NULL, NULL, NULL};
    const double dt = 1.0 / 240.0, g = fluid.gravity;
    const int steps = (int)(seconds / dt + 0.5);
    double evaluateSeconds = 0, evaluateCpu = 0;
    for (int step = 0; step <= steps; ++step) {
        const double t = step * dt;
        double R[3][3];
        quat_to_matrix(q, R);
        double rc[3];
        mat_vec(R, body.center_of_mass, rc);
        plimsoll_pose pose = {{x[0] - rc[0], x[1] - rc[1], x[2] - rc[2]}, {q[0], q[1], q[2], q[3]}};
        /* Velocities from the momenta: v = P / m, w = I_world^-1 L. */
        double Iw[3][3], Iinv[3][3], RI[3][3];
        for (int i = 0; i < 3; ++i)
            for (int j = 0; j < 3; ++j)
                RI[i][j] = R[i][0] * body.inertia[0][j] + R[i][1] * body.inertia[1][j] + R[i][2] * body.inertia[2][j];
        for (int i = 0; i < 3; ++i)
            for (int j = 0; j < 3; ++j)
                Iw[i][j] = RI[i][0] * R[j][0] + RI[i][1] * R[j][1] + RI[i][2] * R[j][2];
        if (!invert(Iw, Iinv)) {
            fprintf(stderr, "float_body: singular inertia\n");
            return 1;
        }
        plimsoll_velocity vel;
        for (int k = 0; k < 3; ++k) vel.linear[k] = P[k] / body.mass;
        mat_vec(Iinv, L, vel.angular);

        plimsoll_forces f;
        const double before = now_seconds();
        const clock_t cpuBefore = clock();
        if (!plimsoll_bundle_evaluate(bundle, &pose, &vel, &water, &fluid, t, &f)) {
            fprintf(stderr, "float_body: %s\n", plimsoll_runtime_last_error());
            return 1;
        }
        evaluateSeconds += now_seconds() - before;
        evaluateCpu += (double)(clock() - cpuBefore) / CLOCKS_PER_SEC;
        double force[3] = {f.force[0], f.force[1] - body.mass * g, f.force[2]};
        double torque[3] = {f.torque[0], f.torque[1], f.torque[2]};
        /* Water inside (a flooding body): its weight at its centre of mass. */
        if (nodes > 0) {
            if (plimsoll_graph_step(bundle, &pose, &water, t, dt) < 0) {
                fprintf(stderr, "float_body: %s\n", plimsoll_runtime_last_error());
                return 1;
            }
            const plimsoll_mass w = plimsoll_graph_water_mass(bundle, q);
            if (w.mass > 0) {
                double offset[3], arm[3], weight[3] = {0, -w.mass * g, 0}, moment[3];
                for (int k = 0; k < 3; ++k) offset[k] = w.center_of_mass[k] - body.center_of_mass[k];
                mat_vec(R, offset, arm);
                cross(arm, weight, moment);
                force[1] += weight[1];
                for (int k = 0; k < 3; ++k) torque[k] += moment[k];
            }
        }
        const double wet = body.volume > 0 ? fmin(1.0, fmax(0.0, f.submerged_volume / body.volume)) : 0.0;
        double dragF[3], dragT[3];
        for (int k = 0; k < 3; ++k) {
            dragF[k] = f.drag_force[k] - wet * linearDamping * P[k];
            dragT[k] = f.drag_torque[k] - wet * angularDamping * L[k];
        }
        limit(dragF, P, dt);
        limit(dragT, L, dt);
        for (int k = 0; k < 3; ++k) {
            force[k] += dragF[k];
            torque[k] += dragT[k];
        }

        const double heel = acos(fmin(1.0, fmax(-1.0, R[1][1]))) * 180.0 / 3.14159265358979323846;
        if (step % 120 == 0) {
            printf("t %6.2f s  height %+.4f m  heel %6.2f deg  submerged %.4f m^3\n", t, x[1], heel,
                   f.submerged_volume);
        }
        int finite = isfinite(heel) && isfinite(f.submerged_volume);
        for (int k = 0; k < 3; ++k) finite = finite && isfinite(x[k]) && isfinite(force[k]) && isfinite(torque[k]);
        if (!finite) {
            fprintf(stderr, "float_body: non-finite state at t = %.3f s\n", t);
            plimsoll_bundle_free(bundle);
            return 1;
        }
        if (step == steps) break;

        /* Semi-implicit Euler: momenta first, then position and orientation with the new
         * velocities. */
        for (int k = 0; k < 3; ++k) {
            P[k] += dt * force[k];
            L[k] += dt * torque[k];
            x[k] += dt * P[k] / body.mass;
        }
        double w[3];
        mat_vec(Iinv, L, w);
        const double dq[4] = {-w[0] * q[1] - w[1] * q[2] - w[2] * q[3],
                              w[0] * q[0] + w[1] * q[3] - w[2] * q[2],
                              w[1] * q[0] + w[2] * q[1] - w[0] * q[3],
                              w[2] * q[0] + w[0] * q[2] - w[1] * q[1]};
        double n = 0;
        for (int k = 0; k < 4; ++k) {
            q[k] += 0.5 * dt * dq[k];
            n += q[k] * q[k];
        }
        n = sqrt(n);
        for (int k = 0; k < 4; ++k) q[k] /= n;
    }
    /* Wall clock, for orientation only (plimsoll bench is where speed is measured). */
    printf("evaluate: %.1f us wall, %.1f us CPU per call over %d calls (%zu samples)\n",
           1e6 * evaluateSeconds / (steps + 1), 1e6 * evaluateCpu / (steps + 1), steps + 1,
           plimsoll_bundle_sample_count(bundle));
    plimsoll_bundle_free(bundle);
    return 0;
}
