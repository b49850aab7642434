#include "document/command.h"

#include "plimsoll/core/limits.h"
#include "plimsoll/io/json_depth.h"
#include "plimsoll/io/mesh_io.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <set>

namespace plimsoll::editor {

namespace fs = std::filesystem;
using Json = nlohmann::json;

PaintCommand::PaintCommand(std::string name, std::size_t body, MapChannel channel,
                           std::vector<PartChange> changes, std::optional<PaintedMap> created,
                           std::string createdPath)
    : name_(std::move(name)),
      body_(body),
      channel_(channel),
      changes_(std::move(changes)),
      created_(std::move(created)),
      createdPath_(std::move(createdPath)) {}

std::size_t PaintCommand::pixelsChanged() const {
    std::size_t n = 0;
    for (const PartChange& c : changes_) n += c.change.pixels.size();
    return n;
}

PaintedMap PaintCommand::preview(const Document& document) const {
    const LayerStack* layers = created_ ? nullptr : document.layers(body_, channel_);
    if (!layers) {
        PaintedMap map = created_ ? *created_ : PaintedMap{};
        if (!created_) {
            if (const PaintedMap* current = document.map(body_, channel_)) map = *current;
        }
        for (const PartChange& c : changes_) applyValues(map, c.change.pixels, c.change.after);
        return map;
    }
    // The stack shares its pixels with the document: the parts painted are copied first.
    LayerStack stack = *layers;
    for (const PartChange& c : changes_) {
        std::shared_ptr<PaintedMap>& part =
            stack.layers.at(static_cast<std::size_t>(c.target.layer)).part(c.target.part);
        if (!part) continue;
        if (part == layers->layers[static_cast<std::size_t>(c.target.layer)].part(c.target.part)) {
            part = std::make_shared<PaintedMap>(*part);
        }
        applyValues(*part, c.change.pixels, c.change.after);
    }
    return flattenLayers(stack);
}

Status PaintCommand::apply(Document& document) {
    if (body_ >= document.bodyCount()) {
        return makeError(ErrorKind::invalidArgument, "no body " + std::to_string(body_));
    }
    if (created_) {
        // The made map replaces the channel's map, layers and all: kept for the undo.
        replaced_ = document.mapState(body_, channel_);
        Project project = document.project();
        previousPath_ = channelPath(project.bodies[body_], channel_);
        channelPath(project.bodies[body_], channel_) = createdPath_;
        document.setProject(std::move(project), detached_);
        document.setLayers(body_, channel_, std::nullopt);
        document.setMap(body_, channel_, *created_);
    }
    for (const PartChange& c : changes_) {
        PaintedMap* pixels = document.paintPixels(body_, channel_, c.target);
        if (!pixels) {
            return makeError(
                ErrorKind::invalidArgument,
                std::string("no ") + channelName(channel_) + " map, layer or mask to paint");
        }
        applyValues(*pixels, c.change.pixels, c.change.after);
    }
    document.pixelsChanged(body_, channel_);
    return Ok{};
}

void PaintCommand::revert(Document& document) {
    for (auto c = changes_.rbegin(); c != changes_.rend(); ++c) {
        if (PaintedMap* pixels = document.paintPixels(body_, channel_, c->target)) {
            applyValues(*pixels, c->change.pixels, c->change.before);
        }
    }
    document.pixelsChanged(body_, channel_);
    if (created_) {
        Project project = document.project();
        channelPath(project.bodies[body_], channel_) = previousPath_;
        document.setMap(body_, channel_, std::nullopt);
        document.setProject(std::move(project), detached_);
        if (replaced_) document.restoreMapState(body_, channel_, *replaced_);
        replaced_.reset();
    }
}

ProjectCommand::ProjectCommand(std::string name, Project before, Project after,
                               DetachedAssets detached)
    : name_(std::move(name)),
      before_(std::move(before)),
      after_(std::move(after)),
      detached_(std::move(detached)) {}

Status ProjectCommand::apply(Document& document) {
    document.setProject(after_, detached_);
    return Ok{};
}

void ProjectCommand::revert(Document& document) { document.setProject(before_, detached_); }

LayerCommand::LayerCommand(std::string name, std::size_t body, MapChannel channel,
                           std::optional<LayerStack> before, LayerStack after)
    : name_(std::move(name)),
      body_(body),
      channel_(channel),
      before_(std::move(before)),
      after_(std::move(after)) {}

Status LayerCommand::apply(Document& document) {
    if (body_ >= document.bodyCount() || !document.map(body_, channel_)) {
        return makeError(ErrorKind::invalidArgument,
                         std::string("no ") + channelName(channel_) + " map for layers");
    }
    if (!before_) mapBefore_ = document.mapState(body_, channel_);
    document.setLayers(body_, channel_, after_);
    return Ok{};
}

void LayerCommand::revert(Document& document) {
    if (mapBefore_) {
        document.restoreMapState(body_, channel_, *mapBefore_);
        mapBefore_.reset();
    } else {
        document.setLayers(body_, channel_, before_);
    }
}

namespace {

Status checkTarget(const Document& document, std::size_t body, MapChannel channel) {
    if (body >= document.bodyCount()) {
        return makeError(ErrorKind::invalidArgument,
                         "no body " + std::to_string(body) + " (the project has " +
                             std::to_string(document.bodyCount()) + ")");
    }
    if (!document.assets(body).mesh) {
        return makeError(ErrorKind::io, "body " + std::to_string(body) + ": mesh not loaded: " +
                                            document.assets(body).meshError);
    }
    if (channelNeedsShell(channel) &&
        !document.project().bodies[body].material.shellSurfaceDensity) {
        return makeError(
            ErrorKind::invalidArgument,
            "body " + std::to_string(body) + ": a " + channelName(channel) +
                " map scales the shell, and the material has none (set material.shell)");
    }
    return Ok{};
}

/// What a paint operation does to one buffer: moves pixels toward `value` (Paint), toward 0
/// (Erase) or smooths them, by its own weights.
using BufferEdit =
    std::function<PixelChange(const PaintedMap& buffer, BrushMode mode, double value)>;

/// The changes of a paint operation on `target`. A layer with coverage is painted the way
/// layers are in painting tools: paint sets the value and raises coverage by the same weights
/// (where nothing was painted yet the value is set outright, so a half-strength stroke shows
/// the colour at half opacity, not half the colour); erase lowers coverage; smooth smooths
/// the values.
std::vector<PaintCommand::PartChange> partChanges(const PaintedMap& pixels,
                                                  const PaintedMap* coverage, PaintTarget target,
                                                  BrushMode mode, double value,
                                                  const BufferEdit& edit) {
    std::vector<PaintCommand::PartChange> changes;
    if (!coverage || target.part != LayerPart::Pixels) {
        changes.push_back({target, edit(pixels, mode, value)});
        return changes;
    }
    const PaintTarget coverageTarget{target.layer, LayerPart::Coverage};
    if (mode == BrushMode::Paint) {
        PixelChange values = edit(pixels, mode, value);
        for (std::size_t k = 0; k < values.pixels.size(); ++k) {
            if (coverage->values[values.pixels[k]] <= 0.0f)
                values.after[k] = static_cast<float>(value);
        }
        changes.push_back({target, std::move(values)});
        changes.push_back({coverageTarget, edit(*coverage, BrushMode::Paint, 1.0)});
    } else if (mode == BrushMode::Erase) {
        changes.push_back({coverageTarget, edit(*coverage, BrushMode::Erase, 0.0)});
    } else {
        changes.push_back({target, edit(pixels, mode, value)});
    }
    return changes;
}

/// The layer (or its mask) a paint operation on a layered map changes: `target` checked, or
/// the topmost paint layer when it names none.
Result<PaintTarget> layerTarget(const LayerStack& stack, PaintTarget target) {
    const int count = static_cast<int>(stack.layers.size());
    if (target.layer < 0) {
        if (target.part == LayerPart::Mask) {
            return makeError(ErrorKind::invalidArgument, "painting a mask: name its layer");
        }
        for (int i = count - 1; i >= 0; --i) {
            if (stack.layers[static_cast<std::size_t>(i)].kind == LayerKind::Paint) {
                return PaintTarget{i, target.part};
            }
        }
        return makeError(ErrorKind::invalidArgument, "the map has no paint layer to paint");
    }
    if (target.layer >= count) {
        return makeError(ErrorKind::invalidArgument, "no layer " + std::to_string(target.layer) +
                                                         " (the map has " + std::to_string(count) +
                                                         ")");
    }
    const MapLayer& layer = stack.layers[static_cast<std::size_t>(target.layer)];
    if (target.part == LayerPart::Mask && !layer.mask) {
        return makeError(ErrorKind::invalidArgument,
                         "layer '" + layer.name + "' has no mask (add one)");
    }
    if (target.part == LayerPart::Pixels && !layer.pixels) {
        return makeError(ErrorKind::invalidArgument, "layer '" + layer.name + "' is a " +
                                                         layerKindName(layer.kind) +
                                                         (layer.isFolder() ? " " : " layer") +
                                                         ": paint its mask, or a paint layer");
    }
    return target;
}

/// Runs `edit` on the body's map (or on the layer `target` names), making a blank map first
/// (as part of the same command) when there is none.
Result<std::unique_ptr<Command>> paintEdit(
    Document& document, std::size_t body, MapChannel channel, const std::string& name,
    BrushMode mode, double value, PaintTarget target,
    const std::function<BufferEdit(const PaintSurface&)>& editOn) {
    if (Status ok = checkTarget(document, body, channel); !ok) return ok.error();
    std::optional<PaintedMap> created;
    std::string createdPath;
    PaintedMap blank;
    const PaintedMap* map = document.map(body, channel);
    std::shared_ptr<const PaintSurface> surface;
    if (!map) {
        if (target.layer >= 0 || target.part != LayerPart::Pixels) {
            return makeError(
                ErrorKind::invalidArgument,
                std::string("body has no ") + channelName(channel) + " map (no layers)");
        }
        blank = uniformMap(kDefaultMapSize, kDefaultMapSize, 0.0f);
        created = blank;
        createdPath = channelPath(document.project().bodies[body], channel);
        if (createdPath.empty()) createdPath = document.defaultMapPath(body, channel);
        map = &blank;
        Result<PaintSurface> built =
            buildPaintSurface(*document.assets(body).mesh, blank.width, blank.height);
        if (!built) return built.error();
        surface = std::make_shared<const PaintSurface>(std::move(built).value());
    } else {
        auto cached = document.paintSurface(body, channel);
        if (!cached) return cached.error();
        surface = *cached;
    }
    const PaintedMap* pixels = map;
    const PaintedMap* coverage = nullptr;
    if (const LayerStack* stack = document.layers(body, channel)) {
        Result<PaintTarget> resolved = layerTarget(*stack, target);
        if (!resolved) return resolved.error();
        target = *resolved;
        const MapLayer& layer = stack->layers[static_cast<std::size_t>(target.layer)];
        pixels = (target.part == LayerPart::Mask ? layer.mask : layer.pixels).get();
        coverage = layer.coverage.get();
    } else if (target.layer >= 0 || target.part != LayerPart::Pixels) {
        return makeError(ErrorKind::invalidArgument,
                         std::string("the ") + channelName(channel) + " map has no layers");
    }
    std::vector<PaintCommand::PartChange> changes =
        partChanges(*pixels, coverage, target, mode, value, editOn(*surface));
    if (document.layers(body, channel)) {
        for (PaintCommand::PartChange& c : changes) {
            for (float& v : c.change.after) v = quantize16(v);
        }
    }
    // A mask's strokes say so ("Paint permeability mask"): the history tells them from paint.
    const std::string label = target.part == LayerPart::Mask ? name + " mask" : name;
    return std::unique_ptr<Command>(std::make_unique<PaintCommand>(
        label, body, channel, std::move(changes), std::move(created), std::move(createdPath)));
}

/// A change moved only `strength` of the way (1: all of it).
PixelChange scaled(PixelChange change, double strength) {
    const float k = static_cast<float>(std::clamp(strength, 0.0, 1.0));
    for (std::size_t i = 0; i < change.after.size(); ++i) {
        change.after[i] = change.before[i] + (change.after[i] - change.before[i]) * k;
    }
    return change;
}

std::size_t islandCount(const PaintSurface& surface) {
    return std::set<std::uint32_t>(surface.island.begin(), surface.island.end()).size();
}

}  // namespace

Result<std::unique_ptr<Command>> makeStrokeCommand(Document& document, std::size_t body,
                                                   MapChannel channel, const Brush& brush,
                                                   std::span<const Eigen::Vector3d> points,
                                                   PaintTarget target) {
    const char* verb = brush.mode == BrushMode::Erase    ? "Erase"
                       : brush.mode == BrushMode::Smooth ? "Smooth"
                                                         : "Paint";
    return paintEdit(document, body, channel, std::string(verb) + " " + channelName(channel),
                     brush.mode, brush.value, target, [&](const PaintSurface& surface) {
                         return [&](const PaintedMap& buffer, BrushMode mode, double value) {
                             Brush b = brush;
                             b.mode = mode;
                             b.value = value;
                             return strokeChange(buffer, surface, b, points);
                         };
                     });
}

Result<std::unique_ptr<Command>> makeFillIslandCommand(Document& document, std::size_t body,
                                                       MapChannel channel,
                                                       const Eigen::Vector3d& point, double value,
                                                       bool mirrorX, double strength,
                                                       PaintTarget target) {
    std::string name = std::string("Fill island ") + channelName(channel);
    if (document.map(body, channel)) {
        // A map whose mesh is one UV island fills everywhere: say so rather than surprise.
        if (auto surface = document.paintSurface(body, channel);
            surface && islandCount(**surface) == 1) {
            name += " (the mesh is one UV island: all of it)";
        }
    }
    return paintEdit(document, body, channel, name, BrushMode::Paint, value, target,
                     [&](const PaintSurface& surface) {
                         return [&](const PaintedMap& buffer, BrushMode, double v) {
                             return scaled(fillIslandChange(buffer, surface, point, v, mirrorX),
                                           strength);
                         };
                     });
}

Result<std::unique_ptr<Command>> makeFillAllCommand(Document& document, std::size_t body,
                                                    MapChannel channel, double value,
                                                    double strength, PaintTarget target) {
    return paintEdit(document, body, channel, std::string("Fill ") + channelName(channel),
                     BrushMode::Paint, value, target, [&](const PaintSurface&) {
                         return [&](const PaintedMap& buffer, BrushMode, double v) {
                             return scaled(fillAllChange(buffer, v), strength);
                         };
                     });
}

Result<std::unique_ptr<Command>> makeNewMapCommand(Document& document, std::size_t body,
                                                   MapChannel channel, int width, int height,
                                                   double value, std::string path) {
    if (Status ok = checkTarget(document, body, channel); !ok) return ok.error();
    if (width < 1 || height < 1 || width > 16384 || height > 16384) {
        return makeError(ErrorKind::invalidArgument, "map size must be 1..16384 pixels a side");
    }
    PaintedMap blank;
    blank.width = width;
    blank.height = height;
    blank.values.assign(static_cast<std::size_t>(width) * height,
                        static_cast<float>(std::clamp(value, 0.0, 1.0)));
    if (path.empty()) path = document.defaultMapPath(body, channel);
    return std::unique_ptr<Command>(std::make_unique<PaintCommand>(
        std::string("New ") + channelName(channel) + " map", body, channel,
        std::vector<PaintCommand::PartChange>{}, std::move(blank), std::move(path)));
}

namespace {

/// Resamples one axis of `rows` lines of `from` values each to `to` values (stride 1 within
/// a line, lines `from` apart in and `to` apart out). Shrinking: each new pixel is the
/// area-weighted mean of the old pixels it covers (the integral over the map is kept exactly).
/// Growing: linear between the old pixels' centres, the edges held (smooth, no blocks).
std::vector<float> resampleLines(const std::vector<float>& in, int rows, int from, int to) {
    std::vector<float> out(static_cast<std::size_t>(rows) * to);
    const double ratio = double(from) / to;  // old pixels per new pixel
    for (int r = 0; r < rows; ++r) {
        const float* line = in.data() + static_cast<std::size_t>(r) * from;
        float* result = out.data() + static_cast<std::size_t>(r) * to;
        for (int k = 0; k < to; ++k) {
            if (ratio >= 1.0) {
                const double a = k * ratio, b = (k + 1) * ratio;
                double sum = 0;
                for (int i = static_cast<int>(std::floor(a));
                     i < std::min(from, static_cast<int>(std::ceil(b))); ++i) {
                    sum += line[i] * (std::min(b, i + 1.0) - std::max(a, double(i)));
                }
                result[k] = static_cast<float>(sum / ratio);
            } else {
                const double x = std::clamp((k + 0.5) * ratio - 0.5, 0.0, from - 1.0);
                const int i = std::min(static_cast<int>(x), from - 1);
                const double t = x - i;
                result[k] =
                    static_cast<float>(line[i] * (1 - t) + line[std::min(i + 1, from - 1)] * t);
            }
        }
    }
    return out;
}

/// Rows and columns swapped (so the second axis can be resampled as lines).
std::vector<float> transposed(const std::vector<float>& in, int width, int height) {
    std::vector<float> out(in.size());
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x)
            out[static_cast<std::size_t>(x) * height + y] =
                in[static_cast<std::size_t>(y) * width + x];
    return out;
}

}  // namespace

PaintedMap resampledMap(const PaintedMap& map, int width, int height) {
    PaintedMap out;
    out.width = width;
    out.height = height;
    std::vector<float> across =
        resampleLines(map.values, map.height, map.width, width);  // height x width
    std::vector<float> down =
        resampleLines(transposed(across, width, map.height), width, map.height, height);
    out.values = transposed(down, height, width);
    return out;
}

namespace {

std::shared_ptr<PaintedMap> resampledPart(const std::shared_ptr<PaintedMap>& part, int width,
                                          int height) {
    return part ? std::make_shared<PaintedMap>(resampledMap(*part, width, height)) : nullptr;
}

}  // namespace

Result<std::unique_ptr<Command>> makeResizeMapCommand(Document& document, std::size_t body,
                                                      MapChannel channel, int width, int height) {
    if (Status ok = checkTarget(document, body, channel); !ok) return ok.error();
    const PaintedMap* map = document.map(body, channel);
    if (!map)
        return makeError(ErrorKind::invalidArgument,
                         std::string("no ") + channelName(channel) + " map to resize");
    if (width < 1 || height < 1 || width > kMaxPaintedMapSide || height > kMaxPaintedMapSide) {
        return makeError(ErrorKind::limit, "map size " + std::to_string(width) + " x " +
                                               std::to_string(height) +
                                               " is outside 1..kMaxPaintedMapSide = " +
                                               std::to_string(kMaxPaintedMapSide) + " (limits.h)");
    }
    const std::string name = std::string("Resize ") + channelName(channel) + " map to " +
                             std::to_string(width) + " x " + std::to_string(height);
    if (const LayerStack* layers = document.layers(body, channel)) {
        // Every layer's pixels, mask and coverage, at the 16 bits layers keep.
        LayerStack after = *layers;
        after.width = width;
        after.height = height;
        for (MapLayer& layer : after.layers) {
            for (LayerPart part : {LayerPart::Pixels, LayerPart::Mask, LayerPart::Coverage}) {
                layer.part(part) = resampledPart(layer.part(part), width, height);
                if (layer.part(part)) {
                    for (float& v : layer.part(part)->values) v = quantize16(v);
                }
            }
        }
        if (Status ok = checkStack(after); !ok) return ok.error();
        return std::unique_ptr<Command>(
            std::make_unique<LayerCommand>(name, body, channel, *layers, std::move(after)));
    }
    return std::unique_ptr<Command>(std::make_unique<PaintCommand>(
        name, body, channel, std::vector<PaintCommand::PartChange>{},
        resampledMap(*map, width, height), channelPath(document.project().bodies[body], channel)));
}

namespace {

/// A LayerCommand from `change` run on a copy of the map's stack (a map without layers: a
/// stack of its one Base layer).
Result<std::unique_ptr<Command>> layerEdit(const Document& document, std::size_t body,
                                           MapChannel channel, std::string name,
                                           const std::function<Status(LayerStack&)>& change) {
    if (body >= document.bodyCount()) {
        return makeError(ErrorKind::invalidArgument, "no body " + std::to_string(body));
    }
    const PaintedMap* map = document.map(body, channel);
    if (!map) {
        return makeError(ErrorKind::invalidArgument, "body " + std::to_string(body) + " has no " +
                                                         channelName(channel) +
                                                         " map (paint or make one first)");
    }
    const LayerStack* current = document.layers(body, channel);
    std::optional<LayerStack> before;
    if (current) before = *current;
    LayerStack after = current ? *current : stackOfMap(*map);
    if (Status ok = change(after); !ok) return ok.error();
    if (Status ok = checkStack(after); !ok) return ok.error();
    return std::unique_ptr<Command>(std::make_unique<LayerCommand>(
        std::move(name), body, channel, std::move(before), std::move(after)));
}

Status checkLayerIndex(const LayerStack& stack, int layer) {
    if (layer < 0 || static_cast<std::size_t>(layer) >= stack.layers.size()) {
        return makeError(ErrorKind::invalidArgument, "no layer " + std::to_string(layer) +
                                                         " (the map has " +
                                                         std::to_string(stack.layers.size()) + ")");
    }
    return Ok{};
}

Status checkUnit(double value, const char* what) {
    if (!(value >= 0.0 && value <= 1.0)) {
        return makeError(ErrorKind::invalidArgument, std::string(what) + " must be 0..1");
    }
    return Ok{};
}

}  // namespace

namespace {

const char* defaultNameStem(LayerKind kind) {
    return kind == LayerKind::Fill ? "Fill" : kind == LayerKind::Folder ? "Folder" : "Layer";
}

/// Inserts `layer` at `index` (clamped; -1: on top). It is in a folder where the layer below
/// it is, and right below a folder's entry (an empty folder is filled this way); a folder is
/// never in one, and refused between a folder's layers.
Status insertLayer(LayerStack& stack, MapLayer layer, int index) {
    const int count = static_cast<int>(stack.layers.size());
    const int at = index < 0 || index > count ? count : index;
    const bool betweenLayers = at > 0 && stack.layers[std::size_t(at - 1)].inFolder;
    const bool underEntry = at < count && stack.layers[std::size_t(at)].isFolder();
    if (betweenLayers && layer.isFolder())
        return makeError(ErrorKind::invalidArgument,
                         "a folder cannot go inside folder '" +
                             stack.layers[std::size_t(folderOf(stack, at - 1))].name +
                             "' (folders do not nest)");
    layer.inFolder = !layer.isFolder() && (betweenLayers || underEntry);
    stack.layers.insert(stack.layers.begin() + at, std::move(layer));
    return Ok{};
}

}  // namespace

Result<std::unique_ptr<Command>> makeAddLayerCommand(const Document& document, std::size_t body,
                                                     MapChannel channel, LayerKind kind,
                                                     std::string name, double fillValue,
                                                     int index) {
    if (Status ok = checkUnit(fillValue, "a fill layer's value"); !ok) return ok.error();
    const std::string label = kind == LayerKind::Folder
                                  ? std::string("Add folder")
                                  : std::string("Add ") + layerKindName(kind) + " layer";
    return layerEdit(document, body, channel, label, [&](LayerStack& stack) -> Status {
        if (Status ok = checkLayerBudget(stack, 1, kind == LayerKind::Paint ? 2 : 0); !ok)
            return ok;
        MapLayer layer;
        layer.kind = kind;
        // The default names count up from the stack's size, past any taken
        // (a removed layer's number is not reused while a layer has it).
        if (name.empty()) {
            layer.name = unusedLayerName(stack, defaultNameStem(kind), stack.layers.size());
        } else if (Status ok = checkLayerName(stack, -1, name); !ok) {
            return ok;
        } else {
            layer.name = trimmedLayerName(name);
        }
        if (kind == LayerKind::Paint) {
            layer.pixels =
                std::make_shared<PaintedMap>(uniformMap(stack.width, stack.height, 0.0f));
            layer.coverage =
                std::make_shared<PaintedMap>(uniformMap(stack.width, stack.height, 0.0f));
        } else if (kind == LayerKind::Fill) {
            layer.fillValue = static_cast<float>(fillValue);
        }
        return insertLayer(stack, std::move(layer), index);
    });
}

Result<std::unique_ptr<Command>> makeRemoveLayerCommand(const Document& document, std::size_t body,
                                                        MapChannel channel, int layer) {
    const LayerStack* current =
        body < document.bodyCount() ? document.layers(body, channel) : nullptr;
    const bool folder = current && layer >= 0 && std::size_t(layer) < current->layers.size() &&
                        current->layers[std::size_t(layer)].isFolder();
    return layerEdit(
        document, body, channel, folder ? "Remove folder" : "Remove layer",
        [&](LayerStack& stack) -> Status {
            if (Status ok = checkLayerIndex(stack, layer); !ok) return ok;
            // A folder goes with the layers it holds.
            const int start = blockStart(stack, layer);
            if (layer - start + 1 == static_cast<int>(stack.layers.size())) {
                return makeError(ErrorKind::invalidArgument, "the map's last layer cannot go");
            }
            stack.layers.erase(stack.layers.begin() + start, stack.layers.begin() + layer + 1);
            return Ok{};
        });
}

Result<std::unique_ptr<Command>> makeMoveLayerCommand(const Document& document, std::size_t body,
                                                      MapChannel channel, int from, int to) {
    return layerEdit(document, body, channel, "Move layer", [&](LayerStack& stack) -> Status {
        if (Status ok = checkLayerIndex(stack, from); !ok) return ok;
        if (Status ok = checkLayerIndex(stack, to); !ok) return ok;
        if (from == to) return Ok{};
        // Among the items of one folder (or of the top level); a folder moves with its layers.
        if (folderOf(stack, from) != folderOf(stack, to)) {
            return makeError(ErrorKind::invalidArgument,
                             "layers " + std::to_string(from) + " and " + std::to_string(to) +
                                 " are not in the same folder: move the layer into or out "
                                 "of the folder");
        }
        moveItem(stack, from, to);
        return Ok{};
    });
}

Result<std::unique_ptr<Command>> makeMoveIntoFolderCommand(const Document& document,
                                                           std::size_t body, MapChannel channel,
                                                           int layer, int folder) {
    return layerEdit(
        document, body, channel, "Move layer into folder", [&](LayerStack& stack) -> Status {
            if (Status ok = checkLayerIndex(stack, layer); !ok) return ok;
            if (Status ok = checkLayerIndex(stack, folder); !ok) return ok;
            const MapLayer& l = stack.layers[std::size_t(layer)];
            const MapLayer& f = stack.layers[std::size_t(folder)];
            if (!f.isFolder())
                return makeError(ErrorKind::invalidArgument,
                                 "layer '" + f.name + "' is not a folder");
            if (l.isFolder())
                return makeError(
                    ErrorKind::invalidArgument,
                    "folder '" + l.name + "' cannot go into a folder (folders do not nest)");
            if (folderOf(stack, layer) == folder)
                return makeError(ErrorKind::invalidArgument,
                                 "layer '" + l.name + "' is in folder '" + f.name + "' already");
            // On top of the folder's layers, as a drop on a folder puts it.
            MapLayer moved = std::move(stack.layers[std::size_t(layer)]);
            stack.layers.erase(stack.layers.begin() + layer);
            moved.inFolder = true;
            const int at = layer < folder ? folder - 1 : folder;
            stack.layers.insert(stack.layers.begin() + at, std::move(moved));
            return Ok{};
        });
}

Result<std::unique_ptr<Command>> makeMoveOutOfFolderCommand(const Document& document,
                                                            std::size_t body, MapChannel channel,
                                                            int layer) {
    return layerEdit(
        document, body, channel, "Move layer out of folder", [&](LayerStack& stack) -> Status {
            if (Status ok = checkLayerIndex(stack, layer); !ok) return ok;
            const int folder = folderOf(stack, layer);
            if (folder < 0)
                return makeError(
                    ErrorKind::invalidArgument,
                    "layer '" + stack.layers[std::size_t(layer)].name + "' is in no folder");
            // Right above the folder it leaves.
            MapLayer moved = std::move(stack.layers[std::size_t(layer)]);
            stack.layers.erase(stack.layers.begin() + layer);
            moved.inFolder = false;
            stack.layers.insert(stack.layers.begin() + folder, std::move(moved));
            return Ok{};
        });
}

Result<std::unique_ptr<Command>> makeRenameLayerCommand(const Document& document, std::size_t body,
                                                        MapChannel channel, int layer,
                                                        std::string_view typed) {
    const std::string name = trimmedLayerName(typed);
    // The label names the layer as it was: a map without layers has only its "Base" (layerEdit
    // refuses any other index).
    const LayerStack* current =
        body < document.bodyCount() ? document.layers(body, channel) : nullptr;
    const std::string old =
        current && layer >= 0 && static_cast<std::size_t>(layer) < current->layers.size()
            ? current->layers[static_cast<std::size_t>(layer)].name
            : std::string("Base");
    return layerEdit(document, body, channel, "Rename layer '" + old + "' to '" + name + "'",
                     [&](LayerStack& stack) -> Status {
                         if (Status ok = checkLayerIndex(stack, layer); !ok) return ok;
                         if (Status ok = checkLayerName(stack, layer, name); !ok) return ok;
                         MapLayer& l = stack.layers[static_cast<std::size_t>(layer)];
                         if (l.name == name) {
                             return makeError(ErrorKind::invalidArgument,
                                              "the layer is named '" + name + "' already");
                         }
                         l.name = name;
                         return Ok{};
                     });
}

Result<std::unique_ptr<Command>> makeSetLayerCommand(const Document& document, std::size_t body,
                                                     MapChannel channel, int layer,
                                                     const LayerEdit& edit) {
    // A change of the name alone is a rename, and says so in the history.
    if (edit.name && !edit.opacity && !edit.blend && !edit.visible && !edit.fillValue) {
        return makeRenameLayerCommand(document, body, channel, layer, *edit.name);
    }
    return layerEdit(document, body, channel, "Layer settings", [&](LayerStack& stack) -> Status {
        if (Status ok = checkLayerIndex(stack, layer); !ok) return ok;
        MapLayer& l = stack.layers[static_cast<std::size_t>(layer)];
        if (edit.opacity) {
            if (Status ok = checkUnit(*edit.opacity, "opacity"); !ok) return ok;
            l.opacity = static_cast<float>(*edit.opacity);
        }
        if (edit.fillValue) {
            if (l.kind != LayerKind::Fill) {
                return makeError(ErrorKind::invalidArgument,
                                 "layer '" + l.name + "' is a paint layer: it has no fill value");
            }
            if (Status ok = checkUnit(*edit.fillValue, "a fill layer's value"); !ok) return ok;
            l.fillValue = static_cast<float>(*edit.fillValue);
        }
        if (edit.name) {
            if (Status ok = checkLayerName(stack, layer, *edit.name); !ok) return ok;
            l.name = trimmedLayerName(*edit.name);
        }
        if (edit.blend) l.blend = *edit.blend;
        if (edit.visible) l.visible = *edit.visible;
        return Ok{};
    });
}

Result<std::unique_ptr<Command>> makeAddMaskCommand(const Document& document, std::size_t body,
                                                    MapChannel channel, int layer, double value) {
    if (Status ok = checkUnit(value, "a mask's value"); !ok) return ok.error();
    return layerEdit(document, body, channel, "Add mask", [&](LayerStack& stack) -> Status {
        if (Status ok = checkLayerIndex(stack, layer); !ok) return ok;
        MapLayer& l = stack.layers[static_cast<std::size_t>(layer)];
        if (l.mask)
            return makeError(ErrorKind::invalidArgument, "layer '" + l.name + "' has a mask");
        if (Status ok = checkLayerBudget(stack, 0, 1); !ok) return ok;
        l.mask = std::make_shared<PaintedMap>(
            uniformMap(stack.width, stack.height, quantize16(static_cast<float>(value))));
        return Ok{};
    });
}

Result<std::unique_ptr<Command>> makeRemoveMaskCommand(const Document& document, std::size_t body,
                                                       MapChannel channel, int layer) {
    return layerEdit(document, body, channel, "Remove mask", [&](LayerStack& stack) -> Status {
        if (Status ok = checkLayerIndex(stack, layer); !ok) return ok;
        MapLayer& l = stack.layers[static_cast<std::size_t>(layer)];
        if (!l.mask)
            return makeError(ErrorKind::invalidArgument, "layer '" + l.name + "' has no mask");
        l.mask.reset();
        return Ok{};
    });
}

Result<std::unique_ptr<Command>> makeSmartMaskCommand(Document& document, std::size_t body,
                                                      MapChannel channel, int layer,
                                                      const SmartMask& mask) {
    if (mask.kind == SmartMask::Kind::Depth && !(mask.depth > 0))
        return makeError(ErrorKind::invalidArgument, "a depth mask needs a depth above 0");
    const bool byCurvature =
        mask.kind == SmartMask::Kind::Curvature || mask.kind == SmartMask::Kind::Cavity;
    if (byCurvature && !(mask.radius > 0 && mask.fullCurvature > 0 && std::isfinite(mask.radius) &&
                         std::isfinite(mask.fullCurvature)))
        return makeError(ErrorKind::invalidArgument,
                         "a curvature or cavity mask needs a radius and a full curvature above 0");
    if (body >= document.bodyCount() || !document.map(body, channel)) {
        return makeError(ErrorKind::invalidArgument, "body " + std::to_string(body) + " has no " +
                                                         channelName(channel) + " map");
    }
    Result<std::shared_ptr<const PaintSurface>> surface = document.paintSurface(body, channel);
    if (!surface) return surface.error();
    const PaintSurface& grid = **surface;
    // The mesh the paint surface was built over: curvature is measured on it.
    const std::shared_ptr<const TriangleMesh> mesh = document.assets(body).mesh;
    if (byCurvature && !mesh)
        return makeError(ErrorKind::invalidArgument, "the body's mesh did not load");
    return layerEdit(document, body, channel, "Smart mask: " + smartMaskName(mask.kind),
                     [&](LayerStack& stack) -> Status {
                         if (Status ok = checkLayerIndex(stack, layer); !ok) return ok;
                         if (grid.width != stack.width || grid.height != stack.height)
                             return makeError(ErrorKind::invalidArgument,
                                              "the map's paint surface is not its size");
                         MapLayer& l = stack.layers[static_cast<std::size_t>(layer)];
                         if (!l.mask) {
                             if (Status ok = checkLayerBudget(stack, 0, 1); !ok) return ok;
                         }
                         PaintedMap image = smartMaskImage(grid, mask, mesh.get());
                         for (float& v : image.values) v = quantize16(v);
                         l.mask = std::make_shared<PaintedMap>(std::move(image));
                         return Ok{};
                     });
}

std::string propertyLabel(const Project& project, const std::string& pointer) {
    std::vector<std::string> parts;
    for (std::size_t at = 0; at < pointer.size();) {
        const std::size_t next = std::min(pointer.find('/', at + 1), pointer.size());
        if (next > at + 1) parts.push_back(pointer.substr(at + 1, next - at - 1));
        at = next;
    }
    auto isIndex = [](const std::string& t) {
        return !t.empty() &&
               std::all_of(t.begin(), t.end(), [](char c) { return c >= '0' && c <= '9'; });
    };
    std::string label;
    auto add = [&](std::string word) {
        std::replace(word.begin(), word.end(), '_', ' ');
        if (!label.empty()) label += ' ';
        label += word;
    };
    for (std::size_t i = 0; i < parts.size(); ++i) {
        const std::string& t = parts[i];
        if (t == "bodies" && i + 1 < parts.size() && isIndex(parts[i + 1])) {
            const std::size_t b = std::stoul(parts[++i]);
            add(b < project.bodies.size() && !project.bodies[b].name.empty()
                    ? project.bodies[b].name
                    : "body " + std::to_string(b + 1));
        } else if (t == "material" || t == "simulation") {
            continue;  // the property's own name says enough
        } else if (isIndex(t) && i > 0 && t.size() == 1 && t[0] < '3' &&
                   (parts[i - 1] == "position" || parts[i - 1] == "rotation_deg" ||
                    parts[i - 1] == "gravity" || parts[i - 1] == "velocity" ||
                    parts[i - 1] == "angular_velocity")) {
            add(std::string(1, "xyz"[t[0] - '0']));
        } else if (isIndex(t)) {
            add(std::to_string(std::stoul(t) + 1));
        } else {
            add(t == "rotation_deg" ? "rotation" : t == "mesh" ? "mesh file" : t);
        }
    }
    return label.empty() ? pointer : label;
}

Result<std::unique_ptr<Command>> makeSetPropertyCommand(const Document& document,
                                                        const std::string& pointer,
                                                        const Json& value) {
    Json json = Json::parse(projectToJson(document.project()));
    try {
        json[Json::json_pointer(pointer)] = value;
    } catch (const Json::exception& e) {
        return makeError(ErrorKind::schema, pointer + ": " + boundedExcerpt(e.what(), 200));
    }
    Result<Project> edited = parseProject(json.dump(), "set " + pointer, document.project().folder);
    if (!edited) return edited.error();
    return std::unique_ptr<Command>(
        std::make_unique<ProjectCommand>("Set " + propertyLabel(document.project(), pointer),
                                         document.project(), std::move(edited).value()));
}

Result<std::unique_ptr<Command>> makeImportMeshCommand(const Document& document,
                                                       const fs::path& mesh,
                                                       std::optional<std::size_t> body) {
    Result<TriangleMesh> loaded = loadMesh(mesh);
    if (!loaded) return loaded.error();
    Project project = document.project();
    const fs::path absolute = fs::absolute(mesh).lexically_normal();
    fs::path relative = absolute.lexically_relative(project.folder);
    const std::string written = relative.empty() ? absolute.string() : relative.generic_string();
    if (body) {
        if (*body >= project.bodies.size())
            return makeError(ErrorKind::invalidArgument, "no body " + std::to_string(*body));
        project.bodies[*body].mesh = written;
    } else {
        BodyDesc added;
        added.name = mesh.stem().string();
        added.mesh = written;
        added.material.density = 500.0;
        project.bodies.push_back(std::move(added));
    }
    return std::unique_ptr<Command>(std::make_unique<ProjectCommand>(
        "Import " + mesh.filename().string(), document.project(), std::move(project)));
}

namespace {

Status checkBody(const Document& document, std::size_t body) {
    if (body >= document.bodyCount()) {
        return makeError(ErrorKind::invalidArgument,
                         "no body " + std::to_string(body) + " (the project has " +
                             std::to_string(document.bodyCount()) + ")");
    }
    return Ok{};
}

std::string bodyLabel(const BodyDesc& body, std::size_t index) {
    return body.name.empty() ? "body " + std::to_string(index) : body.name;
}

}  // namespace

Result<std::unique_ptr<Command>> makeDuplicateBodyCommand(const Document& document,
                                                          std::size_t body) {
    if (Status ok = checkBody(document, body); !ok) return ok.error();
    Project project = document.project();
    BodyDesc copy = project.bodies[body];
    const std::string stem = bodyLabel(copy, body) + " copy";
    auto taken = [&](const std::string& name) {
        return std::any_of(project.bodies.begin(), project.bodies.end(),
                           [&](const BodyDesc& b) { return b.name == name; });
    };
    copy.name = stem;
    for (int k = 2; taken(copy.name); ++k) copy.name = stem + " " + std::to_string(k);
    // Beside the original, not inside it: its width along x (as posed) and a tenth more.
    double width = 1.0;
    if (const auto& mesh = document.assets(body).mesh; mesh && !mesh->positions.empty()) {
        const Pose pose = document.bodyPose(body);
        double lo = std::numeric_limits<double>::infinity(), hi = -lo;
        for (const Eigen::Vector3d& p : mesh->positions) {
            const double x = pose.apply(p).x();
            lo = std::min(lo, x);
            hi = std::max(hi, x);
        }
        if (hi > lo) width = hi - lo;
    }
    copy.position.x() += 1.1 * width;
    // The copy's maps and graph: the original's as edited (unsaved paint included), under
    // files of the copy's own (two bodies saving their edits over one file would lose one's),
    // written at the next save. A map or graph that failed to load has nothing to copy.
    std::set<fs::path> used;
    for (const BodyDesc& b : project.bodies) {
        for (MapChannel c : kMapChannels) {
            if (!channelPath(b, c).empty()) used.insert(project.resolvePath(channelPath(b, c)));
        }
        if (b.waterGraph) used.insert(project.resolvePath(b.waterGraph->graph));
    }
    auto freePath = [&](const std::string& wanted) {
        const fs::path w(wanted);
        std::string path = wanted;
        for (int k = 2;; ++k) {
            std::error_code ec;
            const fs::path resolved = project.resolvePath(path);
            if (!used.count(resolved) && !fs::exists(resolved, ec)) {
                used.insert(resolved);
                return path;
            }
            const std::string name = w.filename().string();
            const auto dot = name.find('.');
            path = (w.parent_path() / (name.substr(0, dot) + "_" + std::to_string(k) +
                                       (dot == std::string::npos ? "" : name.substr(dot))))
                       .generic_string();
        }
    };
    DetachedAssets copies;
    const BodyAssets& source = document.assets(body);
    for (MapChannel c : kMapChannels) {
        std::string& path = channelPath(copy, c);
        const BodyAssets::Map& original = source.maps[static_cast<int>(c)];
        if (path.empty()) continue;
        if (!original.image) {
            path.clear();
            continue;
        }
        path = freePath(document.defaultMapPath(copy.name, c));
        BodyAssets::Map map = original;
        map.path = project.resolvePath(path);
        map.dirty = true;
        copies.maps[map.path] = std::move(map);
    }
    if (copy.waterGraph) {
        if (const WaterGraph* graph = document.graph(body)) {
            copy.waterGraph->graph = freePath(document.defaultGraphPath(copy.name));
            copies.graphs[project.resolvePath(copy.waterGraph->graph)] = *graph;
        } else {
            copy.waterGraph.reset();
        }
    }
    project.bodies.insert(project.bodies.begin() + static_cast<std::ptrdiff_t>(body) + 1, copy);
    return std::unique_ptr<Command>(std::make_unique<ProjectCommand>(
        "Duplicate " + bodyLabel(project.bodies[body], body), document.project(),
        std::move(project), std::move(copies)));
}

Result<std::unique_ptr<Command>> makeRemoveBodyCommand(const Document& document, std::size_t body) {
    if (Status ok = checkBody(document, body); !ok) return ok.error();
    Project project = document.project();
    const std::string name = bodyLabel(project.bodies[body], body);
    project.bodies.erase(project.bodies.begin() + static_cast<std::ptrdiff_t>(body));
    return std::unique_ptr<Command>(
        std::make_unique<ProjectCommand>("Remove " + name, document.project(), std::move(project)));
}

Result<std::unique_ptr<Command>> makeSetBodyTransformCommand(
    const Document& document, std::size_t body, const Eigen::Vector3d& position,
    const Eigen::Vector3d& rotationDegrees) {
    if (Status ok = checkBody(document, body); !ok) return ok.error();
    if (!position.allFinite() || !rotationDegrees.allFinite()) {
        return makeError(ErrorKind::invalidArgument,
                         "a body's position and rotation must be finite numbers");
    }
    Project project = document.project();
    BodyDesc& b = project.bodies[body];
    const bool moved = b.position != position, turned = b.rotationDegrees != rotationDegrees;
    b.position = position;
    b.rotationDegrees = rotationDegrees;
    const std::string verb = moved && turned ? "Move and rotate " : turned ? "Rotate " : "Move ";
    return std::unique_ptr<Command>(std::make_unique<ProjectCommand>(
        verb + bodyLabel(b, body), document.project(), std::move(project)));
}

Result<std::unique_ptr<Command>> makeSetCapCommand(const Document& document, std::size_t body,
                                                   std::size_t cap, const CapDesc& settings) {
    if (Status ok = checkBody(document, body); !ok) return ok.error();
    if (settings.height && !std::isfinite(*settings.height))
        return makeError(ErrorKind::invalidArgument, "a cap's height must be a finite number");
    if (settings.mode == OpeningsMode::None)
        return makeError(ErrorKind::invalidArgument,
                         "a cap is open or sealed (\"none\" is the body's openings)");
    if (cap > 4096)
        return makeError(ErrorKind::invalidArgument, "no opening " + std::to_string(cap + 1));
    Project project = document.project();
    BodyDesc& b = project.bodies[body];
    const CapDesc before = cap < b.caps.size() ? b.caps[cap] : CapDesc{};
    if (before == settings)
        return makeError(ErrorKind::invalidArgument, "the cap is already so: nothing to change");
    if (b.caps.size() <= cap) b.caps.resize(cap + 1);
    b.caps[cap] = settings;
    while (!b.caps.empty() && b.caps.back() == CapDesc{}) b.caps.pop_back();
    std::string verb = "Set ";
    if (before.height == settings.height)
        verb = settings.mode == OpeningsMode::Sealed ? "Seal "
               : settings.mode == OpeningsMode::Open ? "Open "
                                                     : "Set ";
    else if (before.mode == settings.mode)
        verb = "Move ";
    return std::unique_ptr<Command>(std::make_unique<ProjectCommand>(
        verb + bodyLabel(b, body) + " cap " + std::to_string(cap + 1), document.project(),
        std::move(project)));
}

}  // namespace plimsoll::editor
