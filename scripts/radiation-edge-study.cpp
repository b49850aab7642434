// Bake time and accuracy of the panel method against the panel edge (docs/radiation.md, "The
// default panel edge"): a 1 m cube of density 250 in water of 1000 kg/m^3 (rest volume 0.25 m^3,
// draft 0.25 m), placed and split as the scene's computeBodyRadiation does, solved at the
// default 16 frequencies (K L = 0.05 to 5, L = cbrt(V) / 2) and at infinite frequency.
// Not part of the build; after scripts/build.sh:
//
//   g++ -O3 -DNDEBUG -std=c++20 -isystem /usr/include/eigen3 -Iengine/include \
//       -Iengine/eval/include scripts/radiation-edge-study.cpp engine/src/samples/primitives.cpp \
//       build/engine/libplimsoll_core.a -lpthread -o /tmp/radiation-edge-study
//   THREADS=1 /usr/bin/time -f "%U s CPU" /tmp/radiation-edge-study 2      # edge cbrt(V) / 2
//   THREADS=2 /tmp/radiation-edge-study 0 16 0.15                          # the reference, 0.15 m
//
// Arguments: divisor (edge = cbrt(V) / divisor), frequencies (default 16), an absolute edge in
// metres that overrides the divisor. THREADS: RadiationSettings::threads (default all cores).
// Prints the panel counts, then A and B of surge (x), heave (y) and trim (rotation about z)
// per frequency, in kg and kg/s (kg m^2 and kg m^2/s for trim), about the centre of the cube.
#include "plimsoll/physics/radiation.h"
#include "plimsoll/samples/primitives.h"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>

using namespace plimsoll;

int main(int argc, char** argv) {
    const double divisor = argc > 1 ? std::atof(argv[1]) : 2.0;
    const int frequencies = argc > 2 ? std::atoi(argv[2]) : 16;
    const double absoluteEdge = argc > 3 ? std::atof(argv[3]) : 0.0;
    const TriangleMesh mesh = makeBox(Eigen::Vector3d(1, 1, 1));
    const double volume = 0.25, gravity = 9.81;
    const auto start = std::chrono::steady_clock::now();
    const double height = equilibriumHeight(mesh, Eigen::Affine3d::Identity(), volume);
    const Eigen::Affine3d atRest(Eigen::Translation3d(0, height, 0));
    const auto wetted = wettedPanels(mesh, atRest, 1e-4 * std::pow(volume, 2.0 / 3.0));
    const double size = std::cbrt(volume);
    const double edge = absoluteEdge > 0 ? absoluteEdge : size / divisor;
    RadiationSettings settings{gravity, 1000.0};
    if (const char* threads = std::getenv("THREADS"))
        settings.threads = static_cast<unsigned>(std::atoi(threads));
    const RadiationSolver solver(refinedPanels(wetted, edge), atRest * Eigen::Vector3d::Zero(),
                                 settings);
    const auto setUp = std::chrono::steady_clock::now();
    std::printf("edge %.4f panels %zu lid %zu setup %.2f s\n", edge, solver.panelCount(),
                solver.lidPanels().size(), std::chrono::duration<double>(setUp - start).count());
    const double length = size / 2;
    const double low = std::sqrt(0.05 * gravity / length), high = std::sqrt(5.0 * gravity / length);
    for (int k = 0; k < frequencies; ++k) {
        const double omega =
            frequencies == 1 ? low : low * std::pow(high / low, k / double(frequencies - 1));
        const RadiationCoefficients c = solver.at(omega);
        std::printf("w %.17g A11 %.17g B11 %.17g A33 %.17g B33 %.17g A55 %.17g B55 %.17g\n", omega,
                    c.addedMass(0, 0), c.damping(0, 0), c.addedMass(1, 1), c.damping(1, 1),
                    c.addedMass(5, 5), c.damping(5, 5));
    }
    const Matrix6d infinity = solver.infiniteFrequencyAddedMass();
    const auto end = std::chrono::steady_clock::now();
    std::printf("Ainf11 %.6f Ainf33 %.6f\n", infinity(0, 0), infinity(1, 1));
    std::printf("frequencies %.2f s total %.2f s\n",
                std::chrono::duration<double>(end - setUp).count(),
                std::chrono::duration<double>(end - start).count());
}
