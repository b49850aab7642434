#include "plimsoll/io/file_util.h"
#include "plimsoll/io/json_depth.h"

#include "plimsoll/core/limits.h"

#include "io/test_hooks.h"
#include "io/temporary_file.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <atomic>
#include <cstdio>
#include <iterator>
#include <cerrno>
#include <cstring>
#include <streambuf>
#include <fcntl.h>
#include <fstream>
#include <mutex>
#include <sys/stat.h>
#include <system_error>
#include <unistd.h>
#include <vector>

namespace plimsoll {

namespace fs = std::filesystem;

namespace {
BeforeReplaceHook& beforeReplaceHook() {
    static BeforeReplaceHook hook;
    return hook;
}
FileStepHook& fileStepHook() {
    static FileStepHook hook;
    return hook;
}

std::string systemMessage(int error) {
    return std::error_code(error, std::generic_category()).message();
}

/// What a file that is not a regular one is, for messages.
const char* fileTypeName(mode_t mode) {
    if (S_ISDIR(mode)) return "a folder";
    if (S_ISFIFO(mode)) return "a FIFO";
    if (S_ISCHR(mode)) return "a character device";
    if (S_ISBLK(mode)) return "a block device";
    if (S_ISSOCK(mode)) return "a socket";
    return "not a plain file";
}

/// Opens `path` for reading without blocking (a FIFO with no writer would block the open) and
/// checks on the descriptor that it is a regular file. Returns the descriptor and its size.
Result<std::pair<int, std::uint64_t>> openRegular(const fs::path& path) {
    const std::string name = path.string();
    if (name.find('\0') != std::string::npos)
        return makeError(ErrorKind::invalidArgument,
                         "'" + std::string(name.c_str()) + "...': the path holds a NUL byte");
    const int fd = ::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC | O_NOCTTY);
    if (fd < 0) {
        const int error = errno;
        if (error == ENOENT) return makeError(ErrorKind::io, name + ": no such file");
        return makeError(ErrorKind::io, name + ": cannot open: " + systemMessage(error));
    }
    struct stat st {};
    if (::fstat(fd, &st) != 0) {
        const int error = errno;
        ::close(fd);
        return makeError(ErrorKind::io, name + ": cannot read: " + systemMessage(error));
    }
    if (!S_ISREG(st.st_mode)) {
        ::close(fd);
        if (S_ISDIR(st.st_mode))
            return makeError(ErrorKind::io, name + ": is a folder, not a file");
        return makeError(ErrorKind::io,
                         name + ": is " + fileTypeName(st.st_mode) + ", not a regular file");
    }
    return std::pair<int, std::uint64_t>{fd, static_cast<std::uint64_t>(st.st_size)};
}

/// 0666 less the process's umask, read once (umask can only be read by setting it).
mode_t createdFileMode() {
    static const mode_t mode = [] {
        const mode_t mask = ::umask(022);
        ::umask(mask);
        return static_cast<mode_t>(0666 & ~mask);
    }();
    return mode;
}

/// An output buffer over a descriptor that keeps the errno of its first failed write, so that
/// a failed save names its cause ("No space left on device", "File too large"), and closes
/// the descriptor.
class DescriptorBuffer : public std::streambuf {
public:
    explicit DescriptorBuffer(int fd) : fd_(fd), buffer_(1 << 16) {
        setp(buffer_.data(), buffer_.data() + buffer_.size());
    }
    ~DescriptorBuffer() override { ::close(fd_); }
    DescriptorBuffer(const DescriptorBuffer&) = delete;
    DescriptorBuffer& operator=(const DescriptorBuffer&) = delete;

    int error() const { return error_; }

protected:
    int_type overflow(int_type c) override {
        if (!drain()) return traits_type::eof();
        if (!traits_type::eq_int_type(c, traits_type::eof())) {
            *pptr() = traits_type::to_char_type(c);
            pbump(1);
        }
        return traits_type::not_eof(c);
    }
    int sync() override { return drain() ? 0 : -1; }

private:
    bool drain() {
        for (const char* at = pbase(); at < pptr();) {
            if (error_ != 0) return false;
            const ssize_t k = ::write(fd_, at, static_cast<std::size_t>(pptr() - at));
            if (k < 0 && errno == EINTR) continue;
            if (k <= 0)
                error_ = k < 0 ? errno : ENOSPC;  // 0 bytes written: nothing more fits
            else
                at += k;
        }
        setp(buffer_.data(), buffer_.data() + buffer_.size());
        return error_ == 0;
    }

    int fd_;
    std::vector<char> buffer_;
    int error_ = 0;
};

/// Writes `write`'s stream into the open temporary `fd` (closing it), then flushes to disk.
Status writeThroughDescriptor(int fd, const fs::path& target,
                              const std::function<bool(std::ostream&)>& write) {
    DescriptorBuffer buffer(fd);
    std::ostream out(&buffer);
    if (!write(out)) return makeError(ErrorKind::io, target.string() + ": write abandoned");
    out.flush();
    int error = buffer.error();
    if (error == 0 && !out) error = EIO;
    if (error == 0 && ::fdatasync(fd) != 0) error = errno;
    if (error != 0)
        return makeError(ErrorKind::io,
                         target.string() + ": write failed: " + systemMessage(error));
    return Ok{};  // the buffer closes fd
}

Result<int> createTemporaryDescriptor(const fs::path& target, fs::path& temp) {
    const fs::path dir = target.parent_path();
    std::string pattern = (dir.empty() ? fs::path(".") : dir).string() + "/." +
                          target.filename().string() + ".tmp-XXXXXX";
    // mkstemp: O_CREAT | O_EXCL with a random name, so nothing planted there is followed.
    const int fd = ::mkostemp(pattern.data(), O_CLOEXEC);
    if (fd < 0) {
        const int error = errno;
        return makeError(ErrorKind::io, target.string() + ": cannot create a temporary file: " +
                                            systemMessage(error));
    }
    ::fchmod(fd, createdFileMode());
    temp = pattern;
    return fd;
}
}  // namespace

Status checkReplaceable(const fs::path& target) {
    struct stat st {};
    if (::lstat(target.c_str(), &st) != 0) {
        const int error = errno;
        if (error == ENOENT) return Ok{};
        return makeError(ErrorKind::io,
                         target.string() + ": cannot write: " + systemMessage(error));
    }
    if (S_ISREG(st.st_mode)) return Ok{};
    // A rename over a link, a device node or a FIFO replaces the node itself (run as root,
    // `--out /dev/null` would replace /dev/null): only regular files are replaced.
    const char* type = S_ISLNK(st.st_mode) ? "a symbolic link" : fileTypeName(st.st_mode);
    return makeError(ErrorKind::io, target.string() + ": is " + std::string(type) +
                                        ", not a regular file: not replaced (name a new or a "
                                        "regular file)");
}

static std::atomic<bool> exchangeDisabled{false};

void disableRenameExchangeForTesting(bool disabled) { exchangeDisabled = disabled; }

namespace {
/// Folders left aside by an interrupted fallback swap of `target`: ".NAME.old-*" beside it.
std::vector<fs::path> foldersSetAside(const fs::path& target) {
    std::vector<fs::path> found;
    const std::string prefix = "." + target.filename().string() + ".old-";
    std::error_code ec;
    const fs::path parent = target.parent_path().empty() ? fs::path(".") : target.parent_path();
    for (fs::directory_iterator it(parent, ec), end; !ec && it != end; it.increment(ec)) {
        const std::string name = it->path().filename().string();
        if (name.rfind(prefix, 0) == 0 && it->is_directory(ec) && !it->is_symlink(ec))
            found.push_back(it->path());
    }
    std::sort(found.begin(), found.end());
    return found;
}
}  // namespace

Status restoreInterruptedFolderSwap(const fs::path& target) {
    std::error_code ec;
    if (fs::exists(fs::symlink_status(target, ec))) return Ok{};
    const std::vector<fs::path> aside = foldersSetAside(target);
    if (aside.empty()) return Ok{};
    // The fallback swap moved the previous folder aside and died before the new one took its
    // place: the previous one goes back.
    if (::rename(aside.back().c_str(), target.c_str()) != 0)
        return makeError(ErrorKind::io,
                         target.string() + ": cannot restore " + aside.back().string() +
                             " after an interrupted replace: " + systemMessage(errno));
    return Ok{};
}

Status replaceFolder(const fs::path& staging, const fs::path& target, const fs::path& aside) {
    struct stat st {};
    const bool hadOld = ::lstat(target.c_str(), &st) == 0;
    if (hadOld && (S_ISLNK(st.st_mode) || !S_ISDIR(st.st_mode)))
        return makeError(ErrorKind::io,
                         target.string() + ": is " +
                             (S_ISLNK(st.st_mode) ? "a symbolic link" : fileTypeName(st.st_mode)) +
                             ", not a folder: not replaced");
    if (Status step = fileStep("renaming", target); !step.ok()) return step;
    if (!hadOld) {
        if (::rename(staging.c_str(), target.c_str()) != 0)
            return makeError(ErrorKind::io,
                             target.string() + ": cannot create: " + systemMessage(errno));
        return Ok{};
    }
    // One exchange: readers see the old folder or the new one at the path, never none, and a
    // process killed at any instant leaves a complete folder there.
    if (!exchangeDisabled &&
        ::renameat2(AT_FDCWD, staging.c_str(), AT_FDCWD, target.c_str(), RENAME_EXCHANGE) == 0) {
        std::error_code ec;
        fs::remove_all(staging, ec);  // now the previous folder
        return Ok{};
    }
    const int error = exchangeDisabled ? EINVAL : errno;
    if (error != EINVAL && error != ENOSYS && error != ENOTSUP)
        return makeError(ErrorKind::io,
                         target.string() + ": cannot replace: " + systemMessage(error));
    // Fallback where the file system has no exchange: two renames. Between them the path is
    // missing for a moment; a process killed there leaves the previous folder aside, and
    // restoreInterruptedFolderSwap (run by the next replace or check) puts it back.
    if (::rename(target.c_str(), aside.c_str()) != 0)
        return makeError(ErrorKind::io,
                         target.string() + ": cannot replace: " + systemMessage(errno));
    Status moved = fileStep("renaming", staging);
    if (moved.ok() && ::rename(staging.c_str(), target.c_str()) != 0)
        moved =
            makeError(ErrorKind::io, target.string() + ": cannot replace: " + systemMessage(errno));
    std::error_code ec;
    if (!moved.ok()) {
        ::rename(aside.c_str(), target.c_str());
        return moved;
    }
    fs::remove_all(aside, ec);
    return Ok{};
}

// Steps left before the injected failure; 0: none armed. Atomic: writers may run on threads.
static std::atomic<int> failingStep{0};

Status fileStep(const char* what, const fs::path& path) {
    if (fileStepHook()) fileStepHook()(what, path);
    int left = failingStep.load();
    while (left > 0 && !failingStep.compare_exchange_weak(left, left - 1)) {
    }
    if (left == 1)
        return makeError(ErrorKind::io, path.string() + ": " + what + " failed (injected fault)");
    return Ok{};
}

void failFileStepForTesting(int k) { failingStep = k > 0 ? k : 0; }

void setFileStepHookForTesting(FileStepHook hook) { fileStepHook() = std::move(hook); }

Result<std::string> readWholeFile(const fs::path& path, std::uint64_t maxBytes,
                                  const char* limitName) {
    Result<std::pair<int, std::uint64_t>> opened = openRegular(path);
    if (!opened) return opened.error();
    const auto [fd, size] = *opened;
    auto tooLarge = [&](std::uint64_t bytes) {
        return makeError(ErrorKind::limit, path.string() + ": " + formatBytes(double(bytes)) +
                                               ", more than the limit " + limitName + " = " +
                                               formatBytes(double(maxBytes)) + " (limits.h)");
    };
    if (size > maxBytes) {
        ::close(fd);
        return tooLarge(size);
    }
    std::string bytes(static_cast<std::size_t>(size), '\0');
    std::size_t done = 0;
    // Up to the size fstat gave, then one byte more to see whether the file grew meanwhile.
    for (;;) {
        if (done == bytes.size()) {
            if (bytes.size() >= maxBytes + 1) break;
            bytes.resize(std::min<std::uint64_t>(maxBytes + 1, bytes.size() + (1 << 16)));
        }
        const ssize_t n = ::read(fd, bytes.data() + done, bytes.size() - done);
        if (n < 0 && errno == EINTR) continue;
        if (n < 0) {
            const int error = errno;
            ::close(fd);
            return makeError(ErrorKind::io,
                             path.string() + ": read error: " + systemMessage(error));
        }
        if (n == 0) break;
        done += static_cast<std::size_t>(n);
    }
    ::close(fd);
    if (done > maxBytes) return tooLarge(done);
    bytes.resize(done);
    return bytes;
}

Status checkRegularFile(const fs::path& path) {
    Result<std::pair<int, std::uint64_t>> opened = openRegular(path);
    if (!opened) return opened.error();
    ::close(opened->first);
    return Ok{};
}

std::string safeFileName(const std::string& name, const std::string& prefix) {
    std::string safe = name;
    for (char& c : safe) {
        const bool ok = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') ||
                        (c >= '0' && c <= '9') || c == '.' || c == '_' || c == '-';
        if (!ok) c = '_';
    }
    if (safe.empty() || safe.front() == '.') safe = prefix + safe;
    return safe;
}

Result<fs::path> pathInside(const fs::path& folder, const std::string& relative,
                            const std::string& what) {
    auto leaves = [&](const std::string& why) {
        return makeError(ErrorKind::format, what + " \"" + std::string(relative.c_str()) +
                                                "\" leaves the folder " + folder.string() + " (" +
                                                why + ")");
    };
    if (relative.empty()) return makeError(ErrorKind::format, what + " is empty");
    if (relative.find('\0') != std::string::npos) return leaves("a NUL byte");
    if (relative.find('\\') != std::string::npos) return leaves("a backslash");
    const fs::path p(relative);
    if (p.is_absolute()) return leaves("an absolute path");
    for (const fs::path& part : p) {
        if (part == "..") return leaves("a '..' component");
    }
    return folder / p;
}

Result<fs::path> createTemporaryFor(const fs::path& target) {
    fs::path temp;
    Result<int> fd = createTemporaryDescriptor(target, temp);
    if (!fd) return fd.error();
    ::close(*fd);
    return temp;
}

Result<int> openTemporaryForWriting(const fs::path& temp, const fs::path& target) {
    // No O_TRUNC: a file swapped in under the temporary's name is checked before it is cut.
    const int fd = ::open(temp.c_str(), O_WRONLY | O_NOFOLLOW | O_CLOEXEC | O_NOCTTY | O_NONBLOCK);
    if (fd < 0) {
        const int error = errno;
        return makeError(ErrorKind::io, target.string() + ": cannot open " + temp.string() +
                                            " for writing: " + systemMessage(error));
    }
    struct stat st {};
    if (::fstat(fd, &st) != 0 || !S_ISREG(st.st_mode) || st.st_nlink != 1 ||
        ::ftruncate(fd, 0) != 0) {
        ::close(fd);
        return makeError(ErrorKind::io, target.string() + ": the temporary " + temp.string() +
                                            " was replaced by another file: not written");
    }
    return fd;
}

void setBeforeReplaceHookForTesting(BeforeReplaceHook hook) {
    beforeReplaceHook() = std::move(hook);
}

Status replaceFileAtomically(const fs::path& target,
                             const std::function<Status(const fs::path&)>& write) {
    if (Status step = fileStep("writing", target); !step.ok()) return step;
    if (Status replaceable = checkReplaceable(target); !replaceable.ok()) return replaceable;
    Result<fs::path> temp = createTemporaryFor(target);
    if (!temp) return temp.error();
    Status written = write(*temp);
    std::error_code ec;
    if (!written.ok()) {
        fs::remove(*temp, ec);
        return written;
    }
    if (beforeReplaceHook()) beforeReplaceHook()(*temp, target);
    if (Status step = fileStep("renaming", target); !step.ok()) {
        fs::remove(*temp, ec);
        return step;
    }
    if (::rename(temp->c_str(), target.c_str()) != 0) {
        const int error = errno;
        fs::remove(*temp, ec);
        return makeError(ErrorKind::io,
                         target.string() + ": cannot replace file: " + systemMessage(error));
    }
    return Ok{};
}

namespace {

constexpr const char* kJournalFormat = "plimsoll-replace-journal";

fs::path journalPathFor(const fs::path& lastTarget) {
    return lastTarget.parent_path() / ("." + lastTarget.filename().string() + ".journal");
}

/// Paths in the journal are relative to its folder (so a folder moved after a crash still
/// completes), and only inside it: the writer refuses a target elsewhere, the reader a journal
/// naming one. Empty when `p` is not inside `folder`.
std::string relativeTo(const fs::path& p, const fs::path& folder) {
    const fs::path base = fs::absolute(folder.empty() ? fs::path(".") : folder).lexically_normal();
    const fs::path r = fs::absolute(p).lexically_normal().lexically_relative(base);
    if (r.empty() || r == "." || *r.begin() == "..") return {};
    return r.generic_string();
}

/// `relative`, a path a journal names, resolved inside `folder`: relative, no "..", no
/// backslash or NUL, and no symbolic link among the folders between (a link there would carry
/// the rename elsewhere).
Result<fs::path> journalPathInside(const fs::path& folder, const std::string& relative,
                                   const fs::path& journal) {
    Result<fs::path> inside = pathInside(folder, relative, journal.string() + ": the file");
    if (!inside) return inside.error();
    fs::path walked = folder;
    const fs::path rel(relative);
    for (auto it = rel.begin(); it != rel.end(); ++it) {
        if (std::next(it) == rel.end()) break;  // the file itself: renamed over, never followed
        walked /= *it;
        struct stat st {};
        if (::lstat(walked.c_str(), &st) == 0 && !S_ISDIR(st.st_mode))
            return makeError(ErrorKind::format, journal.string() + ": the file \"" + relative +
                                                    "\" passes through " + walked.string() +
                                                    ", not a folder (a link?)");
    }
    return inside;
}

/// One file of the set: its temporary, its target and the previous version kept aside.
struct JournalEntry {
    fs::path temp, target, backup;
};

/// Renames each remaining temporary over its target and removes the backups and the journal:
/// the completion of a committed set, in this process or after a crash.
Status rollForward(const std::vector<JournalEntry>& entries, const fs::path& journal) {
    std::error_code ec;
    for (const JournalEntry& e : entries) {
        if (!fs::exists(fs::symlink_status(e.temp, ec))) continue;  // renamed before the crash
        if (::rename(e.temp.c_str(), e.target.c_str()) != 0) {
            const int error = errno;
            return makeError(ErrorKind::io,
                             e.target.string() +
                                 ": cannot complete an interrupted save: " + systemMessage(error));
        }
    }
    for (const JournalEntry& e : entries) {
        if (!e.backup.empty()) fs::remove(e.backup, ec);
    }
    fs::remove(journal, ec);
    return Ok{};
}

}  // namespace

Status finishInterruptedReplace(const fs::path& lastTarget) {
    const fs::path journal = journalPathFor(lastTarget);
    std::error_code ec;
    if (!fs::exists(fs::symlink_status(journal, ec))) return Ok{};
    Result<std::string> text = readWholeFile(journal, kMaxJsonFileBytes, "kMaxJsonFileBytes");
    if (!text) return withContext("interrupted save: ", text.error());
    const fs::path folder = lastTarget.parent_path();
    std::vector<JournalEntry> entries;
    if (Status depth = checkJsonDepth(*text, journal.string()); !depth.ok()) return depth;
    try {
        const nlohmann::json j = nlohmann::json::parse(*text);
        if (j.at("format").get<std::string>() != kJournalFormat) throw std::runtime_error("format");
        for (const nlohmann::json& f : j.at("files")) {
            JournalEntry entry;
            for (auto [key, into] :
                 {std::pair{"temp", &entry.temp}, std::pair{"target", &entry.target},
                  std::pair{"backup", &entry.backup}}) {
                const std::string p = f.at(key).get<std::string>();
                if (p.empty() && into == &entry.backup) continue;  // no previous version
                // A journal names files of its own folder only: anything else (an absolute
                // path, "..", a link on the way) is refused before a single file moves.
                Result<fs::path> inside = journalPathInside(folder, p, journal);
                if (!inside)
                    return makeError(ErrorKind::format, inside.error().message +
                                                            ": journal refused, nothing moved "
                                                            "(remove it to load the project)");
                *into = *inside;
            }
            entries.push_back(std::move(entry));
        }
    } catch (const std::exception& e) {
        return makeError(ErrorKind::format, journal.string() +
                                                ": unreadable journal of an interrupted save: " +
                                                boundedExcerpt(e.what(), 200));
    }
    // Only temporaries of this journal's own making are renamed: each must sit beside its
    // target and carry its name, so an edited journal cannot move arbitrary files.
    auto madeFor = [](const fs::path& file, const fs::path& target, const std::string& kind) {
        const std::string prefix = "." + target.filename().string() + kind + ".tmp-";
        return file.parent_path() == target.parent_path() &&
               file.filename().string().rfind(prefix, 0) == 0;
    };
    for (const JournalEntry& e : entries) {
        if (!madeFor(e.temp, e.target, "") ||
            (!e.backup.empty() && !madeFor(e.backup, e.target, ".previous")))
            return makeError(ErrorKind::format, journal.string() + ": names " + e.temp.string() +
                                                    ", not a temporary of " + e.target.string());
    }
    return rollForward(entries, journal);
}

Status replaceFilesTogether(const std::vector<FileWriter>& files) {
    if (files.empty()) return Ok{};
    std::vector<JournalEntry> entries;
    std::error_code ec;
    auto removeTemps = [&] {
        for (const JournalEntry& e : entries) fs::remove(e.temp, ec);
    };
    // The journal names every file relative to the last one's folder: a set reaching outside
    // it is refused before anything is written.
    const fs::path setFolder = files.back().first.parent_path();
    for (const auto& [target, write] : files) {
        if (relativeTo(target, setFolder).empty())
            return makeError(ErrorKind::invalidArgument,
                             target.string() + ": outside " +
                                 (setFolder.empty() ? fs::path(".") : setFolder).string() +
                                 ", the folder of the files it is saved with: not written");
    }
    // Phase 1: every temporary file; the targets are not touched yet.
    for (const auto& [target, write] : files) {
        Status written = fileStep("writing", target);
        if (written.ok()) written = checkReplaceable(target);
        Result<fs::path> temp =
            written.ok() ? createTemporaryFor(target) : Result<fs::path>(written.error());
        if (!temp) {
            removeTemps();
            return temp.error();
        }
        entries.push_back({*temp, target, {}});
        written = write(*temp);
        if (!written.ok()) {
            removeTemps();
            return written;
        }
    }
    // Phase 2: the previous versions kept aside (hard links, so the targets stay in place).
    auto removeBackups = [&] {
        for (const JournalEntry& e : entries) {
            if (!e.backup.empty()) fs::remove(e.backup, ec);
        }
    };
    for (JournalEntry& e : entries) {
        if (!fs::exists(e.target, ec)) continue;
        Result<fs::path> backup = createTemporaryFor(e.target.string() + ".previous");
        if (backup) fs::remove(*backup, ec);  // a unique name, for the link
        if (backup) fs::create_hard_link(e.target, *backup, ec);
        if (backup && ec) fs::copy_file(e.target, *backup, ec);
        if (!backup || ec) {
            removeTemps();
            removeBackups();
            return makeError(ErrorKind::io, e.target.string() +
                                                ": cannot keep the previous version: " +
                                                (backup ? ec.message() : backup.error().message));
        }
        e.backup = *backup;
    }
    // Phase 3: the journal, renamed into place: the commit.
    const fs::path& last = files.back().first;
    const fs::path journal = journalPathFor(last);
    nlohmann::json list = nlohmann::json::array();
    for (const JournalEntry& e : entries) {
        list.push_back(
            {{"temp", relativeTo(e.temp, last.parent_path())},
             {"target", relativeTo(e.target, last.parent_path())},
             {"backup", e.backup.empty() ? "" : relativeTo(e.backup, last.parent_path())}});
    }
    const std::string journalText =
        nlohmann::json{{"format", kJournalFormat}, {"files", list}}.dump(1) + "\n";
    Status committed = replaceFileAtomically(journal, [&](const fs::path& temp) -> Status {
        Result<int> fd = openTemporaryForWriting(temp, journal);
        if (!fd) return fd.error();
        return writeThroughDescriptor(*fd, journal,
                                      [&](std::ostream& out) { return bool(out << journalText); });
    });
    if (!committed.ok()) {
        removeTemps();
        removeBackups();
        return committed;
    }
    // Phase 4: each temporary over its target. A failure puts back what was replaced.
    std::size_t replaced = 0;
    Status failure = Ok{};
    for (; replaced < entries.size(); ++replaced) {
        const JournalEntry& e = entries[replaced];
        if (beforeReplaceHook()) beforeReplaceHook()(e.temp, e.target);
        if (failure = fileStep("renaming", e.target); !failure.ok()) break;
        if (::rename(e.temp.c_str(), e.target.c_str()) != 0) {
            failure =
                makeError(ErrorKind::io,
                          e.target.string() + ": cannot replace file: " + systemMessage(errno));
            break;
        }
    }
    if (!failure.ok()) {
        std::error_code ignored;
        fs::remove(journal, ignored);  // from here on the previous set is the one to keep
        for (std::size_t i = 0; i < replaced; ++i) {
            if (!entries[i].backup.empty())
                fs::rename(entries[i].backup, entries[i].target, ignored);
            else
                fs::remove(entries[i].target, ignored);
        }
        removeTemps();
        removeBackups();
        return failure;
    }
    return rollForward(entries, journal);  // every temporary is gone: backups and journal
}

FileWriter bytesFileWriter(const fs::path& target, std::string bytes) {
    return {target, [target, bytes = std::move(bytes)](const fs::path& temp) -> Status {
                Result<int> fd = openTemporaryForWriting(temp, target);
                if (!fd) return fd.error();
                return writeThroughDescriptor(
                    *fd, target, [&](std::ostream& out) { return bool(out << bytes); });
            }};
}

Status writeFileAtomically(const fs::path& target,
                           const std::function<bool(std::ostream&)>& write) {
    return replaceFileAtomically(target, [&](const fs::path& temp) -> Status {
        // The temporary was created exclusively a moment ago; a link swapped in since is refused.
        Result<int> fd = openTemporaryForWriting(temp, target);
        if (!fd) return fd.error();
        return writeThroughDescriptor(*fd, target, write);
    });
}

}  // namespace plimsoll
