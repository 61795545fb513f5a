// The outline of a PMXML file, found without building its DOM: the elements
// around the parts (the model container, subsystems, the <bodies>, <joints>
// and <grounds> lists, names and statuses) and, for each <Body>, <Ground>
// and <SimpleJoint> in such a list, only where its text begins and ends.
// The reader parses those one at a time as small pugixml fragments, so a
// 100k-part file never has a DOM of its own size (the largest share of
// reading it was building that DOM and walking it again out of the caches).
//
// Only a plain subset of XML is outlined: UTF-8 text (declared or not), no
// byte-order mark, no NUL, and outside the parts no comments, CDATA,
// DOCTYPE, processing instructions, character or entity references or
// carriage returns. For anything else, and anything malformed, outline_pmxml
// returns false and the reader parses the whole file with pugixml as before,
// so results and errors never depend on which way a file was read.
#pragma once
#include <cstddef>
#include <cstring>
#include <string_view>
#include <vector>

namespace mbx_files {

// The characters of the subset, shared with pmxml_part_tree.
namespace xml_subset {
inline bool is_space(char c) { return c == ' ' || c == '\t' || c == '\n' || c == '\r'; }
// ASCII names only; pugixml also takes bytes >= 0x80, which fall back to it.
inline bool name_start(char c) { return (c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z') || c == '_' || c == ':'; }
inline bool name_char(char c) { return name_start(c) || (c >= '0' && c <= '9') || c == '-' || c == '.'; }
inline bool blank(std::string_view s) {
    for (char c : s)
        if (!is_space(c)) return false;
    return true;
}
// Whether text would need pugixml's conversions: a reference ('&') or a
// line end ('\r'). Looked for only where the file holds the character at
// all (one memchr each over the file), so real files, which hold neither,
// are not searched segment by segment.
struct Conversions {
    bool ampersand = false, carriage_return = false;
    bool in(std::string_view s) const {
        return (ampersand && std::memchr(s.data(), '&', s.size())) ||
               (carriage_return && std::memchr(s.data(), '\r', s.size()));
    }
};
}  // namespace xml_subset

struct OutlineElement {
    std::string_view name;
    size_t offset = 0;      // of the name in the text, as pugixml's offset_debug
    std::string_view text;  // the first text child that is not blank, as pugixml's child_value(); "" if none
    int first_child = -1, next_sibling = -1;  // element indices, -1 for none
    // For a part: its whole element, '<' to the end of its end tag, which
    // the outline did not look into. begin == end for other elements.
    size_t part_begin = 0, part_end = 0;
    bool is_part() const { return part_end > part_begin; }
};

struct PmxmlOutline {
    std::vector<OutlineElement> elements;
    int root = -1;
    xml_subset::Conversions conversions;  // what the parts' text must be checked for

    // The first child element of `e` named `name`, -1 if none (as pugixml's child(name)).
    int child(int e, std::string_view name) const {
        if (e < 0) return -1;
        for (int c = elements[size_t(e)].first_child; c >= 0; c = elements[size_t(c)].next_sibling)
            if (elements[size_t(c)].name == name) return c;
        return -1;
    }
};


// The outline of `text` (the file's bytes), or false where the reader must
// parse the whole file with pugixml instead (see above).
bool outline_pmxml(std::string_view text, PmxmlOutline& out);

}  // namespace mbx_files
