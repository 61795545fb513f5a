#include "numbers.h"

#include <charconv>
#include <cmath>

namespace mbx_files {

std::string_view trim(std::string_view text) {
    const char* ws = " \t\r\n\f\v";
    const size_t first = text.find_first_not_of(ws);
    if (first == std::string_view::npos) return {};
    const size_t last = text.find_last_not_of(ws);
    return text.substr(first, last - first + 1);
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
