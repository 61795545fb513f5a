// A small JSON reader for the files mbx writes and reads back (the URDF
// export's cut joints, calibration.json for mbx excite): objects, arrays, strings, numbers, true, false,
// null, each value with the line it starts on. Hostile input is refused with
// a JsonError naming the line (depth capped at 64, numbers finite, strings
// valid escapes), never a crash.
#pragma once
#include <map>
#include <memory>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

namespace mbx {

class JsonError : public std::runtime_error {
public:
    JsonError(int line, const std::string& message) : std::runtime_error(message), line_(line) {}
    int line() const { return line_; }

private:
    int line_;
};

struct JsonValue {
    enum class Kind { null, boolean, number, string, array, object } kind = Kind::null;
    int line = 0;
    bool boolean = false;
    double number = 0;
    std::string string;
    std::vector<JsonValue> array;
    std::vector<std::pair<std::string, JsonValue>> object;  // in file order

    // The member `key` of an object; null when absent or not an object.
    const JsonValue* find(std::string_view key) const;
    bool is_null() const { return kind == Kind::null; }
};

// Throws JsonError for text that is not one JSON value.
JsonValue parse_json(std::string_view text);

}  // namespace mbx
