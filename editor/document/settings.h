// Per-user editor settings and recent files, kept in the XDG config folder
// ($XDG_CONFIG_HOME/plimsoll, default ~/.config/plimsoll) as settings.json.
#pragma once

#include "document/brush_presets.h"
#include "document/paint.h"
#include "document/sea_floor.h"
#include "document/panel_layout.h"
#include "plimsoll/core/result.h"

#include <nlohmann/json_fwd.hpp>

#include <filesystem>
#include <string>
#include <vector>

namespace plimsoll::editor {

/// A falloff curve as JSON, [[distance / radius, weight], ...], and back through
/// FalloffCurve::sanitised (malformed entries skipped): the settings file and edit scripts.
nlohmann::json falloffCurveJson(const FalloffCurve& curve);
FalloffCurve readFalloffCurve(const nlohmann::json& points);

/// $XDG_CONFIG_HOME/plimsoll, or $HOME/.config/plimsoll (created on first write).
std::filesystem::path userConfigDir();

struct Settings {
    std::vector<std::string> recentFiles;  ///< most recent first, at most kMaxRecent
    int windowWidth = 1600;
    int windowHeight = 900;
    double autosaveSeconds = 120.0;  ///< autosave period of a dirty document
    bool blenderNavigation = true;   ///< middle mouse orbits (else left + Alt)
    float uiScale = 1.0f;
    PanelLayout layout;  ///< the splitters' places
    Brush brush;         ///< the brush as last used
    /// The painter's own brush presets ("brush_presets"), in the order saved; the built-in
    /// ones (builtinBrushPresets) are not stored.
    std::vector<BrushPreset> brushPresets;
    /// The live preview's sea floor ("sea_floor"): on, 5 m down, unless the user changed it.
    SeaFloor seaFloor{.enabled = true};

    static constexpr std::size_t kMaxRecent = 10;
    void addRecent(const std::filesystem::path& file);
    /// Keeps `brush`'s tip as the preset `name` (without the spaces at its ends), replacing
    /// the painter's preset of that name. Refused: an empty name, a built-in preset's name,
    /// and a new preset past kMaxUserBrushPresets.
    Status saveBrushPreset(const std::string& name, const Brush& brush);
    /// Removes the painter's preset `name`; false if there is none.
    bool removeBrushPreset(const std::string& name);

    /// Reads settings.json from `folder` (defaults where absent or unreadable).
    static Settings load(const std::filesystem::path& folder = userConfigDir());
    Status save(const std::filesystem::path& folder = userConfigDir()) const;
};

}  // namespace plimsoll::editor
