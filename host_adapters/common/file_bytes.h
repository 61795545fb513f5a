// A whole input file in a buffer of its own, for the XML readers that parse
// in place (pugixml's offsets are then the file's): only regular files, and
// no zero fill first (a std::string's would touch every page once more
// before the read does).
#pragma once
#include <cstddef>
#include <memory>
#include <string>

namespace mbx_files {

struct FileBytes {
    std::unique_ptr<char[]> data;  // size bytes, and one more for a parser's terminator
    size_t size = 0;
};

// Throws FileError naming `path`: no such file, not a regular file, unreadable.
FileBytes read_file_bytes(const std::string& path);

}  // namespace mbx_files
