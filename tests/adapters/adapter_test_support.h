// Helpers shared by the file adapter tests: temporary directories, text
// surgery on hand-written PMXML, the real files' location.
#pragma once

#include <unistd.h>

#include <atomic>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <system_error>

#include <doctest/doctest.h>

#include "../common/temp_dir.h"
#include "../common/file_text.h"

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

// shared/data/pmxml beside the repository; "" (and a message) when absent.
inline std::string pmxml_data_dir() {
    const std::filesystem::path dir = std::filesystem::path(MBX_SHARED_DIR) / "data" / "pmxml";
    std::error_code ec;
    if (!std::filesystem::is_directory(dir, ec)) {
        MESSAGE("skipped: the real PMXML files are not at " << dir.string());
        return {};
    }
    return dir.string();
}

}  // namespace atest
