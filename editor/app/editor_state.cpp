#include "app/editor_state.h"

#include "app/preview_panel.h"
#include "document/command.h"

#include <algorithm>

namespace plimsoll::editor {

PaintTarget EditorState::paintTarget() const {
    PaintTarget target;
    if (selectedBody < 0 || !document->layers(static_cast<std::size_t>(selectedBody), channel)) {
        return target;
    }
    target.layer = activeLayer;
    if (paintMask) target.part = LayerPart::Mask;
    return target;
}

bool EditorState::execute(Result<std::unique_ptr<Command>> command) {
    if (!command) {
        status = command.error().message;
        return false;
    }
    const std::string name = (*command)->name();
    Status done = document->execute(std::move(command).value());
    if (!done) {
        status = name + ": " + done.error().message;
        return false;
    }
    status = name;
    overlaysDirty = true;
    ++documentRevision;
    return true;
}

void EditorState::undo() {
    const std::string name = document->undoName();
    if (document->undo()) {
        status = "Undo " + name;
        overlaysDirty = true;
        ++documentRevision;
    }
}

void EditorState::redo() {
    const std::string name = document->redoName();
    if (document->redo()) {
        status = "Redo " + name;
        overlaysDirty = true;
        ++documentRevision;
    }
}

void EditorState::jumpToHistory(std::size_t position) {
    const std::size_t before = document->historyPosition();
    const bool ok = document->jumpToHistory(position);
    const std::size_t after = document->historyPosition();
    if (after != before) {
        overlaysDirty = true;
        ++documentRevision;
    }
    const std::size_t steps = after > before ? after - before : before - after;
    status = (after < before ? "Undid " : "Redid ") + std::to_string(steps) + " step" +
             (steps == 1 ? "" : "s") + (ok ? "" : " (a redo failed: stopped there)");
}

bool EditorState::open(const std::string& path) {
    if (path.empty()) {
        document = std::make_unique<Document>();
    } else {
        Result<std::unique_ptr<Document>> opened = Document::open(path);
        if (!opened) {
            status = opened.error().message;
            return false;
        }
        document = std::move(opened).value();
        settings.addRecent(path);
        (void)settings.save();
        recoveryOffer = Document::findAutosave(path);
    }
    physicsBakes = std::make_shared<PhysicsBakes>();  // the old document's bakes stop
    selectedBody = 0;
    activeLayer = -1;
    paintMask = false;
    layerRename = {};
    stroke = {};
    overlaysDirty = true;
    ++documentRevision;
    frameAll();
    status = path.empty() ? "New project" : "Opened " + path;
    return true;
}

std::shared_ptr<const SurfaceTextures> EditorState::physicsFor(std::size_t body) {
    return physicsBakes->texturesFor(*document, body);
}

bool EditorState::setTextureSize(std::size_t body, int size) {
    if (!execute(makeSetPropertyCommand(
            *document, "/bodies/" + std::to_string(body) + "/texture_size", size))) {
        return false;
    }
    (void)physicsFor(body);  // the bake starts now, not when a panel first looks
    if (preview && preview->session) preview->session->requestTextureSize(size, body);
    return true;
}

void EditorState::cancelTextureBake(std::size_t body) {
    const int previous = physicsBakes->cancel(body);
    if (preview && preview->session && preview->session->rebuilding())
        preview->session->cancelRebuild();
    if (previous > 0) {
        (void)execute(makeSetPropertyCommand(
            *document, "/bodies/" + std::to_string(body) + "/texture_size", previous));
        (void)physicsFor(body);  // the textures still held: no bake
    }
}

void EditorState::pollPhysicsBakes() {
    if (physicsSolids->poll()) {
        overlaysDirty = true;
        ++documentRevision;
    }
    if (physicsBakes->poll(*document)) {
        // The panels cache what they show against the revision; the document's edits are the same.
        overlaysDirty = true;
        ++documentRevision;
    }
}

void EditorState::openSaveAs() {
    const std::string name =
        !document->path().empty() ? document->path().filename().string()
        : document->project().name.empty() || document->project().name == "untitled"
            ? std::string("project.plim.json")
            : document->project().name + ".plim.json";
    browser.open(FileBrowser::Purpose::SaveProjectAs, document->project().folder, name);
}

void EditorState::save() {
    if (document->path().empty()) {
        openSaveAs();
        return;
    }
    Status saved = document->save();
    status = saved ? "Saved " + document->path().string() : saved.error().message;
    if (saved) {
        settings.addRecent(document->path());
        (void)settings.save();
    }
}

void EditorState::saveAs(const std::filesystem::path& path, bool replace) {
    std::filesystem::path target = path;
    if (target.string().find(".plim.json") == std::string::npos) target += ".plim.json";
    pendingSaveAs.reset();
    if (!replace) {
        // Replacing another file is asked first; a file the project reads is refused at once.
        Result<std::vector<std::filesystem::path>> replaces = document->replacedBySaveAs(target);
        if (!replaces) {
            status = replaces.error().message;
            return;
        }
        if (!replaces->empty()) {
            pendingSaveAs = target;
            pendingSaveAsReplaces = std::move(*replaces);
            return;
        }
    }
    // A new project ("untitled") takes the name it is saved under, as a document does in any
    // program; a project that has a name keeps it.
    if (document->project().name == "untitled") {
        std::string stem = target.filename().string();
        const std::string suffix = ".plim.json";
        if (stem.ends_with(suffix)) stem.resize(stem.size() - suffix.size());
        if (!stem.empty()) {
            // A project edit of its own (an empty project, which the JSON edit path refuses to
            // parse back, can be named too).
            Project named = document->project();
            named.name = stem;
            (void)execute(std::unique_ptr<Command>(std::make_unique<ProjectCommand>(
                "Name the project " + stem, document->project(), std::move(named))));
        }
    }
    Status saved = document->saveAs(target, replace);
    status = saved ? "Saved " + target.string() : saved.error().message;
    if (saved) {
        settings.addRecent(target);
        (void)settings.save();
        overlaysDirty = true;
    }
}

void EditorState::frameAll() {
    Bounds3 bounds = document->worldBounds();
    if (bounds.min.x() > bounds.max.x()) {
        bounds.min = Eigen::Vector3d::Constant(-1);
        bounds.max = Eigen::Vector3d::Constant(1);
    }
    const bool ortho = camera.orthographic;
    const double yaw = camera.yaw, pitch = camera.pitch;
    camera.frame(bounds);
    camera.orthographic = ortho;
    camera.yaw = yaw;
    camera.pitch = pitch;
}

void EditorState::setView(ViewPreset view) {
    Bounds3 bounds = document->worldBounds();
    if (bounds.min.x() > bounds.max.x()) {
        bounds.min = Eigen::Vector3d::Constant(-1);
        bounds.max = Eigen::Vector3d::Constant(1);
    }
    camera = Camera::preset(view, bounds);
}

std::optional<EditorState::SurfacePick> EditorState::pickSurface(float x, float y) const {
    const auto hit = pickHit(x, y);
    if (!hit) return std::nullopt;
    const TriangleMesh& mesh = *document->assets(hit->first).mesh;
    // The hit triangle's outward normal (the ray cast names the triangle it hit).
    const Triangle& t = mesh.triangles[hit->second.triangle];
    const Eigen::Vector3d n = (mesh.positions[t[1]] - mesh.positions[t[0]])
                                  .cross(mesh.positions[t[2]] - mesh.positions[t[0]]);
    const Eigen::Vector3d normal =
        n.norm() > 0 ? Eigen::Vector3d(n.normalized()) : Eigen::Vector3d::UnitY();
    const Pose pose = shownPose(hit->first);
    return SurfacePick{hit->first, pose.apply(hit->second.point), pose.rotation * normal};
}

Pose EditorState::shownPose(std::size_t body) const {
    return body < previewPoses.size() ? previewPoses[body] : document->bodyPose(body);
}

std::optional<std::pair<std::size_t, Eigen::Vector3d>> EditorState::pick(float x, float y) const {
    const auto hit = pickHit(x, y);
    if (!hit) return std::nullopt;
    return std::make_pair(hit->first, hit->second.point);
}

std::optional<std::pair<std::size_t, SurfaceHit>> EditorState::pickHit(float x, float y) const {
    if (viewport.w < 1 || viewport.h < 1) return std::nullopt;
    Eigen::Vector3d origin, direction;
    camera.rayThrough(x - viewport.x, y - viewport.y, static_cast<int>(viewport.w),
                      static_cast<int>(viewport.h), origin, direction);
    std::optional<std::pair<std::size_t, SurfaceHit>> best;
    double bestDistance = 1e300;
    for (std::size_t b = 0; b < document->bodyCount(); ++b) {
        const auto& mesh = document->assets(b).mesh;
        if (!mesh) continue;
        const Pose pose = shownPose(b);
        // Into object space: p = R^T (w - t).
        const Eigen::Vector3d o = pose.rotation.transpose() * (origin - pose.translation);
        const Eigen::Vector3d d = pose.rotation.transpose() * direction;
        if (auto hit = raycast(*mesh, o, d); hit && hit->distance < bestDistance) {
            bestDistance = hit->distance;
            best = std::make_pair(b, *hit);
        }
    }
    return best;
}

}  // namespace plimsoll::editor
