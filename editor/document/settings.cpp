#include "document/settings.h"

#include "plimsoll/file_util.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cstdlib>
#include <fstream>

namespace plimsoll::editor {

namespace fs = std::filesystem;

fs::path userConfigDir() {
    if (const char* xdg = std::getenv("XDG_CONFIG_HOME"); xdg && *xdg) {
        return fs::path(xdg) / "plimsoll";
    }
    if (const char* home = std::getenv("HOME"); home && *home) {
        return fs::path(home) / ".config" / "plimsoll";
    }
    return fs::temp_directory_path() / "plimsoll-config";
}

void Settings::addRecent(const fs::path& file) {
    const std::string absolute = fs::absolute(file).lexically_normal().string();
    recentFiles.erase(std::remove(recentFiles.begin(), recentFiles.end(), absolute),
                      recentFiles.end());
    recentFiles.insert(recentFiles.begin(), absolute);
    if (recentFiles.size() > kMaxRecent) recentFiles.resize(kMaxRecent);
}

Settings Settings::load(const fs::path& folder) {
    Settings settings;
    std::ifstream in(folder / "settings.json");
    if (!in) return settings;
    try {
        const nlohmann::json j = nlohmann::json::parse(in);
        settings.recentFiles = j.value("recent_files", settings.recentFiles);
        settings.windowWidth = j.value("window_width", settings.windowWidth);
        settings.windowHeight = j.value("window_height", settings.windowHeight);
        settings.autosaveSeconds = j.value("autosave_seconds", settings.autosaveSeconds);
        settings.blenderNavigation = j.value("blender_navigation", settings.blenderNavigation);
        settings.uiScale = j.value("ui_scale", settings.uiScale);
    } catch (const nlohmann::json::exception&) {
        return Settings{};  // a damaged settings file must not stop the editor
    }
    return settings;
}

Status Settings::save(const fs::path& folder) const {
    nlohmann::json j;
    j["recent_files"] = recentFiles;
    j["window_width"] = windowWidth;
    j["window_height"] = windowHeight;
    j["autosave_seconds"] = autosaveSeconds;
    j["blender_navigation"] = blenderNavigation;
    j["ui_scale"] = uiScale;
    std::error_code ec;
    fs::create_directories(folder, ec);
    const std::string text = j.dump(2) + "\n";
    return writeFileAtomically(folder / "settings.json", [&](std::ostream& out) {
        out << text;
        return static_cast<bool>(out);
    });
}

}  // namespace plimsoll::editor
