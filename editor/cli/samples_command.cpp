#include "cli/commands.h"

#include "plimsoll/mesh_io.h"
#include "plimsoll/primitives.h"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <memory>
#include <string>
#include <system_error>

namespace plimsoll::cli {

namespace {

namespace fs = std::filesystem;

/// Frames of the deforming sample: a balloon inflating from radius 0.3 m to 0.6 m, the radius
/// growing geometrically (r_k = 0.3 * 2^(k / 23)), so the volume grows by the same factor
/// every frame. Same topology and UVs in every frame, as a deforming mesh must keep.
constexpr int kBalloonFrames = 24;

TriangleMesh balloonFrame(int k) {
    return makeUvSphere(0.3 * std::pow(2.0, k / (kBalloonFrames - 1.0)), 32, 16);
}

std::string balloonFrameName(int k) {
    char name[32];
    std::snprintf(name, sizeof name, "frame_%03d.obj", k);
    return name;
}

int writeBalloon(const fs::path& outDir) {
    const fs::path dir = outDir / "balloon";
    std::error_code ec;
    fs::create_directories(dir, ec);
    if (ec) {
        std::cerr << dir.string() << ": cannot create folder: " << ec.message() << "\n";
        return kExitFailure;
    }
    TriangleMesh frame;
    for (int k = 0; k < kBalloonFrames; ++k) {
        frame = balloonFrame(k);
        const Status written = writeObj(frame, dir / balloonFrameName(k));
        if (!written.ok()) {
            std::cerr << written.error().message << "\n";
            return kExitFailure;
        }
    }
    std::cout << (dir / balloonFrameName(0)).string() << " .. "
              << balloonFrameName(kBalloonFrames - 1) << ": " << kBalloonFrames << " frames of "
              << frame.vertexCount() << " vertices, " << frame.triangleCount() << " triangles\n";
    return kExitOk;
}

int runSamples(const fs::path& outDir) {
    std::error_code ec;
    fs::create_directories(outDir, ec);
    if (ec) {
        std::cerr << outDir.string() << ": cannot create folder: " << ec.message() << "\n";
        return kExitFailure;
    }
    // The committed assets/ are exactly this output; tests/test_primitives.cpp holds them to it.
    const struct {
        const char* file;
        TriangleMesh mesh;
    } samples[] = {
        {"sphere.obj", makeUvSphere(0.5, 64, 32)},
        {"box.obj", makeBox({1.0, 0.5, 0.25})},
        {"cylinder.obj", makeCylinder(0.3, 1.0, 64)},
        {"buoy.obj", makeBuoy()},
    };
    for (const auto& sample : samples) {
        const fs::path path = outDir / sample.file;
        const Status written = writeObj(sample.mesh, path);
        if (!written.ok()) {
            std::cerr << written.error().message << "\n";
            return kExitFailure;
        }
        std::cout << path.string() << ": " << sample.mesh.vertexCount() << " vertices, "
                  << sample.mesh.triangleCount() << " triangles\n";
    }
    return writeBalloon(outDir);
}

}  // namespace

void addSamplesCommand(CLI::App& root, CommandRunner& selected) {
    CLI::App* sub =
        root.add_subcommand("samples", "Write the generated sample meshes (assets/) to a folder");
    // Shared with the runner, which outlives this function.
    auto outDir = std::make_shared<std::string>();
    sub->add_option("--out", *outDir,
                    "Folder to write sphere.obj, box.obj, cylinder.obj, buoy.obj and "
                    "balloon/frame_000.obj .. frame_023.obj")
        ->required();
    sub->callback([&selected, outDir] { selected = [outDir] { return runSamples(*outDir); }; });
}

}  // namespace plimsoll::cli
