// The 3D view: Blender-like navigation (middle mouse orbits, Shift pans, Ctrl or the wheel
// zooms; Alt + left mouse orbits too), painting with the left mouse, and what is drawn over the
// scene (view name, brush circle).
#include "app/panels.h"

#include "document/command.h"

#include <GLFW/glfw3.h>
#include <imgui.h>

#include <cmath>

namespace plimsoll::editor {

namespace {

struct DragState {
    bool navigating = false;
    int button = -1;
};
DragState drag;

const char* viewName(const Camera& c) {
    const double halfPi = 1.5707963267948966;
    if (!c.orthographic) return "Perspective";
    if (std::abs(c.pitch - halfPi) < 1e-6) return "Top (orthographic)";
    if (std::abs(c.pitch) < 1e-6 && std::abs(c.yaw) < 1e-6) return "Front (orthographic)";
    if (std::abs(c.pitch) < 1e-6 && std::abs(c.yaw - halfPi) < 1e-6) return "Side (orthographic)";
    return "User (orthographic)";
}

void addStrokePoint(EditorState& s, const Eigen::Vector3d& p) {
    if (!s.stroke.points.empty() &&
        (p - s.stroke.points.back()).norm() < s.brush.radius * 0.25) {
        return;
    }
    s.stroke.points.push_back(p);
    s.stroke.previewDirty = true;
}

}  // namespace

void viewportInput(EditorState& s) {
    ImGuiIO& io = ImGui::GetIO();
    const ImVec2 mouse = io.MousePos;
    const bool hovered = s.viewport.contains(mouse.x, mouse.y) && !io.WantCaptureMouse;
    const double dx = io.MouseDelta.x / std::max(1.0f, s.viewport.h);
    const double dy = io.MouseDelta.y / std::max(1.0f, s.viewport.h);

    // The water graph's tools take the left mouse first while its panel edits in the view
    // (the middle mouse and Alt + left still navigate).
    if (!drag.navigating && !io.KeyAlt && graphViewportInput(s)) return;

    // Navigation.
    const bool orbitButton = ImGui::IsMouseDown(2) || (io.KeyAlt && ImGui::IsMouseDown(0)) ||
                             (s.tool == Tool::Navigate && ImGui::IsMouseDown(0));
    if (hovered && (ImGui::IsMouseClicked(2) || ImGui::IsMouseClicked(1) ||
                    (ImGui::IsMouseClicked(0) && (io.KeyAlt || s.tool == Tool::Navigate)))) {
        drag.navigating = true;
    }
    if (drag.navigating) {
        if (!ImGui::IsMouseDown(0) && !ImGui::IsMouseDown(1) && !ImGui::IsMouseDown(2)) {
            drag.navigating = false;
        } else if (ImGui::IsMouseDown(1) || (io.KeyShift && orbitButton)) {
            s.camera.pan(dx, dy);
        } else if (io.KeyCtrl && orbitButton) {
            s.camera.zoom(-dy * 10.0);
        } else if (orbitButton) {
            if (s.camera.orthographic && (dx != 0 || dy != 0)) s.camera.orthographic = false;
            s.camera.orbit(dx, dy);
        }
    }
    if (hovered && io.MouseWheel != 0) s.camera.zoom(io.MouseWheel);

    // Tools with the left mouse.
    if (drag.navigating || io.KeyAlt) return;
    if (s.tool == Tool::Brush) {
        if (hovered && ImGui::IsMouseClicked(0)) {
            if (auto hit = s.pick(mouse.x, mouse.y)) {
                s.stroke = ActiveStroke{true, hit->first, {}, false};
                s.selectedBody = static_cast<int>(hit->first);
                if (overlayChannel(s.overlay) != s.channel) {
                    s.overlay = s.channel == MapChannel::Permeability ? Overlay::Permeability
                                : s.channel == MapChannel::Density    ? Overlay::Density
                                                                      : Overlay::Thickness;
                    s.overlaysDirty = true;
                }
                addStrokePoint(s, hit->second);
            }
        } else if (s.stroke.active && ImGui::IsMouseDown(0)) {
            if (auto hit = s.pick(mouse.x, mouse.y); hit && hit->first == s.stroke.body) {
                addStrokePoint(s, hit->second);
            }
        }
    } else if (hovered && ImGui::IsMouseClicked(0)) {
        auto hit = s.pick(mouse.x, mouse.y);
        if (!hit) return;
        s.selectedBody = static_cast<int>(hit->first);
        if (s.tool == Tool::FillIsland) {
            s.execute(makeFillIslandCommand(*s.document, hit->first, s.channel, hit->second,
                                            s.brush.value, s.brush.mirrorX));
        } else if (s.tool == Tool::FillAll) {
            s.execute(makeFillAllCommand(*s.document, hit->first, s.channel, s.brush.value));
        } else if (s.tool == Tool::Pick) {
            const PaintedMap* map = s.document->map(hit->first, s.channel);
            auto surface = s.document->paintSurface(hit->first, s.channel);
            if (map && surface) {
                if (auto v = pickValue(*map, **surface, hit->second)) {
                    s.brush.value = *v;
                    s.status = "Picked " + std::to_string(*v);
                }
            } else {
                s.status = std::string("no ") + channelName(s.channel) + " map to pick from";
            }
        }
    }
}

void drawViewportOverlay(EditorState& s) {
    ImDrawList* draw = ImGui::GetForegroundDrawList();
    const ImVec2 origin(s.viewport.x + 8, s.viewport.y + 6);
    std::string line = std::string(viewName(s.camera)) + "   overlay: " + overlayName(s.overlay);
    draw->AddText(origin, IM_COL32(230, 230, 230, 255), line.c_str());
    drawGraphOverlay(s);
    // The brush circle: the radius at the surface under the cursor, projected.
    const ImVec2 mouse = ImGui::GetIO().MousePos;
    if ((s.tool == Tool::Brush) && s.viewport.contains(mouse.x, mouse.y) &&
        !ImGui::GetIO().WantCaptureMouse) {
        if (auto hit = s.pick(mouse.x, mouse.y)) {
            const Pose pose = s.document->bodyPose(hit->first);
            const Eigen::Vector3d centre = pose.apply(hit->second);
            const auto a = s.camera.toPixel(centre, int(s.viewport.w), int(s.viewport.h));
            const auto b = s.camera.toPixel(centre + s.camera.right() * s.brush.radius,
                                            int(s.viewport.w), int(s.viewport.h));
            if (a && b) {
                draw->AddCircle(mouse, static_cast<float>((*b - *a).norm()),
                                IM_COL32(255, 255, 255, 200), 48, 1.5f);
            }
        }
    }
}

}  // namespace plimsoll::editor
