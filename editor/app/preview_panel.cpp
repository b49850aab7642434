// The live preview's controls, its input (grabbing a body) and what it draws over the 3D view
// (preview_panel.h). Index:
//   [SECTION] session start / update
//   [SECTION] control window
//   [SECTION] grabbing
//   [SECTION] drawing over the view (arrows, waterline, performance)
//   [SECTION] scene and report
#include "app/preview_panel.h"

#include "app/panels.h"  // tooltip

#include "document/command.h"

#include <imgui.h>
#include <imgui_internal.h>  // MovingWindow: the user moved the window

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>

namespace plimsoll::editor {

namespace {

/// Overlay texture slots of the wet-texel images, clear of the document's (one per body).
constexpr int kWetSlotBase = 1000;

const char* const kIntegratorNames[] = {"explicit Euler", "semi-implicit Euler", "RK4"};
constexpr Integrator kIntegrators[] = {Integrator::ExplicitEuler, Integrator::SemiImplicitEuler,
                                       Integrator::RK4};
constexpr int kTextureSizes[] = {32, 64, 128, 256, 512, 1024, 2048};

PreviewUi& ui(EditorState& s) {
    if (!s.preview) s.preview = std::make_shared<PreviewUi>();
    return *s.preview;
}

ImU32 colourOf(const Eigen::Vector3f& c, int alpha = 255) {
    return IM_COL32(int(255 * c.x()), int(255 * c.y()), int(255 * c.z()), alpha);
}

}  // namespace

// [SECTION] session start / update -------------------------------------------------------------

bool startPreview(EditorState& s, bool play) {
    PreviewUi& p = ui(s);
    p.open = true;
    p.error.clear();
    p.session.reset();
    // The preview runs the document as edited, saved or not: its meshes, graphs and maps in
    // memory, the files untouched.
    Result<Scene> scene = s.document->simulationScene();
    if (!scene) {
        p.error = scene.error().message;
        s.status = "Live preview: " + p.error;
        return false;
    }
    Result<std::unique_ptr<PreviewSession>> made =
        PreviewSession::create(std::move(*scene), p.device);
    if (!made) {
        p.error = made.error().message;
        s.status = "Live preview: " + p.error;
        return false;
    }
    p.session = std::move(*made);
    p.session->setSeaFloor(s.settings.seaFloor);
    // Notes the paint the preview starts from; later edits go in as they are made.
    (void)p.session->followDocument(*s.document);
    p.followedState = s.document->stateId();
    for (int i = 0; i < 3; ++i) {
        if (kIntegrators[i] == p.session->scene().simulation.integrator) p.integrator = i;
    }
    p.lastCheckTime = -1;
    p.plotted.clear();
    if (play) p.session->play();
    s.status = "Live preview on " + p.session->deviceName();
    return true;
}

/// A line per body whose edited water graph the preview holds back, in red, for as long as
/// it does: the status line's message is replaced by the next one, this stays.
static void drawHeldGraphs(const PreviewSession& session) {
    for (std::size_t b = 0; b < session.scene().bodies.size(); ++b) {
        const std::string problem = session.graphProblem(b);
        if (problem.empty()) continue;
        ImGui::PushStyleColor(ImGuiCol_Text, ImVec4(1, 0.45f, 0.4f, 1));
        ImGui::TextWrapped("%s: water graph not simulated (%s); the last valid one runs",
                           session.scene().bodies[b].label.c_str(), problem.c_str());
        ImGui::PopStyleColor();
    }
}

void stopPreview(EditorState& s) {
    PreviewUi& p = ui(s);
    const bool wasRunning = static_cast<bool>(p.session);
    p.session.reset();
    s.previewPoses.clear();
    s.overlaysDirty = true;  // the document's overlays back on the bodies
    // The status line said where the preview ran; it no longer does.
    if (wasRunning) s.status = "Live preview stopped";
}

void updatePreview(EditorState& s, double wallSeconds) {
    if (!s.preview || !s.preview->session) return;
    PreviewUi& p = *s.preview;
    PreviewSession& session = *p.session;
    if (s.document->stateId() != p.followedState) {
        // An edit (a stroke, a fill, an undo) while it runs: the next frame simulates it.
        p.followedState = s.document->stateId();
        Result<std::vector<std::size_t>> taken = session.followDocument(*s.document);
        if (!taken)
            s.status = "Live preview: " + taken.error().message;
        else if (!taken->empty())
            s.status = "Live preview: the new paint is simulated";
    }
    Status done = Ok{};
    if (p.fixedStep) {
        if (session.playing()) done = session.step();
    } else {
        Result<int> frames = session.update(wallSeconds);
        if (!frames) done = frames.error();
    }
    if (!done.ok()) {
        session.pause();
        p.error = done.error().message;
        s.status = "Live preview stopped: " + p.error;
    }
    // The volume error, four times a simulated second (an exact clip of the mesh each time).
    const double now = session.world().time();
    if (p.lastCheckTime < 0 || std::abs(now - p.lastCheckTime) >= 0.25) {
        p.lastCheckTime = now;
        const std::size_t body =
            std::clamp<std::size_t>(static_cast<std::size_t>(std::max(0, s.selectedBody)), 0,
                                    session.world().bodies().size() - 1);
        Result<SubmergedVolumeCheck> check = session.volumeCheck(body);
        char line[256];
        if (check) {
            std::snprintf(line, sizeof line,
                          "%s: texture %.6g m^3, exact %.6g m^3, error %+.3g m^3 (%+.3f %%)",
                          session.world().bodies()[body].name.c_str(), check->texture, check->exact,
                          check->error, 100.0 * check->relativeError);
            p.lastCheck = line;
        } else {
            p.lastCheck = check.error().message;
        }
    }
}

// [SECTION] control window ---------------------------------------------------------------------

namespace {

/// The water model's controls; true when something changed.
bool editWater(WaterModel& water) {
    bool changed = false;
    const char* kinds[] = {"flat", "Gerstner waves", "height field"};
    int kind = static_cast<int>(water.kind);
    // A height field needs its grid file: it can be kept, not chosen here.
    if (ImGui::Combo("water", &kind, kinds, water.kind == WaterModel::Kind::HeightField ? 3 : 2)) {
        water.kind = static_cast<WaterModel::Kind>(kind);
        if (water.kind == WaterModel::Kind::Gerstner && water.waves.empty()) {
            water.waves.push_back(GerstnerWave{});
        }
        changed = true;
    }
    tooltip("Flat water, or a sum of Gerstner waves; a height field comes from the project.");
    float level = static_cast<float>(water.level);
    if (ImGui::DragFloat("level (m)", &level, 0.01f)) {
        water.level = level;
        changed = true;
    }
    tooltip("The still-water height, metres (drag, or Ctrl+click to type).");
    if (water.kind == WaterModel::Kind::Gerstner) {
        for (std::size_t i = 0; i < water.waves.size(); ++i) {
            GerstnerWave& w = water.waves[i];
            ImGui::PushID(static_cast<int>(i));
            ImGui::Text("wave %zu", i + 1);
            float a = float(w.amplitude), l = float(w.wavelength), q = float(w.steepness);
            if (ImGui::SliderFloat("amplitude (m)", &a, 0.0f, 2.0f))
                w.amplitude = a, changed = true;
            tooltip("Half the wave's height from trough to crest, metres.");
            if (ImGui::SliderFloat("wavelength (m)", &l, 0.5f, 100.0f, "%.2f",
                                   ImGuiSliderFlags_Logarithmic)) {
                w.wavelength = l;
                changed = true;
            }
            tooltip("Crest to crest, metres; the period follows from deep-water dispersion.");
            if (ImGui::SliderFloat("steepness", &q, 0.0f, 1.0f)) w.steepness = q, changed = true;
            tooltip(
                "Gerstner's Q: 0 is a sine wave, 1 sharp crests (above 1 the surface would loop).");
            ImGui::PopID();
        }
        if (ImGui::SmallButton("add wave")) {
            water.waves.push_back(GerstnerWave{});
            changed = true;
        }
        tooltip("Adds another wave to the sum.");
        if (water.waves.size() > 1) {
            ImGui::SameLine();
            if (ImGui::SmallButton("remove last")) {
                water.waves.pop_back();
                changed = true;
            }
            tooltip("Removes the last wave of the sum.");
        }
    }
    return changed;
}

/// The physics texture size: the running one, or the one being baked with its progress and
/// Cancel. The bake runs on a worker; the running size stays until the new one is ready.
void drawTextureSizeChoice(PreviewSession& session) {
    const int running = session.textureSize();
    const int baking = session.rebuildingSize();
    char label[32];
    std::snprintf(label, sizeof label, "%d^2", running);
    if (ImGui::BeginCombo("physics texture", label)) {
        for (int size : kTextureSizes) {
            std::snprintf(label, sizeof label, size == baking ? "%d^2 (baking)" : "%d^2", size);
            if (ImGui::Selectable(label, size == running) && size != baking) {
                // The running size again: just stop the bake of another.
                if (size == running)
                    session.cancelRebuild();
                else
                    session.requestTextureSize(size);
            }
        }
        ImGui::EndCombo();
    }
    if (ImGui::IsItemHovered()) {
        ImGui::SetTooltip(
            "Texels per side of the physics textures the preview simulates with. A new "
            "size is baked in the background; the current one runs until it is ready.");
    }
    if (baking > 0) {
        char overlay[48];
        std::snprintf(overlay, sizeof overlay, "baking %d^2: %.0f %%", baking,
                      100.0 * session.rebuildProgress());
        ImGui::ProgressBar(static_cast<float>(session.rebuildProgress()), ImVec2(-70.0f, 0.0f),
                           overlay);
        ImGui::SameLine();
        if (ImGui::Button("Cancel")) session.cancelRebuild();
        tooltip("Stops the bake; the preview keeps its current size.");
        ImGui::TextWrapped("Running at %d^2 until the new bake is ready.", running);
    } else if (!session.rebuildError().empty()) {
        ImGui::TextWrapped("The new size failed to bake: %s", session.rebuildError().c_str());
    }
}

/// Moves the current window back inside the view where it reaches past it (a window made
/// smaller, a section opened): never over the status bar or off the screen.
void keepInsideView(const Rect& view) {
    const ImVec2 at = ImGui::GetWindowPos(), size = ImGui::GetWindowSize();
    ImVec2 to = at;
    to.x = std::max(view.x, std::min(to.x, view.x + view.w - size.x));
    to.y = std::max(view.y, std::min(to.y, view.y + view.h - size.y));
    if (to.x != at.x || to.y != at.y) ImGui::SetWindowPos(to);
}

/// The sea floor's switch and depth; a change goes to the session and the settings.
void drawSeaFloorControls(EditorState& s, PreviewSession& session) {
    SeaFloor floor = session.seaFloor();
    bool changed = ImGui::Checkbox("sea floor", &floor.enabled);
    tooltip("A floor the bodies rest on, so that a sinking body stays in view");
    ImGui::BeginDisabled(!floor.enabled);
    float depth = static_cast<float>(floor.depth);
    if (ImGui::DragFloat("depth", &depth, 0.05f, 0.1f, 1000.0f, "%.2f m",
                         ImGuiSliderFlags_AlwaysClamp)) {
        floor.depth = depth;
        changed = true;
    }
    const bool done = ImGui::IsItemDeactivatedAfterEdit();
    tooltip("How far below the still-water level the floor lies (kept in the settings)");
    ImGui::EndDisabled();
    if (changed) {
        session.setSeaFloor(floor);
        s.settings.seaFloor = session.seaFloor();
    }
    // Written when a change is finished, not at every step of a drag.
    if ((changed && !ImGui::IsItemActive()) || done) (void)s.settings.save();
}

}  // namespace

void drawPreviewPanel(EditorState& s) {
    PreviewUi& p = ui(s);
    s.previewWindow.setEmpty();
    if (!p.open) return;
    // The view's lower-left corner, its sections folded: the bodies stay in sight. Anchored
    // there (sections opened grow it upward, a window resized keeps it in the corner) until
    // the user moves it.
    if (p.anchored) {
        ImGui::SetNextWindowPos(ImVec2(s.viewport.x + 8, s.viewport.y + s.viewport.h - 8),
                                ImGuiCond_Always, ImVec2(0, 1));
    }
    ImGui::SetNextWindowSize(ImVec2(340, 0), ImGuiCond_FirstUseEver);
    const bool expanded = ImGui::Begin("Live preview", &p.open);
    if (ImGui::GetCurrentContext()->MovingWindow == ImGui::GetCurrentWindow() &&
        ImGui::IsMouseDragging(0)) {
        p.anchored = false;
    }
    keepInsideView(s.viewport);
    // Its rectangle, folded to its title bar or not: the view's legend moves out from under it.
    const ImVec2 at = ImGui::GetWindowPos(), size = ImGui::GetWindowSize();
    s.previewWindow = Eigen::AlignedBox2f(Eigen::Vector2f(at.x, at.y),
                                          Eigen::Vector2f(at.x + size.x, at.y + size.y));
    if (!expanded) {
        ImGui::End();
        return;
    }
    if (!p.session) {
        const char* devices[] = {"default", "reference", "cpu", "gpu"};
        int device = 0;
        for (int i = 1; i < 4; ++i) {
            if (p.device == devices[i]) device = i;
        }
        if (ImGui::Combo("device", &device, devices, 4))
            p.device = device == 0 ? "" : devices[device];
        tooltip(
            "Where the buoyancy is computed: the default device, the reference code, the CPU or "
            "the GPU");
        if (ImGui::Button("Start")) startPreview(s, true);
        tooltip("Simulate the project as it is now, unsaved edits included (P)");
        if (!p.error.empty()) ImGui::TextWrapped("%s", p.error.c_str());
        ImGui::End();
        return;
    }
    PreviewSession& session = *p.session;
    if (ImGui::Button(session.playing() ? "Pause" : "Play")) {
        session.playing() ? session.pause() : session.play();
    }
    tooltip("Play or pause the simulation (Space)");
    ImGui::SameLine();
    if (ImGui::Button("Step")) {
        session.pause();
        if (Status st = session.step(); !st.ok()) p.error = st.error().message;
    }
    tooltip("Pause and advance one frame");
    ImGui::SameLine();
    if (ImGui::Button("Reset")) {
        if (Status st = session.reset(); !st.ok()) p.error = st.error().message;
        p.lastCheckTime = -1;
    }
    tooltip("Back to the starting poses at t = 0, keeping the settings changed here");
    ImGui::SameLine();
    const bool stop = ImGui::Button("Stop");
    tooltip("End the preview (P): the view shows the project's starting poses again");
    if (stop) {
        stopPreview(s);
        ImGui::End();
        return;
    }
    ImGui::SameLine();
    ImGui::Text("t = %.2f s", session.world().time());
    drawHeldGraphs(session);
    float scale = static_cast<float>(session.timeScale());
    if (ImGui::SliderFloat("time scale", &scale, 0.05f, 4.0f, "%.2fx",
                           ImGuiSliderFlags_Logarithmic)) {
        session.setTimeScale(scale);
    }
    tooltip("Simulated seconds per wall-clock second");

    if (ImGui::CollapsingHeader("Water")) {
        WaterModel water = session.scene().water;
        if (editWater(water)) session.setWater(water);
        // The preview's water is its own until kept: one undoable project edit.
        const bool differs = !(session.scene().water == s.document->project().water);
        ImGui::BeginDisabled(!differs);
        if (ImGui::Button("Keep in project")) {
            Project after = s.document->project();
            after.water = session.scene().water;
            s.execute(std::unique_ptr<Command>(std::make_unique<ProjectCommand>(
                "Keep the preview's water", s.document->project(), std::move(after))));
        }
        ImGui::EndDisabled();
        tooltip(differs ? "Write these water and wave settings into the project (undoable)"
                        : "The project's water is the same");
    }
    if (ImGui::CollapsingHeader("Sea floor")) drawSeaFloorControls(s, session);
    if (ImGui::CollapsingHeader("Speed and accuracy")) {
        if (ImGui::Combo("integrator", &p.integrator, kIntegratorNames, 3)) {
            session.setIntegrator(kIntegrators[p.integrator]);
        }
        tooltip("How each step advances the bodies (the accuracy against cost trade-off)");
        drawTextureSizeChoice(session);
        const PreviewTimings& t = session.timings();
        ImGui::Text("device: %s", session.deviceName().c_str());
        ImGui::Text("kernel %.3f ms / frame, step %.3f ms / frame (%d sub-steps)", t.kernelMs,
                    t.frameMs, t.subSteps);
        ImGui::Text("bodies %zu, texels %zu (texture %d^2)", session.world().bodies().size(),
                    session.coveredTexels(), session.textureSize());
        if (t.droppedFrames > 0)
            ImGui::Text("behind real time: %d frames dropped", t.droppedFrames);
        ImGui::TextWrapped("submerged volume vs exact (flat water at the mean level): %s",
                           p.lastCheck.c_str());
    }
    if (ImGui::CollapsingHeader("Show")) {
        ImGui::Checkbox("forces", &p.showForces);
        tooltip(
            "Weight (red, at the centre of mass) and buoyancy (green, at the centre of buoyancy)");
        ImGui::SameLine();
        ImGui::Checkbox("waterline", &p.showWaterline);
        tooltip("Where the water surface cuts the hull");
        ImGui::SameLine();
        ImGui::Checkbox("wet texels", &p.showWetTexels);
        tooltip("The texels under water this frame, over the hull");
        ImGui::Checkbox("performance", &p.showPerformance);
        tooltip("Frame, step and kernel times over the view");
        ImGui::SameLine();
        ImGui::Checkbox("plots", &p.showPlots);
        tooltip("The plot windows of the recorded quantities");
        ImGui::Checkbox("camera follows the body", &p.followBody);
        tooltip("The view's centre stays on the selected body's centre of mass as it moves (C)");
    }
    ImGui::TextDisabled(s.tool == Tool::Brush
                            ? "The Brush paints on the floating body; the simulation takes each "
                              "stroke at once. Another tool: left-drag a body to pull it."
                            : "Left-drag a body to pull it (a spring).");
    if (!p.error.empty()) ImGui::TextWrapped("%s", p.error.c_str());
    ImGui::End();
}

// [SECTION] grabbing ---------------------------------------------------------------------------

namespace {

void mouseRay(const EditorState& s, Eigen::Vector3d& origin, Eigen::Vector3d& direction) {
    const ImVec2 mouse = ImGui::GetIO().MousePos;
    s.camera.rayThrough(mouse.x - s.viewport.x, mouse.y - s.viewport.y,
                        static_cast<int>(s.viewport.w), static_cast<int>(s.viewport.h), origin,
                        direction);
}
}  // namespace

bool previewInput(EditorState& s) {
    if (!s.preview || !s.preview->session) return false;
    PreviewSession& session = *s.preview->session;
    const ImGuiIO& io = ImGui::GetIO();
    GrabDrag& grabDrag = s.preview->grabDrag;
    if (grabDrag.active) {
        if (!ImGui::IsMouseDown(0) || !session.grabbing()) {
            session.release();
            grabDrag.active = false;
            return true;
        }
        // The target: the mouse ray on the plane through the grab facing the camera.
        Eigen::Vector3d origin, direction;
        mouseRay(s, origin, direction);
        const Eigen::Vector3d normal = s.camera.forward();
        const double denom = direction.dot(normal);
        if (std::abs(denom) > 1e-9) {
            const double t = (grabDrag.planePoint - origin).dot(normal) / denom;
            if (t > 0) session.moveGrab(origin + t * direction);
        }
        return true;
    }
    const ImVec2 mouse = io.MousePos;
    // With the Brush the left mouse paints, on the body where it floats now (viewportInput).
    if (io.WantCaptureMouse || io.KeyAlt || !s.viewport.contains(mouse.x, mouse.y) ||
        !ImGui::IsMouseClicked(0) || s.tool == Tool::Brush) {
        return false;
    }
    Eigen::Vector3d origin, direction;
    mouseRay(s, origin, direction);
    std::optional<std::pair<std::size_t, Eigen::Vector3d>> best;
    double bestDistance = 1e300;
    const auto& bodies = session.world().bodies();
    for (std::size_t b = 0; b < bodies.size() && b < s.document->bodyCount(); ++b) {
        const auto& mesh = s.document->assets(b).mesh;
        if (!mesh) continue;
        const Pose pose = bodies[b].pose();
        const Eigen::Vector3d o = pose.rotation.transpose() * (origin - pose.translation);
        const Eigen::Vector3d d = pose.rotation.transpose() * direction;
        if (auto hit = raycast(*mesh, o, d); hit && hit->distance < bestDistance) {
            bestDistance = hit->distance;
            best = std::make_pair(b, hit->point);
        }
    }
    if (!best) return false;  // empty space: the view navigates
    const Eigen::Vector3d world = bodies[best->first].pose().apply(best->second);
    if (!session.grab(best->first, best->second, world).ok()) return false;
    s.selectedBody = static_cast<int>(best->first);
    grabDrag = {true, world};
    // A painter with a fill or the picker up learns why the drag pulled (the Brush paints).
    if (s.tool != Tool::Navigate) {
        s.status =
            "The live preview is running: the left mouse pulls the body. The Brush (B) "
            "paints on it, or stop the preview (P)";
    }
    return true;
}

// [SECTION] drawing over the view --------------------------------------------------------------

void drawPreviewOverlay(EditorState& s) {
    if (!s.preview || !s.preview->session) return;
    PreviewUi& p = *s.preview;
    PreviewSession& session = *p.session;
    ImDrawList* draw = ImGui::GetForegroundDrawList();
    const ImVec2 lo(s.viewport.x, s.viewport.y),
        hi(s.viewport.x + s.viewport.w, s.viewport.y + s.viewport.h);
    draw->PushClipRect(lo, hi, true);
    const int w = static_cast<int>(s.viewport.w), h = static_cast<int>(s.viewport.h);
    auto screen = [&](const Eigen::Vector3d& world) -> std::optional<ImVec2> {
        const auto px = s.camera.toPixel(world, w, h);
        if (!px) return std::nullopt;
        return ImVec2(s.viewport.x + float(px->x()), s.viewport.y + float(px->y()));
    };
    std::vector<const TriangleMesh*> meshes;
    for (std::size_t b = 0; b < session.world().bodies().size(); ++b) {
        meshes.push_back(b < s.document->bodyCount() && p.showWaterline
                             ? s.document->assets(b).mesh.get()
                             : nullptr);
    }
    const ForceOverlay overlay = buildForceOverlay(session.world(), meshes);
    if (p.showWaterline) {
        const ImU32 colour = colourOf(kWaterlineColour);
        for (const OverlaySegment& seg : overlay.waterline) {
            const auto a = screen(seg.a), b = screen(seg.b);
            if (a && b) draw->AddLine(*a, *b, colour, 2.0f);
        }
    }
    if (p.showForces) {
        // On a symmetric body the arrows are collinear (front view): buoyancy widest at the
        // bottom, drag on it, the weight thinnest on top, so that each stays visible.
        const std::pair<Eigen::Vector3f, float> order[] = {
            {kBuoyancyColour, 9.0f}, {kDragColour, 5.0f}, {kWeightColour, 3.0f}};
        for (const auto& [kind, thickness] : order) {
            for (const OverlayArrow& arrow : overlay.arrows) {
                if (arrow.colour != kind) continue;
                const auto a = screen(arrow.from), b = screen(arrow.to);
                if (!a || !b) continue;
                const ImU32 colour = colourOf(arrow.colour);
                draw->AddLine(*a, *b, colour, thickness);
                const float dx = b->x - a->x, dy = b->y - a->y;
                const float length = std::sqrt(dx * dx + dy * dy);
                if (length > 1.0f) {
                    const float ux = dx / length, uy = dy / length,
                                head = std::min(10.0f + thickness, 0.4f * length);
                    draw->AddTriangleFilled(*b,
                                            ImVec2(b->x - ux * head - uy * head * 0.5f,
                                                   b->y - uy * head + ux * head * 0.5f),
                                            ImVec2(b->x - ux * head + uy * head * 0.5f,
                                                   b->y - uy * head - ux * head * 0.5f),
                                            colour);
                }
                draw->AddCircleFilled(*a, thickness, colour);
            }
        }
    }
    if (session.grabbing()) {
        const auto a = screen(session.grabPoint()), b = screen(session.grabTarget());
        if (a && b) {
            draw->AddLine(*a, *b, IM_COL32(255, 255, 255, 220), 1.5f);
            draw->AddCircleFilled(*b, 4.0f, IM_COL32(255, 255, 255, 220));
        }
    }
    draw->PopClipRect();
    if (p.showPerformance) {
        const PreviewTimings& t = session.timings();
        char text[256];
        std::snprintf(text, sizeof text,
                      "frame %.2f ms   step %.2f ms\nkernel %.3f ms\nbodies %zu, texels %zu, %s",
                      p.uiFrameMs, t.frameMs, t.kernelMs, session.world().bodies().size(),
                      session.coveredTexels(), session.playing() ? "playing" : "paused");
        // Bottom right of the view, the corner no window opens in (the title line is top left,
        // the plots top right, the Live preview bottom left), clear of the Live preview and the
        // legend where a narrow view brings them near; behind the floating windows, as the
        // title is, so that a window moved over it stays whole.
        const ImVec2 textSize = ImGui::CalcTextSize(text);
        const Eigen::Vector2f size(textSize.x + 8, textSize.y + 4);  // with its backing's margin
        const Eigen::AlignedBox2f avoid[] = {s.previewWindow, s.legendBox};
        const Eigen::Vector2f place =
            overlayPlace(s.viewport.box(), size, avoid, ViewCorner::LowerRight);
        const ImVec2 at(place.x() + 4, place.y() + 2);
        ImDrawList* behind = ImGui::GetBackgroundDrawList();
        behind->AddRectFilled(ImVec2(place.x(), place.y()),
                              ImVec2(place.x() + size.x(), place.y() + size.y()),
                              IM_COL32(0, 0, 0, 140));
        behind->AddText(at, IM_COL32(230, 230, 230, 255), text);
    }
}

// [SECTION] scene and report -------------------------------------------------------------------

void applyPreviewToScene(EditorState& s, RenderScene& scene) {
    if (!s.preview || !s.preview->session) return;
    PreviewUi& p = *s.preview;
    const World& world = p.session->world();
    scene.time = world.time();
    scene.water = s.showWater ? &world.scene().water : nullptr;
    scene.floor = p.session->floorHeight();
    if (p.followBody && s.selectedBody >= 0 &&
        static_cast<std::size_t>(s.selectedBody) < world.bodies().size()) {
        // Before the scene is drawn: the camera looks at where the body is this frame.
        s.camera.target = world.bodies()[static_cast<std::size_t>(s.selectedBody)].state.position;
    }
    s.previewPoses.clear();
    for (const SimulatedBody& body : world.bodies()) s.previewPoses.push_back(body.pose());
    for (std::size_t b = 0; b < scene.bodies.size() && b < world.bodies().size(); ++b) {
        scene.bodies[b].pose = world.bodies()[b].pose();
        // With the Brush the hull shows the map being painted, not the wet texels.
        if (p.showWetTexels && s.tool != Tool::Brush) {
            const int slot = kWetSlotBase + static_cast<int>(b);
            const SimulatedBody& body = world.bodies()[b];
            if (p.wetSamples.size() <= b) p.wetSamples.resize(b + 1);
            PreviewUi::WetSamples& wet = p.wetSamples[b];
            const std::uint64_t key = texturesKey(body.textures);  // 1 ms at 1024^2
            if (wet.finding.valid() &&
                wet.finding.wait_for(std::chrono::seconds(0)) == std::future_status::ready) {
                wet.ready = wet.finding.get();
            }
            if (wet.ready.key != key && !(wet.finding.valid() && wet.findingKey == key)) {
                // Other textures: their samples found on a worker, from a copy of where the
                // covered texels are (the world may be swapped again meanwhile).
                wet.findingKey = key;
                wet.finding = std::async(std::launch::async, [size = body.textures.size,
                                                              index = body.textures.texelIndex] {
                    lowerThisThreadsPriority();
                    return wetTexelSamples(size, index);
                });
            }
            // Until they arrive the last image stays (a frame or two; none at the start).
            if (wet.ready.key == key && wet.ready.shown > 0) {
                s.renderer->setOverlay(
                    slot, wetTexelOverlay(body, world.scene().water, world.time(), wet.ready));
            }
            if (s.renderer->overlayTexture(slot)) scene.bodies[b].overlay = slot;
        }
    }
}

nlohmann::json previewReport(const EditorState& s) {
    nlohmann::json out;
    if (!s.preview || !s.preview->session) return out;
    const PreviewSession& session = *s.preview->session;
    const World& world = session.world();
    auto vec = [](const Eigen::Vector3d& v) { return nlohmann::json{v.x(), v.y(), v.z()}; };
    out["time"] = world.time();
    out["device"] = session.deviceName();
    out["kernel_ms"] = session.timings().kernelMs;
    out["step_ms"] = session.timings().frameMs;
    out["sub_steps"] = session.timings().subSteps;
    out["texels"] = session.coveredTexels();
    std::vector<const TriangleMesh*> none(world.bodies().size(), nullptr);
    const ForceOverlay overlay = buildForceOverlay(world, none);
    nlohmann::json arrows = nlohmann::json::array();
    for (const OverlayArrow& a : overlay.arrows) {
        arrows.push_back({{"from", vec(a.from)},
                          {"to", vec(a.to)},
                          {"colour", {a.colour.x(), a.colour.y(), a.colour.z()}}});
    }
    out["arrows"] = arrows;
    nlohmann::json bodies = nlohmann::json::array();
    for (const SimulatedBody& b : world.bodies()) {
        bodies.push_back({{"name", b.name},
                          {"center_of_mass", vec(b.state.position)},
                          {"center_of_buoyancy", vec(b.buoyancy.centerOfBuoyancy)},
                          {"submerged_volume", b.buoyancy.submergedVolume}});
    }
    out["bodies"] = bodies;
    const Camera& c = s.camera;
    out["camera"] = {{"target", vec(c.target)}, {"yaw", c.yaw},
                     {"pitch", c.pitch},        {"distance", c.distance},
                     {"fov_y", c.fovY},         {"orthographic", c.orthographic}};
    return out;
}

}  // namespace plimsoll::editor
