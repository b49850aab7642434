// Reading hand-written JSON with a JSON path in every problem (json_reader.h).
#include "io/json_reader.h"
#include "plimsoll/io/json_depth.h"

#include "plimsoll/io/json_keys.h"

#include <cmath>

namespace plimsoll::detail {

namespace {

/// The bound `value` breaks, as words for "must be ...", or nullptr.
const char* brokenLimit(double value, Limit limit) {
    switch (limit) {
        case Limit::Any:
            return nullptr;
        case Limit::Positive:
            return value > 0 ? nullptr : "> 0";
        case Limit::NonNegative:
            return value >= 0 ? nullptr : ">= 0";
        case Limit::Fraction:
            return value >= 0 && value <= 1 ? nullptr : "in 0..1";
    }
    return nullptr;
}

}  // namespace

Result<Json> parseJson(const std::string& text, const std::string& source) {
    if (Status depth = checkJsonDepth(text, source); !depth.ok()) return depth.error();
    // nlohmann keeps the last of two equal keys silently: refused before parsing.
    if (Status keys = checkNoDuplicateKeys(text, source); !keys.ok()) return keys.error();
    try {
        return Json::parse(text);
    } catch (const Json::exception& e) {
        const std::string what = boundedExcerpt(e.what(), 200);
        const std::size_t tagEnd = what.find("] ");
        return makeError(
            ErrorKind::format,
            source + ": " + (tagEnd == std::string::npos ? what : what.substr(tagEnd + 2)));
    }
}

std::string member(const std::string& path, std::string_view key) {
    return path.empty() ? std::string(key) : path + "." + std::string(key);
}

std::string element(const std::string& path, std::size_t index) {
    return path + "[" + std::to_string(index) + "]";
}

const Json* find(const Json& object, const char* key) {
    const auto it = object.find(key);
    return it == object.end() ? nullptr : &*it;
}

void JsonReader::problem(const std::string& path, const std::string& message) {
    problems_.push_back(source_ + ": " + (path.empty() ? "" : path + ": ") + message);
}

Error JsonReader::problems() const {
    std::string message;
    for (const std::string& line : problems_) message += (message.empty() ? "" : "\n") + line;
    return makeError(ErrorKind::schema, std::move(message));
}

bool JsonReader::expectObject(const Json& value, const std::string& path,
                              std::initializer_list<std::string_view> keys) {
    if (!value.is_object()) {
        problem(path, "must be an object");
        return false;
    }
    for (const auto& item : value.items()) {
        bool known = false;
        for (std::string_view key : keys) known = known || item.key() == key;
        if (!known) problem(member(path, boundedExcerpt(item.key())), "unknown key");
    }
    return true;
}

bool JsonReader::numberValue(const Json& value, const std::string& path, double& out, Limit limit) {
    // JSON has no NaN or infinity, and the parser rejects numbers that overflow a double, so
    // every number here is finite.
    if (!value.is_number()) {
        problem(path, "must be a number");
        return false;
    }
    const double number = value.get<double>();
    if (const char* bound = brokenLimit(number, limit)) {
        problem(path, std::string("must be ") + bound);
        return false;
    }
    out = number;
    return true;
}

void JsonReader::number(const Json& object, const std::string& path, const char* key, double& out,
                        Limit limit, Presence presence) {
    if (const Json* value = find(object, key)) {
        numberValue(*value, member(path, key), out, limit);
    } else if (presence == Presence::Required) {
        problem(member(path, key), "required");
    }
}

bool JsonReader::integerValue(const Json& value, const std::string& path, int& out, int min,
                              int max) {
    // Through double: exact for every int, and anything beyond 2^53 is out of range anyway.
    if (!value.is_number() || value.get<double>() != std::floor(value.get<double>())) {
        problem(path, "must be an integer");
        return false;
    }
    const double number = value.get<double>();
    if (number < min || number > max) {
        const bool unbounded = max == std::numeric_limits<int>::max();
        problem(path, !unbounded ? "must be in " + std::to_string(min) + ".." + std::to_string(max)
                      : number < min ? "must be >= " + std::to_string(min)
                                     : std::string("too large"));
        return false;
    }
    out = static_cast<int>(number);
    return true;
}

void JsonReader::integer(const Json& object, const std::string& path, const char* key, int& out,
                         int min, int max) {
    if (const Json* value = find(object, key))
        integerValue(*value, member(path, key), out, min, max);
}

bool JsonReader::stringValue(const Json& value, const std::string& path, std::string& out) {
    if (!value.is_string()) {
        problem(path, "must be a string");
        return false;
    }
    out = value.get<std::string>();
    return true;
}

void JsonReader::string(const Json& object, const std::string& path, const char* key,
                        std::string& out) {
    if (const Json* value = find(object, key)) stringValue(*value, member(path, key), out);
}

void JsonReader::boolean(const Json& object, const std::string& path, const char* key, bool& out) {
    const Json* value = find(object, key);
    if (!value) return;
    if (!value->is_boolean()) {
        problem(member(path, key), "must be true or false");
        return;
    }
    out = value->get<bool>();
}

const Json* JsonReader::array(const Json& value, const std::string& path) {
    if (value.is_array()) return &value;
    problem(path, "must be an array");
    return nullptr;
}

}  // namespace plimsoll::detail
