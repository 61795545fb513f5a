// Shared by the fuzz targets: the fuzzer's bytes as text. Readers take
// std::string / std::string_view, so embedded NULs and invalid UTF-8 reach
// them as they would from a damaged file.
#pragma once
#include <cstddef>
#include <cstdint>
#include <string>

inline std::string fuzz_text(const uint8_t* data, size_t size) {
    return std::string(reinterpret_cast<const char*>(data), size);
}

// Relative Inline urls and library file names resolve against this folder,
// which does not exist, so a run never depends on what lies on the disk
// (absolute names still reach the file system, as they would for a user).
constexpr const char* kFuzzDir = "/nonexistent-mbx-fuzz";
