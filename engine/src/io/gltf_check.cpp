// A glTF's structure, checked before assimp's glTF 2 reader sees it. That reader trusts the
// numbers of the JSON: a bufferView.byteOffset of 2^64-16 wrapped its bounds check and read 16
// bytes before the buffer; a sparse accessor without indices.bufferView dereferenced null, one
// with an index past its accessor wrote outside the array, one with no bufferView allocated
// count times element size of zeros (1.2 GB from 1.7 KB); a Draco-compressed attribute of 16
// components overflowed a 4-element array on the stack; a data URI whose header is longer than
// 127 bytes keeps its offsets in a signed char and read before the string; a triangle fan of
// 2 indices wrote a face into an array of none; a node listed as the child of two nodes is
// imported once per path, so 64 levels of two references each never end. Everything here is
// checked with 64-bit arithmetic that cannot wrap: every comparison subtracts only what is
// already known to be smaller, and every product of counts saturates.
#include "io/mesh_header_check.h"

#include "plimsoll/core/limits.h"
#include "plimsoll/io/json_depth.h"

#include <algorithm>
#include <cctype>
#include <cstring>
#include <limits>
#include <nlohmann/json.hpp>
#include <unordered_set>
#include <vector>

namespace plimsoll::detail {

namespace {

using json = nlohmann::json;

/// Thrown inside the checker for its first refusal and turned into its Status at the boundary:
/// the checks are many and nested, and each is one line this way.
struct Refusal {
    ErrorKind kind;
    std::string message;
};

constexpr std::uint64_t kSaturated = std::numeric_limits<std::uint64_t>::max();

std::uint64_t addCapped(std::uint64_t a, std::uint64_t b) {
    return a > kSaturated - b ? kSaturated : a + b;
}
std::uint64_t mulCapped(std::uint64_t a, std::uint64_t b) {
    return b != 0 && a > kSaturated / b ? kSaturated : a * b;
}

/// Member names repeated in one object, found by a SAX pass before the document is built:
/// nlohmann keeps the last of two "byteOffset" members and assimp's rapidjson the first, so a
/// checked value could differ from the one assimp reads.
class RepeatedNames : public nlohmann::json_sax<json> {
public:
    bool null() override { return true; }
    bool boolean(bool) override { return true; }
    bool number_integer(number_integer_t) override { return true; }
    bool number_unsigned(number_unsigned_t) override { return true; }
    bool number_float(number_float_t, const string_t&) override { return true; }
    bool string(string_t&) override { return true; }
    bool binary(binary_t&) override { return true; }
    bool start_object(std::size_t) override {
        names_.emplace_back();
        return true;
    }
    bool key(string_t& name) override {
        if (names_.back().insert(name).second) return true;
        repeated = name;
        return false;
    }
    bool end_object() override {
        names_.pop_back();
        return true;
    }
    bool start_array(std::size_t) override { return true; }
    bool end_array() override { return true; }
    bool parse_error(std::size_t, const std::string&, const nlohmann::detail::exception&) override {
        return false;
    }

    std::optional<std::string> repeated;

private:
    std::vector<std::unordered_set<std::string>> names_;
};

/// Bytes of one component; 0 for a component type glTF does not define.
std::uint64_t componentBytes(std::uint64_t type) {
    switch (type) {
        case 5120:  // BYTE
        case 5121:  // UNSIGNED_BYTE
            return 1;
        case 5122:  // SHORT
        case 5123:  // UNSIGNED_SHORT
            return 2;
        case 5125:  // UNSIGNED_INT
        case 5126:  // FLOAT
            return 4;
        default:
            return 0;
    }
}
bool isIndexType(std::uint64_t type) { return type == 5121 || type == 5123 || type == 5125; }

/// Rows (and, for a matrix, columns) of an accessor type; 0 for a type glTF does not define.
std::pair<std::uint64_t, std::uint64_t> typeShape(const std::string& type) {
    if (type == "SCALAR") return {1, 1};
    if (type == "VEC2") return {2, 1};
    if (type == "VEC3") return {3, 1};
    if (type == "VEC4") return {4, 1};
    if (type == "MAT2") return {2, 2};
    if (type == "MAT3") return {3, 3};
    if (type == "MAT4") return {4, 4};
    return {0, 0};
}

/// The decoded size of strict base64 (length a multiple of 4, the alphabet only, '=' only as
/// the last one or two characters), or nothing.
std::optional<std::uint64_t> base64Size(std::string_view text) {
    if (text.size() % 4 != 0) return std::nullopt;
    std::size_t padding = 0;
    if (!text.empty() && text.back() == '=') ++padding;
    if (text.size() >= 2 && text[text.size() - 2] == '=') ++padding;
    if (padding == 1 && text.back() != '=') return std::nullopt;  // "x=" then not '='
    for (std::size_t i = 0; i + padding < text.size(); ++i) {
        const char c = text[i];
        if (!std::isalnum(static_cast<unsigned char>(c)) && c != '+' && c != '/')
            return std::nullopt;
    }
    return text.size() / 4 * 3 - padding;
}

std::string decodeBase64(std::string_view text) {
    auto value = [](char c) -> std::uint32_t {
        if (c >= 'A' && c <= 'Z') return static_cast<std::uint32_t>(c - 'A');
        if (c >= 'a' && c <= 'z') return static_cast<std::uint32_t>(c - 'a' + 26);
        if (c >= '0' && c <= '9') return static_cast<std::uint32_t>(c - '0' + 52);
        return c == '+' ? 62 : c == '/' ? 63 : 0;
    };
    std::string out;
    out.reserve(text.size() / 4 * 3);
    for (std::size_t i = 0; i + 4 <= text.size(); i += 4) {
        const std::uint32_t bits = value(text[i]) << 18 | value(text[i + 1]) << 12 |
                                   value(text[i + 2]) << 6 | value(text[i + 3]);
        out += static_cast<char>(bits >> 16 & 0xFF);
        if (text[i + 2] != '=') out += static_cast<char>(bits >> 8 & 0xFF);
        if (text[i + 3] != '=') out += static_cast<char>(bits & 0xFF);
    }
    return out;
}

struct BufferInfo {
    std::uint64_t length = 0;  // byteLength, checked against the bytes it has
    std::string_view bytes;    // its bytes where they are at hand (GLB, external, raw URI)
    std::string_view base64;   // a base64 data URI's text, decoded when needed
    std::shared_ptr<const std::string> held;  // an external file's or a decoded URI's bytes
};
struct ViewInfo {
    std::uint64_t buffer = 0, offset = 0, length = 0, stride = 0;
};
struct AccessorInfo {
    std::uint64_t count = 0, componentType = 0, components = 0, elementBytes = 0;
    std::string type;
    bool hasView = false;
    std::uint64_t view = 0, offset = 0, stride = 0;  ///< where its elements are, with a view
    bool sparse = false;
};

class GltfChecker {
public:
    GltfChecker(const std::string& file, const json& root, std::optional<std::string_view> glbBin,
                const ReadReferencedFile& readReferenced)
        : file_(file), root_(root), glbBin_(glbBin), read_(readReferenced) {}

    void run() {
        if (!root_.is_object()) refuse("(the document)", "not a JSON object");
        checkBuffers();
        checkBufferViews();
        checkAccessors();
        checkImages();
        checkMaterials();
        checkNodes();
        checkMeshes();
        checkSkins();
        checkAnimations();
    }

private:
    [[noreturn]] void refuse(const std::string& path, const std::string& problem,
                             ErrorKind kind = ErrorKind::format) const {
        throw Refusal{kind, file_ + ": glTF " + path + ": " + problem};
    }
    [[noreturn]] void refuseLimit(const std::string& path, const std::string& what,
                                  std::uint64_t amount, const char* limitName,
                                  std::uint64_t limit) const {
        refuse(path,
               what + " " + std::to_string(amount) + ", more than the limit " + limitName + " = " +
                   std::to_string(limit) + " (limits.h)",
               ErrorKind::limit);
    }

    static std::string at(const std::string& path, const char* key) { return path + "." + key; }
    static std::string at(const std::string& path, std::size_t index) {
        return path + "[" + std::to_string(index) + "]";
    }

    /// The array `name` of the document (empty when absent), each element an object.
    const json& topArray(const char* name) {
        static const json kEmpty = json::array();
        const auto it = root_.find(name);
        if (it == root_.end()) return kEmpty;
        if (!it->is_array()) refuse(name, "not an array: " + jsonExcerpt(*it));
        for (std::size_t i = 0; i < it->size(); ++i)
            if (!(*it)[i].is_object())
                refuse(at(name, i), "not an object: " + jsonExcerpt((*it)[i]));
        return *it;
    }
    std::size_t topSize(const char* name) {
        const auto it = root_.find(name);
        return it != root_.end() && it->is_array() ? it->size() : 0;
    }

    const json* member(const json& object, const char* key) const {
        const auto it = object.find(key);
        return it == object.end() ? nullptr : &*it;
    }
    const json* objectMember(const json& object, const char* key, const std::string& path) const {
        const json* value = member(object, key);
        if (value && !value->is_object())
            refuse(at(path, key), "not an object: " + jsonExcerpt(*value));
        return value;
    }
    std::optional<std::uint64_t> optionalNumber(const json& object, const char* key,
                                                const std::string& path) const {
        const json* value = member(object, key);
        if (!value) return std::nullopt;
        if (!value->is_number_unsigned())
            refuse(at(path, key), "not a whole number of at least 0: " + jsonExcerpt(*value));
        return value->get<std::uint64_t>();
    }
    std::uint64_t requiredNumber(const json& object, const char* key,
                                 const std::string& path) const {
        const std::optional<std::uint64_t> value = optionalNumber(object, key, path);
        if (!value) refuse(at(path, key), "missing");
        return *value;
    }
    /// An index into the document's array `array` of `size` elements.
    void checkIndex(std::uint64_t index, const std::string& path, const char* array,
                    std::size_t size) const {
        if (index >= size)
            refuse(path, std::to_string(index) + " names no element of " + array +
                             " (the file has " + std::to_string(size) + ")");
    }
    std::optional<std::uint64_t> optionalIndex(const json& object, const char* key,
                                               const std::string& path, const char* array,
                                               std::size_t size) const {
        const std::optional<std::uint64_t> index = optionalNumber(object, key, path);
        if (index) checkIndex(*index, at(path, key), array, size);
        return index;
    }
    std::uint64_t requiredIndex(const json& object, const char* key, const std::string& path,
                                const char* array, std::size_t size) const {
        const std::optional<std::uint64_t> index = optionalIndex(object, key, path, array, size);
        if (!index) refuse(at(path, key), "missing");
        return *index;
    }
    std::uint64_t indexValue(const json& value, const std::string& path, const char* array,
                             std::size_t size) const {
        if (!value.is_number_unsigned())
            refuse(path, "not a whole number of at least 0: " + jsonExcerpt(value));
        checkIndex(value.get<std::uint64_t>(), path, array, size);
        return value.get<std::uint64_t>();
    }

    /// A data URI "data:[type][;base64],DATA": its data, decoded size and whether it is base64.
    /// Assimp keeps the offsets of its header's parts in a signed char each, so a header past
    /// 127 bytes made it read before the string: refused past 120.
    struct DataUri {
        std::string_view data;
        std::uint64_t size = 0;
        bool base64 = false;
    };
    /// A URI without control characters: assimp takes one starting with byte 0x10 for a data
    /// URI it has already parsed and reads the offsets of its parts from the next four bytes.
    void checkUriText(std::string_view uri, const std::string& path) const {
        for (const char c : uri)
            if (static_cast<unsigned char>(c) < 0x20)
                refuse(path, "a URI with a control character: " + boundedExcerpt(uri));
    }
    DataUri dataUri(std::string_view uri, const std::string& path) const {
        const std::size_t comma = uri.find(',');
        if (comma == std::string_view::npos)
            refuse(path, "a data URI without a comma: " + boundedExcerpt(uri));
        if (comma > 120)
            refuse(path, "a data URI whose header (before its comma) is " + std::to_string(comma) +
                             " bytes, more than 120: " + boundedExcerpt(uri));
        DataUri out;
        const std::string_view header = uri.substr(5, comma - 5);
        out.data = uri.substr(comma + 1);
        out.base64 = header.find(";base64") != std::string_view::npos;
        if (!out.base64) {
            out.size = out.data.size();
            return out;
        }
        const std::optional<std::uint64_t> size = base64Size(out.data);
        if (!size) refuse(path, "a data URI whose base64 data is not well formed");
        out.size = *size;
        return out;
    }

    void checkBuffers() {
        const json& buffers = topArray("buffers");
        for (std::size_t i = 0; i < buffers.size(); ++i) {
            const json& buffer = buffers[i];
            const std::string path = at("buffers", i);
            BufferInfo info;
            info.length = requiredNumber(buffer, "byteLength", path);
            const json* uri = member(buffer, "uri");
            if (uri && !uri->is_string())
                refuse(at(path, "uri"), "not a string: " + jsonExcerpt(*uri));
            if (uri) checkUriText(uri->get_ref<const std::string&>(), at(path, "uri"));
            const std::string what = at(path, "byteLength");
            std::uint64_t has = 0;
            if (glbBin_ && i == 0) {
                // Assimp gives a GLB's first buffer the BIN chunk, whatever its uri says.
                info.bytes = *glbBin_;
                has = glbBin_->size();
                if (info.length > has)
                    refuse(what, std::to_string(info.length) +
                                     " bytes, the GLB's BIN chunk holds " + std::to_string(has));
            } else if (!uri) {
                if (info.length > 0)
                    refuse(path, "no uri (only a GLB's first buffer, its BIN chunk, has none)");
            } else if (const std::string& text = uri->get_ref<const std::string&>();
                       text.starts_with("data:")) {
                const DataUri data = dataUri(text, at(path, "uri"));
                has = data.size;
                (data.base64 ? info.base64 : info.bytes) = data.data;
                if (info.length > has)
                    refuse(what, std::to_string(info.length) + " bytes, its data URI holds " +
                                     std::to_string(has));
            } else if (info.length > 0) {
                // Assimp opens the file only for a buffer of some bytes.
                if (!read_)
                    refuse(
                        at(path, "uri"),
                        "refers to \"" + boundedExcerpt(text) + "\", which is not read from memory",
                        ErrorKind::io);
                Result<std::shared_ptr<const std::string>> bytes = read_(text);
                if (!bytes) throw Refusal{bytes.error().kind, bytes.error().message};
                info.held = *bytes;
                info.bytes = *info.held;
                has = info.bytes.size();
                if (info.length > has)
                    refuse(what, std::to_string(info.length) + " bytes, the file \"" +
                                     boundedExcerpt(text) + "\" has " + std::to_string(has));
            }
            buffers_.push_back(std::move(info));
        }
    }

    /// A buffer's bytes (decoding a base64 data URI the first time).
    std::string_view bufferBytes(std::uint64_t index) {
        BufferInfo& buffer = buffers_[index];
        if (buffer.bytes.empty() && !buffer.base64.empty()) {
            buffer.held = std::make_shared<const std::string>(decodeBase64(buffer.base64));
            buffer.bytes = *buffer.held;
        }
        return buffer.bytes;
    }

    void checkBufferViews() {
        const json& views = topArray("bufferViews");
        for (std::size_t i = 0; i < views.size(); ++i) {
            const json& view = views[i];
            const std::string path = at("bufferViews", i);
            ViewInfo info;
            info.buffer = requiredIndex(view, "buffer", path, "buffers", buffers_.size());
            info.offset = optionalNumber(view, "byteOffset", path).value_or(0);
            info.length = requiredNumber(view, "byteLength", path);
            const std::uint64_t has = buffers_[info.buffer].length;
            if (info.offset > has || info.length > has - info.offset)
                refuse(path, "byteOffset " + std::to_string(info.offset) + " and byteLength " +
                                 std::to_string(info.length) + " reach past the end of buffers[" +
                                 std::to_string(info.buffer) + "] (" + std::to_string(has) +
                                 " bytes)");
            if (const std::optional<std::uint64_t> stride =
                    optionalNumber(view, "byteStride", path)) {
                if (*stride < 4 || *stride > 252 || *stride % 4 != 0)
                    refuse(at(path, "byteStride"),
                           std::to_string(*stride) + " (glTF: 4 to 252, a multiple of 4)");
                info.stride = *stride;
            }
            views_.push_back(info);
        }
    }

    /// `count` elements of `elementBytes` each, `stride` apart, from `offset` in bufferViews[v]:
    /// the last one ends inside the view.
    void checkExtent(const std::string& path, std::uint64_t viewIndex, std::uint64_t offset,
                     std::uint64_t count, std::uint64_t stride, std::uint64_t elementBytes) const {
        const ViewInfo& view = views_[viewIndex];
        // count >= 1, stride <= 252 or the element's size, count <= kMaxVertices: no wrap.
        const std::uint64_t span = (count - 1) * stride + elementBytes;
        if (offset > view.length || span > view.length - offset)
            refuse(path, std::to_string(count) + " elements of " + std::to_string(elementBytes) +
                             " bytes, " + std::to_string(stride) + " apart, from byte " +
                             std::to_string(offset) + " need " + std::to_string(span) +
                             " bytes; bufferViews[" + std::to_string(viewIndex) + "] has " +
                             std::to_string(view.length > offset ? view.length - offset : 0) +
                             " from there");
    }

    void checkAccessors() {
        const json& accessors = topArray("accessors");
        std::uint64_t zeroFilled = 0;
        for (std::size_t i = 0; i < accessors.size(); ++i) {
            const json& accessor = accessors[i];
            const std::string path = at("accessors", i);
            AccessorInfo info;
            info.componentType = requiredNumber(accessor, "componentType", path);
            const std::uint64_t size = componentBytes(info.componentType);
            if (size == 0)
                refuse(at(path, "componentType"),
                       std::to_string(info.componentType) + " is not a glTF component type");
            const json* type = member(accessor, "type");
            if (!type) refuse(at(path, "type"), "missing");
            const auto [rows, columns] = type->is_string()
                                             ? typeShape(type->get_ref<const std::string&>())
                                             : std::pair<std::uint64_t, std::uint64_t>{0, 0};
            if (rows == 0) refuse(at(path, "type"), jsonExcerpt(*type) + " is not a glTF type");
            info.type = type->get<std::string>();
            info.components = rows * columns;
            // A matrix's columns start on 4-byte boundaries (MAT3 of bytes: 12, not 9).
            info.elementBytes = columns == 1 ? rows * size : columns * ((rows * size + 3) / 4 * 4);
            info.count = requiredNumber(accessor, "count", path);
            if (info.count == 0)
                refuse(at(path, "count"), "0 (an accessor has at least 1 element)");
            if (info.count > kMaxVertices)
                refuseLimit(at(path, "count"), "elements:", info.count, "kMaxVertices",
                            kMaxVertices);
            const std::uint64_t offset = optionalNumber(accessor, "byteOffset", path).value_or(0);
            const std::optional<std::uint64_t> view =
                optionalIndex(accessor, "bufferView", path, "bufferViews", views_.size());
            info.hasView = view.has_value();
            info.sparse = accessor.contains("sparse");
            if (view) {
                const std::uint64_t stride =
                    views_[*view].stride ? views_[*view].stride : info.elementBytes;
                info.view = *view;
                info.offset = offset;
                info.stride = stride;
                if (stride < info.elementBytes)
                    refuse(path, "bufferViews[" + std::to_string(*view) + "].byteStride " +
                                     std::to_string(stride) + " is less than an element (" +
                                     std::to_string(info.elementBytes) + " bytes)");
                checkExtent(path, *view, offset, info.count, stride, info.elementBytes);
            } else {
                // All zeros, allocated whole by assimp (when it has sparse values to patch in).
                zeroFilled = addCapped(zeroFilled, info.count * info.elementBytes);
                if (zeroFilled > kMaxGltfZeroFilledBytes)
                    refuseLimit(path,
                                "accessors without a bufferView (zeros) need bytes:", zeroFilled,
                                "kMaxGltfZeroFilledBytes", kMaxGltfZeroFilledBytes);
            }
            if (const json* sparse = objectMember(accessor, "sparse", path)) {
                // Assimp copies a sparse accessor's elements packed, then reads the copy with
                // the view's stride: past its end where the stride is larger.
                if (view && views_[*view].stride != 0 &&
                    views_[*view].stride != info.components * size)
                    refuse(path, "a sparse accessor on bufferViews[" + std::to_string(*view) +
                                     "], whose byteStride " + std::to_string(views_[*view].stride) +
                                     " is not its element's size (assimp reads it packed)");
                checkSparse(*sparse, at(path, "sparse"), info);
            }
            accessors_.push_back(std::move(info));
        }
    }

    /// A sparse accessor: its count within the accessor's, its indices and values each from a
    /// view they fit in, and every index naming an element of the accessor (assimp writes each
    /// value at index times element size without looking).
    void checkSparse(const json& sparse, const std::string& path, const AccessorInfo& accessor) {
        const std::uint64_t count = requiredNumber(sparse, "count", path);
        if (count == 0 || count > accessor.count)
            refuse(at(path, "count"), std::to_string(count) + " (1 to the accessor's count, " +
                                          std::to_string(accessor.count) + ")");
        const json* indices = objectMember(sparse, "indices", path);
        if (!indices) refuse(at(path, "indices"), "missing");
        const json* values = objectMember(sparse, "values", path);
        if (!values) refuse(at(path, "values"), "missing");

        const std::string indicesPath = at(path, "indices");
        const std::uint64_t indicesView =
            requiredIndex(*indices, "bufferView", indicesPath, "bufferViews", views_.size());
        const std::uint64_t indicesOffset =
            optionalNumber(*indices, "byteOffset", indicesPath).value_or(0);
        const std::uint64_t indexType = requiredNumber(*indices, "componentType", indicesPath);
        if (!isIndexType(indexType))
            refuse(at(indicesPath, "componentType"),
                   std::to_string(indexType) +
                       " is not an index type (5121, 5123 or 5125: unsigned byte, short, int)");
        // Assimp 5.2 reads the indices' type from the sparse object itself, unsigned short when
        // it is not there: both readings are checked, so neither reads past the view.
        const std::uint64_t assimpType =
            optionalNumber(sparse, "componentType", path).value_or(5123);
        if (!isIndexType(assimpType))
            refuse(at(path, "componentType"),
                   std::to_string(assimpType) + " is not an index type (5121, 5123 or 5125)");
        const std::uint64_t indexBytes =
            std::max(componentBytes(indexType), componentBytes(assimpType));
        checkExtent(indicesPath, indicesView, indicesOffset, count, indexBytes, indexBytes);

        const std::string valuesPath = at(path, "values");
        const std::uint64_t valuesView =
            requiredIndex(*values, "bufferView", valuesPath, "bufferViews", views_.size());
        const std::uint64_t valuesOffset =
            optionalNumber(*values, "byteOffset", valuesPath).value_or(0);
        checkExtent(valuesPath, valuesView, valuesOffset, count, accessor.elementBytes,
                    accessor.elementBytes);

        const ViewInfo& view = views_[indicesView];
        const std::string_view bytes = bufferBytes(view.buffer);
        const std::uint64_t start = view.offset + indicesOffset;  // inside the buffer, checked
        for (const std::uint64_t type : {indexType, assimpType}) {
            const std::uint64_t bytesEach = componentBytes(type);
            for (std::uint64_t k = 0; k < count; ++k) {
                std::uint64_t index = 0;
                for (std::uint64_t b = bytesEach; b-- > 0;)
                    index =
                        index << 8 | static_cast<unsigned char>(bytes[start + k * bytesEach + b]);
                if (index >= accessor.count)
                    refuse(indicesPath, "index " + std::to_string(k) + " is " +
                                            std::to_string(index) + " (as component type " +
                                            std::to_string(type) + "), past the accessor's " +
                                            std::to_string(accessor.count) + " elements");
            }
        }
    }

    void checkImages() {
        const json& images = topArray("images");
        for (std::size_t i = 0; i < images.size(); ++i) {
            const std::string path = at("images", i);
            optionalIndex(images[i], "bufferView", path, "bufferViews", views_.size());
            const json* uri = member(images[i], "uri");
            if (uri && !uri->is_string())
                refuse(at(path, "uri"), "not a string: " + jsonExcerpt(*uri));
            if (uri) checkUriText(uri->get_ref<const std::string&>(), at(path, "uri"));
            if (uri && uri->get_ref<const std::string&>().starts_with("data:"))
                dataUri(uri->get_ref<const std::string&>(), at(path, "uri"));
        }
    }

    /// Texture transforms anywhere in the materials: assimp reads the first two elements of
    /// their offset and scale arrays without looking at their size (an empty array: a read
    /// through a null pointer). The document nests at most kMaxJsonDepth deep, so this
    /// recursion is bounded.
    void checkTextureTransforms(const json& value, const std::string& path) const {
        if (value.is_array()) {
            for (std::size_t i = 0; i < value.size(); ++i)
                checkTextureTransforms(value[i], at(path, i));
            return;
        }
        if (!value.is_object()) return;
        for (auto it = value.begin(); it != value.end(); ++it) {
            const std::string inner = path + "." + boundedExcerpt(it.key());
            if (it.key() == "KHR_texture_transform" && it->is_object()) {
                for (const char* key : {"offset", "scale"}) {
                    const json* pair = member(*it, key);
                    if (pair && (!pair->is_array() || pair->size() != 2 ||
                                 !(*pair)[0].is_number() || !(*pair)[1].is_number()))
                        refuse(at(inner, key), "not two numbers: " + jsonExcerpt(*pair));
                }
            }
            checkTextureTransforms(*it, inner);
        }
    }
    void checkMaterials() { checkTextureTransforms(topArray("materials"), "materials"); }

    /// The node tree: children and meshes exist, no node is its own ancestor, no chain is
    /// deeper than kMaxGltfNodeDepth (assimp walks the tree recursively), each node has at most
    /// one parent (assimp imports a node once per path to it: two parents at each of 64 levels
    /// are 2^64 imports), and a scene lists each of its roots once. Walked iteratively: a
    /// recursive walk is what overflows.
    void checkNodes() {
        const json& nodes = topArray("nodes");
        const std::size_t n = nodes.size();
        const std::size_t meshes = topSize("meshes");
        std::vector<std::vector<std::size_t>> children(n);
        std::vector<int> parents(n, 0);
        meshUses_.assign(meshes, 0);
        for (std::size_t i = 0; i < n; ++i) {
            const std::string path = at("nodes", i);
            if (const std::optional<std::uint64_t> mesh =
                    optionalIndex(nodes[i], "mesh", path, "meshes", meshes))
                ++meshUses_[*mesh];
            const json* list = member(nodes[i], "children");
            if (!list) continue;
            if (!list->is_array()) refuse(at(path, "children"), "not an array");
            for (const json& c : *list) {
                if (!c.is_number_unsigned() || c.get<std::uint64_t>() >= n)
                    throw Refusal{ErrorKind::format, file_ + ": glTF node " + std::to_string(i) +
                                                         " names child " + jsonExcerpt(c) +
                                                         ", not a node of the file"};
                children[i].push_back(c.get<std::size_t>());
                ++parents[c.get<std::size_t>()];
            }
        }
        std::vector<int> state(n, 0);  // 0: unseen, 1: on the current path, 2: done
        std::vector<std::pair<std::size_t, std::size_t>> path;  // node, next child
        for (std::size_t r = 0; r < n; ++r) {
            if (state[r] != 0 || parents[r] != 0) continue;
            path.push_back({r, 0});
            state[r] = 1;
            while (!path.empty()) {
                auto& [node, next] = path.back();
                if (next == children[node].size()) {
                    state[node] = 2;
                    path.pop_back();
                    continue;
                }
                const std::size_t child = children[node][next++];
                if (state[child] == 1)
                    throw Refusal{ErrorKind::format, file_ + ": glTF node " +
                                                         std::to_string(child) +
                                                         " is its own ancestor (a cycle)"};
                if (state[child] == 2) continue;  // a second parent, refused below
                if (path.size() >= kMaxGltfNodeDepth)
                    throw Refusal{ErrorKind::limit,
                                  file_ + ": glTF nodes nested more than " +
                                      std::to_string(kMaxGltfNodeDepth) +
                                      " deep, more than the limit kMaxGltfNodeDepth (limits.h)"};
                state[child] = 1;
                path.push_back({child, 0});
            }
        }
        for (std::size_t i = 0; i < n; ++i) {
            if (state[i] == 0)
                throw Refusal{ErrorKind::format, file_ + ": glTF node " + std::to_string(i) +
                                                     " is in a cycle of nodes"};
            if (parents[i] > 1)
                refuse(at("nodes", i), "the child of " + std::to_string(parents[i]) +
                                           " nodes (a glTF node has at most one parent)");
        }
        const json& scenes = topArray("scenes");
        for (std::size_t s = 0; s < scenes.size(); ++s) {
            const json* roots = member(scenes[s], "nodes");
            if (!roots) continue;
            const std::string rootsPath = at(at("scenes", s), "nodes");
            if (!roots->is_array()) refuse(rootsPath, "not an array");
            std::unordered_set<std::size_t> listed;
            for (std::size_t k = 0; k < roots->size(); ++k) {
                const std::size_t root = indexValue((*roots)[k], at(rootsPath, k), "nodes", n);
                if (!listed.insert(root).second)
                    refuse(at(rootsPath, k), "node " + std::to_string(root) + " is listed twice");
                if (parents[root] > 0)
                    refuse(at(rootsPath, k),
                           "node " + std::to_string(root) + " has a parent, so is not a root");
            }
        }
    }

    /// An accessor a primitive uses, by the index at `object[key]`.
    const AccessorInfo& accessorAt(const json& value, const std::string& path) const {
        return accessors_[indexValue(value, path, "accessors", accessors_.size())];
    }

    /// Every primitive: accessors that exist, attributes of one count, indices of an index type,
    /// enough elements for its mode (assimp's strips and fans of fewer wrote past an empty face
    /// array), and no Draco compression. What assimp copies out is counted per node that
    /// instances the mesh, against kMaxVertices and kMaxTriangles, before it allocates any.
    void checkMeshes() {
        const json& meshes = topArray("meshes");
        std::uint64_t vertices = 0, corners = 0;
        for (std::size_t m = 0; m < meshes.size(); ++m) {
            const std::string meshPath = at("meshes", m);
            const json* primitives = member(meshes[m], "primitives");
            if (!primitives) continue;
            if (!primitives->is_array()) refuse(at(meshPath, "primitives"), "not an array");
            const std::uint64_t instances = std::max<std::uint64_t>(1, meshUses_[m]);
            for (std::size_t p = 0; p < primitives->size(); ++p) {
                const json& primitive = (*primitives)[p];
                const std::string path = at(at(meshPath, "primitives"), p);
                if (!primitive.is_object()) refuse(path, "not an object");
                if (const json* extensions = objectMember(primitive, "extensions", path);
                    extensions && extensions->contains("KHR_draco_mesh_compression"))
                    refuse(at(at(path, "extensions"), "KHR_draco_mesh_compression"),
                           "Draco-compressed geometry is not read (assimp's decoder trusts the "
                           "attribute layout inside the compressed data); export the mesh "
                           "without Draco compression",
                           ErrorKind::unsupported);
                const json* attributes = objectMember(primitive, "attributes", path);
                if (!attributes) refuse(at(path, "attributes"), "missing");
                std::optional<std::uint64_t> count;
                auto sameCount = [&](const json& set, const std::string& setPath) {
                    const auto position = set.find("POSITION");
                    if (position != set.end() && !count)
                        count = accessorAt(*position, at(setPath, "POSITION")).count;
                    for (auto it = set.begin(); it != set.end(); ++it) {
                        const std::string attributePath = setPath + "." + boundedExcerpt(it.key());
                        const AccessorInfo& accessor = accessorAt(*it, attributePath);
                        if (!count) count = accessor.count;
                        if (accessor.count != *count)
                            refuse(attributePath, std::to_string(accessor.count) +
                                                      " elements, the primitive's "
                                                      "vertices are " +
                                                      std::to_string(*count) +
                                                      " (a primitive's attributes have one count)");
                    }
                };
                // Assimp counts a primitive's vertices by its POSITION alone: a fan or strip
                // of none made it allocate 2^32 - 2 faces (the glTF fuzzer's first finding).
                if (!attributes->contains("POSITION"))
                    refuse(at(at(path, "attributes"), "POSITION"),
                           "missing (a primitive without positions has no surface)");
                sameCount(*attributes, at(path, "attributes"));
                std::uint64_t targets = 0;
                if (const json* list = member(primitive, "targets")) {
                    if (!list->is_array()) refuse(at(path, "targets"), "not an array");
                    targets = list->size();
                    for (std::size_t t = 0; t < list->size(); ++t) {
                        const std::string targetPath = at(at(path, "targets"), t);
                        if (!(*list)[t].is_object()) refuse(targetPath, "not an object");
                        // Assimp takes the number after "POSITION_" (NORMAL_, TANGENT_) in a
                        // target as the index of a list it resizes to hold it: "POSITION_-1"
                        // wrote far outside it, "POSITION_2000000000" asked for 32 GB.
                        for (auto it = (*list)[t].begin(); it != (*list)[t].end(); ++it)
                            for (const char* name : {"POSITION", "NORMAL", "TANGENT"})
                                if (it.key().starts_with(name) && it.key() != name)
                                    refuse(targetPath + "." + boundedExcerpt(it.key()),
                                           "a morph target attribute named after " +
                                               std::string(name) + " but not " + name);
                        sameCount((*list)[t], targetPath);
                    }
                }
                const std::uint64_t mode = optionalNumber(primitive, "mode", path).value_or(4);
                if (mode > 6)
                    refuse(at(path, "mode"), std::to_string(mode) + " is not a glTF mode (0 to 6)");
                std::uint64_t elements = count.value_or(0);
                if (const json* indices = member(primitive, "indices")) {
                    const AccessorInfo& accessor = accessorAt(*indices, at(path, "indices"));
                    if (accessor.type != "SCALAR" || !isIndexType(accessor.componentType))
                        refuse(at(path, "indices"),
                               "accessors[" + std::to_string(indices->get<std::uint64_t>()) +
                                   "] is not SCALAR of an unsigned integer type");
                    elements = accessor.count;
                    checkIndexValues(accessor, count.value_or(0), at(path, "indices"));
                }
                // Points 1, lines and line strips or loops 2, triangles of any kind 3.
                const std::uint64_t least = mode == 0 ? 1 : mode <= 3 ? 2 : 3;
                if (elements < least)
                    refuse(path, std::to_string(elements) + " vertices for mode " +
                                     std::to_string(mode) + ", which needs at least " +
                                     std::to_string(least));
                vertices = addCapped(
                    vertices, mulCapped(instances, mulCapped(count.value_or(0), 1 + targets)));
                corners = addCapped(corners, mulCapped(instances, elements));
            }
        }
        if (vertices > kMaxVertices)
            refuseLimit("meshes", "vertices over every instance and morph target:", vertices,
                        "kMaxVertices", kMaxVertices);
        if (corners > 3 * kMaxTriangles)
            refuseLimit("meshes", "triangle corners over every instance:", corners,
                        "3 * kMaxTriangles", 3 * kMaxTriangles);
    }

    /// Every index a primitive's vertices: assimp logs an index past them and leaves the face
    /// unwritten, and its line loops and strips then read the face before the first (a null
    /// pointer: the GLB fuzzer's finding).
    void checkIndexValues(const AccessorInfo& accessor, std::uint64_t vertices,
                          const std::string& path) {
        if (accessor.sparse)
            refuse(path,
                   "a sparse accessor of indices is not read (its patched values cannot be "
                   "checked before assimp uses them)");
        if (!accessor.hasView) return;  // all zeros: vertex 0, which every primitive has
        const ViewInfo& view = views_[accessor.view];
        const std::string_view bytes = bufferBytes(view.buffer);
        const std::uint64_t start = view.offset + accessor.offset;  // inside, checked
        const std::uint64_t bytesEach = componentBytes(accessor.componentType);
        for (std::uint64_t k = 0; k < accessor.count; ++k) {
            std::uint64_t index = 0;
            const std::uint64_t at = start + k * accessor.stride;
            for (std::uint64_t b = bytesEach; b-- > 0;)
                index = index << 8 | static_cast<unsigned char>(bytes[at + b]);
            if (index >= vertices)
                refuse(path, "index " + std::to_string(k) + " is " + std::to_string(index) +
                                 ", past the primitive's " + std::to_string(vertices) +
                                 " vertices");
        }
    }

    /// Skins: joints that are nodes, inverse bind matrices (MAT4 of floats) for each of them;
    /// assimp copies the matrices once per primitive of each node the skin is used by.
    void checkSkins() {
        const json& skins = topArray("skins");
        std::vector<std::uint64_t> matrices(skins.size(), 0);
        for (std::size_t s = 0; s < skins.size(); ++s) {
            const std::string path = at("skins", s);
            std::uint64_t joints = 0;
            if (const json* list = member(skins[s], "joints")) {
                if (!list->is_array()) refuse(at(path, "joints"), "not an array");
                for (std::size_t k = 0; k < list->size(); ++k)
                    indexValue((*list)[k], at(at(path, "joints"), k), "nodes", topSize("nodes"));
                joints = list->size();
            }
            if (const std::optional<std::uint64_t> index = optionalIndex(
                    skins[s], "inverseBindMatrices", path, "accessors", accessors_.size())) {
                const AccessorInfo& accessor = accessors_[*index];
                if (accessor.type != "MAT4" || accessor.componentType != 5126 ||
                    accessor.count < joints)
                    refuse(at(path, "inverseBindMatrices"),
                           "accessors[" + std::to_string(*index) + "] is not " +
                               std::to_string(joints) + " or more MAT4 of floats (one a joint)");
                matrices[s] = accessor.count;
            }
        }
        const json& nodes = topArray("nodes");
        const json& meshes = topArray("meshes");
        for (std::size_t i = 0; i < nodes.size(); ++i) {
            const std::optional<std::uint64_t> skin =
                optionalIndex(nodes[i], "skin", at("nodes", i), "skins", skins.size());
            const json* mesh = member(nodes[i], "mesh");
            if (!skin || !mesh) continue;
            const json* primitives = member(meshes[mesh->get<std::uint64_t>()], "primitives");
            copied_ =
                addCapped(copied_, mulCapped(matrices[*skin], primitives ? primitives->size() : 0));
        }
        checkCopied("skins");
    }

    /// Animations: channels name samplers of their animation, samplers name accessors, an
    /// output holds an element for each input key; assimp copies a sampler's input and output
    /// once per channel that uses it.
    void checkAnimations() {
        const json& animations = topArray("animations");
        for (std::size_t a = 0; a < animations.size(); ++a) {
            const std::string path = at("animations", a);
            std::vector<std::uint64_t> keys;
            if (const json* samplers = member(animations[a], "samplers")) {
                if (!samplers->is_array()) refuse(at(path, "samplers"), "not an array");
                for (std::size_t s = 0; s < samplers->size(); ++s) {
                    const std::string samplerPath = at(at(path, "samplers"), s);
                    if (!(*samplers)[s].is_object()) refuse(samplerPath, "not an object");
                    const std::uint64_t input = requiredIndex((*samplers)[s], "input", samplerPath,
                                                              "accessors", accessors_.size());
                    const std::uint64_t output = requiredIndex(
                        (*samplers)[s], "output", samplerPath, "accessors", accessors_.size());
                    // Assimp reads an output element for each input key (three for a cubic
                    // spline's in-tangent, value and out-tangent) without comparing counts.
                    const json* interpolation = member((*samplers)[s], "interpolation");
                    const std::uint64_t each =
                        interpolation && *interpolation == "CUBICSPLINE" ? 3 : 1;
                    if (accessors_[output].count < each * accessors_[input].count)
                        refuse(at(samplerPath, "output"),
                               "accessors[" + std::to_string(output) + "] has " +
                                   std::to_string(accessors_[output].count) +
                                   " elements, fewer than " + std::to_string(each) +
                                   " for each of the input's " +
                                   std::to_string(accessors_[input].count) + " keys");
                    keys.push_back(accessors_[input].count + accessors_[output].count);
                }
            }
            if (const json* channels = member(animations[a], "channels")) {
                if (!channels->is_array()) refuse(at(path, "channels"), "not an array");
                for (std::size_t c = 0; c < channels->size(); ++c) {
                    const std::string channelPath = at(at(path, "channels"), c);
                    if (!(*channels)[c].is_object()) refuse(channelPath, "not an object");
                    const std::uint64_t sampler = requiredIndex(
                        (*channels)[c], "sampler", channelPath, "samplers", keys.size());
                    if (const json* target = objectMember((*channels)[c], "target", channelPath))
                        optionalIndex(*target, "node", at(channelPath, "target"), "nodes",
                                      topSize("nodes"));
                    copied_ = addCapped(copied_, keys[sampler]);
                }
            }
        }
        checkCopied("animations");
    }

    /// Keys and matrices assimp copies out of accessors, counted per use, held to the vertex
    /// limit: a real file's are far fewer than its vertices.
    void checkCopied(const char* path) const {
        if (copied_ > kMaxVertices)
            refuseLimit(path, "animation keys and skin matrices over every use:", copied_,
                        "kMaxVertices", kMaxVertices);
    }

    const std::string& file_;
    const json& root_;
    std::optional<std::string_view> glbBin_;
    const ReadReferencedFile& read_;
    std::vector<BufferInfo> buffers_;
    std::vector<ViewInfo> views_;
    std::vector<AccessorInfo> accessors_;
    std::vector<std::uint64_t> meshUses_;
    std::uint64_t copied_ = 0;
};

}  // namespace

Status checkGltf(const std::string& file, std::string_view jsonText,
                 std::optional<std::string_view> glbBin, const ReadReferencedFile& readReferenced) {
    // Deep nesting anywhere (a node's extras 200000 arrays deep) overflows assimp's recursive
    // JSON reader: refused before either parser runs.
    if (Status depth = checkJsonDepth(jsonText, file); !depth.ok()) return depth;
    // Assimp's reader stops at the first NUL byte (GLB JSON chunks are sometimes padded with
    // them), and it does not check UTF-8: the text checked here is the text it reads, with
    // bytes that are not UTF-8 (only ever inside strings, for both) made U+FFFD.
    jsonText = jsonText.substr(0, jsonText.find('\0'));
    const std::string text = validUtf8(jsonText);
    RepeatedNames names;
    if (!nlohmann::json::sax_parse(text, &names)) {
        if (names.repeated)
            return makeError(ErrorKind::format,
                             file + ": glTF JSON names \"" + boundedExcerpt(*names.repeated) +
                                 "\" twice in one object (readers disagree on which counts)");
    }
    const nlohmann::json root = nlohmann::json::parse(text, nullptr, false);
    if (root.is_discarded()) {
        try {
            [[maybe_unused]] const nlohmann::json again = nlohmann::json::parse(text);
        } catch (const nlohmann::json::exception& e) {
            return makeError(ErrorKind::format,
                             file + ": glTF is not JSON: " + boundedExcerpt(e.what(), 200));
        }
    }
    try {
        GltfChecker(file, root, glbBin, readReferenced).run();
    } catch (const Refusal& refusal) {
        return makeError(refusal.kind, refusal.message);
    }
    return Ok{};
}

}  // namespace plimsoll::detail
