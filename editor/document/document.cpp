#include "document/document.h"

#include "document/settings.h"

#include "plimsoll/atlas.h"
#include "plimsoll/file_util.h"
#include "plimsoll/mesh_io.h"

#include <nlohmann/json.hpp>
#include <stb_image.h>

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
        case MapChannel::Permeability: return "permeability";
        case MapChannel::Density: return "density";
        case MapChannel::Thickness: return "thickness";
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
        case MapChannel::Permeability: return body.permeabilityMap;
        case MapChannel::Density: return body.material.shellDensityMap;
        case MapChannel::Thickness: return body.material.shellThicknessMap;
    }
    return body.permeabilityMap;
}

const std::string& channelPath(const BodyDesc& body, MapChannel channel) {
    return channelPath(const_cast<BodyDesc&>(body), channel);
}

bool channelNeedsShell(MapChannel channel) { return channel != MapChannel::Permeability; }

namespace {

/// Images of dirty maps whose path left the project (an undone path change brings them back).
std::map<fs::path, PaintedMap>& detachedMaps() {
    static std::map<fs::path, PaintedMap> maps;
    return maps;
}

/// Edited graphs whose path left the project (an undone path change brings them back).
std::map<fs::path, WaterGraph>& detachedGraphs() {
    static std::map<fs::path, WaterGraph> graphs;
    return graphs;
}

/// A graph file parsed for editing: structure checked, validity not (validateGraph is the
/// graph panel's and World's business).
Result<WaterGraph> readGraphForEditing(const fs::path& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) return makeError(path.string() + ": cannot open");
    return parseGraph(std::string(std::istreambuf_iterator<char>(in), {}), path.string());
}

std::string base64Encode(const std::string& bytes) {
    static const char* alphabet =
        "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    std::string out;
    std::size_t i = 0;
    for (; i + 2 < bytes.size(); i += 3) {
        const unsigned v = (unsigned char)bytes[i] << 16 | (unsigned char)bytes[i + 1] << 8 |
                           (unsigned char)bytes[i + 2];
        for (int s = 18; s >= 0; s -= 6) out += alphabet[(v >> s) & 63];
    }
    if (i < bytes.size()) {
        unsigned v = (unsigned char)bytes[i] << 16;
        if (i + 1 < bytes.size()) v |= (unsigned char)bytes[i + 1] << 8;
        out += alphabet[(v >> 18) & 63];
        out += alphabet[(v >> 12) & 63];
        out += i + 1 < bytes.size() ? alphabet[(v >> 6) & 63] : '=';
        out += '=';
    }
    return out;
}

std::string base64Decode(const std::string& text) {
    std::string out;
    unsigned v = 0;
    int bits = 0;
    for (char c : text) {
        int d;
        if (c >= 'A' && c <= 'Z') d = c - 'A';
        else if (c >= 'a' && c <= 'z') d = c - 'a' + 26;
        else if (c >= '0' && c <= '9') d = c - '0' + 52;
        else if (c == '+') d = 62;
        else if (c == '/') d = 63;
        else continue;
        v = (v << 6) | d;
        bits += 6;
        if (bits >= 8) {
            bits -= 8;
            out += static_cast<char>((v >> bits) & 0xFF);
        }
    }
    return out;
}

Result<PaintedMap> decodePng(const std::string& bytes, const std::string& source) {
    int w = 0, h = 0, channels = 0;
    stbi_us* pixels =
        stbi_load_16_from_memory(reinterpret_cast<const stbi_uc*>(bytes.data()),
                                 static_cast<int>(bytes.size()), &w, &h, &channels, 1);
    if (!pixels) return makeError(source + ": cannot decode map: " + stbi_failure_reason());
    PaintedMap map;
    map.width = w;
    map.height = h;
    map.values.resize(static_cast<std::size_t>(w) * h);
    for (std::size_t i = 0; i < map.values.size(); ++i) map.values[i] = pixels[i] / 65535.0f;
    stbi_image_free(pixels);
    return map;
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
    document->syncAssets();
    return document;
}

std::string Document::title() const {
    const std::string name = path_.empty() ? "untitled" : path_.filename().string();
    return (dirty() ? "*" : "") + name;
}

void Document::setProject(Project project) {
    project.folder = project_.folder;
    project_ = std::move(project);
    syncAssets();
}

void Document::syncAssets() {
    assets_.resize(project_.bodies.size());
    for (std::size_t b = 0; b < assets_.size(); ++b) {
        const BodyDesc& body = project_.bodies[b];
        BodyAssets& a = assets_[b];
        const fs::path meshPath = body.mesh.empty() ? fs::path() : project_.resolvePath(body.mesh);
        if (meshPath != a.meshPath || body.atlas != a.atlas || (!a.mesh && a.meshError.empty())) {
            a.meshPath = meshPath;
            a.atlas = body.atlas;
            a.mesh.reset();
            a.meshError.clear();
            a.paintSurfaces = {};
            a.physics.reset();
            if (!meshPath.empty()) {
                Result<TriangleMesh> mesh = loadMesh(meshPath);
                if (mesh) {
                    // Painted maps lie over the UVs the body bakes: the same choice as World's
                    // (the generated atlas comes from the project's cache once made).
                    Result<AtlasChoice> choice = chooseAtlas(*mesh, validateMesh(*mesh), body.atlas,
                                                             AtlasSettings{},
                                                             project_.atlasCacheFile(b));
                    if (choice) a.mesh = std::make_shared<const TriangleMesh>(std::move(choice->mesh));
                    else a.meshError = choice.error().message;
                } else {
                    a.meshError = mesh.error().message;
                }
            }
        }
        if (a.physics && (a.physics->size != body.textureSize)) a.physics.reset();
        for (MapChannel c : kMapChannels) {
            BodyAssets::Map& m = a.maps[static_cast<int>(c)];
            const std::string& written = channelPath(body, c);
            const fs::path mapPath = written.empty() ? fs::path() : project_.resolvePath(written);
            if (mapPath == m.path) continue;
            if (m.dirty && m.image && !m.path.empty()) detachedMaps()[m.path] = *m.image;
            m = BodyAssets::Map{};
            m.path = mapPath;
            a.paintSurfaces[static_cast<int>(c)].reset();
            if (mapPath.empty()) continue;
            if (auto it = detachedMaps().find(mapPath); it != detachedMaps().end()) {
                m.image = it->second;
                m.dirty = true;
            } else if (fs::exists(mapPath)) {
                Result<PaintedMap> image = loadPaintedMap(mapPath);
                if (image) m.image = std::move(image).value();
                else m.error = image.error().message;
            } else {
                m.error = mapPath.string() + ": no such file (yet)";
            }
        }
        BodyAssets::Graph& g = a.graph;
        const fs::path graphPath = body.waterGraph && !body.waterGraph->graph.empty()
                                       ? project_.resolvePath(body.waterGraph->graph)
                                       : fs::path();
        if (graphPath != g.path) {
            if (g.dirty && g.graph && !g.path.empty()) detachedGraphs()[g.path] = *g.graph;
            g = BodyAssets::Graph{};
            g.path = graphPath;
            if (graphPath.empty()) continue;
            std::error_code ec;
            if (auto it = detachedGraphs().find(graphPath); it != detachedGraphs().end()) {
                g.graph = it->second;
                g.dirty = true;
            } else if (fs::exists(graphPath, ec)) {
                Result<WaterGraph> read = readGraphForEditing(graphPath);
                if (read) g.graph = std::move(read).value();
                else g.error = read.error().message;
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
    std::string stem = path_.empty() ? "untitled" : path_.filename().string();
    if (const auto dot = stem.find('.'); dot != std::string::npos) stem.resize(dot);
    std::string bodyName = body < project_.bodies.size() ? project_.bodies[body].name : "";
    if (bodyName.empty()) bodyName = "body" + std::to_string(body);
    for (char& ch : bodyName) {
        if (!std::isalnum(static_cast<unsigned char>(ch)) && ch != '-') ch = '_';
    }
    return stem + "_" + bodyName;
}

std::string Document::defaultGraphPath(std::size_t body) const {
    return assetFileStem(body) + ".graph.json";
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
    const bool sizeChanged = !image || !m.image || image->width != m.image->width ||
                             image->height != m.image->height;
    m.image = std::move(image);
    m.dirty = true;
    m.error.clear();
    if (sizeChanged) assets_[body].paintSurfaces[static_cast<int>(channel)].reset();
}

void Document::markMapDirty(std::size_t body, MapChannel channel) {
    assets_.at(body).maps[static_cast<int>(channel)].dirty = true;
}

Result<std::shared_ptr<const PaintSurface>> Document::paintSurface(std::size_t body,
                                                                   MapChannel channel) {
    if (body >= assets_.size()) return makeError("no body " + std::to_string(body));
    BodyAssets& a = assets_[body];
    if (!a.mesh) return makeError("body " + std::to_string(body) + ": no mesh (" + a.meshError + ")");
    const PaintedMap* image = map(body, channel);
    if (!image) return makeError("body " + std::to_string(body) + ": no " + channelName(channel) + " map");
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
    if (body >= assets_.size()) return makeError("no body " + std::to_string(body));
    BodyAssets& a = assets_[body];
    if (!a.mesh) return makeError("body " + std::to_string(body) + ": no mesh (" + a.meshError + ")");
    if (!a.physics) {
        BakeSettings settings;
        settings.size = project_.bodies[body].textureSize;
        settings.maxTexelStretch = project_.bodies[body].maxTexelStretch;
        Result<SurfaceTextures> baked = bakeSurfaceTextures(*a.mesh, settings);
        if (!baked) return baked.error();
        a.physics = std::make_shared<const SurfaceTextures>(std::move(baked).value());
    }
    return a.physics;
}

std::string Document::defaultMapPath(std::size_t body, MapChannel channel) const {
    return "maps/" + assetFileStem(body) + "_" + channelName(channel) + ".png";
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

// --- files ---------------------------------------------------------------------------------------

Status Document::writeMaps(bool all) {
    return writeMapsAndProjectFiles(all, false);
}

Status Document::writeMapsAndProjectFiles(bool allMaps, bool withProject) {
    // The changed maps and water graphs and the project are replaced as one (file_util.h): a
    // failure at any step leaves every previous file as it was, so the project on disk never
    // names a map or graph of another save.
    std::vector<FileWriter> files;
    std::vector<BodyAssets::Map*> written;
    std::vector<BodyAssets::Graph*> writtenGraphs;
    for (BodyAssets& a : assets_) {
        for (BodyAssets::Map& m : a.maps) {
            if (!m.image || m.path.empty() || !(m.dirty || allMaps)) continue;
            std::error_code ec;
            fs::create_directories(m.path.parent_path(), ec);
            files.push_back(bytesFileWriter(m.path, encodePaintedMapPng16(*m.image)));
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
    if (path_.empty()) return makeError("untitled: choose a file name (Save As)");
    return writeMapsAndProject(false);
}

Status Document::saveAs(const fs::path& target) {
    const fs::path absolute = fs::absolute(target).lexically_normal();
    const fs::path from = project_.folder, to = absolute.parent_path();
    const std::optional<fs::path> oldAutosave =
        path_.empty() ? std::optional<fs::path>() : std::optional<fs::path>(autosavePath());
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
    project_ = std::move(moved);
    path_ = absolute;
    // Re-point loaded maps at their new files and write them all there.
    for (std::size_t b = 0; b < assets_.size(); ++b) {
        assets_[b].meshPath = project_.bodies[b].mesh.empty()
                                  ? fs::path()
                                  : project_.resolvePath(project_.bodies[b].mesh);
        for (MapChannel c : kMapChannels) {
            const std::string& p = channelPath(project_.bodies[b], c);
            BodyAssets::Map& m = assets_[b].maps[static_cast<int>(c)];
            m.path = p.empty() ? fs::path() : project_.resolvePath(p);
            if (m.image) m.dirty = true;
        }
        BodyAssets::Graph& g = assets_[b].graph;
        const auto& desc = project_.bodies[b].waterGraph;
        g.path = desc && !desc->graph.empty() ? project_.resolvePath(desc->graph) : fs::path();
        if (g.graph) g.dirty = true;
    }
    if (oldAutosave) {
        std::error_code ec;
        fs::remove(*oldAutosave, ec);
    }
    return writeMapsAndProject(true);
}

Status Document::writeMapsAndProject(bool allMaps) {
    Status saved = writeMapsAndProjectFiles(allMaps, true);
    if (!saved) return saved;
    savedState_ = stateId();
    discardAutosave();
    return Ok{};
}

Result<Project> Document::simulationSnapshot(const fs::path& folder) const {
    std::error_code ec;
    fs::create_directories(folder, ec);
    if (ec) return makeError(folder.string() + ": cannot create: " + ec.message());
    Project project = project_;
    for (std::size_t b = 0; b < assets_.size(); ++b) {
        BodyDesc& body = project.bodies[b];
        const BodyAssets::Graph& g = assets_[b].graph;
        if (g.graph && body.waterGraph && (g.dirty || !fs::exists(g.path, ec))) {
            const fs::path file = folder / ("body" + std::to_string(b) + ".graph.json");
            if (Status s = saveGraph(*g.graph, file); !s) return s.error();
            body.waterGraph->graph = fs::absolute(file).string();
        }
        for (MapChannel c : kMapChannels) {
            const BodyAssets::Map& m = assets_[b].maps[static_cast<int>(c)];
            if (!m.image || !(m.dirty || !fs::exists(m.path, ec))) continue;
            const fs::path file =
                folder / ("body" + std::to_string(b) + "_" + channelName(c) + ".png");
            if (Status s = savePaintedMap(*m.image, file); !s) return s.error();
            channelPath(body, c) = fs::absolute(file).string();
        }
    }
    return project;
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
            maps.push_back({{"body", b},
                            {"channel", channelName(c)},
                            {"png_base64", base64Encode(encodePaintedMapPng16(*m.image))}});
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
    return writeFileAtomically(target, [&](std::ostream& out) {
        out << text;
        return static_cast<bool>(out);
    });
}

void Document::discardAutosave() const {
    std::error_code ec;
    fs::remove(autosavePath(), ec);
}

std::optional<fs::path> Document::findAutosave(const fs::path& project) {
    const fs::path candidate =
        project.empty() ? userConfigDir() / "untitled.plim.json.autosave"
                        : autosavePathFor(fs::absolute(project).lexically_normal());
    std::error_code ec;
    if (fs::exists(candidate, ec)) return candidate;
    return std::nullopt;
}

Result<std::unique_ptr<Document>> Document::recover(const fs::path& autosaveFile) {
    std::ifstream in(autosaveFile, std::ios::binary);
    if (!in) return makeError(autosaveFile.string() + ": cannot open");
    Json root;
    try {
        root = Json::parse(std::string(std::istreambuf_iterator<char>(in), {}));
    } catch (const Json::exception& e) {
        return makeError(autosaveFile.string() + ": not an autosave: " + e.what());
    }
    if (!root.contains("plimsoll_autosave") || !root.contains("project")) {
        return makeError(autosaveFile.string() + ": not an autosave");
    }
    const fs::path folder = root.value("folder", std::string());
    Result<Project> project =
        parseProject(root["project"].dump(), autosaveFile.string(), folder);
    if (!project) return project.error();
    auto document = std::make_unique<Document>();
    document->path_ = root.value("project_path", std::string());
    document->project_ = std::move(project).value();
    document->project_.folder = folder;
    document->syncAssets();
    for (const Json& m : root["maps"]) {
        const std::size_t body = m.value("body", std::size_t{0});
        const std::optional<MapChannel> channel = parseChannel(m.value("channel", std::string()));
        if (!channel || body >= document->bodyCount()) continue;
        Result<PaintedMap> image =
            decodePng(base64Decode(m.value("png_base64", std::string())), autosaveFile.string());
        if (!image) return image.error();
        document->setMap(body, *channel, std::move(image).value());
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
