#include "document/material_presets.h"

#include <algorithm>
#include <array>
#include <cctype>

namespace plimsoll::editor {

namespace {

// Densities: engineering handbook and design-code values at room temperature; a real part
// varies by its grade and, for wood, its moisture.
// - Steel 7850 kg/m^3: structural steel, EN 1993-1-1 (Eurocode 3) 3.2.6.
// - Aluminium 2700 kg/m^3: aluminium alloys, EN 1999-1-1 (Eurocode 9) 3.2.5.
// - Concrete 2400 kg/m^3: normal-weight concrete (EN 1991-1-1 Table A.1: 24 kN/m^3 plain).
// - Wood 600 kg/m^3: seasoned timber at 12% moisture spans about 400 (spruce) to 750 (oak)
//   (USDA Forest Products Laboratory, Wood Handbook FPL-GTR-190, ch. 5); 600 is a mid value.
// - Plastic (HDPE) 950 kg/m^3: polyethylene of 941 to 965 kg/m^3 is HDPE by definition
//   (ASTM D4976 / ISO 17855-1 density classes).
// - Foam 50 kg/m^3: rigid closed-cell buoyancy foam (polyurethane, PVC core, extruded
//   polystyrene) is made at about 30 to 100 kg/m^3.
// Shell thicknesses are typical skins of small craft and floats, a starting point to adjust:
// steel plate 6 mm, aluminium plate 4 mm, HDPE rotomoulded wall 6 mm, wood planking 20 mm,
// a foam collar 50 mm, a concrete pontoon wall 100 mm.
constexpr std::array<MaterialPreset, 6> kPresets{{
    {"wood", "Wood", 600.0, 0.020},
    {"steel", "Steel", 7850.0, 0.006},
    {"aluminium", "Aluminium", 2700.0, 0.004},
    {"foam", "Foam", 50.0, 0.050},
    {"hdpe", "Plastic (HDPE)", 950.0, 0.006},
    {"concrete", "Concrete", 2400.0, 0.100},
}};

bool sameText(std::string_view a, std::string_view b) {
    return a.size() == b.size() && std::equal(a.begin(), a.end(), b.begin(), [](char x, char y) {
               return std::tolower(static_cast<unsigned char>(x)) ==
                      std::tolower(static_cast<unsigned char>(y));
           });
}

}  // namespace

std::span<const MaterialPreset> materialPresets() { return kPresets; }

const MaterialPreset* findMaterialPreset(std::string_view keyOrName) {
    for (const MaterialPreset& p : kPresets) {
        if (sameText(p.key, keyOrName) || sameText(p.name, keyOrName)) return &p;
    }
    return nullptr;
}

MaterialDesc withMaterialPreset(const MaterialDesc& material, const MaterialPreset& preset) {
    MaterialDesc out = material;
    if (out.density) out.density = preset.density;
    if (out.shellSurfaceDensity) out.shellSurfaceDensity = preset.shellSurfaceDensity();
    return out;
}

const MaterialPreset* matchingMaterialPreset(const MaterialDesc& material) {
    if (!material.density && !material.shellSurfaceDensity) return nullptr;
    for (const MaterialPreset& p : kPresets) {
        if (withMaterialPreset(material, p) == material) return &p;
    }
    return nullptr;
}

Result<std::unique_ptr<Command>> makeApplyMaterialPresetCommand(const Document& document,
                                                                std::size_t body,
                                                                const MaterialPreset& preset) {
    if (body >= document.bodyCount()) {
        return makeError(ErrorKind::invalidArgument,
                         "no body " + std::to_string(body) + " (the project has " +
                             std::to_string(document.bodyCount()) + ")");
    }
    Project project = document.project();
    BodyDesc& b = project.bodies[body];
    const std::string label = b.name.empty() ? "body " + std::to_string(body + 1) : b.name;
    const MaterialDesc applied = withMaterialPreset(b.material, preset);
    if (applied == b.material) {
        return makeError(
            ErrorKind::invalidArgument,
            label + " has the " + std::string(preset.name) + " preset's values already");
    }
    b.material = applied;
    return std::unique_ptr<Command>(std::make_unique<ProjectCommand>(
        "Set " + label + " material to " + std::string(preset.name), document.project(),
        std::move(project)));
}

}  // namespace plimsoll::editor
