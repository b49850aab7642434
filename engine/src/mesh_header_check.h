// Internal: refuses mesh files whose headers declare more elements than limits.h allows, or
// more than the file can hold, before an importer allocates for them.
#pragma once

#include "plimsoll/result.h"

#include <filesystem>

namespace plimsoll::detail {

/// PLY and GLB (any extension, by their magic) and binary STL (.stl): Ok, or an error naming
/// the file, the declared count and the limit (or the bytes missing). Other formats: Ok.
Status checkMeshHeader(const std::filesystem::path& path);

}  // namespace plimsoll::detail
