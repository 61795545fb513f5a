// Edits of an XML file's own bytes, located through pugixml's offsets into
// the same text: attribute values replaced or added and elements inserted,
// everything else (layout, comments, attribute order and quoting, unknown
// tags, the declaration) left exactly as the user wrote it. pugixml's own
// writer would re-indent and re-quote the whole file.
#pragma once
#include <pugixml.hpp>

#include <string>
#include <string_view>
#include <vector>

namespace mbx {

class XmlSourceEdits {
public:
    // `text` must be the buffer `e` nodes were parsed from (pugixml,
    // encoding_utf8, not in place) and must outlive this object.
    explicit XmlSourceEdits(std::string_view text) : text_(text) {}

    // The value of attribute `name` of element `e` replaced by `value`
    // (escaped here), or the attribute appended after e's last one.
    void set_attribute(const pugi::xml_node& e, const char* name, const std::string& value);
    // `element` (an element's whole text) as e's first child on a line of
    // its own, indented like e's first child (e's indent plus two blanks
    // when it has none).
    void insert_first_child(const pugi::xml_node& e, const std::string& element);

    // 1-based line of e's start tag.
    int line_of(const pugi::xml_node& e) const;
    size_t edit_count() const { return edits_.size(); }
    // The text with every edit made.
    std::string apply() const;

private:
    struct Attribute {
        std::string name;
        size_t value_begin = 0, value_end = 0;  // the value's bytes, quotes excluded
    };
    struct StartTag {
        std::vector<Attribute> attributes;
        size_t name_end = 0;  // just past the element's name
        size_t close = 0;     // the '/' of "/>" or the '>'
        bool self_closing = false;
    };
    struct Edit {
        size_t at = 0, erase = 0;
        std::string insert;
        size_t order = 0;  // for edits at the same place: in the order asked
    };

    StartTag start_tag(const pugi::xml_node& e) const;
    std::string indent_before(size_t at) const;

    std::string_view text_;
    std::vector<Edit> edits_;
};

// Text for an XML attribute value between double quotes.
std::string xml_attribute_text(const std::string& value);

}  // namespace mbx
