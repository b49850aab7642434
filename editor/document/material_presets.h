// Material presets: the densities of the materials floating things are made of, one table for
// the Inspector's preset combo and the edit scripts' `apply_material_preset`. A body's material
// is a solid density, a shell (its surface density, kg/m^2), or both (MaterialDesc); a preset
// sets the parts the body has and leaves its painted maps alone.
#pragma once

#include "document/command.h"

#include "plimsoll/scene/scene_desc.h"

#include <memory>
#include <span>
#include <string_view>

namespace plimsoll::editor {

struct MaterialPreset {
    std::string_view key;   ///< "steel": what an edit script names it by
    std::string_view name;  ///< "Steel": what the Inspector and the history show
    double density;         ///< kg/m^3, the solid's density and the shell material's
    /// m: a typical skin of the material in a hull or float. A shell's surface density is
    /// density x thickness (the project's {"thickness", "material_density"} form).
    double shellThickness;

    double shellSurfaceDensity() const { return density * shellThickness; }  ///< kg/m^2
};

/// The presets, in the order the Inspector lists them.
std::span<const MaterialPreset> materialPresets();

/// The preset of that key or name, case aside ("steel", "Plastic (HDPE)"); null: none.
const MaterialPreset* findMaterialPreset(std::string_view keyOrName);

/// `material` with the preset's values in the parts it has: a solid gets the preset's density,
/// a shell density x thickness; both parts when it has both. Maps stay as they are.
MaterialDesc withMaterialPreset(const MaterialDesc& material, const MaterialPreset& preset);

/// The preset whose values `material` has in every part it has (null: none, "custom").
const MaterialPreset* matchingMaterialPreset(const MaterialDesc& material);

/// Applies the preset to the body's material as one undo step, "Set ball material to Steel".
/// Refused when the body has the preset's values already (a step that changes nothing).
Result<std::unique_ptr<Command>> makeApplyMaterialPresetCommand(const Document& document,
                                                                std::size_t body,
                                                                const MaterialPreset& preset);

}  // namespace plimsoll::editor
