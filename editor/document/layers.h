// Layers and masks of a painted map, as texture artists know them from their painting tools:
// paint layers (their own pixels) and fill layers (one value), each with an opacity, a blend
// mode, an optional mask and a visibility, stacked bottom first, and folders that group layers:
// a folder's layers are composited on their own, and the result meets what is below the folder
// as one layer, with the folder's opacity, blend mode, mask and visibility. The engine never sees
// layers: it reads the flattened map (the map's PNG), which the document keeps equal to
// flattenLayers of the stack. The stack is saved beside the map in a "<map>.layers.json" side
// file (docs/project-schema.md, "Map layers"). No GL, no files here: the document does the I/O.
#pragma once

#include "plimsoll/surface/painted_map.h"
#include "plimsoll/core/result.h"

#include <cstdint>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace plimsoll::editor {

/// Limits on a map's layers, checked before any layer image is allocated (a side file or an
/// edit script can otherwise ask for gigabytes): at most kMaxMapLayers layers, at most
/// kMaxLayerSamples samples in all of a stack's layer images (pixels, masks, coverages; 4 bytes
/// each: 1 GiB, eight paint layers of a 4096^2 map, 32 of a 2048^2 one), and a side file of at
/// most kMaxLayersFileBytes.
inline constexpr int kMaxMapLayers = 64;
inline constexpr std::uint64_t kMaxLayerSamples = std::uint64_t(1) << 28;
inline constexpr std::uint64_t kMaxLayersFileBytes = std::uint64_t(64) << 20;

/// A folder holds no value of its own: it is the entry that closes a group of layers (below).
enum class LayerKind { Paint, Fill, Folder };
/// How a layer's value v combines with the value c below it (before opacity and mask).
enum class BlendMode { Normal, Multiply, Add, Subtract, Screen, Lighten, Darken };
inline constexpr int kBlendModeCount = 7;

const char* layerKindName(LayerKind kind);  ///< "paint", "fill", "folder"
std::optional<LayerKind> parseLayerKind(std::string_view name);
const char* blendModeName(BlendMode mode);  ///< "normal", "multiply", ...
std::optional<BlendMode> parseBlendMode(std::string_view name);

/// The blend of layer value `layer` over `below`, clamped to 0..1.
float blendValue(BlendMode mode, float below, float layer);

/// The parts of a layer a stroke can change.
enum class LayerPart { Pixels, Mask, Coverage };

/// What a stroke or fill changes: the map itself (layer < 0; a map with layers has none of its
/// own pixels), or a part of a layer.
struct PaintTarget {
    int layer = -1;
    LayerPart part = LayerPart::Pixels;
};

struct MapLayer {
    std::string name;
    LayerKind kind = LayerKind::Paint;
    /// A paint layer's pixels (the stack's size). Copies of a stack share them: the history
    /// keeps copies, and only strokes change pixels, undone in the order they were made, so
    /// a copy always sees the pixels its own state had.
    std::shared_ptr<PaintedMap> pixels;
    float fillValue = 1.0f;  ///< a fill layer's value, 0..1
    float opacity = 1.0f;    ///< 0..1
    BlendMode blend = BlendMode::Normal;
    bool visible = true;
    /// 0..1 per pixel (1: the layer shows, 0: hidden); null: no mask (all 1).
    std::shared_ptr<PaintedMap> mask;
    /// A paint layer's own transparency, 0..1 per pixel: painting raises it, erasing lowers it,
    /// so a new layer is clear until painted. Null: covered everywhere (a map's base layer).
    std::shared_ptr<PaintedMap> coverage;
    /// The layer is in the folder above it. A folder's layers lie right below its entry in the
    /// stack, with nothing else between them (checkStack); folders do not nest, so a folder
    /// is never in one.
    bool inFolder = false;

    bool isFolder() const { return kind == LayerKind::Folder; }
    /// The layer's own value at pixel `i` (its pixel, or its fill value).
    float valueAt(std::size_t i) const { return pixels ? pixels->values[i] : fillValue; }
    /// How much of the layer shows at pixel `i`: opacity x mask x coverage.
    float alphaAt(std::size_t i) const {
        return opacity * (mask ? mask->values[i] : 1.0f) * (coverage ? coverage->values[i] : 1.0f);
    }
    /// The part's pixels (null: the layer has none).
    std::shared_ptr<PaintedMap>& part(LayerPart which) {
        return which == LayerPart::Mask ? mask : which == LayerPart::Coverage ? coverage : pixels;
    }
    const std::shared_ptr<PaintedMap>& part(LayerPart which) const {
        return const_cast<MapLayer*>(this)->part(which);
    }
    bool operator==(const MapLayer& other) const;  ///< same settings and same pixel values
};

struct LayerStack {
    int width = 0;
    int height = 0;
    /// Bottom first. A folder's entry comes right after (above) the layers it holds.
    std::vector<MapLayer> layers;

    bool operator==(const LayerStack& other) const = default;
    bool hasFolders() const;
};

// --- folders: an item is a layer, or a folder with the layers it holds (its block) -----------

/// The folder entry holding layer `layer`, or -1 (at the top level, or a folder itself).
int folderOf(const LayerStack& stack, int layer);
/// The lowest index of the item at `item`: a folder's bottom layer (the folder itself when it
/// is empty), or the layer itself.
int blockStart(const LayerStack& stack, int item);
/// The item right above / below `item` among the items of the same folder (or of the top
/// level), as its top entry's index; -1 where there is none.
int siblingAbove(const LayerStack& stack, int item);
int siblingBelow(const LayerStack& stack, int item);
/// Moves the item `from` (a folder with its layers) next to its sibling `to`: above it when
/// `to` is above, below it otherwise. The index `from`'s top entry ends at.
int moveItem(LayerStack& stack, int from, int to);

/// `value` (clamped to 0..1) at the 16 bits of the map files: layer pixels are kept this way,
/// so that a saved stack reads back exactly and flattens to exactly the saved map.
float quantize16(float value);

/// A w x h map with every value `value`.
PaintedMap uniformMap(int width, int height, float value);

/// A stack of one paint layer "Base" holding `map` at 16 bits (what a map without layers is).
LayerStack stackOfMap(const PaintedMap& map);

/// The map the engine reads: starting from 0, each visible item bottom to top moves every
/// pixel from c to blend(c, v) by its alpha (opacity x mask x coverage). A folder's v and alpha
/// are those of its visible layers composited over nothing (W3C Compositing and Blending 1,
/// section 5.8: a layer over a backdrop of alpha ab blends ab of the way and covers the rest),
/// its alpha times the folder's opacity and mask: a folder at 50% over layers that are opaque
/// shows them as one at 50%, not each one at 50% over the other.
PaintedMap flattenLayers(const LayerStack& stack);

/// Why the stack is not well formed (sizes, pixels of paint layers, ranges, folders' layers
/// right below them), or nothing.
Status checkStack(const LayerStack& stack);

/// A layer name as typed, without the spaces (and tabs) at its ends.
std::string trimmedLayerName(std::string_view name);
/// Why `name` (trimmed) cannot be the name of layer `layer` of `stack` (-1: of a new layer):
/// empty, with a control character (a line break would split the panel's row), or the name of
/// another layer of the map (the history and the scripts name layers to the painter). Ok for
/// the layer's own name.
Status checkLayerName(const LayerStack& stack, int layer, std::string_view name);
/// `stem` + " N" with the smallest N from `first` that no layer of the stack is called.
std::string unusedLayerName(const LayerStack& stack, const std::string& stem, std::size_t first);

/// The stack as the side file's JSON text (pixels as base64 16-bit PNG). A stack with folders
/// is version 2 (a folder's object holds its layers in "layers", bottom first); one without
/// stays version 1, which editors before folders read.
std::string layerStackToJson(const LayerStack& stack);
/// Parses a side file of version 1 or 2; `source` names it in messages.
Result<LayerStack> parseLayerStack(const std::string& text, const std::string& source);

/// The side file of a map: "maps/x.png" -> "maps/x.layers.json".
std::filesystem::path layersPathFor(const std::filesystem::path& mapPath);

/// Base64 of bytes and back (the side file and the autosave embed PNGs this way).
std::string base64Encode(const std::string& bytes);
std::string base64Decode(const std::string& text);

/// Ok if `stack` may grow by `layers` more layers holding `images` more images of its size:
/// the layer count and the samples against kMaxMapLayers and kMaxLayerSamples, before
/// anything is allocated. The error names the limits.
Status checkLayerBudget(const LayerStack& stack, int layers, int images);

}  // namespace plimsoll::editor
