// Byte offsets to 1-based line numbers, so that every message about an XML
// element can say where it is (pugixml only knows offsets).
//
// The index must be built from the text before pugixml parses it in place
// (parsing overwrites some newlines with terminators). A 100k-part export has
// about 12 million lines, so line starts are stored in 32 bits, relative to
// the 4 GiB segment they fall in: a quarter of the memory of size_t offsets.
#pragma once
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <string_view>
#include <vector>
#if defined(__SSE2__)
#include <emmintrin.h>
#endif

namespace mbx_files {

class LineIndex {
public:
    LineIndex() {
        segment_first_.push_back(0);
        add(0);
    }
    explicit LineIndex(std::string_view text) : LineIndex() { append(text); }

    // Indexes the next `text.size()` bytes of the text. A reader calls this
    // on each chunk it reads while the chunk is still in the cache, rather
    // than scanning hundreds of megabytes again afterwards.
    void append(std::string_view text) {
        // Many bytes at a time, looking closer only where there is a newline:
        // a byte-by-byte loop cost a third of parsing the XML.
        const char* const p = text.data();
        const size_t n = text.size(), base = indexed_;
        size_t i = 0;
#if defined(__SSE2__)
        const __m128i newline = _mm_set1_epi8('\n');
        for (; i + 16 <= n; i += 16) {
            const __m128i bytes = _mm_loadu_si128(reinterpret_cast<const __m128i*>(p + i));
            for (unsigned mask = unsigned(_mm_movemask_epi8(_mm_cmpeq_epi8(bytes, newline))); mask; mask &= mask - 1)
                add(base + i + size_t(__builtin_ctz(mask)) + 1);
        }
#else
        for (; i + 8 <= n; i += 8) {
            uint64_t word;
            std::memcpy(&word, p + i, 8);
            if (!has_newline(word)) continue;
            for (size_t k = i; k < i + 8; ++k)
                if (p[k] == '\n') add(base + k + 1);
        }
#endif
        for (; i < n; ++i)
            if (p[i] == '\n') add(base + i + 1);
        indexed_ += n;
    }

    // Line holding byte `offset`; 0 for a negative (unknown) offset.
    int line_of(std::ptrdiff_t offset) const {
        if (offset < 0) return 0;
        const size_t at = size_t(offset);
        // Readers ask mostly in file order, a few lines past the previous
        // answer: gallop forward from there rather than search all the lines
        // (in a text under 4 GiB, where stored starts are plain offsets).
        if (segment_first_.size() == 1 && segment_of(at) == 0 && hint_ > 0 && starts_[hint_ - 1] <= at) {
            const size_t n = starts_.size();
            size_t lo = hint_, hi = hint_, step = 1;  // starts_[lo - 1] <= at throughout
            while (hi < n && starts_[hi] <= at) {
                lo = hi + 1;
                hi += step;
                step *= 2;
            }
            hi = std::min(hi, n);  // hi == n or starts_[hi] > at
            const auto it = std::upper_bound(starts_.begin() + std::ptrdiff_t(lo),
                                             starts_.begin() + std::ptrdiff_t(hi), uint32_t(at));
            return int(hint_ = size_t(it - starts_.begin()));
        }
        const size_t segments = segment_first_.size();
        const size_t segment = std::min(segment_of(at), segments - 1);
        // Lines starting in earlier segments all start before `at`.
        const auto first = starts_.begin() + std::ptrdiff_t(segment_first_[segment]);
        const auto last = segment + 1 < segments ? starts_.begin() + std::ptrdiff_t(segment_first_[segment + 1])
                                                 : starts_.end();
        const auto it = segment_of(at) > segment ? last : std::upper_bound(first, last, uint32_t(at));
        hint_ = size_t(it - starts_.begin());
        return int(hint_);
    }

private:
    // Whether any byte of `word` is '\n' (exact: no carries cross bytes).
    [[maybe_unused]] static bool has_newline(uint64_t word) {
        const uint64_t x = word ^ 0x0a0a0a0a0a0a0a0aULL;  // '\n' bytes become 0
        const uint64_t low7 = 0x7f7f7f7f7f7f7f7fULL;
        return (~(((x & low7) + low7) | x) & ~low7) != 0;
    }

    static size_t segment_of(size_t offset) { return size_t(uint64_t(offset) >> 32); }

    void add(size_t start) {
        if (start >= next_segment_) {
            while (segment_of(start) + 1 > segment_first_.size()) segment_first_.push_back(starts_.size());
            next_segment_ = uint64_t(segment_first_.size()) << 32;
        }
        starts_.push_back(uint32_t(start));
    }

    std::vector<uint32_t> starts_;       // offset of each line's first byte, modulo 2^32
    std::vector<size_t> segment_first_;  // index in starts_ of the first line starting in segment k
    size_t indexed_ = 0;                 // bytes appended so far
    mutable size_t hint_ = 0;            // the previous answer
    uint64_t next_segment_ = 0;          // where the segment after the last one starts
};

}  // namespace mbx_files
