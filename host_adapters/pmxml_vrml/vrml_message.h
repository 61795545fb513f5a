// Error and warning texts assembled out of line. The parser and the scene
// builder recurse once per nesting level; building a message inline would
// give every temporary string a slot in those recursive frames (sanitizer
// builds keep them all apart), multiplying the stack each level costs.
#pragma once
#include <cstddef>
#include <initializer_list>
#include <string>
#include <string_view>

namespace mbx_files::vrml {

struct Token;

// One piece of a message: text, an integer, a number as VRML would write
// it, a token as the parser saw it, or text quoted and shortened.
struct Piece {
    enum class Kind { text, integer, real, token, quoted } kind;
    std::string_view text;
    long long integer = 0;
    double real = 0;
    const Token* token = nullptr;

    Piece(const char* s) : kind(Kind::text), text(s) {}
    Piece(std::string_view s) : kind(Kind::text), text(s) {}
    Piece(const std::string& s) : kind(Kind::text), text(s) {}
    Piece(int v) : kind(Kind::integer), integer(v) {}
    Piece(size_t v) : kind(Kind::integer), integer(static_cast<long long>(v)) {}
    Piece(double v) : kind(Kind::real), real(v) {}
    Piece(const Token& t) : kind(Kind::token), token(&t) {}
    static Piece quoted(std::string_view s) {
        Piece p(s);
        p.kind = Kind::quoted;
        return p;
    }
};

#if defined(__GNUC__)
#define MBX_VRML_COLD __attribute__((noinline, cold))
#else
#define MBX_VRML_COLD
#endif

MBX_VRML_COLD std::string join(std::initializer_list<Piece> pieces);

// `text` quoted for a message, shortened and with control bytes escaped.
std::string quoted_excerpt(std::string_view text);

// A token as a message names it: "end of file", "'['", "number '1.5'", ...
std::string describe_token(const Token& t);

// A number without trailing zeros; integers without a fraction.
std::string format_number(double d);

}  // namespace mbx_files::vrml
