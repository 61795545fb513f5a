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

// A number as a message shows it: six significant figures ("1e+308", not
// std::to_string's 309 digits; "2.5e-07", not "0.000000").
inline std::string readable(double x) { return formatted("%.6g", x); }

}  // namespace mbx
