// plimsoll export PROJECT... --out DIR [--jobs N] [--check] [--force] [--shard K/N]
//                 [--junit FILE] [--quiet] [--summary FILE] [--compact]:
// runtime bundles (bundle.h, docs/bundle.md), one folder per body: DIR/<project>/<body>/.
// A body whose bundle on disk was made from the same inputs (manifest input_sha256) is kept
// as it is, unless --force. With --check nothing is written: exits 1 naming every file an
// export would change. --shard K/N exports only this CI shard's bodies; --junit writes one
// test case per body. The summary JSON goes to stdout (and to --summary FILE); progress (on a
// terminal, or with --progress) and errors to stderr. --compact stores the samples and images
// as half floats (docs/bundle.md "Compact bundles"). --web also writes the three.js viewer page
// (web/viewer, assembled by scripts/build-web.sh) into OUT with bundles.json naming the bodies.
#include "cli/commands.h"

#include "cli/common.h"
#include "cli/jobs.h"

#include "plimsoll/export/bundle.h"
#include "plimsoll/io/file_util.h"
#include "plimsoll/io/json_depth.h"
#include "plimsoll/project/project.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdlib>
#include <iomanip>
#include <iostream>
#include <memory>
#include <mutex>
#include <sstream>
#include <thread>

#include <unistd.h>

namespace plimsoll::cli {

namespace {

namespace fs = std::filesystem;

struct ExportOptions {
    std::vector<std::string> projects;
    std::string out;
    std::string summary;
    std::string shard;  ///< "K/N" or empty
    std::string junit;
    int jobs = 1;
    bool check = false;
    bool force = false;
    bool compact = false;
    bool quiet = false;
    bool progress = false;
    bool web = false;
};

struct Task {
    std::size_t project = 0, body = 0;
    fs::path folder;
    std::string key;  ///< "<project folder>/<body folder>": what --shard splits by
    Result<BundleReport> result = makeError(ErrorKind::invalidArgument, "not run");
    double seconds = 0;
};

/// Shard K of N (1 <= K <= N), parsed from "K/N".
struct Shard {
    std::uint64_t index = 1, count = 1;
};

Result<Shard> parseShard(const std::string& text) {
    const std::string problem = "--shard \"" + text + "\": expected K/N with 1 <= K <= N";
    const std::size_t slash = text.find('/');
    if (slash == std::string::npos || slash == 0 || slash + 1 == text.size())
        return makeError(ErrorKind::invalidArgument, problem);
    auto number = [](const std::string& digits, std::uint64_t& value) {
        if (digits.empty() || digits.size() > 6 ||
            digits.find_first_not_of("0123456789") != std::string::npos)
            return false;
        value = std::stoull(digits);
        return true;
    };
    Shard shard;
    if (!number(text.substr(0, slash), shard.index) ||
        !number(text.substr(slash + 1), shard.count) || shard.index < 1 ||
        shard.index > shard.count)
        return makeError(ErrorKind::invalidArgument, problem);
    return shard;
}

/// The shard (1..count) a body belongs to: the first 8 bytes of the SHA-256 of its key, so a
/// body stays in its shard whatever other bodies are added or removed, on every machine.
std::uint64_t shardOf(const std::string& key, std::uint64_t count) {
    const std::string hex = sha256Hex(key).substr(0, 16);
    return std::stoull(hex, nullptr, 16) % count + 1;
}

/// Seconds as JUnit's `time` (xs:decimal: no exponent).
std::string junitTime(double seconds) {
    std::ostringstream out;
    out << std::fixed << std::setprecision(3) << seconds;
    return out.str();
}

/// JUnit XML as Jenkins, GitLab and GitHub's test reporters read it: one <testsuite> per
/// project, one <testcase> per body (classname = the project's folder, name = the body's),
/// a <failure> with the error message for a body that failed (or, with --check, is out of
/// date).
std::string junitXml(const std::vector<Task>& tasks, const std::vector<std::string>& folders,
                     bool check, double seconds) {
    std::ostringstream suites;
    std::size_t allFailures = 0, allTests = 0;
    for (std::size_t p = 0; p < folders.size(); ++p) {
        std::ostringstream cases;
        std::size_t tests = 0, failures = 0;
        double time = 0;
        for (const Task& t : tasks) {
            if (t.project != p) continue;
            ++tests;
            time += t.seconds;
            cases << "    <testcase classname=\"" << xmlEscaped(folders[p]) << "\" name=\""
                  << xmlEscaped(t.folder.filename().string()) << "\" time=\""
                  << junitTime(t.seconds) << "\"";
            std::string failure;
            if (!t.result)
                failure = t.result.error().message;
            else if (check && !t.result->outOfDate.empty()) {
                failure = "out of date:";
                for (const std::string& f : t.result->outOfDate) failure += " " + f;
            }
            if (failure.empty()) {
                cases << "/>\n";
            } else {
                ++failures;
                cases << ">\n      <failure message=\"" << xmlEscaped(failure) << "\" type=\""
                      << (t.result ? "out_of_date" : errorKindName(t.result.error().kind)) << "\">"
                      << xmlEscaped(failure) << "</failure>\n    </testcase>\n";
            }
        }
        if (tests == 0) continue;  // another shard's project
        allTests += tests;
        allFailures += failures;
        suites << "  <testsuite name=\"" << xmlEscaped(folders[p]) << "\" tests=\"" << tests
               << "\" failures=\"" << failures << "\" errors=\"0\" skipped=\"0\" time=\""
               << junitTime(time) << "\">\n"
               << cases.str() << "  </testsuite>\n";
    }
    std::ostringstream xml;
    xml << "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<testsuites name=\"plimsoll "
        << (check ? "export --check" : "export") << "\" tests=\"" << allTests << "\" failures=\""
        << allFailures << "\" errors=\"0\" time=\"" << junitTime(seconds) << "\">\n"
        << suites.str() << "</testsuites>\n";
    return xml.str();
}

Status writeTextFile(const std::string& path, const std::string& text) {
    return writeFileAtomically(path, [&](std::ostream& out) {
        out << text;
        return static_cast<bool>(out);
    });
}

/// The viewer page --web copies: $PLIMSOLL_WEB_VIEWER, else build-web/viewer in the clone whose
/// build folder holds this executable (build/editor/plimsoll), where scripts/build-web.sh puts it.
/// Found at run time, so that nothing path-dependent is compiled in.
Result<fs::path> findWebViewer() {
    std::vector<fs::path> places;
    if (const char* env = std::getenv("PLIMSOLL_WEB_VIEWER"); env && *env) {
        places.emplace_back(env);
    } else {
        std::error_code ec;
        const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
        if (!ec)
            places.push_back(exe.parent_path().parent_path().parent_path() / "build-web" /
                             "viewer");
    }
    std::string looked;
    for (const fs::path& p : places) {
        if (fs::is_regular_file(p / "index.html") && fs::is_regular_file(p / "viewer.js")) return p;
        looked += (looked.empty() ? "" : ", ") + p.string();
    }
    return makeError(
        ErrorKind::io,
        "export --web: no built web viewer (index.html and viewer.js) in " +
            (looked.empty() ? std::string("any known place") : looked) +
            ": run scripts/build-web.sh, or set PLIMSOLL_WEB_VIEWER to the viewer's folder");
}

/// The viewer's files into `out`, and bundles.json listing the bundle folders (relative to out).
Status writeWebViewer(const fs::path& viewer, const fs::path& out,
                      const std::vector<std::string>& bundles) {
    std::error_code ec;
    fs::copy(viewer, out, fs::copy_options::recursive | fs::copy_options::overwrite_existing, ec);
    if (ec)
        return makeError(ErrorKind::io, "export --web: cannot copy " + viewer.string() + " to " +
                                            out.string() + ": " + ec.message());
    return writeTextFile((out / "bundles.json").string(),
                         nlohmann::json{{"bundles", bundles}}.dump(2) + "\n");
}

/// The projects, each loaded and given its output folder's name; on a failure the error is
/// printed (and, with --junit, reported as one failed case) and nullopt returned.
std::optional<std::vector<Project>> loadExportProjects(const ExportOptions& o,
                                                       std::vector<std::string>& folders) {
    std::vector<Project> projects;
    for (const std::string& path : o.projects) {
        Result<Project> project = loadProject(path);
        if (!project) {
            std::cerr << "error: " << project.error().message << "\n";
            if (!o.junit.empty()) {
                // The dashboard still gets a report: one failed case, "project", for the
                // file that stopped the export before any body ran.
                Task failure;
                failure.folder = "project";
                failure.result = project.error();
                const std::string stem = fs::path(path).filename().string();
                const std::string xml = junitXml({failure}, {stem}, o.check, 0.0);
                if (Status s = writeTextFile(o.junit, xml); !s.ok())
                    std::cerr << "error: " << s.error().message << "\n";
            }
            return std::nullopt;
        }
        folders.push_back(exportFolderName(project->fileStem, folders));
        projects.push_back(std::move(*project));
    }
    return projects;
}

/// One task per body of every project, those of this shard only.
std::vector<Task> exportTasks(const ExportOptions& o, const std::vector<Project>& projects,
                              const std::vector<std::string>& folders, const Shard& shard) {
    std::vector<Task> tasks;
    for (std::size_t p = 0; p < projects.size(); ++p) {
        for (std::size_t b = 0; b < projects[p].bodies.size(); ++b) {
            Task task;
            task.project = p;
            task.body = b;
            task.folder = fs::path(o.out) / folders[p] / bundleFolderName(projects[p], b);
            task.key = folders[p] + "/" + bundleFolderName(projects[p], b);
            if (shardOf(task.key, shard.count) != shard.index) continue;
            tasks.push_back(std::move(task));
        }
    }
    return tasks;
}

/// Runs the tasks on `o.jobs` threads (at most one per task), each exporting or checking its
/// body; progress on stderr where wanted. Returns the number of threads used.
int runExportTasks(const ExportOptions& o, const std::vector<Project>& projects,
                   std::vector<Task>& tasks) {
    // Progress is for a person watching: on by default on a terminal, off in CI logs (where
    // the summary and, with --junit, the JUnit file say what happened).
    const bool progress = !o.quiet && (o.progress || ::isatty(STDERR_FILENO) == 1);
    std::mutex printing;
    auto notice = [&](const std::string& line) {  // the bundle writer's notices and warnings
        if (o.quiet) return;
        std::lock_guard lock(printing);
        std::cerr << line << "\n";
    };
    auto say = [&](const std::string& line) {
        if (progress) notice(line);
    };
    std::atomic<std::size_t> next{0}, done{0};
    auto work = [&] {
        for (std::size_t i; (i = next++) < tasks.size();) {
            Task& t = tasks[i];
            const auto begin = std::chrono::steady_clock::now();
            const Project& project = projects[t.project];
            t.result = exportBody(project, t.body, t.folder, {o.check, o.force, o.compact}, notice);
            t.seconds =
                std::chrono::duration<double>(std::chrono::steady_clock::now() - begin).count();
            const std::string where = "[" + std::to_string(++done) + "/" +
                                      std::to_string(tasks.size()) + "] " + t.folder.string();
            if (!t.result) continue;  // reported below, unconditionally
            if (o.check) {
                say(where + (t.result->outOfDate.empty() ? ": up to date" : ": out of date"));
            } else if (t.result->unchanged) {
                say(where + ": unchanged");
            } else {
                say(where + ": " + std::to_string(t.result->files.size()) + " files, " +
                    std::to_string(t.result->totalBytes()) + " bytes, " +
                    std::to_string(t.seconds) + " s");
            }
        }
    };
    const int jobs = std::clamp<int>(o.jobs, 1, std::max<int>(1, static_cast<int>(tasks.size())));
    std::vector<std::thread> threads;
    for (int j = 1; j < jobs; ++j) threads.emplace_back(work);
    work();
    for (std::thread& t : threads) t.join();
    return jobs;
}

/// What the tasks came to: the summary's "bodies" and the counts (errors and out-of-date files
/// printed on the way).
struct ExportTally {
    bool failed = false, outOfDate = false;
    std::size_t unchanged = 0, failures = 0;
    nlohmann::json bodies = nlohmann::json::array();
};

ExportTally tallyExport(const ExportOptions& o, const std::vector<Project>& projects,
                        const std::vector<Task>& tasks) {
    ExportTally tally;
    for (const Task& t : tasks) {
        nlohmann::json entry = {{"project", o.projects[t.project]},
                                {"body", projects[t.project].bodies[t.body].name},
                                {"folder", t.folder.generic_string()},
                                {"seconds", t.seconds}};
        if (!t.result) {
            tally.failed = true;
            ++tally.failures;
            std::cerr << "error: " << t.result.error().message << "\n";
            entry["status"] = "failed";
            entry["error"] = t.result.error().message;
        } else {
            const BundleReport& r = *t.result;
            entry.update(bundleReportJson(r));
            if (o.check) {
                entry["status"] = r.outOfDate.empty() ? "up_to_date" : "out_of_date";
                entry["out_of_date"] = r.outOfDate;
                for (const std::string& f : r.outOfDate) {
                    std::cerr << "out of date: " << (t.folder / f).generic_string() << "\n";
                }
                tally.outOfDate = tally.outOfDate || !r.outOfDate.empty();
            } else {
                entry["status"] = r.unchanged ? "unchanged" : "written";
                tally.unchanged += r.unchanged;
            }
        }
        tally.bodies.push_back(std::move(entry));
    }
    return tally;
}

int runExport(const ExportOptions& o) {
    const auto start = std::chrono::steady_clock::now();
    Shard shard;
    if (!o.shard.empty()) {
        Result<Shard> parsed = parseShard(o.shard);
        if (!parsed) {
            std::cerr << "error: " << parsed.error().message << "\n";
            return kExitUsage;
        }
        shard = *parsed;
    }
    fs::path viewer;
    if (o.web) {
        if (o.check) {
            std::cerr << "error: export --web writes the viewer page; it cannot go with --check\n";
            return kExitUsage;
        }
        Result<fs::path> found = findWebViewer();
        if (!found) {
            std::cerr << "error: " << found.error().message << "\n";
            return kExitFailure;
        }
        viewer = *found;
    }
    std::vector<std::string> folders;
    const std::optional<std::vector<Project>> projects = loadExportProjects(o, folders);
    if (!projects) return kExitFailure;
    std::vector<Task> tasks = exportTasks(o, *projects, folders, shard);
    const int jobs = runExportTasks(o, *projects, tasks);
    const ExportTally tally = tallyExport(o, *projects, tasks);

    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    const nlohmann::json summary = {
        {"command", o.check ? "check" : "export"},
        {"bundle_schema", {{"major", kBundleSchemaMajor}, {"minor", kBundleSchemaMinor}}},
        {"out", o.out},
        {"jobs", jobs},
        {"ok", !tally.failed && !tally.outOfDate},
        {"shard", o.shard.empty() ? nlohmann::json(nullptr)
                                  : nlohmann::json{{"index", shard.index}, {"count", shard.count}}},
        {"unchanged", tally.unchanged},
        {"seconds", seconds},
        {"bodies", tally.bodies}};
    const std::string text = reportJson(summary) + "\n";
    std::cout << text;
    if (!o.check && !o.quiet) {
        // Said even in CI: that a run rewrote nothing is the point of the skip.
        const std::size_t unchanged = tally.unchanged, failures = tally.failures;
        std::cerr << (unchanged == tasks.size() && !tasks.empty()
                          ? "export: all " + std::to_string(unchanged) +
                                " bundles unchanged, nothing rewritten"
                          : "export: " + std::to_string(tasks.size() - unchanged - failures) +
                                " of " + std::to_string(tasks.size()) + " bundles written, " +
                                std::to_string(unchanged) + " unchanged" +
                                (failures ? ", " + std::to_string(failures) + " failed" : ""))
                  << "\n";
    }
    for (const auto& [path, content] :
         {std::pair{o.summary, text},
          std::pair{o.junit, o.junit.empty() ? std::string()
                                             : junitXml(tasks, folders, o.check, seconds)}}) {
        if (path.empty()) continue;
        if (Status s = writeTextFile(path, content); !s.ok()) {
            std::cerr << "error: " << s.error().message << "\n";
            return kExitFailure;
        }
    }
    if (o.web && !tally.failed) {
        std::vector<std::string> bundles;
        for (const Task& t : tasks) bundles.push_back(t.key);
        if (Status s = writeWebViewer(viewer, o.out, bundles); !s.ok()) {
            std::cerr << "error: " << s.error().message << "\n";
            return kExitFailure;
        }
    }
    return tally.failed || tally.outOfDate ? kExitFailure : kExitOk;
}

}  // namespace

std::string exportFolderName(const std::string& fileStem, const std::vector<std::string>& taken) {
    // Two projects with one file stem get "-2", "-3", ... in the order given. The stem is
    // made a safe name: a project named "...plim.json" must not export to OUT/.. .
    const std::string stem = safeFileName(fileStem, "project");
    std::string folder = stem;
    for (int k = 2; std::find(taken.begin(), taken.end(), folder) != taken.end(); ++k)
        folder = stem + "-" + std::to_string(k);
    return folder;
}

Result<BundleReport> exportBody(const Project& project, std::size_t body, const fs::path& folder,
                                const ExportMode& mode,
                                const std::function<void(const std::string&)>& notice) {
    const BundleOptions bundle{mode.compact};
    if (mode.check) return checkBodyBundle(project, body, folder, bundle);
    if (!mode.force) {
        if (std::optional<BundleReport> kept = unchangedBodyBundle(project, body, folder, bundle))
            return std::move(*kept);
    }
    return writeBodyBundle(project, body, folder, notice, bundle);
}

nlohmann::json bundleReportJson(const BundleReport& r) {
    nlohmann::json files = nlohmann::json::array();
    for (const BundleFile& f : r.files)
        files.push_back({{"path", f.path}, {"sha256", f.sha256}, {"bytes", f.bytes}});
    nlohmann::json entry;
    entry["texture_size"] = r.textureSize;
    if (r.tolerance) {
        entry["tolerance"] = *r.tolerance;
        entry["force_error"] = r.forceError;
    }
    entry["covered_texels"] = r.coveredTexels;
    entry["bytes"] = r.totalBytes();
    entry["files"] = files;
    return entry;
}

void addExportCommand(CLI::App& root, CommandRunner& selected) {
    auto o = std::make_shared<ExportOptions>();
    CLI::App* command = root.add_subcommand(
        "export", "Runtime bundles for game engines: one folder per body (docs/bundle.md)");
    command->add_option("PROJECT", o->projects, "Project files (*.plim.json)")->required();
    command->add_option("--out", o->out, "Export folder: OUT/<project>/<body>/")
        ->required()
        ->check(kNonEmptyPath);
    command->add_option("--jobs", o->jobs, "Bodies exported in parallel")
        ->check(CLI::Range(1, 256))
        ->capture_default_str();
    command->add_flag("--check", o->check,
                      "Write nothing; exit 1 naming each file an export would change");
    command->add_flag("--force", o->force,
                      "Rewrite every bundle, even those made from unchanged inputs");
    command->add_option("--shard", o->shard,
                        "K/N: export only the bodies of CI shard K of N (a stable split by "
                        "project and body name; the N shards together export every body once)");
    command
        ->add_option("--junit", o->junit, "Also write a JUnit XML report: one test case per body")
        ->check(kNonEmptyPath);
    command->add_flag("--compact", o->compact,
                      "Half-float samples and images (about half the size; accuracy in "
                      "docs/bundle.md \"Compact bundles\")");
    command->add_flag(
        "--web", o->web,
        "Also write the three.js viewer page into OUT (index.html, bundles.json; "
        "web/README.md): the one scripts/build-web.sh builds, or $PLIMSOLL_WEB_VIEWER");
    command->add_flag("--quiet", o->quiet, "No progress lines or tally on stderr");
    command->add_flag("--progress", o->progress,
                      "Progress lines on stderr even when it is not a terminal");
    command->add_option("--summary", o->summary, "Also write the summary JSON to this file")
        ->check(kNonEmptyPath);
    command->callback([o, &selected] { selected = [o] { return runExport(*o); }; });
}

}  // namespace plimsoll::cli
