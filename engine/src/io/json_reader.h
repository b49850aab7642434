// Reading JSON documents that people write by hand (project files, water graphs): a reader
// records every problem with its JSON path ("SOURCE: bodies[1].material.density: must be > 0")
// and goes on, leaving the default in place, so that one pass reports all of them; typos in
// keys are problems too. Project and graph readers derive from it and add their own members.
#pragma once

#include "plimsoll/core/result.h"

#include <Eigen/Core>
#include <nlohmann/json.hpp>

#include <initializer_list>
#include <limits>
#include <string>
#include <string_view>
#include <vector>

namespace plimsoll::detail {

// Ordered: saved files keep the schema's key order, and problems come in document order.
using Json = nlohmann::ordered_json;

/// The document, or "SOURCE: " and nlohmann's message without its
/// "[json.exception.parse_error.101] " tag (the position and the cause are what a user needs).
Result<Json> parseJson(const std::string& text, const std::string& source);

/// "path.key" ("key" at the top level) and "path[index]".
std::string member(const std::string& path, std::string_view key);
std::string element(const std::string& path, std::size_t index);

/// The member `key` of `object` (an object), or null.
const Json* find(const Json& object, const char* key);

enum class Limit { Any, Positive, NonNegative, Fraction };
enum class Presence { Optional, Required };

class JsonReader {
public:
    explicit JsonReader(std::string source) : source_(std::move(source)) {}

    /// Records "SOURCE: PATH: MESSAGE" ("SOURCE: MESSAGE" for the document itself).
    void problem(const std::string& path, const std::string& message);
    bool hasProblems() const { return !problems_.empty(); }
    /// Every problem, one a line (kind schema).
    Error problems() const;
    const std::string& source() const { return source_; }

    /// Whether `value` is an object; every key not in `keys` is a problem (this catches typos,
    /// which would otherwise silently leave the default in place).
    bool expectObject(const Json& value, const std::string& path,
                      std::initializer_list<std::string_view> keys);

    // Each reader of a value at `path` returns whether it read one; each reader of a member
    // `key` of `object` leaves `out` alone when the member is absent (a problem if Required).
    bool numberValue(const Json& value, const std::string& path, double& out, Limit limit);
    void number(const Json& object, const std::string& path, const char* key, double& out,
                Limit limit = Limit::Any, Presence presence = Presence::Optional);
    /// An integer (256.0 is one too, as in JSON Schema) in min..max.
    bool integerValue(const Json& value, const std::string& path, int& out, int min,
                      int max = std::numeric_limits<int>::max());
    void integer(const Json& object, const std::string& path, const char* key, int& out, int min,
                 int max = std::numeric_limits<int>::max());
    bool stringValue(const Json& value, const std::string& path, std::string& out);
    void string(const Json& object, const std::string& path, const char* key, std::string& out);
    void boolean(const Json& object, const std::string& path, const char* key, bool& out);
    /// An array of N numbers; whether it was given and read without a problem.
    template <int N>
    bool vector(const Json& object, const std::string& path, const char* key,
                Eigen::Matrix<double, N, 1>& out, Presence presence = Presence::Optional) {
        const Json* value = find(object, key);
        const std::string at = member(path, key);
        if (!value) {
            if (presence == Presence::Required) problem(at, "required");
            return false;
        }
        if (!value->is_array() || value->size() != N) {
            problem(at, "must be an array of " + std::to_string(N) + " numbers");
            return false;
        }
        bool valid = true;
        for (int i = 0; i < N; ++i) {
            valid = numberValue((*value)[i], element(at, i), out[i], Limit::Any) && valid;
        }
        return valid;
    }
    /// `value` if it is an array, else null (problem recorded).
    const Json* array(const Json& value, const std::string& path);

private:
    std::string source_;
    std::vector<std::string> problems_;
};

}  // namespace plimsoll::detail
