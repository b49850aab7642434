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

const char* layerKindName(LayerKind kind) { return kind == LayerKind::Fill ? "fill" : "paint"; }

std::optional<LayerKind> parseLayerKind(std::string_view name) {
    if (name == "paint") return LayerKind::Paint;
    if (name == "fill") return LayerKind::Fill;
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
           blend == o.blend && visible == o.visible && sameMap(pixels, o.pixels) &&
           sameMap(mask, o.mask) && sameMap(coverage, o.coverage);
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

PaintedMap flattenLayers(const LayerStack& stack) {
    PaintedMap out = uniformMap(stack.width, stack.height, 0.0f);
    for (const MapLayer& layer : stack.layers) {
        if (!layer.visible || layer.opacity <= 0.0f) continue;
        for (std::size_t i = 0; i < out.values.size(); ++i) {
            const float a = layer.alphaAt(i);
            const float c = out.values[i];
            out.values[i] = c + (blendValue(layer.blend, c, layer.valueAt(i)) - c) * a;
        }
    }
    return out;
}

Status checkStack(const LayerStack& stack) {
    if (stack.width < 1 || stack.height < 1) return makeError(ErrorKind::format, "layers: no size");
    if (stack.layers.empty()) return makeError(ErrorKind::format, "layers: the stack is empty");
    auto sized = [&](const PaintedMap& m) {
        return m.width == stack.width && m.height == stack.height;
    };
    for (std::size_t i = 0; i < stack.layers.size(); ++i) {
        const MapLayer& l = stack.layers[i];
        const std::string where = "layer " + std::to_string(i) + " '" + l.name + "': ";
        if ((l.kind == LayerKind::Paint) != static_cast<bool>(l.pixels)) {
            return makeError(ErrorKind::format,
                             where + "a paint layer has pixels, a fill layer none");
        }
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

std::string layerStackToJson(const LayerStack& stack) {
    Json layers = Json::array();
    for (const MapLayer& l : stack.layers) {
        Json j = {{"name", l.name},
                  {"kind", layerKindName(l.kind)},
                  {"opacity", l.opacity},
                  {"blend", blendModeName(l.blend)},
                  {"visible", l.visible}};
        if (l.pixels)
            j["pixels_png_base64"] = base64Encode(encodePaintedMapPng16(*l.pixels));
        else
            j["value"] = l.fillValue;
        if (l.mask) j["mask_png_base64"] = base64Encode(encodePaintedMapPng16(*l.mask));
        if (l.coverage) j["coverage_png_base64"] = base64Encode(encodePaintedMapPng16(*l.coverage));
        layers.push_back(std::move(j));
    }
    const Json root = {{"plimsoll_map_layers", 1},
                       {"width", stack.width},
                       {"height", stack.height},
                       {"layers", std::move(layers)}};
    return root.dump(1) + "\n";
}

Result<LayerStack> parseLayerStack(const std::string& text, const std::string& source) {
    LayerStack stack;
    if (Status depth = checkJsonDepth(text, source); !depth) return depth.error();
    try {
        const Json root = Json::parse(text);
        if (root.value("plimsoll_map_layers", 0) != 1) {
            return makeError(ErrorKind::format,
                             source + ": not a map layers file (plimsoll_map_layers: 1)");
        }
        stack.width = root.at("width").get<int>();
        stack.height = root.at("height").get<int>();
        // Every limit before the first image is decoded: the count of layers, the size, and
        // the samples of all the images the file declares.
        const Json& declared = root.at("layers");
        if (!declared.is_array())
            return makeError(ErrorKind::format, source + ": \"layers\" is not an array");
        std::uint64_t images = 0;
        for (const Json& j : declared) {
            if (!j.is_object())
                return makeError(ErrorKind::format, source + ": a layer is not an object");
            for (const char* key : {"pixels_png_base64", "mask_png_base64", "coverage_png_base64"})
                images += j.contains(key);
        }
        if (stack.width < 1 || stack.height < 1)
            return makeError(ErrorKind::format, source + ": layers: no size");
        if (Status ok = checkCounts(std::uint64_t(stack.width), std::uint64_t(stack.height),
                                    declared.size(), images);
            !ok)
            return withContext(source + ": ", ok.error());
        for (const Json& j : declared) {
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
                    return makeError(ErrorKind::format, source + ": layer '" + l.name +
                                                            "': " + key + " is not the map's size");
                *target = std::make_shared<PaintedMap>(std::move(image).value());
            }
            stack.layers.push_back(std::move(l));
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
