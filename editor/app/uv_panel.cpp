// The UV view: the selected body's overlay over its UV layout, with the triangles' edges.
// Painting here paints the surface point under the cursor with the same 3D brush.
#include "app/panels.h"

#include <imgui.h>

#include <algorithm>

namespace plimsoll::editor {

void drawUvPanel(EditorState& s, const Rect& area) {
    ImGui::SetNextWindowPos(ImVec2(area.x, area.y));
    ImGui::SetNextWindowSize(ImVec2(area.w, area.h));
    ImGui::Begin("UV view", nullptr,
                 ImGuiWindowFlags_NoMove | ImGuiWindowFlags_NoResize | ImGuiWindowFlags_NoCollapse |
                     ImGuiWindowFlags_NoScrollbar);
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
    ImDrawList* draw = ImGui::GetWindowDrawList();
    draw->AddRectFilled(p0, ImVec2(p0.x + side, p0.y + side), IM_COL32(40, 40, 44, 255));
    if (const unsigned texture = s.renderer->overlayTexture(static_cast<int>(b))) {
        // The texture's row 0 is v = 0: show v upward.
        draw->AddImage(reinterpret_cast<ImTextureID>(static_cast<intptr_t>(texture)), p0,
                       ImVec2(p0.x + side, p0.y + side), ImVec2(0, 1), ImVec2(1, 0));
    }
    ImGui::InvisibleButton("uv", ImVec2(side, side));
    // The triangles' edges: drawn once into a texture (thousands of ImGui lines cost more
    // than the whole 3D view on a software rasteriser).
    const int wireSize = std::max(64, static_cast<int>(side + 0.5f));
    if (const unsigned wire = s.renderer->uvWireframeTexture(s.document->assets(b).mesh, wireSize)) {
        draw->AddImage(reinterpret_cast<ImTextureID>(static_cast<intptr_t>(wire)), p0,
                       ImVec2(p0.x + side, p0.y + side), ImVec2(0, 1), ImVec2(1, 0));
    }
    // Painting in UV space: the surface point at the cursor's uv.
    if (s.tool == Tool::Brush && mesh.hasUvs() && ImGui::IsItemHovered()) {
        const ImVec2 m = ImGui::GetIO().MousePos;
        const Eigen::Vector2d uv((m.x - p0.x) / side, 1.0 - (m.y - p0.y) / side);
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
