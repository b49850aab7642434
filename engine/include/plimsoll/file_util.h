// Safe writing: content goes to a temporary file beside the target, which is renamed over the
// target only once it was written completely, so an interrupted or failed write never destroys
// what was saved before.
#pragma once

#include "plimsoll/result.h"

#include <cstdint>
#include <filesystem>
#include <functional>
#include <ostream>
#include <string>
#include <utility>
#include <vector>

namespace plimsoll {

/// Calls write(stream) on a temporary file next to `target`, then renames it over `target`.
/// write returns false (or the stream fails) to abandon the write; the target is untouched.
Status writeFileAtomically(const std::filesystem::path& target,
                           const std::function<bool(std::ostream&)>& write);

/// The same for writers that need a file name (libraries that open files themselves):
/// write(tempPath) fills the temporary file; on success it is renamed over `target`.
Status replaceFileAtomically(const std::filesystem::path& target,
                             const std::function<Status(const std::filesystem::path&)>& write);

/// Several files replaced as one (a bake folder's images and manifest): every file is written
/// to its temporary first, and a failure there changes nothing; then each is renamed over its
/// target, the previous version kept aside (a hard link) until all are in place, so a failed
/// rename puts the previous files back. Each writer fills the temporary path it is given.
using FileWriter = std::pair<std::filesystem::path,
                             std::function<Status(const std::filesystem::path&)>>;
Status replaceFilesTogether(const std::vector<FileWriter>& files);
/// The writer of a file whose bytes are known up front (a PNG, a JSON text).
FileWriter bytesFileWriter(const std::filesystem::path& target, std::string bytes);

/// Reads a whole file (JSON read in one piece), refusing one larger than `maxBytes` before
/// reading it: "PATH: 3.1 GB, more than the limit NAME = 256.0 MB (limits.h)".
Result<std::string> readWholeFile(const std::filesystem::path& path, std::uint64_t maxBytes,
                                  const char* limitName);

/// Every step of a writer that can fail on a real disk (a temporary file written, a rename, a
/// file written into a staging folder) passes through here first: Ok, or the failure injected
/// by failFileStepForTesting. `what` and `path` name the step in the injected error.
Status fileStep(const char* what, const std::filesystem::path& path);

/// Fault injection for tests: the k-th fileStep from now fails (k >= 1; 0 turns it off), once,
/// the way a full disk or a failed rename would. A test repeats an operation with k = 1, 2, ...
/// until it succeeds, so every step of it is interrupted once.
void failFileStepForTesting(int k);

/// Test hook: called after the temporary file is complete and before it is renamed over the
/// target (a test can end the process there to prove that an interrupted save keeps the previous
/// file). Empty by default; not for production use.
using BeforeReplaceHook = std::function<void(const std::filesystem::path& temp,
                                             const std::filesystem::path& target)>;
void setBeforeReplaceHookForTesting(BeforeReplaceHook hook);

/// Temporary path used for `target` (same folder, hidden, unique to this process).
std::filesystem::path temporaryPathFor(const std::filesystem::path& target);

}  // namespace plimsoll
