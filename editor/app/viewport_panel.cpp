// The 3D view: Blender-like navigation (middle mouse orbits, Shift pans, Ctrl or the wheel
// zooms; Alt + left mouse orbits too), painting with the left mouse, and what is drawn over the
// scene (view name, brush circle).
#include "app/panels.h"
#include "app/preview_panel.h"

#include "document/command.h"

#include <GLFW/glfw3.h>
#include <imgui.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <string>

namespace plimsoll::editor {

namespace {

void addStrokePoint(EditorState& s, const Eigen::Vector3d& p) {
    if (!s.stroke.points.empty() && (p - s.stroke.points.back()).norm() < s.brush.radius * 0.25) {
        return;
    }
    s.stroke.points.push_back(p);
    s.stroke.previewDirty = true;
}

/// The brush's image upright on screen: toward the viewer, in the body's object space; and
/// in a perspective view the camera's place there, which occlusion and the normal falloff
/// see from.
void orientAlpha(EditorState& s, std::size_t body) {
    const Pose pose = s.shownPose(body);
    s.brush.alphaAxis = pose.rotation.transpose() * -s.camera.forward();
    s.brush.eye.reset();
    if (!s.camera.orthographic)
        s.brush.eye = pose.rotation.transpose() * (s.camera.eye() - pose.translation);
}

/// Shift-click: a straight line on screen from the last stroke's end to the cursor, picked on
/// the surface every few pixels and painted as one stroke (one undo step).
void lineStroke(EditorState& s, const Eigen::Vector2d& to) {
    const auto [body, end] = *s.lastStrokeEnd;
    if (body >= s.document->bodyCount()) return;
    const auto from =
        s.camera.toPixel(s.shownPose(body).apply(end), int(s.viewport.w), int(s.viewport.h));
    if (!from) return;
    const Eigen::Vector2d origin(s.viewport.x, s.viewport.y);
    constexpr double kLineStepPixels = 3.0;
    std::vector<Eigen::Vector3d> points{end};
    for (const Eigen::Vector2d& p : lineSamples(origin + *from, to, kLineStepPixels)) {
        auto hit = s.pick(static_cast<float>(p.x()), static_cast<float>(p.y()));
        if (hit && hit->first == body) points.push_back(hit->second);
    }
    if (points.size() < 2) return;
    orientAlpha(s, body);
    if (s.execute(
            makeStrokeCommand(*s.document, body, s.channel, s.brush, points, s.paintTarget()))) {
        s.lastStrokeEnd = {body, points.back()};
        s.lastStrokePoints = points.size();
    }
}

/// The radial control's scale: the radius in use is this many px from the centre, and full
/// strength twice as far.
constexpr double kRadialRadiusPx = 100.0;
constexpr double kRadialStrengthPx = 200.0;
constexpr double kMinBrushRadius = 0.001, kMaxBrushRadius = 5.0;  // the Radius slider's range

/// The value the mouse's distance from the centre gives.
double radialValue(const EditorState::RadialControl& control, const ImVec2& mouse) {
    const double d = (Eigen::Vector2d(mouse.x, mouse.y) - control.centre).norm();
    if (control.strength) return std::clamp(d / kRadialStrengthPx, 0.0, 1.0);
    return std::clamp(control.start * d / kRadialRadiusPx, kMinBrushRadius, kMaxBrushRadius);
}

void endRadialControl(EditorState& s, bool keep) {
    if (!s.radialControl) return;
    if (!keep) {
        (s.radialControl->strength ? s.brush.strength : s.brush.radius) = s.radialControl->start;
    }
    s.status =
        keep ? (s.radialControl->strength ? "Brush strength " + std::to_string(s.brush.strength)
                                          : "Brush radius " + std::to_string(s.brush.radius) + " m")
             : std::string("Brush unchanged");
    s.radialControl.reset();
}

/// While the radial control is up it has the mouse: moves set the value, the left button
/// keeps it (without starting a stroke), the right one cancels. True while it is up.
bool radialControlInput(EditorState& s) {
    if (!s.radialControl) return false;
    const ImGuiIO& io = ImGui::GetIO();
    if (ImGui::IsMousePosValid(&io.MousePos)) {
        (s.radialControl->strength ? s.brush.strength : s.brush.radius) =
            radialValue(*s.radialControl, io.MousePos);
    }
    if (ImGui::IsMouseClicked(0))
        endRadialControl(s, true);
    else if (ImGui::IsMouseClicked(1))
        endRadialControl(s, false);
    return true;
}

}  // namespace

bool radialControlKey(EditorState& s, int key, bool shift) {
    if (s.radialControl) {
        if (key == GLFW_KEY_ENTER || key == GLFW_KEY_KP_ENTER)
            endRadialControl(s, true);
        else if (key == GLFW_KEY_ESCAPE)
            endRadialControl(s, false);
        else
            return false;
        return true;
    }
    // F in paint mode (the Brush); elsewhere F frames.
    if (key != GLFW_KEY_F || s.tool != Tool::Brush) return false;
    const ImGuiIO& io = ImGui::GetIO();
    const Eigen::Vector2d mouse =
        ImGui::IsMousePosValid(&io.MousePos)
            ? Eigen::Vector2d(io.MousePos.x, io.MousePos.y)
            : Eigen::Vector2d(s.viewport.x + s.viewport.w / 2, s.viewport.y + s.viewport.h / 2);
    EditorState::RadialControl control;
    control.strength = shift;
    control.start = shift ? s.brush.strength : s.brush.radius;
    // The centre left of the mouse, as far as the value in use: the value does not jump.
    const double offset = shift ? s.brush.strength * kRadialStrengthPx : kRadialRadiusPx;
    control.centre = mouse - Eigen::Vector2d(offset, 0);
    s.radialControl = control;
    s.stroke = {};
    return true;
}

void viewportInput(EditorState& s) {
    if (radialControlInput(s)) return;
    ImGuiIO& io = ImGui::GetIO();
    const ImVec2 mouse = io.MousePos;
    const bool hovered = s.viewport.contains(mouse.x, mouse.y) && !io.WantCaptureMouse;
    // Under an open menu the wheel and the middle mouse still reach the view (the menu closes).
    const bool underMenu = !hovered && s.viewport.contains(mouse.x, mouse.y) &&
                           ImGui::IsPopupOpen("", ImGuiPopupFlags_AnyPopupId) &&
                           mouseOverNoWindow();
    if (underMenu && (io.MouseWheel != 0 || ImGui::IsMouseClicked(2))) closeMenus();
    const bool navHovered = hovered || underMenu;
    const double dx = io.MouseDelta.x / std::max(1.0f, s.viewport.h);
    const double dy = io.MouseDelta.y / std::max(1.0f, s.viewport.h);

    // The water graph's tools take the left mouse first while its panel edits in the view
    // (the middle mouse and Alt + left still navigate).
    bool& navigating = s.navigating;
    if (!navigating && !io.KeyAlt && graphViewportInput(s)) return;

    // Navigation.
    const bool orbitButton = ImGui::IsMouseDown(2) || (io.KeyAlt && ImGui::IsMouseDown(0)) ||
                             (s.tool == Tool::Navigate && ImGui::IsMouseDown(0));
    if ((hovered || (navHovered && ImGui::IsMouseClicked(2))) &&
        (ImGui::IsMouseClicked(2) || ImGui::IsMouseClicked(1) ||
         (ImGui::IsMouseClicked(0) && (io.KeyAlt || s.tool == Tool::Navigate)))) {
        navigating = true;
    }
    if (navigating) {
        if (!ImGui::IsMouseDown(0) && !ImGui::IsMouseDown(1) && !ImGui::IsMouseDown(2)) {
            navigating = false;
        } else if (ImGui::IsMouseDown(1) || (io.KeyShift && orbitButton)) {
            s.camera.pan(dx, dy);
        } else if (io.KeyCtrl && orbitButton) {
            s.camera.zoom(-dy * 10.0);
        } else if (orbitButton) {
            if (s.camera.orthographic && (dx != 0 || dy != 0)) s.camera.orthographic = false;
            s.camera.orbit(dx, dy);
        }
    }
    if (navHovered && io.MouseWheel != 0) s.camera.zoom(io.MouseWheel);

    // Tools with the left mouse. While the live preview runs they work on the bodies where
    // the view shows them (EditorState::shownPose); a click that previewInput took to grab a
    // body (any tool but the Brush) does not reach here.
    if (navigating || io.KeyAlt) return;
    if (s.tool == Tool::Brush) {
        if (hovered && ImGui::IsMouseClicked(0) && io.KeyShift && s.lastStrokeEnd) {
            lineStroke(s, Eigen::Vector2d(mouse.x, mouse.y));
            return;
        }
        if (hovered && ImGui::IsMouseClicked(0)) {
            // The stroke starts even off the mesh: it paints from where it first crosses a body.
            s.stroke = ActiveStroke{};
            s.stroke.active = true;
            s.stroke.lazy = LazyMouse(s.brush.lazyRadius);
        }
        if (s.stroke.active && ImGui::IsMouseDown(0)) {
            // The lazy mouse: the brush trails the cursor (without it, the brush is the cursor).
            const Eigen::Vector2d at = s.stroke.lazy.follow(Eigen::Vector2d(mouse.x, mouse.y));
            auto hit = s.pick(static_cast<float>(at.x()), static_cast<float>(at.y()));
            if (hit && !s.stroke.onBody) {
                s.stroke.onBody = true;
                s.stroke.body = hit->first;
                orientAlpha(s, hit->first);
                s.selectedBody = static_cast<int>(hit->first);
                if (overlayChannel(s.overlay) != s.channel) {
                    s.overlay = s.channel == MapChannel::Permeability ? Overlay::Permeability
                                : s.channel == MapChannel::Density    ? Overlay::Density
                                                                      : Overlay::Thickness;
                    s.overlaysDirty = true;
                }
            }
            if (hit && hit->first == s.stroke.body) addStrokePoint(s, hit->second);
        }
    } else if (hovered && ImGui::IsMouseClicked(0)) {
        auto hit = s.pick(mouse.x, mouse.y);
        if (!hit) return;
        s.selectedBody = static_cast<int>(hit->first);
        if (s.tool == Tool::FillIsland) {
            s.execute(makeFillIslandCommand(*s.document, hit->first, s.channel, hit->second,
                                            s.brush.value, s.brush.mirrorX, s.brush.strength,
                                            s.paintTarget()));
        } else if (s.tool == Tool::FillAll) {
            s.execute(makeFillAllCommand(*s.document, hit->first, s.channel, s.brush.value,
                                         s.brush.strength, s.paintTarget()));
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
    // Behind every ImGui window (menus, popups, panels) and above the 3D scene, which is drawn
    // before ImGui: the view's labels never cover an open menu.
    ImDrawList* draw = ImGui::GetBackgroundDrawList();
    const ImVec2 origin(s.viewport.x + 8, s.viewport.y + 6);
    std::string line = std::string(viewName(s.camera)) + "   overlay: " + overlayName(s.overlay);
    draw->AddText(origin, IM_COL32(230, 230, 230, 255), line.c_str());
    drawGraphOverlay(s);
    // The overlay's legend, bottom left of the view (clear of the Live preview window): what the
    // colours mean, with units.
    const BodyDesc* selected =
        s.selectedBody >= 0 && static_cast<std::size_t>(s.selectedBody) < s.document->bodyCount()
            ? &s.document->project().bodies[static_cast<std::size_t>(s.selectedBody)]
            : nullptr;
    const OverlayLegend legend = overlayLegend(s.overlay, selected);
    s.legendBox.setEmpty();
    if (!legend.meaning.empty()) {
        constexpr float kRampWidth = 160;
        const float textWidth = ImGui::CalcTextSize(legend.meaning.c_str()).x;
        const Eigen::Vector2f size(
            legend.ramp ? std::max(textWidth, kRampWidth) : textWidth,
            legend.ramp ? 34 + ImGui::GetTextLineHeight() : ImGui::GetTextLineHeight());
        const Eigen::Vector2f place =
            overlayPlace(s.viewport.box(), size, {&s.previewWindow, 1}, ViewCorner::LowerLeft);
        s.legendBox = Eigen::AlignedBox2f(place, place + size);
        const float x = place.x(), y = place.y();
        const ImU32 white = IM_COL32(230, 230, 230, 255);
        draw->AddText(ImVec2(x, y), white, legend.meaning.c_str());
        if (legend.ramp) {
            auto colour = [](double v) {
                const Eigen::Vector3f c = rampColour(v);
                return IM_COL32(int(c.x() * 255), int(c.y() * 255), int(c.z() * 255), 255);
            };
            const ImVec2 a(x, y + 18), b(x + kRampWidth, y + 32);
            // The ramp is linear: two corner colours draw it exactly.
            draw->AddRectFilledMultiColor(a, b, colour(0), colour(1), colour(1), colour(0));
            draw->AddText(ImVec2(x, y + 34), white, legend.low.c_str());
            const float w = ImGui::CalcTextSize(legend.high.c_str()).x;
            draw->AddText(ImVec2(b.x - w, y + 34), white, legend.high.c_str());
        }
    }
    const ImVec2 mouse = ImGui::GetIO().MousePos;
    if (s.radialControl) {
        // Blender's look: a circle about the centre through the mouse, and the value.
        const ImVec2 centre(static_cast<float>(s.radialControl->centre.x()),
                            static_cast<float>(s.radialControl->centre.y()));
        const float d = std::hypot(mouse.x - centre.x, mouse.y - centre.y);
        draw->AddCircle(centre, d, IM_COL32(255, 255, 255, 220), 64, 1.5f);
        draw->AddCircleFilled(centre, 3.0f, IM_COL32(255, 255, 255, 220));
        char text[96];
        if (s.radialControl->strength) {
            std::snprintf(text, sizeof text,
                          "Strength %.3f  (click / Enter: keep, Esc / right: cancel)",
                          s.brush.strength);
        } else {
            std::snprintf(text, sizeof text,
                          "Radius %.4g m  (click / Enter: keep, Esc / right: cancel)",
                          s.brush.radius);
        }
        draw->AddText(ImVec2(centre.x - 40, centre.y + 8), IM_COL32(255, 255, 255, 230), text);
        return;
    }
    if (!s.viewport.contains(mouse.x, mouse.y) || ImGui::GetIO().WantCaptureMouse) return;
    if (s.preview && s.preview->session) return;  // the bodies shown are the simulated ones
    const auto hit = s.pick(mouse.x, mouse.y);
    if (!hit) return;
    // The brush cursor, as Blender and Painter draw it: a circle of the brush's radius lying
    // on the surface under the cursor (in its tangent plane, around the hit triangle's
    // normal), projected, with a short tick along the normal; a glancing surface shows an
    // ellipse, the way the dab will land.
    if (s.tool == Tool::Brush) {
        if (const auto surface = s.pickSurface(mouse.x, mouse.y)) {
            const Eigen::Vector3d n = surface->normal;
            const Eigen::Vector3d helper =
                std::abs(n.y()) < 0.9 ? Eigen::Vector3d::UnitY() : Eigen::Vector3d::UnitX();
            const Eigen::Vector3d u = helper.cross(n).normalized(), v = n.cross(u);
            const ImVec2 offset(s.viewport.x, s.viewport.y);
            constexpr int kSegments = 48;
            ImVec2 ring[kSegments];
            int shown = 0;
            for (int k = 0; k < kSegments; ++k) {
                const double t = 2.0 * std::numbers::pi * k / kSegments;
                const Eigen::Vector3d p =
                    surface->point + s.brush.radius * (std::cos(t) * u + std::sin(t) * v);
                if (const auto px = s.camera.toPixel(p, int(s.viewport.w), int(s.viewport.h))) {
                    ring[shown++] = ImVec2(offset.x + float(px->x()), offset.y + float(px->y()));
                }
            }
            if (shown == kSegments)
                draw->AddPolyline(ring, kSegments, IM_COL32(255, 255, 255, 200), ImDrawFlags_Closed,
                                  1.5f);
            const auto base =
                s.camera.toPixel(surface->point, int(s.viewport.w), int(s.viewport.h));
            const auto tip = s.camera.toPixel(surface->point + n * s.brush.radius * 0.5,
                                              int(s.viewport.w), int(s.viewport.h));
            if (base && tip) {
                draw->AddLine(ImVec2(offset.x + float(base->x()), offset.y + float(base->y())),
                              ImVec2(offset.x + float(tip->x()), offset.y + float(tip->y())),
                              IM_COL32(255, 255, 255, 200), 1.5f);
            }
        }
    }
    // The hover readout: the map's value under the cursor (as the engine reads it, flattened).
    const PaintedMap* map = s.document->map(hit->first, s.channel);
    std::string readout = std::string(channelName(s.channel)) + ": ";
    if (!map) {
        readout += "no map";
    } else if (auto surface = s.document->paintSurface(hit->first, s.channel); surface) {
        const std::optional<double> value = pickValue(*map, **surface, hit->second);
        char text[32];
        std::snprintf(text, sizeof text, "%.3f", value.value_or(0.0));
        readout += value ? text : "-";
    }
    readout += "\n" + surfacePointPhysics(*s.document, hit->first, hit->second, s.waterTime);
    // Right of the cursor, or left of it where it would run under the panels.
    const float textWidth = ImGui::CalcTextSize(readout.c_str()).x;
    const float x = mouse.x + 16 + textWidth > s.viewport.x + s.viewport.w
                        ? mouse.x - 16 - textWidth
                        : mouse.x + 16;
    draw->AddText(ImVec2(x, mouse.y + 14), IM_COL32(255, 255, 255, 230), readout.c_str());
}

}  // namespace plimsoll::editor
