#include "whole_file.h"

#include <sys/stat.h>
#include <unistd.h>

#include <cstdio>
#include <fstream>
#include <stdexcept>

namespace mbx_samples {

void write_whole_file(const std::string& path, const std::string& text) {
    const std::string temp = path + ".tmp." + std::to_string(::getpid());
    {
        std::ofstream out(temp, std::ios::binary);
        out << text;
        if (!out.flush()) {
            std::remove(temp.c_str());
            throw std::runtime_error("cannot write " + path);
        }
    }
    if (std::rename(temp.c_str(), path.c_str()) != 0) {
        std::remove(temp.c_str());
        throw std::runtime_error("cannot write " + path);
    }
}

void make_directory(const std::string& path) {
    struct stat st {};
    if (::stat(path.c_str(), &st) == 0 && S_ISDIR(st.st_mode)) return;
    if (::mkdir(path.c_str(), 0755) != 0) throw std::runtime_error("cannot create the directory " + path);
}

}  // namespace mbx_samples
