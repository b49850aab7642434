#include "document/document.h"
#include "plimsoll/io/json_depth.h"

#include "document/settings.h"

#include "plimsoll/io/atlas_cache.h"
#include "plimsoll/surface/atlas.h"
#include "plimsoll/io/painted_map_io.h"
#include "plimsoll/io/graph_json.h"
#include "plimsoll/surface/painted_map.h"
#include "plimsoll/core/limits.h"
#include "plimsoll/io/file_util.h"
#include "plimsoll/io/mesh_io.h"
#include "plimsoll/project/scene_loader.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <fstream>
#include <iterator>
#include <map>
#include <set>
#include <sstream>

namespace plimsoll::editor {

namespace fs = std::filesystem;
using Json = nlohmann::json;

const char* channelName(MapChannel channel) {
    switch (channel) {
        case MapChannel::Permeability:
            return "permeability";
        case MapChannel::Density:
            return "density";
        case MapChannel::Thickness:
            return "thickness";
    }
    return "?";
}

std::optional<MapChannel> parseChannel(std::string_view name) {
    for (MapChannel c : kMapChannels) {
        if (name == channelName(c)) return c;
    }
    return std::nullopt;
}

std::string& channelPath(BodyDesc& body, MapChannel channel) {
    switch (channel) {
        case MapChannel::Permeability:
            return body.permeabilityMap;
        case MapChannel::Density:
            return body.material.shellDensityMap;
        case MapChannel::Thickness:
            return body.material.shellThicknessMap;
    }
    return body.permeabilityMap;
}

const std::string& channelPath(const BodyDesc& body, MapChannel channel) {
    return channelPath(const_cast<BodyDesc&>(body), channel);
}

bool channelNeedsShell(MapChannel channel) { return channel != MapChannel::Permeability; }

namespace {

/// A graph file parsed for editing: structure checked, validity not (validateGraph is the
/// graph panel's and World's business).
Result<WaterGraph> readGraphForEditing(const fs::path& path) {
    Result<std::string> text = readWholeFile(path, kMaxJsonFileBytes, "kMaxJsonFileBytes");
    if (!text) return text.error();
    return parseGraph(*text, path.string());
}

/// A map file and, when one is beside it, its layer stack. A side file that does not flatten
/// to the map (the PNG was changed by another program) is set aside with a note: the PNG is
/// what the engine reads.
void loadMapFile(BodyAssets::Map& m) {
    Result<PaintedMap> image = loadPaintedMap(m.path);
    if (!image) {
        m.error = image.error().message;
        return;
    }
    m.image = std::move(image).value();
    const fs::path side = layersPathFor(m.path);
    std::error_code ec;
    if (!fs::exists(side, ec)) return;
    Result<std::string> text = readWholeFile(side, kMaxLayersFileBytes, "kMaxLayersFileBytes");
    if (!text) {
        m.error = text.error().message + " (layers not loaded)";
        return;
    }
    Result<LayerStack> stack = parseLayerStack(*text, side.string());
    if (!stack) {
        m.error = stack.error().message + " (layers not loaded)";
        return;
    }
    if (stack->width != m.image->width || stack->height != m.image->height ||
        encodePaintedMapPng16(flattenLayers(*stack)) != encodePaintedMapPng16(*m.image)) {
        m.error = side.string() + ": its layers do not flatten to " + m.path.filename().string() +
                  " (changed by another program?); layers not loaded";
        return;
    }
    m.layers = std::move(stack).value();
}

/// `path` (as written, relative to `from`) rewritten relative to `to`.
std::string rebase(const std::string& path, const fs::path& from, const fs::path& to) {
    if (path.empty() || fs::path(path).is_absolute()) return path;
    const fs::path absolute = (from / path).lexically_normal();
    const fs::path relative = absolute.lexically_relative(to);
    return relative.empty() ? absolute.string() : relative.generic_string();
}

}  // namespace

Document::Document() {
    project_.name = "untitled";
    std::error_code ec;
    project_.folder = fs::current_path(ec);
}

Result<std::unique_ptr<Document>> Document::open(const fs::path& path) {
    Result<Project> project = loadProject(path);
    if (!project) return project.error();
    auto document = std::make_unique<Document>();
    document->path_ = fs::absolute(path).lexically_normal();
    document->project_ = std::move(project).value();
    document->project_.folder = document->path_.parent_path();
    DetachedAssets none;
    document->syncAssets(none);
    return document;
}

std::string Document::title() const {
    const std::string name = path_.empty() ? "untitled" : path_.filename().string();
    return (dirty() ? "*" : "") + name;
}

void Document::setProject(Project project, DetachedAssets& detached) {
    project.folder = project_.folder;
    project_ = std::move(project);
    syncAssets(detached);
}

void Document::syncAssets(DetachedAssets& detached) {
    // Bodies removed or shifted (a body removed or inserted before them): their unsaved maps
    // and graphs are set aside by path first, before the resize drops the last ones, so that
    // the body's new index (or the undo that brings it back) finds them below.
    for (std::size_t b = 0; b < assets_.size(); ++b) {
        const BodyDesc* now = b < project_.bodies.size() ? &project_.bodies[b] : nullptr;
        for (MapChannel c : kMapChannels) {
            BodyAssets::Map& m = assets_[b].maps[static_cast<int>(c)];
            const std::string written = now ? channelPath(*now, c) : std::string();
            const fs::path mapPath = written.empty() ? fs::path() : project_.resolvePath(written);
            if (mapPath == m.path || !m.dirty || !m.image || m.path.empty()) continue;
            detached.maps[m.path] = std::move(m);
            m = BodyAssets::Map{};
            assets_[b].paintSurfaces[static_cast<int>(c)].reset();
        }
        BodyAssets::Graph& g = assets_[b].graph;
        const fs::path graphPath = now && now->waterGraph && !now->waterGraph->graph.empty()
                                       ? project_.resolvePath(now->waterGraph->graph)
                                       : fs::path();
        if (graphPath != g.path && g.dirty && g.graph && !g.path.empty()) {
            detached.graphs[g.path] = *g.graph;
            g = BodyAssets::Graph{};
        }
    }
    assets_.resize(project_.bodies.size());
    for (std::size_t b = 0; b < assets_.size(); ++b) {
        const BodyDesc& body = project_.bodies[b];
        BodyAssets& a = assets_[b];
        const fs::path meshPath = body.mesh.empty() ? fs::path() : project_.resolvePath(body.mesh);
        if (meshPath != a.meshPath || body.atlas != a.atlas || body.unitScale != a.unitScale ||
            (!a.mesh && a.meshError.empty())) {
            a.meshPath = meshPath;
            a.atlas = body.atlas;
            a.unitScale = body.unitScale;
            a.mesh.reset();
            a.meshError.clear();
            a.paintSurfaces = {};
            a.physics.reset();
            a.levelChoice.reset();
            if (!meshPath.empty()) {
                Result<TriangleMesh> mesh =
                    loadMesh(meshPath, MeshLoadOptions{.unitScale = body.unitScale});
                if (mesh) {
                    // Painted maps lie over the UVs the body bakes: the same choice as World's
                    // (the generated atlas comes from the project's cache once made).
                    Result<AtlasChoice> choice =
                        chooseCachedAtlas(*mesh, validateMesh(*mesh), body.atlas, AtlasSettings{},
                                          project_.atlasCacheFile(b));
                    if (choice)
                        a.mesh = std::make_shared<const TriangleMesh>(std::move(choice->mesh));
                    else
                        a.meshError = choice.error().message;
                } else {
                    a.meshError = mesh.error().message;
                }
            }
        }
        if (a.levelChoice && !levelChoice(b)) a.levelChoice.reset();
        if (a.physics && (a.physics->size != physicsBakeSettings(b).size)) a.physics.reset();
        for (MapChannel c : kMapChannels) {
            BodyAssets::Map& m = a.maps[static_cast<int>(c)];
            const std::string& written = channelPath(body, c);
            const fs::path mapPath = written.empty() ? fs::path() : project_.resolvePath(written);
            if (mapPath == m.path) continue;
            if (m.dirty && m.image && !m.path.empty()) detached.maps[m.path] = std::move(m);
            m = BodyAssets::Map{};
            m.path = mapPath;
            a.paintSurfaces[static_cast<int>(c)].reset();
            if (mapPath.empty()) continue;
            if (auto it = detached.maps.find(mapPath); it != detached.maps.end()) {
                m = std::move(it->second);
                detached.maps.erase(it);
            } else if (fs::exists(mapPath)) {
                loadMapFile(m);
            } else {
                m.error = mapPath.string() + ": no such file (yet)";
            }
        }
        BodyAssets::Graph& g = a.graph;
        const fs::path graphPath = body.waterGraph && !body.waterGraph->graph.empty()
                                       ? project_.resolvePath(body.waterGraph->graph)
                                       : fs::path();
        if (graphPath != g.path) {
            if (g.dirty && g.graph && !g.path.empty()) detached.graphs[g.path] = *g.graph;
            g = BodyAssets::Graph{};
            g.path = graphPath;
            if (graphPath.empty()) continue;
            std::error_code ec;
            if (auto it = detached.graphs.find(graphPath); it != detached.graphs.end()) {
                g.graph = std::move(it->second);
                g.dirty = true;
                detached.graphs.erase(it);
            } else if (fs::exists(graphPath, ec)) {
                Result<WaterGraph> read = readGraphForEditing(graphPath);
                if (read)
                    g.graph = std::move(read).value();
                else
                    g.error = read.error().message;
            } else {
                g.error = graphPath.string() + ": no such file (yet)";
            }
        }
    }
}

const WaterGraph* Document::graph(std::size_t body) const {
    if (body >= assets_.size() || !assets_[body].graph.graph) return nullptr;
    return &*assets_[body].graph.graph;
}

void Document::setGraph(std::size_t body, std::optional<WaterGraph> graph) {
    BodyAssets::Graph& g = assets_.at(body).graph;
    g.graph = std::move(graph);
    g.dirty = true;
    g.error.clear();
}

std::string Document::assetFileStem(std::size_t body) const {
    std::string bodyName = body < project_.bodies.size() ? project_.bodies[body].name : "";
    return assetFileStem(bodyName.empty() ? "body" + std::to_string(body) : bodyName);
}

std::string Document::assetFileStem(std::string bodyName) const {
    std::string stem = path_.empty() ? "untitled" : path_.filename().string();
    if (const auto dot = stem.find('.'); dot != std::string::npos) stem.resize(dot);
    for (char& ch : bodyName) {
        if (!std::isalnum(static_cast<unsigned char>(ch)) && ch != '-') ch = '_';
    }
    return stem + "_" + bodyName;
}

std::string Document::defaultGraphPath(std::size_t body) const {
    return assetFileStem(body) + ".graph.json";
}

std::string Document::defaultGraphPath(const std::string& bodyName) const {
    return assetFileStem(bodyName) + ".graph.json";
}

PaintedMap* Document::map(std::size_t body, MapChannel channel) {
    if (body >= assets_.size()) return nullptr;
    auto& image = assets_[body].maps[static_cast<int>(channel)].image;
    return image ? &*image : nullptr;
}

const PaintedMap* Document::map(std::size_t body, MapChannel channel) const {
    return const_cast<Document*>(this)->map(body, channel);
}

void Document::setMap(std::size_t body, MapChannel channel, std::optional<PaintedMap> image) {
    BodyAssets::Map& m = assets_.at(body).maps[static_cast<int>(channel)];
    const bool sizeChanged =
        !image || !m.image || image->width != m.image->width || image->height != m.image->height;
    m.image = std::move(image);
    m.dirty = true;
    m.error.clear();
    if (sizeChanged) assets_[body].paintSurfaces[static_cast<int>(channel)].reset();
}

const LayerStack* Document::layers(std::size_t body, MapChannel channel) const {
    if (body >= assets_.size()) return nullptr;
    const auto& stack = assets_[body].maps[static_cast<int>(channel)].layers;
    return stack ? &*stack : nullptr;
}

void Document::setLayers(std::size_t body, MapChannel channel, std::optional<LayerStack> stack) {
    BodyAssets::Map& m = assets_.at(body).maps[static_cast<int>(channel)];
    m.layers = std::move(stack);
    if (m.layers)
        setMap(body, channel, flattenLayers(*m.layers));
    else
        m.dirty = true;
}

PaintedMap* Document::paintPixels(std::size_t body, MapChannel channel, PaintTarget target) {
    if (body >= assets_.size()) return nullptr;
    BodyAssets::Map& m = assets_[body].maps[static_cast<int>(channel)];
    if (!m.layers) {
        return target.layer < 0 && target.part == LayerPart::Pixels && m.image ? &*m.image
                                                                               : nullptr;
    }
    if (target.layer < 0 || static_cast<std::size_t>(target.layer) >= m.layers->layers.size()) {
        return nullptr;
    }
    return m.layers->layers[static_cast<std::size_t>(target.layer)].part(target.part).get();
}

void Document::pixelsChanged(std::size_t body, MapChannel channel) {
    BodyAssets::Map& m = assets_.at(body).maps[static_cast<int>(channel)];
    if (m.layers) m.image = flattenLayers(*m.layers);
    m.dirty = true;
}

BodyAssets::Map Document::mapState(std::size_t body, MapChannel channel) const {
    return assets_.at(body).maps[static_cast<int>(channel)];
}

void Document::restoreMapState(std::size_t body, MapChannel channel, BodyAssets::Map state) {
    BodyAssets::Map& m = assets_.at(body).maps[static_cast<int>(channel)];
    const bool sizeChanged = !state.image || !m.image || state.image->width != m.image->width ||
                             state.image->height != m.image->height;
    m = std::move(state);
    if (sizeChanged) assets_[body].paintSurfaces[static_cast<int>(channel)].reset();
}

Result<std::shared_ptr<const PaintSurface>> Document::paintSurface(std::size_t body,
                                                                   MapChannel channel) {
    if (body >= assets_.size())
        return makeError(ErrorKind::invalidArgument, "no body " + std::to_string(body));
    BodyAssets& a = assets_[body];
    if (!a.mesh)
        return makeError(ErrorKind::invalidArgument,
                         "body " + std::to_string(body) + ": no mesh (" + a.meshError + ")");
    const PaintedMap* image = map(body, channel);
    if (!image)
        return makeError(ErrorKind::invalidArgument,
                         "body " + std::to_string(body) + ": no " + channelName(channel) + " map");
    auto& cached = a.paintSurfaces[static_cast<int>(channel)];
    if (!cached || cached->width != image->width || cached->height != image->height) {
        // Maps of the same size share one surface.
        for (const auto& other : a.paintSurfaces) {
            if (other && other->width == image->width && other->height == image->height) {
                cached = other;
            }
        }
        if (!cached || cached->width != image->width || cached->height != image->height) {
            Result<PaintSurface> built = buildPaintSurface(*a.mesh, image->width, image->height);
            if (!built) return built.error();
            cached = std::make_shared<const PaintSurface>(std::move(built).value());
        }
    }
    return cached;
}

Pose Document::bodyPose(std::size_t body) const {
    const BodyDesc& b = project_.bodies.at(body);
    return Pose::fromEulerDegrees(b.position, b.rotationDegrees);
}

Bounds3 Document::worldBounds() const {
    Bounds3 bounds;
    for (std::size_t b = 0; b < assets_.size(); ++b) {
        if (!assets_[b].mesh) continue;
        const Pose pose = bodyPose(b);
        for (const Eigen::Vector3d& p : assets_[b].mesh->positions) {
            const Eigen::Vector3d w = pose.apply(p);
            bounds.min = bounds.min.cwiseMin(w);
            bounds.max = bounds.max.cwiseMax(w);
        }
    }
    return bounds;
}

Result<std::shared_ptr<const SurfaceTextures>> Document::physicsTextures(std::size_t body) {
    if (body >= assets_.size())
        return makeError(ErrorKind::invalidArgument, "no body " + std::to_string(body));
    BodyAssets& a = assets_[body];
    if (!a.mesh)
        return makeError(ErrorKind::invalidArgument,
                         "body " + std::to_string(body) + ": no mesh (" + a.meshError + ")");
    if (!a.physics) {
        const BakeSettings settings = physicsBakeSettings(body);
        if (settings.size == 0) {
            Result<LevelChoice> choice =
                chooseLevelForTolerance(*a.mesh, *project_.bodies[body].tolerance, settings);
            if (!choice) return choice.error();
            std::shared_ptr<const SurfaceTextures> textures = std::move(choice->textures);
            adoptLevelChoice(body, a.mesh.get(), settings, *choice);
            a.physics = std::move(textures);
            return a.physics;
        }
        Result<SurfaceTextures> baked = bakeSurfaceTextures(*a.mesh, settings);
        if (!baked) return baked.error();
        a.physics = std::make_shared<const SurfaceTextures>(std::move(baked).value());
    }
    return a.physics;
}

BakeSettings Document::physicsBakeSettings(std::size_t body) const {
    const BodyDesc& desc = project_.bodies[body];
    BakeSettings settings;
    settings.maxTexelStretch = desc.maxTexelStretch;
    if (!desc.tolerance)
        settings.size = desc.textureSize;
    else if (const std::optional<LevelChoice> choice = levelChoice(body))
        settings.size = choice->size;
    else
        settings.size = 0;
    return settings;
}

std::optional<LevelChoice> Document::levelChoice(std::size_t body) const {
    if (body >= assets_.size() || body >= project_.bodies.size()) return std::nullopt;
    const BodyAssets& a = assets_[body];
    const BodyDesc& desc = project_.bodies[body];
    if (!a.levelChoice || !desc.tolerance || a.levelChoice->tolerance != *desc.tolerance ||
        a.levelChoiceStretch != desc.maxTexelStretch) {
        return std::nullopt;
    }
    return a.levelChoice;
}

bool Document::adoptLevelChoice(std::size_t body, const TriangleMesh* mesh,
                                const BakeSettings& settings, const LevelChoice& choice) {
    if (body >= assets_.size() || !mesh || assets_[body].mesh.get() != mesh) return false;
    const BodyDesc& desc = project_.bodies[body];
    if (!desc.tolerance || *desc.tolerance != choice.tolerance ||
        desc.maxTexelStretch != settings.maxTexelStretch) {
        return false;
    }
    LevelChoice kept = choice;
    kept.textures.reset();
    assets_[body].levelChoice = std::move(kept);
    assets_[body].levelChoiceStretch = settings.maxTexelStretch;
    return true;
}

std::shared_ptr<const SurfaceTextures> Document::bakedPhysics(std::size_t body) const {
    return body < assets_.size() ? assets_[body].physics : nullptr;
}

bool Document::adoptPhysics(std::size_t body, const TriangleMesh* mesh,
                            const BakeSettings& settings,
                            std::shared_ptr<const SurfaceTextures> textures) {
    if (body >= assets_.size() || !textures || !mesh || assets_[body].mesh.get() != mesh)
        return false;
    const BakeSettings now = physicsBakeSettings(body);
    if (now.size != settings.size || now.maxTexelStretch != settings.maxTexelStretch ||
        textures->size != settings.size) {
        return false;
    }
    assets_[body].physics = std::move(textures);
    return true;
}

std::string Document::defaultMapPath(std::size_t body, MapChannel channel) const {
    return "maps/" + assetFileStem(body) + "_" + channelName(channel) + ".png";
}

std::string Document::defaultMapPath(const std::string& bodyName, MapChannel channel) const {
    return "maps/" + assetFileStem(bodyName) + "_" + channelName(channel) + ".png";
}

// --- history ------------------------------------------------------------------------------------

Status Document::execute(std::unique_ptr<Command> command) {
    Status applied = command->apply(*this);
    if (!applied) return applied;
    done_.push_back({std::move(command), nextId_++});
    undone_.clear();
    return Ok{};
}

std::string Document::undoName() const { return done_.empty() ? "" : done_.back().command->name(); }
std::string Document::redoName() const {
    return undone_.empty() ? "" : undone_.back().command->name();
}

bool Document::undo() {
    if (done_.empty()) return false;
    done_.back().command->revert(*this);
    undone_.push_back(std::move(done_.back()));
    done_.pop_back();
    return true;
}

bool Document::redo() {
    if (undone_.empty()) return false;
    if (!undone_.back().command->apply(*this)) return false;
    done_.push_back(std::move(undone_.back()));
    undone_.pop_back();
    return true;
}

std::vector<std::string> Document::historyNames() const {
    std::vector<std::string> names;
    names.reserve(done_.size() + undone_.size());
    for (const Entry& e : done_) names.push_back(e.command->name());
    for (auto it = undone_.rbegin(); it != undone_.rend(); ++it)
        names.push_back(it->command->name());
    return names;
}

bool Document::jumpToHistory(std::size_t position) {
    position = std::min(position, done_.size() + undone_.size());
    while (done_.size() > position) undo();
    while (done_.size() < position) {
        if (!redo()) return false;
    }
    return true;
}

// --- files ---------------------------------------------------------------------------------------

Status Document::writeMaps(bool all) { return writeMapsAndProjectFiles(all, false); }

namespace {
/// Whether `file` lies inside `folder` by its path (no "..", not elsewhere absolutely).
bool liesInside(const fs::path& file, const fs::path& folder) {
    const fs::path r = fs::absolute(file).lexically_normal().lexically_relative(
        fs::absolute(folder).lexically_normal());
    return !r.empty() && r != "." && *r.begin() != "..";
}

/// `wanted` (relative to `folder`), or with "_2", "_3", ... before its extension: a name no
/// file in `folder` has yet.
std::string unusedName(const fs::path& folder, const std::string& wanted) {
    const fs::path w(wanted);
    std::error_code ec;
    std::string name = wanted;
    for (int n = 2; fs::exists(fs::symlink_status(folder / name, ec)); ++n)
        name = (w.parent_path() /
                (w.stem().string() + "_" + std::to_string(n) + w.extension().string()))
                   .generic_string();
    return name;
}
}  // namespace

bool Document::keepWritesInsideFolder(bool allMaps) {
    // A project writes only inside its folder: a map or graph read from elsewhere (an absolute
    // path, "../photos/x.png", a source asset) is saved under a new name in the folder, and
    // the project points at it; the file it was read from is never written.
    if (path_.empty()) return false;
    const fs::path folder = path_.parent_path();
    bool moved = false;
    for (std::size_t b = 0; b < assets_.size(); ++b) {
        for (MapChannel c : kMapChannels) {
            BodyAssets::Map& m = assets_[b].maps[static_cast<int>(c)];
            if (!m.image || m.path.empty() || !(m.dirty || allMaps) || liesInside(m.path, folder))
                continue;
            const std::string name = unusedName(folder, defaultMapPath(b, c));
            channelPath(project_.bodies[b], c) = name;
            m.path = folder / name;
            m.dirty = moved = true;
        }
        BodyAssets::Graph& g = assets_[b].graph;
        auto& desc = project_.bodies[b].waterGraph;
        if (g.graph && desc && !g.path.empty() && (g.dirty || allMaps) &&
            !liesInside(g.path, folder)) {
            desc->graph = unusedName(folder, defaultGraphPath(b));
            g.path = folder / desc->graph;
            g.dirty = moved = true;
        }
    }
    return moved;
}

Status Document::writeMapsAndProjectFiles(bool allMaps, bool withProject) {
    // The changed maps and water graphs and the project are replaced as one (file_util.h): a
    // failure at any step leaves every previous file as it was, so the project on disk never
    // names a map or graph of another save.
    if (keepWritesInsideFolder(allMaps)) withProject = true;  // the project names the new files
    std::vector<FileWriter> files;
    std::vector<BodyAssets::Map*> written;
    std::vector<BodyAssets::Graph*> writtenGraphs;
    for (BodyAssets& a : assets_) {
        for (BodyAssets::Map& m : a.maps) {
            if (!m.image || m.path.empty() || !(m.dirty || allMaps)) continue;
            std::error_code ec;
            fs::create_directories(m.path.parent_path(), ec);
            files.push_back(bytesFileWriter(m.path, encodePaintedMapPng16(*m.image)));
            if (m.layers)
                files.push_back(
                    bytesFileWriter(layersPathFor(m.path), layerStackToJson(*m.layers)));
            written.push_back(&m);
        }
        BodyAssets::Graph& g = a.graph;
        if (g.graph && !g.path.empty() && (g.dirty || allMaps)) {
            std::error_code ec;
            fs::create_directories(g.path.parent_path(), ec);
            files.push_back(bytesFileWriter(g.path, graphToJson(*g.graph)));
            writtenGraphs.push_back(&g);
        }
    }
    if (withProject) {
        files.push_back(bytesFileWriter(path_, projectToJson(project_) + "\n"));
    }
    if (files.empty()) return Ok{};
    Status saved = replaceFilesTogether(files);
    if (!saved) return saved;
    for (BodyAssets::Map* m : written) {
        m->dirty = false;
        m->error.clear();
    }
    for (BodyAssets::Graph* g : writtenGraphs) {
        g->dirty = false;
        g->error.clear();
    }
    return Ok{};
}

Status Document::save() {
    if (path_.empty())
        return makeError(ErrorKind::invalidArgument, "untitled: choose a file name (Save As)");
    return writeMapsAndProject(false);
}

Status Document::checkSaveAsTargets(const Project& moved, const fs::path& target,
                                    std::vector<fs::path>& replaced) const {
    auto same = [](const fs::path& a, const fs::path& b) {
        std::error_code ec;
        return fs::equivalent(a, b, ec) || a.lexically_normal() == b.lexically_normal();
    };
    // Every file the project reads and does not rewrite: meshes, and maps and graphs that are
    // not loaded (they keep pointing at their files).
    std::vector<std::pair<fs::path, std::string>> used;
    for (std::size_t b = 0; b < project_.bodies.size(); ++b) {
        const BodyDesc& body = project_.bodies[b];
        const std::string of = " of body '" + body.name + "'";
        if (!body.mesh.empty()) used.push_back({project_.resolvePath(body.mesh), "the mesh" + of});
        for (const std::string& frame : body.meshFrames)
            used.push_back({project_.resolvePath(frame), "a mesh frame" + of});
        for (MapChannel c : kMapChannels) {
            const std::string& p = channelPath(body, c);
            if (!p.empty() && !assets_[b].maps[static_cast<int>(c)].image)
                used.push_back({project_.resolvePath(p), "a painted map" + of});
        }
        if (body.waterGraph && !body.waterGraph->graph.empty() && !assets_[b].graph.graph)
            used.push_back({project_.resolvePath(body.waterGraph->graph), "the water graph" + of});
    }
    // What the save writes: the project and every loaded map and graph, at their new paths.
    std::vector<fs::path> written{target};
    for (std::size_t b = 0; b < moved.bodies.size(); ++b) {
        for (MapChannel c : kMapChannels) {
            const std::string& p = channelPath(moved.bodies[b], c);
            if (!p.empty() && assets_[b].maps[static_cast<int>(c)].image)
                written.push_back(moved.resolvePath(p));
        }
        const auto& graph = moved.bodies[b].waterGraph;
        if (graph && !graph->graph.empty() && assets_[b].graph.graph)
            written.push_back(moved.resolvePath(graph->graph));
    }
    std::vector<fs::path> ours{path_};  // files this document wrote itself: saved over freely
    for (const BodyAssets& a : assets_) {
        for (const BodyAssets::Map& m : a.maps) ours.push_back(m.path);
        ours.push_back(a.graph.path);
    }
    for (const fs::path& file : written) {
        for (const auto& [input, what] : used) {
            if (same(file, input))
                return makeError(ErrorKind::invalidArgument,
                                 file.string() + ": is " + what +
                                     ": saving over it would lose it (choose another name)");
        }
        std::error_code ec;
        const bool exists = fs::exists(fs::symlink_status(file, ec));
        const bool own = std::any_of(ours.begin(), ours.end(), [&](const fs::path& p) {
            return !p.empty() && same(file, p);
        });
        if (exists && !own) replaced.push_back(file);
    }
    return Ok{};
}

Result<std::vector<fs::path>> Document::replacedBySaveAs(const fs::path& target) const {
    const fs::path absolute = fs::absolute(target).lexically_normal();
    std::vector<fs::path> replaced;
    if (Status safe = checkSaveAsTargets(movedTo(absolute), absolute, replaced); !safe.ok())
        return safe.error();
    return replaced;
}

Project Document::movedTo(const fs::path& absolute) const {
    const fs::path from = project_.folder, to = absolute.parent_path();
    Project moved = project_;
    // Files that travel with the project keep their relative paths in the new folder, except
    // those outside the old folder ("../assets/x.png"): written as they are, they would land
    // outside the new folder and could overwrite another project's file. Those go into the
    // new folder under their file name (made unique).
    std::set<std::string> travelled;
    auto travelling = [&](const std::string& path, std::size_t body) {
        std::string kept = path;
        const fs::path normal = fs::path(path).lexically_normal();
        if (!normal.empty() && *normal.begin() == "..") kept = normal.filename().string();
        if (!travelled.insert(kept).second) {
            kept = "body" + std::to_string(body) + "_" + fs::path(kept).filename().string();
            travelled.insert(kept);
        }
        return kept;
    };
    for (BodyDesc& body : moved.bodies) {
        const std::size_t index = static_cast<std::size_t>(&body - moved.bodies.data());
        body.mesh = rebase(body.mesh, from, to);
        for (std::string& frame : body.meshFrames) frame = rebase(frame, from, to);
        // Maps travel with the project when loaded; one not loaded keeps pointing at its file.
        for (MapChannel c : kMapChannels) {
            std::string& p = channelPath(body, c);
            if (p.empty() || fs::path(p).is_absolute()) continue;
            const BodyAssets::Map& m = assets_[index].maps[static_cast<int>(c)];
            p = m.image ? travelling(p, index) : rebase(p, from, to);
        }
        // So does the water graph.
        if (body.waterGraph && !body.waterGraph->graph.empty() &&
            !fs::path(body.waterGraph->graph).is_absolute()) {
            body.waterGraph->graph = assets_[index].graph.graph
                                         ? travelling(body.waterGraph->graph, index)
                                         : rebase(body.waterGraph->graph, from, to);
        }
    }
    moved.folder = to;
    return moved;
}

Status Document::saveAs(const fs::path& target, bool overwrite) {
    const fs::path absolute = fs::absolute(target).lexically_normal();
    const fs::path oldAutosave = autosavePath();
    Project moved = movedTo(absolute);
    std::vector<fs::path> replaced;
    if (Status safe = checkSaveAsTargets(moved, absolute, replaced); !safe.ok()) return safe;
    if (!replaced.empty() && !overwrite)
        return makeError(
            ErrorKind::invalidArgument,
            replaced.front().string() + ": already exists (save with force to replace it)");
    Project previous = std::move(project_);
    const fs::path previousPath = path_;
    const bool ownedAutosave = ownsAutosave_;
    project_ = std::move(moved);
    path_ = absolute;
    pointAssetsAtProject(true);
    ownsAutosave_ = false;  // an autosave at the new path is another session's
    Status saved = writeMapsAndProject(true);
    if (!saved) {
        // Nothing was written (replaceFilesTogether): the document stays the one it was, its
        // autosave in place.
        project_ = std::move(previous);
        path_ = previousPath;
        pointAssetsAtProject(false);
        ownsAutosave_ = ownedAutosave;
        return saved;
    }
    // Only now, the save in place, is the autosave of the previous name obsolete.
    if (ownedAutosave) {
        std::error_code ec;
        fs::remove(oldAutosave, ec);
    }
    return Ok{};
}

void Document::pointAssetsAtProject(bool markLoadedDirty) {
    for (std::size_t b = 0; b < assets_.size(); ++b) {
        assets_[b].meshPath = project_.bodies[b].mesh.empty()
                                  ? fs::path()
                                  : project_.resolvePath(project_.bodies[b].mesh);
        for (MapChannel c : kMapChannels) {
            const std::string& p = channelPath(project_.bodies[b], c);
            BodyAssets::Map& m = assets_[b].maps[static_cast<int>(c)];
            m.path = p.empty() ? fs::path() : project_.resolvePath(p);
            if (m.image && markLoadedDirty) m.dirty = true;
        }
        BodyAssets::Graph& g = assets_[b].graph;
        const auto& desc = project_.bodies[b].waterGraph;
        g.path = desc && !desc->graph.empty() ? project_.resolvePath(desc->graph) : fs::path();
        if (g.graph && markLoadedDirty) g.dirty = true;
    }
}

Status Document::writeMapsAndProject(bool allMaps) {
    Status saved = writeMapsAndProjectFiles(allMaps, true);
    if (!saved) return saved;
    savedState_ = stateId();
    if (ownsAutosave_) discardAutosave();
    return Ok{};
}

Result<Scene> Document::simulationScene(const LogFunction& log) const {
    Scene scene;
    scene.name = project_.name;
    scene.medium = project_.medium;
    scene.water = project_.water;
    scene.simulation = project_.simulation;
    for (std::size_t b = 0; b < assets_.size(); ++b) {
        const BodyDesc& desc = project_.bodies[b];
        const BodyAssets& a = assets_[b];
        const std::string label = bodyLabel(desc);
        // The body as a project run prepares it (its physics solid, openings and all), with the
        // document's maps and graph, painted over the mesh the document holds.
        Result<PreparedBodyMesh> prepared = [&]() -> Result<PreparedBodyMesh> {
            // The document reads a mesh joining its vertices; a deforming body's first frame
            // must keep its frames' triangles: both come from the files, as a project run does.
            if (desc.deforms()) return prepareBodyMesh(project_, b);
            if (!a.mesh)
                return makeError(ErrorKind::io,
                                 label + ": " + (a.meshError.empty() ? "no mesh" : a.meshError));
            return prepareLoadedBodyMesh(project_, b, *a.mesh, /*uvsChosen=*/true);
        }();
        if (!prepared) return prepared.error();
        BodyPaint paint;
        if (!desc.deforms()) paint.paintedOver = a.mesh;
        if (desc.waterGraph) {
            if (!a.graph.graph) {
                return makeError(ErrorKind::io,
                                 label + ": water graph: " +
                                     (a.graph.error.empty() ? "not loaded" : a.graph.error));
            }
            // Edited graphs are parsed, not validated: a simulation needs a valid one.
            const GraphReport report =
                validateGraph(*a.graph.graph, &prepared->mesh, a.graph.path.string());
            if (report.hasErrors()) {
                return makeError(ErrorKind::schema, label + ": water graph: " + report.format());
            }
            if (log && !report.problems.empty()) log(report.format());
            paint.waterGraph = std::make_shared<const WaterGraph>(*a.graph.graph);
        }
        for (MapChannel c : kMapChannels) {
            const BodyAssets::Map& m = a.maps[static_cast<int>(c)];
            std::shared_ptr<const PaintedMap> image;
            if (m.image) {
                image = std::make_shared<const PaintedMap>(*m.image);
            } else if (!channelPath(desc, c).empty()) {
                return makeError(ErrorKind::io, label + ": " + channelName(c) + " map: " +
                                                    (m.error.empty() ? "not loaded" : m.error));
            }
            switch (c) {
                case MapChannel::Permeability:
                    paint.permeabilityMap = std::move(image);
                    break;
                case MapChannel::Density:
                    paint.shellDensityMap = std::move(image);
                    break;
                case MapChannel::Thickness:
                    paint.shellThicknessMap = std::move(image);
                    break;
            }
        }
        BodyDesc bodyDesc = desc;
        Result<BodyParts> assembled = assembleBodyParts(bodyDesc, std::move(*prepared), paint, log);
        if (!assembled) return assembled.error();
        BodyParts parts = std::move(*assembled);
        if (desc.deforms()) {
            Result<std::shared_ptr<const std::vector<TriangleMesh>>> frames =
                loadBodyFrames(project_, b);
            if (!frames) return frames.error();
            parts.frames = std::move(*frames);
        }
        Result<SceneBody> body = bakeSceneBody(bodyDesc, std::move(parts));
        if (!body) return body.error();
        scene.bodies.push_back(std::move(*body));
    }
    return scene;
}

fs::path Document::autosavePathFor(const fs::path& projectPath) {
    return projectPath.parent_path() / ("." + projectPath.filename().string() + ".autosave");
}

fs::path Document::autosavePath() const {
    if (path_.empty()) return userConfigDir() / "untitled.plim.json.autosave";
    return autosavePathFor(path_);
}

Status Document::autosave() const {
    Json root;
    root["plimsoll_autosave"] = 1;
    root["project_path"] = path_.string();
    root["folder"] = project_.folder.string();
    root["project"] = Json::parse(projectToJson(project_));
    Json maps = Json::array();
    for (std::size_t b = 0; b < assets_.size(); ++b) {
        for (MapChannel c : kMapChannels) {
            const BodyAssets::Map& m = assets_[b].maps[static_cast<int>(c)];
            if (!m.image || !m.dirty) continue;
            Json entry = {{"body", b},
                          {"channel", channelName(c)},
                          {"png_base64", base64Encode(encodePaintedMapPng16(*m.image))}};
            if (m.layers) entry["layers"] = Json::parse(layerStackToJson(*m.layers));
            maps.push_back(std::move(entry));
        }
    }
    root["maps"] = std::move(maps);
    Json graphs = Json::array();
    for (std::size_t b = 0; b < assets_.size(); ++b) {
        const BodyAssets::Graph& g = assets_[b].graph;
        if (g.graph && g.dirty) graphs.push_back({{"body", b}, {"graph", graphToJson(*g.graph)}});
    }
    root["graphs"] = std::move(graphs);
    const fs::path target = autosavePath();
    std::error_code ec;
    fs::create_directories(target.parent_path(), ec);
    const std::string text = root.dump();
    Status written = writeFileAtomically(target, [&](std::ostream& out) {
        out << text;
        return static_cast<bool>(out);
    });
    if (written) ownsAutosave_ = true;
    return written;
}

void Document::discardAutosave() const {
    std::error_code ec;
    fs::remove(autosavePath(), ec);
    ownsAutosave_ = false;
}

namespace {
/// The project an autosave belongs to: NAME for ".NAME.autosave" beside it; none (untitled)
/// for the untitled autosave in the user's folder or a file of another name.
fs::path projectOfAutosave(const fs::path& autosaveFile) {
    const fs::path file = fs::absolute(autosaveFile).lexically_normal();
    const std::string name = file.filename().string();
    const std::string suffix = ".autosave";
    if (name.size() <= 1 + suffix.size() || name.front() != '.' ||
        name.compare(name.size() - suffix.size(), suffix.size(), suffix) != 0)
        return {};
    if (file == fs::absolute(userConfigDir() / "untitled.plim.json.autosave").lexically_normal())
        return {};
    return file.parent_path() / name.substr(1, name.size() - 1 - suffix.size());
}
}  // namespace

std::optional<fs::path> Document::findAutosave(const fs::path& project) {
    const fs::path candidate = project.empty()
                                   ? userConfigDir() / "untitled.plim.json.autosave"
                                   : autosavePathFor(fs::absolute(project).lexically_normal());
    std::error_code ec;
    if (fs::exists(candidate, ec)) return candidate;
    return std::nullopt;
}

Result<std::unique_ptr<Document>> Document::recover(const fs::path& autosaveFile) {
    // Its maps are inline PNGs, so it may outgrow a JSON file's limit.
    Result<std::string> text = readWholeFile(autosaveFile, kMaxDataFileBytes, "kMaxDataFileBytes");
    if (!text) return text.error();
    if (Status depth = checkJsonDepth(*text, autosaveFile.string()); !depth) return depth.error();
    Json root;
    try {
        root = Json::parse(*text);
    } catch (const Json::exception& e) {
        return makeError(ErrorKind::format, autosaveFile.string() + ": not an autosave: " +
                                                boundedExcerpt(e.what(), 200));
    }
    if (!root.contains("plimsoll_autosave") || !root.contains("project")) {
        return makeError(ErrorKind::format, autosaveFile.string() + ": not an autosave");
    }
    // The project the autosave lies beside, not the paths it names: recovering and saving
    // writes the project the user opened, relative paths resolved in its folder.
    const fs::path projectPath = projectOfAutosave(autosaveFile);
    const fs::path folder = projectPath.empty() ? fs::path(root.value("folder", std::string()))
                                                : projectPath.parent_path();
    Result<Project> project = parseProject(root["project"].dump(), autosaveFile.string(), folder);
    if (!project) return project.error();
    auto document = std::make_unique<Document>();
    document->path_ = projectPath;
    document->ownsAutosave_ = true;  // saving the recovered document replaces it
    document->project_ = std::move(project).value();
    document->project_.folder = folder;
    DetachedAssets none;
    document->syncAssets(none);
    for (const Json& m : root["maps"]) {
        const std::size_t body = m.value("body", std::size_t{0});
        const std::optional<MapChannel> channel = parseChannel(m.value("channel", std::string()));
        if (!channel || body >= document->bodyCount()) continue;
        Result<PaintedMap> image = decodePaintedMap(
            base64Decode(m.value("png_base64", std::string())), autosaveFile.string());
        if (!image) return image.error();
        document->setMap(body, *channel, std::move(image).value());
        if (m.contains("layers")) {
            Result<LayerStack> stack =
                parseLayerStack(m["layers"].dump(), autosaveFile.string() + " (layers)");
            if (!stack) return stack.error();
            document->setLayers(body, *channel, std::move(stack).value());
        }
    }
    for (const Json& g : root.value("graphs", Json::array())) {
        const std::size_t body = g.value("body", std::size_t{0});
        if (body >= document->bodyCount()) continue;
        Result<WaterGraph> graph =
            parseGraph(g.value("graph", std::string()), autosaveFile.string() + " (graph)");
        if (!graph) return graph.error();
        document->setGraph(body, std::move(graph).value());
    }
    document->savedState_ = ~std::uint64_t{0};  // differs from every state: dirty
    return document;
}

}  // namespace plimsoll::editor
