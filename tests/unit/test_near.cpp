// The suite's comparison helpers (tests/common/near.h) fail where doctest's
// Approx passed: on zero and on a doubled value, whatever the magnitude.
#include <doctest/doctest.h>

#include <cmath>

#include "tests/common/near.h"

namespace MBX_UNITY_ID {

using mbx_test::relative;
using mbx_test::relative_to;
using mbx_test::within;

TEST_CASE("near: a relative check fails on zero and on a doubled value at every magnitude") {
    for (double truth : {3.5e-4, 1e-5, 0.15, 2.0, 8200.0, -0.35}) {
        CAPTURE(truth);
        for (double fraction : {1e-12, 1e-6, 0.05, 0.49}) {
            CAPTURE(fraction);
            CHECK(truth == relative(truth, fraction));
            CHECK(truth * (1 + 0.99 * fraction) == relative(truth, fraction));
            CHECK_FALSE(truth * (1 + 1.01 * fraction) == relative(truth, fraction));
            CHECK_FALSE(0.0 == relative(truth, fraction));
            CHECK_FALSE(2 * truth == relative(truth, fraction));
            CHECK_FALSE(NAN == relative(truth, fraction));
        }
    }
}

TEST_CASE("near: doctest's approximate comparison accepted what relative() refuses (the defect it replaces)") {
    // doctest's approximate comparison with epsilon 0.05 admits |x - 3.5e-4| < 0.05 (1 + 3.5e-4): zero passes.
    const double truth = 3.5e-4, epsilon = 0.05;
    CHECK(std::abs(0.0 - truth) < epsilon * (1 + truth));
    CHECK_FALSE(0.0 == relative(truth, epsilon));
}

TEST_CASE("near: checks that could never fail, or never pass, are refused") {
    CHECK_FALSE(1.0 == relative(1.0, 0.5));   // 0.5 and above lets a doubled value through
    CHECK_FALSE(1.0 == relative(1.0, 0.0));
    CHECK_FALSE(0.0 == relative(0.0, 1e-6));  // a zero expectation needs within() and its reason
    CHECK_FALSE(1.0 == relative(NAN, 1e-6));
    CHECK_FALSE(0.0 == within(0.0, 1e-9, ""));
    CHECK_FALSE(0.0 == within(0.0, -1.0, "negative"));
    CHECK_FALSE(0.0 == relative_to(0.0, 0.0, 1e-6));
}

TEST_CASE("near: relative_to judges a component on its vector's scale, within on its stated tolerance") {
    CHECK(1e-13 == relative_to(0.0, 1.0, 1e-12));
    CHECK_FALSE(2e-12 == relative_to(0.0, 1.0, 1e-12));
    CHECK_FALSE(0.0 == relative_to(0.3, 1.0, 0.1));
    CHECK(-4e-10 == within(0.0, 1e-9, "rounding"));
    CHECK_FALSE(2e-9 == within(0.0, 1e-9, "rounding"));
    CHECK_FALSE(INFINITY == within(0.0, 1e300, "huge"));
}

}  // namespace MBX_UNITY_ID
