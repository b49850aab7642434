// The edits: each a Command (document.h) with do and undo. The functions below build them from
// what a user (or a script) asks for, checking it first; the document executes them.
#pragma once

#include "document/document.h"
#include "document/paint.h"

#include <nlohmann/json.hpp>

#include <memory>
#include <span>

namespace plimsoll::editor {

/// Pixels of one map, before and after, and (when the edit made the map) the map it made.
class PaintCommand final : public Command {
public:
    PaintCommand(std::string name, std::size_t body, MapChannel channel, PixelChange change,
                 std::optional<PaintedMap> created, std::string createdPath);
    std::string name() const override { return name_; }
    Status apply(Document& document) override;
    void revert(Document& document) override;
    const PixelChange& change() const { return change_; }

private:
    std::string name_;
    std::size_t body_;
    MapChannel channel_;
    PixelChange change_;
    std::optional<PaintedMap> created_;  ///< the blank map the edit starts from, when new
    std::string createdPath_;
    std::string previousPath_;
};

/// Any change of the project's content (properties, import, paths): the project before and
/// after. Assets follow the paths (document.h, setProject).
class ProjectCommand final : public Command {
public:
    ProjectCommand(std::string name, Project before, Project after);
    std::string name() const override { return name_; }
    Status apply(Document& document) override;
    void revert(Document& document) override;

private:
    std::string name_;
    Project before_;
    Project after_;
};

/// Size of maps made for a first stroke on a body without one.
inline constexpr int kDefaultMapSize = 512;

/// A paint / erase / smooth stroke through object-space points on body `body`. Makes the
/// map (kDefaultMapSize, value 0) when the body has none.
Result<std::unique_ptr<Command>> makeStrokeCommand(Document& document, std::size_t body,
                                                   MapChannel channel, const Brush& brush,
                                                   std::span<const Eigen::Vector3d> points);
Result<std::unique_ptr<Command>> makeFillIslandCommand(Document& document, std::size_t body,
                                                       MapChannel channel,
                                                       const Eigen::Vector3d& point, double value,
                                                       bool mirrorX);
Result<std::unique_ptr<Command>> makeFillAllCommand(Document& document, std::size_t body,
                                                    MapChannel channel, double value);
/// A new map of the given size filled with `value`, at `path` (relative to the project's
/// folder; empty: defaultMapPath), replacing the body's map of that channel.
Result<std::unique_ptr<Command>> makeNewMapCommand(Document& document, std::size_t body,
                                                   MapChannel channel, int width, int height,
                                                   double value, std::string path);
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

}  // namespace plimsoll::editor
