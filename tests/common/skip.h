// A test that cannot run says why and is reported as skipped, never as passed
// (docs/testing.md). MBX_SKIP("no " << path) prints the reason, records it and
// returns from the test case; from a helper that returns a value, throw
// SkipTest (shared_data.h does). The runner (doctest_main.h) then exits with
// 77, which ctest reports as a skip (SKIP_RETURN_CODE), but only when every
// check that did run passed: a skip never hides a failure.
#pragma once

#include <cstdio>
#include <sstream>
#include <string>
#include <vector>

namespace mbx_test {

inline std::vector<std::string>& skip_reasons() {
    static std::vector<std::string> reasons;
    return reasons;
}

// Thrown where a test cannot go on and cannot return (a helper's value).
struct SkipTest {
    std::string reason;
};

inline void record_skip(const std::string& reason) {
    std::printf("MBX_SKIPPED: %s\n", reason.c_str());
    std::fflush(stdout);
    skip_reasons().push_back(reason);
}

}  // namespace mbx_test

// Records the skip and returns from the enclosing test case (or helper).
#define MBX_SKIP(reason)                          \
    do {                                          \
        std::ostringstream mbx_skip_reason_;      \
        mbx_skip_reason_ << reason;               \
        mbx_test::record_skip(mbx_skip_reason_.str()); \
        return;                                   \
    } while (0)

// Records that part of a test case did not run (its other checks did).
#define MBX_SKIP_PART(reason)                     \
    do {                                          \
        std::ostringstream mbx_skip_reason_;      \
        mbx_skip_reason_ << reason;               \
        mbx_test::record_skip(mbx_skip_reason_.str()); \
    } while (0)
