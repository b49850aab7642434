// glTF 2.0 writer (gltf_writer.h). Spec: https://registry.khronos.org/glTF/specs/2.0/glTF-2.0.html
#include "io/gltf_writer.h"

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <limits>
#include <vector>

namespace plimsoll::detail {

using nlohmann::json;

namespace {

constexpr int kFloat = 5126;           // accessor componentType FLOAT
constexpr int kUnsignedInt = 5125;     // UNSIGNED_INT
constexpr int kArrayBuffer = 34962;    // bufferView target: vertex attributes
constexpr int kElementBuffer = 34963;  // indices
constexpr int kTriangles = 4;

template <typename T>
void append(std::string& bytes, const std::vector<T>& values) {
    const std::size_t at = bytes.size();
    bytes.resize(at + values.size() * sizeof(T));
    if (!values.empty()) std::memcpy(bytes.data() + at, values.data(), values.size() * sizeof(T));
}

}  // namespace

GltfFiles encodeGltf(const TriangleMesh& mesh, const UvPlacement& placement,
                     const std::string& binName, const std::string& nodeName, const json& extras,
                     const json& nodeExtensions) {
    const std::size_t n = mesh.vertexCount();
    std::vector<float> positions, normals, texcoords;
    std::vector<std::uint32_t> indices;
    positions.reserve(3 * n);
    normals.reserve(3 * n);
    texcoords.reserve(2 * n);
    indices.reserve(3 * mesh.triangleCount());

    std::vector<Eigen::Vector3d> normalSum(n, Eigen::Vector3d::Zero());
    for (const Triangle& t : mesh.triangles) {
        const Eigen::Vector3d a = triangleAreaVector(mesh, t);  // area-weighted by its length
        for (std::uint32_t v : t) normalSum[v] += a;
        indices.insert(indices.end(), t.begin(), t.end());
    }
    float lo[3], hi[3];
    std::fill(lo, lo + 3, std::numeric_limits<float>::infinity());
    std::fill(hi, hi + 3, -std::numeric_limits<float>::infinity());
    for (std::size_t v = 0; v < n; ++v) {
        for (int k = 0; k < 3; ++k) {
            const float p = static_cast<float>(mesh.positions[v][k]);
            positions.push_back(p);
            lo[k] = std::min(lo[k], p);
            hi[k] = std::max(hi[k], p);
        }
        const double length = normalSum[v].norm();
        // A vertex only on degenerate triangles has no normal; glTF requires unit length.
        const Eigen::Vector3d normal =
            length > 0 ? Eigen::Vector3d(normalSum[v] / length) : Eigen::Vector3d::UnitY();
        for (int k = 0; k < 3; ++k) normals.push_back(static_cast<float>(normal[k]));
        const Eigen::Vector2d uv =
            mesh.hasUvs() ? placement.apply(mesh.uvs[v]) : Eigen::Vector2d::Zero();
        texcoords.push_back(static_cast<float>(uv.x()));
        texcoords.push_back(static_cast<float>(1.0 - uv.y()));
    }
    if (n == 0) std::fill(lo, lo + 3, 0.0f), std::fill(hi, hi + 3, 0.0f);

    GltfFiles files;
    json views = json::array(), accessors = json::array();
    auto addView = [&](std::size_t offset, std::size_t length, int target) {
        views.push_back(
            {{"buffer", 0}, {"byteOffset", offset}, {"byteLength", length}, {"target", target}});
        return views.size() - 1;
    };
    // Every block is a whole number of 4-byte values, so each view starts 4-byte aligned.
    std::size_t offset = files.bin.size();
    append(files.bin, positions);
    accessors.push_back({{"bufferView", addView(offset, files.bin.size() - offset, kArrayBuffer)},
                         {"componentType", kFloat},
                         {"count", n},
                         {"type", "VEC3"},
                         {"min", {lo[0], lo[1], lo[2]}},
                         {"max", {hi[0], hi[1], hi[2]}}});
    offset = files.bin.size();
    append(files.bin, normals);
    accessors.push_back({{"bufferView", addView(offset, files.bin.size() - offset, kArrayBuffer)},
                         {"componentType", kFloat},
                         {"count", n},
                         {"type", "VEC3"}});
    offset = files.bin.size();
    append(files.bin, texcoords);
    accessors.push_back({{"bufferView", addView(offset, files.bin.size() - offset, kArrayBuffer)},
                         {"componentType", kFloat},
                         {"count", n},
                         {"type", "VEC2"}});
    offset = files.bin.size();
    append(files.bin, indices);
    accessors.push_back({{"bufferView", addView(offset, files.bin.size() - offset, kElementBuffer)},
                         {"componentType", kUnsignedInt},
                         {"count", indices.size()},
                         {"type", "SCALAR"}});

    json node = {{"name", nodeName}, {"mesh", 0}};
    if (!extras.is_null()) node["extras"] = extras;
    json gltf = {
        {"asset", {{"version", "2.0"}, {"generator", "plimsoll"}}},
        {"scene", 0},
        {"scenes", json::array({{{"nodes", json::array({0})}}})},
        {"nodes", json::array({node})},
        {"meshes",
         json::array(
             {{{"name", nodeName},
               {"primitives",
                json::array({{{"attributes", {{"POSITION", 0}, {"NORMAL", 1}, {"TEXCOORD_0", 2}}},
                              {"indices", 3},
                              {"mode", kTriangles}}})}}})},
        {"accessors", accessors},
        {"bufferViews", views},
        {"buffers", json::array({{{"uri", binName}, {"byteLength", files.bin.size()}}})}};
    if (!nodeExtensions.is_null() && !nodeExtensions.empty()) {
        gltf["nodes"][0]["extensions"] = nodeExtensions;
        json used = json::array();
        for (const auto& [name, value] : nodeExtensions.items()) used.push_back(name);
        // Only declared, never required: a reader without them still gets the whole mesh.
        gltf["extensionsUsed"] = used;
    }
    files.gltf = gltf.dump(1) + "\n";
    return files;
}

}  // namespace plimsoll::detail
