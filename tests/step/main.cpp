// The one translation unit per test executable that holds the runner.
#include "tests/common/doctest_main.h"
