#include "document/script.h"
#include "document/settings.h"

#include "document/command.h"
#include "document/graph_edit.h"
#include "document/material_presets.h"
#include "plimsoll/core/limits.h"
#include "plimsoll/graph_auto/graph_auto.h"
#include "plimsoll/io/graph_json.h"
#include "plimsoll/io/file_util.h"
#include "plimsoll/io/json_depth.h"

#include <cmath>
#include <fstream>
#include <iterator>

namespace plimsoll::editor {

namespace fs = std::filesystem;
using Json = nlohmann::json;

namespace {

/// A map value or brush strength: 0..1 (a fill of 7 or a strength of 1e308 was taken as it came).
double unitValue(const Json& j, const char* key, double fallback) {
    const double v = j.value(key, fallback);
    if (!(v >= 0.0 && v <= 1.0))
        throw std::invalid_argument(std::string(key) + " must be in 0..1, not " +
                                    jsonExcerpt(j.at(key)));
    return v;
}

Eigen::Vector3d vec3(const Json& j) {
    if (!j.is_array() || j.size() != 3) throw std::invalid_argument("expected [x, y, z]");
    return {j[0].get<double>(), j[1].get<double>(), j[2].get<double>()};
}

Eigen::Vector2d vec2(const Json& j) {
    if (!j.is_array() || j.size() != 2) throw std::invalid_argument("expected [u, v]");
    return {j[0].get<double>(), j[1].get<double>()};
}

/// Brush fields present in `j` override `brush`.
void readBrush(const Json& j, Brush& brush) {
    if (j.contains("mode")) {
        const std::string mode = j["mode"];
        if (mode == "paint")
            brush.mode = BrushMode::Paint;
        else if (mode == "erase")
            brush.mode = BrushMode::Erase;
        else if (mode == "smooth")
            brush.mode = BrushMode::Smooth;
        else
            throw std::invalid_argument("mode: paint, erase or smooth, not " + mode);
    }
    if (j.contains("falloff")) {
        const std::string f = j["falloff"];
        const std::optional<Falloff> falloff = parseFalloff(f);
        if (!falloff) {
            throw std::invalid_argument(
                "falloff: smooth, linear, constant, sphere, root, sharp, "
                "inverse-square or custom, not " +
                f);
        }
        brush.falloff = *falloff;
    }
    if (j.contains("curve")) {
        if (!j["curve"].is_array() || j["curve"].size() > kMaxFalloffPoints) {
            throw std::invalid_argument("curve: at most " + std::to_string(kMaxFalloffPoints) +
                                        " [distance / radius, weight] points");
        }
        brush.curve = readFalloffCurve(j["curve"]);
    }
    brush.radius = j.value("radius", brush.radius);
    brush.strength = unitValue(j, "strength", brush.strength);
    brush.value = unitValue(j, "value", brush.value);
    brush.spacing = j.value("spacing", brush.spacing);
    brush.mirrorX = j.value("mirror_x", brush.mirrorX);
    brush.mirrorY = j.value("mirror_y", brush.mirrorY);
    brush.mirrorZ = j.value("mirror_z", brush.mirrorZ);
    brush.radial = j.value("radial", brush.radial);
    if (!(brush.radius > 0) || !std::isfinite(brush.radius))
        throw std::invalid_argument("radius must be finite and > 0 (m)");
    if (!(brush.spacing > 0) || !std::isfinite(brush.spacing) || brush.spacing > 100)
        throw std::invalid_argument("spacing must be > 0 and at most 100 (radii)");
    if (brush.radial < 1 || brush.radial > kMaxRadialCopies)
        throw std::invalid_argument("radial must be 1.." + std::to_string(kMaxRadialCopies) +
                                    " copies");
}

MapChannel channelOf(const Json& j, MapChannel current) {
    if (!j.contains("channel")) return current;
    const std::string name = j["channel"];
    const std::optional<MapChannel> c = parseChannel(name);
    if (!c) throw std::invalid_argument("channel: permeability, density or thickness, not " + name);
    return *c;
}

/// The layer part a paint op changes: "layer" (index from the bottom) and "mask" (true: the
/// layer's mask). Absent: the map itself, or the top paint layer of a layered map.
PaintTarget targetOf(const Json& j) {
    PaintTarget target;
    target.layer = j.value("layer", -1);
    if (j.value("mask", false)) target.part = LayerPart::Mask;
    return target;
}

/// Layer ops ("layer_add", ...): their command, or nothing for another op.
std::optional<Result<std::unique_ptr<Command>>> layerCommand(Document& document, std::size_t body,
                                                             MapChannel channel,
                                                             const std::string& op, const Json& c) {
    if (op == "layer_add") {
        const std::string kindName = c.value("kind", std::string("paint"));
        const std::optional<LayerKind> kind = parseLayerKind(kindName);
        if (!kind) throw std::invalid_argument("kind: paint, fill or folder, not " + kindName);
        return makeAddLayerCommand(document, body, channel, *kind, c.value("name", std::string()),
                                   c.value("value", 1.0), c.value("index", -1));
    }
    if (op == "layer_remove") return makeRemoveLayerCommand(document, body, channel, c.at("layer"));
    if (op == "layer_move") {
        return makeMoveLayerCommand(document, body, channel, c.at("layer"), c.at("to"));
    }
    if (op == "layer_into_folder") {
        return makeMoveIntoFolderCommand(document, body, channel, c.at("layer"), c.at("folder"));
    }
    if (op == "layer_out_of_folder") {
        return makeMoveOutOfFolderCommand(document, body, channel, c.at("layer"));
    }
    if (op == "layer_set") {
        LayerEdit e;
        if (c.contains("name")) e.name = c["name"].get<std::string>();
        if (c.contains("opacity")) e.opacity = c["opacity"].get<double>();
        if (c.contains("visible")) e.visible = c["visible"].get<bool>();
        if (c.contains("value")) e.fillValue = c["value"].get<double>();
        if (c.contains("blend")) {
            const std::string name = c["blend"];
            e.blend = parseBlendMode(name);
            if (!e.blend) throw std::invalid_argument("blend: unknown mode " + name);
        }
        return makeSetLayerCommand(document, body, channel, c.at("layer"), e);
    }
    if (op == "layer_rename") {
        return makeRenameLayerCommand(document, body, channel, c.at("layer"),
                                      c.at("name").get<std::string>());
    }
    if (op == "mask_add") {
        return makeAddMaskCommand(document, body, channel, c.at("layer"), c.value("value", 1.0));
    }
    if (op == "mask_remove") return makeRemoveMaskCommand(document, body, channel, c.at("layer"));
    if (op == "smart_mask") {
        // The body at its starting pose against the project's still water.
        SmartMask mask;
        mask.pose = document.bodyPose(body);
        mask.waterLevel = document.project().water.level;
        const std::string kind = c.value("kind", std::string("below_waterline"));
        if (kind == "below_waterline")
            mask.kind = SmartMask::Kind::BelowWaterline;
        else if (kind == "depth")
            mask.kind = SmartMask::Kind::Depth;
        else if (kind == "facing")
            mask.kind = SmartMask::Kind::Facing;
        else if (kind == "curvature")
            mask.kind = SmartMask::Kind::Curvature;
        else if (kind == "cavity")
            mask.kind = SmartMask::Kind::Cavity;
        else
            throw std::invalid_argument(
                "kind: below_waterline, depth, facing, curvature or cavity, not " + kind);
        mask.depth = c.value("depth", 1.0);
        mask.radius = c.value("radius", mask.radius);
        mask.fullCurvature = c.value("full_curvature", mask.fullCurvature);
        if (c.contains("direction")) {
            const Json& d = c["direction"];
            mask.direction = Eigen::Vector3d(d.at(0), d.at(1), d.at(2));
            if (!(mask.direction.norm() > 0))
                throw std::invalid_argument("direction: not a direction");
        }
        return makeSmartMaskCommand(document, body, channel, c.at("layer"), mask);
    }
    return std::nullopt;
}

/// Object-space surface points of a stroke: "points", or "rays" hitting the mesh, or "uvs".
std::vector<Eigen::Vector3d> strokePoints(const Document& document, std::size_t body,
                                          const Json& j) {
    std::vector<Eigen::Vector3d> points;
    if (j.contains("points")) {
        for (const Json& p : j["points"]) points.push_back(vec3(p));
    }
    if (j.contains("point")) points.push_back(vec3(j["point"]));
    const auto& mesh = body < document.bodyCount() ? document.assets(body).mesh : nullptr;
    if (j.contains("rays")) {
        if (!mesh) throw std::invalid_argument("rays need the body's mesh");
        for (const Json& ray : j["rays"]) {
            const auto hit = raycast(*mesh, vec3(ray.at("origin")), vec3(ray.at("direction")));
            if (hit) points.push_back(hit->point);
        }
    }
    if (j.contains("uvs")) {
        if (!mesh) throw std::invalid_argument("uvs need the body's mesh");
        for (const Json& uv : j["uvs"]) {
            if (const auto hit = surfaceAtUv(*mesh, vec2(uv))) points.push_back(hit->point);
        }
    }
    return points;
}

std::vector<std::string> nodeIds(const Json& j) {
    std::vector<std::string> ids;
    const Json& list = j.contains("nodes") ? j["nodes"] : j.at("node");
    if (list.is_string())
        ids.push_back(list.get<std::string>());
    else
        for (const Json& id : list) ids.push_back(id.get<std::string>());
    return ids;
}

NodeEdit readNodeEdit(const Json& j) {
    NodeEdit e;
    if (j.contains("name")) e.name = j["name"].get<std::string>();
    if (j.contains("position")) e.position = vec3(j["position"]);
    if (j.contains("capacity")) e.capacity = j["capacity"].get<double>();
    if (j.contains("water")) e.water = j["water"].get<double>();
    if (j.contains("sealed")) e.sealed = j["sealed"].get<bool>();
    if (j.contains("box")) e.boxSize = vec3(j["box"]);
    return e;
}

PipeEdit readPipeEdit(const Json& j) {
    PipeEdit e;
    if (j.contains("open")) e.open = j["open"].get<bool>();
    if (j.contains("radius")) e.radius = j["radius"].get<double>();
    if (j.contains("length")) e.length = j["length"].get<double>();
    return e;
}

/// The water-graph ops (graph_*); nullopt when `op` is not one of them.
std::optional<Result<std::unique_ptr<Command>>> graphCommand(Document& document, std::size_t body,
                                                             const std::string& op, const Json& c) {
    if (op == "graph_create") {
        return makeCreateGraphCommand(document, body, c.value("path", std::string()));
    }
    if (op == "graph_add_node") {
        GraphNode n;
        n.id = c.value("id", std::string());
        const NodeEdit e = readNodeEdit(c);
        n.name = e.name.value_or("");
        n.position = e.position.value_or(Eigen::Vector3d::Zero());
        n.capacity = e.capacity.value_or(0.0);
        n.water = e.water.value_or(0.0);
        n.sealed = e.sealed.value_or(false);
        n.boxSize = e.boxSize.value_or(Eigen::Vector3d::Zero());
        return makeAddNodeCommand(document, body, std::move(n));
    }
    if (op == "graph_duplicate") {
        return makeDuplicateNodesCommand(
            document, body, nodeIds(c),
            c.contains("offset") ? vec3(c["offset"]) : Eigen::Vector3d::Zero());
    }
    if (op == "graph_delete") return makeDeleteNodesCommand(document, body, nodeIds(c));
    if (op == "graph_move")
        return makeMoveNodesCommand(document, body, nodeIds(c), vec3(c.at("offset")));
    if (op == "graph_set_node") {
        return makeSetNodesCommand(document, body, nodeIds(c), readNodeEdit(c));
    }
    if (op == "graph_connect") {
        GraphPipe p;
        p.a = c.at("a").get<std::string>();
        p.b = c.at("b").get<std::string>();
        const PipeEdit e = readPipeEdit(c);
        p.radius = e.radius.value_or(p.radius);
        p.length = e.length.value_or(p.length);
        p.open = e.open.value_or(true);
        return makeAddPipeCommand(document, body, std::move(p));
    }
    if (op == "graph_disconnect")
        return makeRemovePipeCommand(document, body, c.at("a"), c.at("b"));
    if (op == "graph_set_pipe" || op == "graph_open" || op == "graph_close") {
        PipeEdit e = readPipeEdit(c);
        if (op != "graph_set_pipe") e.open = op == "graph_open";
        return makeSetPipeCommand(document, body, c.at("a"), c.at("b"), e);
    }
    if (op == "graph_replace") {
        Result<WaterGraph> graph =
            makeError(ErrorKind::schema, "graph_replace needs \"graph\" or \"path\"");
        if (c.contains("graph")) {
            graph = parseGraph(c["graph"].dump(), "graph_replace");
        } else if (c.contains("path")) {
            fs::path file = c["path"].get<std::string>();
            if (file.is_relative()) file = document.project().folder / file;
            Result<std::string> text = readWholeFile(file, kMaxJsonFileBytes, "kMaxJsonFileBytes");
            if (!text) return text.error();
            graph = parseGraph(*text, file.string());
        }
        if (!graph) return graph.error();
        return makeReplaceGraphCommand(document, body, std::move(graph).value());
    }
    if (op == "graph_auto") {
        if (body >= document.bodyCount() || !document.assets(body).mesh) {
            return makeError(ErrorKind::schema, "graph_auto needs the body's mesh");
        }
        AutoGraphSettings settings;
        settings.segments = c.value("segments", 0);
        settings.shellThickness = c.value("shell_thickness", 0.0);
        Result<WaterGraph> graph = buildAutomaticGraph(*document.assets(body).mesh, settings);
        if (!graph) return graph.error();
        return makeReplaceGraphCommand(document, body, std::move(graph).value(),
                                       "Auto-generate water graph");
    }
    return std::nullopt;
}

}  // namespace

Result<Json> runEditScript(Document& document, const Json& script) {
    const Json* list = &script;
    if (script.is_object() && script.contains("commands")) list = &script["commands"];
    if (!list->is_array())
        return makeError(ErrorKind::schema, "script: expected a list of commands");
    Json results = Json::array();
    Brush brush;
    MapChannel channel = MapChannel::Permeability;
    std::size_t body = 0;
    for (std::size_t i = 0; i < list->size(); ++i) {
        const Json& c = (*list)[i];
        const std::string where = "command " + std::to_string(i);
        try {
            const std::string op = c.at("op");
            body = c.value("body", body);
            channel = channelOf(c, channel);
            Json result = {{"op", op}};
            Result<std::unique_ptr<Command>> command = makeError(ErrorKind::schema, "");
            bool runs = true;
            if (op == "brush") {
                readBrush(c, brush);
                runs = false;
            } else if (op == "stroke" || op == "paint" || op == "erase" || op == "smooth") {
                Brush b = brush;
                if (op != "stroke")
                    b.mode = op == "paint"   ? BrushMode::Paint
                             : op == "erase" ? BrushMode::Erase
                                             : BrushMode::Smooth;
                readBrush(c, b);
                const std::vector<Eigen::Vector3d> points = strokePoints(document, body, c);
                if (points.empty())
                    return makeError(ErrorKind::schema, where + ": the stroke hits no surface");
                command = makeStrokeCommand(document, body, channel, b, points, targetOf(c));
            } else if (op == "fill_island") {
                const std::vector<Eigen::Vector3d> points = strokePoints(document, body, c);
                if (points.empty())
                    return makeError(ErrorKind::schema, where + ": no surface point");
                command = makeFillIslandCommand(
                    document, body, channel, points.front(), unitValue(c, "value", brush.value),
                    c.value("mirror_x", brush.mirrorX), unitValue(c, "strength", 1.0), targetOf(c));
            } else if (op == "fill_all") {
                command =
                    makeFillAllCommand(document, body, channel, unitValue(c, "value", brush.value),
                                       unitValue(c, "strength", 1.0), targetOf(c));
            } else if (op == "new_map") {
                int w = kDefaultMapSize, h = kDefaultMapSize;
                if (c.contains("size")) {
                    if (c["size"].is_array()) {
                        w = c["size"].at(0);
                        h = c["size"].at(1);
                    } else {
                        w = h = c["size"].get<int>();
                    }
                }
                if (w < 1 || h < 1 || w > kMaxPaintedMapSide || h > kMaxPaintedMapSide)
                    return makeError(ErrorKind::limit, where + ": size " + std::to_string(w) +
                                                           " x " + std::to_string(h) +
                                                           " is outside 1..kMaxPaintedMapSide = " +
                                                           std::to_string(kMaxPaintedMapSide) +
                                                           " (limits.h)");
                command =
                    makeNewMapCommand(document, body, channel, w, h, unitValue(c, "value", 0.0),
                                      c.value("path", std::string()));
            } else if (op == "resize_map") {
                const Json& size = c.at("size");
                const int w = size.is_array() ? size.at(0).get<int>() : size.get<int>();
                const int h = size.is_array() ? size.at(1).get<int>() : size.get<int>();
                command = makeResizeMapCommand(document, body, channel, w, h);
            } else if (op == "set") {
                command = makeSetPropertyCommand(document, c.at("pointer"), c.at("value"));
            } else if (op == "apply_material_preset") {
                const std::string name = c.at("preset");
                const MaterialPreset* preset = findMaterialPreset(name);
                if (!preset) {
                    std::string known;
                    for (const MaterialPreset& p : materialPresets()) {
                        known += (known.empty() ? "" : ", ") + std::string(p.key);
                    }
                    throw std::invalid_argument("preset: " + known + ", not " + name);
                }
                command = makeApplyMaterialPresetCommand(document, body, *preset);
            } else if (op == "import_mesh") {
                std::optional<std::size_t> target;
                if (c.contains("body")) target = c["body"].get<std::size_t>();
                fs::path mesh = c.at("path").get<std::string>();
                if (mesh.is_relative()) mesh = document.project().folder / mesh;
                command = makeImportMeshCommand(document, mesh, target);
            } else if (auto graphEdit = graphCommand(document, body, op, c)) {
                command = std::move(*graphEdit);
            } else if (auto layerEdit = layerCommand(document, body, channel, op, c)) {
                command = std::move(*layerEdit);
            } else if (op == "pick") {
                const std::vector<Eigen::Vector3d> points = strokePoints(document, body, c);
                const PaintedMap* map = document.map(body, channel);
                auto surface = document.paintSurface(body, channel);
                if (points.empty() || !map || !surface) {
                    return makeError(ErrorKind::schema,
                                     where + ": nothing to pick (no point or no map)");
                }
                const std::optional<double> v = pickValue(*map, **surface, points.front());
                if (!v) return makeError(ErrorKind::schema, where + ": nothing to pick");
                brush.value = *v;
                result["value"] = *v;
                runs = false;
            } else if (op == "undo") {
                result["done"] = document.undo();
                runs = false;
            } else if (op == "redo") {
                result["done"] = document.redo();
                runs = false;
            } else if (op == "save") {
                if (Status s = document.save(); !s) return withContext(where + ": ", s.error());
                runs = false;
            } else if (op == "save_as") {
                fs::path target = c.at("path").get<std::string>();
                if (Status s = document.saveAs(target, c.value("force", false)); !s) {
                    return withContext(where + ": ", s.error());
                }
                runs = false;
            } else if (op == "autosave") {
                if (Status s = document.autosave(); !s) {
                    return withContext(where + ": ", s.error());
                }
                runs = false;
            } else {
                return makeError(ErrorKind::schema,
                                 where + ": unknown op \"" + boundedExcerpt(op) + "\"");
            }
            if (runs) {
                if (!command) return withContext(where + " (" + op + "): ", command.error());
                if (auto* paint = dynamic_cast<PaintCommand*>(command->get())) {
                    result["pixels_changed"] = paint->pixelsChanged();
                }
                result["name"] = (*command)->name();
                if (auto* graph = dynamic_cast<GraphCommand*>(command->get());
                    graph && op == "graph_add_node" && graph->after()) {
                    result["id"] = graph->after()->nodes.back().id;
                }
                if (Status s = document.execute(std::move(command).value()); !s) {
                    return withContext(where + " (" + op + "): ", s.error());
                }
            }
            results.push_back(std::move(result));
        } catch (const std::exception& e) {
            return makeError(ErrorKind::schema, where + ": " + boundedExcerpt(e.what(), 200));
        }
    }
    return results;
}

}  // namespace plimsoll::editor
