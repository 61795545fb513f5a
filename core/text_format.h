// Numbers in finding messages, printf-formatted (up to three), shared by the
// checks that word their figures with a format of their own.
#pragma once
#include <cstdio>
#include <string>

namespace mbx {

inline std::string formatted(const char* format, double a, double b = 0, double c = 0) {
    char buf[200];
    std::snprintf(buf, sizeof buf, format, a, b, c);
    return buf;
}

}  // namespace mbx
