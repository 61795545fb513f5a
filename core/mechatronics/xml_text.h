// What the mechatronics XML readers (object library, drive descriptions)
// share: strict, locale-independent numbers and source lines of nodes, so
// every error can name the line a user has to fix.
#pragma once
#include <pugixml.hpp>

#include <string>
#include <vector>

namespace mbx {

// A whole, finite number ("1e-3", "+2"; surrounding blanks allowed).
bool parse_xml_number(const std::string& text, double& out);

// Exactly `count` such numbers separated by blanks ("0 0.01 -2e-3").
bool parse_xml_numbers(const std::string& text, size_t count, double* out);

// Line of a node, from its byte offset (pugixml keeps offsets, not lines).
class XmlLines {
public:
    explicit XmlLines(const std::string& text);
    int line(const pugi::xml_node& n) const;
    int line_at(ptrdiff_t offset) const;

private:
    std::vector<size_t> newlines_;
};

// Reads a whole file (core/input_file.h: a regular file within the input
// limit); false when it cannot, with the reason in `why` when given.
bool read_text_file(const std::string& path, std::string& out, std::string* why = nullptr);

}  // namespace mbx
