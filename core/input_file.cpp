#include "core/input_file.h"

#include <sys/stat.h>

#include <algorithm>
#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <vector>

#include "core/heartbeat.h"
#include "core/text_format.h"

namespace mbx {

uint64_t input_size_limit() {
    constexpr uint64_t kMiB = 1024 * 1024, kDefault = 2048 * kMiB;
    const char* given = std::getenv("MBX_INPUT_LIMIT_MB");
    if (!given || !*given) return kDefault;
    char* end = nullptr;
    const double mib = std::strtod(given, &end);
    // (a limit that cannot be read leaves the default: the input is then
    // still refused above it, never read without a bound)
    if (end == given || *end != '\0' || !(mib > 0) || mib > 1e9) return kDefault;
    return uint64_t(mib * double(kMiB));
}

namespace {

std::string size_text(uint64_t bytes) {
    const double mib = double(bytes) / (1024.0 * 1024.0);
    return mib >= 1 ? formatted("%.4g MiB", mib) : std::to_string(bytes) + " bytes";
}

}  // namespace

std::string input_file_problem(const std::string& path, uint64_t* size) {
    struct stat st {};
    if (::stat(path.c_str(), &st) != 0)
        return errno == ENOENT ? "cannot open it: no such file" : std::string("cannot open it: ") + std::strerror(errno);
    if (!S_ISREG(st.st_mode)) {
        const char* what = S_ISDIR(st.st_mode)    ? "a directory"
                           : S_ISFIFO(st.st_mode) ? "a pipe"
                           : S_ISCHR(st.st_mode)  ? "a character device"
                           : S_ISBLK(st.st_mode)  ? "a block device"
                           : S_ISSOCK(st.st_mode) ? "a socket"
                                                  : "not a file";
        return std::string("not a regular file (") + what + "): only files are read";
    }
    if (size) *size = uint64_t(st.st_size);
    const uint64_t limit = input_size_limit();
    if (uint64_t(st.st_size) > limit)
        return "larger (" + size_text(uint64_t(st.st_size)) + ") than the input limit of " + size_text(limit) +
               " (MBX_INPUT_LIMIT_MB raises it)";
    return "";
}

bool read_input_pieces(const std::string& path, const std::function<void(std::string_view)>& piece, std::string& why) {
    uint64_t size = 0;
    why = input_file_problem(path, &size);
    if (!why.empty()) return false;
    std::ifstream in(path, std::ios::binary);
    if (!in) {
        why = std::string("cannot open it: ") + std::strerror(errno);
        return false;
    }
    // Pieces of 4 MiB (a small file in one): a run reading a record of
    // gigabytes still reports, and its reader need not hold it whole. No more
    // than the limit is read, should the file grow while it is read.
    const uint64_t limit = input_size_limit();
    std::vector<char> buffer(size_t(std::min<uint64_t>(uint64_t(1) << 22, size + 4096)));
    uint64_t total = 0;
    while (in.read(buffer.data(), std::streamsize(buffer.size())) || in.gcount() > 0) {
        const uint64_t n = uint64_t(in.gcount());
        if (total + n > limit) {
            why = "it grew past the input limit of " + size_text(limit) + " while it was read";
            return false;
        }
        total += n;
        heartbeat();
        piece(std::string_view(buffer.data(), size_t(n)));
    }
    return true;
}

bool read_input_file(const std::string& path, std::string& out, std::string& why) {
    out.clear();
    uint64_t size = 0;
    if (input_file_problem(path, &size).empty()) out.reserve(size_t(size));
    if (read_input_pieces(path, [&](std::string_view piece) { out.append(piece); }, why)) return true;
    out.clear();
    return false;
}

}  // namespace mbx
