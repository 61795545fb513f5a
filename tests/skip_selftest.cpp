// The skip policy's own test (docs/testing.md): lint/skip_policy runs each case
// alone and expects the runner's exit code: 77 (a skip) only when nothing
// failed, 1 when a check failed before or beside the skip.
#include "tests/common/doctest_main.h"

#include <string>

namespace {

std::string helper_without_its_file() { throw mbx_test::SkipTest{"no such file (the policy's self-test)"}; }

}  // namespace

TEST_CASE("passes") { CHECK(1 + 1 == 2); }

TEST_CASE("skips") {
    CHECK(1 + 1 == 2);
    MBX_SKIP("the policy's self-test");
}

TEST_CASE("skips from a helper") {
    const std::string path = helper_without_its_file();
    CHECK(path.empty());
}

TEST_CASE("fails then skips") {
    CHECK(1 + 1 == 3);
    MBX_SKIP("the policy's self-test");
}

TEST_CASE("fails then a helper skips") {
    CHECK(1 + 1 == 3);
    (void)helper_without_its_file();
}
