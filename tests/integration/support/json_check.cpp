#include "json_check.h"

#include <cctype>
#include <cstring>

namespace itest {
namespace {

class Parser {
public:
    Parser(const std::string& text, JsonCheck& out) : s_(text), out_(out) {}

    bool document() {
        ws();
        if (!value(0)) return false;
        ws();
        if (i_ != s_.size()) return fail("trailing characters after the document");
        return true;
    }

private:
    bool fail(const char* what) {
        if (out_.error.empty()) out_.error = "offset " + std::to_string(i_) + ": " + what;
        return false;
    }
    void ws() {
        while (i_ < s_.size() && (s_[i_] == ' ' || s_[i_] == '\t' || s_[i_] == '\n' || s_[i_] == '\r')) ++i_;
    }
    bool eat(char c) {
        if (i_ < s_.size() && s_[i_] == c) {
            ++i_;
            return true;
        }
        return false;
    }
    bool literal(const char* word) {
        const size_t n = std::strlen(word);
        if (s_.compare(i_, n, word) != 0) return fail("bad literal");
        i_ += n;
        return true;
    }
    bool string(std::string* into) {
        if (!eat('"')) return fail("expected a string");
        while (i_ < s_.size()) {
            const unsigned char c = static_cast<unsigned char>(s_[i_++]);
            if (c == '"') return true;
            if (c < 0x20) return fail("control character in a string");
            if (c == '\\') {
                if (i_ >= s_.size()) break;
                const char e = s_[i_++];
                if (e == 'u') {
                    for (int k = 0; k < 4; ++k)
                        if (i_ >= s_.size() || !std::isxdigit(static_cast<unsigned char>(s_[i_++])))
                            return fail("bad \\u escape");
                    if (into) *into += '?';
                    continue;
                }
                if (!std::strchr("\"\\/bfnrt", e)) return fail("bad escape");
                if (into) *into += e;
                continue;
            }
            if (into) *into += char(c);
        }
        return fail("unterminated string");
    }
    bool digits() {
        const size_t start = i_;
        while (i_ < s_.size() && std::isdigit(static_cast<unsigned char>(s_[i_]))) ++i_;
        return i_ > start;
    }
    bool number() {
        eat('-');
        if (eat('0')) {
            // no leading zeros
        } else if (!digits()) {
            return fail("bad number");
        }
        if (eat('.') && !digits()) return fail("bad fraction");
        if (i_ < s_.size() && (s_[i_] == 'e' || s_[i_] == 'E')) {
            ++i_;
            if (!eat('+')) eat('-');
            if (!digits()) return fail("bad exponent");
        }
        return true;
    }
    bool value(int depth) {
        if (depth > 200) return fail("nesting too deep");
        if (i_ >= s_.size()) return fail("unexpected end");
        const char c = s_[i_];
        if (c == '{') return object(depth);
        if (c == '[') return array(depth);
        if (c == '"') return string(nullptr);
        if (c == 't') return literal("true");
        if (c == 'f') return literal("false");
        if (c == 'n') return literal("null");
        if (c == '-' || std::isdigit(static_cast<unsigned char>(c))) return number();
        return fail("unexpected character");
    }
    bool object(int depth) {
        eat('{');
        ws();
        if (eat('}')) return true;
        for (;;) {
            std::string key;
            ws();
            if (!string(&key)) return false;
            out_.all_keys.insert(key);
            if (depth == 0) out_.top_keys.insert(key);
            ws();
            if (!eat(':')) return fail("expected ':'");
            ws();
            if (!value(depth + 1)) return false;
            ws();
            if (eat('}')) return true;
            if (!eat(',')) return fail("expected ',' or '}'");
        }
    }
    bool array(int depth) {
        eat('[');
        ws();
        if (eat(']')) return true;
        for (;;) {
            ws();
            if (!value(depth + 1)) return false;
            ws();
            if (eat(']')) return true;
            if (!eat(',')) return fail("expected ',' or ']'");
        }
    }

    const std::string& s_;
    JsonCheck& out_;
    size_t i_ = 0;
};

}  // namespace

JsonCheck check_json(const std::string& text) {
    JsonCheck out;
    out.ok = Parser(text, out).document();
    return out;
}

}  // namespace itest
