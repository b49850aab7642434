#include "cli/commands.h"

#include "plimsoll/mesh_io.h"
#include "plimsoll/primitives.h"

#include <filesystem>
#include <iostream>
#include <memory>
#include <string>
#include <system_error>

namespace plimsoll::cli {

namespace {

namespace fs = std::filesystem;

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
    return kExitOk;
}

}  // namespace

void addSamplesCommand(CLI::App& root, CommandRunner& selected) {
    CLI::App* sub =
        root.add_subcommand("samples", "Write the generated sample meshes (assets/) to a folder");
    // Shared with the runner, which outlives this function.
    auto outDir = std::make_shared<std::string>();
    sub->add_option("--out", *outDir, "Folder to write sphere.obj, box.obj, cylinder.obj, buoy.obj")
        ->required();
    sub->callback([&selected, outDir] { selected = [outDir] { return runSamples(*outDir); }; });
}

}  // namespace plimsoll::cli
