#include "host_adapters/step/part21.h"

#include <sys/stat.h>

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cstdio>
#include <fstream>
#include <memory>

namespace mbx_step {

ReadError::ReadError(std::string file, int line, uint64_t entity, std::string message)
    : std::runtime_error(file + ":" + std::to_string(line) + ": " +
                         (entity ? "#" + std::to_string(entity) + ": " : std::string()) + message),
      file_(std::move(file)),
      line_(line),
      entity_(entity),
      message_(std::move(message)) {}

uint32_t File::type_id(std::string_view upper_name) const {
    const auto it = type_ids_.find(std::string(upper_name));
    return it == type_ids_.end() ? kNoType : it->second;
}

uint32_t File::intern(std::string_view upper_name) {
    auto [it, added] = type_ids_.emplace(std::string(upper_name), uint32_t(type_names_.size()));
    if (added) type_names_.emplace_back(upper_name);
    return it->second;
}

uint32_t File::index_of(uint64_t id) const {
    const auto it = std::lower_bound(by_id_.begin(), by_id_.end(), std::pair<uint64_t, uint32_t>(id, 0));
    return it != by_id_.end() && it->first == id ? it->second : kUnresolved;
}

const Instance* File::find(uint64_t id) const {
    const uint32_t k = index_of(id);
    return k == kUnresolved ? nullptr : &instances[k];
}

const Record* File::record(const Instance& instance, uint32_t type) const {
    for (uint32_t k = 0; k < instance.record_count; ++k)
        if (records[instance.first_record + k].type == type) return &records[instance.first_record + k];
    return nullptr;
}

namespace {

constexpr size_t kMaxProblems = 100;

void add_problem(File& f, int line, uint64_t entity, std::string message) {
    if (f.problems.size() < kMaxProblems) f.problems.push_back({line, entity, std::move(message)});
}

// Appends a code point as UTF-8 (a code point UTF-8 cannot hold becomes U+FFFD).
void put_utf8(std::string& out, uint32_t c) {
    if (c > 0x10FFFF || (c >= 0xD800 && c <= 0xDFFF)) c = 0xFFFD;
    if (c < 0x80) {
        out += char(c);
    } else if (c < 0x800) {
        out += char(0xC0 | (c >> 6));
        out += char(0x80 | (c & 0x3F));
    } else if (c < 0x10000) {
        out += char(0xE0 | (c >> 12));
        out += char(0x80 | ((c >> 6) & 0x3F));
        out += char(0x80 | (c & 0x3F));
    } else {
        out += char(0xF0 | (c >> 18));
        out += char(0x80 | ((c >> 12) & 0x3F));
        out += char(0x80 | ((c >> 6) & 0x3F));
        out += char(0x80 | (c & 0x3F));
    }
}

int hex_digit(char c) {
    if (c >= '0' && c <= '9') return c - '0';
    if (c >= 'A' && c <= 'F') return c - 'A' + 10;
    if (c >= 'a' && c <= 'f') return c - 'a' + 10;
    return -1;
}

// `n` hex digits at s (n <= 8), or -1.
int64_t hex(std::string_view s, size_t at, size_t n) {
    if (at + n > s.size()) return -1;
    int64_t v = 0;
    for (size_t k = 0; k < n; ++k) {
        const int d = hex_digit(s[at + k]);
        if (d < 0) return -1;
        v = v * 16 + d;
    }
    return v;
}

// The control directives of Part 21 strings (\S\, \X\, \X2\...\X0\,
// \X4\...\X0\, \P?\, \\) decoded to UTF-8. Text that follows none of them is
// kept as written: a tolerant reader of a name loses nothing.
std::string decode_string(std::string_view raw) {
    std::string out;
    out.reserve(raw.size());
    for (size_t i = 0; i < raw.size();) {
        const char c = raw[i];
        if (c != '\\') {
            if (uint8_t(c) < 0x80) {
                out += c;
            } else {
                put_utf8(out, uint8_t(c));  // 8-bit text outside the escapes: read as Latin-1
            }
            ++i;
            continue;
        }
        const std::string_view rest = raw.substr(i);
        if (rest.substr(0, 2) == "\\\\") {
            out += '\\';
            i += 2;
        } else if (rest.size() >= 4 && rest.substr(0, 3) == "\\S\\") {
            put_utf8(out, uint8_t(rest[3]) + 128u);
            i += 4;
        } else if (rest.size() >= 4 && rest[1] == 'P' && rest[3] == '\\') {
            i += 4;  // a code page other than Latin-1 is rare; read its \S\ as Latin-1
        } else if (rest.substr(0, 3) == "\\X\\" && hex(rest, 3, 2) >= 0) {
            put_utf8(out, uint32_t(hex(rest, 3, 2)));
            i += 5;
        } else if (rest.substr(0, 4) == "\\X2\\" || rest.substr(0, 4) == "\\X4\\") {
            const size_t width = rest[2] == '2' ? 4 : 8;
            const size_t end = rest.find("\\X0\\", 4);
            if (end == std::string_view::npos) {
                out += c;
                ++i;
                continue;
            }
            uint32_t high = 0;
            for (size_t k = 4; k + width <= end; k += width) {
                const int64_t v = hex(rest, k, width);
                if (v < 0) break;
                if (width == 4 && v >= 0xD800 && v <= 0xDBFF) {
                    high = uint32_t(v);
                    continue;
                }
                if (width == 4 && v >= 0xDC00 && v <= 0xDFFF && high) {
                    put_utf8(out, 0x10000 + ((high - 0xD800) << 10) + (uint32_t(v) - 0xDC00));
                    high = 0;
                    continue;
                }
                put_utf8(out, uint32_t(v));
            }
            i += end + 4;
        } else {
            out += c;
            ++i;
        }
    }
    return out;
}

class Parser {
public:
    Parser(std::string_view text, const std::string& path, const ReadLimits& limits, File& f)
        : p_(text.data()), end_(text.data() + text.size()), path_(path), limits_(limits), f_(f) {
        scratch_.resize(size_t(limits.max_depth) + 2);
    }

    void run() {
        skip();
        expect_word("ISO-10303-21");
        expect(';');
        skip();
        expect_word("HEADER");
        expect(';');
        header();
        bool data = false;
        for (;;) {
            skip();
            const std::string_view word = keyword();
            if (word == "END-ISO-10303-21") {
                expect(';');
                break;
            }
            if (word == "DATA") {
                skip();
                if (peek() == '(') {
                    uint32_t n = 0;
                    list(0, n);  // a named data section's name and schema: not needed
                }
                expect(';');
                instances();
                data = true;
            } else if (word == "ANCHOR" || word == "REFERENCE" || word == "SIGNATURE") {
                skip_section();
            } else if (word.empty()) {
                fail("expected DATA; or END-ISO-10303-21;");
            } else {
                fail("expected DATA; or END-ISO-10303-21; found " + std::string(word));
            }
        }
        if (!data) fail("no DATA section");
    }

private:
    [[noreturn]] void fail(const std::string& why) { throw ReadError(path_, line_, entity_, why); }

    char peek() const { return p_ < end_ ? *p_ : '\0'; }

    // Whitespace and comments between tokens.
    void skip() {
        for (;;) {
            while (p_ < end_ && uint8_t(*p_) <= ' ') {
                if (*p_ == '\n') ++line_;
                ++p_;
            }
            if (end_ - p_ >= 2 && p_[0] == '/' && p_[1] == '*') {
                const int opened = line_;
                p_ += 2;
                for (;;) {
                    if (end_ - p_ < 2) {
                        line_ = opened;
                        fail("a comment that never ends");
                    }
                    if (p_[0] == '*' && p_[1] == '/') break;
                    if (*p_ == '\n') ++line_;
                    ++p_;
                }
                p_ += 2;
                continue;
            }
            return;
        }
    }

    void expect(char c) {
        skip();
        if (peek() != c) {
            std::string got = p_ < end_ ? std::string(1, *p_) : std::string("the end of the file");
            fail(std::string("expected '") + c + "', found " + (p_ < end_ ? "'" + got + "'" : got));
        }
        ++p_;
    }

    void expect_word(std::string_view word) {
        skip();
        if (size_t(end_ - p_) < word.size() || std::string_view(p_, word.size()) != word)
            fail("expected " + std::string(word) + (p_ == end_ ? " (the file ends)" : ""));
        p_ += word.size();
    }

    // A keyword ([A-Z_!][A-Z0-9_-]*), upper-cased in place of a lower-case
    // writer's; empty when none starts here.
    std::string_view keyword() {
        skip();
        const char* start = p_;
        if (p_ < end_ && (std::isalpha(uint8_t(*p_)) || *p_ == '_' || *p_ == '!')) {
            ++p_;
            while (p_ < end_ && (std::isalnum(uint8_t(*p_)) || *p_ == '_' || *p_ == '-')) ++p_;
        }
        const std::string_view word(start, size_t(p_ - start));
        for (char c : word)
            if (c >= 'a' && c <= 'z') {
                upper_.assign(word);
                for (char& u : upper_) u = char(std::toupper(uint8_t(u)));
                return upper_;
            }
        return word;
    }

    void header() {
        for (;;) {
            skip();
            const std::string_view word = keyword();
            if (word == "ENDSEC") {
                expect(';');
                return;
            }
            if (word.empty()) fail("expected a header entity or ENDSEC;");
            const std::string name(word);
            uint32_t count = 0;
            expect_open();
            const uint32_t first = list(0, count);
            expect(';');
            auto string_at = [&](uint32_t k) -> std::string {
                if (k >= count || f_.values[first + k].kind != Kind::String) return {};
                return std::string(f_.text(f_.values[first + k]));
            };
            auto strings_at = [&](uint32_t k) {
                std::vector<std::string> out;
                if (k >= count || f_.values[first + k].kind != Kind::List) return out;
                const Value& l = f_.values[first + k];
                for (uint32_t i = 0; i < uint32_t(l.count); ++i)
                    if (f_.element(l, i).kind == Kind::String) out.emplace_back(f_.text(f_.element(l, i)));
                return out;
            };
            if (name == "FILE_DESCRIPTION") {
                f_.header.description = strings_at(0);
            } else if (name == "FILE_NAME") {
                f_.header.name = string_at(0);
                f_.header.originating_system = string_at(5);
            } else if (name == "FILE_SCHEMA") {
                f_.header.schemas = strings_at(0);
            }
        }
    }

    void expect_open() {
        skip();
        if (peek() != '(') fail("expected '('");
    }

    void skip_section() {
        // Statements until ENDSEC;, strings and comments respected.
        for (;;) {
            skip();
            if (p_ >= end_) fail("a section that never ends (no ENDSEC;)");
            if (end_ - p_ >= 6 && std::string_view(p_, 6) == "ENDSEC") {
                p_ += 6;
                expect(';');
                return;
            }
            if (*p_ == '\'') {
                string_value();
            } else {
                ++p_;
            }
        }
    }

    void instances() {
        for (;;) {
            skip();
            if (peek() == '#') {
                instance();
                continue;
            }
            const std::string_view word = keyword();
            if (word == "ENDSEC") {
                expect(';');
                return;
            }
            if (p_ >= end_) fail("the file ends inside its DATA section");
            fail(word.empty() ? std::string("expected an entity instance (#n=...) or ENDSEC;, found '") + *p_ + "'"
                              : "expected an entity instance (#n=...) or ENDSEC;, found " + std::string(word));
        }
    }

    uint64_t instance_name() {
        ++p_;  // '#'
        const char* start = p_;
        uint64_t id = 0;
        while (p_ < end_ && *p_ >= '0' && *p_ <= '9') {
            if (p_ - start >= 18) fail("an instance number longer than 18 digits");
            id = id * 10 + uint64_t(*p_ - '0');
            ++p_;
        }
        if (p_ == start) fail("'#' without an instance number");
        return id;
    }

    void instance() {
        entity_ = 0;
        const int line = line_;
        const uint64_t id = instance_name();
        entity_ = id;
        if (id == 0) fail("instance number 0 (numbers start at 1)");
        if (f_.instances.size() >= limits_.max_instances)
            fail("more than " + std::to_string(limits_.max_instances) + " instances");
        expect('=');
        Instance in;
        in.id = id;
        in.line = uint32_t(line);
        in.first_record = uint32_t(f_.records.size());
        skip();
        if (peek() == '(') {
            // A complex instance: partial records until the closing ')'.
            ++p_;
            for (;;) {
                skip();
                if (peek() == ')') {
                    ++p_;
                    break;
                }
                record();
                ++in.record_count;
            }
            if (in.record_count == 0) fail("a complex instance with no records");
        } else {
            record();
            in.record_count = 1;
        }
        expect(';');
        f_.instances.push_back(in);
        entity_ = 0;
    }

    void record() {
        const std::string_view word = keyword();
        if (word.empty()) fail(p_ < end_ ? std::string("expected an entity name, found '") + *p_ + "'" : "the file ends inside an instance");
        Record r;
        r.type = f_.intern(word);
        expect_open();
        r.first = list(0, r.count);
        f_.records.push_back(r);
    }

    // "( v, v, ... )" at p_: appends the elements contiguously to f_.values
    // and returns the first one's index.
    uint32_t list(uint32_t depth, uint32_t& count) {
        if (depth > limits_.max_depth) fail("lists nested deeper than " + std::to_string(limits_.max_depth));
        ++p_;  // '('
        std::vector<Value>& items = scratch_[depth];
        items.clear();
        skip();
        if (peek() == ')') {
            ++p_;
        } else {
            for (;;) {
                items.push_back(parameter(depth + 1));
                skip();
                const char c = peek();
                ++p_;
                if (c == ',') continue;
                if (c == ')') break;
                --p_;
                fail(p_ < end_ ? std::string("expected ',' or ')', found '") + c + "'" : "the file ends inside a list");
            }
        }
        // (scratch_[depth] is not touched by the nested calls above, which use deeper levels)
        const uint32_t first = uint32_t(f_.values.size());
        f_.values.insert(f_.values.end(), items.begin(), items.end());
        count = uint32_t(items.size());
        return first;
    }

    Value parameter(uint32_t depth) {
        skip();
        if (p_ >= end_) fail("the file ends inside an instance");
        Value v;
        const char c = *p_;
        switch (c) {
            case '$':
                ++p_;
                v.kind = Kind::Missing;
                return v;
            case '*':
                ++p_;
                v.kind = Kind::Derived;
                return v;
            case '#':
                v.kind = Kind::Reference;
                v.id = instance_name();
                v.a = kUnresolved;
                return v;
            case '\'':
                return string_value();
            case '"': {
                ++p_;
                const char* start = p_;
                while (p_ < end_ && *p_ != '"') {
                    if (hex_digit(*p_) < 0) fail("a binary value with a character that is not a hex digit");
                    ++p_;
                }
                if (p_ >= end_) fail("a binary value that never ends");
                v.kind = Kind::Binary;
                v.a = pool(std::string_view(start, size_t(p_ - start)));
                v.count = uint64_t(p_ - start);
                ++p_;
                return v;
            }
            case '.': {
                ++p_;
                const char* start = p_;
                while (p_ < end_ && (std::isalnum(uint8_t(*p_)) || *p_ == '_')) ++p_;
                if (p_ >= end_ || *p_ != '.' || p_ == start) fail("an enumeration value not of the form .NAME.");
                v.kind = Kind::Enumeration;
                std::string name(start, size_t(p_ - start));
                for (char& u : name) u = char(std::toupper(uint8_t(u)));
                v.a = pool(name);
                v.count = name.size();
                ++p_;
                return v;
            }
            case '(': {
                uint32_t count = 0;
                v.kind = Kind::List;
                v.a = list(depth, count);
                v.count = count;
                return v;
            }
            default:
                break;
        }
        if (c == '+' || c == '-' || (c >= '0' && c <= '9')) return number();
        if (std::isalpha(uint8_t(c)) || c == '_' || c == '!') {
            // A typed parameter: TYPE( value ).
            if (depth > limits_.max_depth) fail("typed values nested deeper than " + std::to_string(limits_.max_depth));
            const uint32_t type = f_.intern(keyword());
            expect('(');
            const Value inner = parameter(depth + 1);
            expect(')');
            v.kind = Kind::Typed;
            v.a = uint32_t(f_.values.size());
            v.type = type;
            f_.values.push_back(inner);
            return v;
        }
        fail(std::string("expected a value, found '") + c + "'");
    }

    Value number() {
        const char* start = p_;
        bool negative = false;
        if (*p_ == '+' || *p_ == '-') negative = *p_++ == '-';
        const char* digits = p_;
        bool real = false;
        while (p_ < end_ && *p_ >= '0' && *p_ <= '9') ++p_;
        if (p_ == digits) fail("a sign without a number");
        if (p_ < end_ && *p_ == '.') {
            real = true;
            ++p_;
            while (p_ < end_ && *p_ >= '0' && *p_ <= '9') ++p_;
        }
        if (p_ < end_ && (*p_ == 'E' || *p_ == 'e')) {
            real = true;
            ++p_;
            if (p_ < end_ && (*p_ == '+' || *p_ == '-')) ++p_;
            const char* exponent = p_;
            while (p_ < end_ && *p_ >= '0' && *p_ <= '9') ++p_;
            if (p_ == exponent) fail("a real with an empty exponent: " + std::string(start, size_t(p_ - start)));
        }
        Value v;
        if (real) {
            double x = 0;
            const auto r = std::from_chars(digits, p_, x, std::chars_format::general);
            if (r.ec == std::errc::result_out_of_range) fail("a real out of range: " + std::string(start, size_t(p_ - start)));
            if (r.ec != std::errc() || r.ptr != p_) fail("not a real: " + std::string(start, size_t(p_ - start)));
            v.kind = Kind::Real;
            v.real = negative ? -x : x;
        } else {
            int64_t x = 0;
            const auto r = std::from_chars(digits, p_, x);
            if (r.ec != std::errc() || r.ptr != p_) fail("an integer out of range: " + std::string(start, size_t(p_ - start)));
            v.kind = Kind::Integer;
            v.integer = negative ? -x : x;
        }
        return v;
    }

    Value string_value() {
        const int opened = line_;
        ++p_;  // '\''
        raw_.clear();
        bool escaped = false;
        for (;;) {
            // Runs of ordinary characters at once.
            const char* run = p_;
            while (p_ < end_ && *p_ != '\'' && *p_ != '\n' && *p_ != '\r' && *p_ != '\\') ++p_;
            raw_.append(run, size_t(p_ - run));
            if (p_ >= end_) {
                line_ = opened;
                fail("a string that never ends");
            }
            const char c = *p_++;
            if (c == '\'') {
                if (p_ < end_ && *p_ == '\'') {
                    raw_ += '\'';
                    ++p_;
                    continue;
                }
                break;
            }
            if (c == '\n') {
                ++line_;  // line breaks inside a string are not part of it
                continue;
            }
            if (c == '\r') continue;
            escaped = true;
            raw_ += c;
        }
        Value v;
        v.kind = Kind::String;
        if (escaped) {
            const std::string decoded = decode_string(raw_);
            v.a = pool(decoded);
            v.count = decoded.size();
        } else {
            v.a = pool(raw_);
            v.count = raw_.size();
        }
        return v;
    }

    uint32_t pool(std::string_view s) {
        if (f_.text_pool.size() + s.size() > 0xFFFFFFFFull) fail("more than 4 GB of strings");
        const uint32_t at = uint32_t(f_.text_pool.size());
        f_.text_pool.append(s);
        return at;
    }

    const char* p_;
    const char* end_;
    const std::string& path_;
    const ReadLimits& limits_;
    File& f_;
    int line_ = 1;
    uint64_t entity_ = 0;
    std::vector<std::vector<Value>> scratch_;
    std::string upper_, raw_;
};

}  // namespace

void File::resolve() {
    by_id_.clear();
    by_id_.reserve(instances.size());
    for (uint32_t k = 0; k < instances.size(); ++k) by_id_.emplace_back(instances[k].id, k);
    std::sort(by_id_.begin(), by_id_.end());
    for (size_t k = 1; k < by_id_.size(); ++k)
        if (by_id_[k].first == by_id_[k - 1].first) {
            const Instance& a = instances[by_id_[k - 1].second];
            const Instance& b = instances[by_id_[k].second];
            throw ReadError(path, int(std::max(a.line, b.line)), a.id,
                            "instance number written twice (lines " + std::to_string(std::min(a.line, b.line)) +
                                " and " + std::to_string(std::max(a.line, b.line)) + ")");
        }
    // References to instance indices, and the reference graph (CSR) for the
    // cycle check. Values of an instance are its records' attributes and the
    // elements and typed values nested in them.
    std::vector<uint32_t> offsets(instances.size() + 1, 0), edges;
    edges.reserve(values.size() / 2);
    std::vector<uint32_t> stack;
    for (uint32_t k = 0; k < instances.size(); ++k) {
        const Instance& in = instances[k];
        offsets[k] = uint32_t(edges.size());
        for (uint32_t r = 0; r < in.record_count; ++r) {
            const Record& rec = records[in.first_record + r];
            for (uint32_t i = 0; i < rec.count; ++i) stack.push_back(rec.first + i);
        }
        while (!stack.empty()) {
            Value& v = values[stack.back()];
            stack.pop_back();
            if (v.kind == Kind::Reference) {
                v.a = index_of(v.id);
                if (v.a == kUnresolved)
                    add_problem(*this, int(in.line), in.id, "refers to #" + std::to_string(v.id) + ", which the file does not have");
                else
                    edges.push_back(v.a);
            } else if (v.kind == Kind::List) {
                for (uint32_t i = 0; i < uint32_t(v.count); ++i) stack.push_back(v.a + i);
            } else if (v.kind == Kind::Typed) {
                stack.push_back(v.a);
            }
        }
    }
    offsets[instances.size()] = uint32_t(edges.size());
    // Cycles: a depth-first walk with three colours, iterative (a chain of a
    // million references must not overflow the stack).
    enum : uint8_t { kWhite, kGrey, kBlack };
    std::vector<uint8_t> colour(instances.size(), kWhite);
    std::vector<std::pair<uint32_t, uint32_t>> trail;  // (instance, next edge)
    size_t cycles = 0;
    for (uint32_t start = 0; start < instances.size(); ++start) {
        if (colour[start] != kWhite) continue;
        trail.emplace_back(start, offsets[start]);
        colour[start] = kGrey;
        while (!trail.empty()) {
            auto& [node, next] = trail.back();
            if (next == offsets[node + 1]) {
                colour[node] = kBlack;
                trail.pop_back();
                continue;
            }
            const uint32_t to = edges[next++];
            if (colour[to] == kWhite) {
                colour[to] = kGrey;
                trail.emplace_back(to, offsets[to]);
            } else if (colour[to] == kGrey) {
                ++cycles;
                std::string chain;
                size_t from = trail.size();
                while (from > 0 && trail[from - 1].first != to) --from;
                for (size_t i = from == 0 ? 0 : from - 1; i < trail.size() && chain.size() < 200; ++i)
                    chain += "#" + std::to_string(instances[trail[i].first].id) + " -> ";
                chain += "#" + std::to_string(instances[to].id);
                add_problem(*this, int(instances[to].line), instances[to].id, "a cycle of references: " + chain);
            }
        }
    }
    (void)cycles;
}

File read_part21(std::string_view text, const std::string& path, const ReadLimits& limits) {
    File f;
    f.path = path;
    // Typical files: about one instance per 60 bytes, three values per instance.
    f.instances.reserve(text.size() / 80);
    f.records.reserve(text.size() / 80);
    f.values.reserve(text.size() / 16);
    Parser(text, f.path, limits, f).run();
    f.resolve();
    return f;
}

File read_part21_file(const std::string& path, uint64_t max_bytes, const ReadLimits& limits) {
    struct stat st {};
    if (::stat(path.c_str(), &st) != 0) throw ReadError(path, 0, 0, "cannot open the file");
    if (!S_ISREG(st.st_mode)) throw ReadError(path, 0, 0, "not a regular file");
    if (uint64_t(st.st_size) > max_bytes)
        throw ReadError(path, 0, 0, "larger than " + std::to_string(max_bytes) + " bytes");
    std::ifstream in(path, std::ios::binary);
    if (!in) throw ReadError(path, 0, 0, "cannot open the file");
    std::string text(size_t(st.st_size), '\0');
    in.read(text.data(), std::streamsize(text.size()));
    if (size_t(in.gcount()) != text.size()) throw ReadError(path, 0, 0, "cannot read the whole file");
    return read_part21(text, path, limits);
}

}  // namespace mbx_step
