// A texture bake that can be stopped part way: an editor bakes a new physics texture size on a
// worker thread and offers Cancel. The same bake as bake.h (bit-identical results).
#pragma once

#include "plimsoll/bake/bake.h"

#include <functional>

namespace plimsoll {

/// Returns true once the caller wants the bake stopped; polled from the baking threads, several
/// at once (an atomic flag's load is enough).
using CancelRequested = std::function<bool()>;

/// What a stopped bake's error message ends with (kind invalidArgument: the caller's own
/// request ended it).
inline constexpr const char* kBakeCancelledMessage = "bake cancelled";

/// bakeSurfaceTextures (bake.h), polling `cancelled` before each band of rows: once it returns
/// true the bake stops after the bands under way and returns an error ending in
/// kBakeCancelledMessage. An empty `cancelled` never stops it.
Result<SurfaceTextures> bakeSurfaceTextures(const TriangleMesh& mesh, const BakeSettings& settings,
                                            SurfacePieceTable* pieces,
                                            const CancelRequested& cancelled);

}  // namespace plimsoll
