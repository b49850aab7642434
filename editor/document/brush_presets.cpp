#include "document/brush_presets.h"

#include "document/settings.h"

#include <nlohmann/json.hpp>

#include <cmath>
#include <vector>

namespace plimsoll::editor {

namespace {

const char* modeName(BrushMode mode) {
    return mode == BrushMode::Erase ? "erase" : mode == BrushMode::Smooth ? "smooth" : "paint";
}

std::optional<BrushMode> parseMode(const std::string& name) {
    if (name == "paint") return BrushMode::Paint;
    if (name == "erase") return BrushMode::Erase;
    if (name == "smooth") return BrushMode::Smooth;
    return std::nullopt;
}

BrushPreset preset(std::string name, double radius, double strength, double value,
                   Falloff falloff) {
    BrushPreset p;
    p.name = std::move(name);
    p.radius = radius;
    p.strength = strength;
    p.value = value;
    p.falloff = falloff;
    return p;
}

}  // namespace

std::span<const BrushPreset> builtinBrushPresets() {
    // Radii for bodies of about a metre (the sample buoy and boat); the painter scales them.
    static const std::vector<BrushPreset> presets{
        preset("Hole", 0.02, 1.0, 1.0, Falloff::Constant),  // a clean opening: all the water in
        preset("Seep", 0.10, 0.25, 1.0, Falloff::Smooth),   // each stroke lets a quarter more in
        preset("Seal", 0.10, 1.0, 0.0, Falloff::Constant),  // closes to the rim: nothing flows
    };
    return presets;
}

BrushPreset brushPresetOf(std::string name, const Brush& brush) {
    BrushPreset p;
    p.name = std::move(name);
    p.mode = brush.mode;
    p.radius = brush.radius;
    p.strength = brush.strength;
    p.value = brush.value;
    p.falloff = brush.falloff;
    // The curve is the tip's only with the custom falloff (and only then saved).
    if (brush.falloff == Falloff::Custom) p.curve = brush.curve;
    p.spacing = brush.spacing;
    return p;
}

void applyBrushPreset(const BrushPreset& preset, Brush& brush) {
    brush.mode = preset.mode;
    brush.radius = preset.radius;
    brush.strength = preset.strength;
    brush.value = preset.value;
    brush.falloff = preset.falloff;
    // A preset of a formula keeps the brush's own curve for when the painter goes back to it.
    if (preset.falloff == Falloff::Custom) brush.curve = preset.curve;
    brush.spacing = preset.spacing;
}

bool brushHasPreset(const Brush& brush, const BrushPreset& preset) {
    return brush.mode == preset.mode && brush.radius == preset.radius &&
           brush.strength == preset.strength && brush.value == preset.value &&
           brush.falloff == preset.falloff && brush.spacing == preset.spacing &&
           (preset.falloff != Falloff::Custom || brush.curve == preset.curve);
}

nlohmann::json brushPresetJson(const BrushPreset& preset) {
    nlohmann::json j = {{"name", preset.name},      {"mode", modeName(preset.mode)},
                        {"radius", preset.radius},  {"strength", preset.strength},
                        {"value", preset.value},    {"falloff", falloffName(preset.falloff)},
                        {"spacing", preset.spacing}};
    if (preset.falloff == Falloff::Custom) j["falloff_curve"] = falloffCurveJson(preset.curve);
    return j;
}

std::optional<BrushPreset> readBrushPreset(const nlohmann::json& j) {
    if (!j.is_object()) return std::nullopt;
    try {
        BrushPreset p;
        p.name = j.at("name").get<std::string>();
        const std::optional<BrushMode> mode = parseMode(j.value("mode", std::string("paint")));
        const std::optional<Falloff> falloff =
            parseFalloff(j.value("falloff", std::string("smooth")));
        if (p.name.empty() || !mode || !falloff) return std::nullopt;
        p.mode = *mode;
        p.falloff = *falloff;
        p.radius = j.value("radius", p.radius);
        p.strength = j.value("strength", p.strength);
        p.value = j.value("value", p.value);
        p.spacing = j.value("spacing", p.spacing);
        if (j.contains("falloff_curve")) p.curve = readFalloffCurve(j["falloff_curve"]);
        const auto unit = [](double v) { return v >= 0 && v <= 1; };
        if (!(p.radius > 0) || !std::isfinite(p.radius) || !unit(p.strength) || !unit(p.value) ||
            !(p.spacing > 0) || !(p.spacing <= 100)) {
            return std::nullopt;
        }
        return p;
    } catch (const nlohmann::json::exception&) {
        return std::nullopt;
    }
}

}  // namespace plimsoll::editor
