// The bundle's glTF 2.0 mesh read back by another decoder (assimp's glTF2 importer): the
// baked mesh's vertices, bounds and physics UVs, a volume equal to the exact one, and the
// node's extras pointing at the bundle's manifest.
#include "test_support.h"

#include "plimsoll/body_setup.h"
#include "plimsoll/bundle.h"
#include "plimsoll/massprops.h"
#include "plimsoll/uv_layout.h"

#include <assimp/Importer.hpp>
#include <assimp/scene.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

namespace plimsoll {
namespace {

namespace fs = std::filesystem;
using test::readFile;

const aiNode* nodeWithMesh(const aiNode* node) {
    if (node->mNumMeshes > 0) return node;
    for (unsigned i = 0; i < node->mNumChildren; ++i)
        if (const aiNode* found = nodeWithMesh(node->mChildren[i])) return found;
    return nullptr;
}

/// A number from assimp metadata, whatever integer or float type the importer chose.
double metaNumber(const aiMetadata& meta, const std::string& key) {
    for (unsigned i = 0; i < meta.mNumProperties; ++i) {
        if (std::string(meta.mKeys[i].C_Str()) != key) continue;
        const void* d = meta.mValues[i].mData;
        switch (meta.mValues[i].mType) {
            case AI_INT32: return *static_cast<const std::int32_t*>(d);
            case AI_UINT64: return static_cast<double>(*static_cast<const std::uint64_t*>(d));
            case AI_FLOAT: return *static_cast<const float*>(d);
            case AI_DOUBLE: return *static_cast<const double*>(d);
            default: break;
        }
    }
    ADD_FAILURE() << "no number '" << key << "' in the node's metadata";
    return -1;
}

TEST(ExportGltf, MeshReadsBackWithAssimpAsTheBakedMeshWithTheBundleInExtras) {
    for (const std::string stem : {"box_half_draft", "damaged_boat", "heavy_side_ball"}) {
        SCOPED_TRACE(stem);
        Result<Project> project = loadProject(fs::path(PLIMSOLL_SOURCE_DIR) / "projects" / (stem + ".plim.json"));
        ASSERT_TRUE(project.ok()) << project.error().message;
        const fs::path folder = test::scratchFolder("export_gltf") / stem;
        Result<BundleReport> report = writeBodyBundle(*project, 0, folder);
        ASSERT_TRUE(report.ok()) << report.error().message;
        const nlohmann::json manifest = nlohmann::json::parse(readFile(folder / "manifest.json"));
        const std::string gltfName = manifest.at("gltf");
        EXPECT_EQ(gltfName, bundleFolderName(*project, 0) + ".gltf");

        Result<PreparedBodyMesh> prepared = prepareBodyMesh(*project, 0);  // the baked mesh
        ASSERT_TRUE(prepared.ok()) << prepared.error().message;
        const TriangleMesh& mesh = prepared->mesh;
        const UvPlacement placement = fitUvsIntoUnitSquare(mesh);
        EXPECT_DOUBLE_EQ(manifest["uv_placement"]["scale"].get<double>(), placement.scale);

        Assimp::Importer importer;
        const aiScene* scene = importer.ReadFile((folder / gltfName).string(), 0);
        ASSERT_NE(scene, nullptr) << importer.GetErrorString();
        ASSERT_EQ(scene->mNumMeshes, 1u);
        const aiMesh& m = *scene->mMeshes[0];
        ASSERT_EQ(m.mNumVertices, mesh.vertexCount());
        ASSERT_EQ(m.mNumFaces, mesh.triangleCount());
        ASSERT_TRUE(m.HasNormals());
        ASSERT_TRUE(m.HasTextureCoords(0));

        // Bounds, vertex positions and UVs: the baked mesh's, to float precision.
        const Bounds3 bounds = computeBounds(mesh);
        Eigen::Vector3d lo = Eigen::Vector3d::Constant(1e300), hi = -lo;
        const double tolerance = 1e-6 * std::max(1.0, bounds.diagonal());
        for (unsigned v = 0; v < m.mNumVertices; ++v) {
            const Eigen::Vector3d p(m.mVertices[v].x, m.mVertices[v].y, m.mVertices[v].z);
            lo = lo.cwiseMin(p);
            hi = hi.cwiseMax(p);
            ASSERT_LT((p - mesh.positions[v]).norm(), tolerance) << v;
            const Eigen::Vector2d uv = placement.apply(mesh.uvs[v]);
            // assimp turns glTF's top-left origin back into v up.
            ASSERT_NEAR(m.mTextureCoords[0][v].x, uv.x(), 1e-6) << v;
            ASSERT_NEAR(m.mTextureCoords[0][v].y, uv.y(), 1e-6) << v;
            const Eigen::Vector3d n(m.mNormals[v].x, m.mNormals[v].y, m.mNormals[v].z);
            ASSERT_NEAR(n.norm(), 1.0, 1e-5) << v;
        }
        EXPECT_LT((lo - bounds.min).norm(), tolerance);
        EXPECT_LT((hi - bounds.max).norm(), tolerance);

        // The glTF mesh encloses the exact volume (divergence theorem over its triangles, in
        // double over the float32 vertices), with the same winding (outward normals).
        double volume = 0;
        for (unsigned f = 0; f < m.mNumFaces; ++f) {
            ASSERT_EQ(m.mFaces[f].mNumIndices, 3u);
            Eigen::Vector3d p[3];
            for (int k = 0; k < 3; ++k) {
                const unsigned i = m.mFaces[f].mIndices[k];
                ASSERT_EQ(i, mesh.triangles[f][k]);
                p[k] = Eigen::Vector3d(m.mVertices[i].x, m.mVertices[i].y, m.mVertices[i].z);
            }
            volume += p[0].dot(p[1].cross(p[2])) / 6.0;
        }
        const double exact = exactSolidMassProperties(mesh, 1.0).volume;
        EXPECT_NEAR(volume, exact, 1e-6 * exact);

        // The node's extras: the bundle's manifest (which exists beside it), version, body,
        // mass, texture size.
        const aiNode* node = nodeWithMesh(scene->mRootNode);
        ASSERT_NE(node, nullptr);
        ASSERT_NE(node->mMetaData, nullptr) << "no extras on the node";
        aiMetadata bundle;
        ASSERT_TRUE(node->mMetaData->Get("plimsoll_bundle", bundle)) << "no extras.plimsoll_bundle";
        aiString manifestPath, body;
        ASSERT_TRUE(bundle.Get("manifest", manifestPath));
        EXPECT_TRUE(fs::is_regular_file(folder / manifestPath.C_Str())) << manifestPath.C_Str();
        ASSERT_TRUE(bundle.Get("body", body));
        EXPECT_EQ(std::string(body.C_Str()), project->bodies[0].name);
        EXPECT_EQ(metaNumber(bundle, "schema_version"), kBundleSchemaMajor);
        EXPECT_EQ(metaNumber(bundle, "schema_minor"), kBundleSchemaMinor);
        EXPECT_EQ(metaNumber(bundle, "texture_size"), manifest["texture_size"].get<double>());
        EXPECT_DOUBLE_EQ(metaNumber(bundle, "mass"),
                         manifest["mass_properties"]["texture"]["mass"].get<double>());
    }
}

}  // namespace
}  // namespace plimsoll
