// Text helpers every file adapter needs: names, units and file extensions are
// compared without regard to ASCII case.
#pragma once
#include <cctype>
#include <string>
#include <string_view>

namespace mbx_files {

inline std::string lower_case(std::string_view s) {
    std::string out(s);
    for (char& c : out) c = char(std::tolower(static_cast<unsigned char>(c)));
    return out;
}

}  // namespace mbx_files
