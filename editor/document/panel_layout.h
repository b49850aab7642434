// The editor window's layout, GL-free: the 3D view on the left, a column of panels (Tools,
// Layers, Inspector, UV view) on the right, their sizes set by splitters the user drags. The
// layout keeps shares, not pixels, so a window that shrinks and grows again gets every panel
// back where it was; the settings keep it between sessions.
#pragma once

#include <array>

namespace plimsoll::editor {

/// What the splitters set.
struct PanelLayout {
    /// The right column, px (at most kMaxColumnShare of the window: the view keeps most of it).
    float columnWidth = 400.0f;
    /// Shares of the column's height: Tools, Layers, Inspector and UV view; they sum to 1.
    std::array<float, 4> shares{0.26f, 0.22f, 0.22f, 0.30f};
    /// The UV view as a main view, beside the 3D view (View > UV view beside the 3D view):
    /// a square as tall as the view (at most half the width left of the column), and the
    /// column holds the other three panels, in their shares of it.
    bool uvBesideView = false;
};

/// Panels never shrink below this many pixels while the window has room for them.
inline constexpr float kMinPanelHeight = 48.0f;
inline constexpr float kMinColumnWidth = 180.0f;
inline constexpr float kMaxColumnShare = 0.4f;

struct PanelRect {
    float x = 0, y = 0, w = 0, h = 0;
};

/// Where everything goes in a window of `width` x `height` with a menu bar and status line of
/// those heights: the view and the column's four panels top to bottom, tiling the space.
struct WindowLayout {
    PanelRect view;
    PanelRect column;                 ///< right of the view: the four panels together
    std::array<PanelRect, 4> panels;  ///< Tools, Layers, Inspector, UV view
    /// The column's panels (4, or 3 with the UV view beside the 3D view: panels[3] then lies
    /// between the view and the column).
    int columnPanels = 4;
};
WindowLayout windowLayout(const PanelLayout& layout, float width, float height, float menu,
                          float status);

/// Moves the splitter below panel `above` (0..2) by `dy` pixels in a column `columnHeight`
/// high: the panels either side trade height, each keeping kMinPanelHeight where it can.
void dragRowSplitter(PanelLayout& layout, int above, float dy, float columnHeight);

/// Moves the splitter between the view and the column by `dx` pixels (left widens the column)
/// in a window `width` wide.
void dragColumnSplitter(PanelLayout& layout, float dx, float width);

/// The layout with its numbers brought into range (a settings file edited by hand): a finite
/// width of at least kMinColumnWidth, positive shares normalised to a sum of 1.
PanelLayout sanitised(PanelLayout layout);

}  // namespace plimsoll::editor
