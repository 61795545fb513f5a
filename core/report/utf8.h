// UTF-8 hygiene shared by the JSON and text writers. Host strings come from
// CAD systems that sometimes hand over Latin-1 or truncated buffers; a report
// must still be valid UTF-8, so ill-formed input is replaced, never copied.
#pragma once
#include <cstddef>
#include <string>
#include <string_view>

namespace mbx {

// Length (1..4) of the well-formed UTF-8 sequence that starts at s[i], or 0
// if it is ill-formed; then *bad is the length of its maximal ill-formed
// subpart (>= 1), which gets one U+FFFD as Unicode's "best practice" advises.
std::size_t utf8_sequence_length(std::string_view s, std::size_t i, std::size_t* bad);

// Appends the three bytes of U+FFFD.
inline void append_replacement_character(std::string& out) { out.append("\xEF\xBF\xBD", 3); }

// Appends the sequence at s[i] if it is well-formed, else one U+FFFD for its
// ill-formed subpart; returns how many bytes of `s` were consumed (>= 1).
inline std::size_t append_utf8_or_replacement(std::string& out, std::string_view s, std::size_t i) {
    std::size_t bad = 0;
    const std::size_t n = utf8_sequence_length(s, i, &bad);
    if (n) {
        out.append(s.data() + i, n);
        return n;
    }
    append_replacement_character(out);
    return bad;
}

// Appends `s` as valid UTF-8 with control characters turned into spaces, so
// a name can neither break a line of a plain-text report nor its encoding.
void append_printable_utf8(std::string& out, std::string_view s);

// Shortens `line` to at most `max_bytes` bytes (an ellipsis included) without
// splitting a code point. `line` must already be valid UTF-8.
void clip_utf8(std::string& line, std::size_t max_bytes);

}  // namespace mbx
