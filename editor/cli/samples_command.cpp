#include "cli/commands.h"

#include "cli/common.h"

#include "plimsoll/io/mesh_io.h"
#include "plimsoll/io/painted_map_io.h"
#include "plimsoll/surface/painted_map.h"
#include "plimsoll/samples/primitives.h"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <functional>
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

/// A map over the mesh's UVs: value(p) at the surface point p each pixel centre maps to, 0
/// where no triangle covers the pixel.
PaintedMap paintByPosition(const TriangleMesh& mesh, int size,
                           const std::function<float(const Eigen::Vector3d&)>& value) {
    PaintedMap map;
    map.width = map.height = size;
    map.values.assign(static_cast<std::size_t>(size) * size, 0.0f);
    for (const Triangle& t : mesh.triangles) {
        const Eigen::Vector2d a = mesh.uvs[t[0]], b = mesh.uvs[t[1]], c = mesh.uvs[t[2]];
        const double det = (b - a).x() * (c - a).y() - (c - a).x() * (b - a).y();
        if (det == 0) continue;
        const Eigen::Vector2d lo = a.cwiseMin(b).cwiseMin(c), hi = a.cwiseMax(b).cwiseMax(c);
        for (int py = 0; py < size; ++py) {
            const double v = 1.0 - (py + 0.5) / size;
            if (v < lo.y() || v > hi.y()) continue;
            for (int px = 0; px < size; ++px) {
                const double u = (px + 0.5) / size;
                if (u < lo.x() || u > hi.x()) continue;
                const Eigen::Vector2d d = Eigen::Vector2d(u, v) - a;
                const double s1 = (d.x() * (c - a).y() - (c - a).x() * d.y()) / det;
                const double s2 = ((b - a).x() * d.y() - d.x() * (b - a).y()) / det;
                if (s1 < 0 || s2 < 0 || s1 + s2 > 1) continue;
                const Eigen::Vector3d p = mesh.positions[t[0]] +
                                          s1 * (mesh.positions[t[1]] - mesh.positions[t[0]]) +
                                          s2 * (mesh.positions[t[2]] - mesh.positions[t[0]]);
                map.values[static_cast<std::size_t>(py) * size + px] = value(p);
            }
        }
    }
    return map;
}

/// The water-graph samples' maps: the hull's stern damage (paper figures 12-13: the last
/// 1 m of the bottom and sides and the transom, below y = 0) and the plush's uniform
/// permeability.
int writeMaps(const fs::path& outDir) {
    const struct {
        const char* file;
        PaintedMap map;
    } maps[] = {
        {"hull_stern_damage.png", paintByPosition(makeHull(), 128,
                                                  [](const Eigen::Vector3d& p) {
                                                      return p.z() < -2.0 && p.y() < 0.0 ? 1.0f
                                                                                         : 0.0f;
                                                  })},
        {"plush_permeable.png",
         paintByPosition(makePlush(), 16, [](const Eigen::Vector3d&) { return 1.0f; })},
    };
    for (const auto& m : maps) {
        const Status written = savePaintedMap(m.map, outDir / m.file);
        if (!written.ok()) {
            std::cerr << written.error().message << "\n";
            return kExitFailure;
        }
        std::cout << (outDir / m.file).string() << ": " << m.map.width << " x " << m.map.height
                  << " painted map\n";
    }
    return kExitOk;
}

int runSamples(const fs::path& outDir) {
    std::error_code ec;
    fs::create_directories(outDir, ec);
    if (ec) {
        std::cerr << outDir.string() << ": cannot create folder: " << ec.message() << "\n";
        return kExitFailure;
    }
    // The committed assets/ are exactly this output; tests/samples/test_primitives.cpp holds them
    // to it.
    const struct {
        const char* file;
        TriangleMesh mesh;
    } samples[] = {
        {"sphere.obj", makeUvSphere(0.5, 64, 32)},
        {"box.obj", makeBox({1.0, 0.5, 0.25})},
        {"cylinder.obj", makeCylinder(0.3, 1.0, 64)},
        {"buoy.obj", makeBuoy()},
        {"hull.obj", makeHull()},
        {"plush.obj", makePlush()},
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
    if (const int code = writeMaps(outDir); code != kExitOk) return code;
    return writeBalloon(outDir);
}

}  // namespace

void addSamplesCommand(CLI::App& root, CommandRunner& selected) {
    CLI::App* sub =
        root.add_subcommand("samples", "Write the generated sample meshes (assets/) to a folder");
    // Shared with the runner, which outlives this function.
    auto outDir = std::make_shared<std::string>();
    sub->add_option("--out", *outDir,
                    "Folder to write sphere.obj, box.obj, cylinder.obj, buoy.obj, hull.obj, "
                    "plush.obj, their painted maps and balloon/frame_000.obj .. frame_023.obj")
        ->required()
        ->check(kNonEmptyPath);
    sub->callback([&selected, outDir] { selected = [outDir] { return runSamples(*outDir); }; });
}

}  // namespace plimsoll::cli
