// The bundle's glTF 2.0 mesh read back by another decoder (assimp's glTF2 importer): the
// baked mesh's vertices, bounds and physics UVs, a volume equal to the exact one, and the
// node's extras pointing at the bundle's manifest.
#include "test_support.h"

#include "plimsoll/project/scene_loader.h"
#include "plimsoll/export/bundle.h"
#include "plimsoll/physics/massprops.h"
#include "plimsoll/geometry/uv_layout.h"

#include "io/gltf_physics.h"

#include <assimp/Importer.hpp>
#include <assimp/scene.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <Eigen/Geometry>

#include <algorithm>

namespace plimsoll {
namespace test_export_gltf {
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
            case AI_INT32:
                return *static_cast<const std::int32_t*>(d);
            case AI_UINT64:
                return static_cast<double>(*static_cast<const std::uint64_t*>(d));
            case AI_FLOAT:
                return *static_cast<const float*>(d);
            case AI_DOUBLE:
                return *static_cast<const double*>(d);
            default:
                break;
        }
    }
    ADD_FAILURE() << "no number '" << key << "' in the node's metadata";
    return -1;
}

TEST(ExportGltf, MeshReadsBackWithAssimpAsTheBakedMeshWithTheBundleInExtras) {
    for (const std::string stem : {"box_half_draft", "damaged_boat", "heavy_side_ball"}) {
        SCOPED_TRACE(stem);
        Result<Project> project =
            loadProject(fs::path(PLIMSOLL_SOURCE_DIR) / "projects" / (stem + ".plim.json"));
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

Eigen::Vector3d vec3(const nlohmann::json& a) {
    return {a.at(0).get<double>(), a.at(1).get<double>(), a.at(2).get<double>()};
}

Eigen::Matrix3d matrix3(const nlohmann::json& rows) {
    Eigen::Matrix3d m;
    for (int r = 0; r < 3; ++r) m.row(r) = vec3(rows.at(r)).transpose();
    return m;
}

/// R diag(moments) R^T from a glTF motion object (quaternion in glTF's [x, y, z, w] order).
Eigen::Matrix3d inertiaOf(const nlohmann::json& motion) {
    const nlohmann::json& q = motion.at("inertiaOrientation");
    EXPECT_EQ(q.size(), 4u);
    const Eigen::Quaterniond rotation(q.at(3).get<double>(), q.at(0).get<double>(),
                                      q.at(1).get<double>(), q.at(2).get<double>());
    EXPECT_NEAR(rotation.norm(), 1.0, 1e-12);
    const Eigen::Matrix3d r = rotation.normalized().toRotationMatrix();
    const Eigen::Vector3d moments = vec3(motion.at("inertiaDiagonal"));
    for (int k = 0; k < 3; ++k) EXPECT_GE(moments[k], 0.0);
    return r * moments.asDiagonal() * r.transpose();
}

// A box's tensor turned by a known rotation: the principal moments come back (ascending), the
// rotation is proper and rebuilds the tensor; a sphere's (three equal moments, any axes) too.
TEST(GltfPhysics, PrincipalInertiaRebuildsTheTensorWithAProperRotation) {
    const double m = 12.0, a = 1.0, b = 2.0, c = 3.0;  // box of sides a, b, c
    const Eigen::Vector3d box(m * (b * b + c * c) / 12, m * (a * a + c * c) / 12,
                              m * (a * a + b * b) / 12);
    const Eigen::Matrix3d turn = (Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, 3).normalized()) *
                                  Eigen::AngleAxisd(-1.9, Eigen::Vector3d::UnitY()))
                                     .toRotationMatrix();
    const Eigen::Matrix3d sphere = Eigen::Matrix3d::Identity() * (0.4 * m * 0.25);
    for (const Eigen::Matrix3d& tensor :
         {Eigen::Matrix3d(turn * box.asDiagonal() * turn.transpose()), sphere,
          Eigen::Matrix3d(box.asDiagonal())}) {
        const detail::PrincipalInertia p = detail::principalInertia(tensor);
        const Eigen::Matrix3d r = p.orientation.toRotationMatrix();
        EXPECT_NEAR(r.determinant(), 1.0, 1e-12);
        EXPECT_GE(p.orientation.w(), 0.0);
        EXPECT_LT((r * p.moments.asDiagonal() * r.transpose() - tensor).norm(),
                  1e-12 * tensor.norm());
        std::vector<double> expected{tensor.trace() / 3, tensor.trace() / 3, tensor.trace() / 3};
        if (tensor != sphere) expected = {box.x(), box.y(), box.z()};
        std::sort(expected.begin(), expected.end());
        for (int k = 0; k < 3; ++k) EXPECT_NEAR(p.moments[k], expected[k], 1e-12 * tensor.norm());
    }
    const nlohmann::json q = detail::gltfQuaternion(Eigen::Quaterniond(0.5, 0.1, 0.2, 0.3));
    EXPECT_EQ(q, nlohmann::json::array({0.1, 0.2, 0.3, 0.5}));  // glTF order: x, y, z, w
}

// The exported glTF read back as JSON: KHR_physics_rigid_bodies and OMI_physics_body carry
// the manifest's exact mass, centre of mass and inertia (R diag(I) R^T = the tensor), or the
// texture ones for the buoy's painted shell, which has no exact ones; all three extensions
// are declared, and PLIMSOLL_buoyancy_bundle names files that exist and that the manifest
// lists.
TEST(GltfPhysics, ExportedGltfCarriesTheManifestsExactMassProperties) {
    for (const std::string stem : {"box_half_draft", "damaged_boat", "buoy"}) {
        SCOPED_TRACE(stem);
        Result<Project> project =
            loadProject(fs::path(PLIMSOLL_SOURCE_DIR) / "projects" / (stem + ".plim.json"));
        ASSERT_TRUE(project.ok()) << project.error().message;
        const fs::path folder = test::scratchFolder("gltf_physics") / stem;
        Result<BundleReport> report = writeBodyBundle(*project, 0, folder);
        ASSERT_TRUE(report.ok()) << report.error().message;
        const nlohmann::json manifest = nlohmann::json::parse(readFile(folder / "manifest.json"));
        const nlohmann::json gltf =
            nlohmann::json::parse(readFile(folder / manifest.at("gltf").get<std::string>()));
        const bool hasExact = manifest.at("mass_properties").at("exact").is_object();
        EXPECT_EQ(hasExact, stem != "buoy");
        const std::string source = hasExact ? "exact" : "texture";
        const nlohmann::json& exact = manifest.at("mass_properties").at(source);

        const std::vector<std::string> used = gltf.at("extensionsUsed");
        for (const char* name :
             {"KHR_physics_rigid_bodies", "OMI_physics_body", "PLIMSOLL_buoyancy_bundle"})
            EXPECT_NE(std::find(used.begin(), used.end(), name), used.end()) << name;
        EXPECT_FALSE(gltf.contains("extensionsRequired"));  // a plain glTF reader still loads it

        const nlohmann::json& extensions = gltf.at("nodes").at(0).at("extensions");
        const Eigen::Matrix3d tensor = matrix3(exact.at("inertia"));
        for (const char* name : {"KHR_physics_rigid_bodies", "OMI_physics_body"}) {
            SCOPED_TRACE(name);
            const nlohmann::json& motion = extensions.at(name).at("motion");
            EXPECT_EQ(motion.at("mass").get<double>(), exact.at("mass").get<double>());
            EXPECT_EQ(vec3(motion.at("centerOfMass")), vec3(exact.at("center_of_mass")));
            EXPECT_LT((inertiaOf(motion) - tensor).norm(), 1e-12 * tensor.norm());
        }
        EXPECT_EQ(extensions["OMI_physics_body"]["motion"]["type"], "dynamic");
        EXPECT_FALSE(extensions["KHR_physics_rigid_bodies"]["motion"].value("isKinematic", false));

        const nlohmann::json& bundle = extensions.at("PLIMSOLL_buoyancy_bundle");
        EXPECT_EQ(bundle.at("manifest"), "manifest.json");
        EXPECT_EQ(bundle.at("body"), manifest.at("body"));
        EXPECT_EQ(bundle.at("schema_minor"), kBundleSchemaMinor);
        EXPECT_EQ(bundle.at("mass_properties"), source);
        std::vector<std::string> listed;
        for (const auto& f : manifest.at("files")) listed.push_back(f.at("path"));
        ASSERT_FALSE(bundle.at("files").empty());
        for (const std::string file : bundle.at("files")) {
            EXPECT_TRUE(fs::is_regular_file(folder / file)) << file;
            EXPECT_NE(std::find(listed.begin(), listed.end(), file), listed.end()) << file;
        }
    }
}

}  // namespace
}  // namespace test_export_gltf
}  // namespace plimsoll
