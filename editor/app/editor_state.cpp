#include "app/editor_state.h"

#include <algorithm>

namespace plimsoll::editor {

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
    selectedBody = 0;
    stroke = {};
    overlaysDirty = true;
    ++documentRevision;
    frameAll();
    status = path.empty() ? "New project" : "Opened " + path;
    return true;
}

void EditorState::save() {
    if (document->path().empty()) {
        browser.open(FileBrowser::Purpose::SaveProjectAs, document->project().folder);
        return;
    }
    Status saved = document->save();
    status = saved ? "Saved " + document->path().string() : saved.error().message;
    if (saved) {
        settings.addRecent(document->path());
        (void)settings.save();
    }
}

void EditorState::saveAs(const std::filesystem::path& path) {
    std::filesystem::path target = path;
    if (target.string().find(".plim.json") == std::string::npos) target += ".plim.json";
    Status saved = document->saveAs(target);
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

std::optional<std::pair<std::size_t, Eigen::Vector3d>> EditorState::pick(float x, float y) const {
    if (viewport.w < 1 || viewport.h < 1) return std::nullopt;
    Eigen::Vector3d origin, direction;
    camera.rayThrough(x - viewport.x, y - viewport.y, static_cast<int>(viewport.w),
                      static_cast<int>(viewport.h), origin, direction);
    std::optional<std::pair<std::size_t, Eigen::Vector3d>> best;
    double bestDistance = 1e300;
    for (std::size_t b = 0; b < document->bodyCount(); ++b) {
        const auto& mesh = document->assets(b).mesh;
        if (!mesh) continue;
        const Pose pose = document->bodyPose(b);
        // Into object space: p = R^T (w - t).
        const Eigen::Vector3d o = pose.rotation.transpose() * (origin - pose.translation);
        const Eigen::Vector3d d = pose.rotation.transpose() * direction;
        if (auto hit = raycast(*mesh, o, d); hit && hit->distance < bestDistance) {
            bestDistance = hit->distance;
            best = std::make_pair(b, hit->point);
        }
    }
    return best;
}

}  // namespace plimsoll::editor
