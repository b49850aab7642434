#include "render/scene.h"

namespace plimsoll::editor {

RenderScene buildRenderScene(Document& document, Renderer& renderer, Overlay overlay,
                             int selectedBody) {
    RenderScene scene;
    scene.water = &document.project().water;
    for (std::size_t b = 0; b < document.bodyCount(); ++b) {
        RenderBody body;
        body.mesh = document.assets(b).mesh;
        body.pose = document.bodyPose(b);
        body.selected = static_cast<int>(b) == selectedBody;
        if (overlay != Overlay::None && body.mesh) {
            Result<OverlayImage> image = buildOverlay(document, b, overlay);
            if (image && image->width > 0) {
                renderer.setOverlay(static_cast<int>(b), *image);
                body.overlay = static_cast<int>(b);
            }
        }
        scene.bodies.push_back(std::move(body));
    }
    return scene;
}

}  // namespace plimsoll::editor
