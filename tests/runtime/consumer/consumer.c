/* A C game's use of the runtime: load a bundle, float two instances of it for a second. Prints
 * the heights and exits 0, or prints the error and exits 1. */
#include <plimsoll_runtime.h>

#include <stdio.h>

int main(int argc, char** argv) {
    if (argc != 2) {
        fprintf(stderr, "usage: consumer BUNDLE_FOLDER\n");
        return 2;
    }
    plimsoll_bundle* bundle = plimsoll_bundle_load(argv[1], 1);
    if (!bundle) {
        fprintf(stderr, "consumer: %s\n", plimsoll_runtime_last_error());
        return 1;
    }
    plimsoll_instance* boats[2] = {plimsoll_instance_create(bundle),
                                   plimsoll_instance_create(bundle)};
    plimsoll_body_state states[2] = {{{{0, 0.2, 0}, {1, 0, 0, 0}}, {{0, 0, 0}, {0, 0, 0}}},
                                     {{{3, 0.4, 0}, {1, 0, 0, 0}}, {{0, 0, 0}, {0, 0, 0}}}};
    const plimsoll_water water = {0.0, NULL, NULL, NULL};
    const plimsoll_fluid fluid = plimsoll_bundle_default_fluid(bundle);
    int ok = boats[0] && boats[1];
    for (int step = 0; ok && step < 120; ++step) {
        for (int i = 0; ok && i < 2; ++i)
            ok = plimsoll_instance_step(boats[i], &states[i], &water, &fluid, step / 120.0,
                                        1.0 / 120.0);
    }
    if (!ok)
        fprintf(stderr, "consumer: %s\n", plimsoll_runtime_last_error());
    else
        printf("consumer (C): heights %.4f %.4f m\n", states[0].pose.position[1],
               states[1].pose.position[1]);
    plimsoll_instance_destroy(boats[0]);
    plimsoll_instance_destroy(boats[1]);
    plimsoll_bundle_destroy(bundle);
    return ok ? 0 : 1;
}
