#include "vrml_ast.h"

#include <algorithm>

namespace mbx_files::vrml {

int Value::line_of_number(size_t index) const {
    // The last line change at or before `index`.
    const auto after = std::upper_bound(number_lines.begin(), number_lines.end(), index,
                                        [](size_t i, const std::pair<uint32_t, int>& mark) { return i < mark.first; });
    return after == number_lines.begin() ? line : std::prev(after)->second;
}

}  // namespace mbx_files::vrml
