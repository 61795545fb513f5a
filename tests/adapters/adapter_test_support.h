// Helpers shared by the file adapter tests: temporary directories, text
// surgery on hand-written PMXML, the real files' location.
#pragma once

#include <unistd.h>

#include <atomic>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <system_error>

#include <doctest/doctest.h>

#include "../common/temp_dir.h"
#include "../common/file_text.h"
#include "tests/common/skip.h"
#include "tests/common/shared_data.h"

namespace atest {

using mbx_test::TempDir;

inline void write_file(const std::string& path, const std::string& text) {
    std::ofstream out(path, std::ios::binary);
    out << text;
    REQUIRE(out.good());
}

inline std::string read_file(const std::string& path) { return mbx_test::read_file(path); }

// 1-based line of the first occurrence of `needle`; fails the test if absent.
inline int line_of(const std::string& text, const std::string& needle) {
    const size_t at = text.find(needle);
    REQUIRE_MESSAGE(at != std::string::npos, "'" << needle << "' not in the text");
    int line = 1;
    for (size_t i = 0; i < at; ++i) line += text[i] == '\n';
    return line;
}

// `text` with the only occurrence of `from` replaced by `to`.
inline std::string replace_once(std::string text, const std::string& from, const std::string& to) {
    const size_t at = text.find(from);
    REQUIRE_MESSAGE(at != std::string::npos, "'" << from << "' not in the text");
    REQUIRE_MESSAGE(text.find(from, at + 1) == std::string::npos, "'" << from << "' occurs more than once");
    return text.replace(at, from.size(), to);
}

// Mutations of a text for the readers' robustness tests: each of 1 to
// `max_edits` edits erases a stretch, inserts one of `tokens`, overwrites a
// byte, or (`last`) applies the caller's own edit at a random place.
// Deterministic for a seed (xorshift64).
class Mutator {
public:
    explicit Mutator(uint64_t seed) : state_(seed) {}
    uint64_t next() {
        state_ ^= state_ << 13;
        state_ ^= state_ >> 7;
        state_ ^= state_ << 17;
        return state_;
    }
    template <size_t N, class Last>
    std::string mutate(std::string text, const char* const (&tokens)[N], int max_edits, size_t max_erase, Last last) {
        const int edits = 1 + int(next() % uint64_t(max_edits));
        for (int e = 0; e < edits; ++e) {
            const size_t at = size_t(next() % text.size());
            switch (next() % 4) {
                case 0:
                    text.erase(at, 1 + next() % max_erase);
                    break;
                case 1:
                    text.insert(at, tokens[next() % N]);
                    break;
                case 2:
                    text[at] = char(next() % 256);
                    break;
                default:
                    last(text, at);
                    break;
            }
            if (text.empty()) text = "<";
        }
        return text;
    }

private:
    uint64_t state_;
};

// shared/data/pmxml beside the repository; the test is skipped without it.
inline std::string pmxml_data_dir() {
    return mbx_test::shared_data("pmxml");
}

}  // namespace atest
