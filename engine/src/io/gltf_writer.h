// Internal glTF 2.0 writer for the bundle (docs/bundle.md, "glTF"): one mesh, one node, the
// bundle referenced from the node's `extras`. Written with nlohmann-json rather than assimp's
// exporter so that every byte is ours to fix (key order, number format, no generator version),
// which the bundle's byte-identical guarantee needs.
#pragma once

#include "plimsoll/geometry/mesh.h"
#include "plimsoll/geometry/uv_layout.h"

#include <nlohmann/json.hpp>

#include <string>

namespace plimsoll::detail {

/// A .gltf (JSON) and the .bin it names.
struct GltfFiles {
    std::string gltf;
    std::string bin;
};

/// Encodes `mesh` (with UVs) as glTF 2.0: float32 POSITION (with min/max), NORMAL (per stored
/// vertex, the area-weighted mean of its triangles' normals: vertices are split at UV seams,
/// so a seam stays a hard edge), TEXCOORD_0 = the texture uv the bake used
/// (placement.apply(uv)) in glTF's orientation (t = 1 - v: glTF's origin is the image's top
/// left, as row 0 of the bundle's images), uint32 indices, triangles. `binName` is the buffer's
/// uri; `extras` goes to the node; `nodeExtensions` (an object: extension name -> value, or
/// null) becomes the node's `extensions`, each name declared in `extensionsUsed`.
/// Deterministic: the same input gives the same bytes.
GltfFiles encodeGltf(const TriangleMesh& mesh, const UvPlacement& placement,
                     const std::string& binName, const std::string& nodeName,
                     const nlohmann::json& extras, const nlohmann::json& nodeExtensions = nullptr);

}  // namespace plimsoll::detail
