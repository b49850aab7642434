// Safe writing: content goes to a temporary file beside the target, which is renamed over the
// target only once it was written completely, so an interrupted or failed write never destroys
// what was saved before.
#pragma once

#include "plimsoll/result.h"

#include <filesystem>
#include <functional>
#include <ostream>
#include <string>

namespace plimsoll {

/// Calls write(stream) on a temporary file next to `target`, then renames it over `target`.
/// write returns false (or the stream fails) to abandon the write; the target is untouched.
Status writeFileAtomically(const std::filesystem::path& target,
                           const std::function<bool(std::ostream&)>& write);

/// The same for writers that need a file name (libraries that open files themselves):
/// write(tempPath) fills the temporary file; on success it is renamed over `target`.
Status replaceFileAtomically(const std::filesystem::path& target,
                             const std::function<Status(const std::filesystem::path&)>& write);

/// Test hook: called after the temporary file is complete and before it is renamed over the
/// target (a test can end the process there to prove that an interrupted save keeps the previous
/// file). Empty by default; not for production use.
using BeforeReplaceHook = std::function<void(const std::filesystem::path& temp,
                                             const std::filesystem::path& target)>;
void setBeforeReplaceHookForTesting(BeforeReplaceHook hook);

/// Temporary path used for `target` (same folder, hidden, unique to this process).
std::filesystem::path temporaryPathFor(const std::filesystem::path& target);

}  // namespace plimsoll
