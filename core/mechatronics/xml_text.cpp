#include "core/mechatronics/xml_text.h"

#include <cctype>
#include <charconv>
#include <cmath>
#include <fstream>
#include <sstream>

#include "core/input_file.h"

namespace mbx {

bool parse_xml_number(const std::string& text, double& out) {
    const char* b = text.data();
    const char* e = b + text.size();
    while (b < e && std::isspace(static_cast<unsigned char>(*b))) ++b;
    while (e > b && std::isspace(static_cast<unsigned char>(e[-1]))) --e;
    if (b < e && *b == '+') ++b;
    const auto r = std::from_chars(b, e, out);
    return r.ec == std::errc() && r.ptr == e && std::isfinite(out);
}

bool parse_xml_numbers(const std::string& text, size_t count, double* out) {
    size_t at = 0, found = 0;
    while (true) {
        while (at < text.size() && std::isspace(static_cast<unsigned char>(text[at]))) ++at;
        if (at == text.size()) break;
        size_t end = at;
        while (end < text.size() && !std::isspace(static_cast<unsigned char>(text[end]))) ++end;
        if (found == count || !parse_xml_number(text.substr(at, end - at), out[found])) return false;
        ++found, at = end;
    }
    return found == count;
}

XmlLines::XmlLines(const std::string& text) {
    for (size_t i = 0; i < text.size(); ++i)
        if (text[i] == '\n') newlines_.push_back(i);
}

int XmlLines::line_at(ptrdiff_t offset) const {
    if (offset < 0) return 0;
    size_t lo = 0, hi = newlines_.size();
    while (lo < hi) {
        const size_t mid = (lo + hi) / 2;
        if (newlines_[mid] < size_t(offset)) lo = mid + 1;
        else hi = mid;
    }
    return int(lo) + 1;
}

int XmlLines::line(const pugi::xml_node& n) const { return line_at(n.offset_debug()); }

bool read_text_file(const std::string& path, std::string& out, std::string* why) {
    std::string reason;
    const bool ok = read_input_file(path, out, reason);
    if (why) *why = reason;
    return ok;
}

}  // namespace mbx
