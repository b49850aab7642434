// The inspector: the project and the selected body — mesh validation, texture size and covered
// texels, material fields (edited through commands), maps, and mass properties from the
// textures against the exact ones (worked out on a worker thread after each edit).
#include "app/panels.h"

#include "document/command.h"
#include "document/material_presets.h"

#include "plimsoll/physics/massprops.h"
#include "plimsoll/project/project.h"
#include "plimsoll/surface/painted_map.h"
#include "plimsoll/geometry/validate.h"
#include "plimsoll/project/scene_loader.h"
#include "plimsoll/repair/physics_solid.h"
#include "plimsoll/scene/scene.h"

#include <GLFW/glfw3.h>
#include <imgui.h>
#include <nlohmann/json.hpp>

#include <atomic>
#include <cmath>
#include <cstdio>
#include <functional>
#include <map>
#include <memory>
#include <thread>
#include <vector>

namespace plimsoll::editor {

namespace {

/// What the inspector shows of a body's textures and mass: sums over every texel entry (about
/// a million at 1024^2, with the painted shell maps sampled at each), so they are worked out on
/// a worker, never in a frame (the frame a new texture size arrived in took 51 ms here).
struct TextureFigures {
    std::size_t covered = 0, distinct = 0;
    int size = 0;
    std::optional<MassProperties> texture, exact;
    bool exactApplies = true;  ///< false with a painted shell (no exact reference)
};

/// The figures of `textures` for `material`; `shellMaps`: the painted density and thickness
/// maps that scale the shell (copies: the document may change them meanwhile).
TextureFigures figuresOf(const SurfaceTextures& t, const TriangleMesh& mesh,
                         const MaterialDesc& material, const std::vector<PaintedMap>& shellMaps) {
    TextureFigures f;
    f.size = t.size;
    f.covered = t.coveredCount();
    f.distinct = t.distinctTexelCount();
    MassProperties texture, exact;
    bool any = false;
    if (material.density) {
        texture = textureSolidMassProperties(t, *material.density);
        exact = exactSolidMassProperties(mesh, *material.density);
        any = true;
    }
    if (material.shellSurfaceDensity) {
        std::vector<double> sigma;
        for (const PaintedMap& map : shellMaps) {
            const std::vector<double> scaled = sampleAtTexels(map, t, 1.0);
            if (sigma.empty()) sigma.assign(scaled.size(), *material.shellSurfaceDensity);
            for (std::size_t i = 0; i < sigma.size(); ++i) sigma[i] *= scaled[i];
            f.exactApplies = false;
        }
        const MassProperties shellT =
            textureShellMassProperties(t, *material.shellSurfaceDensity, sigma);
        const MassProperties shellE = exactShellMassProperties(mesh, *material.shellSurfaceDensity);
        texture = any ? texture + shellT : shellT;
        exact = any ? exact + shellE : shellE;
        any = true;
    }
    if (any) {
        f.texture = texture;
        f.exact = exact;
    }
    return f;
}

/// The figures of a body simulated as its physics solid (an open hull, a repaired mesh): the
/// solid baked and weighed as a project run does (assembleBodyParts, bakeSceneBody: the walls
/// only, the caps no shell), against the exact integrals over that solid less the space behind
/// its caps, and a shell on its faces other than the caps.
TextureFigures figuresOfSolid(const PreparedBodyMesh& prepared,
                              const std::shared_ptr<const TriangleMesh>& artist, BodyDesc desc,
                              const std::vector<PaintedMap>& shellMaps) {
    TextureFigures f;
    BodyPaint paint;
    paint.paintedOver = artist;
    if (!shellMaps.empty()) {
        paint.shellDensityMap = std::make_shared<const PaintedMap>(shellMaps[0]);
        f.exactApplies = false;
    }
    if (shellMaps.size() > 1)
        paint.shellThicknessMap = std::make_shared<const PaintedMap>(shellMaps[1]);
    desc.waterGraph
        .reset();  // the mass does not depend on it, and the graph's file is not read here
    Result<BodyParts> parts = assembleBodyParts(desc, prepared, paint);
    if (!parts) return f;
    desc.waterGraph.reset();
    parts->waterGraph.reset();
    desc.lod.reset();
    Result<SceneBody> body = bakeSceneBody(desc, std::move(*parts));
    if (!body) return f;
    const SurfaceTextures& t = *body->textures;
    f.size = t.size;
    f.covered = t.coveredCount();
    f.distinct = t.distinctTexelCount();
    f.texture = *body->mass;
    MassProperties exact;
    bool any = false;
    const MaterialDesc& material = desc.material;
    if (material.density) {
        exact = withoutHollow(exactSolidMassProperties(prepared.mesh, *material.density),
                              hollowSpace(prepared.openings), *material.density);
        any = true;
    }
    if (material.shellSurfaceDensity) {
        TriangleMesh walls = prepared.mesh;
        std::vector<char> cap(walls.triangles.size(), 0);
        for (const Opening& o : prepared.openings)
            for (std::uint32_t k : o.capTriangles) cap[k] = 1;
        walls.triangles.clear();
        for (std::size_t k = 0; k < cap.size(); ++k)
            if (!cap[k]) walls.triangles.push_back(prepared.mesh.triangles[k]);
        const MassProperties shell = exactShellMassProperties(walls, *material.shellSurfaceDensity);
        exact = any ? exact + shell : shell;
    }
    f.exact = exact;
    return f;
}

/// One computation of the figures on a worker thread of its own (detached: it owns what it
/// reads, and a result nobody waits for any more is simply dropped).
struct FiguresJob {
    std::atomic<bool> done{false};
    TextureFigures figures;
};

struct BodyInfo {
    std::uint64_t revision = ~std::uint64_t{0};
    const TriangleMesh* mesh = nullptr;
    std::vector<std::string> warnings;
    std::string bakeError;
    TextureFigures figures;  ///< the last finished ones (kept while newer ones run)
    bool hasFigures = false;
    std::shared_ptr<FiguresJob> job;  ///< the newest computation, until it finishes
    bool ofSolid = false;             ///< the figures are of the physics solid, not the mesh
};
}  // namespace

/// What the inspector keeps between frames (EditorState::inspector).
struct InspectorCache {
    std::map<std::size_t, BodyInfo> infos;  ///< per body, recomputed on edits
    std::map<std::string, double> editing;  ///< number fields being typed into
    /// Edits made in the last frame's panel, run at the start of the next one: an edit
    /// replaces the project's bodies, and the panel goes on reading the body it drew from
    /// (a reference into them) after the field that made it.
    std::vector<std::function<void()>> deferred;
};

std::shared_ptr<InspectorCache> makeInspectorCache() { return std::make_shared<InspectorCache>(); }

namespace {

BodyInfo& infoFor(EditorState& s, std::size_t b) {
    BodyInfo& info = s.inspector->infos[b];
    if (info.job && info.job->done.load(std::memory_order_acquire)) {
        info.figures = std::move(info.job->figures);
        info.hasFigures = true;
        info.job.reset();
    }
    const auto& mesh = s.document->assets(b).mesh;
    if (info.revision == s.documentRevision && info.mesh == mesh.get()) return info;
    const bool meshChanged = info.mesh != mesh.get();
    info.revision = s.documentRevision;
    info.mesh = mesh.get();
    if (!mesh) return info;
    if (meshChanged) {
        info.warnings.clear();
        const ValidationReport report = validateMesh(*mesh);
        for (const Problem& p : report.problems) {
            info.warnings.push_back(
                std::string(p.severity == Severity::Error ? "error: " : "warning: ") + p.message);
        }
    }
    const BodyDesc& body = s.document->project().bodies[b];
    // Baked on a worker: during a new size's bake, the old size's figures (the poll that
    // brings the new textures bumps the revision).
    const std::shared_ptr<const SurfaceTextures> textures = s.physicsFor(b);
    info.bakeError = s.physicsBakes->error(b);
    if (!textures) {
        info.hasFigures = false;
        info.job.reset();
        return info;
    }
    std::vector<PaintedMap> shellMaps;
    if (body.material.shellSurfaceDensity) {
        for (MapChannel c : {MapChannel::Density, MapChannel::Thickness})
            if (const PaintedMap* map = s.document->map(b, c)) shellMaps.push_back(*map);
    }
    auto job = std::make_shared<FiguresJob>();
    info.job = job;
    // A body simulated as its physics solid is weighed as the simulation weighs it, once the
    // solid is worked out (physics_solids.h); meanwhile, and for any other body, its mesh.
    const PhysicsSolids::Solid solid = s.physicsSolids->solidFor(*s.document, b);
    std::shared_ptr<const PreparedBodyMesh> prepared =
        solid.prepared && !solid.working && !solid.prepared->repairs.empty() ? solid.prepared
                                                                             : nullptr;
    info.ofSolid = prepared != nullptr;
    std::thread([job, textures, mesh, prepared, desc = body, maps = std::move(shellMaps)] {
        // Below the UI's priority, as the bakes are: at 1024^2 this is tens of ms of one core,
        // started in the frame a new size arrives, beside llvmpipe drawing that frame.
        lowerThisThreadsPriority();
        job->figures = prepared ? figuresOfSolid(*prepared, mesh, desc, maps)
                                : figuresOf(*textures, *mesh, desc.material, maps);
        job->done.store(true, std::memory_order_release);
        glfwPostEmptyEvent();  // an idle frame loop draws the figures
    }).detach();
    return info;
}

/// A number field that edits the project when the edit is done: through `commit`, or a
/// command that sets `pointer`.
void numberField(EditorState& s, const char* label, const std::string& pointer, double current,
                 const char* format, const char* help,
                 const std::function<void(double)>& commit = {}) {
    double& value = s.inspector->editing.try_emplace(pointer, current).first->second;
    if (!ImGui::IsItemActive() && !ImGui::IsAnyItemActive()) value = current;
    ImGui::InputDouble(label, &value, 0, 0, format);
    tooltip(help);
    if (ImGui::IsItemDeactivatedAfterEdit() && value != current) {
        s.inspector->deferred.push_back([&s, pointer, commit, edited = value] {
            if (commit)
                commit(edited);
            else
                s.execute(makeSetPropertyCommand(*s.document, pointer, edited));
        });
    }
}

/// The material presets (material_presets.h): one choice sets the body's solid density and its
/// shell (density x a typical thickness), whichever it has, as one undo step. The combo shows
/// the preset the body matches, or "custom".
void materialPresetCombo(EditorState& s, std::size_t b, const MaterialDesc& material) {
    const MaterialPreset* current = matchingMaterialPreset(material);
    if (ImGui::BeginCombo("Preset", current ? std::string(current->name).c_str() : "custom")) {
        for (const MaterialPreset& p : materialPresets()) {
            char label[160];
            if (material.shellSurfaceDensity) {
                std::snprintf(label, sizeof label, "%s  %g kg/m3, %g mm shell: %.4g kg/m2",
                              std::string(p.name).c_str(), p.density, p.shellThickness * 1000,
                              p.shellSurfaceDensity());
            } else {
                std::snprintf(label, sizeof label, "%s  %g kg/m3", std::string(p.name).c_str(),
                              p.density);
            }
            // Choosing the preset the body has changes nothing: no step in the history.
            if (ImGui::Selectable(label, &p == current) && &p != current) {
                s.inspector->deferred.push_back(
                    [&s, b, &p] { s.execute(makeApplyMaterialPresetCommand(*s.document, b, p)); });
            }
        }
        ImGui::EndCombo();
    }
    tooltip(
        "Typical densities of what floating things are made of (engineering handbook values).\n"
        "A solid body gets the density; a shell gets density x a typical skin thickness.\n"
        "One undo step.");
}

/// The texture size field, and while a new size bakes its progress and Cancel.
void textureSizeField(EditorState& s, std::size_t b, const std::string& base, int current) {
    numberField(
        s, "Texture size", base + "/texture_size", current, "%.0f",
        "Texels per side of the physics textures (32 to the engine's limit). A new size "
        "bakes in the background; the old one stays in use until it is ready.",
        [&s, b](double value) { s.setTextureSize(b, static_cast<int>(std::lround(value))); });
    if (const auto baking = s.physicsBakes->progress(b)) {
        const std::string label = "baking " + std::to_string(baking->size) + "^2";
        ImGui::ProgressBar(static_cast<float>(baking->fraction), ImVec2(-80, 0), label.c_str());
        ImGui::SameLine();
        if (ImGui::Button("Cancel##texture_bake")) s.cancelTextureBake(b);
        tooltip("Stop the bake and keep the size in use.");
        if (baking->previousSize > 0) {
            ImGui::TextDisabled("Figures below at %d^2 until the bake is done",
                                baking->previousSize);
        }
    }
}

/// A size picked from a tolerance instead of a texture size: the switch between the two (one
/// undoable step, the body's JSON with one key for the other), the tolerance, and the size it
/// picks with its measured error once the pick, made off the UI thread, is known.
void textureSizeOrTolerance(EditorState& s, std::size_t b, const std::string& base,
                            const BodyDesc& body) {
    bool fromTolerance = body.tolerance.has_value();
    if (ImGui::Checkbox("Size from a tolerance", &fromTolerance)) {
        s.inspector->deferred.push_back([&s, b, base, fromTolerance] {
            const BodyDesc& now = s.document->project().bodies[b];
            nlohmann::json json =
                nlohmann::json::parse(projectToJson(s.document->project()))["bodies"][b];
            if (fromTolerance) {
                json.erase("texture_size");
                json["tolerance"] = 1e-3;
            } else {
                json.erase("tolerance");
                const std::optional<LevelChoice> choice = s.document->levelChoice(b);
                json["texture_size"] = choice ? choice->size : now.textureSize;
            }
            s.execute(makeSetPropertyCommand(*s.document, base, json));
        });
    }
    tooltip(
        "Instead of a texture size, the largest force error allowed against the exact clip of "
        "the mesh (a share of rho g V over 27 poses): the smallest of 16, 32, ... 1024 texels "
        "within it is baked.");
    if (!body.tolerance) {
        textureSizeField(s, b, base, body.textureSize);
        return;
    }
    numberField(
        s, "Tolerance", base + "/tolerance", *body.tolerance, "%.1e",
        "The largest force error allowed, a share of rho g V (1e-3: a tenth of a percent of "
        "the fully submerged buoyancy).");
    if (const std::optional<LevelChoice> choice = s.document->levelChoice(b)) {
        ImGui::Text("Picks %d^2: force error %.1e, torque error %.1e", choice->size,
                    choice->forceError, choice->torqueError);
        if (!choice->coarser.empty()) {
            ImGui::TextDisabled("%d^2 misses it: force error %.1e", choice->coarser.back().first,
                                choice->coarser.back().second);
        }
    } else if (s.physicsBakes->progress(b)) {
        ImGui::TextDisabled("Picking the size: baking 16, 32, ... and measuring each...");
    }
}

/// Add, duplicate and remove: each one undoable step (command.h).
void bodyButtons(EditorState& s) {
    const std::size_t count = s.document->bodyCount();
    const bool hasBody = s.selectedBody >= 0 && static_cast<std::size_t>(s.selectedBody) < count;
    if (ImGui::Button("Add body...")) {
        s.browser.open(FileBrowser::Purpose::ImportMesh, s.document->project().folder);
    }
    tooltip("Adds a body on a mesh file you choose (as File > Import Mesh); Ctrl+Z takes it out.");
    ImGui::SameLine();
    ImGui::BeginDisabled(!hasBody);
    if (ImGui::Button("Duplicate") && hasBody) {
        if (s.execute(makeDuplicateBodyCommand(*s.document, s.selectedBody))) ++s.selectedBody;
    }
    tooltip(hasBody ? "A copy of the selected body beside it (its maps and water graph are not "
                      "copied: a file is painted by one body only)."
                    : "Select a body to duplicate.");
    ImGui::SameLine();
    if (ImGui::Button("Remove") && hasBody) {
        if (s.execute(makeRemoveBodyCommand(*s.document, s.selectedBody))) {
            s.selectedBody =
                std::min(s.selectedBody, static_cast<int>(s.document->bodyCount()) - 1);
        }
    }
    tooltip(hasBody ? "Takes the selected body out of the project (Ctrl+Z brings it back, unsaved "
                      "paint and all)."
                    : "Select a body to remove.");
    ImGui::EndDisabled();
}

/// The body's starting position and rotation: three numbers each, one undo step when a field
/// is left after an edit.
void transformFields(EditorState& s, std::size_t b, const BodyDesc& body) {
    const std::string base = "/bodies/" + std::to_string(b);
    auto field = [&](const char* label, const std::string& key, const Eigen::Vector3d& current,
                     const char* format, const char* help) -> std::optional<Eigen::Vector3d> {
        double values[3];
        for (int k = 0; k < 3; ++k) {
            double& v = s.inspector->editing.try_emplace(key + "/" + std::to_string(k), current[k])
                            .first->second;
            if (!ImGui::IsAnyItemActive()) v = current[k];
            values[k] = v;
        }
        ImGui::InputScalarN(label, ImGuiDataType_Double, values, 3, nullptr, nullptr, format);
        tooltip(help);
        for (int k = 0; k < 3; ++k) s.inspector->editing[key + "/" + std::to_string(k)] = values[k];
        const Eigen::Vector3d edited(values[0], values[1], values[2]);
        if (ImGui::IsItemDeactivatedAfterEdit() && edited != current) return edited;
        return std::nullopt;
    };
    if (auto p = field("Position (m)", base + "/position", body.position, "%.4g",
                       "Where the body starts: x, y (up), z in metres.")) {
        // The command replaces the project: `body` is not read after it.
        s.execute(makeSetBodyTransformCommand(*s.document, b, *p, body.rotationDegrees));
        return;
    }
    if (auto r = field("Rotation (deg)", base + "/rotation_deg", body.rotationDegrees, "%.4g",
                       "The body's starting turn about x, y and z, degrees (turned about x first, "
                       "then y, then z).")) {
        s.execute(makeSetBodyTransformCommand(*s.document, b, body.position, *r));
    }
}

/// Each opening's cap (physics_solids.h works them out): where it is, how much it closes off,
/// and its height and mode, each change one undo step (makeSetCapCommand).
void capsSection(EditorState& s, std::size_t b, const BodyDesc& body) {
    const PhysicsSolids::Solid solid = s.physicsSolids->solidFor(*s.document, b);
    if (solid.working) ImGui::TextDisabled("Caps: working out the physics solid...");
    if (!solid.error.empty()) {
        ImGui::PushStyleColor(ImGuiCol_Text, ImVec4(1, 0.4f, 0.4f, 1));
        ImGui::TextWrapped("%s", solid.error.c_str());
        ImGui::PopStyleColor();
    }
    if (!solid.prepared) return;
    const std::vector<Opening>& openings = solid.prepared->openings;
    if (openings.empty()) {
        ImGui::TextDisabled("No openings: the mesh holds no water poured in from above");
        return;
    }
    for (std::size_t i = 0; i < openings.size(); ++i) {
        const Opening& o = openings[i];
        const CapDesc cap = i < body.caps.size() ? body.caps[i] : CapDesc{};
        ImGui::PushID(static_cast<int>(i));
        ImGui::Text("Cap %zu: area %.4g m2, %.4g m3 behind it%s", i + 1, o.capArea, o.cavity.volume,
                    body.capMode(i) == OpeningsMode::Open ? " (its compartment's capacity)" : "");
        // The height: dragged between the bottom of the space and the rim, set when let go.
        const std::string key =
            "/bodies/" + std::to_string(b) + "/caps/" + std::to_string(i) + "/height";
        double& height = s.inspector->editing.try_emplace(key, o.capHeight).first->second;
        if (!ImGui::IsAnyItemActive()) height = o.capHeight;
        const double low = o.bottomHeight + 1e-3 * (o.rimHeight - o.bottomHeight),
                     high = o.rimHeight;
        ImGui::DragScalar("Height (m)", ImGuiDataType_Double, &height, 0.001f * float(high - low),
                          &low, &high, "%.4f", ImGuiSliderFlags_AlwaysClamp);
        tooltip(
            "Object-space y of the level cap, between the bottom of the space behind it and the "
            "lowest point "
            "of its rim. Lower, it closes off less. One undo step when let go.");
        if (ImGui::IsItemDeactivatedAfterEdit() && height != o.capHeight) {
            CapDesc moved = cap;
            moved.height = height;
            s.inspector->deferred.push_back(
                [&s, b, i, moved] { s.execute(makeSetCapCommand(*s.document, b, i, moved)); });
        }
        int mode = body.capMode(i) == OpeningsMode::Sealed ? 1 : 0;
        if (ImGui::Combo("Mode", &mode, "open (lets water in)\0sealed (a deck)\0")) {
            CapDesc changed = cap;
            changed.mode = mode == 1 ? OpeningsMode::Sealed : OpeningsMode::Open;
            s.inspector->deferred.push_back(
                [&s, b, i, changed] { s.execute(makeSetCapCommand(*s.document, b, i, changed)); });
        }
        tooltip(
            "Open: water gets in through the cap into the compartment behind it. Sealed: none does "
            "(a deck).");
        ImGui::PopID();
    }
}

/// The body's material: preset, density, shell, drag, openings and caps, and its maps.
void materialSection(EditorState& s, std::size_t b, const std::string& base, const BodyDesc& body,
                     const BodyAssets& assets) {
    materialPresetCombo(s, b, body.material);
    if (body.material.density) {
        numberField(s, "Density (kg/m3)", base + "/material/density", *body.material.density,
                    "%.4g", "Mass per volume of the solid body.");
    }
    if (body.material.shellSurfaceDensity) {
        numberField(s, "Shell (kg/m2)", base + "/material/shell/surface_density",
                    *body.material.shellSurfaceDensity, "%.4g",
                    "Mass per area of the hull's skin (scaled by the density and thickness maps).");
    } else {
        const bool add = ImGui::Button("Add shell (1 kg/m2)");
        tooltip(
            "Give the body a hull skin of 1 kg/m2: its density and thickness maps can then be "
            "painted");
        if (add) {
            s.inspector->deferred.push_back([&s, base] {
                s.execute(makeSetPropertyCommand(*s.document, base + "/material/shell",
                                                 nlohmann::json{{"surface_density", 1.0}}));
            });
        }
    }
    numberField(s, "Drag Cd", base + "/drag_coefficient", body.dragCoefficient, "%.4g",
                "Drag coefficient of the wetted surface (dimensionless).");
    // An open hull's or container's openings: capped and flooding, sealed, or left open.
    int openings = static_cast<int>(body.openings);
    if (ImGui::Combo("Openings", &openings,
                     "open (caps let water in)\0sealed (a deck)\0none (as modelled)\0")) {
        const char* name = openingsModeName(static_cast<OpeningsMode>(openings));
        s.inspector->deferred.push_back([&s, base, name] {
            s.execute(
                makeSetPropertyCommand(*s.document, base + "/openings", nlohmann::json(name)));
        });
    }
    tooltip(
        "What becomes of the openings of an open hull or container (space that holds water "
        "poured in "
        "from above), for caps not set below: a level cap at the rim's lowest point that lets "
        "water into "
        "a compartment behind it, a cap that lets none in, or the surface as it is (floats "
        "swamped)");
    if (body.openings != OpeningsMode::None) capsSection(s, b, body);
    for (MapChannel c : kMapChannels) {
        const std::string& path = channelPath(body, c);
        const PaintedMap* map = s.document->map(b, c);
        if (map) {
            ImGui::Text("%s map: %s (%dx%d%s)", channelName(c), path.c_str(), map->width,
                        map->height, assets.maps[int(c)].dirty ? ", unsaved" : "");
        } else {
            ImGui::TextDisabled("%s map: none", channelName(c));
        }
    }
}

/// The texture's mass properties beside the exact ones.
void massPropertiesSection(const BodyInfo& info) {
    if (!ImGui::CollapsingHeader("Mass properties", ImGuiTreeNodeFlags_DefaultOpen) ||
        !info.hasFigures || !info.figures.texture)
        return;
    const MassProperties& t = *info.figures.texture;
    const MassProperties& e = *info.figures.exact;
    if (info.ofSolid)
        ImGui::TextDisabled(
            "Of the physics solid the simulation uses: walls only, caps and the space behind "
            "them no mass");
    ImGui::Text("Volume  %.6f m3 (exact %.6f, %.2e rel)", t.volume, e.volume,
                std::abs(t.volume - e.volume) / std::max(e.volume, 1e-300));
    ImGui::Text("Mass    %.4f kg", t.mass);
    if (info.figures.exactApplies) {
        ImGui::Text("        exact %.4f kg (%.2e rel)", e.mass,
                    std::abs(t.mass - e.mass) / std::max(e.mass, 1e-300));
    } else {
        ImGui::TextDisabled("        painted shell: no exact reference");
    }
    ImGui::Text("CoM     %.4f %.4f %.4f m", t.centerOfMass.x(), t.centerOfMass.y(),
                t.centerOfMass.z());
    ImGui::Text("        exact %.4f %.4f %.4f (|d| %.2e m)", e.centerOfMass.x(), e.centerOfMass.y(),
                e.centerOfMass.z(), (t.centerOfMass - e.centerOfMass).norm());
    ImGui::Text("Inertia diag %.4g %.4g %.4g kg m2", t.inertia(0, 0), t.inertia(1, 1),
                t.inertia(2, 2));
    ImGui::Text("        rel. difference %.2e",
                (t.inertia - e.inertia).norm() / std::max(e.inertia.norm(), 1e-300));
}

}  // namespace

void drawInspectorPanel(EditorState& s, const Rect& area) {
    // Last frame's edits, before anything below reads the project.
    std::vector<std::function<void()>> edits;
    edits.swap(s.inspector->deferred);
    for (const auto& edit : edits) edit();
    // An undo of an added body can leave the selection past the end: the last body then.
    if (s.selectedBody >= static_cast<int>(s.document->bodyCount())) {
        s.selectedBody = static_cast<int>(s.document->bodyCount()) - 1;
    }
    beginColumnPanel("Inspector", area);
    const Project& project = s.document->project();
    ImGui::Text("Project: %s", project.name.c_str());
    ImGui::Text("Medium: %s, %.1f kg/m3", project.medium.name.c_str(), project.medium.density);
    if (ImGui::BeginListBox("Bodies", ImVec2(-1, 3 * ImGui::GetTextLineHeightWithSpacing()))) {
        for (std::size_t b = 0; b < project.bodies.size(); ++b) {
            const std::string label = project.bodies[b].name.empty() ? "body " + std::to_string(b)
                                                                     : project.bodies[b].name;
            if (ImGui::Selectable((label + "##" + std::to_string(b)).c_str(),
                                  s.selectedBody == static_cast<int>(b))) {
                s.selectedBody = static_cast<int>(b);
            }
            tooltip("Select the body the tools and this panel work on");
        }
        ImGui::EndListBox();
    }
    bodyButtons(s);
    if (s.selectedBody < 0 || static_cast<std::size_t>(s.selectedBody) >= project.bodies.size()) {
        ImGui::TextDisabled("No body. Add body... (or File > Import Mesh) adds one.");
        ImGui::End();
        return;
    }
    const std::size_t b = s.selectedBody;
    // Before `body` below is taken: an edit here replaces the project's bodies.
    transformFields(s, b, project.bodies[b]);
    const BodyDesc& body = project.bodies[b];
    const BodyAssets& assets = s.document->assets(b);
    const std::string base = "/bodies/" + std::to_string(b);
    ImGui::Separator();
    ImGui::TextWrapped("Mesh: %s", body.mesh.c_str());
    if (!assets.mesh) {
        ImGui::TextColored(ImVec4(1, 0.4f, 0.4f, 1), "%s", assets.meshError.c_str());
        ImGui::End();
        return;
    }
    BodyInfo& info = infoFor(s, b);
    ImGui::Text("%zu vertices, %zu triangles", assets.mesh->vertexCount(),
                assets.mesh->triangleCount());
    if (info.warnings.empty()) ImGui::TextColored(ImVec4(0.5f, 0.9f, 0.5f, 1), "Mesh valid");
    // Wrapped: a validation message is a sentence, wider than the panel.
    for (const std::string& w : info.warnings) {
        ImGui::PushStyleColor(ImGuiCol_Text, ImVec4(1, 0.75f, 0.3f, 1));
        ImGui::TextWrapped("%s", w.c_str());
        ImGui::PopStyleColor();
    }
    if (ImGui::CollapsingHeader("Texture", ImGuiTreeNodeFlags_DefaultOpen)) {
        textureSizeOrTolerance(s, b, base, body);
        if (!info.bakeError.empty()) {
            ImGui::PushStyleColor(ImGuiCol_Text, ImVec4(1, 0.4f, 0.4f, 1));
            ImGui::TextWrapped("%s", info.bakeError.c_str());
            ImGui::PopStyleColor();
        }
        const TextureFigures& f = info.figures;
        if (info.hasFigures) {
            ImGui::Text("Covered texels: %zu entries, %zu texels (%.1f%%)%s", f.covered, f.distinct,
                        f.size ? 100.0 * f.distinct / (double(f.size) * f.size) : 0.0,
                        info.job ? " (updating)" : "");
        } else if (info.job) {
            ImGui::TextDisabled("Covered texels: computing...");
        }
    }
    if (ImGui::CollapsingHeader("Material", ImGuiTreeNodeFlags_DefaultOpen))
        materialSection(s, b, base, body, assets);
    massPropertiesSection(info);
    ImGui::End();
}

}  // namespace plimsoll::editor
