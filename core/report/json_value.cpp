#include "core/report/json_value.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <optional>
#include <cstdlib>
#include <cstring>

#include <charconv>

namespace mbx {

const JsonValue* JsonValue::find(std::string_view key) const {
    if (kind != Kind::object) return nullptr;
    for (const auto& [k, v] : object)
        if (k == key) return &v;
    return nullptr;
}

namespace {

// A JSON number's text (the grammar's characters, already scanned) as a
// finite double, locale-independent; nullopt when it is not one.
std::optional<double> finite_number(std::string_view text) {
    if (text.empty() || text[0] == '+') return std::nullopt;
    double value = 0;
    const char* end = text.data() + text.size();
    const auto [ptr, ec] = std::from_chars(text.data(), end, value, std::chars_format::general);
    if (ec != std::errc() || ptr != end || !std::isfinite(value)) return std::nullopt;
    return value;
}

constexpr int kMaxDepth = 64;

class Parser {
public:
    explicit Parser(std::string_view text) : text_(text) {}

    JsonValue run() {
        JsonValue v = value(0);
        space();
        if (at_ < text_.size()) fail("text after the JSON value");
        return v;
    }

private:
    [[noreturn]] void fail(const std::string& message) const { throw JsonError(line_, message); }

    void space() {
        while (at_ < text_.size()) {
            const char c = text_[at_];
            if (c == '\n') ++line_;
            else if (c != ' ' && c != '\t' && c != '\r') return;
            ++at_;
        }
    }

    bool take(char c) {
        space();
        if (at_ < text_.size() && text_[at_] == c) {
            ++at_;
            return true;
        }
        return false;
    }

    void expect(char c, const char* where) {
        if (!take(c)) fail(std::string("expected '") + c + "' " + where);
    }

    bool word(std::string_view w) {
        if (text_.substr(at_, w.size()) != w) return false;
        at_ += w.size();
        return true;
    }

    JsonValue value(int depth) {
        if (depth > kMaxDepth) fail("nested deeper than " + std::to_string(kMaxDepth));
        space();
        JsonValue v;
        v.line = line_;
        if (at_ >= text_.size()) fail("the text ends where a value belongs");
        const char c = text_[at_];
        if (c == '{') {
            ++at_;
            v.kind = JsonValue::Kind::object;
            if (take('}')) return v;
            do {
                space();
                if (at_ >= text_.size() || text_[at_] != '"') fail("expected a member name in quotes");
                std::string key = string();
                expect(':', "after a member name");
                v.object.emplace_back(std::move(key), value(depth + 1));
            } while (take(','));
            expect('}', "to close the object");
        } else if (c == '[') {
            ++at_;
            v.kind = JsonValue::Kind::array;
            if (take(']')) return v;
            do v.array.push_back(value(depth + 1));
            while (take(','));
            expect(']', "to close the array");
        } else if (c == '"') {
            v.kind = JsonValue::Kind::string;
            v.string = string();
        } else if (word("true")) {
            v.kind = JsonValue::Kind::boolean;
            v.boolean = true;
        } else if (word("false")) {
            v.kind = JsonValue::Kind::boolean;
        } else if (word("null")) {
            v.kind = JsonValue::Kind::null;
        } else {
            size_t end = at_;
            while (end < text_.size() && (std::isdigit(static_cast<unsigned char>(text_[end])) || text_[end] == '-' ||
                                          text_[end] == '+' || text_[end] == '.' || text_[end] == 'e' || text_[end] == 'E'))
                ++end;
            const std::optional<double> x = end > at_ ? finite_number(text_.substr(at_, end - at_)) : std::nullopt;
            if (!x) {
                size_t stop = at_;
                while (stop < text_.size() && stop - at_ < 20 && !std::strchr(",:]} \t\r\n", text_[stop])) ++stop;
                fail("'" + std::string(text_.substr(at_, std::max<size_t>(1, stop - at_))) + "' is not a JSON value");
            }
            v.kind = JsonValue::Kind::number;
            v.number = *x;
            at_ = end;
        }
        return v;
    }

    std::string string() {
        ++at_;  // the opening quote
        std::string out;
        while (true) {
            if (at_ >= text_.size()) fail("a string that never ends");
            const char c = text_[at_++];
            if (c == '"') return out;
            if (c == '\n') fail("a line break inside a string");
            if (c != '\\') {
                out += c;
                continue;
            }
            if (at_ >= text_.size()) fail("a string that never ends");
            const char e = text_[at_++];
            switch (e) {
            case '"': out += '"'; break;
            case '\\': out += '\\'; break;
            case '/': out += '/'; break;
            case 'b': out += '\b'; break;
            case 'f': out += '\f'; break;
            case 'n': out += '\n'; break;
            case 'r': out += '\r'; break;
            case 't': out += '\t'; break;
            case 'u': {
                if (at_ + 4 > text_.size()) fail("a \\u escape without four hex digits");
                unsigned code = 0;
                for (int k = 0; k < 4; ++k) {
                    const char h = text_[at_++];
                    code <<= 4;
                    if (h >= '0' && h <= '9') code |= unsigned(h - '0');
                    else if (h >= 'a' && h <= 'f') code |= unsigned(h - 'a' + 10);
                    else if (h >= 'A' && h <= 'F') code |= unsigned(h - 'A' + 10);
                    else fail("a \\u escape without four hex digits");
                }
                // UTF-8 of the code unit (pairs of surrogates are kept as written: names mbx writes are ASCII).
                if (code < 0x80) out += char(code);
                else if (code < 0x800) out += char(0xC0 | (code >> 6)), out += char(0x80 | (code & 0x3F));
                else out += char(0xE0 | (code >> 12)), out += char(0x80 | ((code >> 6) & 0x3F)), out += char(0x80 | (code & 0x3F));
                break;
            }
            default: fail(std::string("an unknown escape \\") + e + " in a string");
            }
        }
    }

    std::string_view text_;
    size_t at_ = 0;
    int line_ = 1;
};

}  // namespace

JsonValue parse_json(std::string_view text) { return Parser(text).run(); }

}  // namespace mbx
