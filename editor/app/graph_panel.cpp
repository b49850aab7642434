// The "Water graph" panel and its tools in the 3D view: the selected body's graph drawn inside
// its see-through hull (graph_draw.h), nodes and pipes picked with the mouse (click, shift-click
// to add, drag a rectangle on empty space to box-select), selected nodes dragged (on the view
// plane, a horizontal plane or the hull's surface; holding X, Y or Z keeps the drag on that
// world axis), and the panel's buttons and inspector. Every change is a command of
// graph_edit.h: one undo step per click, per drag, per edited field. "Auto-generate" builds a
// graph on a worker thread (segmentation takes seconds) and shows its segments on the hull
// before "Apply" replaces the graph.
#include "app/panels.h"
#include "plimsoll/graph_auto/graph_auto.h"
#include "app/preview_panel.h"

#include "document/graph_edit.h"
#include "document/graph_view.h"
#include "render/graph_draw.h"
#include "view/graph_pick.h"

#include <GLFW/glfw3.h>
#include <imgui.h>

#include <algorithm>
#include <atomic>
#include <cstring>
#include <functional>
#include <future>
#include <set>

namespace plimsoll::editor {

namespace {

/// Overlay slots of the feed / segment colours: past the bodies' own (slot = body index).
constexpr int kGraphOverlaySlot = 1 << 20;

enum class DragPlane { View = 0, Horizontal = 1, Surface = 2 };

/// A finished automatic graph waiting for "Apply".
struct AutoPreview {
    std::size_t body = 0;
    WaterGraph graph;
    std::vector<int> texelSegment;
    int segments = 0;
    double seconds = 0;
};

struct AutoJob {
    std::future<Result<AutoPreview>> result;
    std::shared_ptr<std::atomic<double>> progress;
    std::size_t body = 0;
};

}  // namespace

/// The panel's state (EditorState::graphUi): selection, tools, the automatic graph's job.
/// The radius of a schematic box's port (the dot on its right edge a pipe is dragged from).
constexpr float kPortRadius = 6.0f;
/// The width a schematic box's label wraps at, pixels.
constexpr float kLabelWidth = 90.0f;

/// A drag begun on the schematic: moving nodes (from a box) or connecting (from a port).
struct SchematicDrag {
    int node = -1;  ///< the node it began on; -1: none
    bool connect = false;
    Eigen::Vector2f from{0, 0};  ///< the mouse where it began, screen pixels
};

struct GraphUi {
    SchematicDrag schematicDrag;
    /// The schematic's mapping of the profile, kept while the nodes move (a drop rescales
    /// nothing), and while the panel's width changes (a warning line that brings a scrollbar),
    /// until "Frame" is pressed or another body is shown.
    std::optional<SchematicFrame> schematicFrame;
    std::size_t schematicBody = ~std::size_t{0};
    bool schematicEmpty = true;  ///< framed with no nodes: the first ones reframe it
    bool editInView = true;      ///< the left mouse edits the graph (else the paint tools)
    bool panelOpen = false;      ///< not collapsed: only then does the graph take the mouse
    bool showGraph = true;
    bool showFeeds = false;
    float hullAlpha = 0.3f;
    DragPlane dragPlane = DragPlane::View;
    std::set<std::string> selected;  ///< node ids (ids survive undo; indices do not)
    std::optional<std::pair<std::string, std::string>> selectedPipe;
    // Mouse in the view.
    bool boxSelecting = false, dragging = false;
    ImVec2 pressAt{0, 0}, mouseAt{0, 0};
    Eigen::Vector3d anchor = Eigen::Vector3d::Zero();      ///< world, the grabbed node
    Eigen::Vector3d dragOffset = Eigen::Vector3d::Zero();  ///< world, so far
    // Auto-generate.
    int segments = 4;
    std::optional<AutoJob> job;
    std::optional<AutoPreview> preview;
    std::string autoError;
    // Overlay upload cache.
    std::uint64_t overlayRevision = ~std::uint64_t{0};
    int overlayKind = -1;
    std::size_t overlayBody = ~std::size_t{0};
    std::unique_ptr<GraphDrawer> drawer;
    std::vector<RenderGraph> drawn;  ///< this frame's, for the scene's drawInside
    WaterGraph dragged;              ///< the graph with the drag applied (drawn while dragging)
    // The inspector's fields while being edited (committed when editing ends).
    char nodeName[128] = {};
    std::string nodeEditingFor;
    GraphNode nodeShown;
    GraphPipe pipeShown;
    std::pair<std::string, std::string> pipeEditingFor;
};

namespace {

GraphUi& uiOf(const EditorState& s) { return *s.graphUi; }

std::size_t bodyOf(const EditorState& s) {
    return static_cast<std::size_t>(std::max(0, s.selectedBody));
}

const WaterGraph* graphOf(const EditorState& s) {
    if (!s.document || bodyOf(s) >= s.document->bodyCount()) return nullptr;
    return s.document->graph(bodyOf(s));
}

std::vector<std::string> selectedIds(const GraphUi& ui, const WaterGraph& g) {
    std::vector<std::string> ids;
    for (const GraphNode& n : g.nodes) {
        if (ui.selected.count(n.id)) ids.push_back(n.id);
    }
    return ids;
}

/// Drops selected ids the graph no longer has (after an undo or a delete).
void pruneSelection(GraphUi& ui, const WaterGraph* g) {
    if (!g) {
        ui.selected.clear();
        ui.selectedPipe.reset();
        return;
    }
    std::erase_if(ui.selected, [&](const std::string& id) { return g->indexOf(id) < 0; });
    if (ui.selectedPipe && findPipe(*g, ui.selectedPipe->first, ui.selectedPipe->second) < 0) {
        ui.selectedPipe.reset();
    }
}

void ray(const EditorState& s, ImVec2 mouse, Eigen::Vector3d& origin, Eigen::Vector3d& direction) {
    s.camera.rayThrough(mouse.x - s.viewport.x, mouse.y - s.viewport.y, int(s.viewport.w),
                        int(s.viewport.h), origin, direction);
}

/// Where the drag puts the grabbed node now (world), from the mouse ray.
std::optional<Eigen::Vector3d> dragTarget(const EditorState& s, ImVec2 mouse) {
    const GraphUi& ui = uiOf(s);
    Eigen::Vector3d o, d;
    ray(s, mouse, o, d);
    for (int axis = 0; axis < 3; ++axis) {
        if (ImGui::IsKeyDown(GLFW_KEY_X + axis)) {
            return closestOnAxis(ui.anchor, Eigen::Vector3d::Unit(axis), o, d);
        }
    }
    switch (ui.dragPlane) {
        case DragPlane::Surface: {
            // Snap onto the hull under the mouse (the inner side is the same surface).
            if (auto hit = s.pick(mouse.x, mouse.y); hit && hit->first == bodyOf(s)) {
                return s.document->bodyPose(hit->first).apply(hit->second);
            }
            return std::nullopt;
        }
        case DragPlane::Horizontal:
            return rayPlane(o, d, ui.anchor, Eigen::Vector3d::UnitY());
        case DragPlane::View:
            break;
    }
    return rayPlane(o, d, ui.anchor, -s.camera.forward());
}

void startAutoGenerate(EditorState& s) {
    GraphUi& ui = uiOf(s);
    const std::size_t body = bodyOf(s);
    auto mesh = s.document->assets(body).mesh;
    const std::shared_ptr<const SurfaceTextures> textures = s.physicsFor(body);
    const bool current = textures && textures == s.document->bakedPhysics(body);
    if (!mesh || !current) {
        ui.autoError =
            !mesh ? "the body has no mesh"
            : !s.physicsBakes->error(body).empty()
                ? s.physicsBakes->error(body)
                : "the physics textures are baking (see the inspector); try again when done";
        return;
    }
    auto progress = std::make_shared<std::atomic<double>>(0.0);
    const int segments = ui.segments;
    std::shared_ptr<const SurfaceTextures> baked = textures;
    // The worker owns shared pointers to what it reads: the document may change meanwhile.
    ui.job = AutoJob{std::async(std::launch::async,
                                [mesh, baked, segments, progress]() -> Result<AutoPreview> {
                                    AutoGraphSettings settings;
                                    settings.segments = segments;
                                    settings.progress = [&](double p) { *progress = 0.9 * p; };
                                    AutoGraphReport report;
                                    Result<WaterGraph> graph =
                                        buildAutomaticGraph(*mesh, settings, &report);
                                    if (!graph) return graph.error();
                                    AutoPreview preview;
                                    preview.graph = std::move(graph).value();
                                    preview.segments = report.segmentation.segmentCount;
                                    preview.seconds = report.totalSeconds;
                                    preview.texelSegment =
                                        texelSegments(*mesh, report.segmentation, *baked,
                                                      [&](double p) { *progress = 0.9 + 0.1 * p; });
                                    return preview;
                                }),
                     progress, body};
    ui.preview.reset();
    ui.autoError.clear();
}

void pollAutoGenerate(GraphUi& ui) {
    if (!ui.job) return;
    if (ui.job->result.wait_for(std::chrono::seconds(0)) != std::future_status::ready) return;
    Result<AutoPreview> done = ui.job->result.get();
    const std::size_t body = ui.job->body;
    ui.job.reset();
    if (!done) {
        ui.autoError = done.error().message;
        return;
    }
    ui.preview = std::move(done).value();
    ui.preview->body = body;
    ui.overlayRevision = ~std::uint64_t{0};  // show the segments
}

/// A number field that commits (true) once when editing ends: one command per edit, not one
/// per keystroke. No step buttons: they are items of their own, outside that test.
bool inputDouble(const char* label, double& value, const char* format = "%.4f") {
    ImGui::InputDouble(label, &value, 0.0, 0.0, format);
    return ImGui::IsItemDeactivatedAfterEdit();
}

void nodeInspector(EditorState& s, const GraphNode& n) {
    ImGui::Text("Node %s", n.id.c_str());
    GraphUi& ui = uiOf(s);
    char(&name)[128] = ui.nodeName;
    std::string& editingFor = ui.nodeEditingFor;
    GraphNode& shown = ui.nodeShown;
    if (editingFor != n.id || !ImGui::IsAnyItemActive()) {
        editingFor = n.id;
        shown = n;
        std::snprintf(name, sizeof name, "%s", n.name.c_str());
    }
    NodeEdit e;
    ImGui::InputText("name", name, sizeof name);
    tooltip("A label for the compartment, shown in the 3D view and the schematic.");
    if (ImGui::IsItemDeactivatedAfterEdit()) e.name = std::string(name);
    ImGui::DragScalarN("position", ImGuiDataType_Double, shown.position.data(), 3, 0.01f);
    tooltip("The node's centre in the body's frame, metres (drag, or Ctrl+click to type).");
    if (ImGui::IsItemDeactivatedAfterEdit()) e.position = shown.position;
    if (inputDouble("capacity m^3", shown.capacity)) e.capacity = shown.capacity;
    tooltip("How much water the compartment holds when full, cubic metres.");
    if (inputDouble("water m^3", shown.water)) e.water = shown.water;
    tooltip("The water in it at the start of a run, cubic metres (0 to capacity).");
    if (ImGui::Checkbox("sealed", &shown.sealed)) e.sealed = shown.sealed;
    tooltip("A sealed compartment takes no water through the hull, only through its pipes.");
    bool box = shown.isBox();
    const bool boxClicked = ImGui::Checkbox("box", &box);
    tooltip(
        "A box compartment: its water fills an upright box and levels as the body heels.\n"
        "Off: a sphere-like node whose level follows its volume alone.");
    if (boxClicked) {
        // A sphere becomes the cube of its capacity; a box a sphere (zero box size).
        const double side = std::cbrt(shown.capacity);
        e.boxSize = box ? Eigen::Vector3d::Constant(side) : Eigen::Vector3d::Zero();
    }
    if (box) {
        ImGui::DragScalarN("box size m", ImGuiDataType_Double, shown.boxSize.data(), 3, 0.01f);
        tooltip("The box's edge lengths along the body's x, y and z, metres.");
        if (ImGui::IsItemDeactivatedAfterEdit()) e.boxSize = shown.boxSize;
    }
    if (e.name || e.position || e.capacity || e.water || e.sealed || e.boxSize) {
        s.execute(makeSetNodeCommand(*s.document, bodyOf(s), n.id, e));
    }
}

/// Several nodes selected: the fields they can share (capacity, water, sealed, box size), set
/// on all of them as one step. Each field shows the first node's value and says when the
/// selection differs in it.
void nodesInspector(EditorState& s, const WaterGraph& g, const std::set<std::string>& selected) {
    GraphUi& ui = uiOf(s);
    std::vector<std::string> ids;
    std::vector<const GraphNode*> nodes;
    for (const std::string& id : selected) {
        if (const int i = g.indexOf(id); i >= 0) {
            ids.push_back(id);
            nodes.push_back(&g.nodes[static_cast<std::size_t>(i)]);
        }
    }
    if (nodes.empty()) return;
    ImGui::Text("%zu nodes selected", ids.size());
    std::string key;
    for (const std::string& id : ids) key += id + '\n';
    GraphNode& shown = ui.nodeShown;
    if (ui.nodeEditingFor != key || !ImGui::IsAnyItemActive()) {
        ui.nodeEditingFor = key;
        shown = *nodes.front();
    }
    auto mixed = [&](auto field) {
        const bool differ = std::any_of(nodes.begin(), nodes.end(), [&](const GraphNode* n) {
            return field(*n) != field(*nodes.front());
        });
        if (differ) {
            ImGui::SameLine();
            ImGui::TextDisabled("(mixed)");
        }
    };
    NodeEdit e;
    if (inputDouble("capacity m^3", shown.capacity)) e.capacity = shown.capacity;
    tooltip("Set every selected compartment's capacity, cubic metres.");
    mixed([](const GraphNode& n) { return n.capacity; });
    if (inputDouble("water m^3", shown.water)) e.water = shown.water;
    tooltip("Set the water every selected compartment starts with, cubic metres.");
    mixed([](const GraphNode& n) { return n.water; });
    if (ImGui::Checkbox("sealed", &shown.sealed)) e.sealed = shown.sealed;
    tooltip("Seal (or open) every selected compartment to the hull.");
    mixed([](const GraphNode& n) { return n.sealed; });
    if (shown.isBox()) {
        ImGui::DragScalarN("box size m", ImGuiDataType_Double, shown.boxSize.data(), 3, 0.01f);
        tooltip("Give every selected compartment this box, metres along the body's x, y and z.");
        if (ImGui::IsItemDeactivatedAfterEdit()) e.boxSize = shown.boxSize;
        mixed([](const GraphNode& n) { return n.boxSize; });
    }
    if (e.capacity || e.water || e.sealed || e.boxSize) {
        s.execute(makeSetNodesCommand(*s.document, bodyOf(s), ids, e));
    }
}

void pipeInspector(EditorState& s, const WaterGraph& g, const GraphPipe& p) {
    ImGui::Text("Pipe %s - %s", p.a.c_str(), p.b.c_str());
    GraphPipe& shown = uiOf(s).pipeShown;
    std::pair<std::string, std::string>& editingFor = uiOf(s).pipeEditingFor;
    if (editingFor != std::pair(p.a, p.b) || !ImGui::IsAnyItemActive()) {
        editingFor = {p.a, p.b};
        shown = p;
    }
    PipeEdit e;
    if (inputDouble("radius m", shown.radius)) e.radius = shown.radius;
    tooltip("The pipe's inner radius, metres: flow grows with its fourth power (Poiseuille).");
    if (inputDouble("length m (0: distance)", shown.length)) e.length = shown.length;
    tooltip("The pipe's length, metres; 0 uses the distance between its two nodes.");
    ImGui::Text("effective length %.3f m", g.pipeLength(p));
    bool open = shown.open;
    if (ImGui::Checkbox("open", &open)) e.open = open;
    tooltip("A closed pipe passes no water (a shut valve or a closed door).");
    if (e.radius || e.length || e.open)
        s.execute(makeSetPipeCommand(*s.document, bodyOf(s), p.a, p.b, e));
}

/// Uploads the feed or segment colours of the selected body when what they show changed.
void updateOverlay(EditorState& s) {
    GraphUi& ui = uiOf(s);
    const std::size_t body = bodyOf(s);
    const bool segments = ui.preview && ui.preview->body == body;
    const int kind = segments ? 2 : ui.showFeeds ? 1 : 0;
    if (kind == ui.overlayKind && s.documentRevision == ui.overlayRevision &&
        body == ui.overlayBody) {
        return;
    }
    ui.overlayKind = kind;
    ui.overlayRevision = s.documentRevision;
    ui.overlayBody = body;
    OverlayImage none;
    s.renderer->setOverlay(kGraphOverlaySlot, none);
    if (kind == 0) return;
    const std::shared_ptr<const SurfaceTextures> textures = s.physicsFor(body);
    if (!textures) return;  // the bake's arrival bumps the revision: drawn then
    if (kind == 2) {
        s.renderer->setOverlay(kGraphOverlaySlot,
                               segmentOverlay(ui.preview->texelSegment, *textures));
    } else if (const WaterGraph* g = graphOf(s)) {
        s.renderer->setOverlay(kGraphOverlaySlot, feedOverlay(*g, *textures));
    }
}

}  // namespace

namespace {

/// The nodes a drag from node `index` moves: the selection when the node is in it, else the
/// node alone.
std::vector<std::string> draggedNodes(const GraphUi& ui, const WaterGraph& g, int index) {
    const std::string& id = g.nodes[index].id;
    if (!ui.selected.count(id)) return {id};
    return std::vector<std::string>(ui.selected.begin(), ui.selected.end());
}

/// The schematic's pipes and boxes with their ports, each box at `centre` (canvas pixels).
void drawSchematicGraph(ImDrawList* draw, const GraphUi& ui, const WaterGraph& g,
                        const std::vector<Eigen::Vector2f>& centre, const Eigen::Vector2f& box,
                        const std::function<ImVec2(const Eigen::Vector2f&)>& at, int hot) {
    for (const GraphPipe& pipe : g.pipes) {
        const int a = g.indexOf(pipe.a), b = g.indexOf(pipe.b);
        if (a < 0 || b < 0) continue;
        const bool selected = ui.selectedPipe == std::pair(pipe.a, pipe.b);
        draw->AddLine(at(centre[a]), at(centre[b]),
                      selected    ? IM_COL32(255, 255, 255, 255)
                      : pipe.open ? IM_COL32(90, 170, 255, 255)
                                  : IM_COL32(120, 120, 120, 255),
                      selected ? 3.0f : 2.0f);
    }
    for (std::size_t i = 0; i < g.nodes.size(); ++i) {
        const GraphNode& node = g.nodes[i];
        const ImVec2 c = at(centre[i]);
        const ImVec2 lo(c.x - 0.5f * box.x(), c.y - 0.5f * box.y()),
            hi(c.x + 0.5f * box.x(), c.y + 0.5f * box.y());
        draw->AddRectFilled(lo, hi, IM_COL32(20, 22, 26, 255));
        const float fill =
            node.capacity > 0 ? std::clamp(float(node.water / node.capacity), 0.0f, 1.0f) : 0.0f;
        if (fill > 0)
            draw->AddRectFilled(ImVec2(lo.x, hi.y - fill * box.y()), hi,
                                IM_COL32(40, 110, 200, 255));
        const Eigen::Vector3f colour = nodeColour(i);
        const ImU32 edge =
            IM_COL32(int(255 * colour.x()), int(255 * colour.y()), int(255 * colour.z()), 255);
        const bool selected = ui.selected.count(node.id) > 0;
        draw->AddRect(lo, hi, selected ? IM_COL32(255, 255, 255, 255) : edge, 0.0f, 0,
                      selected || int(i) == hot ? 2.5f : 1.5f);
        // The whole name, wrapped: every box holds the largest (schematicBoxFor).
        draw->AddText(
            nullptr, 0.0f, ImVec2(lo.x + kSchematicMargin.x(), lo.y + kSchematicMargin.y()),
            IM_COL32(235, 235, 235, 255), schematicLabel(node).c_str(), nullptr, kLabelWidth);
        draw->AddCircleFilled(ImVec2(hi.x, c.y), kPortRadius - 1.5f, edge);
    }
}

/// The end of a drag on the schematic: a pipe from the drag's node to the one dropped on, or
/// the dragged nodes moved by `moved` pixels (one command each); a press without a move
/// selects the node alone.
void dropSchematicDrag(EditorState& s, GraphUi& ui, std::size_t body, const WaterGraph& g,
                       const SchematicLayout& layout, int target,
                       const std::vector<std::string>& moving, const Eigen::Vector2f& moved) {
    const SchematicDrag& drag = ui.schematicDrag;
    const std::string& id = g.nodes[drag.node].id;
    if (drag.connect) {
        if (target < 0 || target == drag.node) return;
        GraphPipe pipe;
        pipe.a = id;
        pipe.b = g.nodes[target].id;
        if (s.execute(makeAddPipeCommand(*s.document, body, pipe)))
            ui.selectedPipe = {pipe.a, pipe.b};
        return;
    }
    if (moved.norm() >= 2.0f) {
        s.execute(
            makeMoveNodesCommand(*s.document, body, moving, schematicDragOffset(layout, moved)));
    } else if (!ImGui::GetIO().KeyShift && !ImGui::GetIO().KeyCtrl) {
        ui.selected = {id};
    }
}

/// The schematic beside the 3D view (graph_view.h), a node editor: boxes at the nodes' profile
/// places, wide enough for their whole names, filled to their water level, pipes between them
/// (closed ones grey). Click to select (Shift adds); drag a box to move the selected nodes
/// across the profile and up or down; drag from a box's port (the dot on its right edge) onto
/// another box to connect the two with a pipe. Each drop is one command (one undo step).
void drawSchematic(EditorState& s, GraphUi& ui, std::size_t body, const WaterGraph& g) {
    const float width = std::max(120.0f, ImGui::GetContentRegionAvail().x);
    // Whole names, wrapped at kLabelWidth: "stern compartment (engine room)" on two lines.
    const Eigen::Vector2f box = schematicBoxFor(
        g,
        [](const std::string& text) {
            const ImVec2 size = ImGui::CalcTextSize(text.c_str(), nullptr, false, kLabelWidth);
            return Eigen::Vector2f(size.x, size.y);
        },
        Eigen::Vector2f(64, 26));
    if (!ui.schematicFrame || ui.schematicBody != body || (ui.schematicEmpty && !g.nodes.empty())) {
        ui.schematicFrame = schematicFrame(g, width, 200.0f, box);
        ui.schematicEmpty = g.nodes.empty();
        ui.schematicBody = body;
    }
    const SchematicLayout layout = schematicLayout(g, *ui.schematicFrame, box);
    // A crowded profile grows past the canvas: the canvas grows with it.
    float right = width, bottom = 200.0f, left = 0, top = 0;
    for (const Eigen::Vector2f& c : layout.centre) {
        right = std::max(right, c.x() + 0.5f * box.x() + kPortRadius);
        bottom = std::max(bottom, c.y() + 0.5f * box.y());
        left = std::min(left, c.x() - 0.5f * box.x());
        top = std::min(top, c.y() - 0.5f * box.y());
    }
    const ImVec2 size(right - left, bottom - top);
    // Wider than the panel (whole names on many boxes): the canvas scrolls sideways.
    ImGui::BeginChild("##schematic_scroll", ImVec2(0, size.y + ImGui::GetStyle().ScrollbarSize),
                      false, ImGuiWindowFlags_HorizontalScrollbar);
    const ImVec2 origin = ImGui::GetCursorScreenPos();
    ImGui::InvisibleButton("##schematic", size);
    const bool hovered = ImGui::IsItemHovered();
    const bool clicked = ImGui::IsItemClicked(0);
    ImDrawList* draw = ImGui::GetWindowDrawList();
    draw->AddRectFilled(origin, ImVec2(origin.x + size.x, origin.y + size.y),
                        IM_COL32(30, 32, 36, 255));
    const ImVec2 mouse = ImGui::GetIO().MousePos;
    const Eigen::Vector2f local(mouse.x - origin.x + left, mouse.y - origin.y + top);
    const int under = hovered ? schematicNodeAt(layout, local) : -1;
    const int port = hovered ? schematicPortAt(layout, local, kPortRadius) : -1;
    SchematicDrag& drag = ui.schematicDrag;
    if (clicked && (port >= 0 || under >= 0))
        drag = {port >= 0 ? port : under, port >= 0, Eigen::Vector2f(mouse.x, mouse.y)};
    // Where each box is drawn: moved with the mouse while its node is dragged.
    const Eigen::Vector2f moved =
        drag.node >= 0 && !drag.connect
            ? Eigen::Vector2f(Eigen::Vector2f(mouse.x, mouse.y) - drag.from)
            : Eigen::Vector2f(Eigen::Vector2f::Zero());
    const std::vector<std::string> moving = drag.node >= 0 && !drag.connect
                                                ? draggedNodes(ui, g, drag.node)
                                                : std::vector<std::string>{};
    std::vector<Eigen::Vector2f> centre = layout.centre;
    for (const std::string& id : moving) centre[g.indexOf(id)] += moved;
    auto at = [&](const Eigen::Vector2f& c) {
        return ImVec2(origin.x + c.x() - left, origin.y + c.y() - top);
    };
    drawSchematicGraph(draw, ui, g, centre, box, at, port >= 0 ? port : under);
    if (drag.node >= 0 && drag.connect) {
        const Eigen::Vector2f from = centre[drag.node] + Eigen::Vector2f(0.5f * box.x(), 0);
        draw->AddLine(at(from), mouse, IM_COL32(255, 220, 120, 255), 2.0f);
    }
    if (drag.node >= 0 && !ImGui::IsMouseDown(0)) {
        dropSchematicDrag(s, ui, body, g, layout, schematicNodeAt(layout, local), moving, moved);
        drag = {};
    } else if (under >= 0 && drag.node < 0) {
        const GraphNode& node = g.nodes[under];
        ImGui::SetTooltip("%s%s%s\nwater %.4g of %.4g m^3%s\ndrag to move, from the dot to connect",
                          node.id.c_str(), node.name.empty() ? "" : ": ", node.name.c_str(),
                          node.water, node.capacity, node.sealed ? "\nsealed" : "");
    }
    if (clicked && under >= 0 && port < 0) {
        const std::string& id = g.nodes[under].id;
        if (ImGui::GetIO().KeyShift || ImGui::GetIO().KeyCtrl) {
            if (!ui.selected.insert(id).second) ui.selected.erase(id);
        } else if (!ui.selected.count(id)) {
            // A press on a selected node keeps the selection: a drag moves all of it.
            ui.selected = {id};
        }
        ui.selectedPipe.reset();
    } else if (clicked && under < 0 && port < 0 && !ImGui::GetIO().KeyShift) {
        ui.selected.clear();
        ui.selectedPipe.reset();
    }
    ImGui::EndChild();
    // Below the canvas, so that it moves nothing: the next frame fits every node again.
    if (ImGui::SmallButton("Frame##schematic")) ui.schematicFrame.reset();
    tooltip("Fit every node into the schematic again (moving nodes keeps its scale).");
}

/// How the graph shows and is edited in the 3D view.
void drawGraphViewOptions(GraphUi& ui) {
    ImGui::Checkbox("Edit in view", &ui.editInView);
    tooltip("Click nodes in the 3D view to select them and drag to move them; painting pauses.");
    ImGui::SameLine();
    ImGui::Checkbox("Show", &ui.showGraph);
    tooltip("Draw the nodes, boxes and pipes in the 3D view.");
    ImGui::SameLine();
    ImGui::Checkbox("Feed colours", &ui.showFeeds);
    tooltip("Colour the hull by the node each texel's water flows into.");
    ImGui::SliderFloat("hull alpha", &ui.hullAlpha, 0.05f, 1.0f, "%.2f");
    tooltip("How opaque the hull is drawn while the graph shows (Ctrl+click to type).");
    const char* planes[] = {"view plane", "horizontal plane", "hull surface"};
    int plane = static_cast<int>(ui.dragPlane);
    if (ImGui::Combo("drag on", &plane, planes, 3)) ui.dragPlane = static_cast<DragPlane>(plane);
    tooltip(
        "Where a dragged node moves: in the plane facing the camera, at its height, or along\n"
        "the hull's surface.");
    ImGui::PushTextWrapPos(0.0f);
    ImGui::TextDisabled("hold X / Y / Z while dragging: along that axis");
    ImGui::PopTextWrapPos();
}

/// The edit buttons, each one command: add, duplicate, delete, connect, disconnect, open/close.
void drawGraphEditButtons(EditorState& s, GraphUi& ui, std::size_t body, const WaterGraph& graph) {
    const WaterGraph* g = &graph;
    const std::vector<std::string> ids = selectedIds(ui, *g);
    const bool addNode = ImGui::Button("Add node");
    tooltip("A new node at the middle of the body's bounds.");
    if (addNode) {
        GraphNode n;
        const Bounds3 bounds = computeBounds(*s.document->assets(body).mesh);
        n.position = 0.5 * (bounds.min + bounds.max);
        n.capacity = std::max(1e-6, 0.05 * (bounds.max - bounds.min).prod());
        if (s.execute(makeAddNodeCommand(*s.document, body, n))) {
            ui.selected = {graphOf(s)->nodes.back().id};
        }
    }
    ImGui::SameLine();
    ImGui::BeginDisabled(ids.empty());
    const bool duplicate = ImGui::Button("Duplicate");
    tooltip("Copies of the selected nodes, shifted along x (select nodes first).");
    if (duplicate) {
        const double shift = 0.1 * std::cbrt(g->nodes[g->indexOf(ids.front())].capacity);
        const std::size_t before = g->nodes.size();
        if (s.execute(makeDuplicateNodesCommand(*s.document, body, ids, {shift, 0, 0}))) {
            ui.selected.clear();
            const WaterGraph& now = *graphOf(s);
            for (std::size_t i = before; i < now.nodes.size(); ++i)
                ui.selected.insert(now.nodes[i].id);
        }
    }
    ImGui::SameLine();
    if (ImGui::Button("Delete")) s.execute(makeDeleteNodesCommand(*s.document, body, ids));
    tooltip("Removes the selected nodes and their pipes (Delete).");
    ImGui::EndDisabled();
    ImGui::BeginDisabled(ids.size() != 2);
    const bool connect = ImGui::Button("Connect");
    tooltip("A pipe between the two selected nodes (select exactly two).");
    if (connect) {
        GraphPipe p;
        p.a = ids[0];
        p.b = ids[1];
        if (s.execute(makeAddPipeCommand(*s.document, body, p))) ui.selectedPipe = {p.a, p.b};
    }
    ImGui::EndDisabled();
    ImGui::SameLine();
    const bool pairJoined = ids.size() == 2 && findPipe(*g, ids[0], ids[1]) >= 0;
    ImGui::BeginDisabled(!ui.selectedPipe && !pairJoined);
    const bool disconnect = ImGui::Button("Disconnect");
    tooltip("Removes the selected pipe, or the one between the two selected nodes.");
    if (disconnect) {
        const auto pair = ui.selectedPipe ? *ui.selectedPipe : std::pair(ids[0], ids[1]);
        s.execute(makeRemovePipeCommand(*s.document, body, pair.first, pair.second));
    }
    ImGui::SameLine();
    const bool toggle = ImGui::Button("Open/Close");
    tooltip("Opens a closed pipe or closes an open one.");
    if (toggle) {
        const auto pair = ui.selectedPipe ? *ui.selectedPipe : std::pair(ids[0], ids[1]);
        PipeEdit e;
        e.open = !g->pipes[findPipe(*g, pair.first, pair.second)].open;
        s.execute(makeSetPipeCommand(*s.document, body, pair.first, pair.second, e));
    }
    ImGui::EndDisabled();
}

/// The graph's totals, its problems, the list of nodes and pipes (click to select), the
/// schematic and the inspector of what is selected.
void drawGraphContents(EditorState& s, GraphUi& ui, std::size_t body, const WaterGraph& graph) {
    const WaterGraph* g = &graph;
    ImGui::Separator();
    ImGui::TextWrapped("%zu nodes, %zu pipes, capacity %.4g m^3, water %.4g m^3", g->nodes.size(),
                       g->pipes.size(), g->totalCapacity(), g->totalWater());
    const GraphReport report = validateGraph(*g, s.document->assets(body).mesh.get());
    // Wrapped: a problem names its node and says why, longer than the panel is wide.
    ImGui::PushTextWrapPos(0.0f);
    for (const GraphProblem& p : report.problems) {
        ImGui::TextColored(p.error ? ImVec4(1, 0.4f, 0.4f, 1) : ImVec4(1, 0.8f, 0.3f, 1), "%s",
                           p.message.c_str());
    }
    ImGui::PopTextWrapPos();
    if (ImGui::BeginListBox("##nodes", ImVec2(-1, 110))) {
        for (std::size_t i = 0; i < g->nodes.size(); ++i) {
            const GraphNode& n = g->nodes[i];
            const Eigen::Vector3f c = nodeColour(i);
            ImGui::ColorButton(("##c" + n.id).c_str(), ImVec4(c.x(), c.y(), c.z(), 1),
                               ImGuiColorEditFlags_NoTooltip, ImVec2(12, 12));
            ImGui::SameLine();
            const std::string label = n.id + (n.name.empty() ? "" : "  " + n.name);
            if (ImGui::Selectable(label.c_str(), ui.selected.count(n.id) > 0)) {
                if (!ImGui::GetIO().KeyShift && !ImGui::GetIO().KeyCtrl) ui.selected.clear();
                if (!ui.selected.insert(n.id).second) ui.selected.erase(n.id);
                ui.selectedPipe.reset();
            }
        }
        for (const GraphPipe& p : g->pipes) {
            const std::string label = "pipe " + p.a + " - " + p.b + (p.open ? "" : " (closed)");
            if (ImGui::Selectable(label.c_str(), ui.selectedPipe == std::pair(p.a, p.b))) {
                ui.selectedPipe = {p.a, p.b};
                ui.selected.clear();
            }
        }
        ImGui::EndListBox();
    }
    if (ImGui::CollapsingHeader("Schematic (side view)", ImGuiTreeNodeFlags_DefaultOpen)) {
        drawSchematic(s, ui, body, *g);
    }
    if (ui.selected.size() == 1) {
        nodeInspector(s, g->nodes[g->indexOf(*ui.selected.begin())]);
    } else if (ui.selected.size() > 1) {
        nodesInspector(s, *g, ui.selected);
    } else if (ui.selectedPipe) {
        pipeInspector(s, *g,
                      g->pipes[findPipe(*g, ui.selectedPipe->first, ui.selectedPipe->second)]);
    }
}

/// Auto-generate: segments the mesh on a worker, previews the graph, applies it as one step.
void drawGraphAutoGenerate(EditorState& s, GraphUi& ui) {
    ImGui::Separator();
    ImGui::TextUnformatted("Auto-generate (paper 4.1: SDF segments)");
    ImGui::InputInt("segments", &ui.segments);
    tooltip("How many compartments the shape diameter function splits the body into (1 to 64).");
    ui.segments = std::clamp(ui.segments, 1, 64);
    if (ui.job) {
        ImGui::ProgressBar(static_cast<float>(*ui.job->progress), ImVec2(-1, 0), "segmenting...");
    } else {
        if (ImGui::Button("Preview")) startAutoGenerate(s);
        tooltip(
            "Segments the mesh on a worker and shows the graph it would make; nothing changes "
            "yet.");
        if (ui.preview) {
            ImGui::SameLine();
            const bool apply = ImGui::Button("Apply");
            tooltip("Replaces the body's water graph with the previewed one (one undo step).");
            if (apply) {
                if (s.execute(makeReplaceGraphCommand(*s.document, ui.preview->body,
                                                      ui.preview->graph,
                                                      "Auto-generate water graph"))) {
                    ui.preview.reset();
                    ui.selected.clear();
                }
            }
            ImGui::SameLine();
            if (ImGui::Button("Cancel")) ui.preview.reset();
            tooltip("Drops the preview; the graph stays as it was.");
            if (ui.preview) {
                ImGui::Text("preview: %zu nodes, %zu pipes from %d segments (%.1f s)",
                            ui.preview->graph.nodes.size(), ui.preview->graph.pipes.size(),
                            ui.preview->segments, ui.preview->seconds);
            }
        }
    }
    if (!ui.autoError.empty())
        ImGui::TextColored(ImVec4(1, 0.4f, 0.4f, 1), "%s", ui.autoError.c_str());
}

}  // namespace

void drawGraphPanel(EditorState& s) {
    GraphUi& ui = uiOf(s);
    pollAutoGenerate(ui);
    const std::size_t body = bodyOf(s);
    const WaterGraph* g = graphOf(s);
    pruneSelection(ui, g);
    const ImVec2 display = ImGui::GetIO().DisplaySize;
    ImGui::SetNextWindowPos(ImVec2(display.x * 0.02f, display.y * 0.08f), ImGuiCond_FirstUseEver);
    // Wide enough for the schematic of a four-compartment hull with its whole names.
    ImGui::SetNextWindowSize(ImVec2(460, 560), ImGuiCond_FirstUseEver);
    // Collapsed at first: a title bar over the view's corner until someone opens it.
    ImGui::SetNextWindowCollapsed(true, ImGuiCond_FirstUseEver);
    ui.panelOpen = ImGui::Begin("Water graph");
    openWhenTitleClicked();
    if (!ui.panelOpen) {
        ImGui::End();
        return;
    }
    if (!s.document || body >= s.document->bodyCount()) {
        ImGui::TextUnformatted("No body selected.");
        ImGui::End();
        return;
    }
    ImGui::Text("Body %zu: %s", body, s.document->project().bodies[body].name.c_str());
    if (!s.document->project().bodies[body].waterGraph) {
        ImGui::TextWrapped("This body has no water graph: it is sealed.");
        if (ImGui::Button("Create water graph"))
            s.execute(makeCreateGraphCommand(*s.document, body));
        tooltip(
            "Gives the body an empty water graph: add nodes by hand or auto-generate them below.");
        ImGui::End();
        return;
    }
    if (!g) {
        ImGui::TextWrapped("Graph not loaded: %s", s.document->assets(body).graph.error.c_str());
        ImGui::End();
        return;
    }
    drawGraphViewOptions(ui);
    drawGraphEditButtons(s, ui, body, *g);
    g = graphOf(s);  // the buttons may have changed it
    pruneSelection(ui, g);
    if (!g) {
        ImGui::End();
        return;
    }
    drawGraphContents(s, ui, body, *g);
    drawGraphAutoGenerate(s, ui);
    ImGui::End();
}

bool graphEditsInView(EditorState& s) {
    GraphUi& ui = uiOf(s);
    return ui.panelOpen && ui.editInView && ui.showGraph && graphOf(s) != nullptr;
}

bool graphViewportInput(EditorState& s) {
    GraphUi& ui = uiOf(s);
    if (!graphEditsInView(s)) return false;
    const WaterGraph* g = graphOf(s);
    ImGuiIO& io = ImGui::GetIO();
    const ImVec2 mouse = io.MousePos;
    ui.mouseAt = mouse;
    const bool hovered = s.viewport.contains(mouse.x, mouse.y) && !io.WantCaptureMouse;
    const Pose pose = s.document->bodyPose(bodyOf(s));
    if (hovered && ImGui::IsKeyPressed(GLFW_KEY_DELETE, false) && !ui.selected.empty()) {
        s.execute(makeDeleteNodesCommand(*s.document, bodyOf(s), selectedIds(ui, *g)));
        return true;
    }
    if (hovered && ImGui::IsMouseClicked(0)) {
        Eigen::Vector3d o, d;
        ray(s, mouse, o, d);
        const auto node = pickNode(*g, pose, o, d);
        const double tolerance = s.camera.distance * 0.01;
        const auto pipeHit = pickPipe(*g, pose, o, d, tolerance);
        ui.pressAt = mouse;
        if (node && (!pipeHit || node->distance <= pipeHit->distance)) {
            const std::string& id = g->nodes[node->index].id;
            if (io.KeyShift) {
                if (!ui.selected.insert(id).second) ui.selected.erase(id);
            } else if (!ui.selected.count(id)) {
                ui.selected = {id};
            }
            ui.selectedPipe.reset();
            if (ui.selected.count(id)) {
                ui.dragging = true;
                ui.anchor = pose.apply(g->nodes[node->index].position);
                ui.dragOffset.setZero();
            }
        } else if (pipeHit) {
            ui.selectedPipe = {g->pipes[pipeHit->index].a, g->pipes[pipeHit->index].b};
            ui.selected.clear();
        } else {
            if (!io.KeyShift) ui.selected.clear();
            ui.selectedPipe.reset();
            ui.boxSelecting = true;
        }
        return true;
    }
    if (ui.dragging) {
        if (ImGui::IsMouseDown(0)) {
            if (auto target = dragTarget(s, mouse)) ui.dragOffset = *target - ui.anchor;
        } else {
            ui.dragging = false;
            // Object-space offset: the drag was in world space.
            const Eigen::Vector3d offset = pose.rotation.transpose() * ui.dragOffset;
            if (offset.norm() > 1e-9) {
                s.execute(
                    makeMoveNodesCommand(*s.document, bodyOf(s), selectedIds(ui, *g), offset));
            }
            ui.dragOffset.setZero();
        }
        return true;
    }
    if (ui.boxSelecting) {
        if (!ImGui::IsMouseDown(0)) {
            ui.boxSelecting = false;
            const auto inside =
                nodesInRect(*g, pose, s.camera, int(s.viewport.w), int(s.viewport.h),
                            ui.pressAt.x - s.viewport.x, ui.pressAt.y - s.viewport.y,
                            mouse.x - s.viewport.x, mouse.y - s.viewport.y);
            for (std::size_t i : inside) ui.selected.insert(g->nodes[i].id);
        }
        return true;
    }
    return false;
}

void drawGraphOverlay(EditorState& s) {
    GraphUi& ui = uiOf(s);
    ImDrawList* draw = ImGui::GetBackgroundDrawList();
    if (ui.boxSelecting) {
        draw->AddRectFilled(ui.pressAt, ui.mouseAt, IM_COL32(120, 170, 255, 40));
        draw->AddRect(ui.pressAt, ui.mouseAt, IM_COL32(120, 170, 255, 200));
    }
    if (ui.dragging) {
        const char* axis = ImGui::IsKeyDown(GLFW_KEY_X)   ? "  along X"
                           : ImGui::IsKeyDown(GLFW_KEY_Y) ? "  along Y"
                           : ImGui::IsKeyDown(GLFW_KEY_Z) ? "  along Z"
                                                          : "";
        char line[160];
        std::snprintf(line, sizeof line, "move %.3f %.3f %.3f m%s", ui.dragOffset.x(),
                      ui.dragOffset.y(), ui.dragOffset.z(), axis);
        draw->AddText(ImVec2(s.viewport.x + 8, s.viewport.y + 24), IM_COL32(255, 255, 160, 255),
                      line);
    }
}

void addGraphToScene(EditorState& s, RenderScene& scene) {
    GraphUi& ui = uiOf(s);
    ui.drawn.clear();
    const std::size_t body = bodyOf(s);
    const WaterGraph* g = graphOf(s);
    // The graph (and the see-through hull it needs) only while its panel is open: collapsed,
    // the boxes would hide the hull and its overlays for no purpose.
    if (!ui.showGraph || !ui.panelOpen || body >= scene.bodies.size()) return;
    if (!ui.drawer) {
        Result<std::unique_ptr<GraphDrawer>> made = GraphDrawer::create();
        if (!made) {
            s.status = made.error().message;
            ui.showGraph = false;
            return;
        }
        ui.drawer = std::move(made).value();
    }
    updateOverlay(s);
    if (s.renderer->overlayTexture(kGraphOverlaySlot))
        scene.bodies[body].overlay = kGraphOverlaySlot;
    const bool previewing = ui.preview && ui.preview->body == body;
    if (!g && !previewing) return;
    RenderGraph r;
    r.pose = s.document->bodyPose(body);
    if (previewing) {
        r.graph = &ui.preview->graph;
    } else if (ui.dragging) {
        ui.dragged = *g;
        const Eigen::Vector3d offset = r.pose.rotation.transpose() * ui.dragOffset;
        for (GraphNode& n : ui.dragged.nodes) {
            if (ui.selected.count(n.id)) n.position += offset;
        }
        r.graph = &ui.dragged;
    } else {
        r.graph = g;
    }
    if (!previewing) {
        for (const GraphNode& n : r.graph->nodes)
            r.selectedNodes.push_back(ui.selected.count(n.id) > 0);
        if (ui.selectedPipe)
            r.selectedPipe = findPipe(*r.graph, ui.selectedPipe->first, ui.selectedPipe->second);
    }
    // While the live preview runs, the graph rides with the simulated body and shows the
    // simulation's water in each node.
    if (s.preview && s.preview->session && !previewing) {
        const World& world = s.preview->session->world();
        if (body < world.bodies().size()) {
            r.pose = world.bodies()[body].pose();
            const WaterGraphSimulation* sim = world.waterGraph(body);
            if (sim && sim->graph().nodes.size() == r.graph->nodes.size()) {
                for (const GraphNode& n : sim->graph().nodes) r.water.push_back(n.water);
            }
        }
    }
    ui.drawn.push_back(std::move(r));
    scene.bodies[body].alpha = ui.hullAlpha;
    const Camera camera = s.camera;
    scene.drawInside = [camera, graph = s.graphUi](const Eigen::Matrix4f& viewProj) {
        for (const RenderGraph& drawn : graph->drawn) graph->drawer->draw(drawn, viewProj, camera);
    };
}

std::shared_ptr<GraphUi> makeGraphUi() { return std::make_shared<GraphUi>(); }

bool graphPanelBusy(const EditorState& s) {
    const GraphUi& ui = uiOf(s);
    return ui.job.has_value() || ui.dragging;
}

void releaseGraphPanel(EditorState& s) {
    GraphUi& ui = uiOf(s);
    if (ui.job) ui.job->result.wait();
    ui.job.reset();
    ui.drawer.reset();
}

}  // namespace plimsoll::editor
