// A small strict JSON reader (RFC 8259) for manifest.json and graph.json: no extensions, no
// comments, no trailing commas; errors say line and column. Numbers parse with from_chars, so
// the reading does not depend on the C locale.
#pragma once

#include <cstddef>
#include <string>
#include <utility>
#include <vector>

namespace plimsoll_runtime::json {

struct Value {
    enum class Kind { Null, Bool, Number, String, Array, Object };
    Kind kind = Kind::Null;
    bool boolean = false;
    double number = 0;
    std::string string;
    std::vector<Value> array;
    std::vector<std::pair<std::string, Value>> object;

    bool isNull() const { return kind == Kind::Null; }
    bool isNumber() const { return kind == Kind::Number; }
    bool isString() const { return kind == Kind::String; }
    bool isObject() const { return kind == Kind::Object; }
    bool isArray() const { return kind == Kind::Array; }
    bool isBool() const { return kind == Kind::Bool; }
    /// The member called `key`, or null when absent (or not an object).
    const Value* find(const std::string& key) const;
};

/// Parses `text`; on error returns false and sets `error` ("line 3, column 7: expected ':'").
bool parse(const std::string& text, Value& out, std::string& error);

const char* kindName(Value::Kind kind);

}  // namespace plimsoll_runtime::json
