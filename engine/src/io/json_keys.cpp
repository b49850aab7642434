#include "plimsoll/io/json_keys.h"
#include "plimsoll/io/json_depth.h"

#include <nlohmann/json.hpp>

#include <set>
#include <vector>

namespace plimsoll {

namespace {

/// Walks the document as SAX events, keeping the keys of every open object and where it is.
class DuplicateKeys : public nlohmann::json_sax<nlohmann::json> {
public:
    bool null() override { return value(); }
    bool boolean(bool) override { return value(); }
    bool number_integer(number_integer_t) override { return value(); }
    bool number_unsigned(number_unsigned_t) override { return value(); }
    bool number_float(number_float_t, const string_t&) override { return value(); }
    bool string(string_t&) override { return value(); }
    bool binary(binary_t&) override { return value(); }
    bool start_object(std::size_t) override {
        frames_.push_back({true, {}, {}, 0});
        return true;
    }
    bool key(string_t& key) override {
        Frame& f = frames_.back();
        if (!f.keys.insert(key).second) {
            duplicate_ = key;
            where_ = path();
            return false;
        }
        f.key = key;
        return true;
    }
    bool end_object() override { return close(); }
    bool start_array(std::size_t) override {
        frames_.push_back({false, {}, {}, 0});
        return true;
    }
    bool end_array() override { return close(); }
    bool parse_error(std::size_t, const std::string&, const nlohmann::detail::exception&) override {
        return false;
    }

    const std::string& duplicate() const { return duplicate_; }
    const std::string& where() const { return where_; }

private:
    struct Frame {
        bool object;
        std::set<std::string> keys;
        std::string key;    ///< the member being read (objects)
        std::size_t index;  ///< the element being read (arrays)
    };
    bool value() {
        if (!frames_.empty() && !frames_.back().object) ++frames_.back().index;
        return true;
    }
    bool close() {
        frames_.pop_back();
        return value();
    }
    /// "bodies[0].material": the object holding the key being read.
    std::string path() const {
        std::string p;
        for (std::size_t i = 0; i + 1 < frames_.size(); ++i) {
            const Frame& f = frames_[i];
            if (f.object)
                p += (p.empty() ? "" : ".") + f.key;
            else
                p += "[" + std::to_string(f.index) + "]";
        }
        return p.empty() ? "the top level" : p;
    }

    std::vector<Frame> frames_;
    std::string duplicate_, where_;
};

}  // namespace

Status checkNoDuplicateKeys(const std::string& text, const std::string& source) {
    DuplicateKeys keys;
    nlohmann::json::sax_parse(text, &keys, nlohmann::json::input_format_t::json, false);
    if (keys.duplicate().empty()) return Ok{};
    return makeError(ErrorKind::format, source + ": " + boundedExcerpt(keys.where(), 200) +
                                            ": the key \"" + boundedExcerpt(keys.duplicate()) +
                                            "\" appears twice in one object (which one counts?)");
}

}  // namespace plimsoll
