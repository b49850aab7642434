#include "app/panel_cache.h"

#include <epoxy/gl.h>
#include <imgui_impl_opengl3.h>

#include <algorithm>
#include <cmath>

namespace plimsoll::editor {
namespace {

using Box = PanelCache::Box;

/// Where a list can put pixels: each command's vertices' box cut to its clip rectangle.
/// nullopt where a command is a callback, whose drawing cannot be known.
std::optional<Box> coverage(const ImDrawList& list) {
    Box box;
    for (const ImDrawCmd& cmd : list.CmdBuffer) {
        if (cmd.UserCallback) return std::nullopt;
        Box c;
        for (unsigned i = 0; i < cmd.ElemCount; ++i) {
            const unsigned index =
                cmd.VtxOffset + list.IdxBuffer[static_cast<int>(cmd.IdxOffset + i)];
            const ImVec2 p = list.VtxBuffer[static_cast<int>(index)].pos;
            c.x0 = std::min(c.x0, p.x);
            c.y0 = std::min(c.y0, p.y);
            c.x1 = std::max(c.x1, p.x);
            c.y1 = std::max(c.y1, p.y);
        }
        c.x0 = std::max(c.x0, cmd.ClipRect.x);
        c.y0 = std::max(c.y0, cmd.ClipRect.y);
        c.x1 = std::min(c.x1, cmd.ClipRect.z);
        c.y1 = std::min(c.y1, cmd.ClipRect.w);
        if (c.empty()) continue;
        box.x0 = std::min(box.x0, c.x0);
        box.y0 = std::min(box.y0, c.y0);
        box.x1 = std::max(box.x1, c.x1);
        box.y1 = std::max(box.y1, c.y1);
    }
    return box;
}

bool within(const Box& b, const ImVec4& r) {
    return b.x0 >= r.x && b.y0 >= r.y && b.x1 <= r.z && b.y1 <= r.w;
}
bool meets(const Box& b, const ImVec4& r) {
    return b.x0 < r.z && r.x < b.x1 && b.y0 < r.w && r.y < b.y1;
}

template <class T>
void append(std::vector<std::uint8_t>& out, const T* data, std::size_t count) {
    const auto* bytes = reinterpret_cast<const std::uint8_t*>(data);
    out.insert(out.end(), bytes, bytes + count * sizeof(T));
}

/// `data` with only `lists` (same display and scale).
ImDrawData subset(const ImDrawData& data, ImVector<ImDrawList*>& lists) {
    ImDrawData out = data;
    out.CmdLists = lists.Data;
    out.CmdListsCount = lists.Size;
    out.TotalVtxCount = out.TotalIdxCount = 0;
    for (const ImDrawList* list : lists) {
        out.TotalVtxCount += list->VtxBuffer.Size;
        out.TotalIdxCount += list->IdxBuffer.Size;
    }
    return out;
}

}  // namespace

void PanelCache::render(ImDrawData& data, const ImVec4& column, const ImVec4& background,
                        const TextureVersion& textureVersion) {
    auto drawAll = [&] {
        previous_.clear();
        ImGui_ImplOpenGL3_RenderDrawData(&data);
    };
    // The column's whole framebuffer pixels, rounded out (the caller's promise covers them).
    const ImVec2 scale = data.FramebufferScale;
    if (data.DisplayPos.x != 0 || data.DisplayPos.y != 0 || !(scale.x > 0) || !(scale.y > 0)) {
        return drawAll();
    }
    const ImVec4 columnPixels(std::floor(column.x * scale.x), std::floor(column.y * scale.y),
                              std::ceil(column.z * scale.x), std::ceil(column.w * scale.y));
    const ImVec4 columnRounded(columnPixels.x / scale.x, columnPixels.y / scale.y,
                               columnPixels.z / scale.x, columnPixels.w / scale.y);
    // The column's lists: those that draw only inside it. The kept region: where they draw.
    std::vector<Box>& boxes = boxes_;
    std::vector<char>& inColumn = inColumn_;
    boxes.assign(static_cast<std::size_t>(data.CmdListsCount), Box{});
    inColumn.assign(boxes.size(), false);
    Box region;
    int lastInColumn = -1;
    for (int i = 0; i < data.CmdListsCount; ++i) {
        const std::optional<Box> box = coverage(*data.CmdLists[i]);
        if (!box) return drawAll();
        boxes[static_cast<std::size_t>(i)] = *box;
        if (box->empty() || !within(*box, columnRounded)) continue;
        inColumn[static_cast<std::size_t>(i)] = true;
        lastInColumn = i;
        region.x0 = std::min(region.x0, std::floor(box->x0 * scale.x));
        region.y0 = std::min(region.y0, std::floor(box->y0 * scale.y));
        region.x1 = std::max(region.x1, std::ceil(box->x1 * scale.x));
        region.y1 = std::max(region.y1, std::ceil(box->y1 * scale.y));
    }
    // Within the framebuffer (a column reaching past the window's edge).
    region.x0 = std::max(region.x0, 0.0f);
    region.y0 = std::max(region.y0, 0.0f);
    region.x1 = std::min(region.x1, std::round(data.DisplaySize.x * scale.x));
    region.y1 = std::min(region.y1, std::round(data.DisplaySize.y * scale.y));
    if (lastInColumn < 0 || region.empty()) return drawAll();
    const ImVec4 regionInDisplay(region.x0 / scale.x, region.y0 / scale.y, region.x1 / scale.x,
                                 region.y1 / scale.y);

    // What the kept pixels depend on, exactly: the column's lists and every list drawn before
    // the last of them that reaches into the region (the menu bar's edge under the first
    // panel's title), with each texture's version.
    // Built in a buffer kept between frames: the key is some 100 kB a frame.
    std::vector<std::uint8_t>& key = key_;
    key.clear();
    const float head[] = {region.x0,          region.y0,          region.x1,    region.y1,
                          background.x,       background.y,       background.z, background.w,
                          data.DisplaySize.x, data.DisplaySize.y, scale.x,      scale.y};
    append(key, head, std::size(head));
    for (int i = 0; i <= lastInColumn; ++i) {
        const Box& box = boxes[static_cast<std::size_t>(i)];
        if (!inColumn[static_cast<std::size_t>(i)] && (box.empty() || !meets(box, regionInDisplay)))
            continue;
        const ImDrawList* list = data.CmdLists[i];
        const int sizes[] = {i, list->VtxBuffer.Size, list->IdxBuffer.Size, list->CmdBuffer.Size};
        append(key, sizes, std::size(sizes));
        append(key, list->VtxBuffer.Data, static_cast<std::size_t>(list->VtxBuffer.Size));
        append(key, list->IdxBuffer.Data, static_cast<std::size_t>(list->IdxBuffer.Size));
        for (const ImDrawCmd& cmd : list->CmdBuffer) {
            const std::optional<std::uint64_t> version = textureVersion(cmd.TextureId);
            if (!version) return drawAll();
            append(key, &cmd.ClipRect, 1);
            const std::uint64_t numbers[] = {reinterpret_cast<std::uintptr_t>(cmd.TextureId),
                                             *version, cmd.VtxOffset, cmd.IdxOffset, cmd.ElemCount};
            append(key, numbers, std::size(numbers));
        }
    }

    GLint target = 0;
    glGetIntegerv(GL_DRAW_FRAMEBUFFER_BINDING, &target);
    const int fbHeight = static_cast<int>(std::lround(data.DisplaySize.y * scale.y));
    const int x = static_cast<int>(region.x0), width = static_cast<int>(region.x1) - x;
    const int height = static_cast<int>(region.y1 - region.y0);
    const int y = fbHeight - static_cast<int>(region.y1);  // GL's: the lower edge
    // Lists up to the last column list, then (after the region is copied or kept) the rest:
    // the order ImGui gives, as nothing after that list is under a panel.
    ImVector<ImDrawList*>& before = before_;
    ImVector<ImDrawList*>& after = after_;
    before.resize(0);
    after.resize(0);
    const bool copying = kept_ == key;
    for (int i = 0; i < data.CmdListsCount; ++i) {
        // A copied region replaces what the column's lists would draw.
        if (copying && inColumn[static_cast<std::size_t>(i)]) continue;
        (i <= lastInColumn ? before : after).push_back(data.CmdLists[i]);
    }
    ImDrawData beforeData = subset(data, before);
    ImGui_ImplOpenGL3_RenderDrawData(&beforeData);
    if (copying) {
        image_.copyTo(target, x, y);
        ++framesCopied_;
    } else if (previous_ == key) {
        // The same two frames running: kept from now on.
        kept_.clear();
        if ((image_.width() == width && image_.height() == height) ||
            image_.resize(width, height, /*depth=*/false)) {
            image_.copyFrom(target, x, y);
            kept_ = key;
            ++framesKept_;
        }
    }
    std::swap(previous_, key_);  // the old buffer is next frame's to fill
    ImDrawData afterData = subset(data, after);
    ImGui_ImplOpenGL3_RenderDrawData(&afterData);
}

}  // namespace plimsoll::editor
