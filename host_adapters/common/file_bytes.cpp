#include "host_adapters/common/file_bytes.h"

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>

#include "core/input_file.h"
#include "host_adapters/common/file_error.h"

namespace mbx_files {

FileBytes read_file_bytes(const std::string& path) {
    std::error_code ec;
    if (const std::string why = mbx::input_file_problem(path); !why.empty()) throw FileError(path, 0, why);
    std::ifstream in(path, std::ios::binary);
    if (!in) throw FileError(path, 0, std::string("cannot open the file: ") + std::strerror(errno));
    const uintmax_t size = std::filesystem::file_size(path, ec);
    if (ec) throw FileError(path, 0, "cannot read the file: " + ec.message());
    FileBytes out;
    out.data.reset(new char[size_t(size) + 1]);
    out.size = size_t(size);
    in.read(out.data.get(), std::streamsize(size));
    if (size_t(in.gcount()) != size) throw FileError(path, 0, "cannot read the file");
    out.data[out.size] = '\0';
    return out;
}

}  // namespace mbx_files
