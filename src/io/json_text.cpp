#include "io/json_text.h"

#include <vector>

namespace sculpt::io {

namespace {

using nlohmann::json;

// A SAX pass that only tracks where it is (the stack of objects and arrays, with the current key or index), so
// a parse error can name the field path of the value at fault. nlohmann's DOM parse reports no position for
// a number that overflows a double; its SAX parse_error does.
class PathTracker final : public nlohmann::json_sax<json> {
public:
    size_t errorByte = 0;
    std::string errorPath;

    bool null() override { return value(); }
    bool boolean(bool) override { return value(); }
    bool number_integer(number_integer_t) override { return value(); }
    bool number_unsigned(number_unsigned_t) override { return value(); }
    bool number_float(number_float_t, const string_t&) override { return value(); }
    bool string(string_t&) override { return value(); }
    bool binary(binary_t&) override { return value(); }
    bool start_object(std::size_t) override {
        frames_.push_back({false, 0, {}});
        return true;
    }
    bool key(string_t& name) override {
        frames_.back().key = name;
        return true;
    }
    bool end_object() override {
        frames_.pop_back();
        return value();
    }
    bool start_array(std::size_t) override {
        frames_.push_back({true, 0, {}});
        return true;
    }
    bool end_array() override {
        frames_.pop_back();
        return value();
    }
    bool parse_error(std::size_t position, const std::string&, const nlohmann::detail::exception&) override {
        errorByte = position;
        for (const Frame& f : frames_) {
            if (f.array)
                errorPath += "[" + std::to_string(f.index) + "]";
            else if (!f.key.empty())
                errorPath += (errorPath.empty() ? "" : ".") + f.key;
        }
        return false;
    }

private:
    struct Frame {
        bool array;
        int index;
        std::string key;
    };
    std::vector<Frame> frames_;
    // A value ended: the enclosing array moves on to its next element.
    bool value() {
        if (!frames_.empty() && frames_.back().array) ++frames_.back().index;
        return true;
    }
};

}  // namespace

int lineOfByte(const std::string& text, size_t byte) {
    int line = 1;
    for (size_t i = 0; i < byte && i < text.size(); ++i) line += text[i] == '\n';
    return line;
}

Status parseJsonText(const std::string& text, const std::string& displayName, nlohmann::json& out) {
    try {
        out = json::parse(text);
        return Status::success();
    } catch (const json::exception& e) {
        PathTracker tracker;
        try {
            json::sax_parse(text, &tracker);
        } catch (const json::exception&) {  // note: sax_parse reports through parse_error; this is belt and braces
        }
        // note: the position nlohmann reports is one past the offending token; the line is that of its end.
        const size_t byte = tracker.errorByte > 0 ? tracker.errorByte - 1 : 0;
        return Status::error(displayName + ":" + std::to_string(lineOfByte(text, byte)) + ": " +
                             (tracker.errorPath.empty() ? std::string() : tracker.errorPath + ": ") + "invalid JSON (" + e.what() + ")");
    }
}

}  // namespace sculpt::io
