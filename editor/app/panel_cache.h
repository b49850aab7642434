// The column's panels (Tools, Layers, Inspector, UV view) kept as an image while what they draw
// stays the same, as Renderer keeps a still 3D view: on llvmpipe drawing them costs about 5 ms
// of a frame at 1600 x 900, copying their rows back (WindowImage) about 0.3 ms.
//
// Each frame ImGui's draw lists are split by where they draw: the column's lists draw only
// inside the column; the kept region is where they draw. Lists are drawn in ImGui's order up to
// the last column list, the region is then kept (or, in a frame that copies, the copy replaces
// the column's lists), and the remaining lists are drawn over it. The kept pixels depend on the
// column's lists and on every earlier list that reaches into the region (a floating window
// behind a panel, the menu bar's edge): all of them are compared byte for byte (vertices,
// indices, commands, each texture's version), never hashed, so a kept image is only shown for
// exactly the panels it was taken of.
#pragma once

#include "render/window_image.h"

#include <imgui.h>

#include <cstdint>
#include <functional>
#include <limits>
#include <optional>
#include <vector>

namespace plimsoll::editor {

class PanelCache {
public:
    /// Which version of a texture's contents ImGui draws with; nullopt for a texture whose
    /// changes are not tracked (a list that shows one is then always drawn).
    using TextureVersion = std::function<std::optional<std::uint64_t>(ImTextureID)>;

    PanelCache() = default;
    PanelCache(const PanelCache&) = delete;
    PanelCache& operator=(const PanelCache&) = delete;

    /// Draws `data` into the bound framebuffer. `column` is the column's rectangle in display
    /// coordinates (min x, min y, max x, max y); every framebuffer pixel it touches must have
    /// been cleared to `background` this frame and hold nothing else drawn outside ImGui.
    /// Needs ImGui's OpenGL 3 backend initialised.
    void render(ImDrawData& data, const ImVec4& column, const ImVec4& background,
                const TextureVersion& textureVersion);

    /// Frames whose column was copied from the kept image, and frames whose column was drawn
    /// and kept, since the start (tests, reports).
    std::uint64_t framesCopied() const { return framesCopied_; }
    std::uint64_t framesKept() const { return framesKept_; }

    /// Where a list draws: its pixels' box in display coordinates (empty: nowhere).
    struct Box {
        float x0 = std::numeric_limits<float>::infinity(),
              y0 = std::numeric_limits<float>::infinity();
        float x1 = -std::numeric_limits<float>::infinity(),
              y1 = -std::numeric_limits<float>::infinity();
        bool empty() const { return !(x0 < x1 && y0 < y1); }
    };

private:
    WindowImage image_;  ///< the kept region's pixels
    /// This frame's boxes and column lists by list, and the lists drawn before and after the
    /// region: kept between frames (no allocation a frame).
    std::vector<Box> boxes_;
    std::vector<char> inColumn_;
    ImVector<ImDrawList*> before_, after_;
    /// Keys (never empty: a key starts with the region and the display): the one kept, last
    /// frame's, and this frame's being built. Empty: none.
    std::vector<std::uint8_t> kept_, previous_, key_;
    std::uint64_t framesCopied_ = 0, framesKept_ = 0;
};

}  // namespace plimsoll::editor
