// Project files (project.h, docs/project-schema.md): JSON text <-> Project. Reading checks the
// whole document and reports every problem at once, each with its JSON path, so that a user
// fixing a hand-written file sees all of them in one go rather than one per run.
#include "plimsoll/project/project.h"
#include "plimsoll/io/mesh_io.h"
#include "plimsoll/scene/level_ladder.h"
#include "plimsoll/scene/world.h"
#include "plimsoll/scene/scene_radiation.h"

#include "plimsoll/core/limits.h"

#include "plimsoll/bake/bake.h"
#include "plimsoll/io/file_util.h"

#include "io/graph_settings_json.h"
#include "io/json_reader.h"
#include "plimsoll/io/json_depth.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iterator>
#include <initializer_list>
#include <limits>
#include <string_view>
#include <utility>

namespace plimsoll {

namespace fs = std::filesystem;

namespace {

using detail::element;
using detail::find;
using detail::Json;
using detail::Limit;
using detail::member;

constexpr std::array<std::pair<const char*, WaterModel::Kind>, 3> kWaterModels = {{
    {"flat", WaterModel::Kind::Flat},
    {"gerstner", WaterModel::Kind::Gerstner},
    {"heightfield", WaterModel::Kind::HeightField},
}};

constexpr std::array kIntegrators = {Integrator::ExplicitEuler, Integrator::SemiImplicitEuler,
                                     Integrator::RK4};

const char* waterModelName(WaterModel::Kind kind) {
    for (const auto& [name, k] : kWaterModels) {
        if (k == kind) return name;
    }
    return "flat";
}

std::string printedInteger(double n) {
    char text[32];
    std::snprintf(text, sizeof text, "%.0f", n);
    return text;
}

/// Reads a parsed document into a Project. Each reader leaves the default in place when its
/// key is absent, records a problem and goes on when the value is wrong.
class ProjectReader : public detail::JsonReader {
public:
    explicit ProjectReader(std::string source) : JsonReader(std::move(source)) {}

    Result<Project> read(const Json& root, const fs::path& folder) {
        Project project;
        project.folder = folder;
        if (!root.is_object()) {
            return makeError(ErrorKind::schema, source() + ": must be a JSON object");
        }
        // A newer file may use keys this version does not know: report the version alone
        // rather than a list of "unknown key" lines that would hide the real problem.
        int version = 0;
        if (const Json* v = find(root, "schema_version")) {
            if (integerValue(*v, "schema_version", version, 1) && version > kProjectSchemaVersion) {
                return makeError(ErrorKind::unsupported,
                                 source() + ": schema_version: " + std::to_string(version) +
                                     " is newer than this Plimsoll reads (" +
                                     std::to_string(kProjectSchemaVersion) + ")");
            }
        } else {
            problem("schema_version", "required");
        }
        expectObject(root, "",
                     {"schema_version", "name", "medium", "water", "simulation", "bodies"});
        string(root, "", "name", project.name);
        if (const Json* medium = find(root, "medium")) readMedium(*medium, project.medium);
        if (const Json* water = find(root, "water")) readWater(*water, project.water);
        if (const Json* simulation = find(root, "simulation")) {
            readSimulation(*simulation, project.simulation);
        }
        readBodies(find(root, "bodies"), project.bodies);
        if (hasProblems()) return problems();
        return project;
    }

private:
    void readMedium(const Json& value, MediumDesc& medium) {
        const std::string path = "medium";
        if (!expectObject(value, path, {"name", "density", "viscosity"})) return;
        string(value, path, "name", medium.name);
        number(value, path, "density", medium.density, Limit::Positive);
        number(value, path, "viscosity", medium.viscosity, Limit::NonNegative);
    }

    void readWater(const Json& value, WaterModel& water) {
        const std::string path = "water";
        if (!expectObject(value, path, {"model", "level", "gravity", "waves", "grid"})) return;
        std::string model;
        const Json* modelValue = find(value, "model");
        if (modelValue && stringValue(*modelValue, member(path, "model"), model)) {
            bool known = false;
            for (const auto& [name, kind] : kWaterModels) {
                if (model == name) {
                    water.kind = kind;
                    known = true;
                }
            }
            if (!known) {
                std::string names;
                for (const auto& entry : kWaterModels) {
                    names += (names.empty() ? "" : ", ") + std::string(entry.first);
                }
                problem(member(path, "model"),
                        "unknown '" + boundedExcerpt(model) + "' (" + names + ")");
            }
        }
        number(value, path, "level", water.level);
        number(value, path, "gravity", water.gravity, Limit::Positive);

        // Waves and grid are read whatever the model, so that a file switched between models
        // keeps both (and saves them again); the model only decides which one is required.
        const std::string wavesPath = member(path, "waves");
        const Json* waves = find(value, "waves");
        if (waves && array(*waves, wavesPath)) {
            if (waves->size() > static_cast<std::size_t>(kMaxGerstnerWaves)) {
                problem(wavesPath, "at most " + std::to_string(kMaxGerstnerWaves));
            }
            for (std::size_t i = 0; i < waves->size(); ++i) {
                readWave((*waves)[i], element(wavesPath, i), water.waves.emplace_back());
            }
        }
        if (water.kind == WaterModel::Kind::Gerstner &&
            (!waves || (waves->is_array() && waves->empty()))) {
            problem(wavesPath, "model 'gerstner' needs at least one wave");
        }
        if (const Json* grid = find(value, "grid")) {
            readGrid(*grid, member(path, "grid"), water.grid);
        } else if (water.kind == WaterModel::Kind::HeightField) {
            problem(member(path, "grid"), "required for model 'heightfield'");
        }
    }

    void readWave(const Json& value, const std::string& path, GerstnerWave& wave) {
        if (!expectObject(value, path,
                          {"amplitude", "wavelength", "direction", "steepness", "phase"})) {
            return;
        }
        number(value, path, "amplitude", wave.amplitude, Limit::NonNegative);
        number(value, path, "wavelength", wave.wavelength, Limit::Positive);
        // A zero direction has no normal form; the model would fall back to +x silently.
        if (vector(value, path, "direction", wave.direction) && wave.direction.isZero(0.0)) {
            problem(member(path, "direction"), "must not be [0, 0]");
        }
        number(value, path, "steepness", wave.steepness, Limit::Fraction);
        number(value, path, "phase", wave.phase);
    }

    void readGrid(const Json& value, const std::string& path, HeightGrid& grid) {
        if (!expectObject(value, path, {"count", "spacing", "origin", "heights"})) return;
        const std::string countPath = member(path, "count");
        bool countValid = false;
        if (const Json* count = find(value, "count")) {
            if (!count->is_array() || count->size() != 2) {
                problem(countPath, "must be an array of 2 integers");
            } else {
                countValid = integerValue((*count)[0], element(countPath, 0), grid.countX, 1);
                countValid =
                    integerValue((*count)[1], element(countPath, 1), grid.countZ, 1) && countValid;
            }
        } else {
            problem(countPath, "required");
        }
        number(value, path, "spacing", grid.spacing, Limit::Positive);
        vector(value, path, "origin", grid.origin);

        const std::string heightsPath = member(path, "heights");
        const Json* heights = find(value, "heights");
        if (!heights) {
            problem(heightsPath, "required");
            return;
        }
        if (!array(*heights, heightsPath)) return;
        const std::size_t expected = static_cast<std::size_t>(grid.countX) * grid.countZ;
        if (countValid && heights->size() != expected) {
            problem(heightsPath, std::to_string(heights->size()) + " values; count [" +
                                     std::to_string(grid.countX) + ", " +
                                     std::to_string(grid.countZ) + "] needs " +
                                     std::to_string(expected));
        }
        // A generated grid that is wrong tends to be wrong everywhere: name the first bad
        // value and count the rest instead of printing thousands of lines.
        std::size_t bad = 0;
        grid.heights.reserve(heights->size());
        for (std::size_t i = 0; i < heights->size(); ++i) {
            const Json& height = (*heights)[i];
            const char* message = nullptr;
            if (!height.is_number()) {
                message = "must be a number";
            } else if (std::abs(height.get<double>()) > std::numeric_limits<float>::max()) {
                message = "outside the float range";
            }
            if (message) {
                if (bad++ == 0) problem(element(heightsPath, i), message);
                continue;
            }
            grid.heights.push_back(static_cast<float>(height.get<double>()));
        }
        if (bad > 1) problem(heightsPath, std::to_string(bad - 1) + " more invalid values");
    }

    void readSimulation(const Json& value, SimulationDesc& simulation) {
        const std::string path = "simulation";
        if (!expectObject(value, path,
                          {"gravity", "time_step", "sub_steps", "max_phase_step", "integrator",
                           "duration", "sleep"})) {
            return;
        }
        vector(value, path, "gravity", simulation.gravity);
        number(value, path, "time_step", simulation.timeStep, Limit::Positive);
        // At most World's own cap: beyond it the step count was clamped with lo > hi.
        integer(value, path, "sub_steps", simulation.subSteps, 1, World::kMaxSubSteps);
        number(value, path, "max_phase_step", simulation.maxPhaseStep, Limit::Positive);
        std::string name;
        const Json* integratorValue = find(value, "integrator");
        if (integratorValue && stringValue(*integratorValue, member(path, "integrator"), name)) {
            if (const auto integrator = integratorFromName(name)) {
                simulation.integrator = *integrator;
            } else {
                std::string known;
                for (Integrator i : kIntegrators) {
                    known += (known.empty() ? "" : ", ") + std::string(integratorName(i));
                }
                problem(member(path, "integrator"),
                        "unknown '" + boundedExcerpt(name) + "' (" + known + ")");
            }
        }
        number(value, path, "duration", simulation.duration, Limit::NonNegative);
        if (const Json* sleep = find(value, "sleep")) {
            readSleep(*sleep, member(path, "sleep"), simulation.sleep);
        }
    }

    void readSleep(const Json& value, const std::string& path,
                   plimsoll_eval::SleepSettings& sleep) {
        if (!expectObject(value, path,
                          {"enabled", "linear_speed", "angular_speed", "linear_acceleration",
                           "angular_acceleration", "rest_time", "wake_height"})) {
            return;
        }
        boolean(value, path, "enabled", sleep.enabled);
        number(value, path, "linear_speed", sleep.linearSpeed, Limit::NonNegative);
        number(value, path, "angular_speed", sleep.angularSpeed, Limit::NonNegative);
        number(value, path, "linear_acceleration", sleep.linearAcceleration, Limit::NonNegative);
        number(value, path, "angular_acceleration", sleep.angularAcceleration, Limit::NonNegative);
        number(value, path, "rest_time", sleep.restTime, Limit::NonNegative);
        number(value, path, "wake_height", sleep.wakeHeight, Limit::NonNegative);
    }

    void readBodies(const Json* value, std::vector<BodyDesc>& bodies) {
        const std::string path = "bodies";
        if (!value) {
            problem(path, "required");
            return;
        }
        if (!array(*value, path)) return;
        if (value->empty()) problem(path, "at least one body required");
        for (std::size_t i = 0; i < value->size(); ++i) {
            readBody((*value)[i], element(path, i), bodies.emplace_back());
        }
    }

    void readBody(const Json& value, const std::string& path, BodyDesc& body) {
        if (!expectObject(value, path,
                          {"name",
                           "mesh",
                           "mesh_frames",
                           "frames_per_second",
                           "texture_size",
                           "tolerance",
                           "max_texel_stretch",
                           "material",
                           "position",
                           "rotation_deg",
                           "velocity",
                           "angular_velocity",
                           "drag_coefficient",
                           "friction_coefficient",
                           "linear_damping",
                           "angular_damping",
                           "permeability_map",
                           "water_graph",
                           "atlas",
                           "openings",
                           "caps",
                           "radiation",
                           "unit",
                           "lod"})) {
            return;
        }
        string(value, path, "name", body.name);
        if (const Json* unit = find(value, "unit")) {
            // A name ("cm") or metres per file unit (0.01); absent: the file's own unit.
            std::optional<double> metres;
            if (unit->is_string())
                metres = parseLengthUnit(unit->get<std::string>());
            else if (unit->is_number() && unit->get<double>() > 0 &&
                     std::isfinite(unit->get<double>()))
                metres = unit->get<double>();
            if (metres)
                body.unitScale = *metres;
            else
                problem(
                    member(path, "unit"),
                    "expected m, cm, mm, km, in, ft, yd or metres per file unit (a number > 0)");
        }
        if (const Json* mesh = find(value, "mesh")) {
            if (stringValue(*mesh, member(path, "mesh"), body.mesh) && body.mesh.empty()) {
                problem(member(path, "mesh"), "must not be empty");
            }
        } else {
            problem(member(path, "mesh"), "required");
        }
        const std::string framesPath = member(path, "mesh_frames");
        const Json* frames = find(value, "mesh_frames");
        if (frames && array(*frames, framesPath)) {
            for (std::size_t i = 0; i < frames->size(); ++i) {
                std::string& frame = body.meshFrames.emplace_back();
                if (stringValue((*frames)[i], element(framesPath, i), frame) && frame.empty()) {
                    problem(element(framesPath, i), "must not be empty");
                }
            }
        }
        number(value, path, "frames_per_second", body.framesPerSecond, Limit::Positive);
        if (const Json* size = find(value, "texture_size");
            size && size->is_number() && size->get<double>() > kMaxTextureSize) {
            // Name the limit and what was asked for: a texture this size is refused before any
            // bake tries to allocate it (limits.h: ~72 bytes a covered texel).
            const double n = std::floor(size->get<double>());
            problem(member(path, "texture_size"),
                    "must be in " + std::to_string(kMinTextureSize) + ".." +
                        std::to_string(kMaxTextureSize) + ": " + printedInteger(n) +
                        " is more than the limit kMaxTextureSize (limits.h); its texels would "
                        "need up to " +
                        formatBytes(n * n * 72.0));
        } else {
            integer(value, path, "texture_size", body.textureSize, kMinTextureSize,
                    kMaxTextureSize);
        }
        if (const Json* tolerance = find(value, "tolerance")) {
            double share = 0;
            if (numberValue(*tolerance, member(path, "tolerance"), share, Limit::Positive)) {
                if (find(value, "texture_size"))
                    problem(member(path, "tolerance"), "give texture_size or tolerance, not both");
                else if (!(share < 1))
                    problem(member(path, "tolerance"), "must be below 1 (a share of rho g V)");
                else
                    body.tolerance = share;
            }
        }
        number(value, path, "max_texel_stretch", body.maxTexelStretch, Limit::NonNegative);
        std::string atlas;
        const Json* atlasValue = find(value, "atlas");
        if (atlasValue && stringValue(*atlasValue, member(path, "atlas"), atlas)) {
            if (const auto mode = parseAtlasMode(atlas))
                body.atlas = *mode;
            else
                problem(member(path, "atlas"),
                        "unknown '" + boundedExcerpt(atlas) + "' (mesh, auto, generate)");
        }
        std::string openings;
        const Json* openingsValue = find(value, "openings");
        if (openingsValue && stringValue(*openingsValue, member(path, "openings"), openings)) {
            if (const auto mode = parseOpeningsMode(openings))
                body.openings = *mode;
            else
                problem(member(path, "openings"),
                        "unknown '" + boundedExcerpt(openings) + "' (open, sealed, none)");
        }
        if (const Json* caps = find(value, "caps")) readCaps(*caps, member(path, "caps"), body);
        if (const Json* material = find(value, "material")) {
            readMaterial(*material, member(path, "material"), body.material);
        } else {
            problem(member(path, "material"), "required (density or shell)");
        }
        vector(value, path, "position", body.position);
        vector(value, path, "rotation_deg", body.rotationDegrees);
        vector(value, path, "velocity", body.velocity);
        vector(value, path, "angular_velocity", body.angularVelocity);
        number(value, path, "drag_coefficient", body.dragCoefficient, Limit::NonNegative);
        number(value, path, "friction_coefficient", body.frictionCoefficient, Limit::NonNegative);
        optionalNumber(value, path, "linear_damping", body.linearDamping);
        optionalNumber(value, path, "angular_damping", body.angularDamping);
        string(value, path, "permeability_map", body.permeabilityMap);
        if (const Json* graph = find(value, "water_graph")) {
            readWaterGraph(*graph, member(path, "water_graph"), body.waterGraph.emplace());
        }
        if (const Json* radiation = find(value, "radiation")) {
            readRadiation(*radiation, member(path, "radiation"), body.radiation.emplace());
        }
        if (const Json* lod = find(value, "lod")) readLod(*lod, member(path, "lod"), body);
    }

    void readCaps(const Json& value, const std::string& path, BodyDesc& body) {
        if (!array(value, path)) return;
        for (std::size_t i = 0; i < value.size(); ++i) {
            const std::string at = element(path, i);
            CapDesc& cap = body.caps.emplace_back();
            if (!expectObject(value[i], at, {"mode", "height"})) continue;
            std::string name;
            const Json* mode = find(value[i], "mode");
            if (mode && stringValue(*mode, member(at, "mode"), name)) {
                const std::optional<OpeningsMode> parsed = parseOpeningsMode(name);
                if (parsed && *parsed != OpeningsMode::None)
                    cap.mode = parsed;
                else
                    problem(member(at, "mode"),
                            "unknown '" + boundedExcerpt(name) + "' (open, sealed)");
            }
            double height = 0;
            const Json* h = find(value[i], "height");
            if (h && numberValue(*h, member(at, "height"), height, Limit::Any)) cap.height = height;
        }
    }

    void readLod(const Json& value, const std::string& path, BodyDesc& body) {
        if (!expectObject(value, path, {"levels"})) return;
        LodDesc& lod = body.lod.emplace();
        const std::string levelsPath = member(path, "levels");
        const Json* levels = find(value, "levels");
        if (!levels) {
            problem(levelsPath, "required (texture sizes, e.g. [16, 32])");
            return;
        }
        if (!array(*levels, levelsPath)) return;
        for (std::size_t i = 0; i < levels->size(); ++i) {
            int size = 0;
            // The body's texture_size (read above) is the finest level; a tolerance's size is
            // known only when it is met, so its levels are checked then (ladderSizes).
            if (!integerValue((*levels)[i], element(levelsPath, i), size, kMinTextureSize,
                              body.tolerance ? kToleranceMaxTextureSize : body.textureSize))
                continue;
            lod.levels.push_back(size);
        }
    }

    /// A non-negative number into an optional: left empty when the member is absent.
    void optionalNumber(const Json& object, const std::string& path, const char* key,
                        std::optional<double>& out) {
        if (!find(object, key)) return;
        double v = 0;
        number(object, path, key, v, Limit::NonNegative);
        out = v;
    }

    /// `true` or `false`, or an object of settings (`{}`: on with the automatic ones).
    void readRadiation(const Json& value, const std::string& path, RadiationDesc& radiation) {
        if (value.is_boolean()) {
            radiation.enabled = value.get<bool>();
            return;
        }
        if (!expectObject(
                value, path,
                {"enabled", "panel_edge", "frequencies", "min_frequency", "max_frequency"})) {
            return;
        }
        boolean(value, path, "enabled", radiation.enabled);
        number(value, path, "panel_edge", radiation.panelEdge, Limit::NonNegative);
        integer(value, path, "frequencies", radiation.frequencies, kMinRadiationFrequencies,
                kMaxRadiationFrequencies);
        number(value, path, "min_frequency", radiation.minFrequency, Limit::NonNegative);
        number(value, path, "max_frequency", radiation.maxFrequency, Limit::NonNegative);
        // Both given or both automatic: half a range would be a guess.
        if ((radiation.minFrequency > 0) != (radiation.maxFrequency > 0)) {
            problem(path, "min_frequency and max_frequency go together (or neither: automatic)");
        } else if (radiation.minFrequency > 0 && radiation.maxFrequency <= radiation.minFrequency) {
            problem(member(path, "max_frequency"), "must be more than min_frequency");
        }
    }

    void readWaterGraph(const Json& value, const std::string& path, WaterGraphDesc& graph) {
        if (!expectObject(
                value, path,
                {"graph", "permeability", "inflow", "inflow_rate", "discharge_coefficient", "flow",
                 "diffusion_pressure", "free_surface", "seed"})) {
            return;
        }
        if (const Json* file = find(value, "graph")) {
            if (stringValue(*file, member(path, "graph"), graph.graph) && graph.graph.empty()) {
                problem(member(path, "graph"), "must not be empty");
            }
        } else {
            problem(member(path, "graph"), "required (a graph.json)");
        }
        number(value, path, "permeability", graph.permeability, Limit::Fraction);
        std::string name;
        const Json* inflow = find(value, "inflow");
        if (inflow && stringValue(*inflow, member(path, "inflow"), name) &&
            !plimsoll_eval::inflowModelFromName(name, graph.settings.inflow)) {
            problem(member(path, "inflow"),
                    "unknown '" + boundedExcerpt(name) + "' (linear, torricelli)");
        }
        GraphSettings& settings = graph.settings;
        number(value, path, "inflow_rate", settings.inflowRate, Limit::NonNegative);
        number(value, path, "discharge_coefficient", settings.dischargeCoefficient,
               Limit::Fraction);
        const Json* flow = find(value, "flow");
        if (flow && stringValue(*flow, member(path, "flow"), name) &&
            !plimsoll_eval::flowModeFromName(name, settings.flow)) {
            problem(member(path, "flow"),
                    "unknown '" + boundedExcerpt(name) + "' (poiseuille, diffusion)");
        }
        number(value, path, "diffusion_pressure", settings.diffusionPressure, Limit::NonNegative);
        boolean(value, path, "free_surface", settings.freeSurface);
        int seed = static_cast<int>(settings.seed);
        integer(value, path, "seed", seed, 0);
        settings.seed = static_cast<std::uint64_t>(seed);
    }

    void readMaterial(const Json& value, const std::string& path, MaterialDesc& material) {
        if (!expectObject(value, path, {"density", "shell", "map", "thickness_map"})) return;
        double parsed = 0;
        const Json* density = find(value, "density");
        if (density && numberValue(*density, member(path, "density"), parsed, Limit::Positive)) {
            material.density = parsed;
        }
        const Json* shell = find(value, "shell");
        if (shell) readShell(*shell, member(path, "shell"), material);
        if (!density && !shell) problem(path, "needs density or shell");
        string(value, path, "map", material.shellDensityMap);
        // The map scales the shell's surface density; without a shell it would weigh nothing.
        if (!material.shellDensityMap.empty() && !shell) {
            problem(member(path, "map"), "needs a shell");
        }
        string(value, path, "thickness_map", material.shellThicknessMap);
        if (!material.shellThicknessMap.empty() && !shell) {
            problem(member(path, "thickness_map"), "needs a shell");
        }
    }

    void readShell(const Json& value, const std::string& path, MaterialDesc& material) {
        if (!expectObject(value, path, {"surface_density", "thickness", "material_density"})) {
            return;
        }
        const Json* surface = find(value, "surface_density");
        const Json* thickness = find(value, "thickness");
        const Json* materialDensity = find(value, "material_density");
        if (surface) {
            double sigma = 0;
            if (thickness || materialDensity) {
                problem(path, "surface_density, or thickness and material_density, not both");
            } else if (numberValue(*surface, member(path, "surface_density"), sigma,
                                   Limit::Positive)) {
                material.shellSurfaceDensity = sigma;
            }
            return;
        }
        if (!thickness && !materialDensity) {
            problem(path, "needs surface_density, or thickness and material_density");
            return;
        }
        if (!thickness) problem(member(path, "thickness"), "required with material_density");
        if (!materialDensity) problem(member(path, "material_density"), "required with thickness");
        double t = 0, rho = 0;
        const bool thicknessValid =
            thickness && numberValue(*thickness, member(path, "thickness"), t, Limit::Positive);
        const bool densityValid =
            materialDensity &&
            numberValue(*materialDensity, member(path, "material_density"), rho, Limit::Positive);
        if (thicknessValid && densityValid) material.shellSurfaceDensity = t * rho;
    }
};

/// As dump(2), except that arrays of numbers and strings stay on one line ("position": [1.0,
/// 2.0, 3.0] rather than five lines): project files are read and edited by people.
void writeIndented(const Json& value, int level, std::string& out) {
    const auto newline = [&](int indent) {
        out += '\n';
        out.append(2 * static_cast<std::size_t>(indent), ' ');
    };
    const bool nested =
        std::any_of(value.begin(), value.end(), [](const Json& v) { return v.is_structured(); });
    if (value.is_object() && !value.empty()) {
        out += '{';
        for (auto it = value.begin(); it != value.end(); ++it) {
            out += it == value.begin() ? "" : ",";
            newline(level + 1);
            out += Json(it.key()).dump() + ": ";
            writeIndented(it.value(), level + 1, out);
        }
        newline(level);
        out += '}';
    } else if (value.is_array() && nested) {
        out += '[';
        for (auto it = value.begin(); it != value.end(); ++it) {
            out += it == value.begin() ? "" : ",";
            newline(level + 1);
            writeIndented(*it, level + 1, out);
        }
        newline(level);
        out += ']';
    } else if (value.is_array()) {
        out += '[';
        for (auto it = value.begin(); it != value.end(); ++it) {
            out += (it == value.begin() ? "" : ", ") + it->dump();
        }
        out += ']';
    } else {
        out += value.dump();
    }
}

template <int N>
Json toJson(const Eigen::Matrix<double, N, 1>& v) {
    Json array = Json::array();
    for (int i = 0; i < N; ++i) array.push_back(v[i]);
    return array;
}

/// A float's shortest decimal form, as a double: the file shows 0.1 rather than
/// 0.10000000149011612 (the float widened), and reads back as the same float. The check
/// guards the double rounding (decimal -> double -> float), which could in principle land on
/// the neighbouring float.
double shortestDouble(float value) {
    char buffer[32];
    const char* end = std::to_chars(buffer, buffer + sizeof buffer, value).ptr;
    double result = 0;
    std::from_chars(buffer, end, result);
    return static_cast<float>(result) == value ? result : static_cast<double>(value);
}

Json toJson(const WaterModel& water) {
    Json json;
    json["model"] = waterModelName(water.kind);
    json["level"] = water.level;
    json["gravity"] = water.gravity;
    // Flat water needs neither waves nor a grid; leaving the empty ones out keeps files short.
    if (water.kind == WaterModel::Kind::Gerstner || !water.waves.empty()) {
        Json waves = Json::array();
        for (const GerstnerWave& w : water.waves) {
            Json wave;
            wave["amplitude"] = w.amplitude;
            wave["wavelength"] = w.wavelength;
            wave["direction"] = toJson(w.direction);
            wave["steepness"] = w.steepness;
            wave["phase"] = w.phase;
            waves.push_back(std::move(wave));
        }
        json["waves"] = std::move(waves);
    }
    if (water.kind == WaterModel::Kind::HeightField || water.grid != HeightGrid{}) {
        Json grid;
        grid["count"] = Json::array({water.grid.countX, water.grid.countZ});
        grid["spacing"] = water.grid.spacing;
        grid["origin"] = toJson(water.grid.origin);
        Json heights = Json::array();
        for (float h : water.grid.heights) heights.push_back(shortestDouble(h));
        grid["heights"] = std::move(heights);
        json["grid"] = std::move(grid);
    }
    return json;
}

Json toJson(const MaterialDesc& material) {
    Json json = Json::object();
    if (material.density) json["density"] = *material.density;
    // Shells given as thickness and material density are saved as their product.
    if (material.shellSurfaceDensity) {
        json["shell"]["surface_density"] = *material.shellSurfaceDensity;
    }
    if (!material.shellDensityMap.empty()) json["map"] = material.shellDensityMap;
    if (!material.shellThicknessMap.empty()) json["thickness_map"] = material.shellThicknessMap;
    return json;
}

Json toJson(const BodyDesc& body) {
    Json json;
    json["name"] = body.name;
    json["mesh"] = body.mesh;
    if (body.unitScale > 0) json["unit"] = body.unitScale;
    json["mesh_frames"] = body.meshFrames;
    json["frames_per_second"] = body.framesPerSecond;
    if (body.tolerance)
        json["tolerance"] = *body.tolerance;
    else
        json["texture_size"] = body.textureSize;
    json["max_texel_stretch"] = body.maxTexelStretch;
    json["atlas"] = atlasModeName(body.atlas);
    if (body.openings != OpeningsMode::Open) json["openings"] = openingsModeName(body.openings);
    if (!body.caps.empty()) {
        Json caps = Json::array();
        for (const CapDesc& cap : body.caps) {
            Json entry = Json::object();
            if (cap.mode) entry["mode"] = openingsModeName(*cap.mode);
            if (cap.height) entry["height"] = *cap.height;
            caps.push_back(std::move(entry));
        }
        json["caps"] = std::move(caps);
    }
    json["material"] = toJson(body.material);
    json["position"] = toJson(body.position);
    json["rotation_deg"] = toJson(body.rotationDegrees);
    json["velocity"] = toJson(body.velocity);
    json["angular_velocity"] = toJson(body.angularVelocity);
    json["drag_coefficient"] = body.dragCoefficient;
    json["friction_coefficient"] = body.frictionCoefficient;
    if (body.linearDamping) json["linear_damping"] = *body.linearDamping;
    if (body.angularDamping) json["angular_damping"] = *body.angularDamping;
    if (!body.permeabilityMap.empty()) json["permeability_map"] = body.permeabilityMap;
    if (body.waterGraph) {
        const WaterGraphDesc& g = *body.waterGraph;
        Json graph;
        graph["graph"] = g.graph;
        graph["permeability"] = g.permeability;
        writeGraphModels(g.settings, graph);
        json["water_graph"] = std::move(graph);
    }
    if (body.lod) json["lod"] = {{"levels", body.lod->levels}};
    if (body.radiation && !body.radiation->enabled &&
        *body.radiation == RadiationDesc{.enabled = false}) {
        json["radiation"] = false;
    } else if (body.radiation) {
        const RadiationDesc& r = *body.radiation;
        json["radiation"] = {{"enabled", r.enabled},
                             {"panel_edge", r.panelEdge},
                             {"frequencies", r.frequencies},
                             {"min_frequency", r.minFrequency},
                             {"max_frequency", r.maxFrequency}};
    }
    return json;
}

}  // namespace

fs::path Project::resolvePath(const std::string& path) const {
    const fs::path p(path);
    return p.is_absolute() ? p : (folder / p).lexically_normal();
}

fs::path Project::atlasCacheFile(std::size_t index) const {
    if (folder.empty()) return {};
    return folder / (fileStem + ".cache") / ("atlas-" + std::to_string(index) + ".json");
}

fs::path Project::radiationCacheFile(std::size_t index) const {
    if (folder.empty()) return {};
    return folder / (fileStem + ".cache") / ("radiation-" + std::to_string(index) + ".json");
}

fs::path Project::levelCacheFolder(std::size_t index) const {
    if (folder.empty()) return {};
    return folder / (fileStem + ".cache") / ("levels-" + std::to_string(index));
}

bool Project::operator==(const Project& other) const {
    return name == other.name && bodies == other.bodies && medium == other.medium &&
           water == other.water && simulation == other.simulation;
}

Result<Project> parseProject(const std::string& text, const std::string& source,
                             const fs::path& folder) {
    Result<Json> root = detail::parseJson(text, source);
    if (!root) return root.error();
    return ProjectReader(source).read(*root, folder);
}

Result<Project> loadProject(const fs::path& path) {
    std::error_code ec;
    // A save of the project with its maps that was killed after its commit is completed first.
    if (Status finished = finishInterruptedReplace(path); !finished.ok()) return finished.error();
    Result<std::string> read = readWholeFile(path, kMaxJsonFileBytes, "kMaxJsonFileBytes");
    if (!read) return read.error();
    const std::string& text = *read;
    // Absolute, so that the project's paths stay valid if the working directory changes.
    const fs::path absolute = fs::absolute(path, ec);
    Result<Project> project =
        parseProject(text, path.string(), (ec ? path : absolute).parent_path());
    if (project) {
        std::string stem = path.filename().string();
        for (const char* suffix : {".plim.json", ".json"}) {
            const std::string s(suffix);
            if (stem.size() > s.size() && stem.ends_with(s)) {
                stem.resize(stem.size() - s.size());
                break;
            }
        }
        project->fileStem = stem;
    }
    return project;
}

std::string projectToJson(const Project& project) {
    Json json;
    json["schema_version"] = kProjectSchemaVersion;
    json["name"] = project.name;
    json["medium"]["name"] = project.medium.name;
    json["medium"]["density"] = project.medium.density;
    json["medium"]["viscosity"] = project.medium.viscosity;
    json["water"] = toJson(project.water);
    const SimulationDesc& simulation = project.simulation;
    json["simulation"]["gravity"] = toJson(simulation.gravity);
    json["simulation"]["time_step"] = simulation.timeStep;
    json["simulation"]["sub_steps"] = simulation.subSteps;
    json["simulation"]["max_phase_step"] = simulation.maxPhaseStep;
    json["simulation"]["integrator"] = integratorName(simulation.integrator);
    json["simulation"]["duration"] = simulation.duration;
    json["simulation"]["sleep"] = {{"enabled", simulation.sleep.enabled},
                                   {"linear_speed", simulation.sleep.linearSpeed},
                                   {"angular_speed", simulation.sleep.angularSpeed},
                                   {"linear_acceleration", simulation.sleep.linearAcceleration},
                                   {"angular_acceleration", simulation.sleep.angularAcceleration},
                                   {"rest_time", simulation.sleep.restTime},
                                   {"wake_height", simulation.sleep.wakeHeight}};
    Json bodies = Json::array();
    for (const BodyDesc& body : project.bodies) bodies.push_back(toJson(body));
    json["bodies"] = std::move(bodies);
    std::string text;
    writeIndented(json, 0, text);
    return text;
}

Status saveProject(const Project& project, const fs::path& path) {
    const std::string text = projectToJson(project);
    return writeFileAtomically(path, [&](std::ostream& out) {
        out << text << '\n';
        return true;
    });
}

}  // namespace plimsoll
