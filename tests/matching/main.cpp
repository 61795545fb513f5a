// The matching tests' own entry point: they link only the file adapter
// library, not the SDK's test support.
#define DOCTEST_CONFIG_IMPLEMENT_WITH_MAIN
#include <doctest/doctest.h>
