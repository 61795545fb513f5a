#include "vrml_message.h"

#include <cmath>
#include <cstdio>

#include "vrml_lexer.h"

namespace mbx_files::vrml {

std::string join(std::initializer_list<Piece> pieces) {
    std::string out;
    for (const Piece& p : pieces) {
        switch (p.kind) {
            case Piece::Kind::text: out += p.text; break;
            case Piece::Kind::integer: out += std::to_string(p.integer); break;
            case Piece::Kind::real: out += format_number(p.real); break;
            case Piece::Kind::token: out += describe_token(*p.token); break;
            case Piece::Kind::quoted: out += quoted_excerpt(p.text); break;
        }
    }
    return out;
}

std::string quoted_excerpt(std::string_view text) {
    constexpr size_t max_chars = 32;
    static const char* hex = "0123456789abcdef";
    std::string out = "'";
    for (size_t i = 0; i < text.size() && i < max_chars; ++i) {
        const auto b = static_cast<unsigned char>(text[i]);
        if (b < 0x20 || b == 0x7f) {
            out += "\\x";
            out += hex[b >> 4];
            out += hex[b & 15];
        } else {
            out += static_cast<char>(b);
        }
    }
    if (text.size() > max_chars) out += "...";
    return out + "'";
}

std::string describe_token(const Token& t) {
    switch (t.kind) {
        case Tok::eof: return "end of file";
        case Tok::identifier: return quoted_excerpt(t.text);
        case Tok::number: return "number " + quoted_excerpt(t.text);
        case Tok::string: return "a string";
        case Tok::lbracket: return "'['";
        case Tok::rbracket: return "']'";
        case Tok::lbrace: return "'{'";
        case Tok::rbrace: return "'}'";
        case Tok::period: return "'.'";
    }
    return "?";
}

std::string format_number(double d) {
    if (d == std::floor(d) && std::fabs(d) < 1e15) return std::to_string(static_cast<long long>(d));
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.17g", d);
    return buf;
}

}  // namespace mbx_files::vrml
