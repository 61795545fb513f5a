// A whole file as bytes ("" when it cannot be read), for tests that compare
// what the SDK wrote. Shared by the test suites.
#pragma once

#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

namespace mbx_test {

inline std::string read_file(const std::filesystem::path& path) {
    std::ifstream in(path, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

}  // namespace mbx_test
