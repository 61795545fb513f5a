// Tokens of the VRML97 classic encoding (ISO/IEC 14772-1, clause 5) over a
// text held in memory. Hand-written because the bulk of a CAD export is
// numbers: they are converted here with std::from_chars, once, as they are
// scanned.
#pragma once
#include <string>
#include <string_view>

namespace mbx_files::vrml {

enum class Tok { eof, identifier, number, string, lbracket, rbracket, lbrace, rbrace, period };

struct Token {
    Tok kind = Tok::eof;
    int line = 0;
    std::string_view text;  // identifier spelling, or the number as written
    double number = 0;      // Tok::number (hex integers too)
    std::string str;        // Tok::string, escapes resolved
};

// One token of lookahead: peek() shows it, advance() moves past it. Errors
// (junk bytes, malformed or non-finite numbers, unterminated strings) throw
// VrmlError naming `file` and the line.
class Lexer {
public:
    Lexer(std::string_view text, const std::string& file);

    const Token& peek() const { return token_; }
    void advance() { scan(); }
    // The current string token's text, moved out; then advances.
    std::string take_string();

    const std::string& file() const { return file_; }
    [[noreturn]] void fail(int line, const std::string& message) const;

private:
    void scan();
    void skip_blank();
    void scan_number();
    void scan_string();
    void scan_identifier();

    const char* p_;
    const char* end_;
    int line_ = 1;
    const std::string& file_;
    Token token_;
};

}  // namespace mbx_files::vrml
