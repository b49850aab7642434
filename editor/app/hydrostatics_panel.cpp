// The hydrostatics window of the live preview: for the selected body of the running scene,
// the equilibrium, KB, BM, GM and the righting-arm curve from the textures and from the exact
// clip (physics/hydrostatics.h, docs/hydrostatics.md), computed on request ("Compute": a
// hull's textures at 256^2 take about a second); and, for a body with radiation on, its
// added mass and damping against frequency and a free heave decay test run on a worker
// (scene/radiation_decay.h, docs/radiation.md). Collapsed until opened.
#include "app/panels.h"
#include "app/preview_panel.h"
#include "plimsoll/scene/radiation_decay.h"
#include "plimsoll/scene/scene_hydrostatics.h"
#include "plimsoll/scene/scene_radiation.h"

#include <GLFW/glfw3.h>
#include <imgui.h>

#include <algorithm>
#include <cfloat>
#include <chrono>
#include <cstdio>
#include <future>
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

/// The decay test of one body: running on a worker, or its result.
struct DecayRun {
    std::string body;  ///< the body's label it is for
    std::future<Result<HeaveDecayTest>> running;
    std::optional<Result<HeaveDecayTest>> result;
};
DecayRun gDecay;
int gRadiationMode = kHeaveY;

void startDecayTest(const Scene& scene, std::size_t index) {
    gDecay.body = scene.bodies[index].label;
    gDecay.result.reset();
    // The worker has its own copy of the scene (its bodies' bakes are shared, read-only) and
    // wakes the frame loop when it is done, which an idle window waits in.
    gDecay.running = std::async(std::launch::async, [scene, index] {
        Result<HeaveDecayTest> result = runHeaveDecayTest(scene, index);
        glfwPostEmptyEvent();
        return result;
    });
}

/// A(omega) and B(omega) of the chosen mode over the body's frequencies, then the decay test.
void drawRadiation(const Scene& scene, std::size_t index) {
    const SceneBody& body = scene.bodies[index];
    if (!body.radiation) {
        ImGui::TextWrapped("Radiation is off for this body: give it a \"radiation\" object in the "
                           "project (docs/project-schema.md) for its added mass, damping and decay test.");
        return;
    }
    const BodyRadiation& r = *body.radiation;
    const char* modes[] = {"surge (x)", "heave (y)", "sway (z)", "roll (about x)", "yaw (about y)", "pitch (about z)"};
    ImGui::Combo("mode", &gRadiationMode, modes, 6);
    tooltip("Which motion's added mass and damping are plotted (body axes, about the centre of mass).");
    const int mode = std::clamp(gRadiationMode, 0, 5);
    std::vector<float> added, damping;
    for (const RadiationCoefficients& c : r.coefficients) {
        added.push_back(static_cast<float>(c.addedMass(mode, mode)));
        damping.push_back(static_cast<float>(c.damping(mode, mode)));
    }
    const char* unit = mode < 3 ? "kg" : "kg m^2";
    ImGui::Text("%zu panels, %zu frequencies %.3g..%.3g rad/s", r.panelCount, r.coefficients.size(),
                r.coefficients.front().omega, r.coefficients.back().omega);
    char label[96];
    std::snprintf(label, sizeof label, "A (%s); A_inf %.4g", unit, r.addedMassInfinity(mode, mode));
    ImGui::PlotLines("##radiation A", added.data(), static_cast<int>(added.size()), 0, label, FLT_MAX, FLT_MAX,
                     ImVec2(0, 80));
    tooltip("Added mass against frequency, low to high (the frequencies are log-spaced).");
    std::snprintf(label, sizeof label, "B (%s/s)", unit);
    ImGui::PlotLines("##radiation B", damping.data(), static_cast<int>(damping.size()), 0, label, FLT_MAX,
                     FLT_MAX, ImVec2(0, 80));
    tooltip("Radiation damping against frequency: the waves the motion makes carry its energy away.");

    const bool running = gDecay.running.valid();
    ImGui::BeginDisabled(running);
    if (ImGui::Button("Decay test")) startDecayTest(scene, index);
    ImGui::EndDisabled();
    tooltip("Releases the body 2 cm below its rest waterline in calm water, alone, with drag and\n"
            "damping off, and measures the damped period and log decrement of its heave against\n"
            "what A and B predict (on a worker: the preview runs on).");
    if (running) {
        if (gDecay.running.wait_for(std::chrono::seconds(0)) == std::future_status::ready) {
            gDecay.result = gDecay.running.get();
        } else {
            ImGui::SameLine();
            ImGui::TextUnformatted("running...");
        }
    }
    if (!gDecay.result || gDecay.body != body.label) return;
    if (!*gDecay.result) {
        ImGui::TextWrapped("decay test: %s", gDecay.result->error().message.c_str());
        return;
    }
    const HeaveDecayTest& t = gDecay.result->value();
    // At most 600 points of the record (a max per bucket keeps the peaks).
    std::vector<float> heave;
    const std::size_t bucket = std::max<std::size_t>(1, t.offset.size() / 600);
    for (std::size_t i = 0; i < t.offset.size(); i += bucket) {
        double extreme = 0;
        for (std::size_t k = i; k < std::min(t.offset.size(), i + bucket); ++k)
            if (std::abs(t.offset[k]) > std::abs(extreme)) extreme = t.offset[k];
        heave.push_back(static_cast<float>(extreme * 1000));
    }
    ImGui::PlotLines("##decay", heave.data(), static_cast<int>(heave.size()), 0, "heave from rest (mm)", FLT_MAX,
                     FLT_MAX, ImVec2(0, 90));
    auto percent = [](double measured, double predicted) { return 100 * (measured / predicted - 1); };
    ImGui::Text("period %.4f s (A and B predict %.4f, %+.1f%%)", t.measured.period, t.predicted.period,
                percent(t.measured.period, t.predicted.period));
    ImGui::Text("log decrement %.4f (predicted %.4f, %+.1f%%)", t.measured.logDecrement, t.predicted.logDecrement,
                percent(t.measured.logDecrement, t.predicted.logDecrement));
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
    if (ImGui::CollapsingHeader("Radiation: added mass, damping, decay test"))
        drawRadiation(scene, static_cast<std::size_t>(s.selectedBody));
    ImGui::End();
}

}  // namespace plimsoll::editor
