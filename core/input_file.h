// Outside input read whole (docs/limits.md, "Input files"): only regular
// files, and none larger than the stated limit. A FIFO, a device such as
// /dev/zero or an endless pipe would otherwise be read until memory runs
// out, and a directory would read as an empty file.
#pragma once
#include <cstdint>
#include <functional>
#include <string>
#include <string_view>

namespace mbx {

// The largest input file read whole, in bytes: MBX_INPUT_LIMIT_MB (MiB) from
// the environment, or 2048 MiB.
uint64_t input_size_limit();

// Why `path` cannot be read whole ("" when it can): no such file, not a
// regular file (saying what it is), or larger than the limit (both sizes
// named). `size` gets its size when it can.
std::string input_file_problem(const std::string& path, uint64_t* size = nullptr);

// `path` whole into `out`; false with `why` (as above, or the read's
// failure) when it cannot be read. Never reads past the limit, even from a
// file that grows while it is read.
bool read_input_file(const std::string& path, std::string& out, std::string& why);

// The same in pieces of a few MiB, each handed to `piece` as it is read, for
// a reader that keeps only what it makes of them (a record's numbers).
bool read_input_pieces(const std::string& path, const std::function<void(std::string_view)>& piece, std::string& why);

}  // namespace mbx
