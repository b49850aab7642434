#include "document/command.h"

#include "plimsoll/mesh_io.h"

namespace plimsoll::editor {

namespace fs = std::filesystem;
using Json = nlohmann::json;

PaintCommand::PaintCommand(std::string name, std::size_t body, MapChannel channel,
                           PixelChange change, std::optional<PaintedMap> created,
                           std::string createdPath)
    : name_(std::move(name)), body_(body), channel_(channel), change_(std::move(change)),
      created_(std::move(created)), createdPath_(std::move(createdPath)) {}

Status PaintCommand::apply(Document& document) {
    if (body_ >= document.bodyCount()) return makeError("no body " + std::to_string(body_));
    if (created_) {
        Project project = document.project();
        previousPath_ = channelPath(project.bodies[body_], channel_);
        channelPath(project.bodies[body_], channel_) = createdPath_;
        document.setProject(std::move(project));
        document.setMap(body_, channel_, *created_);
    }
    PaintedMap* map = document.map(body_, channel_);
    if (!map) return makeError(std::string("no ") + channelName(channel_) + " map to paint");
    applyValues(*map, change_.pixels, change_.after);
    document.markMapDirty(body_, channel_);
    return Ok{};
}

void PaintCommand::revert(Document& document) {
    if (PaintedMap* map = document.map(body_, channel_)) {
        applyValues(*map, change_.pixels, change_.before);
        document.markMapDirty(body_, channel_);
    }
    if (created_) {
        Project project = document.project();
        channelPath(project.bodies[body_], channel_) = previousPath_;
        document.setMap(body_, channel_, std::nullopt);
        document.setProject(std::move(project));
    }
}

ProjectCommand::ProjectCommand(std::string name, Project before, Project after)
    : name_(std::move(name)), before_(std::move(before)), after_(std::move(after)) {}

Status ProjectCommand::apply(Document& document) {
    document.setProject(after_);
    return Ok{};
}

void ProjectCommand::revert(Document& document) { document.setProject(before_); }

namespace {

Status checkTarget(const Document& document, std::size_t body, MapChannel channel) {
    if (body >= document.bodyCount()) {
        return makeError("no body " + std::to_string(body) + " (the project has " +
                         std::to_string(document.bodyCount()) + ")");
    }
    if (!document.assets(body).mesh) {
        return makeError("body " + std::to_string(body) + ": mesh not loaded: " +
                         document.assets(body).meshError);
    }
    if (channelNeedsShell(channel) &&
        !document.project().bodies[body].material.shellSurfaceDensity) {
        return makeError("body " + std::to_string(body) + ": a " + channelName(channel) +
                         " map scales the shell, and the material has none (set material.shell)");
    }
    return Ok{};
}

/// Runs `edit` on the body's map, making a blank one first (as part of the same command) when
/// there is none.
template <class Edit>
Result<std::unique_ptr<Command>> paintEdit(Document& document, std::size_t body,
                                           MapChannel channel, const std::string& name,
                                           Edit edit) {
    if (Status ok = checkTarget(document, body, channel); !ok) return ok.error();
    std::optional<PaintedMap> created;
    std::string createdPath;
    PaintedMap blank;
    const PaintedMap* map = document.map(body, channel);
    std::shared_ptr<const PaintSurface> surface;
    if (!map) {
        blank.width = blank.height = kDefaultMapSize;
        blank.values.assign(static_cast<std::size_t>(kDefaultMapSize) * kDefaultMapSize, 0.0f);
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
    PixelChange change = edit(*map, *surface);
    return std::unique_ptr<Command>(std::make_unique<PaintCommand>(
        name, body, channel, std::move(change), std::move(created), std::move(createdPath)));
}

}  // namespace

Result<std::unique_ptr<Command>> makeStrokeCommand(Document& document, std::size_t body,
                                                   MapChannel channel, const Brush& brush,
                                                   std::span<const Eigen::Vector3d> points) {
    const char* verb = brush.mode == BrushMode::Erase    ? "Erase"
                       : brush.mode == BrushMode::Smooth ? "Smooth"
                                                         : "Paint";
    return paintEdit(document, body, channel, std::string(verb) + " " + channelName(channel),
                     [&](const PaintedMap& map, const PaintSurface& surface) {
                         return strokeChange(map, surface, brush, points);
                     });
}

Result<std::unique_ptr<Command>> makeFillIslandCommand(Document& document, std::size_t body,
                                                       MapChannel channel,
                                                       const Eigen::Vector3d& point, double value,
                                                       bool mirrorX) {
    return paintEdit(document, body, channel, std::string("Fill island ") + channelName(channel),
                     [&](const PaintedMap& map, const PaintSurface& surface) {
                         return fillIslandChange(map, surface, point, value, mirrorX);
                     });
}

Result<std::unique_ptr<Command>> makeFillAllCommand(Document& document, std::size_t body,
                                                    MapChannel channel, double value) {
    return paintEdit(document, body, channel, std::string("Fill ") + channelName(channel),
                     [&](const PaintedMap& map, const PaintSurface&) {
                         return fillAllChange(map, value);
                     });
}

Result<std::unique_ptr<Command>> makeNewMapCommand(Document& document, std::size_t body,
                                                   MapChannel channel, int width, int height,
                                                   double value, std::string path) {
    if (Status ok = checkTarget(document, body, channel); !ok) return ok.error();
    if (width < 1 || height < 1 || width > 16384 || height > 16384) {
        return makeError("map size must be 1..16384 pixels a side");
    }
    PaintedMap blank;
    blank.width = width;
    blank.height = height;
    blank.values.assign(static_cast<std::size_t>(width) * height,
                        static_cast<float>(std::clamp(value, 0.0, 1.0)));
    if (path.empty()) path = document.defaultMapPath(body, channel);
    return std::unique_ptr<Command>(std::make_unique<PaintCommand>(
        std::string("New ") + channelName(channel) + " map", body, channel, PixelChange{},
        std::move(blank), std::move(path)));
}

Result<std::unique_ptr<Command>> makeSetPropertyCommand(const Document& document,
                                                        const std::string& pointer,
                                                        const Json& value) {
    Json json = Json::parse(projectToJson(document.project()));
    try {
        json[Json::json_pointer(pointer)] = value;
    } catch (const Json::exception& e) {
        return makeError(pointer + ": " + e.what());
    }
    Result<Project> edited = parseProject(json.dump(), "set " + pointer, document.project().folder);
    if (!edited) return edited.error();
    return std::unique_ptr<Command>(std::make_unique<ProjectCommand>(
        "Set " + pointer, document.project(), std::move(edited).value()));
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
        if (*body >= project.bodies.size()) return makeError("no body " + std::to_string(*body));
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

}  // namespace plimsoll::editor
