// Baking a scene's bodies in memory (scene.h).
#include "plimsoll/scene/scene.h"
#include "plimsoll/scene/controlled_bake.h"

#include "plimsoll/surface/deform.h"

#include <algorithm>
#include <sstream>

namespace plimsoll {

const char* openingsModeName(OpeningsMode mode) {
    switch (mode) {
        case OpeningsMode::Open:
            return "open";
        case OpeningsMode::Sealed:
            return "sealed";
        case OpeningsMode::None:
            return "none";
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
                                              const std::string& label,
                                              const PaintedMap* shellThicknessMap) {
    return bodyMassProperties(textures, material, shellDensityMap, nullptr, MassProperties{}, label,
                              shellThicknessMap);
}

std::vector<double> wallShares(const TriangleMesh& mesh, const SurfaceTextures& textures,
                               const SurfacePieceTable& pieces,
                               const std::vector<std::uint32_t>& caps) {
    std::vector<char> isCap(mesh.triangles.size(), 0);
    for (std::uint32_t t : caps)
        if (t < isCap.size()) isCap[t] = 1;
    std::vector<double> share(textures.coveredCount(), 1.0);
    for (std::size_t i = 0; i < share.size() && i < pieces.entryCount(); ++i) {
        double cap = 0, all = 0;
        for (std::uint32_t p = pieces.firstPiece[i]; p < pieces.firstPiece[i + 1]; ++p) {
            const SurfacePiece& piece = pieces.pieces[p];
            const double area =
                piece.share * triangleAreaVector(mesh, mesh.triangles[piece.triangle]).norm();
            all += area;
            if (isCap[piece.triangle]) cap += area;
        }
        if (all > 0) share[i] = std::clamp(1.0 - cap / all, 0.0, 1.0);
    }
    return share;
}

Result<MassProperties> bodyMassProperties(const SurfaceTextures& textures,
                                          const MaterialDesc& material,
                                          const PaintedMap* shellDensityMap,
                                          const std::vector<double>* wallShare,
                                          const MassProperties& hollow, const std::string& label,
                                          const PaintedMap* shellThicknessMap) {
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
        // The relative thickness multiplies the painted (or uniform) surface density.
        if (shellThicknessMap) {
            const std::vector<double> thickness = sampleAtTexels(*shellThicknessMap, textures, 1.0);
            if (painted.empty()) painted.assign(thickness.size(), *material.shellSurfaceDensity);
            for (std::size_t i = 0; i < painted.size() && i < thickness.size(); ++i)
                painted[i] *= thickness[i];
        }
        // The caps are no material: the shell lies on the walls only.
        if (wallShare && wallShare->size() == textures.coveredCount()) {
            if (painted.empty())
                painted.assign(textures.coveredCount(), *material.shellSurfaceDensity);
            for (std::size_t i = 0; i < painted.size(); ++i) painted[i] *= (*wallShare)[i];
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
    if (material.density && hollow.mass > 0) {
        total = withoutHollow(total, hollow, *material.density);
        if (!(total.mass > 0))
            return makeError(
                ErrorKind::invalidArgument,
                label +
                    ": the space behind the caps of its openings is as large as the solid: no "
                    "material is left");
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
    // A shell on a body with caps needs to know which entries are cap: the bake's pieces say.
    SurfacePieceTable capPieces;
    const bool sharesNeeded = desc.material.shellSurfaceDensity && !parts.capTriangles.empty();
    SurfacePieceTable* recorded = pieces ? pieces.get() : sharesNeeded ? &capPieces : nullptr;
    std::shared_ptr<const SurfaceTextures> chosen;
    if (desc.tolerance) {
        Result<LevelChoice> choice =
            chooseLevelForTolerance(*parts.mesh, *desc.tolerance, settings);
        if (!choice) return withContext(body.label + ": tolerance: ", choice.error());
        desc.textureSize = settings.size = choice->size;
        // A bake that records its pieces (a deforming body, a shell with caps) is made again.
        if (!recorded) chosen = choice->textures;
        choice->textures.reset();
        body.levelChoice = std::move(*choice);
    }
    if (!chosen) {
        Result<SurfaceTextures> baked =
            bakeSurfaceTextures(*parts.mesh, settings, recorded, control.cancelled);
        if (!baked) return withContext(body.label + ": ", baked.error());
        chosen = std::make_shared<const SurfaceTextures>(std::move(*baked));
    }
    if (sharesNeeded)
        body.wallShare = std::make_shared<const std::vector<double>>(
            wallShares(*parts.mesh, *chosen, *recorded, parts.capTriangles));
    Result<MassProperties> mass = bodyMassProperties(
        *chosen, desc.material, parts.shellDensityMap.get(), body.wallShare.get(), parts.hollow,
        body.label, parts.shellThicknessMap.get());
    if (!mass) return mass.error();

    body.textures = std::move(chosen);
    body.pieces = std::move(pieces);
    body.mass = std::make_shared<const MassProperties>(*mass);
    body.desc = std::move(desc);
    body.parts = std::move(parts);
    Result<std::shared_ptr<const std::vector<BuoyancyLevel>>> levels =
        bakeBodyLevels(body, control.threads);
    if (!levels) return levels.error();
    body.levels = std::move(*levels);
    return body;
}

std::optional<std::vector<int>> bodyLadderSizes(const SceneBody& body, Status& status) {
    status = Ok{};
    const BodyDesc& desc = body.desc;
    // A deforming body's coarser levels would not deform with it, and a water graph's permeable
    // samples are those of textureSize: both keep their own level.
    if (!desc.lod || desc.deforms() || desc.waterGraph) return std::nullopt;
    Result<std::vector<int>> sizes = ladderSizes(desc.lod->levels, desc.textureSize);
    if (!sizes) {
        status = withContext(body.label + ": ", sizes.error());
        return std::nullopt;
    }
    if (sizes->size() < 2) return std::nullopt;
    return std::move(*sizes);
}

Result<std::shared_ptr<const std::vector<BuoyancyLevel>>> bakeBodyLevels(const SceneBody& body,
                                                                         unsigned threads) {
    Status status = Ok{};
    const std::optional<std::vector<int>> sizes = bodyLadderSizes(body, status);
    if (!status) return status.error();
    if (!sizes) return std::shared_ptr<const std::vector<BuoyancyLevel>>{};
    // About the body's own centre of mass; its mass properties stay those of textureSize.
    BakeSettings settings;
    settings.size = body.desc.textureSize;
    settings.maxTexelStretch = body.desc.maxTexelStretch;
    settings.threads = threads;
    Result<std::vector<BuoyancyLevel>> ladder =
        bakeLevelLadder(*body.parts.mesh, *sizes, body.desc.textureSize, body.textures, settings,
                        body.mass->centerOfMass);
    if (!ladder) return withContext(body.label + ": ", ladder.error());
    return std::make_shared<const std::vector<BuoyancyLevel>>(std::move(*ladder));
}

}  // namespace plimsoll
