#include "core/report/json_writer.h"

#include <charconv>
#include <cmath>
#include <stdexcept>

#include "core/report/utf8.h"

namespace mbx {
namespace {

// 0: copy as is; 1: needs an escape; 2: starts a multi-byte (or bad) sequence.
struct ByteClasses {
    unsigned char cls[256];
    constexpr ByteClasses() : cls() {
        for (int c = 0; c < 256; ++c) cls[c] = c < 0x20 || c == '"' || c == '\\' ? 1 : c >= 0x80 ? 2 : 0;
    }
};
constexpr ByteClasses kBytes;

void append_escape(std::string& out, unsigned char c) {
    switch (c) {
        case '"': out.append("\\\""); return;
        case '\\': out.append("\\\\"); return;
        case '\b': out.append("\\b"); return;
        case '\f': out.append("\\f"); return;
        case '\n': out.append("\\n"); return;
        case '\r': out.append("\\r"); return;
        case '\t': out.append("\\t"); return;
        default: break;
    }
    static constexpr char kHex[] = "0123456789abcdef";
    const char u[6] = {'\\', 'u', '0', '0', kHex[c >> 4], kHex[c & 0xF]};
    out.append(u, 6);
}

template <class T>
void append_integer(std::string& out, T v) {
    char buf[24];
    const auto r = std::to_chars(buf, buf + sizeof buf, v);
    out.append(buf, r.ptr);
}

}  // namespace

void append_json_string(std::string& out, std::string_view s) {
    out.push_back('"');
    std::size_t i = 0;
    while (i < s.size()) {
        // Copy the longest plain run in one go; most names are plain ASCII.
        std::size_t run = i;
        while (run < s.size() && kBytes.cls[static_cast<unsigned char>(s[run])] == 0) ++run;
        out.append(s.data() + i, run - i);
        i = run;
        if (i == s.size()) break;

        const auto c = static_cast<unsigned char>(s[i]);
        if (kBytes.cls[c] == 1) {
            append_escape(out, c);
            ++i;
            continue;
        }
        i += append_utf8_or_replacement(out, s, i);
    }
    out.push_back('"');
}

void append_json_number(std::string& out, double d) {
    if (!std::isfinite(d)) {
        out.append("null");
        return;
    }
    // Plain to_chars picks the shortest form that round-trips ("0.1", "1e-300",
    // "-0") and, unlike printf, never consults the locale.
    char buf[32];
    const auto r = std::to_chars(buf, buf + sizeof buf, d);
    out.append(buf, r.ptr);
}

void JsonWriter::newline(std::size_t depth) {
    out_.push_back('\n');
    out_.append(2 * depth, ' ');
}

void JsonWriter::separate(Level& level) {
    if (!level.empty) out_.push_back(',');
    if (level.inline_layout) {
        if (!level.empty) out_.push_back(' ');
    } else {
        newline(stack_.size());
    }
    level.empty = false;
}

void JsonWriter::before_value() {
    if (stack_.empty()) {
        if (done_) throw std::logic_error("JsonWriter: a second top-level value");
        return;
    }
    Level& top = stack_.back();
    if (top.object) {
        if (!after_key_) throw std::logic_error("JsonWriter: a value inside an object needs a key");
        after_key_ = false;
    } else {
        separate(top);
    }
}

void JsonWriter::after_value() {
    if (stack_.empty()) done_ = true;
}

JsonWriter& JsonWriter::key(std::string_view name) {
    if (stack_.empty() || !stack_.back().object || after_key_)
        throw std::logic_error("JsonWriter: a key outside an object or after another key");
    separate(stack_.back());
    append_json_string(out_, name);
    out_.append(": ");
    after_key_ = true;
    return *this;
}

JsonWriter& JsonWriter::open(bool object, Layout layout, char bracket) {
    before_value();
    // Anything nested in a one-line container must stay on that line.
    const bool inline_layout = layout == Layout::Inline || (!stack_.empty() && stack_.back().inline_layout);
    stack_.push_back({object, inline_layout, true});
    out_.push_back(bracket);
    return *this;
}

JsonWriter& JsonWriter::close(bool object, char bracket) {
    if (stack_.empty() || stack_.back().object != object || after_key_)
        throw std::logic_error("JsonWriter: unbalanced end of a container");
    const Level level = stack_.back();
    stack_.pop_back();
    if (!level.empty && !level.inline_layout) newline(stack_.size());
    out_.push_back(bracket);
    after_value();
    return *this;
}

JsonWriter& JsonWriter::begin_object(Layout layout) { return open(true, layout, '{'); }
JsonWriter& JsonWriter::end_object() { return close(true, '}'); }
JsonWriter& JsonWriter::begin_array(Layout layout) { return open(false, layout, '['); }
JsonWriter& JsonWriter::end_array() { return close(false, ']'); }

JsonWriter& JsonWriter::value(std::string_view s) {
    before_value();
    append_json_string(out_, s);
    after_value();
    return *this;
}

JsonWriter& JsonWriter::value(const char* s) { return s ? value(std::string_view(s)) : null(); }

JsonWriter& JsonWriter::value(bool b) {
    before_value();
    out_.append(b ? "true" : "false");
    after_value();
    return *this;
}

JsonWriter& JsonWriter::value(double d) {
    before_value();
    append_json_number(out_, d);
    after_value();
    return *this;
}

JsonWriter& JsonWriter::value(long long i) {
    before_value();
    append_integer(out_, i);
    after_value();
    return *this;
}

JsonWriter& JsonWriter::value(unsigned long long u) {
    before_value();
    append_integer(out_, u);
    after_value();
    return *this;
}

JsonWriter& JsonWriter::null() {
    before_value();
    out_.append("null");
    after_value();
    return *this;
}

JsonWriter& JsonWriter::number_array(const double* v, std::size_t n) {
    begin_array(Layout::Inline);
    for (std::size_t i = 0; i < n; ++i) value(v[i]);
    return end_array();
}

std::string JsonWriter::take() {
    std::string text = std::move(out_);
    out_.clear();
    stack_.clear();
    after_key_ = false;
    done_ = false;
    return text;
}

}  // namespace mbx
