// The window's panel layout (panel_layout.h).
#include "document/panel_layout.h"

#include <algorithm>
#include <cmath>

namespace plimsoll::editor {

PanelLayout sanitised(PanelLayout layout) {
    if (!std::isfinite(layout.columnWidth)) layout.columnWidth = PanelLayout{}.columnWidth;
    layout.columnWidth = std::max(layout.columnWidth, kMinColumnWidth);
    float sum = 0;
    for (float& share : layout.shares) {
        if (!std::isfinite(share) || share <= 0) share = 0.05f;
        sum += share;
    }
    for (float& share : layout.shares) share /= sum;
    return layout;
}

WindowLayout windowLayout(const PanelLayout& wanted, float width, float height, float menu,
                          float status) {
    const PanelLayout layout = sanitised(wanted);
    WindowLayout out;
    const float column =
        std::clamp(layout.columnWidth, std::min(kMinColumnWidth, width),
                   std::max(std::min(kMinColumnWidth, width), kMaxColumnShare * width));
    const float below = std::max(0.0f, height - menu - status);
    const float left = std::max(0.0f, width - column);
    const int count = layout.uvBesideView ? 3 : 4;
    out.columnPanels = count;
    const float uv = layout.uvBesideView ? std::min(below, 0.5f * left) : 0.0f;
    out.view = {0, menu, left - uv, below};
    out.column = {width - column, menu, column, below};
    if (layout.uvBesideView) out.panels[3] = {left - uv, menu, uv, below};
    // Each panel its share, raised to the minimum where the column has room for all of them,
    // the others giving up height in proportion to what they have above it.
    std::array<float, 4> h{};
    float shares = 0;
    for (int i = 0; i < count; ++i) shares += layout.shares[i];
    for (int i = 0; i < count; ++i) h[i] = layout.shares[i] / shares * below;
    const float minimum = std::min(kMinPanelHeight, below / count);
    float deficit = 0, spare = 0;
    for (int i = 0; i < count; ++i) {
        deficit += std::max(0.0f, minimum - h[i]);
        spare += std::max(0.0f, h[i] - minimum);
    }
    if (deficit > 0 && spare > 0) {
        for (int i = 0; i < count; ++i)
            h[i] = h[i] < minimum ? minimum : h[i] - (h[i] - minimum) * deficit / spare;
    }
    float y = menu;
    for (int i = 0; i < count; ++i) {
        // The last panel ends where the column does: no rounding gap above the status line.
        const float panelHeight = i == count - 1 ? menu + below - y : h[i];
        out.panels[i] = {width - column, y, column, panelHeight};
        y += h[i];
    }
    return out;
}

void dragRowSplitter(PanelLayout& layout, int above, float dy, float columnHeight) {
    if (above < 0 || above > 2 || !(columnHeight > 0) || !std::isfinite(dy)) return;
    layout = sanitised(layout);
    const float minimum = std::min(kMinPanelHeight, columnHeight / 4) / columnHeight;
    float& a = layout.shares[above];
    float& b = layout.shares[above + 1];
    const float move =
        std::clamp(dy / columnHeight, std::min(0.0f, minimum - a), std::max(0.0f, b - minimum));
    a += move;
    b -= move;
}

void dragColumnSplitter(PanelLayout& layout, float dx, float width) {
    if (!std::isfinite(dx) || !(width > 0)) return;
    // From the width shown (a wider one kept from a bigger window would make the first part
    // of a drag do nothing).
    const float widest = std::max(kMinColumnWidth, kMaxColumnShare * width);
    const float shown = std::min(layout.columnWidth, widest);
    layout.columnWidth = std::clamp(shown - dx, kMinColumnWidth, widest);
}

}  // namespace plimsoll::editor
