// A fresh, uniquely named directory under the system temp dir, removed with
// everything in it when the object goes out of scope. Shared by the test suites.
#pragma once

#include <unistd.h>

#include <atomic>
#include <filesystem>
#include <string>
#include <system_error>

namespace mbx_test {

struct TempDir {
    std::filesystem::path path;

    explicit TempDir(const std::string& tag = "mbx_test") {
        static std::atomic<int> serial{0};
        path = std::filesystem::temp_directory_path() /
               (tag + "_" + std::to_string(::getpid()) + "_" + std::to_string(serial++));
        std::filesystem::remove_all(path);
        std::filesystem::create_directories(path);
    }
    ~TempDir() {
        std::error_code ignored;
        std::filesystem::remove_all(path, ignored);
    }
    TempDir(const TempDir&) = delete;
    TempDir& operator=(const TempDir&) = delete;
    std::string file(const std::string& name) const { return (path / name).string(); }
};

}  // namespace mbx_test
