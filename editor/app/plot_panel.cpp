// The live preview's plots over time: one movable, collapsible window per quantity group and
// body (submerged volume, heel and trim, forces, water per node), each with "Export CSV".
// Debian's Dear ImGui 1.86 is built without the docking branch, so the windows float.
#include "app/preview_panel.h"

#include "app/panels.h"
#include "app/tooltip.h"

#include <imgui.h>
#include <imgui_internal.h>  // MovingWindow: the user moved a plot window

#include <algorithm>
#include <cctype>
#include <cfloat>
#include <cstdio>
#include <string>

namespace plimsoll::editor {

namespace {

struct PlotGroup {
    std::string title;  ///< window title
    std::vector<const PlotSeries*> series;
};

/// The groups of a body's series, by the names PreviewSession records.
std::vector<PlotGroup> groupsOf(const PreviewHistory& history, const std::string& body) {
    std::vector<PlotGroup> groups{{"Submerged volume: " + body, {}},
                                  {"Heel and trim: " + body, {}},
                                  {"Forces: " + body, {}},
                                  {"Water per node: " + body, {}}};
    auto ends = [](const std::string& name, const std::string& tail) {
        return name.size() >= tail.size() &&
               name.compare(name.size() - tail.size(), tail.size(), tail) == 0;
    };
    for (const PlotSeries& s : history.series) {
        if (s.name.rfind(body + " ", 0) != 0) continue;
        const std::string what = s.name.substr(body.size() + 1);
        if (what == "submerged volume")
            groups[0].series.push_back(&s);
        else if (what == "heel" || what == "trim")
            groups[1].series.push_back(&s);
        else if (what == "weight" || what == "buoyancy" || what == "drag")
            groups[2].series.push_back(&s);
        else if (what.rfind("water ", 0) == 0 || ends(what, " water"))
            groups[3].series.push_back(&s);
    }
    groups.erase(std::remove_if(groups.begin(), groups.end(),
                                [](const PlotGroup& g) { return g.series.empty(); }),
                 groups.end());
    return groups;
}

std::string fileSafe(std::string text) {
    for (char& c : text) {
        if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
    }
    return text;
}

}  // namespace

void drawPlotPanels(EditorState& s) {
    if (!s.preview || !s.preview->session || !s.preview->showPlots) return;
    PreviewUi& p = *s.preview;
    const PreviewSession& session = *p.session;
    const PreviewHistory& history = session.history();
    if (history.time.empty()) return;
    float y = s.viewport.y + 30;
    for (std::size_t b = 0; b < session.world().bodies().size(); ++b) {
        const std::string& named = session.world().bodies()[b].name;
        const std::string body = named.empty() ? "body " + std::to_string(b) : named;
        for (const PlotGroup& group : groupsOf(history, body)) {
            // Stacked down the right edge of the view, each below the one above as it is this
            // frame (an opened one pushes the rest down), until the user moves it.
            const bool stacked = !p.plotsMoved.contains(group.title);
            if (stacked)
                ImGui::SetNextWindowPos(ImVec2(s.viewport.x + s.viewport.w - 330, y),
                                        ImGuiCond_Always);
            ImGui::SetNextWindowSize(ImVec2(320, 0), ImGuiCond_FirstUseEver);
            ImGui::SetNextWindowCollapsed(true, ImGuiCond_FirstUseEver);  // title bars first
            const bool open = ImGui::Begin(group.title.c_str());
            openWhenTitleClicked();
            if (ImGui::GetCurrentContext()->MovingWindow == ImGui::GetCurrentWindow() &&
                ImGui::IsMouseDragging(0)) {
                p.plotsMoved.insert(group.title);
            }
            if (stacked) y += ImGui::GetWindowHeight() + 4;
            if (!open) {
                ImGui::End();
                continue;
            }
            // The last 10 s (or what there is), as floats for ImGui.
            const std::size_t rows = history.time.size();
            const std::size_t shown = std::min<std::size_t>(rows, 600);
            std::vector<float> values(shown);
            // An explicit width: Debian's ImGui 1.86 sizes a plot of width -1 to nothing in a
            // window whose height fits its content.
            const float plotWidth = std::max(120.0f, ImGui::GetContentRegionAvail().x);
            for (const PlotSeries* series : group.series) {
                for (std::size_t k = 0; k < shown; ++k)
                    values[k] = float(series->values[rows - shown + k]);
                char overlay[128];
                std::snprintf(overlay, sizeof overlay, "%s %.4g %s",
                              series->name.c_str() + body.size() + 1, series->values.back(),
                              series->unit.c_str());
                ImGui::PlotLines(("##" + series->name).c_str(), values.data(), int(shown), 0,
                                 overlay, FLT_MAX, FLT_MAX, ImVec2(plotWidth, 60));
            }
            const bool exportCsv = ImGui::Button("Export CSV");
            tooltip(
                "Writes these series, one row per frame, to a CSV file in the project's folder.");
            if (exportCsv) {
                std::vector<std::string> names;
                for (const PlotSeries* series : group.series) names.push_back(series->name);
                const std::filesystem::path folder = s.document->project().folder.empty()
                                                         ? std::filesystem::current_path()
                                                         : s.document->project().folder;
                const std::filesystem::path path = folder / (fileSafe(group.title) + ".csv");
                const Status written = writeHistoryCsv(history, names, path);
                p.plotStatus = written ? "Wrote " + path.string() : written.error().message;
                s.status = p.plotStatus;
            }
            ImGui::SameLine();
            ImGui::TextDisabled("%zu rows, t = %.1f..%.1f s", rows, history.time.front(),
                                history.time.back());
            ImGui::End();
        }
    }
}

}  // namespace plimsoll::editor
