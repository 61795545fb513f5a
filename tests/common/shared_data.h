// Files of ../shared/data (real exports and measured records) that tests read.
// A test whose file is missing is skipped with the path it looked for
// (docs/testing.md); in CI, where ../shared is present, that skip fails the run.
#pragma once

#include <filesystem>
#include <string>

#include "tests/common/skip.h"

#ifndef MBX_SHARED_DATA
#error "a test target that reads ../shared/data defines MBX_SHARED_DATA"
#endif

namespace mbx_test {

// The path of `relative` (a file or a folder) under ../shared/data; throws
// SkipTest when it is not there.
inline std::string shared_data(const std::string& relative) {
    const std::string path = std::string(MBX_SHARED_DATA) + "/" + relative;
    std::error_code ec;
    if (!std::filesystem::exists(path, ec)) throw SkipTest{"no " + path + " (../shared beside the repository)"};
    return path;
}

}  // namespace mbx_test
