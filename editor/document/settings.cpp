#include "document/settings.h"

#include "plimsoll/core/limits.h"
#include "plimsoll/io/file_util.h"
#include "plimsoll/io/json_depth.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
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

nlohmann::json falloffCurveJson(const FalloffCurve& curve) {
    nlohmann::json points = nlohmann::json::array();
    for (const Eigen::Vector2d& p : curve.points) points.push_back({p.x(), p.y()});
    return points;
}

FalloffCurve readFalloffCurve(const nlohmann::json& points) {
    std::vector<Eigen::Vector2d> read;
    if (points.is_array()) {
        for (const nlohmann::json& p : points) {
            if (p.is_array() && p.size() == 2 && p[0].is_number() && p[1].is_number())
                read.emplace_back(p[0].get<double>(), p[1].get<double>());
            if (read.size() > 4 * static_cast<std::size_t>(kMaxFalloffPoints)) break;
        }
    }
    return FalloffCurve::sanitised(std::move(read));
}

void Settings::addRecent(const fs::path& file) {
    const std::string absolute = fs::absolute(file).lexically_normal().string();
    recentFiles.erase(std::remove(recentFiles.begin(), recentFiles.end(), absolute),
                      recentFiles.end());
    recentFiles.insert(recentFiles.begin(), absolute);
    if (recentFiles.size() > kMaxRecent) recentFiles.resize(kMaxRecent);
}

Status Settings::saveBrushPreset(const std::string& typed, const Brush& brush) {
    std::string name = typed;
    name.erase(0, name.find_first_not_of(" \t"));
    name.erase(name.find_last_not_of(" \t") + 1);
    if (name.empty()) return makeError(ErrorKind::invalidArgument, "a brush preset needs a name");
    for (const BrushPreset& p : builtinBrushPresets()) {
        if (p.name == name) {
            return makeError(ErrorKind::invalidArgument,
                             "'" + name + "' is a built-in preset: choose another name");
        }
    }
    BrushPreset preset = brushPresetOf(name, brush);
    for (BrushPreset& p : brushPresets) {
        if (p.name == name) {
            p = std::move(preset);
            return Ok{};
        }
    }
    if (brushPresets.size() >= kMaxUserBrushPresets) {
        return makeError(ErrorKind::limit, "at most " + std::to_string(kMaxUserBrushPresets) +
                                               " brush presets: remove one first");
    }
    brushPresets.push_back(std::move(preset));
    return Ok{};
}

bool Settings::removeBrushPreset(const std::string& name) {
    const auto it = std::find_if(brushPresets.begin(), brushPresets.end(),
                                 [&](const BrushPreset& p) { return p.name == name; });
    if (it == brushPresets.end()) return false;
    brushPresets.erase(it);
    return true;
}

Settings Settings::load(const fs::path& folder) {
    Settings settings;
    // Read as any other JSON file: bounded, not a FIFO, nesting checked before parsing. A file
    // that fails gives the defaults, as a malformed one always has.
    Result<std::string> text =
        readWholeFile(folder / "settings.json", kMaxJsonFileBytes, "kMaxJsonFileBytes");
    if (!text || !checkJsonDepth(*text, "settings.json").ok()) return settings;
    try {
        const nlohmann::json j = nlohmann::json::parse(*text);
        settings.recentFiles = j.value("recent_files", settings.recentFiles);
        settings.windowWidth = j.value("window_width", settings.windowWidth);
        settings.windowHeight = j.value("window_height", settings.windowHeight);
        settings.autosaveSeconds = j.value("autosave_seconds", settings.autosaveSeconds);
        settings.blenderNavigation = j.value("blender_navigation", settings.blenderNavigation);
        settings.uiScale = j.value("ui_scale", settings.uiScale);
        if (j.contains("layout")) {
            const nlohmann::json& l = j["layout"];
            settings.layout.columnWidth = l.value("column_width", settings.layout.columnWidth);
            settings.layout.shares = l.value("shares", settings.layout.shares);
            settings.layout.uvBesideView = l.value("uv_beside_view", false);
            settings.layout = sanitised(settings.layout);
        }
        if (j.contains("brush")) {
            // Out-of-range numbers fall back to the defaults: a hand-edited file must not
            // give a brush the panel cannot show.
            const nlohmann::json& b = j["brush"];
            Brush& brush = settings.brush;
            const Brush defaults;
            auto unit = [](double v, double fallback) { return v >= 0 && v <= 1 ? v : fallback; };
            brush.radius = b.value("radius", brush.radius);
            if (!(brush.radius > 0) || !std::isfinite(brush.radius)) brush.radius = defaults.radius;
            brush.strength = unit(b.value("strength", brush.strength), defaults.strength);
            brush.value = unit(b.value("value", brush.value), defaults.value);
            brush.spacing = b.value("spacing", brush.spacing);
            if (!(brush.spacing > 0) || !std::isfinite(brush.spacing))
                brush.spacing = defaults.spacing;
            brush.falloff =
                parseFalloff(b.value("falloff", std::string(falloffName(brush.falloff))))
                    .value_or(defaults.falloff);
            if (b.contains("falloff_curve")) brush.curve = readFalloffCurve(b["falloff_curve"]);
            brush.mirrorX = b.value("mirror_x", brush.mirrorX);
            brush.mirrorY = b.value("mirror_y", brush.mirrorY);
            brush.mirrorZ = b.value("mirror_z", brush.mirrorZ);
            brush.radial = std::clamp(b.value("radial", brush.radial), 1, kMaxRadialCopies);
            brush.lazyRadius = b.value("lazy_radius", brush.lazyRadius);
            if (!(brush.lazyRadius >= 0) || !(brush.lazyRadius <= kMaxLazyRadius))
                brush.lazyRadius = defaults.lazyRadius;
            brush.normalAngle = b.value("normal_angle", brush.normalAngle);
            if (!(brush.normalAngle >= 0) || !(brush.normalAngle <= 180))
                brush.normalAngle = defaults.normalAngle;
            brush.frontFacesOnly = b.value("front_faces_only", brush.frontFacesOnly);
            brush.occlusion = b.value("occlusion", brush.occlusion);
            // The image itself is loaded by the window (a missing file: no alpha).
            brush.alphaPath = b.value("alpha", brush.alphaPath);
        }
        if (j.contains("sea_floor")) {
            const nlohmann::json& f = j["sea_floor"];
            settings.seaFloor.enabled = f.value("enabled", settings.seaFloor.enabled);
            const double depth = f.value("depth", settings.seaFloor.depth);
            if (depth > 0 && std::isfinite(depth)) settings.seaFloor.depth = depth;
        }
        if (const auto presets = j.find("brush_presets");
            presets != j.end() && presets->is_array()) {
            // A preset the panel could not show, a second of one name (a built-in's too), or
            // one past the limit is left out; the others are kept.
            const auto builtins = builtinBrushPresets();
            for (const nlohmann::json& entry : *presets) {
                std::optional<BrushPreset> preset = readBrushPreset(entry);
                if (!preset || settings.brushPresets.size() >= kMaxUserBrushPresets) continue;
                const auto named = [&](const BrushPreset& p) { return p.name == preset->name; };
                const auto& kept = settings.brushPresets;
                if (std::any_of(kept.begin(), kept.end(), named) ||
                    std::any_of(builtins.begin(), builtins.end(), named))
                    continue;
                settings.brushPresets.push_back(std::move(*preset));
            }
        }
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
    j["layout"] = {{"column_width", layout.columnWidth},
                   {"shares", layout.shares},
                   {"uv_beside_view", layout.uvBesideView}};
    j["brush"] = {{"radius", brush.radius},
                  {"strength", brush.strength},
                  {"value", brush.value},
                  {"spacing", brush.spacing},
                  {"falloff", falloffName(brush.falloff)},
                  {"mirror_x", brush.mirrorX},
                  {"mirror_y", brush.mirrorY},
                  {"mirror_z", brush.mirrorZ},
                  {"radial", brush.radial},
                  {"lazy_radius", brush.lazyRadius},
                  {"alpha", brush.alphaPath},
                  {"normal_angle", brush.normalAngle},
                  {"front_faces_only", brush.frontFacesOnly},
                  {"occlusion", brush.occlusion},
                  {"falloff_curve", falloffCurveJson(brush.curve)}};
    j["sea_floor"] = {{"enabled", seaFloor.enabled}, {"depth", seaFloor.depth}};
    j["brush_presets"] = nlohmann::json::array();
    for (const BrushPreset& p : brushPresets) j["brush_presets"].push_back(brushPresetJson(p));
    std::error_code ec;
    fs::create_directories(folder, ec);
    const std::string text = j.dump(2) + "\n";
    return writeFileAtomically(folder / "settings.json", [&](std::ostream& out) {
        out << text;
        return static_cast<bool>(out);
    });
}

}  // namespace plimsoll::editor
