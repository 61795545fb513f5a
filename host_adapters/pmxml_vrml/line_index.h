// Byte offsets to 1-based line numbers, so that every message about an XML
// element can say where it is (pugixml only knows offsets).
#pragma once
#include <algorithm>
#include <cstddef>
#include <string_view>
#include <vector>

namespace mbx_files {

class LineIndex {
public:
    explicit LineIndex(std::string_view text) {
        starts_.push_back(0);
        for (size_t i = 0; i < text.size(); ++i)
            if (text[i] == '\n') starts_.push_back(i + 1);
    }
    // Line holding byte `offset`; 0 for a negative (unknown) offset.
    int line_of(std::ptrdiff_t offset) const {
        if (offset < 0) return 0;
        const auto it = std::upper_bound(starts_.begin(), starts_.end(), size_t(offset));
        return int(it - starts_.begin());
    }

private:
    std::vector<size_t> starts_;  // offset of the first byte of each line
};

}  // namespace mbx_files
