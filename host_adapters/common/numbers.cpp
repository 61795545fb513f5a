#include "numbers.h"

#include <charconv>
#include <cmath>

namespace mbx_files {

namespace {
bool is_space(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\n' || c == '\f' || c == '\v'; }
}  // namespace

// By hand: find_first_not_of(" \t\r\n\f\v") searches the set once per
// character, and trim runs on every value of a file.
std::string_view trim(std::string_view text) {
    size_t first = 0, end = text.size();
    while (first < end && is_space(text[first])) ++first;
    while (end > first && is_space(text[end - 1])) --end;
    return text.substr(first, end - first);
}

std::optional<double> parse_number(std::string_view text) {
    text = trim(text);
    // from_chars takes no leading '+', which some exporters write.
    if (!text.empty() && text[0] == '+') {
        text.remove_prefix(1);
        if (!text.empty() && (text[0] == '-' || text[0] == '+')) return std::nullopt;
    }
    if (text.empty()) return std::nullopt;
    double value = 0;
    const char* end = text.data() + text.size();
    const auto [ptr, ec] = std::from_chars(text.data(), end, value, std::chars_format::general);
    if (ec != std::errc() || ptr != end || !std::isfinite(value)) return std::nullopt;
    return value;
}

bool parse_number_list(std::string_view text, double* out, size_t count) {
    size_t n = 0;
    while (true) {
        const size_t comma = text.find(',');
        const std::string_view item = text.substr(0, comma);
        if (n == count) return false;
        const std::optional<double> v = parse_number(item);
        if (!v) return false;
        out[n++] = *v;
        if (comma == std::string_view::npos) break;
        text.remove_prefix(comma + 1);
    }
    return n == count;
}

}  // namespace mbx_files
