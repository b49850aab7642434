// The re-panelling's error (docs/radiation.md "Coarser panels for fine meshes"): a sample
// project's body solved at its default settings (the fine mesh re-panelled by coarsenedPanels,
// as the loader does) and on the mesh's own wetted triangles (not re-panelled), at the default
// 16 frequencies and infinite frequency; prints both and the largest differences of the diagonal
// A and B as a share of each curve's peak. Not part of the build; after the build:
//
//   g++ -O3 -DNDEBUG -std=c++20 -isystem /usr/include/eigen3 -Iengine/include \
//       -Iengine/eval/include -Iengine/src scripts/radiation-repanel-study.cpp \
//       -Wl,--start-group build/engine/*.a -Wl,--end-group -lassimp -lmpfr -lgmp -lz -ldraco
//       -lminizip -lOpenEXR-3_1 -lImath-3_1 -lIlmThread-3_1 -lIex-3_1 -lOpenCL -lcrypto -lpthread \
//       -o /tmp/repanel-study
//   /tmp/repanel-study projects/neutral_ball.plim.json [body index] [threads] [coarse]
#include "plimsoll/project/project.h"
#include "plimsoll/project/scene_loader.h"
#include "plimsoll/scene/scene_hydrostatics.h"
#include "plimsoll/scene/scene_radiation.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>

using namespace plimsoll;

int main(int argc, char** argv) {
    if (argc < 2) return 2;
    const std::size_t index = argc > 2 ? std::strtoul(argv[2], nullptr, 10) : 0;
    const unsigned threads = argc > 3 ? static_cast<unsigned>(std::atoi(argv[3])) : 0;
    Result<Project> project = loadProject(argv[1]);
    if (!project) return std::printf("%s\n", project.error().message.c_str()), 1;
    Project bare = *project;
    bare.bodies[index].radiation = RadiationDesc{.enabled = false};
    Result<SceneBody> body = loadSceneBody(bare, index);
    if (!body) return std::printf("%s\n", body.error().message.c_str()), 1;
    const Eigen::Vector3d gravity = project->simulation.gravity;
    Result<RestRadiationSurface> coarse =
        restRadiationSurface(*body, {}, project->medium, gravity, threads);
    if (!coarse) return std::printf("%s\n", coarse.error().message.c_str()), 1;
    // The fine solver: the loader's steps without the re-panelling.
    const Eigen::Affine3d atRest(Eigen::Translation3d(0, coarse->restHeight, 0));
    const double minArea = 1e-4 * std::pow(coarse->restVolume, 2.0 / 3.0);
    std::vector<RadiationPanel> fine = bisectedPanels(
        wettedPanels(*body->parts.mesh, atRest, minArea), coarse->resolved.panelEdge);
    Result<FloatingBody> floating = floatingBodyOf(*body, project->medium);
    if (!floating) return std::printf("%s\n", floating.error().message.c_str()), 1;
    const Eigen::Vector3d reference = atRest * floating->body.centerOfMass;
    std::printf("panels: re-panelled %zu (+%zu lid), own %zu\n", coarse->solver->panelCount(),
                coarse->solver->lidPanels().size(), fine.size());
    // A fourth argument "coarse": the re-panelled solve alone, against itself.
    if (argc > 4) fine = coarse->solver->panels();
    const RadiationSolver reference_solver(
        std::move(fine), reference,
        RadiationSettings{
            .gravity = gravity.norm(), .density = project->medium.density, .threads = threads});
    std::printf("lid of the own panels %zu\n", reference_solver.lidPanels().size());
    const RadiationDesc& r = coarse->resolved;
    const int modes[] = {0, 1, 2, 3, 5};
    const char* names[] = {"surge", "heave", "sway", "roll", "pitch"};
    double peakA[5] = {}, peakB[5] = {}, dA[5] = {}, dB[5] = {};
    for (int k = 0; k < r.frequencies; ++k) {
        const double omega = r.minFrequency * std::pow(r.maxFrequency / r.minFrequency,
                                                       k / double(r.frequencies - 1));
        const RadiationCoefficients c = coarse->solver->at(omega), f = reference_solver.at(omega);
        std::printf("w %.4f", omega);
        for (int m = 0; m < 5; ++m) {
            const int d = modes[m];
            peakA[m] = std::max(peakA[m], std::abs(f.addedMass(d, d)));
            peakB[m] = std::max(peakB[m], std::abs(f.damping(d, d)));
            dA[m] = std::max(dA[m], std::abs(c.addedMass(d, d) - f.addedMass(d, d)));
            dB[m] = std::max(dB[m], std::abs(c.damping(d, d) - f.damping(d, d)));
            std::printf("  %s A %.4g/%.4g B %.4g/%.4g", names[m], c.addedMass(d, d),
                        f.addedMass(d, d), c.damping(d, d), f.damping(d, d));
        }
        std::printf("\n");
        std::fflush(stdout);
    }
    const Matrix6d ac = coarse->solver->infiniteFrequencyAddedMass(),
                   af = reference_solver.infiniteFrequencyAddedMass();
    for (int m = 0; m < 5; ++m) {
        const int d = modes[m];
        std::printf(
            "%s: largest difference A %.1f%%, B %.1f%% of the peak; A_inf %.4g against %.4g "
            "(%+.1f%%)\n",
            names[m], 100 * dA[m] / peakA[m], 100 * dB[m] / peakB[m], ac(d, d), af(d, d),
            100 * (ac(d, d) / af(d, d) - 1));
    }
}
