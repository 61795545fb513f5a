#include "vrml_lexer.h"

#include <array>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>

#include "vrml_message.h"
#include "host_adapters/common/vrml_scene.h"

namespace mbx_files::vrml {
namespace {

enum : uint8_t { blank = 1, id_first = 2, id_rest = 4, digit = 8, stop = 16 };

// Character classes of clause 5.1: commas are whitespace, and identifiers
// may hold any byte that is not a delimiter (so UTF-8 names pass).
constexpr std::array<uint8_t, 256> make_classes() {
    std::array<uint8_t, 256> c{};
    for (int b = 0x21; b < 256; ++b) c[b] = id_first | id_rest;
    for (int b = '0'; b <= '9'; ++b) c[b] = id_rest | digit;
    c['+'] = id_rest;
    c['-'] = id_rest;
    for (char d : {'"', '#', '\'', ',', '.', '[', '\\', ']', '{', '}'}) c[static_cast<unsigned char>(d)] = 0;
    c[0x7f] = 0;
    for (char w : {' ', '\t', '\n', '\r', ',', '\f', '\v'}) c[static_cast<unsigned char>(w)] = blank;
    // What may follow a number: anything else glued to it makes it malformed.
    for (char d : {' ', '\t', '\n', '\r', ',', '\f', '\v', '[', ']', '{', '}', '#', '"'})
        c[static_cast<unsigned char>(d)] |= stop;
    return c;
}
constexpr std::array<uint8_t, 256> classes = make_classes();

inline uint8_t cls(char c) { return classes[static_cast<unsigned char>(c)]; }
inline bool is_digit(char c) { return c >= '0' && c <= '9'; }

}  // namespace

Lexer::Lexer(std::string_view text, const std::string& file)
    : p_(text.data()), end_(text.data() + text.size()), file_(file) {
    scan();
}

void Lexer::fail(int line, const std::string& message) const { throw VrmlError(file_, line, message); }

std::string Lexer::take_string() {
    std::string s = std::move(token_.str);
    scan();
    return s;
}

void Lexer::skip_blank() {
    while (p_ < end_) {
        const char c = *p_;
        if (c == '\n') {
            ++line_;
            ++p_;
        } else if (cls(c) & blank) {
            ++p_;
        } else if (c == '#') {
            const void* nl = std::memchr(p_, '\n', static_cast<size_t>(end_ - p_));
            p_ = nl ? static_cast<const char*>(nl) : end_;
        } else {
            return;
        }
    }
}

void Lexer::scan() {
    skip_blank();
    token_.line = line_;
    token_.text = {};
    if (p_ == end_) {
        token_.kind = Tok::eof;
        return;
    }
    const char c = *p_;
    switch (c) {
        case '[':
            token_.kind = Tok::lbracket;
            ++p_;
            return;
        case ']':
            token_.kind = Tok::rbracket;
            ++p_;
            return;
        case '{':
            token_.kind = Tok::lbrace;
            ++p_;
            return;
        case '}':
            token_.kind = Tok::rbrace;
            ++p_;
            return;
        case '"': scan_string(); return;
        case '.':
            if (p_ + 1 < end_ && is_digit(p_[1])) {
                scan_number();
            } else {
                token_.kind = Tok::period;
                ++p_;
            }
            return;
        default: break;
    }
    if (is_digit(c) || c == '+' || c == '-') {
        scan_number();
    } else if (cls(c) & id_first) {
        scan_identifier();
    } else {
        const auto b = static_cast<unsigned char>(c);
        if (b < 0x20 || b == 0x7f) {
            static const char* hex = "0123456789abcdef";
            fail(line_, std::string("unexpected byte 0x") + hex[b >> 4] + hex[b & 15] + " (binary data?)");
        }
        fail(line_, std::string("unexpected character '") + c + "'");
    }
}

void Lexer::scan_identifier() {
    const char* s = p_;
    while (p_ < end_ && (cls(*p_) & id_rest)) ++p_;
    token_.kind = Tok::identifier;
    token_.text = std::string_view(s, static_cast<size_t>(p_ - s));
}

void Lexer::scan_number() {
    const char* s = p_;
    const char* q = p_;
    auto malformed = [&]() {
        const char* e = q;
        while (e < end_ && !(cls(*e) & stop)) ++e;
        fail(line_, "malformed number " + quoted_excerpt(std::string_view(s, static_cast<size_t>(e - s))));
    };
    const bool negative = *q == '-';
    if (*q == '+' || *q == '-') ++q;
    double value = 0;
    if (end_ - q > 2 && q[0] == '0' && (q[1] == 'x' || q[1] == 'X')) {
        // Hex integers: SFInt32 (colours of PixelTexture images).
        q += 2;
        const char* h = q;
        while (q < end_ && std::isxdigit(static_cast<unsigned char>(*q))) ++q;
        uint64_t v = 0;
        if (q == h || q - h > 16) malformed();
        std::from_chars(h, q, v, 16);
        value = negative ? -static_cast<double>(v) : static_cast<double>(v);
    } else {
        const char* m = q;
        while (q < end_ && is_digit(*q)) ++q;
        size_t mantissa_digits = static_cast<size_t>(q - m);
        if (q < end_ && *q == '.') {
            ++q;
            const char* f = q;
            while (q < end_ && is_digit(*q)) ++q;
            mantissa_digits += static_cast<size_t>(q - f);
        }
        if (mantissa_digits == 0) malformed();
        if (q < end_ && (*q == 'e' || *q == 'E')) {
            ++q;
            if (q < end_ && (*q == '+' || *q == '-')) ++q;
            const char* e = q;
            while (q < end_ && is_digit(*q)) ++q;
            if (q == e) malformed();
        }
        const char* from = *s == '+' ? s + 1 : s;
        auto [ptr, ec] = std::from_chars(from, q, value);
        if (ec == std::errc::result_out_of_range) {
            // from_chars reports underflow like overflow; strtod tells them
            // apart (a denormal or zero is a fine coordinate, infinity is not).
            const std::string copy(from, q);
            value = std::strtod(copy.c_str(), nullptr);
            ptr = q;
        } else if (ec != std::errc()) {
            malformed();
        }
        if (ptr != q) malformed();
        if (!std::isfinite(value)) {
            fail(line_, "number out of range " + quoted_excerpt(std::string_view(s, static_cast<size_t>(q - s))));
        }
    }
    if (q < end_ && !(cls(*q) & stop)) malformed();
    token_.kind = Tok::number;
    token_.number = value;
    token_.text = std::string_view(s, static_cast<size_t>(q - s));
    p_ = q;
}

void Lexer::scan_string() {
    const int start_line = line_;
    token_.kind = Tok::string;
    token_.str.clear();
    ++p_;
    for (;;) {
        const char* q = p_;
        while (q < end_ && *q != '"' && *q != '\\') {
            if (*q == '\n') ++line_;
            ++q;
        }
        token_.str.append(p_, q);
        if (q == end_) fail(start_line, "unterminated string (end of file reached)");
        if (*q == '"') {
            p_ = q + 1;
            return;
        }
        // VRML97 defines \" and \\; any other escaped byte stands for itself.
        if (q + 1 == end_) fail(start_line, "unterminated string (end of file reached)");
        if (q[1] == '\n') ++line_;
        token_.str += q[1];
        p_ = q + 2;
    }
}

}  // namespace mbx_files::vrml
