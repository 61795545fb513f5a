// The body of every test executable's main.cpp: doctest's runner, and exit
// code 77 (ctest's SKIP_RETURN_CODE, set on every discovered test) when a test
// case skipped (skip.h) and nothing failed.
#pragma once

#define DOCTEST_CONFIG_IMPLEMENT
#include <doctest/doctest.h>

#include "tests/common/skip.h"

int main(int argc, char** argv) {
    doctest::Context context(argc, argv);
    const int status = context.run();
    if (context.shouldExit() || status != 0) return status;
    return mbx_test::skip_reasons().empty() ? 0 : 77;
}
