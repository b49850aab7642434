// The hydrostatics window of the live preview: for the selected body of the running scene,
// the equilibrium, KB, BM, GM and the righting-arm curve from the textures and from the exact
// clip (physics/hydrostatics.h, docs/hydrostatics.md), then the stability report (TPC,
// MCT1cm, the largest GZ, the downflooding angle, the IMO 2008 IS Code's criteria and the KN
// cross curves), computed on request ("Compute": a hull's textures at 256^2 take a few
// seconds); and, for a body with radiation on, its
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
#include <cmath>
#include <cstdio>
#include <future>
#include <memory>
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
/// The figures being computed on a worker (the window shows "computing..." meanwhile).
std::future<HydrostaticsFigures> gComputing;
/// Without a running preview, the document's scene as it was when Compute was pressed.
std::shared_ptr<const Scene> gOwnScene;

HydrostaticsFigures compute(const SceneBody& body, const Scene& scene) {
    HydrostaticsFigures figures{body.label, std::nullopt, std::nullopt, {}};
    Result<HydrostaticsSettings> settings =
        hydrostaticsSettingsOf(scene.medium, scene.simulation.gravity);
    Result<FloatingBody> floating = floatingBodyOf(body, scene.medium);
    if (!settings || !floating) {
        figures.error = !settings ? settings.error().message : floating.error().message;
        return figures;
    }
    Result<HydrostaticsResult> textures =
        hydrostaticsFromTextures(*body.textures, floating->body, *settings);
    Result<HydrostaticsResult> exact =
        hydrostaticsExact(*body.parts.mesh, floating->body, *settings);
    if (!textures || !exact) {
        figures.error = !textures ? textures.error().message : exact.error().message;
        return figures;
    }
    figures.textures = std::move(*textures);
    figures.exact = std::move(*exact);
    return figures;
}

/// Starts computing body `index` of `scene` (a copy the worker keeps) on a worker.
void startCompute(std::shared_ptr<const Scene> scene, std::size_t index) {
    gComputing = std::async(std::launch::async, [scene, index] {
        HydrostaticsFigures figures = compute(scene->bodies[index], *scene);
        glfwPostEmptyEvent();  // an idle frame loop shows them at once
        return figures;
    });
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

/// A tick step of 1, 2 or 5 times a power of ten that cuts `span` into about `count` parts.
double niceStep(double span, int count) {
    if (!(span > 0)) return 1.0;
    const double raw = span / count, power = std::pow(10.0, std::floor(std::log10(raw)));
    for (double m : {1.0, 2.0, 5.0}) {
        if (m * power >= raw) return m * power;
    }
    return 10 * power;
}

/// The righting-arm curves of both methods on one pair of axes: heel (deg) across, GZ (m) up,
/// ticks and grid, a legend, and under the mouse the heel and both arms there.
void drawGzPlot(const HydrostaticsResult& t, const HydrostaticsResult& e) {
    const std::vector<RightingArm>* curves[2] = {&t.gz, &e.gz};
    const ImU32 colours[2] = {IM_COL32(90, 160, 255, 255), IM_COL32(255, 150, 60, 255)};
    double x0 = 1e300, x1 = -1e300, y0 = 0, y1 = 0;
    for (const auto* curve : curves) {
        for (const RightingArm& a : *curve) {
            x0 = std::min(x0, a.heelDegrees);
            x1 = std::max(x1, a.heelDegrees);
            y0 = std::min(y0, a.arm);
            y1 = std::max(y1, a.arm);
        }
    }
    if (!(x1 > x0)) return;
    const double yStep = niceStep(y1 - y0, 4);
    y0 = std::floor(y0 / yStep) * yStep;
    y1 = std::ceil(y1 / yStep) * yStep;
    if (!(y1 > y0)) y1 = y0 + yStep;
    ImGui::TextUnformatted("Righting arm GZ (m) against heel (deg)");
    const float width = std::max(200.0f, ImGui::GetContentRegionAvail().x);
    const ImVec2 origin = ImGui::GetCursorScreenPos();
    ImGui::InvisibleButton("##gz", ImVec2(width, 170));
    const bool hovered = ImGui::IsItemHovered();
    ImDrawList* draw = ImGui::GetWindowDrawList();
    const float left = origin.x + 46, right = origin.x + width - 6, top = origin.y + 4,
                bottom = origin.y + 150;
    auto px = [&](double x) { return left + float((x - x0) / (x1 - x0)) * (right - left); };
    auto py = [&](double y) { return bottom - float((y - y0) / (y1 - y0)) * (bottom - top); };
    const ImU32 grid = IM_COL32(80, 80, 90, 255), text = ImGui::GetColorU32(ImGuiCol_Text);
    char label[48];
    for (double y = y0; y <= y1 + 1e-9 * yStep; y += yStep) {
        draw->AddLine(ImVec2(left, py(y)), ImVec2(right, py(y)),
                      std::abs(y) < 1e-9 * yStep ? text : grid);
        std::snprintf(label, sizeof label, "%.3g", std::abs(y) < 1e-9 * yStep ? 0.0 : y);
        draw->AddText(ImVec2(origin.x, py(y) - 7), text, label);
    }
    const double xStep =
        x1 - x0 >= 90 ? 30 : niceStep(x1 - x0, 6);  // degrees: by 30 on a wide range
    for (double x = std::ceil(x0 / xStep) * xStep; x <= x1 + 1e-9; x += xStep) {
        draw->AddLine(ImVec2(px(x), top), ImVec2(px(x), bottom), grid);
        std::snprintf(label, sizeof label, "%g", x);
        draw->AddText(ImVec2(px(x) - 8, bottom + 2), text, label);
    }
    for (int c = 0; c < 2; ++c) {
        std::vector<ImVec2> points;
        for (const RightingArm& a : *curves[c]) points.emplace_back(px(a.heelDegrees), py(a.arm));
        draw->AddPolyline(points.data(), static_cast<int>(points.size()), colours[c], 0, 2.0f);
        const char* name = c == 0 ? "textures" : "exact";
        const ImVec2 at(right - 80, top + 4 + 16.0f * c);
        draw->AddLine(ImVec2(at.x, at.y + 7), ImVec2(at.x + 14, at.y + 7), colours[c], 2.0f);
        draw->AddText(ImVec2(at.x + 18, at.y), text, name);
    }
    if (!hovered) return;
    // Under the mouse: the heel there and each curve's arm at its nearest point.
    const double heel = x0 + (ImGui::GetIO().MousePos.x - left) / (right - left) * (x1 - x0);
    draw->AddLine(ImVec2(px(std::clamp(heel, x0, x1)), top),
                  ImVec2(px(std::clamp(heel, x0, x1)), bottom), text);
    std::string tip;
    for (int c = 0; c < 2; ++c) {
        const auto nearest = std::min_element(
            curves[c]->begin(), curves[c]->end(), [&](const RightingArm& a, const RightingArm& b) {
                return std::abs(a.heelDegrees - heel) < std::abs(b.heelDegrees - heel);
            });
        if (nearest == curves[c]->end()) continue;
        std::snprintf(label, sizeof label, "%s%s: GZ %.4f m at %.1f deg", tip.empty() ? "" : "\n",
                      c == 0 ? "textures" : "exact", nearest->arm, nearest->heelDegrees);
        tip += label;
    }
    tooltip(tip.c_str());  // the plot is the last item
}

/// A row of figures that may be missing ("none": the downflooding angle without openings).
void optionalRow(const char* name, std::optional<double> textures, std::optional<double> exact) {
    ImGui::TableNextRow();
    ImGui::TableNextColumn();
    ImGui::TextUnformatted(name);
    for (const std::optional<double>& v : {textures, exact}) {
        ImGui::TableNextColumn();
        if (v) {
            ImGui::Text("%.6g", *v);
        } else {
            ImGui::TextUnformatted("none");
        }
    }
    ImGui::TableNextColumn();
    if (textures && exact) ImGui::Text("%.3g", *textures - *exact);
}

/// TPC, MCT1cm, the largest GZ, the downflooding angle, the IS Code's criteria with each
/// method's verdict, and the KN cross curves.
void drawStabilityReport(const HydrostaticsResult& t, const HydrostaticsResult& e) {
    if (!ImGui::CollapsingHeader("Stability report", ImGuiTreeNodeFlags_DefaultOpen)) return;
    if (ImGui::BeginTable("##stability", 4, ImGuiTableFlags_RowBg | ImGuiTableFlags_Borders)) {
        ImGui::TableSetupColumn("", ImGuiTableColumnFlags_WidthFixed, 180.0f);
        ImGui::TableSetupColumn("textures");
        ImGui::TableSetupColumn("exact");
        ImGui::TableSetupColumn("difference");
        ImGui::TableHeadersRow();
        row("waterline length (m)", t.waterlineLength, e.waterlineLength);
        row("TPC (t/cm)", t.tonnesPerCentimetre, e.tonnesPerCentimetre);
        row("MCT1cm (t m/cm)", t.momentToChangeTrim, e.momentToChangeTrim);
        row("GZ max (m)", t.gzMax, e.gzMax);
        row("angle of GZ max (deg)", t.gzMaxDegrees, e.gzMaxDegrees);
        optionalRow("downflooding angle (deg)", t.downfloodingDegrees, e.downfloodingDegrees);
        ImGui::EndTable();
    }
    tooltip(
        "TPC: tonnes per centimetre of immersion. MCT1cm: the moment that trims the body by "
        "1 cm over its waterline length. Downflooding: the least heel at which an opening "
        "(a permeable texel of the water graph, an open hull's cap) reaches the water.");
    ImGui::Text("IMO 2008 IS Code, A 2.2: textures %s, exact %s",
                t.isCode2008.pass ? "pass" : "FAIL", e.isCode2008.pass ? "pass" : "FAIL");
    tooltip(
        "The general intact stability criteria (Res. MSC.267(85)) on the GZ curve less the "
        "free-surface loss times sin(heel); the areas to 40 degrees end at the downflooding "
        "angle where that is less.");
    if (ImGui::BeginTable("##iscode", 4, ImGuiTableFlags_RowBg | ImGuiTableFlags_Borders)) {
        ImGui::TableSetupColumn("criterion", ImGuiTableColumnFlags_WidthFixed, 180.0f);
        ImGui::TableSetupColumn("required");
        ImGui::TableSetupColumn("textures");
        ImGui::TableSetupColumn("exact");
        ImGui::TableHeadersRow();
        for (std::size_t i = 0;
             i < t.isCode2008.criteria.size() && i < e.isCode2008.criteria.size(); ++i) {
            const StabilityCriterion& a = t.isCode2008.criteria[i];
            const StabilityCriterion& b = e.isCode2008.criteria[i];
            ImGui::TableNextRow();
            ImGui::TableNextColumn();
            ImGui::Text("%s (%s)", a.name.c_str(), a.unit.c_str());
            ImGui::TableNextColumn();
            ImGui::Text(">= %.4g", a.required);
            for (const StabilityCriterion* c : {&a, &b}) {
                ImGui::TableNextColumn();
                ImGui::TextColored(
                    c->pass ? ImVec4(0.45f, 0.85f, 0.45f, 1) : ImVec4(1, 0.4f, 0.35f, 1), "%.4g %s",
                    c->value, c->pass ? "pass" : "FAIL");
            }
        }
        ImGui::EndTable();
    }
    if (e.crossCurves.empty()) return;
    const bool open = ImGui::TreeNode("KN cross curves (exact clip, m)");
    tooltip("KN = GZ + KG sin(heel), the righting arm about the keel, at several displacements.");
    if (!open) return;
    const std::vector<CrossCurve>& curves = e.crossCurves;
    if (ImGui::BeginTable("##kn", static_cast<int>(curves.size()) + 1,
                          ImGuiTableFlags_RowBg | ImGuiTableFlags_Borders)) {
        ImGui::TableSetupColumn("heel (deg)");
        char label[48];
        for (const CrossCurve& c : curves) {
            std::snprintf(label, sizeof label, "%.4g m^3", c.displacement);
            ImGui::TableSetupColumn(label);
        }
        ImGui::TableHeadersRow();
        for (std::size_t i = 0; i < curves[0].heelsDegrees.size(); ++i) {
            ImGui::TableNextRow();
            ImGui::TableNextColumn();
            ImGui::Text("%g", curves[0].heelsDegrees[i]);
            for (const CrossCurve& c : curves) {
                ImGui::TableNextColumn();
                ImGui::Text("%.4f", c.kn[i]);
            }
        }
        ImGui::EndTable();
    }
    ImGui::TreePop();
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
    drawGzPlot(t, e);  // before the report: the window's plot stays where it was
    drawStabilityReport(t, e);
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
        ImGui::TextWrapped(
            "Radiation is off for this body: give it a \"radiation\" object in the "
            "project (docs/project-schema.md) for its added mass, damping and decay test.");
        return;
    }
    const BodyRadiation& r = *body.radiation;
    const char* modes[] = {"surge (x)",      "heave (y)",     "sway (z)",
                           "roll (about x)", "yaw (about y)", "pitch (about z)"};
    ImGui::Combo("mode", &gRadiationMode, modes, 6);
    tooltip(
        "Which motion's added mass and damping are plotted (body axes, about the centre of mass).");
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
    ImGui::PlotLines("##radiation A", added.data(), static_cast<int>(added.size()), 0, label,
                     FLT_MAX, FLT_MAX, ImVec2(0, 80));
    tooltip("Added mass against frequency, low to high (the frequencies are log-spaced).");
    std::snprintf(label, sizeof label, "B (%s/s)", unit);
    ImGui::PlotLines("##radiation B", damping.data(), static_cast<int>(damping.size()), 0, label,
                     FLT_MAX, FLT_MAX, ImVec2(0, 80));
    tooltip(
        "Radiation damping against frequency: the waves the motion makes carry its energy away.");

    const bool running = gDecay.running.valid();
    ImGui::BeginDisabled(running);
    if (ImGui::Button("Decay test")) startDecayTest(scene, index);
    ImGui::EndDisabled();
    tooltip(
        "Releases the body 2 cm below its rest waterline in calm water, alone, with drag and\n"
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
    ImGui::PlotLines("##decay", heave.data(), static_cast<int>(heave.size()), 0,
                     "heave from rest (mm)", FLT_MAX, FLT_MAX, ImVec2(0, 90));
    auto percent = [](double measured, double predicted) {
        return 100 * (measured / predicted - 1);
    };
    ImGui::Text("period %.4f s (A and B predict %.4f, %+.1f%%)", t.measured.period,
                t.predicted.period, percent(t.measured.period, t.predicted.period));
    ImGui::Text("log decrement %.4f (predicted %.4f, %+.1f%%)", t.measured.logDecrement,
                t.predicted.logDecrement,
                percent(t.measured.logDecrement, t.predicted.logDecrement));
}

}  // namespace

void drawHydrostaticsPanel(EditorState& s) {
    const bool previewing = s.preview && s.preview->session;
    if (!previewing && !s.showHydrostatics) return;
    const int selected = s.selectedBody;
    if (selected < 0 || static_cast<std::size_t>(selected) >= s.document->bodyCount()) return;
    const std::size_t index = static_cast<std::size_t>(selected);
    // Folded at first beside a preview; opened at once from Simulate > Hydrostatics.
    ImGui::SetNextWindowCollapsed(!s.showHydrostatics, ImGuiCond_FirstUseEver);
    if (s.hydrostaticsOpenRequest) ImGui::SetNextWindowCollapsed(false, ImGuiCond_Always);
    s.hydrostaticsOpenRequest = false;
    ImGui::SetNextWindowPos(ImVec2(20, 160), ImGuiCond_FirstUseEver);
    ImGui::SetNextWindowSize(ImVec2(460, 560), ImGuiCond_FirstUseEver);
    bool open = true;
    const bool expanded = ImGui::Begin("Hydrostatics", previewing ? nullptr : &open);
    if (!open) s.showHydrostatics = false;
    if (!expanded) {
        ImGui::End();
        return;
    }
    const Scene* scene = previewing ? &s.preview->session->scene() : gOwnScene.get();
    const std::string label = scene && index < scene->bodies.size()
                                  ? scene->bodies[index].label
                                  : s.document->project().bodies[index].name;
    ImGui::TextWrapped("%s: calm water, heel about x, trim about z%s", label.c_str(),
                       previewing ? "" : " (the project as edited)");
    const bool computing = gComputing.valid();
    ImGui::BeginDisabled(computing);
    if (ImGui::Button("Compute")) {
        // The preview's scene, or the document's as it is now (its bake on this thread).
        std::shared_ptr<const Scene> copy;
        if (previewing) {
            copy = std::make_shared<const Scene>(*scene);
        } else if (Result<Scene> built = s.document->simulationScene(); built) {
            copy = gOwnScene = std::make_shared<const Scene>(std::move(built).value());
        } else {
            gFigures = {label, std::nullopt, std::nullopt, built.error().message};
        }
        if (copy && index < copy->bodies.size()) startCompute(copy, index);
    }
    ImGui::EndDisabled();
    tooltip(
        "Finds the body's equilibrium in calm water and its righting-arm curve, from the\n"
        "textures and from the exact clip side by side (on a worker: the window stays live).");
    if (computing) {
        if (gComputing.wait_for(std::chrono::seconds(0)) == std::future_status::ready) {
            gFigures = gComputing.get();
        } else {
            ImGui::SameLine();
            ImGui::TextUnformatted("computing...");
        }
    }
    if (gFigures.body == label) {
        if (!gFigures.error.empty()) ImGui::TextWrapped("error: %s", gFigures.error.c_str());
        if (gFigures.textures && gFigures.exact) drawFigures(*gFigures.textures, *gFigures.exact);
    }
    if (scene && index < scene->bodies.size() &&
        ImGui::CollapsingHeader("Radiation: added mass, damping, decay test"))
        drawRadiation(*scene, index);
    ImGui::End();
}

bool hydrostaticsComputing() { return gComputing.valid(); }

}  // namespace plimsoll::editor
