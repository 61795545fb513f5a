// A fresh directory under the system temp dir, removed with everything in it.
#pragma once
#include <filesystem>
#include <string>

#include <unistd.h>

namespace samples_test {

class TempDir {
public:
    explicit TempDir(const std::string& tag) {
        std::string pattern = (std::filesystem::temp_directory_path() / ("mbx_" + tag + "_XXXXXX")).string();
        if (mkdtemp(pattern.data()) != nullptr) path_ = pattern;
    }
    ~TempDir() {
        std::error_code ignored;
        if (!path_.empty()) std::filesystem::remove_all(path_, ignored);
    }
    TempDir(const TempDir&) = delete;
    TempDir& operator=(const TempDir&) = delete;
    const std::string& path() const { return path_; }

private:
    std::string path_;
};

}  // namespace samples_test
