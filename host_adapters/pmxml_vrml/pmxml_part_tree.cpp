#include "pmxml_part_tree.h"

#if defined(__SSE2__)
#include <emmintrin.h>
#endif


namespace mbx_files {

using xml_subset::blank;
using xml_subset::is_space;
using xml_subset::name_char;
using xml_subset::name_start;

namespace {

// Bytes readable past the part's end (zeros), so the search below may load
// whole 16-byte blocks.
constexpr size_t kPadding = 16;

// The first '<' in [p, e), or null. Text between tags is short (a number
// list, a quoted name, a line break and indentation): memchr's call cost
// more than the search.
char* find_tag(char* p, char* e) {
#if defined(__SSE2__)
    const __m128i lt = _mm_set1_epi8('<');
    for (; p < e; p += 16) {
        const int hits = _mm_movemask_epi8(_mm_cmpeq_epi8(_mm_loadu_si128(reinterpret_cast<const __m128i*>(p)), lt));
        if (hits) {
            char* at = p + __builtin_ctz(unsigned(hits));
            return at < e ? at : nullptr;
        }
    }
    return nullptr;
#else
    return static_cast<char*>(std::memchr(p, '<', size_t(e - p)));
#endif
}

}  // namespace

bool parse_part(std::string_view part, size_t offset, const xml_subset::Conversions& conversions, PartTree& tree) {
    tree.elements.clear();
    tree.attributes.clear();
    tree.text.resize(part.size() + 1 + kPadding);
    std::memcpy(tree.text.data(), part.data(), part.size());
    std::memset(tree.text.data() + part.size(), 0, 1 + kPadding);
    char* const b = tree.text.data();
    char* const e = b + part.size();
    char* p = b;
    std::vector<int> open, last_child;  // as in the outline
    bool closed = false;

    // A name at p, ended in place; `after` is the character it replaced.
    size_t name_length = 0;
    const auto name = [&](char& after) -> const char* {
        if (p == e || !name_start(*p)) return nullptr;
        const char* start = p;
        while (p < e && name_char(*p)) ++p;
        name_length = size_t(p - start);
        after = *p;  // the text's own NUL at e if the name runs to the end
        *p = '\0';
        if (p < e) ++p;
        return start;
    };
    const auto skip_space = [&] {
        while (p < e && is_space(*p)) ++p;
    };

    while (p < e) {
        char* lt = *p == '<' ? p : find_tag(p, e);
        const std::string_view segment(p, size_t((lt ? lt : e) - p));
        if (!segment.empty() && !blank(segment)) {
            if (open.empty() || conversions.in(segment)) return false;
            PartTree::Element& el = tree.elements[size_t(open.back())];
            if (!*el.text) {
                el.text = p;
                if (lt) *lt = '\0';
            }
        }
        if (!lt) break;
        if (closed) return false;  // more after the part's end tag
        p = lt + 1;
        if (p == e) return false;
        if (*p == '/') {
            ++p;
            const char* start = p;
            while (p < e && name_char(*p)) ++p;
            const std::string_view n(start, size_t(p - start));
            if (n.empty() || open.empty()) return false;
            const PartTree::Element& opened = tree.elements[size_t(open.back())];
            if (n.size() != opened.name_length || std::memcmp(n.data(), opened.name, n.size()) != 0) return false;
            skip_space();
            if (p == e || *p != '>') return false;
            ++p;
            tree.elements[size_t(open.back())].subtree_end = int(tree.elements.size());
            open.pop_back();
            last_child.pop_back();
            closed = open.empty();
            continue;
        }
        if (*p == '!' || *p == '?') return false;
        PartTree::Element el;
        char after = 0;
        el.name = name(after);
        if (!el.name) return false;
        el.name_length = name_length;
        el.offset = std::ptrdiff_t(offset) + (el.name - b);
        el.first_attribute = int(tree.attributes.size());
        bool self_closing = false;
        if (after == '/' || after == '>') {
            if (after == '/') {
                if (p == e || *p != '>') return false;
                ++p;
                self_closing = true;
            }
        } else {
            if (!is_space(after)) return false;
            for (;;) {
                skip_space();
                if (p == e) return false;
                if (*p == '>') {
                    ++p;
                    break;
                }
                if (*p == '/') {
                    if (p + 1 == e || p[1] != '>') return false;
                    p += 2;
                    self_closing = true;
                    break;
                }
                char attribute_after = 0;
                const char* attribute_name = name(attribute_after);
                if (!attribute_name) return false;
                if (is_space(attribute_after)) {
                    skip_space();
                    if (p == e || *p != '=') return false;
                    ++p;
                } else if (attribute_after != '=') {
                    return false;
                }
                skip_space();
                if (p == e || (*p != '"' && *p != '\'')) return false;
                const char quote = *p++;
                char* close = static_cast<char*>(std::memchr(p, quote, size_t(e - p)));
                if (!close) return false;
                // pugixml turns tabs and line feeds in values into spaces; none here.
                if (std::string_view(p, size_t(close - p)).find_first_of("<&\t\n\r") != std::string_view::npos)
                    return false;
                *close = '\0';
                tree.attributes.push_back({attribute_name, p});
                p = close + 1;
                if (p < e && !is_space(*p) && *p != '/' && *p != '>') return false;
            }
        }
        el.attribute_count = int(tree.attributes.size()) - el.first_attribute;
        const int index = int(tree.elements.size());
        if (!open.empty()) {
            int& last = last_child.back();
            if (last < 0)
                tree.elements[size_t(open.back())].first_child = index;
            else
                tree.elements[size_t(last)].next_sibling = index;
            last = index;
        } else if (index != 0) {
            return false;  // a second element beside the part
        }
        tree.elements.push_back(el);
        if (self_closing) {
            tree.elements.back().subtree_end = index + 1;
            closed = open.empty();
        } else {
            open.push_back(index);
            last_child.push_back(-1);
        }
    }
    return closed && open.empty();
}

}  // namespace mbx_files
