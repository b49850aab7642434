// assimp adapter: the only file that includes assimp. Everything downstream sees TriangleMesh.
#include "plimsoll/mesh_io.h"

#include "mesh_header_check.h"
#include "plimsoll/limits.h"

#include <assimp/Importer.hpp>
#include <assimp/postprocess.h>
#include <assimp/scene.h>

#include <cctype>
#include <cmath>
#include <fstream>
#include <sstream>
#include <string>
#include <system_error>

namespace plimsoll {

namespace fs = std::filesystem;

namespace {

void configure(Assimp::Importer& importer) {
    // Points and lines carry no surface: drop them instead of failing on mixed files.
    importer.SetPropertyInteger(AI_CONFIG_PP_SBP_REMOVE,
                                aiPrimitiveType_POINT | aiPrimitiveType_LINE);
}

unsigned importFlags(MeshLoadOptions options) {
    // No normal generation, no degenerate removal, no vertex welding beyond exact duplicates
    // (and none at all for the frames of a deforming mesh): validation must see the file as it
    // is.
    unsigned flags = aiProcess_Triangulate | aiProcess_PreTransformVertices | aiProcess_SortByPType;
    if (options.joinIdenticalVertices) flags |= aiProcess_JoinIdenticalVertices;
    return flags;
}

Result<TriangleMesh> fromScene(const aiScene* scene, const Assimp::Importer& importer,
                               const std::string& name) {
    if (!scene || !scene->mRootNode) {
        return makeError(name + ": cannot read mesh: " + importer.GetErrorString());
    }

    // Formats without a count in a header (OBJ, glTF) are counted once read, before copying.
    std::uint64_t triangles = 0, vertices = 0;
    for (unsigned m = 0; m < scene->mNumMeshes; ++m) {
        triangles += scene->mMeshes[m]->mNumFaces;
        vertices += scene->mMeshes[m]->mNumVertices;
    }
    if (triangles > kMaxTriangles || vertices > kMaxVertices) {
        return makeError(name + ": " + std::to_string(triangles) + " triangles, " +
                         std::to_string(vertices) + " vertices: more than the limit " +
                         (triangles > kMaxTriangles
                              ? "kMaxTriangles = " + std::to_string(kMaxTriangles)
                              : "kMaxVertices = " + std::to_string(kMaxVertices)) +
                         " (limits.h)");
    }

    TriangleMesh mesh;
    mesh.source = name;
    bool allHaveUvs = true;
    for (unsigned m = 0; m < scene->mNumMeshes; ++m) {
        const aiMesh* part = scene->mMeshes[m];
        if (!(part->mPrimitiveTypes & aiPrimitiveType_TRIANGLE)) continue;
        allHaveUvs = allHaveUvs && part->HasTextureCoords(0);
    }

    for (unsigned m = 0; m < scene->mNumMeshes; ++m) {
        const aiMesh* part = scene->mMeshes[m];
        if (!(part->mPrimitiveTypes & aiPrimitiveType_TRIANGLE)) continue;
        const auto base = static_cast<std::uint32_t>(mesh.positions.size());
        for (unsigned v = 0; v < part->mNumVertices; ++v) {
            const aiVector3D& p = part->mVertices[v];
            mesh.positions.emplace_back(p.x, p.y, p.z);
            if (allHaveUvs) {
                const aiVector3D& t = part->mTextureCoords[0][v];
                mesh.uvs.emplace_back(t.x, t.y);
            }
        }
        for (unsigned f = 0; f < part->mNumFaces; ++f) {
            const aiFace& face = part->mFaces[f];
            if (face.mNumIndices != 3) continue;
            mesh.triangles.push_back(
                {base + face.mIndices[0], base + face.mIndices[1], base + face.mIndices[2]});
        }
    }
    if (mesh.triangles.empty()) return makeError(name + ": the file holds no triangles");
    return mesh;
}

/// An OBJ's text through detail::objGeometry (v / vt / vn / f only, every index checked), and
/// only that checked geometry through assimp: its OBJ reader crashes on what the check refuses.
Result<TriangleMesh> loadObj(std::istream& text, const std::string& source,
                             MeshLoadOptions options) {
    Result<std::string> geometry = detail::objGeometry(text, source);
    if (!geometry) return geometry.error();
    if (geometry->empty()) return makeError(source + ": no triangles (no v or f lines)");
    Assimp::Importer importer;
    configure(importer);
    const aiScene* scene = importer.ReadFileFromMemory(geometry->data(), geometry->size(),
                                                       importFlags(options), "obj");
    return fromScene(scene, importer, source);
}

}  // namespace

Result<TriangleMesh> loadMesh(const fs::path& path, MeshLoadOptions options) {
    const std::string name = path.string();
    std::error_code ec;
    if (!fs::exists(path, ec)) return makeError(name + ": no such file");
    if (fs::is_directory(path, ec)) return makeError(name + ": is a folder, not a mesh file");
    if (Status header = detail::checkMeshHeader(path); !header.ok()) return header.error();
    std::string extension = path.extension().string();
    for (char& c : extension) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    if (extension == ".obj") {
        std::ifstream text(path, std::ios::binary);
        if (!text) return makeError(name + ": cannot open");
        return loadObj(text, name, options);
    }

    Assimp::Importer importer;
    configure(importer);
    const aiScene* scene = importer.ReadFile(name, importFlags(options));
    return fromScene(scene, importer, name);
}

Result<TriangleMesh> loadMeshFromMemory(std::string_view bytes, const std::string& format,
                                        const std::string& source, MeshLoadOptions options) {
    if (bytes.empty()) return makeError(source + ": empty file");
    if (format == "obj") {
        std::istringstream text{std::string(bytes)};
        return loadObj(text, source, options);
    }
    Assimp::Importer importer;
    configure(importer);
    const aiScene* scene =
        importer.ReadFileFromMemory(bytes.data(), bytes.size(), importFlags(options), format.c_str());
    return fromScene(scene, importer, source);
}

}  // namespace plimsoll
