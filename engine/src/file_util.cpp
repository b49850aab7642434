#include "plimsoll/file_util.h"

#include "plimsoll/limits.h"

#include <atomic>
#include <fstream>
#include <iterator>
#include <system_error>
#include <unistd.h>

namespace plimsoll {

namespace fs = std::filesystem;

namespace {
BeforeReplaceHook& beforeReplaceHook() {
    static BeforeReplaceHook hook;
    return hook;
}
}  // namespace

// Steps left before the injected failure; 0: none armed. Atomic: writers may run on threads.
static std::atomic<int> failingStep{0};

Status fileStep(const char* what, const fs::path& path) {
    int left = failingStep.load();
    while (left > 0 && !failingStep.compare_exchange_weak(left, left - 1)) {
    }
    if (left == 1) return makeError(path.string() + ": " + what + " failed (injected fault)");
    return Ok{};
}

void failFileStepForTesting(int k) { failingStep = k > 0 ? k : 0; }

Result<std::string> readWholeFile(const fs::path& path, std::uint64_t maxBytes,
                                  const char* limitName) {
    std::error_code ec;
    if (!fs::exists(path, ec)) return makeError(path.string() + ": no such file");
    if (fs::is_directory(path, ec)) return makeError(path.string() + ": is a folder, not a file");
    const std::uintmax_t size = fs::file_size(path, ec);
    if (!ec && size > maxBytes) {
        return makeError(path.string() + ": " + formatBytes(double(size)) +
                         ", more than the limit " + limitName + " = " +
                         formatBytes(double(maxBytes)) + " (limits.h)");
    }
    std::ifstream in(path, std::ios::binary);
    if (!in) return makeError(path.string() + ": cannot open");
    std::string text{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
    if (in.bad()) return makeError(path.string() + ": read error");
    return text;
}

void setBeforeReplaceHookForTesting(BeforeReplaceHook hook) {
    beforeReplaceHook() = std::move(hook);
}

fs::path temporaryPathFor(const fs::path& target) {
    fs::path dir = target.parent_path();
    std::string name = "." + target.filename().string() + ".tmp" + std::to_string(::getpid());
    return dir.empty() ? fs::path(name) : dir / name;
}

Status replaceFileAtomically(const fs::path& target,
                             const std::function<Status(const fs::path&)>& write) {
    const fs::path temp = temporaryPathFor(target);
    Status written = fileStep("writing", temp);
    if (written.ok()) written = write(temp);
    std::error_code ec;
    if (!written.ok()) {
        fs::remove(temp, ec);
        return written;
    }
    if (beforeReplaceHook()) beforeReplaceHook()(temp, target);
    if (Status step = fileStep("renaming", target); !step.ok()) {
        fs::remove(temp, ec);
        return step;
    }
    fs::rename(temp, target, ec);
    if (ec) {
        fs::remove(temp, ec);
        return makeError(target.string() + ": cannot replace file: " + ec.message());
    }
    return Ok{};
}

Status replaceFilesTogether(const std::vector<FileWriter>& files) {
    std::vector<fs::path> temps;
    std::error_code ec;
    auto removeAll = [&](const std::vector<fs::path>& paths) {
        for (const fs::path& p : paths) fs::remove(p, ec);
    };
    // Phase 1: every temporary file; the targets are not touched yet.
    for (const auto& [target, write] : files) {
        temps.push_back(temporaryPathFor(target));
        Status written = fileStep("writing", temps.back());
        if (written.ok()) written = write(temps.back());
        if (!written.ok()) {
            removeAll(temps);
            return written;
        }
    }
    // Phase 2: keep each previous version aside, then rename the new one over it.
    std::vector<fs::path> backups(files.size());
    std::size_t replaced = 0;
    Status failure = Ok{};
    for (; replaced < files.size(); ++replaced) {
        const fs::path& target = files[replaced].first;
        if (beforeReplaceHook()) beforeReplaceHook()(temps[replaced], target);
        if (fs::exists(target, ec)) {
            backups[replaced] = temporaryPathFor(target).string() + ".previous";
            fs::remove(backups[replaced], ec);
            fs::create_hard_link(target, backups[replaced], ec);
            if (ec) fs::copy_file(target, backups[replaced], ec);
            if (ec) {
                failure = makeError(target.string() + ": cannot keep the previous version: " +
                                    ec.message());
                backups[replaced].clear();
                break;
            }
        }
        if (failure = fileStep("renaming", target); !failure.ok()) break;
        fs::rename(temps[replaced], target, ec);
        if (ec) {
            failure = makeError(target.string() + ": cannot replace file: " + ec.message());
            break;
        }
    }
    if (!failure.ok()) {
        // Put back what was replaced (and remove files that did not exist before).
        std::error_code ignored;
        for (std::size_t i = 0; i < replaced; ++i) {
            if (!backups[i].empty()) fs::rename(backups[i], files[i].first, ignored);
            else fs::remove(files[i].first, ignored);
        }
        if (replaced < files.size() && !backups[replaced].empty())
            fs::remove(backups[replaced], ignored);
        for (std::size_t i = replaced; i < temps.size(); ++i) fs::remove(temps[i], ignored);
        return failure;
    }
    for (const fs::path& b : backups) {
        if (!b.empty()) fs::remove(b, ec);
    }
    return Ok{};
}

FileWriter bytesFileWriter(const fs::path& target, std::string bytes) {
    return {target, [target, bytes = std::move(bytes)](const fs::path& temp) -> Status {
                std::ofstream out(temp, std::ios::binary | std::ios::trunc);
                if (!out) return makeError(target.string() + ": cannot open for writing");
                out << bytes;
                out.close();
                if (!out) return makeError(target.string() + ": write failed (disk full?)");
                return Ok{};
            }};
}

Status writeFileAtomically(const fs::path& target,
                           const std::function<bool(std::ostream&)>& write) {
    return replaceFileAtomically(target, [&](const fs::path& temp) -> Status {
        std::ofstream out(temp, std::ios::binary | std::ios::trunc);
        if (!out) return makeError(target.string() + ": cannot open for writing");
        if (!write(out)) return makeError(target.string() + ": write abandoned");
        out.flush();
        if (!out) return makeError(target.string() + ": write failed (disk full?)");
        return Ok{};
    });
}

}  // namespace plimsoll
