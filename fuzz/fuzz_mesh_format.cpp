// libFuzzer target, one build per format (PLIMSOLL_FUZZ_FORMAT: obj, ply, stl, gltf, glb, fbx): the
// bytes through loadMeshFromMemory, the real import path (the checks before assimp, then
// assimp), then validateMesh on what it gives. From memory no referenced file is ever opened.
#include "plimsoll/geometry/validate.h"
#include "plimsoll/io/mesh_io.h"

#include <cstdint>
#include <cstdlib>
#include <string_view>

#ifndef PLIMSOLL_FUZZ_FORMAT
#error "PLIMSOLL_FUZZ_FORMAT names the format (fuzz/CMakeLists.txt)"
#endif

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::string_view bytes(reinterpret_cast<const char*>(data), size);
    plimsoll::Result<plimsoll::TriangleMesh> mesh =
        plimsoll::loadMeshFromMemory(bytes, PLIMSOLL_FUZZ_FORMAT, "fuzz." PLIMSOLL_FUZZ_FORMAT);
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
