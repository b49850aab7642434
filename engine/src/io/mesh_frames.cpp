// The frames of a deforming mesh, one file each (mesh_io.h loadMeshFrames).
#include "plimsoll/io/mesh_io.h"

#include <string>

namespace plimsoll {

namespace {

/// The first way `frame` differs from `reference`, as an error naming the file.
Status compareFrames(const TriangleMesh& reference, const TriangleMesh& frame) {
    const std::string against = " (the first frame, " + reference.source + ", has ";
    if (frame.triangleCount() != reference.triangleCount()) {
        return makeError(ErrorKind::invalidArgument,
                         frame.source + ": " + std::to_string(frame.triangleCount()) +
                             " triangles" + against + std::to_string(reference.triangleCount()) +
                             ")");
    }
    if (frame.vertexCount() != reference.vertexCount()) {
        return makeError(ErrorKind::invalidArgument,
                         frame.source + ": " + std::to_string(frame.vertexCount()) + " vertices" +
                             against + std::to_string(reference.vertexCount()) + ")");
    }
    const auto text = [](const Triangle& t) {
        return "(" + std::to_string(t[0]) + ", " + std::to_string(t[1]) + ", " +
               std::to_string(t[2]) + ")";
    };
    for (std::size_t i = 0; i < frame.triangleCount(); ++i) {
        if (frame.triangles[i] != reference.triangles[i]) {
            return makeError(ErrorKind::invalidArgument, frame.source + ": triangle " +
                                                             std::to_string(i) + " has vertices " +
                                                             text(frame.triangles[i]) + against +
                                                             text(reference.triangles[i]) + ")");
        }
    }
    if (frame.hasUvs() != reference.hasUvs()) {
        return makeError(ErrorKind::invalidArgument, frame.source +
                                                         (frame.hasUvs() ? ": has" : ": has no") +
                                                         " texture coordinates" + against +
                                                         (reference.hasUvs() ? "them)" : "none)"));
    }
    // The piece table is baked from the first frame's UVs: other UVs would regather silently
    // wrong textures.
    for (std::size_t v = 0; v < frame.uvs.size(); ++v) {
        if (frame.uvs[v] != reference.uvs[v]) {
            return makeError(ErrorKind::invalidArgument,
                             frame.source + ": vertex " + std::to_string(v) +
                                 " has other texture coordinates than in the first frame, " +
                                 reference.source + " (a deforming mesh keeps its UVs)");
        }
    }
    return Ok{};
}

}  // namespace

Result<std::vector<TriangleMesh>> loadMeshFrames(const std::vector<std::filesystem::path>& paths) {
    if (paths.empty())
        return makeError(ErrorKind::invalidArgument, "a deforming mesh needs at least one frame");
    std::vector<TriangleMesh> frames;
    frames.reserve(paths.size());
    for (const std::filesystem::path& path : paths) {
        Result<TriangleMesh> frame =
            loadMesh(path, MeshLoadOptions{.joinIdenticalVertices = false});
        if (!frame) return frame.error();
        if (!frames.empty()) {
            if (Status same = compareFrames(frames.front(), *frame); !same) return same.error();
        }
        frames.push_back(std::move(frame).value());
    }
    return frames;
}

}  // namespace plimsoll
