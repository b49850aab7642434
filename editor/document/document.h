// The editor's document: a Project, the assets it names (meshes, painted maps) as loaded into
// memory, and its edit history. Every edit is a Command (command.h) executed through the
// document, so the window, `plimsoll edit --script` and the tests edit the same way and undo
// the same way. Saving writes the maps (16-bit PNG) and then the project, each atomically; an
// autosave side file holds the unsaved state for recovery after a crash.
#pragma once

#include "document/layers.h"
#include "document/paint.h"

#include "plimsoll/bake/bake.h"
#include "plimsoll/graph/graph.h"
#include "plimsoll/geometry/mesh.h"
#include "plimsoll/surface/painted_map.h"
#include "plimsoll/physics/pose.h"
#include "plimsoll/project/project.h"
#include "plimsoll/scene/scene.h"
#include "plimsoll/core/result.h"

#include <array>
#include <map>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace plimsoll::editor {

/// The maps a body can have painted.
enum class MapChannel { Permeability = 0, Density = 1, Thickness = 2 };
inline constexpr int kMapChannelCount = 3;
inline constexpr std::array<MapChannel, kMapChannelCount> kMapChannels{
    MapChannel::Permeability, MapChannel::Density, MapChannel::Thickness};

const char* channelName(MapChannel channel);  ///< "permeability", "density", "thickness"
std::optional<MapChannel> parseChannel(std::string_view name);

/// The project field that names a body's map of `channel` (permeability_map, material.map,
/// material.thickness_map).
std::string& channelPath(BodyDesc& body, MapChannel channel);
const std::string& channelPath(const BodyDesc& body, MapChannel channel);

/// Density and thickness maps scale a shell: a body without one cannot have them.
bool channelNeedsShell(MapChannel channel);

/// A body's files as loaded.
struct BodyAssets {
    std::filesystem::path meshPath;  ///< resolved path the mesh was loaded from
    /// The mesh with the UVs the body bakes and is painted over: its own, or its generated
    /// physics atlas (BodyDesc::atlas, as World chooses). Null when it failed to load.
    std::shared_ptr<const TriangleMesh> mesh;
    AtlasMode atlas = AtlasMode::Auto;  ///< the mode `mesh` was chosen with
    double unitScale = 0;               ///< the body's unit `mesh` was read in (0: the file's)
    std::string meshError;
    struct Map {
        std::filesystem::path path;  ///< resolved path (what it was loaded from/for)
        /// What the engine reads: with layers, always flattenLayers(*layers).
        std::optional<PaintedMap> image;
        /// The map's layers (saved beside it, layersPathFor); none: the image is all there is.
        std::optional<LayerStack> layers;
        bool dirty = false;  ///< differs from the file
        std::string error;
    };
    std::array<Map, kMapChannelCount> maps;
    /// Paint surfaces, built on first use for the map's size.
    std::array<std::shared_ptr<const PaintSurface>, kMapChannelCount> paintSurfaces;
    /// The physics bake (body.textureSize, or the size its tolerance picks), built on first use.
    std::shared_ptr<const SurfaceTextures> physics;
    /// For a body that gives a tolerance: the size it picks on `mesh` and that size's measured
    /// errors, with the tolerance and stretch limit it was picked for (textures dropped).
    std::optional<LevelChoice> levelChoice;
    double levelChoiceStretch = 0;
    /// The body's water graph (the file BodyDesc::waterGraph names) as loaded and edited. It
    /// is parsed but not validated: a graph with errors can still be opened and fixed.
    struct Graph {
        std::filesystem::path path;  ///< resolved path; empty: the body has none
        std::optional<WaterGraph> graph;
        bool dirty = false;  ///< differs from the file
        std::string error;
    };
    Graph graph;
};

class Document;

/// Edited maps and graphs whose paths left the project (a path changed): the command that
/// changed the path keeps them, so that its undo brings them back unchanged.
struct DetachedAssets {
    std::map<std::filesystem::path, BodyAssets::Map> maps;
    std::map<std::filesystem::path, WaterGraph> graphs;
};

/// One edit with its inverse. apply() is do and redo; revert() is undo. A command holds what
/// it needs to go both ways (a paint stroke: the changed pixels before and after).
class Command {
public:
    virtual ~Command() = default;
    virtual std::string name() const = 0;
    virtual Status apply(Document& document) = 0;
    virtual void revert(Document& document) = 0;
};

class Document {
public:
    /// An empty, untitled project (folder: the current directory).
    Document();
    /// Loads the project and everything it names (a mesh or map that fails to load is recorded
    /// in its BodyAssets, not fatal).
    static Result<std::unique_ptr<Document>> open(const std::filesystem::path& path);

    const Project& project() const { return project_; }
    /// Path of the project file; empty while untitled.
    const std::filesystem::path& path() const { return path_; }
    std::string title() const;  ///< file name (or "untitled") with "*" when dirty

    std::size_t bodyCount() const { return project_.bodies.size(); }
    const BodyAssets& assets(std::size_t body) const { return assets_[body]; }

    // --- editing: every change goes through execute -------------------------------------------
    /// Applies the command and puts it on the undo stack (clearing redo). On failure nothing
    /// changed and the stack is untouched.
    Status execute(std::unique_ptr<Command> command);
    bool canUndo() const { return !done_.empty(); }
    bool canRedo() const { return !undone_.empty(); }
    std::string undoName() const;
    std::string redoName() const;
    bool undo();
    bool redo();
    /// The history's steps by name, oldest first: the done ones, then the undone ones in the
    /// order redo would bring them back.
    std::vector<std::string> historyNames() const;
    /// Steps done (0: the state as opened); historyNames()[0, position) are done.
    std::size_t historyPosition() const { return done_.size(); }
    /// Undoes or redoes step by step, as undo() and redo() do, until `position` steps are
    /// done (clamped to the history). False if a redo failed (the history stops there).
    bool jumpToHistory(std::size_t position);

    /// Unsaved changes (the state differs from the one last saved or opened).
    bool dirty() const { return stateId() != savedState_; }

    // --- files --------------------------------------------------------------------------------
    /// Writes changed maps, then the project (each atomically), and removes the autosave.
    Status save();
    /// Saves under a new name; relative paths are rewritten for the new folder, and every loaded
    /// map is written beside it where it was relative. Never over a file the project reads (its
    /// mesh, a map it does not rewrite); over another existing file only with `overwrite`.
    Status saveAs(const std::filesystem::path& path, bool overwrite = false);
    /// The existing files saveAs(path) would replace (so need `overwrite`, after asking); an
    /// error where it would write over a file the project reads (refused whatever the answer).
    Result<std::vector<std::filesystem::path>> replacedBySaveAs(
        const std::filesystem::path& path) const;

    /// The project as it is being edited, as a scene for World: every body baked from the
    /// document's own mesh, water graph and painted maps, unsaved edits included (a deforming
    /// body's frames, which the document does not hold, are read from their files). Writes
    /// nothing and changes nothing in the document: the live preview runs this. The log hears
    /// the graphs' warnings.
    Result<Scene> simulationScene(const LogFunction& log = {}) const;

    /// The autosave side file of a project path (".NAME.autosave" beside it).
    static std::filesystem::path autosavePathFor(const std::filesystem::path& projectPath);
    /// Writes the unsaved state (project and changed maps) to `autosavePath()`.
    Status autosave() const;
    std::filesystem::path autosavePath() const;
    /// Removes the autosave (a clean close).
    void discardAutosave() const;
    /// A project whose autosave is still there was not closed cleanly: the autosave to offer.
    static std::optional<std::filesystem::path> findAutosave(const std::filesystem::path& project);
    /// The document as it was autosaved, dirty, at the path of the project the autosave lies
    /// beside (".NAME.autosave" -> NAME; untitled for the user's untitled autosave), whatever
    /// path the autosave names inside: a save writes the project the user opened.
    static Result<std::unique_ptr<Document>> recover(const std::filesystem::path& autosaveFile);

    // --- what commands use ----------------------------------------------------------------------
    /// Replaces the project; assets whose paths changed are reloaded. Edited maps and graphs
    /// whose paths leave the project go into `detached`; those whose paths come back are taken
    /// from it (a map that is dirty and still named keeps its pixels).
    void setProject(Project project, DetachedAssets& detached);
    PaintedMap* map(std::size_t body, MapChannel channel);
    const PaintedMap* map(std::size_t body, MapChannel channel) const;
    /// Installs (or with nullopt removes) a body's map image; marks it dirty.
    void setMap(std::size_t body, MapChannel channel, std::optional<PaintedMap> image);
    /// The map's layers (null: it has none).
    const LayerStack* layers(std::size_t body, MapChannel channel) const;
    /// Installs (or with nullopt drops) the map's layer stack; with one, the map becomes its
    /// flattening. Marks the map dirty.
    void setLayers(std::size_t body, MapChannel channel, std::optional<LayerStack> stack);
    /// The pixels `target` names (null: no such map, layer or mask).
    PaintedMap* paintPixels(std::size_t body, MapChannel channel, PaintTarget target);
    /// After pixels of paintPixels changed: re-flattens a layered map; marks the map dirty.
    void pixelsChanged(std::size_t body, MapChannel channel);
    /// Everything the document holds for one map (image, layers, dirty flag), and back: a
    /// command that replaces a map keeps the old one this way for its undo.
    BodyAssets::Map mapState(std::size_t body, MapChannel channel) const;
    void restoreMapState(std::size_t body, MapChannel channel, BodyAssets::Map state);
    /// The body's water graph as edited (null: none, or its file failed to load).
    const WaterGraph* graph(std::size_t body) const;
    /// Installs (or with nullopt removes) the body's graph image; marks it dirty. The project's
    /// water_graph entry names the file it is saved to (graph_edit.h changes both).
    void setGraph(std::size_t body, std::optional<WaterGraph> graph);
    /// Where a new graph for `body` goes: "<project>_<body>.graph.json" beside the project.
    std::string defaultGraphPath(std::size_t body) const;
    /// The same for a body named `bodyName` (one not in the project yet: a duplicate).
    std::string defaultGraphPath(const std::string& bodyName) const;
    /// The paint surface for the body's current map of `channel` (built and cached).
    Result<std::shared_ptr<const PaintSurface>> paintSurface(std::size_t body, MapChannel channel);
    /// Bounds of every loaded body at its starting pose, world, m.
    Bounds3 worldBounds() const;
    /// A body's starting pose (position, rotation_deg).
    Pose bodyPose(std::size_t body) const;
    /// The body's physics textures at its texture size (baked on first use, cached).
    Result<std::shared_ptr<const SurfaceTextures>> physicsTextures(std::size_t body);
    /// What physicsTextures(body) would bake with (size, stretch limit). For a body that gives
    /// a tolerance, the size it picks, or 0 while that is not known (levelChoice).
    BakeSettings physicsBakeSettings(std::size_t body) const;
    /// The size a body's tolerance picks on its mesh, and that size's measured errors; none
    /// for a body with a texture size, or while the pick is not made (PhysicsBakes makes it
    /// off the UI thread, physicsTextures on the calling thread).
    std::optional<LevelChoice> levelChoice(std::size_t body) const;
    /// Installs a pick made elsewhere from `mesh` with `settings` (the stretch limit) for
    /// `choice.tolerance`, when the body still has that mesh, tolerance and limit (true).
    bool adoptLevelChoice(std::size_t body, const TriangleMesh* mesh, const BakeSettings& settings,
                          const LevelChoice& choice);
    /// The body's physics textures if they are baked at its current size (null: not yet;
    /// never bakes). The window's panels read this and bake in the background (physics_bakes.h).
    std::shared_ptr<const SurfaceTextures> bakedPhysics(std::size_t body) const;
    /// Installs textures baked elsewhere from `mesh` with `settings`, when the body still has
    /// that mesh and those settings (true); otherwise they are stale and nothing changes.
    bool adoptPhysics(std::size_t body, const TriangleMesh* mesh, const BakeSettings& settings,
                      std::shared_ptr<const SurfaceTextures> textures);
    /// Where a new map of `channel` for `body` goes: "maps/<project>_<body>_<channel>.png".
    std::string defaultMapPath(std::size_t body, MapChannel channel) const;
    std::string defaultMapPath(const std::string& bodyName, MapChannel channel) const;
    /// "<project stem>_<body name>" with characters unsafe in file names replaced: the
    /// stem of the files the document creates for a body (maps, water graph).
    std::string assetFileStem(std::size_t body) const;
    std::string assetFileStem(std::string bodyName) const;
    /// Names the document's state: it changes with every command executed, undone or redone
    /// (the live preview takes the paint of a new state).
    std::uint64_t stateId() const { return done_.empty() ? 0 : done_.back().id; }

private:
    void syncAssets(DetachedAssets& detached);
    /// Writes the changed (or all) maps and water graphs, each atomically.
    Status writeMaps(bool all);
    /// Re-points loaded maps and graphs whose files lie outside the project's folder at new
    /// names inside it (the project updated), those about to be written (changed, or all when
    /// `allMaps`); true if any moved.
    bool keepWritesInsideFolder(bool allMaps);
    /// Points every body's mesh, map and graph path at project_'s (after a move), marking the
    /// loaded maps and graphs to be written when `markLoadedDirty`.
    void pointAssetsAtProject(bool markLoadedDirty);
    /// writeMaps(allMaps), then the project to path_; marks the document saved.
    /// The project as saveAs(absolute) would write it: relative paths rewritten for the new folder.
    Project movedTo(const std::filesystem::path& absolute) const;
    /// saveAs's refusals: `moved` (the project as it will be saved to `target`) must not write
    /// over a file the project reads; the other existing files it writes over go to `replaced`.
    Status checkSaveAsTargets(const Project& moved, const std::filesystem::path& target,
                              std::vector<std::filesystem::path>& replaced) const;
    Status writeMapsAndProject(bool allMaps);
    /// The changed maps and graphs (all loaded ones if `allMaps`) and, if `withProject`, the
    /// project, replaced together (replaceFilesTogether).
    Status writeMapsAndProjectFiles(bool allMaps, bool withProject);

    struct Entry {
        std::unique_ptr<Command> command;
        std::uint64_t id;
    };
    Project project_;
    std::filesystem::path path_;
    std::vector<BodyAssets> assets_;
    std::vector<Entry> done_;
    std::vector<Entry> undone_;
    std::uint64_t nextId_ = 1;
    /// stateId() when last saved or opened; ~0 for "never" (recovered documents).
    std::uint64_t savedState_ = 0;
    /// Whether the autosave at autosavePath() is this document's own (written by autosave(), or
    /// the one it was recovered from): only then does a save remove it. An autosave another
    /// session left (a crash) is kept until the user recovers or discards it.
    mutable bool ownsAutosave_ = false;
};

}  // namespace plimsoll::editor
