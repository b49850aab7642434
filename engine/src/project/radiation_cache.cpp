// The radiation cache (radiation_cache.h).
#include "plimsoll/project/radiation_cache.h"
#include "plimsoll/io/json_depth.h"

#include "plimsoll/core/limits.h"
#include "plimsoll/io/file_util.h"

#include <nlohmann/json.hpp>

#include <chrono>
#include <cmath>
#include <sstream>
#include <stdexcept>

namespace plimsoll {

namespace {

constexpr const char* kFormat = "plimsoll-radiation";

nlohmann::json matrixJson(const Matrix6d& m) {
    std::vector<double> values(m.data(), m.data() + 36);  // column-major
    return values;
}

/// A 6 x 6 matrix of finite numbers, or a std::runtime_error saying what is wrong.
Matrix6d matrixFrom(const nlohmann::json& j, const char* what) {
    const auto values = j.get<std::vector<double>>();
    if (values.size() != 36) throw std::runtime_error(std::string(what) + ": not 36 numbers");
    Matrix6d m;
    for (int k = 0; k < 36; ++k) {
        if (!std::isfinite(values[k])) throw std::runtime_error(std::string(what) + ": not finite");
        m.data()[k] = values[k];
    }
    return m;
}

double finiteFrom(const nlohmann::json& j, const char* what) {
    const double v = j.get<double>();
    if (!std::isfinite(v)) throw std::runtime_error(std::string(what) + ": not finite");
    return v;
}

}  // namespace

Result<std::optional<BodyRadiation>> readRadiationCache(const std::filesystem::path& file,
                                                        const std::string& key) {
    std::error_code ec;
    if (!std::filesystem::exists(file, ec)) return std::optional<BodyRadiation>{};
    Result<std::string> text = readWholeFile(file, kMaxJsonFileBytes, "kMaxJsonFileBytes");
    if (!text) return text.error();
    const auto damaged = [&](const std::string& why) {
        return makeError(ErrorKind::format,
                         file.string() + ": not a readable radiation cache: " + why);
    };
    if (Status depth = checkJsonDepth(*text, file.string()); !depth.ok()) return depth.error();
    try {
        const nlohmann::json j = nlohmann::json::parse(*text);
        if (!j.is_object() || j.value("format", "") != kFormat)
            return damaged("no \"format\": \"" + std::string(kFormat) + "\"");
        if (j.at("key").get<std::string>() != key) return std::optional<BodyRadiation>{};
        BodyRadiation r;
        r.restVolume = finiteFrom(j.at("rest_volume"), "rest_volume");
        r.restHeight = finiteFrom(j.at("rest_height"), "rest_height");
        r.panelEdge = finiteFrom(j.at("panel_edge"), "panel_edge");
        r.panelCount = j.at("panel_count").get<std::size_t>();
        r.addedMassInfinity = matrixFrom(j.at("added_mass_infinity"), "added_mass_infinity");
        const nlohmann::json& samples = j.at("coefficients");
        if (!samples.is_array() || samples.size() < 2 || samples.size() > 10000)
            return damaged("coefficients: not a list of 2 to 10000 frequencies");
        double previous = 0;
        for (const nlohmann::json& s : samples) {
            RadiationCoefficients c;
            c.omega = finiteFrom(s.at("omega"), "omega");
            if (!(c.omega > previous))
                return damaged("coefficients: frequencies not positive and increasing");
            previous = c.omega;
            c.addedMass = matrixFrom(s.at("added_mass"), "added_mass");
            c.damping = matrixFrom(s.at("damping"), "damping");
            r.coefficients.push_back(c);
        }
        if (!(r.restVolume > 0)) return damaged("rest_volume: not positive");
        fitRadiationModel(r);
        return std::optional<BodyRadiation>(std::move(r));
    } catch (const std::exception& e) {
        return damaged(boundedExcerpt(e.what(), 200));
    }
}

Status writeRadiationCache(const std::filesystem::path& file, const std::string& key,
                           const BodyRadiation& radiation) {
    nlohmann::json samples = nlohmann::json::array();
    for (const RadiationCoefficients& c : radiation.coefficients) {
        samples.push_back({{"omega", c.omega},
                           {"added_mass", matrixJson(c.addedMass)},
                           {"damping", matrixJson(c.damping)}});
    }
    const nlohmann::json j = {{"format", kFormat},
                              {"key", key},
                              {"rest_volume", radiation.restVolume},
                              {"rest_height", radiation.restHeight},
                              {"panel_edge", radiation.panelEdge},
                              {"panel_count", radiation.panelCount},
                              {"added_mass_infinity", matrixJson(radiation.addedMassInfinity)},
                              {"coefficients", samples}};
    std::error_code ec;
    if (!file.parent_path().empty()) std::filesystem::create_directories(file.parent_path(), ec);
    const std::string text = j.dump() + "\n";
    return writeFileAtomically(file, [&](std::ostream& out) { return bool(out << text); });
}

Result<std::shared_ptr<const BodyRadiation>> cachedBodyRadiation(
    const SceneBody& body, const RadiationDesc& desc, const MediumDesc& medium,
    const Eigen::Vector3d& gravity, const std::filesystem::path& cacheFile, const LogFunction& log,
    const ProgressCallback& progress) {
    const auto say = [&](const std::string& line) {
        if (log) log(line);
    };
    const std::string key = radiationKey(body, desc, medium, gravity);
    if (!cacheFile.empty()) {
        Result<std::optional<BodyRadiation>> cached = readRadiationCache(cacheFile, key);
        if (!cached) {
            say(body.label + ": " + cached.error().message + "; computing it again");
        } else if (*cached) {
            say(body.label + ": radiation from the cache " + cacheFile.string());
            return std::make_shared<const BodyRadiation>(std::move(**cached));
        }
    }
    const auto start = std::chrono::steady_clock::now();
    Result<BodyRadiation> computed = computeBodyRadiation(body, desc, medium, gravity, progress);
    if (!computed) return computed.error();
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    std::ostringstream line;
    line << body.label << ": radiation computed over " << computed->panelCount << " panels at "
         << computed->coefficients.size() << " frequencies in " << seconds << " s";
    if (!cacheFile.empty()) {
        if (Status saved = writeRadiationCache(cacheFile, key, *computed); !saved) {
            return withContext(body.label + ": could not cache the radiation coefficients: ",
                               saved.error());
        }
        line << ", cached in " << cacheFile.string();
    }
    say(line.str());
    return std::make_shared<const BodyRadiation>(std::move(*computed));
}

}  // namespace plimsoll
