// The document as the renderer sees it: one RenderBody per body (overlay texture slot = body
// index), the water of the project's scene.
#pragma once

#include "document/document.h"
#include "document/overlay.h"
#include "render/renderer.h"

namespace plimsoll::editor {

/// Uploads every body's overlay (slot = body index) and returns the scene. Overlay errors (a
/// body whose bake fails) leave that body grey.
RenderScene buildRenderScene(Document& document, Renderer& renderer, Overlay overlay,
                             int selectedBody = -1);

}  // namespace plimsoll::editor
