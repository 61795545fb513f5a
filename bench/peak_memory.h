// Peak resident memory of a stretch of work (Linux): reset the kernel's
// high-water mark, run, read VmHWM. Shared by the benchmarks.
#pragma once
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <string>

namespace mbx_bench {

// A "Vm...:" line of /proc/self/status in kB, -1 if absent.
inline long status_kb(const char* key) {
    std::ifstream in("/proc/self/status");
    std::string line;
    const size_t n = std::strlen(key);
    while (std::getline(in, line))
        if (line.compare(0, n, key) == 0) return std::atol(line.c_str() + n + 1);
    return -1;
}

// Resets VmHWM so it measures only what follows.
inline void reset_peak() {
    std::ofstream clear("/proc/self/clear_refs");
    clear << "5";
}

}  // namespace mbx_bench
