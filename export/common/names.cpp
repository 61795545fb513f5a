#include "export/common/names.h"

#include <algorithm>
#include <array>
#include <cctype>

namespace mbx {

namespace {
std::string lower(std::string_view s) {
    std::string out(s);
    for (char& c : out) c = char(std::tolower(static_cast<unsigned char>(c)));
    return out;
}
bool word_char(char c) { return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9'); }
}  // namespace

std::string sanitize_identifier(std::string_view raw, std::string_view fallback) {
    std::string out;
    out.reserve(raw.size());
    for (char c : raw) {
        if (word_char(c)) out += c;
        else if (!out.empty() && out.back() != '_') out += '_';
    }
    while (!out.empty() && out.back() == '_') out.pop_back();
    if (out.empty()) out = std::string(fallback);
    if (out[0] >= '0' && out[0] <= '9') out.insert(out.begin(), '_');
    return out;
}

void NameTable::reserve(std::string_view name) { used_.insert(lower(name)); }

bool NameTable::taken(std::string_view name) const { return used_.count(lower(name)) != 0; }

std::string NameTable::claim(std::string_view base) {
    std::string name(base);
    for (int k = 2; taken(name); ++k) name = std::string(base) + "_" + std::to_string(k);
    reserve(name);
    return name;
}

bool is_modelica_keyword(std::string_view w) {
    static const std::array<std::string_view, 64> keywords = {
        "algorithm", "and",      "annotation", "block",     "break",       "class",     "connect",   "connector",
        "constant",  "constrainedby", "der",   "discrete",  "each",        "else",      "elseif",    "elsewhen",
        "encapsulated", "end",   "enumeration", "equation", "expandable",  "extends",   "external",  "false",
        "final",     "flow",     "for",        "function",  "if",          "import",    "impure",    "in",
        "initial",   "inner",    "input",      "loop",      "model",       "not",       "operator",  "or",
        "outer",     "output",   "package",    "parameter", "partial",     "protected", "public",    "pure",
        "record",    "redeclare", "replaceable", "return",  "stream",      "then",      "true",      "type",
        "when",      "while",    "within",     "time",      "Real",        "Integer",   "Boolean",   "String"};
    return std::find(keywords.begin(), keywords.end(), w) != keywords.end();
}

}  // namespace mbx
