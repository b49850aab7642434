// Safe reading and writing. Reading: only regular files (a FIFO, a device or a link to one is
// refused before it can block or feed endless bytes), only up to a size limit. Names that
// become paths are confined to their folder. Writing: content goes to a temporary file beside
// the target, created exclusively (O_EXCL, so a planted link is never followed) and renamed
// over the target only once written completely, so an interrupted or failed write never
// destroys what was saved before.
#pragma once

#include "plimsoll/core/result.h"

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

/// Several files replaced as one (a project and its maps, a bake folder's images and manifest):
/// every file is written to its temporary first, and a failure there changes nothing. Then a
/// journal naming every (temporary, target) pair is renamed into place beside the last target:
/// that rename is the commit. Each temporary is then renamed over its target, the previous
/// version kept aside (a hard link) so that a failed rename puts the previous files back, and
/// the journal is removed. Every target lies inside the last target's folder (the journal names
/// them by relative path, and a journal naming anything else is refused when read). A process
/// killed after the commit leaves the journal, and
/// finishInterruptedReplace (called by the loaders of the last target) completes the set; one
/// killed before leaves the previous set. Each writer fills the temporary path it is given.
using FileWriter =
    std::pair<std::filesystem::path, std::function<Status(const std::filesystem::path&)>>;
Status replaceFilesTogether(const std::vector<FileWriter>& files);
/// Completes a replaceFilesTogether whose process died after its commit: `lastTarget` is the
/// last file of that set (the project file, a bake manifest). Ok when there was nothing to do.
Status finishInterruptedReplace(const std::filesystem::path& lastTarget);
/// Puts the complete folder `staging` at `target` (a sibling of it), replacing the folder there:
/// by one renameat2(RENAME_EXCHANGE), so that at every instant a reader finds the old or the
/// new folder at `target`, then the old one removed. Where the file system has no exchange,
/// two renames through `aside` (a sibling name): the path is missing between them, and a kill
/// there leaves the old folder at `aside` for restoreInterruptedFolderSwap. A `target` that is
/// a link or not a folder is refused. `staging` is left for the caller to remove on failure.
Status replaceFolder(const std::filesystem::path& staging, const std::filesystem::path& target,
                     const std::filesystem::path& aside);
/// Where `target` is missing and a folder of an interrupted fallback replaceFolder (".NAME.old-*"
/// beside it) remains, puts that folder back. Ok when there was nothing to do.
Status restoreInterruptedFolderSwap(const std::filesystem::path& target);

/// The writer of a file whose bytes are known up front (a PNG, a JSON text).
FileWriter bytesFileWriter(const std::filesystem::path& target, std::string bytes);

/// Reads a whole regular file, refusing before reading anything one that is not (a folder, a
/// FIFO, a device, a socket, or a link to one: "PATH: is a FIFO, not a regular file") and one
/// larger than `maxBytes` ("PATH: 3.1 GB, more than the limit NAME = 256.0 MB (limits.h)").
/// The file is opened without blocking and checked on the open descriptor, so what is checked
/// is what is read; a path holding a NUL byte is refused (it would open another file).
Result<std::string> readWholeFile(const std::filesystem::path& path, std::uint64_t maxBytes,
                                  const char* limitName);

/// Ok if `target` may be replaced by a rename: it does not exist or is a regular file. A link,
/// a device node, a FIFO, a socket or a folder is refused by name (a rename would replace the
/// node itself, not write into what it names).
Status checkReplaceable(const std::filesystem::path& target);

/// For libraries that open a file themselves: Ok if `path` is a regular file (links followed),
/// else the error readWholeFile would give.
Status checkRegularFile(const std::filesystem::path& path);

/// `name` made one safe path component (a bundle folder, an export folder): ASCII letters,
/// digits, '.', '_' and '-' kept, anything else '_'; a name that is empty or starts with '.'
/// (".", "..", a hidden name) gets `prefix` in front. The result never leaves its folder.
std::string safeFileName(const std::string& name, const std::string& prefix);

/// `relative` (a path a file names: a manifest's file, a glTF buffer URI) resolved inside
/// `folder`; an error naming `what` if it is empty, absolute, holds a ".." component, a
/// backslash or a NUL byte ("\"../x\" leaves the folder").
Result<std::filesystem::path> pathInside(const std::filesystem::path& folder,
                                         const std::string& relative, const std::string& what);

/// Every step of a writer that can fail on a real disk (a temporary file written, a rename, a
/// file written into a staging folder) passes through here first: Ok, or the failure injected
/// by the tests (io/test_hooks.h). `what` and `path` name the step in the injected error.
Status fileStep(const char* what, const std::filesystem::path& path);

/// A new empty temporary file for `target` (same folder, hidden, ".NAME.tmp-XXXXXX" with a
/// random suffix), created with O_EXCL so that nothing already there (a planted link) is
/// opened; its permissions are those of a file the process creates (0666 less the umask).
Result<std::filesystem::path> createTemporaryFor(const std::filesystem::path& target);

}  // namespace plimsoll
