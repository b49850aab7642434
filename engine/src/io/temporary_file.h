// Internal to the io library: reopening a temporary file that file_util made, for the writers
// in this folder that fill it through a descriptor (file_util.cpp, exr_io.cpp).
#pragma once

#include "plimsoll/core/result.h"

#include <filesystem>

namespace plimsoll {

/// Opens a temporary that createTemporaryFor made (the path a FileWriter is given) for writing,
/// emptied: never through a link (O_NOFOLLOW) and only if it is still a regular file with no
/// other name (a hard link to another file swapped in is refused before anything is cut).
/// `target` names the file in errors. The caller closes the descriptor.
Result<int> openTemporaryForWriting(const std::filesystem::path& temp,
                                    const std::filesystem::path& target);

}  // namespace plimsoll
