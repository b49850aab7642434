// The edits: each a Command (document.h) with do and undo. The functions below build them from
// what a user (or a script) asks for, checking it first; the document executes them.
#pragma once

#include "document/document.h"
#include "document/paint.h"
#include "document/smart_mask.h"

#include <nlohmann/json.hpp>

#include <memory>
#include <span>

namespace plimsoll::editor {

/// Pixels of one map (or of one of its layers or masks), before and after, and (when the edit
/// made the map) the map it made. A made map replaces whatever the channel had (a saved map,
/// its layers): that is kept here and comes back on undo.
class PaintCommand final : public Command {
public:
    /// The pixels one stroke changed in one part (a stroke on a layer changes its pixels and
    /// its coverage together).
    struct PartChange {
        PaintTarget target;
        PixelChange change;
    };
    PaintCommand(std::string name, std::size_t body, MapChannel channel,
                 std::vector<PartChange> changes, std::optional<PaintedMap> created,
                 std::string createdPath);
    std::string name() const override { return name_; }
    Status apply(Document& document) override;
    void revert(Document& document) override;
    /// Pixels changed, over every part.
    std::size_t pixelsChanged() const;
    /// The map as it would be after apply(), the document unchanged (a stroke's live preview).
    PaintedMap preview(const Document& document) const;

private:
    std::string name_;
    std::size_t body_;
    MapChannel channel_;
    std::vector<PartChange> changes_;
    std::optional<PaintedMap> created_;  ///< the blank map the edit starts from, when new
    std::string createdPath_;
    std::string previousPath_;
    std::optional<BodyAssets::Map> replaced_;  ///< the channel's map before a made one
    DetachedAssets detached_;
};

/// Any change of the project's content (properties, import, paths): the project before and
/// after. Assets follow the paths (document.h, setProject).
class ProjectCommand final : public Command {
public:
    /// `detached`: maps and graphs the new project's paths name that are in no file yet (a
    /// duplicated body's copies); the first apply installs them.
    ProjectCommand(std::string name, Project before, Project after, DetachedAssets detached = {});
    std::string name() const override { return name_; }
    Status apply(Document& document) override;
    void revert(Document& document) override;

private:
    std::string name_;
    Project before_;
    Project after_;
    DetachedAssets detached_;  ///< edited maps and graphs a path change took out
};

/// A change of one map's layer stack (add, remove, move, settings, masks): the stack before and
/// after (copies share layer pixels, layers.h). A map without layers gets a stack whose base
/// layer is the map; its undo gives the map back as it was.
class LayerCommand final : public Command {
public:
    LayerCommand(std::string name, std::size_t body, MapChannel channel,
                 std::optional<LayerStack> before, LayerStack after);
    std::string name() const override { return name_; }
    Status apply(Document& document) override;
    void revert(Document& document) override;

private:
    std::string name_;
    std::size_t body_;
    MapChannel channel_;
    std::optional<LayerStack> before_;
    LayerStack after_;
    std::optional<BodyAssets::Map> mapBefore_;  ///< the map as it was, when it had no layers
};

/// Size of maps made for a first stroke on a body without one.
inline constexpr int kDefaultMapSize = 512;

/// A paint / erase / smooth stroke through object-space points on body `body`. Makes the
/// map (kDefaultMapSize, value 0) when the body has none.
/// On a map with layers, `target` names the layer (or its mask) painted; a stroke that
/// changes no pixel (it misses the mesh) is an error, not an empty undo step.
Result<std::unique_ptr<Command>> makeStrokeCommand(Document& document, std::size_t body,
                                                   MapChannel channel, const Brush& brush,
                                                   std::span<const Eigen::Vector3d> points,
                                                   PaintTarget target = {});
/// Fills move pixels toward `value` by `strength` (1: set).
Result<std::unique_ptr<Command>> makeFillIslandCommand(Document& document, std::size_t body,
                                                       MapChannel channel,
                                                       const Eigen::Vector3d& point, double value,
                                                       bool mirrorX, double strength = 1.0,
                                                       PaintTarget target = {});
Result<std::unique_ptr<Command>> makeFillAllCommand(Document& document, std::size_t body,
                                                    MapChannel channel, double value,
                                                    double strength = 1.0, PaintTarget target = {});
/// A new map of the given size filled with `value`, at `path` (relative to the project's
/// folder; empty: defaultMapPath), replacing the body's map of that channel.
Result<std::unique_ptr<Command>> makeNewMapCommand(Document& document, std::size_t body,
                                                   MapChannel channel, int width, int height,
                                                   double value, std::string path);
/// The map at a new size, filtered: area-weighted means where it shrinks (its integral kept
/// exactly), linear between pixel centres where it grows.
PaintedMap resampledMap(const PaintedMap& map, int width, int height);
/// Resizes the body's map keeping its content (resampledMap; with layers, every layer's
/// pixels, mask and coverage): one undo step, the map's file unchanged.
Result<std::unique_ptr<Command>> makeResizeMapCommand(Document& document, std::size_t body,
                                                      MapChannel channel, int width, int height);
// --- layers: each a LayerCommand; `layer` counts from the bottom (0) -------------------------

/// A new layer at `index` (clamped; -1: on top). A map without layers first becomes a stack
/// with the map as its "Base" layer. A paint layer starts transparent-black (value 0, and
/// Normal blend at its opacity); a fill layer holds `fillValue`; a folder starts empty. An
/// empty `name` gives the first free "Layer N" / "Fill N" / "Folder N"; a name another layer
/// has is refused (checkLayerName). A layer put right above one of a folder's layers, or right
/// below a folder's entry, goes into that folder; a folder between a folder's layers is
/// refused (folders do not nest).
Result<std::unique_ptr<Command>> makeAddLayerCommand(const Document& document, std::size_t body,
                                                     MapChannel channel, LayerKind kind,
                                                     std::string name, double fillValue = 1.0,
                                                     int index = -1);
/// Removes a layer, or a folder with the layers it holds ("Remove folder"); the map keeps one
/// layer at least.
Result<std::unique_ptr<Command>> makeRemoveLayerCommand(const Document& document, std::size_t body,
                                                        MapChannel channel, int layer);
/// Moves layer `from` to position `to` (the others keep their order). With folders, `from`
/// and `to` are items of one folder (or both at the top level), a folder moving with its
/// layers next to `to` (above it when `to` is above); into and out of a folder below.
Result<std::unique_ptr<Command>> makeMoveLayerCommand(const Document& document, std::size_t body,
                                                      MapChannel channel, int from, int to);
/// Moves layer `layer` (not a folder) into folder `folder`, on top of its layers.
Result<std::unique_ptr<Command>> makeMoveIntoFolderCommand(const Document& document,
                                                           std::size_t body, MapChannel channel,
                                                           int layer, int folder);
/// Moves layer `layer` out of its folder, right above the folder.
Result<std::unique_ptr<Command>> makeMoveOutOfFolderCommand(const Document& document,
                                                            std::size_t body, MapChannel channel,
                                                            int layer);
/// Settings of a layer to change; unset ones stay.
struct LayerEdit {
    std::optional<std::string> name;  ///< checked as makeRenameLayerCommand checks it
    std::optional<double> opacity;
    std::optional<BlendMode> blend;
    std::optional<bool> visible;
    std::optional<double> fillValue;  ///< fill layers only
};
Result<std::unique_ptr<Command>> makeSetLayerCommand(const Document& document, std::size_t body,
                                                     MapChannel channel, int layer,
                                                     const LayerEdit& edit);
/// Renames layer `layer`, one step called "Rename layer 'Layer 2' to 'Rust'". The name is
/// taken without the spaces at its ends; refused (checkLayerName) when empty or another
/// layer's, and when it is the layer's name already (a step that changes nothing).
Result<std::unique_ptr<Command>> makeRenameLayerCommand(const Document& document, std::size_t body,
                                                        MapChannel channel, int layer,
                                                        std::string_view name);
/// Gives the layer a mask of `value` everywhere (1: all shown), or removes its mask.
Result<std::unique_ptr<Command>> makeAddMaskCommand(const Document& document, std::size_t body,
                                                    MapChannel channel, int layer,
                                                    double value = 1.0);
Result<std::unique_ptr<Command>> makeRemoveMaskCommand(const Document& document, std::size_t body,
                                                       MapChannel channel, int layer);
/// Gives the layer a smart mask (smart_mask.h), replacing its mask if it has one: one step
/// called "Smart mask: below the waterline", undone to the mask it had. Worked out over the
/// map's own pixel grid (the document's paint surface of the map).
Result<std::unique_ptr<Command>> makeSmartMaskCommand(Document& document, std::size_t body,
                                                      MapChannel channel, int layer,
                                                      const SmartMask& mask);

/// What a project edit at `pointer` is called in the history: "/bodies/0/material/density" of
/// a body named boat is "boat density", "/bodies/0/position/1" "boat position y",
/// "/water/amplitude" "water amplitude".
std::string propertyLabel(const Project& project, const std::string& pointer);

/// Sets the value at a JSON pointer of the project's JSON ("/bodies/0/material/density"); the
/// result must be a valid project.
Result<std::unique_ptr<Command>> makeSetPropertyCommand(const Document& document,
                                                        const std::string& pointer,
                                                        const nlohmann::json& value);
/// Adds a body with the mesh (solid of density 500 kg/m^3), or with `body` replaces that body's
/// mesh. The mesh must load.
Result<std::unique_ptr<Command>> makeImportMeshCommand(const Document& document,
                                                       const std::filesystem::path& mesh,
                                                       std::optional<std::size_t> body);

/// A copy of the body beside it: a unique name ("ball copy", "ball copy 2", ...), moved along
/// x by its mesh's width and a tenth so that the two do not overlap. Its maps and water graph
/// are not copied: two bodies naming one file would each save their own edits over it.
Result<std::unique_ptr<Command>> makeDuplicateBodyCommand(const Document& document,
                                                          std::size_t body);
/// Takes the body out of the project; the undo brings it back with its unsaved paint.
Result<std::unique_ptr<Command>> makeRemoveBodyCommand(const Document& document, std::size_t body);
/// Sets the body's starting place: position (m) and rotation (degrees, Rz Ry Rx as the
/// project's rotation_deg). Finite values only.
Result<std::unique_ptr<Command>> makeSetBodyTransformCommand(
    const Document& document, std::size_t body, const Eigen::Vector3d& position,
    const Eigen::Vector3d& rotationDegrees);
/// Sets the cap of opening `cap` (BodyDesc::caps, in the openings' order) of body `body`: its
/// mode ("open" or "sealed"; nullopt: the body's `openings`) and height (object y, m; nullopt:
/// the rim's). The list grows with default entries up to `cap` and loses default entries at
/// its end. One undo step ("Seal boat cap 1", "Move boat cap 1"); a height that is not finite,
/// a mode of "none" and a change that changes nothing are refused. Whether the height fits the
/// opening is checked when the body is loaded (the repair knows its rim).
Result<std::unique_ptr<Command>> makeSetCapCommand(const Document& document, std::size_t body,
                                                   std::size_t cap, const CapDesc& settings);

}  // namespace plimsoll::editor
