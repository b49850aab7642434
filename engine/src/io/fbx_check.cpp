// FBX before assimp: a binary file's records and arrays in one linear pass, then the element
// tree of either form as assimp's parser builds it (no deeper than kMaxFbxDepth), checked against
// what assimp's document and converter read without looking, and the objects Plimsoll does not read
// renamed in assimp's copy (docs/security.md, "Mesh files").
#include "io/mesh_header_check.h"

#include "plimsoll/core/limits.h"

#include <algorithm>
#include <charconv>
#include <functional>
#include <cstdint>
#include <map>
#include <optional>
#include <set>
#include <string>
#include <string_view>
#include <system_error>
#include <variant>
#include <vector>
#include <zlib.h>

namespace plimsoll::detail {

namespace {

Status fbxTooDeep(const std::string& file, std::uint64_t at) {
    return makeError(ErrorKind::limit, file + ": FBX scopes nested more than " +
                                           std::to_string(kMaxFbxDepth) + " deep (at byte " +
                                           std::to_string(at) +
                                           "), more than the limit kMaxFbxDepth (limits.h)");
}

std::uint64_t readLittleEndian(std::string_view bytes, std::size_t at, int size) {
    std::uint64_t v = 0;
    for (int k = size - 1; k >= 0; --k) v = v << 8 | static_cast<unsigned char>(bytes[at + k]);
    return v;
}

/// An array property's zlib data inflates to exactly `expected` bytes and ends there, as assimp's
/// parser needs: it inflates into a buffer of that size and, on any other outcome, throws
/// between zlib's inflateInit and inflateEnd, leaking zlib's state (the FBX fuzzer's first
/// finding). Inflated here through a small window, so that nothing of `expected` is allocated.
/// `each`, where given, sees the inflated bytes a window at a time.
bool inflatesToExactly(
    std::string_view compressed, std::uint64_t expected,
    const std::function<void(const unsigned char*, std::size_t)>& each = nullptr) {
    z_stream stream{};
    if (inflateInit(&stream) != Z_OK) return false;
    stream.next_in = reinterpret_cast<Bytef*>(const_cast<char*>(compressed.data()));
    stream.avail_in = static_cast<uInt>(compressed.size());
    unsigned char window[1 << 15];
    std::uint64_t produced = 0;
    int status = Z_OK;
    while (status == Z_OK && produced <= expected) {
        stream.next_out = window;
        stream.avail_out = sizeof window;
        status = inflate(&stream, Z_NO_FLUSH);
        produced += sizeof window - stream.avail_out;
        if (each) each(window, sizeof window - stream.avail_out);
        if (status == Z_BUF_ERROR && stream.avail_in == 0) break;  // the data ends early
    }
    inflateEnd(&stream);
    return status == Z_STREAM_END && produced == expected;
}

/// The properties of one binary FBX record: every array (f, d, l, i, b) holds its elements raw
/// (encoding 0, exactly count times the element's size) or as zlib data that inflates to exactly
/// that (encoding 1), and all arrays together inflate to no more than kMaxFbxInflatedBytes
/// (assimp allocates each array whole before inflating it). `inflated` sums over the file. A
/// property list assimp's tokenizer cannot read ends the check here: assimp refuses it too.
Status checkFbxProperties(const std::string& file, std::string_view bytes, std::uint64_t at,
                          std::uint64_t count, std::uint64_t end, std::uint64_t& inflated) {
    for (std::uint64_t k = 0; k < count && at < end; ++k) {
        // Scalars (bool, int16, int32, float, double, int64), then strings and raw data (a
        // 4-byte length), then arrays (bool, float, int32, double, int64).
        constexpr std::string_view kScalars = "CYIFDL", kArrays = "bfidl";
        constexpr int kScalarBytes[] = {1, 2, 4, 4, 8, 8}, kElementBytes[] = {1, 4, 4, 8, 8};
        const char type = bytes[at++];
        if (const std::size_t scalar = kScalars.find(type); scalar != std::string_view::npos) {
            at += kScalarBytes[scalar];
            continue;
        }
        if (type == 'S' || type == 'R') {
            if (end - at < 4) return Ok{};
            at += 4 + readLittleEndian(bytes, at, 4);
            continue;
        }
        const std::size_t kind = kArrays.find(type);
        if (kind == std::string_view::npos) return Ok{};
        const std::uint64_t element = kElementBytes[kind];
        if (end - at < 12) return Ok{};
        const std::uint64_t length = readLittleEndian(bytes, at, 4);
        const std::uint64_t encoding = readLittleEndian(bytes, at + 4, 4);
        const std::uint64_t stored = readLittleEndian(bytes, at + 8, 4);
        const std::uint64_t array = at - 1;
        at += 12;
        if (stored > end - at) return Ok{};
        const std::uint64_t expected = length * element;
        auto refused = [&](const std::string& why) {
            return makeError(ErrorKind::format, file + ": the FBX array at byte " +
                                                    std::to_string(array) + " (" +
                                                    std::to_string(length) + " elements of '" +
                                                    std::string(1, type) + "') " + why);
        };
        inflated += expected;
        if (inflated > kMaxFbxInflatedBytes) {
            return makeError(ErrorKind::limit,
                             file + ": the FBX arrays hold more than " +
                                 std::to_string(kMaxFbxInflatedBytes) + " bytes (at byte " +
                                 std::to_string(array) +
                                 "), more than the limit kMaxFbxInflatedBytes (limits.h)");
        }
        if (encoding == 0 && stored != expected)
            return refused("stores " + std::to_string(stored) + " bytes, not " +
                           std::to_string(expected));
        if (encoding == 1 && !inflatesToExactly(bytes.substr(at, stored), expected))
            return refused("has zlib data that does not inflate to its " +
                           std::to_string(expected) + " bytes");
        if (encoding > 1) return refused("has the unknown encoding " + std::to_string(encoding));
        at += stored;
    }
    return Ok{};
}

/// Binary FBX: node records (end offset, property count, property bytes, name, properties,
/// nested records ended by a null record), walked with a stack of end offsets: the nesting
/// (kMaxFbxDepth) and every record's arrays (checkFbxProperties). A record whose offsets do not
/// fit its parent ends the walk: assimp's reader, which meets the records in the same order,
/// stops at the same record with an error, no deeper than the walk went.
Status checkBinaryFbx(const std::string& file, std::string_view bytes) {
    constexpr std::size_t kStart = 27;  // magic (23 bytes) and the version
    if (bytes.size() < kStart) return Ok{};
    const bool wide = readLittleEndian(bytes, 23, 4) >= 7500;  // 64-bit offsets from 7.5
    const int field = wide ? 8 : 4;
    const std::size_t header = 3 * static_cast<std::size_t>(field) + 1;
    std::vector<std::uint64_t> ends{bytes.size()};  // the end of each open scope
    std::uint64_t at = kStart, inflated = 0;
    while (true) {
        while (ends.size() > 1 && at >= ends.back()) {
            at = ends.back();
            ends.pop_back();
        }
        if (at + header > ends.back()) return Ok{};
        const std::uint64_t end = readLittleEndian(bytes, at, field);
        if (end == 0) {  // a null record: the end of this list
            if (ends.size() == 1) return Ok{};
            at = ends.back();
            ends.pop_back();
            continue;
        }
        if (ends.size() > kMaxFbxDepth) return fbxTooDeep(file, at);  // this record's level
        const std::uint64_t propertyCount = readLittleEndian(bytes, at + field, field);
        const std::uint64_t propertyBytes = readLittleEndian(bytes, at + 2 * field, field);
        const std::uint64_t nameBytes = static_cast<unsigned char>(bytes[at + 3 * field]);
        // assimp compares a record's end with its parent's as numbers, but the file's own end
        // is one byte further for it (it appends a NUL): a record ending on that byte passed
        // into reads past the file (the PLY fuzzer's second finding, FBX by content).
        if (end <= at || end > ends.back())
            return makeError(ErrorKind::format, file + ": the FBX record at byte " +
                                                    std::to_string(at) + " ends at byte " +
                                                    std::to_string(end) + ", outside " +
                                                    (ends.size() == 1 ? "the file" : "its parent"));
        // assimp adds the property length to a pointer before comparing it with the record's
        // end: a 64-bit length near 2^64 wraps past that check into an assertion (abort). A
        // length past the record's end is refused here, whatever it is.
        if (propertyBytes > end - at)
            return makeError(ErrorKind::format, file + ": the FBX record at byte " +
                                                    std::to_string(at) + " declares " +
                                                    std::to_string(propertyBytes) +
                                                    " bytes of properties, past its end at byte " +
                                                    std::to_string(end));
        const std::uint64_t properties = at + header + nameBytes;
        if (properties + propertyBytes <= end) {
            Status arrays = checkFbxProperties(file, bytes, properties, propertyCount,
                                               properties + propertyBytes, inflated);
            if (!arrays.ok()) return arrays;
        }
        const std::uint64_t nested = properties + propertyBytes;
        if (nested >= end) {  // no nested records (or offsets assimp refuses)
            at = end;
            continue;
        }
        ends.push_back(end);
        at = nested;
    }
}

// ---------------------------------------------------------------------------------------------
// The element tree: what assimp's FBX parser builds from either form, read the same way, so
// that the rules below judge the tree assimp's document and converter will walk.

/// One property: a binary record's typed value, or an ASCII data token as written.
struct FbxProperty {
    char type = 0;          ///< binary type code; 0 for an ASCII token
    std::string_view data;  ///< ASCII: the token; S/R: the bytes; arrays: the stored bytes
    std::int64_t integer = 0;
    bool isInteger = false;
    std::uint64_t length = 0, encoding = 0;  ///< arrays: elements and encoding (1: zlib)
};

struct FbxElement {
    std::string_view name;
    std::uint64_t nameAt = 0;  ///< byte offset of the name in the file
    std::vector<FbxProperty> properties;
    std::vector<FbxElement> children;

    const FbxElement* child(std::string_view key) const {
        for (const FbxElement& c : children)
            if (c.name == key) return &c;
        return nullptr;
    }
};

/// Where the tree could not be read: assimp's parser would refuse the file there too.
struct FbxSyntaxError {
    std::uint64_t at = 0;
    std::string what;
    bool tooDeep = false;  ///< scopes nested past kMaxFbxDepth
};

std::optional<std::int64_t> integerOf(const FbxProperty& p) {
    if (p.type != 0) return p.isInteger ? std::optional(p.integer) : std::nullopt;
    std::int64_t value = 0;
    const char* first = p.data.data();
    const char* last = first + p.data.size();
    const auto [end, error] = std::from_chars(first, last, value);
    if (error != std::errc() || end != last) return std::nullopt;
    return value;
}

std::optional<std::string_view> stringOf(const FbxProperty& p) {
    if (p.type == 'S') return p.data;
    if (p.type == 0 && p.data.size() >= 2 && p.data.front() == '"' && p.data.back() == '"')
        return p.data.substr(1, p.data.size() - 2);
    return std::nullopt;
}

/// An element's first property as a string ("" where it has none or another type).
std::string_view firstString(const FbxElement* e) {
    if (!e || e->properties.empty()) return {};
    return stringOf(e->properties[0]).value_or(std::string_view());
}

// --- ASCII, as assimp's tokenizer and parser read it ---

struct FbxToken {
    enum Kind { data, key, open, close, comma } kind = data;
    std::string_view text;
    std::uint64_t at = 0, line = 0;
};

/// Tokens as assimp's tokenizer makes them: data, "key:", braces and commas; strings in double
/// quotes (no escapes) are one data token with their quotes; ';' comments to the line's end. It
/// reads the text as a C string: a NUL ends it.
std::variant<std::vector<FbxToken>, FbxSyntaxError> asciiTokens(std::string_view text) {
    text = text.substr(0, std::min(text.size(), text.find('\0')));
    std::vector<FbxToken> tokens;
    std::uint64_t line = 1;
    std::size_t begin = std::string_view::npos;  // start of the pending data token
    const auto flush = [&](std::size_t end, FbxToken::Kind kind) {
        if (begin != std::string_view::npos)
            tokens.push_back({kind, text.substr(begin, end - begin), begin, line});
        begin = std::string_view::npos;
    };
    for (std::size_t i = 0; i < text.size(); ++i) {
        const char c = text[i];
        if (c == '"') {
            if (begin != std::string_view::npos) return FbxSyntaxError{i, "a quote inside a token"};
            const std::size_t end = text.find('"', i + 1);
            if (end == std::string_view::npos) return FbxSyntaxError{i, "an unterminated string"};
            tokens.push_back({FbxToken::data, text.substr(i, end + 1 - i), i, line});
            line +=
                static_cast<std::uint64_t>(std::count(text.begin() + i, text.begin() + end, '\n'));
            i = end;
        } else if (c == ';') {
            flush(i, FbxToken::data);
            const std::size_t end = text.find_first_of("\r\n", i);
            if (end == std::string_view::npos) break;
            i = end - 1;
        } else if (c == '{' || c == '}' || c == ',') {
            flush(i, FbxToken::data);
            tokens.push_back({c == '{'   ? FbxToken::open
                              : c == '}' ? FbxToken::close
                                         : FbxToken::comma,
                              text.substr(i, 1), i, line});
        } else if (c == ':') {
            if (begin == std::string_view::npos) return FbxSyntaxError{i, "a colon with no key"};
            flush(i, FbxToken::key);
        } else if (c == ' ' || c == '\t' || c == '\r' || c == '\n') {
            flush(i, FbxToken::data);
        } else if (begin == std::string_view::npos) {
            begin = i;
        }
        if (c == '\n') ++line;
    }
    flush(text.size(), FbxToken::data);
    return tokens;
}

/// Elements from tokens as assimp's Parser builds them: a key, its data tokens (commas between
/// them, or a new line), then a scope in braces or nothing.
class AsciiTree {
public:
    explicit AsciiTree(const std::vector<FbxToken>& tokens) : tokens_(tokens) {}

    std::optional<FbxSyntaxError> scope(std::vector<FbxElement>& out, std::uint64_t depth) {
        const bool top = depth == 0;
        while (i_ < tokens_.size()) {
            const FbxToken& t = tokens_[i_];
            if (t.kind == FbxToken::close) {
                if (top) i_ = tokens_.size();  // a stray '}' ends the file for assimp
                return std::nullopt;
            }
            if (t.kind != FbxToken::key) return FbxSyntaxError{t.at, "a value where a key belongs"};
            out.emplace_back();
            if (auto error = element(out.back(), depth)) return error;
        }
        if (!top)
            return FbxSyntaxError{tokens_.empty() ? 0 : tokens_.back().at, "a scope not closed"};
        return std::nullopt;
    }

private:
    std::optional<FbxSyntaxError> element(FbxElement& e, std::uint64_t depth) {
        e.name = tokens_[i_].text;
        e.nameAt = tokens_[i_].at;
        ++i_;
        while (i_ < tokens_.size()) {
            const FbxToken& t = tokens_[i_];
            if (t.kind == FbxToken::key || t.kind == FbxToken::close) return std::nullopt;
            ++i_;
            if (t.kind == FbxToken::comma) continue;
            if (t.kind == FbxToken::open) {
                if (depth + 1 > kMaxFbxDepth)
                    return FbxSyntaxError{t.at, "scopes nested too deep", true};
                if (auto error = scope(e.children, depth + 1)) return error;
                if (i_ >= tokens_.size()) return FbxSyntaxError{t.at, "a scope not closed"};
                ++i_;  // its '}'
                return std::nullopt;
            }
            e.properties.push_back({0, t.text});
            if (i_ < tokens_.size() && tokens_[i_].kind == FbxToken::data &&
                tokens_[i_].line != t.line + 1)
                return FbxSyntaxError{tokens_[i_].at, "two values with no comma between them"};
        }
        return FbxSyntaxError{e.nameAt, "the file ends inside an element"};
    }

    const std::vector<FbxToken>& tokens_;
    std::size_t i_ = 0;
};

// --- binary, as assimp's binary tokenizer reads it (after checkBinaryFbx) ---

class BinaryTree {
public:
    explicit BinaryTree(std::string_view bytes)
        : bytes_(bytes), field_(readLittleEndian(bytes, 23, 4) >= 7500 ? 8 : 4) {}

    /// The top level: records up to a null record or the file's end.
    std::optional<FbxSyntaxError> top(std::vector<FbxElement>& out) {
        std::uint64_t at = 27;
        while (at < bytes_.size()) {
            bool ended = false;
            if (auto error = record(at, bytes_.size(), 0, out, ended)) return error;
            if (ended) break;
        }
        return std::nullopt;
    }

private:
    std::uint64_t header() const { return 3 * static_cast<std::uint64_t>(field_) + 1; }
    std::uint64_t sentinel() const { return header(); }

    std::optional<FbxSyntaxError> record(std::uint64_t& at, std::uint64_t limit,
                                         std::uint64_t depth, std::vector<FbxElement>& out,
                                         bool& ended) {
        if (limit - at < header()) return FbxSyntaxError{at, "a record header past its parent"};
        const std::uint64_t end = readLittleEndian(bytes_, at, field_);
        if (end == 0) {
            ended = true;
            at += header();
            return std::nullopt;
        }
        const std::uint64_t count = readLittleEndian(bytes_, at + field_, field_);
        const std::uint64_t length = readLittleEndian(bytes_, at + 2 * field_, field_);
        const std::uint64_t nameBytes = static_cast<unsigned char>(bytes_[at + 3 * field_]);
        const std::uint64_t properties = at + header() + nameBytes;
        if (end <= at || end > limit || properties > end || length > end - properties)
            return FbxSyntaxError{at, "a record whose lengths do not fit"};
        FbxElement& e = out.emplace_back();
        e.name = bytes_.substr(at + header(), nameBytes);
        e.nameAt = at + header();
        if (auto error = readProperties(properties, properties + length, count, e)) return error;
        std::uint64_t nested = properties + length;
        if (nested < end) {
            if (depth + 1 > kMaxFbxDepth)
                return FbxSyntaxError{at, "records nested too deep", true};
            if (end - nested < sentinel()) return FbxSyntaxError{at, "a record without its end"};
            while (nested < end - sentinel()) {
                bool childEnded = false;
                // A null record inside a list does not end it for assimp: the list ends at
                // its parent's sentinel.
                if (auto error =
                        record(nested, end - sentinel(), depth + 1, e.children, childEnded))
                    return error;
            }
        }
        at = end;
        return std::nullopt;
    }

    std::optional<FbxSyntaxError> readProperties(std::uint64_t at, std::uint64_t end,
                                                 std::uint64_t count, FbxElement& e) const {
        constexpr std::string_view kScalars = "CYIFDL", kArrays = "bfidl";
        constexpr int kScalarBytes[] = {1, 2, 4, 4, 8, 8};
        for (std::uint64_t k = 0; k < count; ++k) {
            if (at >= end) return FbxSyntaxError{at, "fewer properties than the record says"};
            FbxProperty p;
            p.type = bytes_[at++];
            if (const std::size_t s = kScalars.find(p.type); s != std::string_view::npos) {
                const int size = kScalarBytes[s];
                if (end - at < static_cast<std::uint64_t>(size))
                    return FbxSyntaxError{at, "a value past its record"};
                const std::uint64_t raw = readLittleEndian(bytes_, at, size);
                if (p.type == 'Y' || p.type == 'I' || p.type == 'L') {
                    p.isInteger = true;
                    p.integer = p.type == 'Y'   ? static_cast<std::int16_t>(raw)
                                : p.type == 'I' ? static_cast<std::int32_t>(raw)
                                                : static_cast<std::int64_t>(raw);
                }
                at += size;
            } else if (p.type == 'S' || p.type == 'R') {
                if (end - at < 4) return FbxSyntaxError{at, "a string past its record"};
                const std::uint64_t size = readLittleEndian(bytes_, at, 4);
                if (end - at - 4 < size) return FbxSyntaxError{at, "a string past its record"};
                p.data = bytes_.substr(at + 4, size);
                at += 4 + size;
            } else if (kArrays.find(p.type) != std::string_view::npos) {
                if (end - at < 12) return FbxSyntaxError{at, "an array past its record"};
                p.length = readLittleEndian(bytes_, at, 4);
                p.encoding = readLittleEndian(bytes_, at + 4, 4);
                const std::uint64_t stored = readLittleEndian(bytes_, at + 8, 4);
                if (end - at - 12 < stored) return FbxSyntaxError{at, "an array past its record"};
                p.data = bytes_.substr(at + 12, stored);
                at += 12 + stored;
            } else {
                return FbxSyntaxError{at - 1, "a property of unknown type"};
            }
            e.properties.push_back(p);
        }
        return std::nullopt;
    }

    std::string_view bytes_;
    int field_;
};

/// How many values of an integer array element are negative: a binary 'i' or 'l' array, raw or
/// inflated through a small window (its size was checked by checkFbxProperties), or the ASCII
/// values of its "a" child; nothing where a value is not an integer. Counted as the bytes go by,
/// so that an array that inflates to gigabytes is never held here.
std::optional<std::uint64_t> negativeCount(const FbxElement& e) {
    std::uint64_t negatives = 0;
    if (!e.properties.empty() && (e.properties[0].type == 'i' || e.properties[0].type == 'l')) {
        const FbxProperty& p = e.properties[0];
        const std::uint64_t size = p.type == 'i' ? 4 : 8;
        std::uint64_t seen = 0;
        // Little-endian: a value's sign is the top bit of its last byte.
        const auto count = [&](const unsigned char* bytes, std::size_t n) {
            for (std::size_t k = 0; k < n; ++k, ++seen)
                if (seen % size == size - 1 && (bytes[k] & 0x80) != 0) ++negatives;
        };
        const std::string_view data = p.data;
        if (p.encoding == 0)
            count(reinterpret_cast<const unsigned char*>(data.data()), data.size());
        else if (!inflatesToExactly(data, p.length * size, count))
            return std::nullopt;
        if (seen != p.length * size) return std::nullopt;
        return negatives;
    }
    const FbxElement* a = e.child("a");
    if (!a) return negatives;
    for (const FbxProperty& p : a->properties) {
        const std::optional<std::int64_t> v = integerOf(p);
        if (!v) return std::nullopt;
        negatives += *v < 0 ? 1 : 0;
    }
    return negatives;
}

/// Elements in an array element: a binary array's count, or the ASCII "a" child's values.
std::uint64_t arrayLength(const FbxElement& e) {
    if (!e.properties.empty() && e.properties[0].type != 0 && e.properties[0].length > 0)
        return e.properties[0].length;
    const FbxElement* a = e.child("a");
    return a ? a->properties.size() : 0;
}

// --- the rules ---

/// The objects assimp is given: models, their materials and polygon meshes. Every other object
/// (animation, deformers and blend shapes, textures, videos, node attributes, lines, NURBS)
/// is renamed in assimp's copy, so that it reads none of them: Plimsoll reads shapes, and the
/// converters of those objects trust their files (an animation curve with no keys, a texture
/// link from a model, a rotation curve that asks for gigabytes of keys, a name that overflows
/// a fixed buffer: docs/security.md).
bool assimpReads(const FbxElement& object) {
    if (object.name == "Model" || object.name == "Material") return true;
    return object.name == "Geometry" && object.properties.size() >= 3 &&
           stringOf(object.properties[2]) == std::string_view("Mesh");
}

class FbxRules {
public:
    FbxRules(const std::string& file) : file_(file) {}

    /// Ok, or the first rule the tree breaks; `renamed` receives the byte offsets of the names
    /// that assimp's copy changes.
    Status check(const std::vector<FbxElement>& top, std::vector<std::uint64_t>& renamed) {
        const FbxElement* objects = nullptr;
        const FbxElement* connections = nullptr;
        for (const FbxElement& e : top) {
            if (e.name == "Objects" && !objects) objects = &e;
            if (e.name == "Connections" && !connections) connections = &e;
        }
        if (Status s = propertyNames(top); !s.ok()) return s;
        if (!objects) return Ok{};
        std::set<std::int64_t> models;
        for (const FbxElement& object : objects->children) {
            if (object.name.empty()) return refuse(object, "an object with no name");
            if (!assimpReads(object)) {
                if (object.name.back() != '_')
                    renamed.push_back(object.nameAt + object.name.size() - 1);
                continue;
            }
            if (object.name == "Geometry") {
                if (Status s = mesh(object); !s.ok()) return s;
            } else if (object.name == "Model" && !object.properties.empty()) {
                if (const std::optional<std::int64_t> id = integerOf(object.properties[0]))
                    models.insert(*id);
            }
        }
        return connections ? modelTree(*connections, models) : Ok{};
    }

private:
    Status refuse(const FbxElement& at, const std::string& why) const {
        return makeError(ErrorKind::format, file_ + ": the FBX element '" +
                                                std::string(at.name.substr(0, 64)) + "' at byte " +
                                                std::to_string(at.nameAt) + " has " + why);
    }

    /// Assimp keeps every property of a material (its own and its template's, a "P" element of
    /// any Properties70) under the key "$raw." + its name, in a fixed buffer of 1024 bytes that
    /// it asserts (abort) the name fits.
    Status propertyNames(const std::vector<FbxElement>& elements) const {
        for (const FbxElement& e : elements) {
            if (e.name == "P" && !e.properties.empty()) {
                const FbxProperty& name = e.properties[0];
                const std::size_t bytes = stringOf(name).value_or(name.data).size();
                if (bytes > kMaxFbxPropertyName)
                    return refuse(e, "a property name of " + std::to_string(bytes) +
                                         " bytes, more than the limit kMaxFbxPropertyName (" +
                                         std::to_string(kMaxFbxPropertyName) + ")");
            }
            if (Status s = propertyNames(e.children); !s.ok()) return s;
        }
        return Ok{};
    }

    /// A polygon mesh's layers: assimp reads a layer's index and a layer element's index without
    /// looking (a missing one is read from an empty list; a negative one writes before its array),
    /// and takes a per-polygon material list of any length (the converter then walks past the
    /// polygons).
    Status mesh(const FbxElement& geometry) const {
        for (const FbxElement& c : geometry.children) {
            if (c.name == "Layer") {
                if (c.properties.empty()) return refuse(c, "no index");
                for (const FbxElement& element : c.children) {
                    if (element.name != "LayerElement") continue;
                    const FbxElement* typed = element.child("TypedIndex");
                    if (typed && !typed->properties.empty() &&
                        integerOf(typed->properties[0]).value_or(0) < 0)
                        return refuse(*typed, "a negative index");
                }
            } else if (c.name.substr(0, 12) == "LayerElement" && !c.properties.empty()) {
                if (integerOf(c.properties[0]).value_or(0) < 0)
                    return refuse(c, "a negative index");
                if (c.name == "LayerElementMaterial")
                    if (Status s = materials(geometry, c); !s.ok()) return s;
            }
        }
        return Ok{};
    }

    Status materials(const FbxElement& geometry, const FbxElement& layer) const {
        const FbxElement* list = layer.child("Materials");
        if (!list || firstString(layer.child("MappingInformationType")) == "AllSame") return Ok{};
        // A polygon ends at a negative (bit-inverted) vertex index.
        const FbxElement* indices = geometry.child("PolygonVertexIndex");
        const std::optional<std::uint64_t> polygons =
            indices ? negativeCount(*indices) : std::optional<std::uint64_t>(0);
        if (!polygons) return refuse(geometry, "polygon vertex indices that cannot be read");
        const std::uint64_t listed = arrayLength(*list);
        if (listed != *polygons)
            return refuse(*list, std::to_string(listed) + " materials for " +
                                     std::to_string(*polygons) + " polygons");
        return Ok{};
    }

    /// Assimp converts a model's children recursively (every connection whose source and
    /// destination are models, of any type) without remembering where it has been: a model that
    /// is its own ancestor recurses forever, and a chain of kMaxFbxModelDepth models exhausts
    /// the stack as surely.
    Status modelTree(const FbxElement& connections, const std::set<std::int64_t>& models) const {
        std::map<std::int64_t, std::vector<std::int64_t>> children;
        for (const FbxElement& c : connections.children) {
            if (c.name != "C" || c.properties.size() < 3) continue;
            const std::optional<std::int64_t> child = integerOf(c.properties[1]);
            const std::optional<std::int64_t> parent = integerOf(c.properties[2]);
            if (child && parent && models.count(*child) && models.count(*parent))
                children[*parent].push_back(*child);
        }
        // Depth-first with an explicit stack: on the path, or done with the height of the
        // model's subtree (1: a leaf).
        std::set<std::int64_t> onPath;
        std::map<std::int64_t, std::uint64_t> height;
        for (const auto& [root, unused] : children) {
            if (height.count(root)) continue;
            std::vector<std::pair<std::int64_t, std::size_t>> path{{root, 0}};
            onPath.insert(root);
            while (!path.empty()) {
                const std::int64_t node = path.back().first;
                const auto found = children.find(node);
                const std::size_t next = path.back().second++;
                if (found != children.end() && next < found->second.size()) {
                    const std::int64_t child = found->second[next];
                    if (onPath.count(child))
                        return makeError(ErrorKind::format,
                                         file_ + ": the FBX model " + std::to_string(child) +
                                             " is its own ancestor (its parent links form a "
                                             "cycle)");
                    if (!height.count(child)) {
                        onPath.insert(child);
                        path.push_back({child, 0});
                    }
                    continue;
                }
                std::uint64_t h = 1;
                if (found != children.end())
                    for (const std::int64_t child : found->second)
                        h = std::max(h, height[child] + 1);
                if (h > kMaxFbxModelDepth)
                    return makeError(ErrorKind::limit,
                                     file_ + ": FBX models nested more than " +
                                         std::to_string(kMaxFbxModelDepth) + " deep (under model " +
                                         std::to_string(node) +
                                         "), more than the limit kMaxFbxModelDepth (limits.h)");
                height[node] = h;
                onPath.erase(node);
                path.pop_back();
            }
        }
        return Ok{};
    }

    const std::string& file_;
};

Status fbxSyntax(const std::string& file, const FbxSyntaxError& error) {
    if (error.tooDeep) return fbxTooDeep(file, error.at);
    return makeError(ErrorKind::format, file + ": not a well-formed FBX file: " + error.what +
                                            " (at byte " + std::to_string(error.at) + ")");
}

/// The element tree of either form, or where it cannot be read.
std::variant<std::vector<FbxElement>, FbxSyntaxError> fbxTree(std::string_view bytes, bool binary) {
    std::vector<FbxElement> top;
    if (binary) {
        if (auto error = BinaryTree(bytes).top(top)) return *error;
        return top;
    }
    auto tokens = asciiTokens(bytes);
    if (auto* error = std::get_if<FbxSyntaxError>(&tokens)) return *error;
    if (auto error = AsciiTree(std::get<std::vector<FbxToken>>(tokens)).scope(top, 0))
        return *error;
    return top;
}

}  // namespace

Status checkFbx(const std::string& file, std::string_view bytes, std::string* forAssimp) {
    // assimp reads a file as binary FBX when its first 18 bytes say so, whatever follows.
    const bool binary = bytes.substr(0, 18) == "Kaydara FBX Binary";
    if (binary && bytes.size() < 27) return Ok{};  // assimp refuses it
    // The binary form's records and arrays in one linear pass first; the tree below refuses
    // either form nested past kMaxFbxDepth before its recursion goes deeper.
    if (binary)
        if (Status scanned = checkBinaryFbx(file, bytes); !scanned.ok()) return scanned;
    auto tree = fbxTree(bytes, binary);
    if (auto* error = std::get_if<FbxSyntaxError>(&tree)) return fbxSyntax(file, *error);
    std::vector<std::uint64_t> renamed;
    if (Status s = FbxRules(file).check(std::get<std::vector<FbxElement>>(tree), renamed); !s.ok())
        return s;
    if (forAssimp && !renamed.empty()) {
        // The same bytes with each renamed object's name changed at its last letter: nothing
        // moves, and assimp's reader meets an object type it does not know and skips it.
        *forAssimp = std::string(bytes);
        for (const std::uint64_t at : renamed) (*forAssimp)[at] = '_';
    }
    return Ok{};
}

}  // namespace plimsoll::detail
