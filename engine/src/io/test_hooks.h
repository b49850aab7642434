// Fault injection for the tests, kept out of the public headers: the tests include this
// (engine/src is on their include path); nothing else does.
#pragma once

#include <filesystem>
#include <functional>

namespace plimsoll {

/// The k-th fileStep (file_util.h) from now fails (k >= 1; 0 turns it off), once, the way a
/// full disk or a failed rename would. A test repeats an operation with k = 1, 2, ... until it
/// succeeds, so every step of it is interrupted once.
void failFileStepForTesting(int k);

/// Called after a temporary file is complete and before it is renamed over its target (a test
/// can end the process there to prove that an interrupted save keeps the previous file). Empty
/// by default.
using BeforeReplaceHook =
    std::function<void(const std::filesystem::path& temp, const std::filesystem::path& target)>;
void setBeforeReplaceHookForTesting(BeforeReplaceHook hook);

/// Called at every fileStep before it runs (a test in a child process ends the process at the
/// k-th step to prove that a kill at any instant loses nothing). Empty by default.
using FileStepHook = std::function<void(const char* what, const std::filesystem::path& path)>;
void setFileStepHookForTesting(FileStepHook hook);

/// replaceFolder (file_util.h) takes its fallback of two renames, as on a file system without
/// renameat2(RENAME_EXCHANGE), while `disabled`.
void disableRenameExchangeForTesting(bool disabled);

}  // namespace plimsoll
