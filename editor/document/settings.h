// Per-user editor settings and recent files, kept in the XDG config folder
// ($XDG_CONFIG_HOME/plimsoll, default ~/.config/plimsoll) as settings.json.
#pragma once

#include "document/paint.h"
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
    std::vector<std::string> recentFiles;   ///< most recent first, at most kMaxRecent
    int windowWidth = 1600;
    int windowHeight = 900;
    double autosaveSeconds = 120.0;         ///< autosave period of a dirty document
    bool blenderNavigation = true;          ///< middle mouse orbits (else left + Alt)
    float uiScale = 1.0f;
    PanelLayout layout;                     ///< the splitters' places
    Brush brush;                            ///< the brush as last used

    static constexpr std::size_t kMaxRecent = 10;
    void addRecent(const std::filesystem::path& file);

    /// Reads settings.json from `folder` (defaults where absent or unreadable).
    static Settings load(const std::filesystem::path& folder = userConfigDir());
    Status save(const std::filesystem::path& folder = userConfigDir()) const;
};

}  // namespace plimsoll::editor
