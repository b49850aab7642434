#include "document/layers.h"
#include "plimsoll/io/json_depth.h"
#include "plimsoll/core/limits.h"
#include "plimsoll/io/painted_map_io.h"

#include <nlohmann/json.hpp>
#include <stb_image.h>

#include <algorithm>
#include <array>
#include <cmath>

namespace plimsoll::editor {

using Json = nlohmann::json;

namespace {

constexpr std::array<const char*, kBlendModeCount> kBlendNames{
    "normal", "multiply", "add", "subtract", "screen", "lighten", "darken"};

bool sameMap(const std::shared_ptr<PaintedMap>& a, const std::shared_ptr<PaintedMap>& b) {
    if (!a || !b) return !a && !b;
    return a->width == b->width && a->height == b->height && a->values == b->values;
}

}  // namespace

const char* layerKindName(LayerKind kind) {
    return kind == LayerKind::Fill ? "fill" : kind == LayerKind::Folder ? "folder" : "paint";
}

std::optional<LayerKind> parseLayerKind(std::string_view name) {
    if (name == "paint") return LayerKind::Paint;
    if (name == "fill") return LayerKind::Fill;
    if (name == "folder") return LayerKind::Folder;
    return std::nullopt;
}

const char* blendModeName(BlendMode mode) { return kBlendNames[static_cast<int>(mode)]; }

std::optional<BlendMode> parseBlendMode(std::string_view name) {
    for (int i = 0; i < kBlendModeCount; ++i) {
        if (name == kBlendNames[i]) return static_cast<BlendMode>(i);
    }
    return std::nullopt;
}

float blendValue(BlendMode mode, float c, float v) {
    float out = v;
    switch (mode) {
        case BlendMode::Normal:
            out = v;
            break;
        case BlendMode::Multiply:
            out = c * v;
            break;
        case BlendMode::Add:
            out = c + v;
            break;
        case BlendMode::Subtract:
            out = c - v;
            break;
        case BlendMode::Screen:
            out = 1.0f - (1.0f - c) * (1.0f - v);
            break;
        case BlendMode::Lighten:
            out = std::max(c, v);
            break;
        case BlendMode::Darken:
            out = std::min(c, v);
            break;
    }
    return std::clamp(out, 0.0f, 1.0f);
}

bool MapLayer::operator==(const MapLayer& o) const {
    return name == o.name && kind == o.kind && fillValue == o.fillValue && opacity == o.opacity &&
           blend == o.blend && visible == o.visible && inFolder == o.inFolder &&
           sameMap(pixels, o.pixels) && sameMap(mask, o.mask) && sameMap(coverage, o.coverage);
}

float quantize16(float value) {
    // As encodePaintedMapPng16 rounds and loadPaintedMap divides.
    return static_cast<float>(std::lround(std::clamp(value, 0.0f, 1.0f) * 65535.0f)) / 65535.0f;
}

PaintedMap uniformMap(int width, int height, float value) {
    PaintedMap map;
    map.width = width;
    map.height = height;
    map.values.assign(static_cast<std::size_t>(width) * height, value);
    return map;
}

LayerStack stackOfMap(const PaintedMap& map) {
    LayerStack stack;
    stack.width = map.width;
    stack.height = map.height;
    MapLayer base;
    base.name = "Base";
    base.pixels = std::make_shared<PaintedMap>(map);
    for (float& v : base.pixels->values) v = quantize16(v);
    stack.layers.push_back(std::move(base));
    return stack;
}

bool LayerStack::hasFolders() const {
    return std::any_of(layers.begin(), layers.end(),
                       [](const MapLayer& l) { return l.isFolder(); });
}

int folderOf(const LayerStack& stack, int layer) {
    const int count = static_cast<int>(stack.layers.size());
    if (layer < 0 || layer >= count || !stack.layers[std::size_t(layer)].inFolder) return -1;
    for (int i = layer + 1; i < count; ++i) {
        if (stack.layers[std::size_t(i)].isFolder()) return i;
    }
    return -1;
}

int blockStart(const LayerStack& stack, int item) {
    if (item < 0 || !stack.layers[std::size_t(item)].isFolder()) return item;
    int start = item;
    while (start > 0 && stack.layers[std::size_t(start - 1)].inFolder) --start;
    return start;
}

int siblingAbove(const LayerStack& stack, int item) {
    const int above = item + 1;
    if (above >= static_cast<int>(stack.layers.size())) return -1;
    const MapLayer& next = stack.layers[std::size_t(above)];
    if (stack.layers[std::size_t(item)].inFolder) return next.inFolder ? above : -1;
    // Above a top-level item: a top-level layer, or the bottom layer of a folder's block.
    return next.inFolder ? folderOf(stack, above) : above;
}

int siblingBelow(const LayerStack& stack, int item) {
    const int below = blockStart(stack, item) - 1;
    if (below < 0) return -1;
    const bool inner = stack.layers[std::size_t(item)].inFolder;
    // Below a folder's layer: its sibling, or what lies below the folder (not a sibling).
    // Below a top-level item: the top entry of the item below, a layer or a folder.
    return inner == stack.layers[std::size_t(below)].inFolder ? below : -1;
}

int moveItem(LayerStack& stack, int from, int to) {
    auto& layers = stack.layers;
    const int start = blockStart(stack, from);
    std::vector<MapLayer> block(std::make_move_iterator(layers.begin() + start),
                                std::make_move_iterator(layers.begin() + from + 1));
    layers.erase(layers.begin() + start, layers.begin() + from + 1);
    const int size = static_cast<int>(block.size());
    // `to`'s block, in the stack without `from`'s.
    const bool up = to > from;
    const int toTop = up ? to - size : to;
    const int at = up ? toTop + 1 : blockStart(stack, toTop);
    layers.insert(layers.begin() + at, std::make_move_iterator(block.begin()),
                  std::make_move_iterator(block.end()));
    return at + size - 1;
}

namespace {

/// Composites `layer` (value v, alpha a) over a backdrop of value c and alpha ab (W3C
/// Compositing and Blending 1, 5.8): the blend counts where the backdrop is, the layer's own
/// value where it is not, and the result covers a + ab (1 - a).
void compositeOver(BlendMode mode, float v, float a, float& c, float& ab) {
    const float source = (1.0f - ab) * v + ab * blendValue(mode, c, v);
    const float alpha = a + ab * (1.0f - a);
    c = alpha > 0.0f ? (a * source + ab * c * (1.0f - a)) / alpha : 0.0f;
    ab = alpha;
}

/// Folder `folder`'s layers composited over nothing at every pixel: values and alphas.
void compositeFolder(const LayerStack& stack, int folder, std::vector<float>& value,
                     std::vector<float>& alpha) {
    value.assign(std::size_t(stack.width) * std::size_t(stack.height), 0.0f);
    alpha.assign(value.size(), 0.0f);
    for (int k = blockStart(stack, folder); k < folder; ++k) {
        const MapLayer& layer = stack.layers[std::size_t(k)];
        if (!layer.visible || layer.opacity <= 0.0f) continue;
        for (std::size_t i = 0; i < value.size(); ++i)
            compositeOver(layer.blend, layer.valueAt(i), layer.alphaAt(i), value[i], alpha[i]);
    }
}

}  // namespace

PaintedMap flattenLayers(const LayerStack& stack) {
    PaintedMap out = uniformMap(stack.width, stack.height, 0.0f);
    std::vector<float> groupValue;
    std::vector<float> groupAlpha;
    for (int k = 0; k < static_cast<int>(stack.layers.size()); ++k) {
        const MapLayer& layer = stack.layers[std::size_t(k)];
        // A folder's layers reach the map through the folder.
        if (layer.inFolder || !layer.visible || layer.opacity <= 0.0f) continue;
        if (layer.isFolder()) compositeFolder(stack, k, groupValue, groupAlpha);
        for (std::size_t i = 0; i < out.values.size(); ++i) {
            const float v = layer.isFolder() ? groupValue[i] : layer.valueAt(i);
            const float a = layer.alphaAt(i) * (layer.isFolder() ? groupAlpha[i] : 1.0f);
            const float c = out.values[i];
            out.values[i] = c + (blendValue(layer.blend, c, v) - c) * a;
        }
    }
    return out;
}

namespace {

/// Why layer `i` does not fit its place among the folders, or nothing: a folder is in no
/// folder, and a folder's layer has a layer of the folder or the folder's entry right above.
Status checkFolderPlace(const LayerStack& stack, std::size_t i, const std::string& where) {
    const MapLayer& l = stack.layers[i];
    if (l.isFolder() && (l.inFolder || l.pixels || l.coverage))
        return makeError(ErrorKind::format, where + "a folder holds no pixels and no folder");
    if (!l.inFolder) return Ok{};
    const bool closed = i + 1 < stack.layers.size() &&
                        (stack.layers[i + 1].inFolder || stack.layers[i + 1].isFolder());
    if (!closed) return makeError(ErrorKind::format, where + "is in a folder that is not above it");
    return Ok{};
}

}  // namespace

Status checkStack(const LayerStack& stack) {
    if (stack.width < 1 || stack.height < 1) return makeError(ErrorKind::format, "layers: no size");
    if (stack.layers.empty()) return makeError(ErrorKind::format, "layers: the stack is empty");
    auto sized = [&](const PaintedMap& m) {
        return m.width == stack.width && m.height == stack.height;
    };
    for (std::size_t i = 0; i < stack.layers.size(); ++i) {
        const MapLayer& l = stack.layers[i];
        const std::string where = "layer " + std::to_string(i) + " '" + l.name + "': ";
        if (!l.isFolder() && (l.kind == LayerKind::Paint) != static_cast<bool>(l.pixels)) {
            return makeError(ErrorKind::format,
                             where + "a paint layer has pixels, a fill layer none");
        }
        if (Status ok = checkFolderPlace(stack, i, where); !ok) return ok;
        if (l.pixels && !sized(*l.pixels)) {
            return makeError(ErrorKind::format, where + "pixels are not the map's size");
        }
        if (l.mask && !sized(*l.mask)) {
            return makeError(ErrorKind::format, where + "mask is not the map's size");
        }
        if (l.coverage && (!l.pixels || !sized(*l.coverage))) {
            return makeError(ErrorKind::format,
                             where + "coverage is a paint layer's, of the map's size");
        }
        if (!(l.opacity >= 0.0f && l.opacity <= 1.0f) ||
            !(l.fillValue >= 0.0f && l.fillValue <= 1.0f)) {
            return makeError(ErrorKind::schema, where + "opacity and value must be 0..1");
        }
    }
    return Ok{};
}

std::string trimmedLayerName(std::string_view name) {
    const auto blank = [](char c) { return c == ' ' || c == '\t'; };
    while (!name.empty() && blank(name.front())) name.remove_prefix(1);
    while (!name.empty() && blank(name.back())) name.remove_suffix(1);
    return std::string(name);
}

Status checkLayerName(const LayerStack& stack, int layer, std::string_view typed) {
    const std::string name = trimmedLayerName(typed);
    if (name.empty()) return makeError(ErrorKind::invalidArgument, "a layer needs a name");
    if (std::any_of(name.begin(), name.end(),
                    [](char c) { return static_cast<unsigned char>(c) < 0x20 || c == 0x7f; }))
        return makeError(ErrorKind::invalidArgument, "a layer's name is one line of text");
    for (std::size_t i = 0; i < stack.layers.size(); ++i) {
        if (static_cast<int>(i) != layer && stack.layers[i].name == name)
            return makeError(ErrorKind::invalidArgument,
                             "the map already has a layer named '" + name + "'");
    }
    return Ok{};
}

std::string unusedLayerName(const LayerStack& stack, const std::string& stem, std::size_t first) {
    for (std::size_t n = first;; ++n) {
        std::string name = stem + " " + std::to_string(n);
        if (std::none_of(stack.layers.begin(), stack.layers.end(),
                         [&](const MapLayer& l) { return l.name == name; }))
            return name;
    }
}

namespace {
/// The samples of the images `stack` holds now.
std::uint64_t imagesHeld(const LayerStack& stack) {
    std::uint64_t images = 0;
    for (const MapLayer& l : stack.layers)
        images += bool(l.pixels) + bool(l.mask) + bool(l.coverage);
    return images;
}

Status checkCounts(std::uint64_t width, std::uint64_t height, std::uint64_t layers,
                   std::uint64_t images) {
    if (layers > std::uint64_t(kMaxMapLayers))
        return makeError(ErrorKind::limit, std::to_string(layers) +
                                               " layers, more than the limit "
                                               "kMaxMapLayers = " +
                                               std::to_string(kMaxMapLayers) + " (layers.h)");
    const std::uint64_t side = std::uint64_t(kMaxPaintedMapSide);
    if (width > side || height > side)
        return makeError(ErrorKind::limit, "layers of " + std::to_string(width) + " x " +
                                               std::to_string(height) +
                                               " pixels, more than "
                                               "kMaxPaintedMapSide (limits.h)");
    const std::uint64_t samples = width * height * images;  // < 2^26 * 2^32: no overflow
    if (images > (std::uint64_t(1) << 32) || samples > kMaxLayerSamples)
        return makeError(
            ErrorKind::limit,
            std::to_string(images) + " layer images of " + std::to_string(width) + " x " +
                std::to_string(height) + " pixels (" + formatBytes(4.0 * double(samples)) +
                "), more than the limit kMaxLayerSamples = " + std::to_string(kMaxLayerSamples) +
                " samples (layers.h)");
    return Ok{};
}
}  // namespace

Status checkLayerBudget(const LayerStack& stack, int layers, int images) {
    return checkCounts(std::uint64_t(std::max(stack.width, 0)),
                       std::uint64_t(std::max(stack.height, 0)),
                       stack.layers.size() + std::uint64_t(std::max(layers, 0)),
                       imagesHeld(stack) + std::uint64_t(std::max(images, 0)));
}

namespace {

Json layerJson(const MapLayer& l) {
    Json j = {{"name", l.name},
              {"kind", layerKindName(l.kind)},
              {"opacity", l.opacity},
              {"blend", blendModeName(l.blend)},
              {"visible", l.visible}};
    if (l.pixels)
        j["pixels_png_base64"] = base64Encode(encodePaintedMapPng16(*l.pixels));
    else if (!l.isFolder())
        j["value"] = l.fillValue;
    if (l.mask) j["mask_png_base64"] = base64Encode(encodePaintedMapPng16(*l.mask));
    if (l.coverage) j["coverage_png_base64"] = base64Encode(encodePaintedMapPng16(*l.coverage));
    return j;
}

}  // namespace

std::string layerStackToJson(const LayerStack& stack) {
    Json layers = Json::array();
    for (int k = 0; k < static_cast<int>(stack.layers.size()); ++k) {
        const MapLayer& l = stack.layers[std::size_t(k)];
        if (l.inFolder) continue;  // written in its folder's "layers"
        Json j = layerJson(l);
        if (l.isFolder()) {
            j["layers"] = Json::array();
            for (int m = blockStart(stack, k); m < k; ++m)
                j["layers"].push_back(layerJson(stack.layers[std::size_t(m)]));
        }
        layers.push_back(std::move(j));
    }
    const Json root = {{"plimsoll_map_layers", stack.hasFolders() ? 2 : 1},
                       {"width", stack.width},
                       {"height", stack.height},
                       {"layers", std::move(layers)}};
    return root.dump(1) + "\n";
}

namespace {

/// The layers and images `declared` (a "layers" array) holds, a folder's own layers counted;
/// an error where an entry is not an object.
Status countDeclared(const Json& declared, const std::string& source, std::uint64_t& layers,
                     std::uint64_t& images) {
    if (!declared.is_array())
        return makeError(ErrorKind::format, source + ": \"layers\" is not an array");
    for (const Json& j : declared) {
        if (!j.is_object())
            return makeError(ErrorKind::format, source + ": a layer is not an object");
        ++layers;
        for (const char* key : {"pixels_png_base64", "mask_png_base64", "coverage_png_base64"})
            images += j.contains(key);
        if (j.contains("layers") && j.value("kind", std::string()) == "folder") {
            if (Status ok = countDeclared(j["layers"], source, layers, images); !ok) return ok;
        }
    }
    return Ok{};
}

Result<MapLayer> parseLayer(const Json& j, const LayerStack& stack, const std::string& source) {
    MapLayer l;
    l.name = j.value("name", std::string());
    const auto kind = parseLayerKind(j.value("kind", std::string("paint")));
    const auto blend = parseBlendMode(j.value("blend", std::string("normal")));
    if (!kind || !blend) {
        return makeError(ErrorKind::format,
                         source + ": layer '" + l.name + "': unknown kind or blend mode");
    }
    l.kind = *kind;
    l.blend = *blend;
    l.opacity = j.value("opacity", 1.0f);
    l.visible = j.value("visible", true);
    l.fillValue = j.value("value", 1.0f);
    for (auto [key, target] :
         {std::pair{"pixels_png_base64", &l.pixels}, std::pair{"mask_png_base64", &l.mask},
          std::pair{"coverage_png_base64", &l.coverage}}) {
        if (!j.contains(key)) continue;
        Result<PaintedMap> image = decodePaintedMap(base64Decode(j[key].get<std::string>()),
                                                    source + ": layer '" + l.name + "'");
        if (!image) return image.error();
        if (image->width != stack.width || image->height != stack.height)
            return makeError(ErrorKind::format, source + ": layer '" + l.name + "': " + key +
                                                    " is not the map's size");
        *target = std::make_shared<PaintedMap>(std::move(image).value());
    }
    return l;
}

/// Appends the item `j` to the stack: a layer, or a folder's layers and then its entry.
Status appendItem(const Json& j, LayerStack& stack, const std::string& source) {
    Result<MapLayer> item = parseLayer(j, stack, source);
    if (!item) return item.error();
    if (item->isFolder() && j.contains("layers")) {
        for (const Json& inner : j["layers"]) {
            Result<MapLayer> layer = parseLayer(inner, stack, source);
            if (!layer) return layer.error();
            if (layer->isFolder())
                return makeError(ErrorKind::format, source + ": folder '" + layer->name +
                                                        "' is in a folder (folders do not nest)");
            layer->inFolder = true;
            stack.layers.push_back(std::move(layer).value());
        }
    }
    stack.layers.push_back(std::move(item).value());
    return Ok{};
}

}  // namespace

Result<LayerStack> parseLayerStack(const std::string& text, const std::string& source) {
    LayerStack stack;
    if (Status depth = checkJsonDepth(text, source); !depth) return depth.error();
    try {
        const Json root = Json::parse(text);
        const int version = root.value("plimsoll_map_layers", 0);
        if (version != 1 && version != 2) {
            return makeError(ErrorKind::format,
                             source + ": not a map layers file (plimsoll_map_layers: 1 or 2)");
        }
        stack.width = root.at("width").get<int>();
        stack.height = root.at("height").get<int>();
        // Every limit before the first image is decoded: the count of layers, the size, and
        // the samples of all the images the file declares.
        const Json& declared = root.at("layers");
        std::uint64_t layers = 0;
        std::uint64_t images = 0;
        if (Status ok = countDeclared(declared, source, layers, images); !ok) return ok.error();
        if (stack.width < 1 || stack.height < 1)
            return makeError(ErrorKind::format, source + ": layers: no size");
        if (Status ok = checkCounts(std::uint64_t(stack.width), std::uint64_t(stack.height), layers,
                                    images);
            !ok)
            return withContext(source + ": ", ok.error());
        for (const Json& j : declared) {
            if (Status ok = appendItem(j, stack, source); !ok) return ok.error();
        }
    } catch (const Json::exception& e) {
        return makeError(ErrorKind::format, source + ": " + boundedExcerpt(e.what(), 200));
    }
    if (Status ok = checkStack(stack); !ok) return withContext(source + ": ", ok.error());
    return stack;
}

std::filesystem::path layersPathFor(const std::filesystem::path& mapPath) {
    std::filesystem::path p = mapPath;
    return p.replace_extension(".layers.json");
}

std::string base64Encode(const std::string& bytes) {
    static const char* alphabet =
        "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    std::string out;
    std::size_t i = 0;
    for (; i + 2 < bytes.size(); i += 3) {
        const unsigned v = (unsigned char)bytes[i] << 16 | (unsigned char)bytes[i + 1] << 8 |
                           (unsigned char)bytes[i + 2];
        for (int s = 18; s >= 0; s -= 6) out += alphabet[(v >> s) & 63];
    }
    if (i < bytes.size()) {
        unsigned v = (unsigned char)bytes[i] << 16;
        if (i + 1 < bytes.size()) v |= (unsigned char)bytes[i + 1] << 8;
        out += alphabet[(v >> 18) & 63];
        out += alphabet[(v >> 12) & 63];
        out += i + 1 < bytes.size() ? alphabet[(v >> 6) & 63] : '=';
        out += '=';
    }
    return out;
}

std::string base64Decode(const std::string& text) {
    std::string out;
    unsigned v = 0;
    int bits = 0;
    for (char c : text) {
        int d;
        if (c >= 'A' && c <= 'Z')
            d = c - 'A';
        else if (c >= 'a' && c <= 'z')
            d = c - 'a' + 26;
        else if (c >= '0' && c <= '9')
            d = c - '0' + 52;
        else if (c == '+')
            d = 62;
        else if (c == '/')
            d = 63;
        else
            continue;
        v = (v << 6) | d;
        bits += 6;
        if (bits >= 8) {
            bits -= 8;
            out += static_cast<char>((v >> bits) & 0xFF);
        }
    }
    return out;
}

}  // namespace plimsoll::editor
