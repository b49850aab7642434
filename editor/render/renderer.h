// The viewport renderer (OpenGL 4.5 core through libepoxy): meshes with a map overlay, the
// water (flat or waves, seen as through a translucent sheet: water_view.h), grid and axes. The
// window draws it into its framebuffer; `plimsoll render` into an OffscreenTarget of a headless
// EGL context. It needs a current context and knows nothing of windows.
#pragma once

#include "document/overlay.h"
#include "view/camera.h"
#include "view/water_view.h"
#include "render/window_image.h"

#include "plimsoll/geometry/mesh.h"
#include "plimsoll/physics/pose.h"
#include "plimsoll/core/result.h"
#include "plimsoll/physics/water.h"

#include <Eigen/Core>

#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <vector>

namespace plimsoll::editor {

struct RenderBody {
    std::shared_ptr<const TriangleMesh> mesh;
    Pose pose;
    /// Overlay texture slot (see Renderer::setOverlay); -1: plain grey.
    int overlay = -1;
    bool selected = false;
    /// Below 1: see-through (drawn after RenderScene::drawInside, blended, depth not written).
    float alpha = 1.0f;
};

struct RenderScene {
    std::vector<RenderBody> bodies;
    const WaterModel* water = nullptr;  ///< nullptr: no water surface
    double time = 0.0;                  ///< s, for waves
    bool grid = true;
    /// The preview's sea floor, world y: drawn as a sand-coloured grid (nothing when unset).
    std::optional<double> floor;
    bool axes = true;
    Eigen::Vector3f background{0.20f, 0.21f, 0.23f};
    /// Drawn after the opaque bodies and before the see-through ones (what is inside a hull:
    /// the water graph), with the view-projection matrix; depth testing on.
    std::function<void(const Eigen::Matrix4f& viewProj)> drawInside;
};

/// A framebuffer object with colour and depth, for rendering without a window.
class OffscreenTarget {
public:
    static Result<std::unique_ptr<OffscreenTarget>> create(int width, int height);
    ~OffscreenTarget();
    void bind() const;
    int width() const { return width_; }
    int height() const { return height_; }
    /// RGBA8, row 0 at the top of the image.
    std::vector<std::uint8_t> readRgba() const;

private:
    OffscreenTarget() = default;
    unsigned framebuffer_ = 0, colour_ = 0, depth_ = 0;
    int width_ = 0, height_ = 0;
};

class Renderer {
public:
    /// Compiles the shaders; needs a current OpenGL 4.5 core context.
    static Result<std::unique_ptr<Renderer>> create();
    ~Renderer();
    Renderer(const Renderer&) = delete;
    Renderer& operator=(const Renderer&) = delete;

    /// Uploads an overlay image into texture slot `slot` (replacing what was there).
    void setOverlay(int slot, const OverlayImage& image);
    /// The GL texture name of a slot (0 when empty), for ImGui::Image in the UV view.
    unsigned overlayTexture(int slot) const;

    /// A size x size texture (RGBA8, transparent) with the mesh's UV triangles' edges drawn in
    /// white, for the UV view; made once per mesh. Row 0 is v = 0. 0 when the mesh has no UVs.
    unsigned uvWireframeTexture(const std::shared_ptr<const TriangleMesh>& mesh, int size);
    /// Which upload of its contents a texture of this renderer's (an overlay's or a
    /// wireframe's) holds: it changes whenever they change. nullopt for any other texture.
    std::optional<std::uint64_t> textureVersion(unsigned texture) const;

    /// Draws into the bound framebuffer, in the viewport (x, y, width, height) (GL's
    /// convention: x, y of the lower-left corner), clearing only that rectangle unless the
    /// caller has `cleared` the whole target's colour to clearColour() this frame; then
    /// the renderer clears the whole target's depth and stencil, and only in a frame in
    /// which it rasters the scene.
    /// A scene drawn the same two frames running (camera, size, bodies, poses, overlays,
    /// water, time) is kept in a texture and copied from it while it stays the same: a frame
    /// that only changes the panels or the cursor does not raster the 3D view again. Scenes
    /// with drawInside (the water graph) are always drawn.
    void draw(const RenderScene& scene, const Camera& camera, int width, int height, int x = 0,
              int y = 0, bool cleared = false);
    /// The colour a caller that clears the whole target (draw's `cleared`) clears it with: the
    /// larger part of the view's background, the water's or the plain one (water_view.h).
    Eigen::Vector3f clearColour(const RenderScene& scene, const Camera& camera, int width,
                                int height);
    /// The water's look: its colour and the opacity of a sheet of it.
    static inline const Eigen::Vector3f kWaterColour{0.15f, 0.45f, 0.75f};
    static constexpr float kWaterOpacity = 0.35f;
    /// The next scene drawn (directly) is also drawn into the kept texture and copied from it,
    /// unseen, so that the driver's first use of both (llvmpipe compiles shaders for each)
    /// falls in that frame and not in a later one. For a window (its first frame); a one-off
    /// image has no later frame to spare.
    void warmUpOnFirstDraw() { cache_.warmUp = true; }
    /// Frames copied from the kept scene, and frames drawn, since the start (tests, reports).
    std::uint64_t framesCopied() const { return framesCopied_; }
    std::uint64_t framesDrawn() const { return framesDrawn_; }

private:
    Renderer() = default;
    struct MeshBuffers {
        unsigned vao = 0, vbo = 0;
        int vertexCount = 0;
        /// A closed, outward-wound surface: drawn opaque, its back faces are never seen from
        /// outside and are culled (on llvmpipe they cost as much as the front: ~2.5 ms of the
        /// buoy preview's 3D view at 1600 x 900).
        bool closedSolid = false;
        std::weak_ptr<const TriangleMesh> owner;
    };
    struct Overlay {
        unsigned texture = 0;
        Eigen::Vector2f scale{1, 1}, offset{0, 0};
    };
    MeshBuffers& buffersFor(const std::shared_ptr<const TriangleMesh>& mesh);
    /// The scene at (0, 0, width, height) of the bound framebuffer, its rectangle cleared
    /// already (the body of draw()); upsideDown mirrors it top to bottom.
    void drawScene(const RenderScene& scene, const Camera& camera, int width, int height,
                   bool upsideDown = false);
    /// The scene into the kept image (made or resized to width x height), upside down, which
    /// stays bound as the framebuffer; false where this driver cannot draw into it.
    bool drawIntoCache(const RenderScene& scene, const Camera& camera, int width, int height);
    /// Everything a drawn scene depends on.
    struct SceneKey {
        std::vector<double> numbers;  ///< size, camera, time, flags, poses, overlays
        std::vector<const void*> meshes;
        bool operator==(const SceneKey&) const = default;
    };
    SceneKey keyOf(const RenderScene& scene, const Camera& camera, int width, int height);
    /// The kept scene: a framebuffer of its size, and the key it was drawn for.
    struct SceneCache {
        WindowImage image;
        std::optional<SceneKey> kept, previous;
        bool warmUp = false;  ///< see warmUpOnFirstDraw
    } cache_;
    std::uint64_t textureUploads_ = 0;                   ///< bumps on every texture upload
    std::map<unsigned, std::uint64_t> textureVersions_;  ///< see textureVersion
    std::uint64_t framesCopied_ = 0, framesDrawn_ = 0;
    void drawLines(const std::vector<float>& vertices, const Eigen::Matrix4f& viewProj);
    /// The scene's lines: the grid (on waves the water's surface), the sea floor and the axes.
    void drawLinesOf(const RenderScene& scene, const Camera& camera, const WaterView* water,
                     const Eigen::Matrix4f& viewProj);
    /// drawLinesOf's vertices and the water's net, kept between frames (no allocation a frame).
    std::vector<float> frameLines_;
    std::vector<Eigen::Vector3f> frameNet_;

    unsigned meshProgram_ = 0, lineProgram_ = 0;
    unsigned lineVao_ = 0, lineVbo_ = 0;
    /// The uniform block (std140) and the heights of water_view.vert and .frag, at these
    /// binding points.
    struct WaterBlock {
        float tint[4], grid[4], eye[4], forward[4];
    };
    static constexpr unsigned kWaterBlockBinding = 2, kWaterHeightsUnit = 3;
    unsigned waterBlock_ = 0, waterHeights_ = 0;
    /// Fills the block for `view`, or says "no water" (nullptr).
    void setWaterBlock(const WaterView* view);
    /// The scene's water as the view shows it (nullptr: none), its heights kept while the
    /// water, the time, the target and the distance stay.
    const WaterView* waterViewOf(const RenderScene& scene, const Camera& camera);
    static Eigen::Vector3f backdropColour(const RenderScene& scene, bool seenThroughWater);
    std::map<const TriangleMesh*, MeshBuffers> meshes_;
    std::map<int, Overlay> overlays_;
    struct Wireframe {
        unsigned texture = 0;
        int size = 0;
        std::weak_ptr<const TriangleMesh> owner;
    };
    std::map<const TriangleMesh*, Wireframe> wireframes_;
    /// The water by content, counted: bumps whenever the water drawn differs from the last
    /// (the document edits its own in place, so the pointer says nothing). The scene key and
    /// the water view both go by it.
    std::uint64_t waterGeneration(const WaterModel& water);
    std::optional<WaterModel> lastWater_;  ///< a copy of the last water drawn, to compare
    std::uint64_t waterGeneration_ = 0;
    struct WaterCache {
        std::uint64_t generation = 0;  ///< waterGeneration() of the water sampled
        double time = -1;
        WaterView view;
        bool uploaded = false;  ///< view.heights are in waterHeights_
    } waterCache_;
};

}  // namespace plimsoll::editor
