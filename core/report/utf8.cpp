#include "core/report/utf8.h"

namespace mbx {

std::size_t utf8_sequence_length(std::string_view s, std::size_t i, std::size_t* bad) {
    const auto b0 = static_cast<unsigned char>(s[i]);
    if (b0 < 0x80) return 1;

    // The second byte's range is narrower for a few lead bytes: that is what
    // rules out overlong forms, UTF-16 surrogates and code points > U+10FFFF.
    std::size_t trail = 0;
    unsigned char lo = 0x80, hi = 0xBF;
    if (b0 >= 0xC2 && b0 <= 0xDF) {
        trail = 1;
    } else if (b0 >= 0xE0 && b0 <= 0xEF) {
        trail = 2;
        if (b0 == 0xE0) lo = 0xA0;
        if (b0 == 0xED) hi = 0x9F;
    } else if (b0 >= 0xF0 && b0 <= 0xF4) {
        trail = 3;
        if (b0 == 0xF0) lo = 0x90;
        if (b0 == 0xF4) hi = 0x8F;
    } else {
        *bad = 1;
        return 0;
    }

    std::size_t k = 1;
    for (; k <= trail && i + k < s.size(); ++k) {
        const auto c = static_cast<unsigned char>(s[i + k]);
        if (c < lo || c > hi) break;
        lo = 0x80;
        hi = 0xBF;
    }
    if (k == trail + 1) return k;
    *bad = k;
    return 0;
}

void append_printable_utf8(std::string& out, std::string_view s) {
    std::size_t i = 0;
    while (i < s.size()) {
        const auto c = static_cast<unsigned char>(s[i]);
        if (c < 0x80) {
            out.push_back(c < 0x20 || c == 0x7F ? ' ' : static_cast<char>(c));
            ++i;
            continue;
        }
        i += append_utf8_or_replacement(out, s, i);
    }
}

void clip_utf8(std::string& line, std::size_t max_bytes) {
    if (line.size() <= max_bytes) return;
    static constexpr std::string_view kEllipsis = "...";
    std::size_t cut = max_bytes > kEllipsis.size() ? max_bytes - kEllipsis.size() : 0;
    // Step back over continuation bytes so the cut lands on a code point start.
    while (cut > 0 && (static_cast<unsigned char>(line[cut]) & 0xC0) == 0x80) --cut;
    line.resize(cut);
    line.append(kEllipsis.substr(0, max_bytes - cut));
}

}  // namespace mbx
