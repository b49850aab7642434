// A C++ game's use of the runtime: the C ABI (what the shared library exports) and, against the
// static library, the C++ API too. Prints what it found and exits 0, or the error and exits 1.
#include <plimsoll_runtime.h>
#ifndef PLIMSOLL_RUNTIME_SHARED
#include <plimsoll_runtime/runtime.hpp>
#endif

#include <cstdio>
#include <memory>
#include <string>

int main(int argc, char** argv) {
    if (argc != 2) {
        std::fprintf(stderr, "usage: consumer BUNDLE_FOLDER\n");
        return 2;
    }
    std::unique_ptr<plimsoll_bundle, decltype(&plimsoll_bundle_destroy)> bundle(
        plimsoll_bundle_load(argv[1], 1), &plimsoll_bundle_destroy);
    if (!bundle) {
        std::fprintf(stderr, "consumer: %s\n", plimsoll_runtime_last_error());
        return 1;
    }
    std::unique_ptr<plimsoll_instance, decltype(&plimsoll_instance_destroy)> boat(
        plimsoll_instance_create(bundle.get()), &plimsoll_instance_destroy);
    plimsoll_body_state state = {{{0, 0.2, 0}, {1, 0, 0, 0}}, {{0, 0, 0}, {0, 0, 0}}};
    const plimsoll_water water = {0.0, nullptr, nullptr, nullptr};
    const plimsoll_fluid fluid = plimsoll_bundle_default_fluid(bundle.get());
    for (int step = 0; step < 120; ++step) {
        if (!plimsoll_instance_step(boat.get(), &state, &water, &fluid, step / 120.0,
                                    1.0 / 120.0)) {
            std::fprintf(stderr, "consumer: %s\n", plimsoll_runtime_last_error());
            return 1;
        }
    }
    std::printf("consumer (C++): height %.4f m", state.pose.position[1]);
#ifndef PLIMSOLL_RUNTIME_SHARED
    std::string error;
    const std::unique_ptr<plimsoll_runtime::Bundle> cpp =
        plimsoll_runtime::loadBundle(argv[1], error);
    if (!cpp) {
        std::fprintf(stderr, "\nconsumer: %s\n", error.c_str());
        return 1;
    }
    plimsoll_runtime::Body body(*cpp);
    plimsoll_runtime::BundleManifest manifest;
    if (!plimsoll_runtime::readBundleManifest(argv[1], manifest, error)) {
        std::fprintf(stderr, "\nconsumer: %s\n", error.c_str());
        return 1;
    }
    std::printf("; C++ API: %zu samples, instance %llu bytes, %zu files verified",
                cpp->samples().size(), static_cast<unsigned long long>(body.memoryBytes()),
                manifest.files.size());
#endif
    std::printf("\n");
    return 0;
}
