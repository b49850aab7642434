// Preparing a project's body for baking (body_setup.h).
#include "plimsoll/body_setup.h"

#include "plimsoll/bake.h"
#include "plimsoll/mesh_io.h"
#include "plimsoll/painted_map.h"
#include "plimsoll/validate.h"

namespace plimsoll {

std::string bodyLabel(const BodyDesc& body) {
    return "body '" + body.name + "' (" + body.mesh + ")";
}

Result<PreparedBodyMesh> prepareBodyMesh(const Project& project, std::size_t index) {
    if (index >= project.bodies.size()) return makeError("no body " + std::to_string(index));
    const BodyDesc& desc = project.bodies[index];
    const std::string label = bodyLabel(desc);
    // A deforming body's frames are read without joining vertices (deform.h); its first frame
    // is read the same way, so that its triangles are theirs.
    Result<TriangleMesh> loaded = loadMesh(
        project.resolvePath(desc.mesh), MeshLoadOptions{.joinIdenticalVertices = !desc.deforms()});
    if (!loaded) return Error{label + ": " + loaded.error().message};
    const ValidationReport report = validateMesh(*loaded);
    ValidationReport surface = report;  // what no atlas can fix
    std::erase_if(surface.problems, [](const Problem& p) { return isUvProblem(p.kind); });
    if (surface.hasErrors()) return Error{label + ":\n" + surface.format()};
    // Default settings, not the physics texture size: the atlas (and the maps painted over
    // it) must not change when the physics texture size does (BodyDesc::atlas).
    Result<AtlasChoice> atlas = chooseAtlas(*loaded, report, desc.atlas, AtlasSettings{},
                                            project.atlasCacheFile(index));
    if (!atlas) return Error{label + ": " + atlas.error().message};
    PreparedBodyMesh prepared;
    prepared.mesh = std::move(atlas->mesh);
    prepared.atlas = std::move(*atlas);
    prepared.atlas.mesh = {};
    return prepared;
}

Result<MassProperties> bodyMaterialMass(const SurfaceTextures& textures,
                                        const MaterialDesc& material, const Project& project,
                                        const std::string& label) {
    MassProperties total;
    bool any = false;
    if (material.density) {
        total = textureSolidMassProperties(textures, *material.density);
        any = true;
    }
    if (material.shellSurfaceDensity) {
        std::vector<double> painted;
        if (!material.shellDensityMap.empty()) {
            Result<PaintedMap> map = loadPaintedMap(project.resolvePath(material.shellDensityMap));
            if (!map) return Error{label + ": " + map.error().message};
            painted = sampleAtTexels(*map, textures, *material.shellSurfaceDensity);
        }
        const MassProperties shell =
            textureShellMassProperties(textures, *material.shellSurfaceDensity, painted);
        total = any ? total + shell : shell;
        any = true;
    }
    if (!any || !(total.mass > 0) || !total.inertia.allFinite()) {
        return makeError(label + ": the material gives no positive mass");
    }
    return total;
}

}  // namespace plimsoll
