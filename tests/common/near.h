// The suite's one way to compare real numbers (docs/testing.md).
//
//   CHECK(x == relative(expected, 0.01));            // |x - expected| <= 1 % of |expected|
//   CHECK(v[k] == relative_to(e[k], e.norm(), 1e-9));  // a component, on its vector's scale
//   CHECK(q == within(0.0, 1e-9, "an angle at rest")); // |q - expected| <= 1e-9, and why
//
// doctest's Approx adds 1 to the magnitude it scales its epsilon by, so on a
// value far below 1 a "relative" epsilon is an absolute tolerance that zero
// passes; the suite therefore does not use it (tests/check_comparisons.sh).
// relative() refuses a zero expectation and fractions of 0.5 or more, so a
// check written with it always fails on zero and on a doubled value; within()
// is for quantities that are naturally absolute (a position at the origin, an
// angle, a residual that should vanish) and asks for the reason.
#pragma once

#include <doctest/doctest.h>

#include <cmath>
#include <sstream>
#include <string>
#include <type_traits>

namespace mbx_test {

struct Near {
    double expected;
    double tolerance;  // absolute, already scaled for relative checks
    double fraction;   // the relative fraction, or NaN for an absolute check
    const char* reason;
    const char* refused;  // why this expectation can never pass, or null

    bool admits(double value) const {
        return refused == nullptr && std::isfinite(value) && std::abs(value - expected) <= tolerance;
    }
};

// |value - expected| <= fraction * |expected|, with 0 < fraction < 0.5.
inline Near relative(double expected, double fraction) {
    Near n{expected, std::abs(expected) * fraction, fraction, nullptr, nullptr};
    if (!(fraction > 0 && fraction < 0.5))
        n.refused = "a relative tolerance must lie in (0, 0.5) so that zero and a doubled value fail";
    else if (!(std::isfinite(expected) && expected != 0))
        n.refused = "a relative comparison needs a finite, non-zero expectation: use within() with a reason";
    return n;
}

// |value - expected| <= fraction * |magnitude|: a component of a vector (or a
// value of a signal) judged against the size of the whole, so a component that
// is zero is compared on the scale its neighbours set.
inline Near relative_to(double expected, double magnitude, double fraction) {
    Near n{expected, std::abs(magnitude) * fraction, fraction, nullptr, nullptr};
    if (!(fraction > 0 && fraction < 0.5))
        n.refused = "a relative tolerance must lie in (0, 0.5) so that zero and a doubled value fail";
    else if (!(std::isfinite(magnitude) && magnitude != 0 && std::isfinite(expected)))
        n.refused = "a relative comparison needs a finite, non-zero magnitude";
    return n;
}

// |value - expected| <= tolerance, for a quantity that is naturally absolute.
inline Near within(double expected, double tolerance, const char* reason) {
    Near n{expected, tolerance, NAN, reason, nullptr};
    if (!(tolerance >= 0 && std::isfinite(tolerance) && std::isfinite(expected)))
        n.refused = "an absolute tolerance must be finite and not negative";
    else if (reason == nullptr || *reason == '\0')
        n.refused = "an absolute tolerance needs its reason";
    return n;
}

template <class T, class = std::enable_if_t<std::is_arithmetic<T>::value>>
bool operator==(T value, const Near& n) {
    return n.admits(double(value));
}
template <class T, class = std::enable_if_t<std::is_arithmetic<T>::value>>
bool operator==(const Near& n, T value) {
    return n.admits(double(value));
}
template <class T, class = std::enable_if_t<std::is_arithmetic<T>::value>>
bool operator!=(T value, const Near& n) {
    return !n.admits(double(value));
}

}  // namespace mbx_test

namespace doctest {
template <>
struct StringMaker<mbx_test::Near> {
    static String convert(const mbx_test::Near& n) {
        std::ostringstream out;
        out.precision(10);
        out << n.expected;
        if (std::isnan(n.fraction))
            out << " +- " << n.tolerance << " (" << (n.reason ? n.reason : "") << ")";
        else
            out << " +- " << 100 * n.fraction << " %";
        if (n.refused) out << " [refused: " << n.refused << "]";
        return String(out.str().c_str());
    }
};
}  // namespace doctest
