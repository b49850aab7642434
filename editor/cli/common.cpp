#include "cli/common.h"

#include "plimsoll/bake/bake_cost.h"
#include "plimsoll/core/limits.h"
#include "plimsoll/io/json_depth.h"
#include "plimsoll/io/mesh_io.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <sstream>
#include <unistd.h>

namespace plimsoll::cli {

namespace {
/// A validator that parses the whole argument as a double and applies `accept`.
CLI::Validator finiteNumber(const char* name, bool (*accept)(double), const char* what) {
    return CLI::Validator(
        [accept, what](std::string& text) -> std::string {
            double value = 0;
            const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
            if (ec != std::errc() || end != text.data() + text.size() || !std::isfinite(value) ||
                !accept(value))
                return "'" + text + "' is not " + what;
            return {};
        },
        name);
}
}  // namespace

const CLI::Validator kFiniteNumber = finiteNumber(
    "FINITE", [](double) { return true; }, "a finite number");
const CLI::Validator kFinitePositive = finiteNumber(
    "POSITIVE", [](double v) { return v > 0; }, "a finite number > 0");
const CLI::Validator kFiniteNonNegative = finiteNumber(
    "NONNEGATIVE", [](double v) { return v >= 0; }, "a finite number >= 0");
const CLI::Validator kNonEmptyPath(
    [](std::string& text) -> std::string {
        if (text.empty()) return "an empty path (it would mean the current folder)";
        if (text.find('\0') != std::string::npos) return "a path holding a NUL byte";
        return {};
    },
    "PATH");

CLI::Option* addUnitOption(CLI::App& command, double& unitScale) {
    return command.add_option_function<std::string>(
        "--unit",
        [&unitScale](const std::string& text) {
            const std::optional<double> metres = parseLengthUnit(text);
            if (!metres)
                throw CLI::ValidationError("--unit",
                                           "expected m, cm, mm, km, in, ft, yd or metres per "
                                           "file unit (a number > 0), got '" +
                                               text + "'");
            unitScale = *metres;
        },
        "Length unit of the file: m, cm, mm, km, in, ft, yd or metres per file unit [the file's "
        "own: FBX UnitScaleFactor, glTF metres; metres for OBJ, STL and PLY]");
}

namespace {
/// The solid to use for `mesh`: itself, or its physics solid with a note of the repairs.
Result<PhysicsSolid> solidOrRepair(const TriangleMesh& mesh, const ValidationReport& report,
                                   const std::string& path, const Reporter& reporter) {
    Result<PhysicsSolid> solid = physicsSolidFor(mesh, report);
    if (!solid) return solid.error();
    if (!solid->repairs.empty()) {
        std::ostringstream text;
        text << "note: " << path
             << ": not one closed solid as it is, or an open hull: using its physics solid ("
             << describeRepairs(solid->repairs) << "), " << solid->materialVolume << " m^3\n";
        for (const Repair& r : solid->repairs) text << "  " << r.kind << ": " << r.detail << "\n";
        reporter.note(text.str());
    }
    return solid;
}

MeshReport meshReportOf(const MeshFileFacts& facts, const PhysicsSolid& solid) {
    return {facts, solid.repairs, solid.materialVolume, solid.displacementVolume,
            hollowSpace(solid.openings)};
}

/// The value of `result`, or nothing with its error printed on stderr (the command line's way).
template <class T>
std::optional<T> printingError(Result<T> result) {
    if (!result) {
        std::cerr << "error: " << result.error().message << "\n";
        return std::nullopt;
    }
    return std::move(*result);
}
}  // namespace

Reporter stderrReporter() {
    return {[](const std::string& text) { std::cerr << text; }, stderrProgress};
}

nlohmann::json repairsJson(const std::vector<Repair>& repairs) {
    nlohmann::json out = nlohmann::json::array();
    for (const Repair& r : repairs)
        out.push_back({{"kind", r.kind},
                       {"count", r.count},
                       {"volume_change", r.volumeChange},
                       {"detail", r.detail}});
    return out;
}

Result<TriangleMesh> closedMeshOf(const std::string& path, double unitScale, MeshReport* meshReport,
                                  const Reporter& reporter) {
    MeshFileFacts facts;
    MeshLoadOptions options;
    options.unitScale = unitScale;
    Result<TriangleMesh> mesh = loadMesh(path, options, &facts);
    if (!mesh) return mesh.error();
    ValidationReport report = validateMesh(*mesh);
    // The exact integrals never look at UVs: their problems are noise here.
    std::erase_if(report.problems, [](const Problem& p) { return isUvProblem(p.kind); });
    if (!report.problems.empty()) reporter.note(report.format());
    Result<PhysicsSolid> solid = solidOrRepair(*mesh, report, path, reporter);
    if (!solid) return solid.error();
    if (meshReport) *meshReport = meshReportOf(facts, *solid);
    return std::move(solid->mesh);
}

std::optional<TriangleMesh> loadClosedMesh(const std::string& path, double unitScale,
                                           MeshReport* meshReport) {
    return printingError(closedMeshOf(path, unitScale, meshReport, stderrReporter()));
}

Result<BakeableMesh> bakeableMeshOf(const std::string& path, const BakeOptions& options,
                                    const Reporter& reporter) {
    MeshFileFacts facts;
    MeshLoadOptions loadOptions;
    loadOptions.unitScale = options.unitScale;
    Result<TriangleMesh> loaded = loadMesh(path, loadOptions, &facts);
    if (!loaded) return loaded.error();
    const ValidationReport surfaceReport = validateMesh(*loaded);
    ValidationReport surface = surfaceReport;  // what the atlas cannot fix
    std::erase_if(surface.problems, [](const Problem& p) { return isUvProblem(p.kind); });
    Result<PhysicsSolid> solid = solidOrRepair(*loaded, surface, path, reporter);
    if (!solid) {
        reporter.note(surface.format());
        return solid.error();
    }
    // A repaired solid has no UVs of its own: its report is the solid's.
    const ValidationReport report =
        solid->repairs.empty() ? surfaceReport : validateMesh(solid->mesh);
    AtlasSettings atlas;
    atlas.textureSize = options.size;
    atlas.progress = reporter.progressFor("generating a physics atlas");
    Result<AtlasChoice> choice = chooseAtlas(solid->mesh, report, options.atlas, atlas);
    if (!choice) return choice.error();
    // The UV findings are moot when a generated atlas replaces the UVs; the rest is worth saying.
    ValidationReport shown = choice->generated ? surface : surfaceReport;
    if (!shown.problems.empty()) reporter.note(shown.format());
    if (!choice->notice.empty()) reporter.note("note: " + choice->notice + "\n");
    return BakeableMesh{std::move(choice->mesh), choice->generated, meshReportOf(facts, *solid)};
}

std::optional<BakeableMesh> loadMeshForBake(const std::string& path, const BakeOptions& options) {
    return printingError(bakeableMeshOf(path, options, stderrReporter()));
}

nlohmann::json vectorJson(const Eigen::Vector3d& v) { return {v.x(), v.y(), v.z()}; }

std::string reportJson(const nlohmann::json& report, int indent) {
    return report.dump(indent, ' ', false, nlohmann::json::error_handler_t::replace);
}

std::optional<Eigen::Vector3d> parseVector(const std::string& text) {
    Eigen::Vector3d v;
    const char* cursor = text.data();
    const char* const end = text.data() + text.size();
    for (int k = 0; k < 3; ++k) {
        const char* const fieldEnd = k < 2 ? std::find(cursor, end, ',') : end;
        if (fieldEnd == end && k < 2) return std::nullopt;
        const auto [stop, ec] = std::from_chars(cursor, fieldEnd, v[k]);
        if (ec != std::errc{} || stop != fieldEnd || !std::isfinite(v[k])) return std::nullopt;
        cursor = fieldEnd + 1;
    }
    return v;
}

CLI::Option* addVectorOption(CLI::App& command, const std::string& name, Eigen::Vector3d& target,
                             const std::string& description) {
    return command.add_option_function<std::string>(
        name,
        [name, &target](const std::string& text) {
            std::optional<Eigen::Vector3d> v = parseVector(text);
            if (!v) {
                throw CLI::ValidationError(
                    name, "expected three finite numbers separated by commas, got '" + text + "'");
            }
            target = *v;
        },
        description);
}

Result<std::size_t> bodyIndexOf(const Project& project, const std::string& name,
                                const std::string& projectPath) {
    if (project.bodies.empty())
        return makeError(ErrorKind::invalidArgument, projectPath + ": the project has no bodies");
    if (name.empty()) return std::size_t{0};
    for (std::size_t i = 0; i < project.bodies.size(); ++i)
        if (project.bodies[i].name == name) return i;
    std::string names;
    for (const BodyDesc& b : project.bodies) names += (names.empty() ? "'" : ", '") + b.name + "'";
    return makeError(ErrorKind::invalidArgument,
                     projectPath + ": no body named '" + name + "' (the bodies: " + names + ")");
}

std::optional<std::size_t> bodyIndexByName(const Project& project, const std::string& name,
                                           const std::string& projectPath) {
    return printingError(bodyIndexOf(project, name, projectPath));
}

/// Evaluates through a buoyancy backend on the baked textures. The first evaluate uploads the
/// body, so a second one is timed: that is what every later frame costs.
ProgressCallback stderrProgress(const std::string& label) {
    if (!::isatty(STDERR_FILENO)) return {};
    return [label, last = -1](double fraction) mutable {
        const int percent = static_cast<int>(fraction * 100.0);
        if (percent == last) return;
        last = percent;
        std::fprintf(stderr, "\r%s %3d%%%s", label.c_str(), percent, percent >= 100 ? "\n" : "");
        std::fflush(stderr);
    };
}

CLI::Option* addBakeOptions(CLI::App& command, BakeOptions& options) {
    command
        .add_option("--max-texel-stretch", options.maxTexelStretch,
                    "Sub-texel refinement where the UV map squeezes surface: cut triangles whose "
                    "texels span more than this many typical texel sides (0 = off)")
        ->check(kFiniteNonNegative)
        ->capture_default_str();
    command.add_option_function<std::string>(
        "--atlas",
        [&options](const std::string& text) {
            std::optional<AtlasMode> mode = parseAtlasMode(text);
            if (!mode) {
                throw CLI::ValidationError("--atlas",
                                           "expected mesh, auto or generate, got '" + text + "'");
            }
            options.atlas = *mode;
        },
        "UVs to bake: mesh (the mesh's own; refused when not bijective), auto (the mesh's "
        "when bijective, else generated) or generate (a physics atlas) [auto]");
    return command.add_option("--size", options.size, "Texels per side of the bake")
        ->check(CLI::Range(kMinTextureSize, kMaxTextureSize))
        ->capture_default_str();
}

Result<SurfaceTextures> bakeTextures(const TriangleMesh& mesh, const BakeOptions& options,
                                     const Reporter& reporter) {
    BakeSettings settings;
    settings.size = options.size;
    settings.maxTexelStretch = options.maxTexelStretch;
    // The cost is said before it is spent (bake_cost.h).
    if (const std::string cost = describeBakeCost(mesh, options.size); !cost.empty())
        reporter.note("note: " + cost + "\n");
    settings.progress = reporter.progressFor("baking " + std::to_string(options.size) + "^2");
    return bakeSurfaceTextures(mesh, settings);
}

std::optional<SurfaceTextures> bakeWithProgress(const TriangleMesh& mesh,
                                                const BakeOptions& options) {
    return printingError(bakeTextures(mesh, options, stderrReporter()));
}

std::string xmlEscaped(const std::string& text) {
    std::string out;
    // A name or a message from any file may hold bytes that are not UTF-8 (the document says
    // it is): each becomes U+FFFD.
    for (const char c : validUtf8(text)) {
        switch (c) {
            case '&':
                out += "&amp;";
                break;
            case '<':
                out += "&lt;";
                break;
            case '>':
                out += "&gt;";
                break;
            case '"':
                out += "&quot;";
                break;
            case '\'':
                out += "&apos;";
                break;
            default:
                // XML 1.0 admits no control characters but tab, newline and carriage return.
                if (static_cast<unsigned char>(c) < 0x20 && c != '\t' && c != '\n' && c != '\r')
                    out += ' ';
                else
                    out += c;
        }
    }
    return out;
}

}  // namespace plimsoll::cli
