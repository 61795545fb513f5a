#include "pmxml_outline.h"

#include <cstring>
#include <string>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

namespace mbx_files {
namespace {

using xml_subset::blank;
using xml_subset::is_space;
using xml_subset::name_char;
using xml_subset::name_start;

bool equals_ignoring_case(std::string_view a, std::string_view b) {
    if (a.size() != b.size()) return false;
    for (size_t i = 0; i < a.size(); ++i) {
        char x = a[i], y = b[i];
        if (x >= 'A' && x <= 'Z') x = char(x - 'A' + 'a');
        if (y >= 'A' && y <= 'Z') y = char(y - 'A' + 'a');
        if (x != y) return false;
    }
    return true;
}

// The first `needle` ("</name") in [p, e), or null. Looks at end tags only
// ("</" pairs, found 16 bytes at a time): memmem compared at every '<'.
const char* find_end_tag(const char* p, const char* e, std::string_view needle) {
#if defined(__SSE2__)
    const __m128i lt = _mm_set1_epi8('<'), slash = _mm_set1_epi8('/');
    // (p + 1 .. p + 16 must be readable: the last 16 bytes go below.)
    for (; e - p >= 17; p += 16) {
        const __m128i a = _mm_loadu_si128(reinterpret_cast<const __m128i*>(p));
        const __m128i b = _mm_loadu_si128(reinterpret_cast<const __m128i*>(p + 1));
        unsigned hits = unsigned(_mm_movemask_epi8(_mm_and_si128(_mm_cmpeq_epi8(a, lt), _mm_cmpeq_epi8(b, slash))));
        while (hits) {
            const char* at = p + __builtin_ctz(hits);
            if (size_t(e - at) >= needle.size() && std::memcmp(at, needle.data(), needle.size()) == 0) return at;
            hits &= hits - 1;
        }
    }
#endif
    const void* hit = memmem(p, size_t(e - p), needle.data(), needle.size());
    return static_cast<const char*>(hit);
}

// The part list an element of this name belongs to, when it is a part.
const char* part_list(std::string_view name) {
    if (name == "Body") return "bodies";
    if (name == "SimpleJoint") return "joints";
    if (name == "Ground") return "grounds";
    return nullptr;
}

// Whether `text` holds a NUL, a '&' or a '\r', in one pass.
void census(std::string_view text, bool& nul, xml_subset::Conversions& conversions) {
    const char* p = text.data();
    const char* const e = p + text.size();
#if defined(__SSE2__)
    __m128i any_nul = _mm_setzero_si128(), any_amp = any_nul, any_cr = any_nul;
    const __m128i zero = _mm_setzero_si128(), amp = _mm_set1_epi8('&'), cr = _mm_set1_epi8('\r');
    for (; e - p >= 16; p += 16) {
        const __m128i v = _mm_loadu_si128(reinterpret_cast<const __m128i*>(p));
        any_nul = _mm_or_si128(any_nul, _mm_cmpeq_epi8(v, zero));
        any_amp = _mm_or_si128(any_amp, _mm_cmpeq_epi8(v, amp));
        any_cr = _mm_or_si128(any_cr, _mm_cmpeq_epi8(v, cr));
    }
    nul = _mm_movemask_epi8(any_nul) != 0;
    conversions.ampersand = _mm_movemask_epi8(any_amp) != 0;
    conversions.carriage_return = _mm_movemask_epi8(any_cr) != 0;
#else
    nul = conversions.ampersand = conversions.carriage_return = false;
#endif
    for (; p < e; ++p) {
        nul = nul || *p == '\0';
        conversions.ampersand = conversions.ampersand || *p == '&';
        conversions.carriage_return = conversions.carriage_return || *p == '\r';
    }
}

class Outliner {
public:
    Outliner(std::string_view text, PmxmlOutline& out) : b_(text.data()), p_(text.data()), e_(text.data() + text.size()), out_(out) {}

    bool run() {
        out_.elements.clear();
        out_.root = -1;
        if (e_ - b_ < 4) return false;
        bool nul = false;
        census(std::string_view(b_, size_t(e_ - b_)), nul, out_.conversions);
        if (nul) return false;
        if (!declaration()) return false;
        bool root_closed = false;
        while (p_ < e_) {
            const char* lt = static_cast<const char*>(std::memchr(p_, '<', size_t(e_ - p_)));
            const std::string_view segment(p_, size_t((lt ? lt : e_) - p_));
            if (!text(segment)) return false;
            if (!lt) break;
            p_ = lt + 1;
            if (p_ == e_) return false;
            if (*p_ == '/') {
                if (!end_tag()) return false;
                if (open_.empty()) root_closed = true;
            } else {
                if (root_closed || !start_tag(lt)) return false;
            }
        }
        return root_closed && open_.empty();
    }

private:
    // An XML declaration that leaves the text UTF-8 (pugixml skips it as a
    // processing instruction); any other start than '<' or one is refused.
    bool declaration() {
        if (*p_ != '<') return false;  // a byte-order mark, or text before the root
        const std::string_view head(p_, size_t(e_ - p_));
        if (head.compare(0, 5, "<?xml") != 0 || head.size() < 6 || !is_space(head[5])) return true;
        const size_t close = head.find("?>");
        if (close == std::string_view::npos) return false;
        const std::string_view decl = head.substr(0, close);
        const size_t at = decl.find("encoding");
        if (at != std::string_view::npos) {
            size_t i = at + 8;
            while (i < decl.size() && is_space(decl[i])) ++i;
            if (i >= decl.size() || decl[i] != '=') return false;
            ++i;
            while (i < decl.size() && is_space(decl[i])) ++i;
            if (i >= decl.size() || (decl[i] != '"' && decl[i] != '\'')) return false;
            const size_t end = decl.find(decl[i], i + 1);
            if (end == std::string_view::npos) return false;
            const std::string_view value = decl.substr(i + 1, end - i - 1);
            if (!equals_ignoring_case(value, "utf-8") && !equals_ignoring_case(value, "utf8")) return false;
        }
        p_ += close + 2;
        return true;
    }

    // Text between tags: blank text is dropped (as pugixml does without
    // parse_ws_pcdata); the first other text of an element is its value.
    bool text(std::string_view segment) {
        if (segment.empty() || blank(segment)) return true;
        if (open_.empty()) return false;  // text outside the root element
        // References and line ends would need pugixml's conversions.
        if (out_.conversions.in(segment)) return false;
        OutlineElement& e = out_.elements[size_t(open_.back())];
        if (e.text.empty()) e.text = segment;
        return true;
    }

    std::string_view name() {
        const char* start = p_;
        if (p_ == e_ || !name_start(*p_)) return {};
        while (p_ < e_ && name_char(*p_)) ++p_;
        return std::string_view(start, size_t(p_ - start));
    }

    void skip_space() {
        while (p_ < e_ && is_space(*p_)) ++p_;
    }

    bool end_tag() {
        ++p_;  // '/'
        const std::string_view n = name();
        if (n.empty() || open_.empty() || out_.elements[size_t(open_.back())].name != n) return false;
        skip_space();
        if (p_ == e_ || *p_ != '>') return false;
        ++p_;
        open_.pop_back();
        last_child_.pop_back();
        return true;
    }

    // `lt` is the tag's '<'; p_ is just after it.
    bool start_tag(const char* lt) {
        if (*p_ == '?' || *p_ == '!') return false;  // instructions, comments, CDATA, DOCTYPE
        const size_t name_offset = size_t(p_ - b_);
        const std::string_view n = name();
        if (n.empty()) return false;
        // Attributes: each after white space, name="value" or name='value'.
        bool self_closing = false;
        for (;;) {
            const char* before = p_;
            skip_space();
            if (p_ == e_) return false;
            if (*p_ == '>') {
                ++p_;
                break;
            }
            if (*p_ == '/') {
                if (p_ + 1 == e_ || p_[1] != '>') return false;
                p_ += 2;
                self_closing = true;
                break;
            }
            if (p_ == before || name().empty()) return false;
            skip_space();
            if (p_ == e_ || *p_ != '=') return false;
            ++p_;
            skip_space();
            if (p_ == e_ || (*p_ != '"' && *p_ != '\'')) return false;
            const char quote = *p_++;
            const char* close = static_cast<const char*>(std::memchr(p_, quote, size_t(e_ - p_)));
            if (!close) return false;
            const std::string_view value(p_, size_t(close - p_));
            if (value.find_first_of("<&") != std::string_view::npos) return false;
            p_ = close + 1;
        }

        const int index = int(out_.elements.size());
        OutlineElement element;
        element.name = n;
        element.offset = name_offset;
        if (open_.empty()) {
            out_.root = index;
        } else {
            const int parent = open_.back();
            int& last = last_child_.back();
            if (last < 0)
                out_.elements[size_t(parent)].first_child = index;
            else
                out_.elements[size_t(last)].next_sibling = index;
            last = index;
            const char* list = part_list(n);
            if (list && out_.elements[size_t(parent)].name == list) {
                element.part_begin = size_t(lt - b_);
                if (!self_closing && !skip_part(n)) return false;
                element.part_end = size_t(p_ - b_);
                out_.elements.push_back(element);
                return true;
            }
        }
        out_.elements.push_back(element);
        if (!self_closing) {
            open_.push_back(index);
            last_child_.push_back(-1);
        }
        return true;
    }

    // Past the end tag of the part `n` whose start tag ends at p_: the first
    // "</n" followed by '>' (after optional white space). Parts do not nest
    // in PMXML; where a hostile file nests them, or hides an end tag in a
    // comment, the part's text is not well-formed on its own and its
    // fragment parse fails, which sends the whole file to pugixml.
    bool skip_part(std::string_view n) {
        needle_.assign("</");
        needle_.append(n);
        for (;;) {
            const char* hit = find_end_tag(p_, e_, needle_);
            if (!hit) return false;
            p_ = hit + needle_.size();
            const char* q = p_;
            while (q < e_ && is_space(*q)) ++q;
            if (q < e_ && *q == '>') {
                p_ = q + 1;
                return true;
            }
        }
    }

    const char* b_;
    const char* p_;
    const char* e_;
    PmxmlOutline& out_;
    std::vector<int> open_;        // elements whose end tag is still to come, outermost first
    std::vector<int> last_child_;  // of each open element, -1 before its first
    std::string needle_;
};

}  // namespace

bool outline_pmxml(std::string_view text, PmxmlOutline& out) { return Outliner(text, out).run(); }

}  // namespace mbx_files
