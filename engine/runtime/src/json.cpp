#include "json.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cerrno>
#include <cstdint>
#include <cstdlib>
#include <string>
#include <unordered_set>

namespace plimsoll_runtime::json {

const Value* Value::find(const std::string& key) const {
    if (kind != Kind::Object) return nullptr;
    for (const auto& [k, v] : object) {
        if (k == key) return &v;
    }
    return nullptr;
}

const char* kindName(Value::Kind kind) {
    switch (kind) {
        case Value::Kind::Null:
            return "null";
        case Value::Kind::Bool:
            return "a boolean";
        case Value::Kind::Number:
            return "a number";
        case Value::Kind::String:
            return "a string";
        case Value::Kind::Array:
            return "an array";
        case Value::Kind::Object:
            return "an object";
    }
    return "?";
}

namespace {

/// std::from_chars for a double. Emscripten's libc++ (3.1.6) has none for floating point; there
/// strtod, which rounds correctly as from_chars does and runs in the "C" locale (the only one a
/// WebAssembly module has), gives the same value and the same range errors.
std::from_chars_result parseDouble(const char* first, const char* last, double& v) {
#if defined(__EMSCRIPTEN__)
    const std::string text(first, last);
    char* end = nullptr;
    errno = 0;
    const double parsed = std::strtod(text.c_str(), &end);
    const char* ptr = first + (end - text.c_str());
    if (end == text.c_str()) return {first, std::errc::invalid_argument};
    if (errno == ERANGE) return {ptr, std::errc::result_out_of_range};
    v = parsed;
    return {ptr, std::errc()};
#else
    return std::from_chars(first, last, v);
#endif
}

/// Nesting deeper than this is refused before the parser descends further, so a hostile file
/// cannot overflow the stack: the engine's kMaxJsonDepth (limits.h), restated (the runtime
/// builds alone).
constexpr int kMaxDepth = 128;
/// Objects with fewer members than this look for a repeated name by a scan (no allocation).
constexpr std::size_t kScanMembers = 16;

class Parser {
public:
    explicit Parser(const std::string& text) : s_(text) {}

    bool document(Value& out, std::string& error) {
        skipSpace();
        if (!value(out, 0)) {
            error = error_;
            return false;
        }
        skipSpace();
        if (pos_ != s_.size()) {
            fail("unexpected text after the JSON value");
            error = error_;
            return false;
        }
        return true;
    }

private:
    bool fail(const std::string& what) {
        std::size_t line = 1, column = 1;
        for (std::size_t i = 0; i < pos_ && i < s_.size(); ++i) {
            if (s_[i] == '\n') {
                ++line;
                column = 1;
            } else {
                ++column;
            }
        }
        error_ =
            "line " + std::to_string(line) + ", column " + std::to_string(column) + ": " + what;
        return false;
    }

    void skipSpace() {
        while (pos_ < s_.size() &&
               (s_[pos_] == ' ' || s_[pos_] == '\t' || s_[pos_] == '\n' || s_[pos_] == '\r'))
            ++pos_;
    }

    bool literal(const char* word) {
        std::size_t n = 0;
        while (word[n]) ++n;
        if (s_.compare(pos_, n, word) != 0) return fail("invalid literal");
        pos_ += n;
        return true;
    }

    bool value(Value& out, int depth) {
        if (pos_ >= s_.size()) return fail("unexpected end of input");
        const char c = s_[pos_];
        if ((c == '{' || c == '[') && depth >= kMaxDepth)
            return fail("nested more than " + std::to_string(kMaxDepth) +
                        " deep, more than the limit kMaxJsonDepth");
        switch (c) {
            case '{':
                return object(out, depth);
            case '[':
                return array(out, depth);
            case '"':
                out.kind = Value::Kind::String;
                return string(out.string);
            case 't':
                out.kind = Value::Kind::Bool;
                out.boolean = true;
                return literal("true");
            case 'f':
                out.kind = Value::Kind::Bool;
                out.boolean = false;
                return literal("false");
            case 'n':
                out.kind = Value::Kind::Null;
                return literal("null");
            default:
                if (c == '-' || (c >= '0' && c <= '9')) return number(out);
                return fail(std::string("unexpected character '") + c + "'");
        }
    }

    bool object(Value& out, int depth) {
        out.kind = Value::Kind::Object;
        ++pos_;
        skipSpace();
        if (pos_ < s_.size() && s_[pos_] == '}') {
            ++pos_;
            return true;
        }
        std::unordered_set<std::string> seen;
        for (;;) {
            skipSpace();
            if (pos_ >= s_.size() || s_[pos_] != '"') return fail("expected a member name");
            std::string key;
            if (!string(key)) return false;
            // A scan of the members so far for small objects; past a few, a set (a scan per
            // member made an object of a million members cost 5e11 comparisons).
            bool repeated = false;
            if (out.object.size() < kScanMembers) {
                repeated = std::any_of(out.object.begin(), out.object.end(),
                                       [&](const auto& m) { return m.first == key; });
                if (!repeated && out.object.size() + 1 == kScanMembers) {
                    for (const auto& m : out.object) seen.insert(m.first);
                    seen.insert(key);
                }
            } else {
                repeated = !seen.insert(key).second;
            }
            if (repeated) return fail("duplicate member \"" + key + "\"");
            skipSpace();
            if (pos_ >= s_.size() || s_[pos_] != ':') return fail("expected ':'");
            ++pos_;
            skipSpace();
            Value v;
            if (!value(v, depth + 1)) return false;
            out.object.emplace_back(std::move(key), std::move(v));
            skipSpace();
            if (pos_ < s_.size() && s_[pos_] == ',') {
                ++pos_;
                continue;
            }
            if (pos_ < s_.size() && s_[pos_] == '}') {
                ++pos_;
                return true;
            }
            return fail("expected ',' or '}'");
        }
    }

    bool array(Value& out, int depth) {
        out.kind = Value::Kind::Array;
        ++pos_;
        skipSpace();
        if (pos_ < s_.size() && s_[pos_] == ']') {
            ++pos_;
            return true;
        }
        for (;;) {
            skipSpace();
            Value v;
            if (!value(v, depth + 1)) return false;
            out.array.push_back(std::move(v));
            skipSpace();
            if (pos_ < s_.size() && s_[pos_] == ',') {
                ++pos_;
                continue;
            }
            if (pos_ < s_.size() && s_[pos_] == ']') {
                ++pos_;
                return true;
            }
            return fail("expected ',' or ']'");
        }
    }

    static void appendUtf8(std::string& out, std::uint32_t cp) {
        if (cp < 0x80) {
            out += static_cast<char>(cp);
        } else if (cp < 0x800) {
            out += static_cast<char>(0xC0 | (cp >> 6));
            out += static_cast<char>(0x80 | (cp & 0x3F));
        } else if (cp < 0x10000) {
            out += static_cast<char>(0xE0 | (cp >> 12));
            out += static_cast<char>(0x80 | ((cp >> 6) & 0x3F));
            out += static_cast<char>(0x80 | (cp & 0x3F));
        } else {
            out += static_cast<char>(0xF0 | (cp >> 18));
            out += static_cast<char>(0x80 | ((cp >> 12) & 0x3F));
            out += static_cast<char>(0x80 | ((cp >> 6) & 0x3F));
            out += static_cast<char>(0x80 | (cp & 0x3F));
        }
    }

    bool hex4(std::uint32_t& out) {
        if (pos_ + 4 > s_.size()) return fail("truncated \\u escape");
        out = 0;
        for (int i = 0; i < 4; ++i) {
            const char c = s_[pos_++];
            out <<= 4;
            if (c >= '0' && c <= '9')
                out |= static_cast<std::uint32_t>(c - '0');
            else if (c >= 'a' && c <= 'f')
                out |= static_cast<std::uint32_t>(c - 'a' + 10);
            else if (c >= 'A' && c <= 'F')
                out |= static_cast<std::uint32_t>(c - 'A' + 10);
            else
                return fail("invalid \\u escape");
        }
        return true;
    }

    // One well-formed UTF-8 sequence (RFC 3629: no overlong forms, no surrogates, at most
    // U+10FFFF) copied to out. JSON text is UTF-8, and what a reader accepts here is written
    // back by other JSON libraries that refuse anything else.
    bool utf8Sequence(std::string& out) {
        const auto byte = [&](std::size_t i) { return static_cast<unsigned char>(s_[i]); };
        const unsigned char lead = byte(pos_);
        std::size_t length = 0;
        unsigned char low = 0x80, high = 0xBF;  // allowed range of the second byte
        if (lead >= 0xC2 && lead <= 0xDF) {
            length = 2;
        } else if (lead >= 0xE0 && lead <= 0xEF) {
            length = 3;
            if (lead == 0xE0) low = 0xA0;
            if (lead == 0xED) high = 0x9F;
        } else if (lead >= 0xF0 && lead <= 0xF4) {
            length = 4;
            if (lead == 0xF0) low = 0x90;
            if (lead == 0xF4) high = 0x8F;
        } else {
            return false;
        }
        if (pos_ + length > s_.size()) return false;
        if (byte(pos_ + 1) < low || byte(pos_ + 1) > high) return false;
        for (std::size_t i = 2; i < length; ++i)
            if (byte(pos_ + i) < 0x80 || byte(pos_ + i) > 0xBF) return false;
        out.append(s_, pos_, length);
        pos_ += length;
        return true;
    }

    bool string(std::string& out) {
        ++pos_;  // opening quote
        out.clear();
        while (pos_ < s_.size()) {
            const char c = s_[pos_++];
            if (c == '"') return true;
            if (static_cast<unsigned char>(c) < 0x20) return fail("control character in a string");
            if (static_cast<unsigned char>(c) >= 0x80) {
                --pos_;
                if (!utf8Sequence(out)) return fail("invalid UTF-8 in a string");
                continue;
            }
            if (c != '\\') {
                out += c;
                continue;
            }
            if (pos_ >= s_.size()) break;
            const char e = s_[pos_++];
            switch (e) {
                case '"':
                    out += '"';
                    break;
                case '\\':
                    out += '\\';
                    break;
                case '/':
                    out += '/';
                    break;
                case 'b':
                    out += '\b';
                    break;
                case 'f':
                    out += '\f';
                    break;
                case 'n':
                    out += '\n';
                    break;
                case 'r':
                    out += '\r';
                    break;
                case 't':
                    out += '\t';
                    break;
                case 'u': {
                    std::uint32_t cp = 0;
                    if (!hex4(cp)) return false;
                    if (cp >= 0xD800 && cp < 0xDC00) {
                        std::uint32_t low = 0;
                        if (s_.compare(pos_, 2, "\\u") != 0) return fail("unpaired surrogate");
                        pos_ += 2;
                        if (!hex4(low)) return false;
                        if (low < 0xDC00 || low > 0xDFFF) return fail("unpaired surrogate");
                        cp = 0x10000 + ((cp - 0xD800) << 10) + (low - 0xDC00);
                    } else if (cp >= 0xDC00 && cp < 0xE000) {
                        return fail("unpaired surrogate");
                    }
                    appendUtf8(out, cp);
                    break;
                }
                default:
                    return fail(std::string("invalid escape '\\") + e + "'");
            }
        }
        return fail("unterminated string");
    }

    bool number(Value& out) {
        // Grammar check first (from_chars alone accepts forms JSON does not, e.g. "01").
        const std::size_t start = pos_;
        if (s_[pos_] == '-') ++pos_;
        if (pos_ >= s_.size()) return fail("invalid number");
        if (s_[pos_] == '0') {
            ++pos_;
        } else if (s_[pos_] >= '1' && s_[pos_] <= '9') {
            while (pos_ < s_.size() && s_[pos_] >= '0' && s_[pos_] <= '9') ++pos_;
        } else {
            return fail("invalid number");
        }
        if (pos_ < s_.size() && s_[pos_] == '.') {
            ++pos_;
            if (pos_ >= s_.size() || !(s_[pos_] >= '0' && s_[pos_] <= '9'))
                return fail("invalid number");
            while (pos_ < s_.size() && s_[pos_] >= '0' && s_[pos_] <= '9') ++pos_;
        }
        if (pos_ < s_.size() && (s_[pos_] == 'e' || s_[pos_] == 'E')) {
            ++pos_;
            if (pos_ < s_.size() && (s_[pos_] == '+' || s_[pos_] == '-')) ++pos_;
            if (pos_ >= s_.size() || !(s_[pos_] >= '0' && s_[pos_] <= '9'))
                return fail("invalid number");
            while (pos_ < s_.size() && s_[pos_] >= '0' && s_[pos_] <= '9') ++pos_;
        }
        const char* first = s_.data() + start;
        const char* last = s_.data() + pos_;
        double v = 0;
        const auto [ptr, ec] = parseDouble(first, last, v);
        if (ptr != last || (ec != std::errc() && ec != std::errc::result_out_of_range)) {
            pos_ = start;
            return fail("invalid number");
        }
        if (ec == std::errc::result_out_of_range) {
            // Underflow reads as zero; overflow is refused.
            const std::string text(first, last);
            if (text.find("e-") == std::string::npos && text.find("E-") == std::string::npos) {
                pos_ = start;
                return fail("number out of range");
            }
            v = 0;
        }
        if (!std::isfinite(v)) {
            pos_ = start;
            return fail("number out of range");
        }
        out.kind = Value::Kind::Number;
        out.number = v;
        return true;
    }

    const std::string& s_;
    std::size_t pos_ = 0;
    std::string error_;
};

}  // namespace

bool parse(const std::string& text, Value& out, std::string& error) {
    out = Value{};
    return Parser(text).document(out, error);
}

}  // namespace plimsoll_runtime::json
