// libFuzzer target: Wavefront OBJ bytes through the mesh importer (loadMeshFromMemory, the
// same assimp path as loadMesh), then validateMesh on what it gives.
#include "plimsoll/mesh_io.h"
#include "plimsoll/validate.h"

#include <cstdint>
#include <cstdlib>
#include <string_view>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::string_view bytes(reinterpret_cast<const char*>(data), size);
    plimsoll::Result<plimsoll::TriangleMesh> mesh = plimsoll::loadMeshFromMemory(bytes, "obj", "fuzz.obj");
    if (!mesh) {
        if (mesh.error().message.empty()) std::abort();
        return 0;
    }
    // The importer's promise: every index names a vertex, and UVs are all or none.
    for (const plimsoll::Triangle& t : mesh->triangles)
        for (std::uint32_t v : t)
            if (v >= mesh->vertexCount()) std::abort();
    if (!mesh->uvs.empty() && mesh->uvs.size() != mesh->positions.size()) std::abort();
    (void)plimsoll::validateMesh(*mesh).format();
    return 0;
}
