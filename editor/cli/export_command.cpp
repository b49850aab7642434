// plimsoll export PROJECT... --out DIR [--jobs N] [--check] [--quiet] [--summary FILE]:
// runtime bundles (bundle.h, docs/bundle.md), one folder per body: DIR/<project>/<body>/.
// With --check nothing is written: exits 1 naming every file an export would change.
// The summary JSON goes to stdout (and to --summary FILE); progress and errors to stderr.
#include "cli/commands.h"

#include "plimsoll/bundle.h"
#include "plimsoll/file_util.h"
#include "plimsoll/project.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <iostream>
#include <memory>
#include <mutex>
#include <thread>

namespace plimsoll::cli {

namespace {

namespace fs = std::filesystem;

struct ExportOptions {
    std::vector<std::string> projects;
    std::string out;
    std::string summary;
    int jobs = 1;
    bool check = false;
    bool quiet = false;
};

struct Task {
    std::size_t project = 0, body = 0;
    fs::path folder;
    Result<BundleReport> result = makeError("not run");
    double seconds = 0;
};

int runExport(const ExportOptions& o) {
    const auto start = std::chrono::steady_clock::now();
    std::vector<Project> projects;
    std::vector<std::string> folders;
    for (const std::string& path : o.projects) {
        Result<Project> project = loadProject(path);
        if (!project) {
            std::cerr << "error: " << project.error().message << "\n";
            return kExitFailure;
        }
        // Two projects with one file stem get "-2", "-3", ... in the order given.
        std::string folder = project->fileStem;
        for (int k = 2; std::find(folders.begin(), folders.end(), folder) != folders.end(); ++k)
            folder = project->fileStem + "-" + std::to_string(k);
        folders.push_back(folder);
        projects.push_back(std::move(*project));
    }
    std::vector<Task> tasks;
    for (std::size_t p = 0; p < projects.size(); ++p) {
        for (std::size_t b = 0; b < projects[p].bodies.size(); ++b) {
            Task task;
            task.project = p;
            task.body = b;
            task.folder = fs::path(o.out) / folders[p] / bundleFolderName(projects[p], b);
            tasks.push_back(std::move(task));
        }
    }

    std::mutex printing;
    auto say = [&](const std::string& line) {
        if (o.quiet) return;
        std::lock_guard lock(printing);
        std::cerr << line << "\n";
    };
    std::atomic<std::size_t> next{0}, done{0};
    auto work = [&] {
        for (std::size_t i; (i = next++) < tasks.size();) {
            Task& t = tasks[i];
            const auto begin = std::chrono::steady_clock::now();
            t.result = o.check ? checkBodyBundle(projects[t.project], t.body, t.folder)
                               : writeBodyBundle(projects[t.project], t.body, t.folder, say);
            t.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - begin).count();
            const std::string where = "[" + std::to_string(++done) + "/" +
                                      std::to_string(tasks.size()) + "] " + t.folder.string();
            if (!t.result) continue;  // reported below, unconditionally
            if (o.check) {
                say(where + (t.result->outOfDate.empty() ? ": up to date" : ": out of date"));
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

    bool failed = false, outOfDate = false;
    nlohmann::json bodies = nlohmann::json::array();
    for (const Task& t : tasks) {
        nlohmann::json entry = {{"project", o.projects[t.project]},
                                {"body", projects[t.project].bodies[t.body].name},
                                {"folder", t.folder.generic_string()},
                                {"seconds", t.seconds}};
        if (!t.result) {
            failed = true;
            std::cerr << "error: " << t.result.error().message << "\n";
            entry["status"] = "failed";
            entry["error"] = t.result.error().message;
        } else {
            const BundleReport& r = *t.result;
            nlohmann::json files = nlohmann::json::array();
            for (const BundleFile& f : r.files)
                files.push_back({{"path", f.path}, {"sha256", f.sha256}, {"bytes", f.bytes}});
            entry["texture_size"] = r.textureSize;
            entry["covered_texels"] = r.coveredTexels;
            entry["bytes"] = r.totalBytes();
            entry["files"] = files;
            if (o.check) {
                entry["status"] = r.outOfDate.empty() ? "up_to_date" : "out_of_date";
                entry["out_of_date"] = r.outOfDate;
                for (const std::string& f : r.outOfDate) {
                    std::cerr << "out of date: " << (t.folder / f).generic_string() << "\n";
                }
                outOfDate = outOfDate || !r.outOfDate.empty();
            } else {
                entry["status"] = "written";
            }
        }
        bodies.push_back(std::move(entry));
    }
    const nlohmann::json summary = {
        {"command", o.check ? "check" : "export"},
        {"bundle_schema", {{"major", kBundleSchemaMajor}, {"minor", kBundleSchemaMinor}}},
        {"out", o.out},
        {"jobs", jobs},
        {"ok", !failed && !outOfDate},
        {"seconds", std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count()},
        {"bodies", bodies}};
    const std::string text = summary.dump(2) + "\n";
    std::cout << text;
    if (!o.summary.empty()) {
        Status s = writeFileAtomically(o.summary, [&](std::ostream& out) {
            out << text;
            return static_cast<bool>(out);
        });
        if (!s.ok()) {
            std::cerr << "error: " << s.error().message << "\n";
            return kExitFailure;
        }
    }
    return failed || outOfDate ? kExitFailure : kExitOk;
}

}  // namespace

void addExportCommand(CLI::App& root, CommandRunner& selected) {
    auto o = std::make_shared<ExportOptions>();
    CLI::App* command = root.add_subcommand(
        "export", "Runtime bundles for game engines: one folder per body (docs/bundle.md)");
    command->add_option("PROJECT", o->projects, "Project files (*.plim.json)")->required();
    command->add_option("--out", o->out, "Export folder: OUT/<project>/<body>/")->required();
    command->add_option("--jobs", o->jobs, "Bodies exported in parallel")
        ->check(CLI::Range(1, 256))
        ->capture_default_str();
    command->add_flag("--check", o->check,
                      "Write nothing; exit 1 naming each file an export would change");
    command->add_flag("--quiet", o->quiet, "No progress lines on stderr");
    command->add_option("--summary", o->summary, "Also write the summary JSON to this file");
    command->callback([o, &selected] { selected = [o] { return runExport(*o); }; });
}

}  // namespace plimsoll::cli
