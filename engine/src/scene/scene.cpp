// Baking a scene's bodies in memory (scene.h).
#include "plimsoll/scene/scene.h"
#include "plimsoll/scene/controlled_bake.h"

#include "plimsoll/surface/deform.h"

#include <sstream>

namespace plimsoll {

const char* openingsModeName(OpeningsMode mode) {
    switch (mode) {
    case OpeningsMode::Open: return "open";
    case OpeningsMode::Sealed: return "sealed";
    case OpeningsMode::None: return "none";
    }
    return "open";
}

std::optional<OpeningsMode> parseOpeningsMode(std::string_view name) {
    for (OpeningsMode mode : {OpeningsMode::Open, OpeningsMode::Sealed, OpeningsMode::None})
        if (name == openingsModeName(mode)) return mode;
    return std::nullopt;
}

std::string bodyLabel(const BodyDesc& body) {
    return "body '" + body.name + "' (" + body.mesh + ")";
}

Status checkBakeableSurface(const ValidationReport& report, const std::string& label) {
    ValidationReport surface = report;
    std::erase_if(surface.problems, [](const Problem& p) { return isUvProblem(p.kind); });
    if (surface.hasErrors()) return makeError(ErrorKind::schema, label + ":\n" + surface.format());
    return Ok{};
}

Status checkGravity(const Eigen::Vector3d& g) {
    if (g.allFinite() && g.x() == 0 && g.z() == 0 && g.y() <= 0) return Ok{};
    std::ostringstream text;
    text << "gravity (" << g.x() << ", " << g.y() << ", " << g.z()
         << ") m/s^2 does not point straight down (-y): buoyancy takes the water surface as "
            "horizontal with y up, so only a gravity (0, -g, 0) can be simulated";
    return makeError(ErrorKind::unsupported, text.str());
}

Result<MassProperties> materialMassProperties(const SurfaceTextures& textures,
                                              const MaterialDesc& material,
                                              const PaintedMap* shellDensityMap,
                                              const std::string& label) {
    MassProperties total;
    bool any = false;
    if (material.density) {
        total = textureSolidMassProperties(textures, *material.density);
        any = true;
    }
    if (material.shellSurfaceDensity) {
        std::vector<double> painted;
        if (shellDensityMap) {
            painted = sampleAtTexels(*shellDensityMap, textures, *material.shellSurfaceDensity);
        }
        const MassProperties shell =
            textureShellMassProperties(textures, *material.shellSurfaceDensity, painted);
        total = any ? total + shell : shell;
        any = true;
    }
    if (!any || !(total.mass > 0) || !total.inertia.allFinite()) {
        return makeError(ErrorKind::invalidArgument,
                         label + ": the material gives no positive mass");
    }
    return total;
}

Result<SceneBody> bakeSceneBody(BodyDesc desc, BodyParts parts) {
    return bakeSceneBody(std::move(desc), std::move(parts), BakeControl{});
}

Result<SceneBody> bakeSceneBody(BodyDesc desc, BodyParts parts, const BakeControl& control) {
    SceneBody body;
    body.label = bodyLabel(desc);
    const auto refuse = [&](const std::string& what) {
        return makeError(ErrorKind::invalidArgument, body.label + ": " + what);
    };
    if (!parts.mesh) return refuse("no mesh");
    if (desc.deforms() != (parts.frames != nullptr)) {
        return refuse(desc.deforms() ? "mesh_frames named but no frames given"
                                     : "frames given to a body without mesh_frames");
    }
    if (parts.frames && parts.frames->size() != desc.meshFrames.size() + 1) {
        return refuse(std::to_string(parts.frames->size()) + " frames given for " +
                      std::to_string(desc.meshFrames.size() + 1) + " named");
    }
    if (desc.waterGraph && !parts.waterGraph) return refuse("water graph named but none given");

    BakeSettings settings;
    settings.size = desc.textureSize;
    settings.maxTexelStretch = desc.maxTexelStretch;
    settings.threads = control.threads;
    settings.progress = control.progress;
    auto pieces = desc.deforms() ? std::make_shared<SurfacePieceTable>() : nullptr;
    std::shared_ptr<const SurfaceTextures> chosen;
    if (desc.tolerance) {
        // The error is measured about the solid's own centroid: the force error, which the
        // tolerance bounds, does not depend on the point.
        Result<LevelChoice> choice =
            chooseLevelForTolerance(*parts.mesh, *desc.tolerance, settings,
                                    exactSolidMassProperties(*parts.mesh, 1.0).centerOfMass);
        if (!choice) return withContext(body.label + ": tolerance: ", choice.error());
        desc.textureSize = settings.size = choice->size;
        // A deforming body's bake records its pieces: bake the chosen size again for them.
        if (!pieces) chosen = choice->textures;
        choice->textures.reset();
        body.levelChoice = std::move(*choice);
    }
    if (!chosen) {
        Result<SurfaceTextures> baked =
            bakeSurfaceTextures(*parts.mesh, settings, pieces.get(), control.cancelled);
        if (!baked) return withContext(body.label + ": ", baked.error());
        chosen = std::make_shared<const SurfaceTextures>(std::move(*baked));
    }
    Result<MassProperties> mass =
        materialMassProperties(*chosen, desc.material, parts.shellDensityMap.get(), body.label);
    if (!mass) return mass.error();
    if (desc.material.density && parts.hollow.mass > 0) {
        *mass = withoutHollow(*mass, parts.hollow, *desc.material.density);
        if (!(mass->mass > 0))
            return refuse("the space behind the caps of its openings is as large as the solid: no material is left");
    }

    body.textures = std::move(chosen);
    // The level ladder, about the body's own centre of mass (its mass properties stay those of
    // textureSize). A deforming body's coarser levels would not deform with it, and a water
    // graph's permeable samples are those of textureSize: both keep their own level.
    if (desc.lod && !desc.deforms() && !desc.waterGraph) {
        Result<std::vector<int>> sizes = ladderSizes(desc.lod->levels, desc.textureSize);
        if (!sizes) return withContext(body.label + ": ", sizes.error());
        if (sizes->size() > 1) {
            Result<std::vector<BuoyancyLevel>> ladder = bakeLevelLadder(
                *parts.mesh, *sizes, desc.textureSize, body.textures, settings, mass->centerOfMass);
            if (!ladder) return withContext(body.label + ": ", ladder.error());
            body.levels = std::make_shared<const std::vector<BuoyancyLevel>>(std::move(*ladder));
        }
    }
    body.pieces = std::move(pieces);
    body.mass = std::make_shared<const MassProperties>(*mass);
    body.desc = std::move(desc);
    body.parts = std::move(parts);
    return body;
}

}  // namespace plimsoll
