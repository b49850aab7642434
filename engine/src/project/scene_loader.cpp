// A project on disk turned into a scene in memory (scene_loader.h).
#include "plimsoll/project/scene_loader.h"
#include "plimsoll/io/atlas_cache.h"
#include "plimsoll/io/painted_map_io.h"
#include "plimsoll/io/graph_json.h"

#include "plimsoll/bake/bake_cost.h"
#include "plimsoll/surface/deform.h"
#include "plimsoll/surface/painted_map.h"
#include "plimsoll/geometry/validate.h"
#include "plimsoll/io/mesh_io.h"
#include "plimsoll/project/level_cache.h"
#include "plimsoll/project/radiation_cache.h"
#include "plimsoll/repair/physics_solid.h"
#include "plimsoll/surface/map_transfer.h"

#include <optional>
#include <sstream>

namespace plimsoll {

std::string projectFileName(const Project& project) {
    return project.sourceName.empty() ? project.fileStem + ".plim.json" : project.sourceName;
}

namespace {

/// Texels per side of the permeability map made for the caps of a body that has none painted.
constexpr int kOpeningMapSize = 512;

/// One node per open cap (`open`: opening indices), for the space behind it: a box node (its
/// level follows the space's box) with the space's volume as capacity, empty. Named by the
/// opening's index, so that sealing one cap does not rename the others' nodes.
void appendOpeningNodes(WaterGraph& graph, const std::vector<Opening>& openings,
                        const std::vector<std::size_t>& open) {
    for (std::size_t i : open) {
        const Opening& opening = openings[i];
        GraphNode node;
        node.id = "opening-" + std::to_string(i + 1);
        while (graph.indexOf(node.id) >= 0) node.id += "'";
        node.name = "behind the cap of opening " + std::to_string(i + 1);
        node.position = 0.5 * (opening.boundsMin + opening.boundsMax);
        node.boxSize = opening.boundsMax - opening.boundsMin;
        node.capacity = opening.cavity.volume;
        graph.nodes.push_back(std::move(node));
    }
}

}  // namespace

Result<PreparedBodyMesh> prepareBodyMesh(const Project& project, std::size_t index) {
    if (index >= project.bodies.size()) {
        return makeError(ErrorKind::invalidArgument, "no body " + std::to_string(index));
    }
    const BodyDesc& desc = project.bodies[index];
    // A deforming body's frames are read without joining vertices (deform.h); its first frame
    // is read the same way, so that its triangles are theirs.
    Result<TriangleMesh> loaded = loadMesh(
        project.resolvePath(desc.mesh),
        MeshLoadOptions{.joinIdenticalVertices = !desc.deforms(), .unitScale = desc.unitScale});
    if (!loaded) return withContext(bodyLabel(desc) + ": ", loaded.error());
    return prepareLoadedBodyMesh(project, index, std::move(*loaded));
}

Result<PreparedBodyMesh> prepareLoadedBodyMesh(const Project& project, std::size_t index,
                                               TriangleMesh loaded, bool uvsChosen) {
    if (index >= project.bodies.size()) {
        return makeError(ErrorKind::invalidArgument, "no body " + std::to_string(index));
    }
    const BodyDesc& desc = project.bodies[index];
    const std::string label = bodyLabel(desc);
    ValidationReport report = validateMesh(loaded);
    PreparedBodyMesh prepared;
    // A rigid surface that is not one closed solid, or that holds water above (an open hull), is
    // baked as its physics solid; the artist's mesh is kept, for the maps painted over its UVs.
    if (!desc.deforms()) {
        RepairSettings settings;
        settings.closeOpenings = desc.openings != OpeningsMode::None;
        for (const CapDesc& cap : desc.caps) settings.capHeights.push_back(cap.height);
        Result<PhysicsSolid> solid = physicsSolidFor(loaded, report, settings);
        if (!solid) return withContext(label + ": ", solid.error());
        if (!solid->repairs.empty()) {
            prepared.repairs = std::move(solid->repairs);
            prepared.openings = std::move(solid->openings);
            prepared.artist = std::make_shared<const TriangleMesh>(std::move(loaded));
            loaded = std::move(solid->mesh);
            report = validateMesh(loaded);
        }
    }
    if (Status s = checkBakeableSurface(report, label); !s) return s.error();
    if (uvsChosen && prepared.repairs.empty()) {
        prepared.mesh = std::move(loaded);
        return prepared;
    }
    // Default settings, not the physics texture size: the atlas (and the maps painted over
    // it) must not change when the physics texture size does (BodyDesc::atlas).
    Result<AtlasChoice> atlas = chooseCachedAtlas(loaded, report, desc.atlas, AtlasSettings{},
                                                  project.atlasCacheFile(index));
    if (!atlas) return withContext(label + ": ", atlas.error());
    prepared.mesh = std::move(atlas->mesh);
    prepared.atlas = std::move(*atlas);
    prepared.atlas.mesh = {};
    return prepared;
}

Result<std::shared_ptr<const std::vector<TriangleMesh>>> loadBodyFrames(const Project& project,
                                                                        std::size_t index) {
    const BodyDesc& desc = project.bodies.at(index);
    // The frames keep the first frame's triangles and corner order, and so does a generated
    // atlas: the pieces baked on it regather from every frame unchanged.
    std::vector<std::filesystem::path> paths{project.resolvePath(desc.mesh)};
    for (const std::string& frame : desc.meshFrames) paths.push_back(project.resolvePath(frame));
    Result<std::vector<TriangleMesh>> frames = loadMeshFrames(paths);
    if (!frames) return withContext(bodyLabel(desc) + ": ", frames.error());
    return std::make_shared<const std::vector<TriangleMesh>>(std::move(*frames));
}

Result<BodyParts> assembleBodyParts(BodyDesc& desc, PreparedBodyMesh prepared,
                                    const BodyPaint& paint, const LogFunction& log) {
    const std::string label = bodyLabel(desc);
    const auto say = [&](const std::string& line) {
        if (log) log(line);
    };
    BodyParts parts;
    auto mesh = std::make_shared<const TriangleMesh>(std::move(prepared.mesh));
    parts.mesh = mesh;
    parts.generatedAtlas = prepared.atlas.generated;
    parts.atlasCharts = prepared.atlas.chartCount;
    // Maps painted over the artist's UVs, moved onto the physics solid through the surface.
    const TriangleMesh* paintedOver =
        paint.paintedOver ? paint.paintedOver.get() : prepared.artist.get();
    const bool moved = !prepared.repairs.empty();
    const auto onSolid = [&](const std::shared_ptr<const PaintedMap>& map,
                             std::shared_ptr<const PaintedMap>& into) -> Status {
        if (!map || !moved) {
            into = map;
            return Ok{};
        }
        if (!paintedOver || !paintedOver->hasUvs())
            return makeError(ErrorKind::schema,
                             label + ": a painted map needs the mesh's own UVs, and it has none");
        Result<PaintedMap> onto =
            transferPaintedMap(*map, *paintedOver, *mesh, map->width, map->height);
        if (!onto) return withContext(label + ": ", onto.error());
        into = std::make_shared<const PaintedMap>(std::move(*onto));
        return Ok{};
    };
    if (Status s = onSolid(paint.permeabilityMap, parts.permeabilityMap); !s) return s.error();
    if (Status s = onSolid(paint.shellDensityMap, parts.shellDensityMap); !s) return s.error();
    if (Status s = onSolid(paint.shellThicknessMap, parts.shellThicknessMap); !s) return s.error();

    // Sealed or open, the space behind a cap holds no material, and a cap is not wall.
    parts.hollow = hollowSpace(prepared.openings);
    std::vector<std::size_t> open;
    std::vector<std::uint32_t> openCaps, sealedCaps;  // their triangles
    for (std::size_t i = 0; i < prepared.openings.size(); ++i) {
        const std::vector<std::uint32_t>& cap = prepared.openings[i].capTriangles;
        parts.capTriangles.insert(parts.capTriangles.end(), cap.begin(), cap.end());
        const bool lets = desc.capMode(i) == OpeningsMode::Open;
        if (lets) open.push_back(i);
        std::vector<std::uint32_t>& into = lets ? openCaps : sealedCaps;
        into.insert(into.end(), cap.begin(), cap.end());
    }
    WaterGraph graph = paint.waterGraph ? *paint.waterGraph : WaterGraph{};
    if (!open.empty()) {
        appendOpeningNodes(graph, prepared.openings, open);
        if (!desc.waterGraph) {
            // An opening is an orifice, not a seeping surface: Torricelli's law, so a hull
            // pushed under fills in a moment as a real one does.
            desc.waterGraph.emplace();
            desc.waterGraph->settings.inflow = InflowModel::Torricelli;
        }
        // The caps let water in: permeability 1 over their triangles, on top of what is painted.
        PaintedMap permeability;
        if (parts.permeabilityMap) {
            permeability = *parts.permeabilityMap;
        } else {
            permeability.width = permeability.height = kOpeningMapSize;
            permeability.values.assign(static_cast<std::size_t>(kOpeningMapSize) * kOpeningMapSize,
                                       0.0f);
        }
        if (Status s = paintTriangles(permeability, *mesh, openCaps, 1.0f); !s)
            return withContext(label + ": ", s.error());
        parts.permeabilityMap = std::make_shared<const PaintedMap>(std::move(permeability));
        say(label + ": " + std::to_string(open.size()) + " of " +
            std::to_string(prepared.openings.size()) +
            (prepared.openings.size() == 1 ? " opening" : " openings") +
            " closed by caps that let water in: compartments of the water graph, empty at the "
            "start");
    }
    if (const std::size_t sealed = prepared.openings.size() - open.size(); sealed > 0) {
        if (parts.permeabilityMap) {
            // A sealed cap lets nothing in, whatever was painted near the rim it closes.
            PaintedMap permeability = *parts.permeabilityMap;
            if (Status s = paintTriangles(permeability, *mesh, sealedCaps, 0.0f); !s)
                return withContext(label + ": ", s.error());
            parts.permeabilityMap = std::make_shared<const PaintedMap>(std::move(permeability));
        }
        say(label + ": " + std::to_string(sealed) + (sealed == 1 ? " opening" : " openings") +
            " closed by sealed caps (decks): no water gets in");
    }
    if (desc.waterGraph) parts.waterGraph = std::make_shared<const WaterGraph>(std::move(graph));
    return parts;
}

Result<SceneBody> loadSceneBody(const Project& project, std::size_t index, const LogFunction& log,
                                const ProgressFactory& progress) {
    if (index >= project.bodies.size()) {
        return makeError(ErrorKind::invalidArgument, "no body " + std::to_string(index));
    }
    const BodyDesc& desc = project.bodies[index];
    const std::string label = bodyLabel(desc);
    const std::string at = projectFileName(project) + ": bodies[" + std::to_string(index) + "]";
    // The JSON path of the entry that failed, then the message (which names body and file); a
    // scene without a project file (simulate --mesh) has no JSON path to give.
    const auto fail = [&](const std::string& member, const Error& error) {
        if (!project.sourceName.empty()) return error;
        return withContext(at + member + ": ", error);
    };
    const auto say = [&](const std::string& line) {
        if (log) log(line);
    };

    Result<PreparedBodyMesh> prepared = prepareBodyMesh(project, index);
    if (!prepared) return fail(".mesh", prepared.error());
    if (!prepared->atlas.notice.empty()) say(label + ": " + prepared->atlas.notice);
    if (!prepared->repairs.empty())
        say(label +
            ": not one closed solid as it is, or an open hull: its physics solid is baked (" +
            describeRepairs(prepared->repairs) + ")");
    if (const std::string cost = describeBakeCost(prepared->mesh, desc.textureSize);
        !cost.empty() && !desc.tolerance)
        say(label + ": " + cost);
    BodyPaint paint;
    paint.paintedOver = prepared->artist;
    if (desc.waterGraph) {
        std::string warnings;
        Result<WaterGraph> graph =
            loadGraph(project.resolvePath(desc.waterGraph->graph), &prepared->mesh, &warnings);
        if (!graph) {
            return fail(".water_graph.graph",
                        withContext(label + ": water graph: ", graph.error()));
        }
        if (!warnings.empty()) say(warnings);
        paint.waterGraph = std::make_shared<const WaterGraph>(std::move(*graph));
    }
    const auto loadMap = [&](const std::string& path, const char* member,
                             std::shared_ptr<const PaintedMap>& into) -> Status {
        if (path.empty()) return Ok{};
        Result<PaintedMap> map = loadPaintedMap(project.resolvePath(path));
        if (!map) return fail(member, withContext(label + ": ", map.error()));
        into = std::make_shared<const PaintedMap>(std::move(*map));
        return Ok{};
    };
    if (Status s = loadMap(desc.permeabilityMap, ".permeability_map", paint.permeabilityMap); !s)
        return s.error();
    if (Status s = loadMap(desc.material.shellDensityMap, ".material.map", paint.shellDensityMap);
        !s)
        return s.error();
    if (Status s = loadMap(desc.material.shellThicknessMap, ".material.thickness_map",
                           paint.shellThicknessMap);
        !s)
        return s.error();

    BodyDesc bodyDesc = desc;
    Result<BodyParts> parts = assembleBodyParts(bodyDesc, std::move(*prepared), paint, log);
    if (!parts) return fail("", parts.error());
    if (desc.deforms()) {
        Result<std::shared_ptr<const std::vector<TriangleMesh>>> frames =
            loadBodyFrames(project, index);
        if (!frames) return fail(".mesh_frames", frames.error());
        parts->frames = std::move(*frames);
    }
    // The ladder comes through the project's cache (level_cache.h), not with the bake.
    std::optional<LodDesc> lod = std::move(bodyDesc.lod);
    bodyDesc.lod.reset();
    Result<SceneBody> body = bakeSceneBody(bodyDesc, std::move(*parts));
    if (!body) return fail("", body.error());
    body->desc.lod = std::move(lod);
    Result<std::shared_ptr<const std::vector<BuoyancyLevel>>> levels =
        cachedBodyLevels(*body, project.levelCacheFolder(index), log);
    if (!levels) return fail(".lod", levels.error());
    body->levels = std::move(*levels);
    if (body->levelChoice)
        say(label + ": its tolerance picks " + describeLevelChoice(*body->levelChoice));
    // Radiation: asked for ("radiation": {...}), it must apply; by default (no "radiation") it
    // applies to a rigid body that floats, and any other is told why it runs without.
    if (desc.radiates()) {
        const bool asked = desc.radiationRequired();
        std::optional<std::string> inapplicable =
            defaultRadiationInapplicable(*body, project.medium);
        if (!asked && inapplicable) {
            say(label + ": radiation off (" + *inapplicable + "); the stand-in damping applies");
        } else {
            Result<std::shared_ptr<const BodyRadiation>> radiation = cachedBodyRadiation(
                *body, desc.radiation.value_or(RadiationDesc{}), project.medium,
                project.simulation.gravity, project.radiationCacheFile(index), log,
                progress ? progress(label + ": radiation") : ProgressCallback{});
            if (!radiation && asked) return fail(".radiation", radiation.error());
            if (!radiation) {
                say(label + ": radiation off (" + radiation.error().message +
                    "); the stand-in damping applies (\"radiation\": false says so in the "
                    "project)");
            } else {
                body->radiation = std::move(*radiation);
            }
        }
    }
    return body;
}

Result<Scene> loadScene(const Project& project, const LogFunction& log,
                        const ProgressFactory& progress) {
    const std::string file = projectFileName(project);
    if (Status s = checkGravity(project.simulation.gravity); !s) {
        return withContext(file + ": simulation.gravity: ", s.error());
    }
    const double g = project.simulation.gravity.norm();
    if (project.water.kind == WaterModel::Kind::Gerstner && project.water.gravity != g) {
        std::ostringstream text;
        text << file << ": water.gravity: " << project.water.gravity
             << " m/s^2 is not the magnitude of simulation.gravity (" << g
             << " m/s^2): the waves move under the scene's one gravity; make them agree or "
                "leave water.gravity out";
        return makeError(ErrorKind::schema, text.str());
    }
    Scene scene;
    scene.name = project.name;
    scene.medium = project.medium;
    scene.water = project.water;
    scene.simulation = project.simulation;
    // Every body's problems, one after the other, not only the first body's.
    std::string problems;
    std::optional<ErrorKind> kind;  // the first body's failure's
    for (std::size_t i = 0; i < project.bodies.size(); ++i) {
        Result<SceneBody> body = loadSceneBody(project, i, log, progress);
        if (body) {
            scene.bodies.push_back(std::move(*body));
            continue;
        }
        if (!kind) kind = body.error().kind;
        problems += (problems.empty() ? "" : "\n") + body.error().message;
    }
    if (kind) return makeError(*kind, problems);
    return scene;
}

}  // namespace plimsoll
