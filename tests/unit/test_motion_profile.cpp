// Motion targets: values, velocities and accelerations against the closed
// forms of each interpolation, and bad tables refused with the point named.
#include <doctest/doctest.h>

#include <cmath>
#include <limits>
#include <stdexcept>

#include "core/mechatronics/motion_profile.h"
#include "tests/common/near.h"

namespace MBX_UNITY_ID {

using namespace mbx;

TEST_CASE("motion profile: no motion holds 0, and outside the table the end values hold") {
    CHECK(MotionProfile().at(3.0).position == 0);
    const MotionProfile p({{1, 0.2}, {2, 0.8}}, Interpolation::Linear);
    CHECK(p.at(0).position == 0.2);
    CHECK(p.at(0).velocity == 0);
    CHECK(p.at(5).position == 0.8);
}

TEST_CASE("motion profile: linear segments") {
    const MotionProfile p({{0, 0}, {2, 1}, {3, -1}}, Interpolation::Linear);
    CHECK(p.at(0.5).position == mbx_test::relative(0.25, 1e-6));
    CHECK(p.at(0.5).velocity == mbx_test::relative(0.5, 1e-6));
    CHECK(p.at(2.5).position == mbx_test::within(0.0, 1e-9, "the segment from 1 to -1 crosses zero there"));
    CHECK(p.at(2.5).velocity == mbx_test::relative(-2.0, 1e-6));
}

TEST_CASE("motion profile: steps hold the earlier value until the next point") {
    const MotionProfile p({{0, 1}, {1, 2}, {2, 3}}, Interpolation::Step);
    CHECK(p.at(0.999).position == 1);
    CHECK(p.at(1.0).position == 2);
    CHECK(p.at(1.5).position == 2);
    CHECK(p.at(1.5).velocity == 0);
}

TEST_CASE("motion profile: smooth segments are rest-to-rest quintics") {
    const double T = 2, dq = 0.6;
    const MotionProfile p({{1, 0.1}, {1 + T, 0.1 + dq}}, Interpolation::Smooth);
    // Midpoint: half the travel, peak velocity 15/8 dq/T, zero acceleration.
    const MotionSample mid = p.at(1 + T / 2);
    CHECK(mid.position == mbx_test::relative(0.1 + dq / 2, 1e-6));
    CHECK(mid.velocity == mbx_test::relative(15.0 / 8 * dq / T, 1e-6));
    CHECK(mid.acceleration == mbx_test::within(0, 1e-9, "a profile at rest: zero, within rounding"));
    // Peak acceleration at u = 1/2 - sqrt(3)/6: 10 sqrt(3)/3 dq/T^2.
    const double u = 0.5 - std::sqrt(3.0) / 6;
    CHECK(p.at(1 + u * T).acceleration == mbx_test::relative(10 * std::sqrt(3.0) / 3 * dq / (T * T), 1e-6));
    // At rest at both ends; velocity is the derivative of position.
    CHECK(p.at(1 + 1e-9).velocity == mbx_test::within(0, 1e-9, "a profile at rest: zero, within rounding"));
    CHECK(p.at(1 + T - 1e-9).acceleration == mbx_test::within(0, 1e-7, "1e-9 s before rest: the jerk times 1e-9"));
    const double h = 1e-6, t = 1.7;
    CHECK(p.at(t).velocity == mbx_test::relative((p.at(t + h).position - p.at(t - h).position) / (2 * h), 1e-6));
}

TEST_CASE("motion profile: tables with non-increasing times or non-finite numbers are refused") {
    CHECK_THROWS_WITH_AS(MotionProfile({{0, 0}, {0, 1}}, Interpolation::Linear),
                         "motion point 2: times must increase strictly", std::invalid_argument);
    CHECK_THROWS_WITH_AS(MotionProfile({{0, 0}, {1, std::nan("")}}, Interpolation::Smooth),
                         "motion point 2 is not a finite number", std::invalid_argument);
    Interpolation i;
    CHECK(parse_interpolation("smooth", i));
    CHECK(i == Interpolation::Smooth);
    CHECK_FALSE(parse_interpolation("cubic", i));
}
}  // namespace MBX_UNITY_ID
