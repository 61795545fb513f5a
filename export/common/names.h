// Identifiers for the targets: CAD names collide and carry characters that
// Modelica, MJCF, URDF or a file system reject.
#pragma once
#include <string>
#include <string_view>
#include <unordered_set>

namespace mbx {

// Letters, digits and '_' only (others become '_', runs collapsed, ends
// trimmed); never empty and never starting with a digit ("_" prefix).
std::string sanitize_identifier(std::string_view raw, std::string_view fallback = "unnamed");

// Hands out unique names: the base when free, else base_2, base_3, ...
// Comparison ignores ASCII case, so the names also work as file names on
// case-insensitive file systems.
class NameTable {
public:
    void reserve(std::string_view name);  // make a name unavailable (keywords, fixed names)
    std::string claim(std::string_view base);
    bool taken(std::string_view name) const;

private:
    std::unordered_set<std::string> used_;  // lower-cased
};

bool is_modelica_keyword(std::string_view word);

}  // namespace mbx
