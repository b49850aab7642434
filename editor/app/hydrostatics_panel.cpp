// The hydrostatics window of the live preview: for the selected body of the running scene,
// the equilibrium, KB, BM, GM and the righting-arm curve from the textures and from the exact
// clip (physics/hydrostatics.h, docs/hydrostatics.md), computed on request ("Compute": a
// hull's textures at 256^2 take about a second). Collapsed until opened.
#include "app/panels.h"
#include "app/preview_panel.h"
#include "plimsoll/scene/scene_hydrostatics.h"

#include <imgui.h>

#include <cfloat>
#include <optional>
#include <string>
#include <vector>

namespace plimsoll::editor {

namespace {

/// The last figures computed, for one body of one scene. One window, one set: kept here
/// rather than in EditorState, which every panel includes.
struct HydrostaticsFigures {
    std::string body;  ///< the body's label they are for
    std::optional<HydrostaticsResult> textures, exact;
    std::string error;
};
HydrostaticsFigures gFigures;

void compute(const SceneBody& body, const Scene& scene) {
    gFigures = {body.label, std::nullopt, std::nullopt, {}};
    Result<HydrostaticsSettings> settings =
        hydrostaticsSettingsOf(scene.medium, scene.simulation.gravity);
    Result<FloatingBody> floating = floatingBodyOf(body, scene.medium);
    if (!settings || !floating) {
        gFigures.error = !settings ? settings.error().message : floating.error().message;
        return;
    }
    Result<HydrostaticsResult> textures =
        hydrostaticsFromTextures(*body.textures, floating->body, *settings);
    Result<HydrostaticsResult> exact =
        hydrostaticsExact(*body.parts.mesh, floating->body, *settings);
    if (!textures || !exact) {
        gFigures.error = !textures ? textures.error().message : exact.error().message;
        return;
    }
    gFigures.textures = std::move(*textures);
    gFigures.exact = std::move(*exact);
}

void row(const char* name, double textures, double exact) {
    ImGui::TableNextRow();
    ImGui::TableNextColumn();
    ImGui::TextUnformatted(name);
    ImGui::TableNextColumn();
    ImGui::Text("%.6g", textures);
    ImGui::TableNextColumn();
    ImGui::Text("%.6g", exact);
    ImGui::TableNextColumn();
    ImGui::Text("%.3g", textures - exact);
}

void drawFigures(const HydrostaticsResult& t, const HydrostaticsResult& e) {
    if (ImGui::BeginTable("##hydrostatics", 4, ImGuiTableFlags_RowBg | ImGuiTableFlags_Borders)) {
        ImGui::TableSetupColumn("", ImGuiTableColumnFlags_WidthFixed, 180.0f);
        ImGui::TableSetupColumn("textures");
        ImGui::TableSetupColumn("exact");
        ImGui::TableSetupColumn("difference");
        ImGui::TableHeadersRow();
        row("draft (m)", t.draft, e.draft);
        row("trim (deg)", t.trimDegrees, e.trimDegrees);
        row("heel (deg)", t.heelDegrees, e.heelDegrees);
        row("displacement (m^3)", t.displacement, e.displacement);
        row("waterplane (m^2)", t.waterplaneArea, e.waterplaneArea);
        row("KB (m)", t.kb, e.kb);
        row("KG (m)", t.kg, e.kg);
        row("BM transverse (m)", t.bmTransverse, e.bmTransverse);
        row("BM longitudinal (m)", t.bmLongitudinal, e.bmLongitudinal);
        row("GM transverse (m)", t.gmTransverse, e.gmTransverse);
        row("GM longitudinal (m)", t.gmLongitudinal, e.gmLongitudinal);
        row("free-surface loss T (m)", t.freeSurfaceLossTransverse, e.freeSurfaceLossTransverse);
        row("vanishing stability (deg)", t.vanishingStabilityDegrees, e.vanishingStabilityDegrees);
        ImGui::EndTable();
    }
    ImGui::TextUnformatted("GZ (m), heel 0..180 deg: textures, then exact");
    for (const HydrostaticsResult* r : {&t, &e}) {
        std::vector<float> arms;
        for (const RightingArm& p : r->gz) arms.push_back(static_cast<float>(p.arm));
        ImGui::PlotLines(r == &t ? "##gz textures" : "##gz exact", arms.data(),
                         static_cast<int>(arms.size()), 0, hydrostaticsMethodName(r->method),
                         FLT_MAX, FLT_MAX, ImVec2(0, 90));
    }
}

}  // namespace

void drawHydrostaticsPanel(EditorState& s) {
    if (!s.preview || !s.preview->session) return;
    const Scene& scene = s.preview->session->scene();
    if (s.selectedBody < 0 || s.selectedBody >= static_cast<int>(scene.bodies.size())) return;
    const SceneBody& body = scene.bodies[static_cast<std::size_t>(s.selectedBody)];
    ImGui::SetNextWindowCollapsed(true, ImGuiCond_FirstUseEver);
    ImGui::SetNextWindowPos(ImVec2(20, 160), ImGuiCond_FirstUseEver);
    ImGui::SetNextWindowSize(ImVec2(460, 560), ImGuiCond_FirstUseEver);
    if (!ImGui::Begin("Hydrostatics")) {
        ImGui::End();
        return;
    }
    ImGui::TextWrapped("%s: calm water, heel about x, trim about z", body.label.c_str());
    if (ImGui::Button("Compute")) compute(body, scene);
    tooltip("Finds the body's equilibrium in calm water and its righting-arm curve, from the\n"
            "textures and from the exact clip side by side.");
    if (gFigures.body == body.label) {
        if (!gFigures.error.empty()) ImGui::TextWrapped("error: %s", gFigures.error.c_str());
        if (gFigures.textures && gFigures.exact) drawFigures(*gFigures.textures, *gFigures.exact);
    }
    ImGui::End();
}

}  // namespace plimsoll::editor
