// bakeSceneBody with progress and Cancel: an editor re-bakes its bodies at a new physics
// texture size on a worker thread while the user keeps working (scene.h's bake otherwise).
#pragma once

#include "plimsoll/bake/cancellable_bake.h"
#include "plimsoll/scene/scene.h"

namespace plimsoll {

/// How bakeSceneBody reports and stops; every part may be empty.
struct BakeControl {
    ProgressCallback progress;  ///< the texture bake's fraction done, 0..1
    CancelRequested cancelled;  ///< cancellable_bake.h
    unsigned threads = 0;       ///< baking threads; 0 = all hardware threads
};

/// bakeSceneBody (scene.h) under `control`: the same body, or the bake's error (one ending in
/// kBakeCancelledMessage when `control.cancelled` stopped it).
Result<SceneBody> bakeSceneBody(BodyDesc desc, BodyParts parts, const BakeControl& control);

}  // namespace plimsoll
