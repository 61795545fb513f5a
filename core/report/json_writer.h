// A streaming JSON writer: values go straight into one growing string, in the
// order they are written, so output is deterministic and linear in size. It
// knows nothing of mbx types and is meant to be reused by exporters.
//
//   JsonWriter w;
//   w.begin_object();
//   w.member("name", "crank").key("com").number_array(com, 3);
//   w.end_object();
//
// Output is pretty-printed with 2-space indentation. A container opened with
// Layout::Inline (and everything inside it) stays on one line, which keeps
// vectors and matrices readable. Strings are escaped and made valid UTF-8;
// non-finite numbers become null since JSON cannot spell them. Misuse (a
// value without a key in an object, unbalanced ends, two top-level values)
// throws std::logic_error: it is a bug in the caller, never a data problem.
#pragma once
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <type_traits>
#include <vector>

namespace mbx {

class JsonWriter {
public:
    enum class Layout { Pretty, Inline };

    JsonWriter() = default;
    explicit JsonWriter(std::size_t reserve_bytes) { out_.reserve(reserve_bytes); }

    JsonWriter& begin_object(Layout layout = Layout::Pretty);
    JsonWriter& end_object();
    JsonWriter& begin_array(Layout layout = Layout::Pretty);
    JsonWriter& end_array();

    // Inside an object: the next value's name.
    JsonWriter& key(std::string_view name);

    JsonWriter& value(std::string_view s);
    JsonWriter& value(const std::string& s) { return value(std::string_view(s)); }
    JsonWriter& value(const char* s);  // nullptr writes null
    JsonWriter& value(bool b);
    JsonWriter& value(double d);       // shortest round-trip form; NaN/Inf -> null
    JsonWriter& value(long long i);
    JsonWriter& value(unsigned long long u);
    // Any other integer type, without the ambiguity of int -> long long/double.
    template <class T, std::enable_if_t<std::is_integral_v<T> && !std::is_same_v<T, bool>, int> = 0>
    JsonWriter& value(T v) {
        if constexpr (std::is_signed_v<T>)
            return value(static_cast<long long>(v));
        else
            return value(static_cast<unsigned long long>(v));
    }
    JsonWriter& null();

    template <class T>
    JsonWriter& member(std::string_view name, const T& v) {
        key(name);
        return value(v);
    }
    // An inline array of `n` doubles: the common case for vectors/matrices.
    JsonWriter& number_array(const double* v, std::size_t n);

    // True once exactly one complete top-level value has been written.
    bool complete() const { return done_ && stack_.empty(); }
    const std::string& str() const { return out_; }
    // Moves the text out; the writer is then empty and may be reused.
    std::string take();

private:
    struct Level {
        bool object;
        bool inline_layout;
        bool empty;
    };

    void before_value();
    void after_value();
    void separate(Level& level);
    void newline(std::size_t depth);
    JsonWriter& open(bool object, Layout layout, char bracket);
    JsonWriter& close(bool object, char bracket);

    std::string out_;
    std::vector<Level> stack_;
    bool after_key_ = false;
    bool done_ = false;
};

// Appends `s` as a quoted JSON string. Exposed for writers that build JSON
// fragments by hand.
void append_json_string(std::string& out, std::string_view s);
// Appends the shortest text that parses back to exactly `d` ("null" if d is
// not finite). Independent of the C and C++ locales.
void append_json_number(std::string& out, double d);

}  // namespace mbx
