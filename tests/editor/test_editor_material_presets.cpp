// Material presets (document/material_presets.h): the table's densities against the handbook
// ranges, a preset applied to a solid, a shell and both as one undo step whose undo gives the
// previous material back exactly, and the same from an edit script.
#include "test_support.h"
#include "editor/document_test_support.h"

#include "document/command.h"
#include "document/document.h"
#include "document/material_presets.h"
#include "document/script.h"

#include <gtest/gtest.h>

#include <fstream>
#include <set>

namespace plimsoll::editor {
namespace test_editor_material_presets {
namespace {

namespace fs = std::filesystem;
using test::executeOrFail;
using test::openOrFail;

/// A project with the unit sphere of `material` (JSON) in a fresh folder.
fs::path sphereProject(const std::string& name, const std::string& material) {
    const fs::path dir = test::freshFolder("editor_material_presets", name);
    const fs::path path = dir / "presets.plim.json";
    std::ofstream(path)
        << R"({"schema_version": 1, "name": "t", "bodies": [{"name": "ball", "mesh": ")"
        << test::assetPath("sphere.obj").string() << R"(", "material": )" << material << "}]}";
    return path;
}

const MaterialPreset& presetOrFail(std::string_view name) {
    const MaterialPreset* preset = findMaterialPreset(name);
    EXPECT_TRUE(preset) << name;
    static const MaterialPreset none{"", "", 1.0, 1.0};
    return preset ? *preset : none;
}

TEST(EditorMaterialPresets, TableHoldsTheHandbookDensities) {
    EXPECT_EQ(presetOrFail("steel").density, 7850.0);
    EXPECT_EQ(presetOrFail("aluminium").density, 2700.0);
    EXPECT_EQ(presetOrFail("concrete").density, 2400.0);
    const double wood = presetOrFail("wood").density;
    EXPECT_TRUE(wood >= 500 && wood <= 700) << wood;
    const double foam = presetOrFail("foam").density;
    EXPECT_TRUE(foam >= 30 && foam <= 100) << foam;
    const double hdpe = presetOrFail("Plastic (HDPE)").density;
    EXPECT_TRUE(hdpe >= 941 && hdpe <= 965) << hdpe;
    // Keys and names are found whatever their case; unknown names are not.
    EXPECT_EQ(findMaterialPreset("STEEL"), findMaterialPreset("Steel"));
    EXPECT_EQ(findMaterialPreset("plastic (hdpe)"), findMaterialPreset("hdpe"));
    EXPECT_EQ(findMaterialPreset("unobtainium"), nullptr);
    std::set<std::string_view> keys;
    for (const MaterialPreset& p : materialPresets()) {
        EXPECT_TRUE(keys.insert(p.key).second) << p.key;
        EXPECT_TRUE(p.shellThickness > 0 && p.shellThickness <= 0.2)
            << p.name << " " << p.shellThickness;
    }
    EXPECT_EQ(keys.size(), 6u);
}

TEST(EditorMaterialPresets, PresetIsOneStepAndOneUndoRestoresTheMaterialExactly) {
    // A solid with a shell: both parts take the preset (the shell as density x thickness).
    auto d = openOrFail(
        sphereProject("both", R"({"density": 512.25, "shell": {"surface_density": 10.125}})"));
    ASSERT_TRUE(d);
    const Project before = d->project();
    const std::string beforeJson = projectToJson(before);
    EXPECT_EQ(matchingMaterialPreset(before.bodies[0].material), nullptr);
    const MaterialPreset& steel = presetOrFail("steel");
    executeOrFail(*d, makeApplyMaterialPresetCommand(*d, 0, steel));
    EXPECT_EQ(d->historyPosition(), 1u);
    EXPECT_EQ(d->undoName(), "Set ball material to Steel");
    const MaterialDesc& applied = d->project().bodies[0].material;
    EXPECT_EQ(applied.density, 7850.0);
    EXPECT_EQ(applied.shellSurfaceDensity, 7850.0 * steel.shellThickness);
    EXPECT_EQ(matchingMaterialPreset(applied), &steel);
    // Applying it again would be a step that changes nothing.
    Result<std::unique_ptr<Command>> again = makeApplyMaterialPresetCommand(*d, 0, steel);
    ASSERT_FALSE(again.ok());
    EXPECT_NE(again.error().message.find("already"), std::string::npos) << again.error().message;

    ASSERT_TRUE(d->undo());
    EXPECT_TRUE(d->project() == before);
    EXPECT_EQ(d->project().bodies[0].material.density, 512.25);
    EXPECT_EQ(d->project().bodies[0].material.shellSurfaceDensity, 10.125);
    EXPECT_EQ(projectToJson(d->project()), beforeJson);
    ASSERT_TRUE(d->redo());
    EXPECT_EQ(d->project().bodies[0].material.density, 7850.0);

    // Saved and reopened, the body still reads as the preset.
    ASSERT_TRUE(d->save().ok());
    auto reopened = openOrFail(d->path());
    ASSERT_TRUE(reopened);
    EXPECT_EQ(matchingMaterialPreset(reopened->project().bodies[0].material), &steel);
}

TEST(EditorMaterialPresets, PresetSetsOnlyThePartsTheBodyHas) {
    auto solid = openOrFail(sphereProject("solid", R"({"density": 500})"));
    ASSERT_TRUE(solid);
    executeOrFail(*solid, makeApplyMaterialPresetCommand(*solid, 0, presetOrFail("foam")));
    EXPECT_EQ(solid->project().bodies[0].material.density, presetOrFail("foam").density);
    EXPECT_FALSE(solid->project().bodies[0].material.shellSurfaceDensity) << "no shell is added";

    auto shell = openOrFail(
        sphereProject("shell", R"({"shell": {"thickness": 0.01, "material_density": 1200}})"));
    ASSERT_TRUE(shell);
    const MaterialPreset& alu = presetOrFail("aluminium");
    executeOrFail(*shell, makeApplyMaterialPresetCommand(*shell, 0, alu));
    EXPECT_FALSE(shell->project().bodies[0].material.density) << "no solid is added";
    EXPECT_EQ(shell->project().bodies[0].material.shellSurfaceDensity, 2700.0 * alu.shellThickness);
    EXPECT_FALSE(makeApplyMaterialPresetCommand(*shell, 3, alu).ok()) << "no body 3";
}

TEST(EditorMaterialPresets, EditScriptAppliesAPresetByName) {
    auto d = openOrFail(sphereProject("script", R"({"density": 500})"));
    ASSERT_TRUE(d);
    Result<nlohmann::json> ran = runEditScript(*d, nlohmann::json::parse(R"json([
        {"op": "apply_material_preset", "preset": "concrete"},
        {"op": "apply_material_preset", "preset": "Plastic (HDPE)"},
        {"op": "undo"}
    ])json"));
    ASSERT_TRUE(ran.ok()) << ran.error().message;
    EXPECT_EQ((*ran)[0]["name"], "Set ball material to Concrete");
    EXPECT_EQ(d->project().bodies[0].material.density, 2400.0);

    Result<nlohmann::json> unknown = runEditScript(
        *d, nlohmann::json::parse(R"([{"op": "apply_material_preset", "preset": "balsa"}])"));
    ASSERT_FALSE(unknown.ok());
    // The message lists the presets there are.
    EXPECT_NE(unknown.error().message.find("wood, steel"), std::string::npos)
        << unknown.error().message;
    EXPECT_NE(unknown.error().message.find("balsa"), std::string::npos);
}

}  // namespace
}  // namespace test_editor_material_presets
}  // namespace plimsoll::editor
