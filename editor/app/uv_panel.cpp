// The UV view: the selected body's overlay over its UV layout, with the triangles' edges.
// Painting here paints the surface point under the cursor with the same 3D brush.
#include "app/panels.h"

#include <imgui.h>

#include <algorithm>
#include <cmath>

namespace plimsoll::editor {

void drawUvPanel(EditorState& s, const Rect& area) {
    s.uvUnderMouse.reset();
    beginColumnPanel("UV view", area,
                     ImGuiWindowFlags_NoScrollbar | ImGuiWindowFlags_NoScrollWithMouse);
    if (s.selectedBody < 0 || static_cast<std::size_t>(s.selectedBody) >= s.document->bodyCount() ||
        !s.document->assets(s.selectedBody).mesh) {
        ImGui::TextDisabled("No mesh selected");
        ImGui::End();
        return;
    }
    const std::size_t b = s.selectedBody;
    const TriangleMesh& mesh = *s.document->assets(b).mesh;
    const ImVec2 avail = ImGui::GetContentRegionAvail();
    const float side = std::max(16.0f, std::min(avail.x, avail.y));
    const ImVec2 p0 = ImGui::GetCursorScreenPos();
    const ImVec2 p1(p0.x + side, p0.y + side);
    ImGui::InvisibleButton("uv", ImVec2(side, side),
                           ImGuiButtonFlags_MouseButtonLeft | ImGuiButtonFlags_MouseButtonMiddle);
    tooltip(
        "The map over the mesh's UV layout. Wheel: zoom at the cursor; middle mouse: pan; "
        "double-click: the whole square. With the Brush, left mouse paints here too.");
    const bool hovered = ImGui::IsItemHovered();
    // Under an open menu the wheel and the middle mouse still reach the view (the menu closes).
    const bool underMenu = !hovered &&
                           ImGui::IsItemHovered(ImGuiHoveredFlags_AllowWhenBlockedByPopup) &&
                           ImGui::IsPopupOpen("", ImGuiPopupFlags_AnyPopupId);
    const ImGuiIO& io = ImGui::GetIO();
    if (underMenu && (io.MouseWheel != 0 || ImGui::IsMouseClicked(ImGuiMouseButton_Middle)))
        closeMenus();
    // A middle drag that starts here pans until the button is let go, wherever the mouse goes.
    if ((hovered || underMenu) && ImGui::IsMouseClicked(ImGuiMouseButton_Middle))
        s.uvPanning = true;
    if (!ImGui::IsMouseDown(ImGuiMouseButton_Middle)) s.uvPanning = false;
    // The window onto uv space: uv (u, v) is at p0 + ((u - left) scale, (top - v) scale),
    // v upward as the textures' row 0 is v = 0.
    auto left = [&] { return s.uvCentre.x() - 0.5f / s.uvZoom; };
    auto top = [&] { return s.uvCentre.y() + 0.5f / s.uvZoom; };
    auto uvAt = [&](const ImVec2& m) {
        const float scale = side * s.uvZoom;
        return Eigen::Vector2f(left() + (m.x - p0.x) / scale, top() - (m.y - p0.y) / scale);
    };
    if ((hovered || underMenu) && io.MouseWheel != 0) {
        // Zoom about the cursor: the uv under it stays there.
        const Eigen::Vector2f held = uvAt(io.MousePos);
        s.uvZoom = std::clamp(s.uvZoom * std::pow(1.25f, io.MouseWheel), 1.0f, 64.0f);
        const float scale = side * s.uvZoom;
        s.uvCentre = Eigen::Vector2f(held.x() - (io.MousePos.x - p0.x) / scale + 0.5f / s.uvZoom,
                                     held.y() + (io.MousePos.y - p0.y) / scale - 0.5f / s.uvZoom);
    }
    if (s.uvPanning && ImGui::IsMouseDragging(ImGuiMouseButton_Middle, 0.0f)) {
        const float scale = side * s.uvZoom;
        s.uvCentre += Eigen::Vector2f(-io.MouseDelta.x / scale, io.MouseDelta.y / scale);
    }
    if (hovered && ImGui::IsMouseDoubleClicked(ImGuiMouseButton_Middle)) {
        s.uvZoom = 1.0f;
        s.uvCentre = Eigen::Vector2f(0.5f, 0.5f);
    }
    if (s.uvZoom <= 1.0f) s.uvCentre = Eigen::Vector2f(0.5f, 0.5f);
    const float scale = side * s.uvZoom;
    // The whole 0..1 square's place on screen, clipped to the view.
    const ImVec2 q0(p0.x - left() * scale, p0.y - (top() - 1.0f) * scale);
    const ImVec2 q1(q0.x + scale, q0.y + scale);
    ImDrawList* draw = ImGui::GetWindowDrawList();
    draw->PushClipRect(p0, p1, true);
    draw->AddRectFilled(p0, p1, IM_COL32(40, 40, 44, 255));
    if (const unsigned texture = s.renderer->overlayTexture(static_cast<int>(b))) {
        draw->AddImage(reinterpret_cast<ImTextureID>(static_cast<intptr_t>(texture)), q0, q1,
                       ImVec2(0, 1), ImVec2(1, 0));
    }
    // The triangles' edges: drawn once into a texture (thousands of ImGui lines cost more
    // than the whole 3D view on a software rasteriser), at the view's size (up to 2048: 16 MB).
    const int wireSize = std::clamp(static_cast<int>(scale + 0.5f), 64, 2048);
    if (const unsigned wire =
            s.renderer->uvWireframeTexture(s.document->assets(b).mesh, wireSize)) {
        draw->AddImage(reinterpret_cast<ImTextureID>(static_cast<intptr_t>(wire)), q0, q1,
                       ImVec2(0, 1), ImVec2(1, 0));
    }
    draw->PopClipRect();
    if (hovered) s.uvUnderMouse = uvAt(io.MousePos);
    // Painting in UV space: the surface point at the cursor's uv.
    if (s.tool == Tool::Brush && mesh.hasUvs() && hovered) {
        const Eigen::Vector2d uv = uvAt(io.MousePos).cast<double>();
        const auto hit = surfaceAtUv(mesh, uv);
        if (ImGui::IsMouseClicked(0) && hit) {
            s.stroke = ActiveStroke{true, true, b, {hit->point}, true, LazyMouse{}};
        } else if (s.stroke.active && s.stroke.body == b && ImGui::IsMouseDown(0) && hit &&
                   (s.stroke.points.empty() ||
                    (hit->point - s.stroke.points.back()).norm() >= s.brush.radius * 0.25)) {
            s.stroke.points.push_back(hit->point);
            s.stroke.previewDirty = true;
        }
    }
    ImGui::End();
}

}  // namespace plimsoll::editor
