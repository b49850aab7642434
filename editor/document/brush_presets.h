// Brush presets: named brush tips, a few built in and the painter's own, kept in the settings
// file (settings.h). A preset holds the tip (mode, radius, strength, value, falloff, spacing);
// symmetry, lazy mouse, alpha and the facing and occlusion limits stay as they are, because
// they belong to the model being painted and the painter's hand, not to the tip.
#pragma once

#include "document/paint.h"

#include <nlohmann/json_fwd.hpp>

#include <optional>
#include <span>
#include <string>

namespace plimsoll::editor {

struct BrushPreset {
    std::string name;
    BrushMode mode = BrushMode::Paint;
    double radius = 0.05;   ///< m
    double strength = 1.0;  ///< 0..1
    double value = 1.0;     ///< 0..1
    Falloff falloff = Falloff::Smooth;
    FalloffCurve curve = FalloffCurve::preset(Falloff::Smooth);  ///< with Falloff::Custom
    double spacing = 0.25;                                       ///< radii

    bool operator==(const BrushPreset&) const = default;
};

/// At most this many presets of the painter's own.
inline constexpr std::size_t kMaxUserBrushPresets = 64;

/// The built-in presets: "Hole" (a small hard brush that opens the map fully: permeability 1),
/// "Seep" (a soft, weak brush that lets a little in per stroke) and "Seal" (paints 0).
std::span<const BrushPreset> builtinBrushPresets();

/// The preset of `brush`'s tip, named `name`.
BrushPreset brushPresetOf(std::string name, const Brush& brush);
/// `brush` with the preset's tip (the rest kept).
void applyBrushPreset(const BrushPreset& preset, Brush& brush);
/// Whether `brush`'s tip is the preset's.
bool brushHasPreset(const Brush& brush, const BrushPreset& preset);

/// The preset as the settings file's JSON object, and back: nothing where the name is
/// missing or a number is out of range (a hand-edited file must not give a brush the panel
/// cannot show).
nlohmann::json brushPresetJson(const BrushPreset& preset);
std::optional<BrushPreset> readBrushPreset(const nlohmann::json& json);

}  // namespace plimsoll::editor
