#include <doctest/doctest.h>

#include "core/translator/mass_properties.h"
#include "assembly_builder.h"
#include "tests/common/near.h"

namespace MBX_UNITY_ID {

using namespace mbx;

TEST_CASE("compound inertia of two parts: parallel axis and tensor rotation, by hand") {
    // Two 1 kg parts at x = -1 and x = +1; the second is turned 90 deg about z,
    // so its own diag(1,2,3) reads diag(2,1,3) in the reference axes. About the
    // common centre (origin) each adds m*d^2 = 1 to Iyy and Izz:
    // diag(1,2,3) + diag(2,1,3) + 2*diag(0,1,1) = diag(3,5,8).
    Pose ref;
    ref.position = Vec3(-1, 0, 0);
    MassAccumulator acc(ref);
    const Mat3 local = Vec3(1, 2, 3).asDiagonal();
    acc.add(1.0, Vec3::Zero(), local, ref);
    Pose second;
    second.position = Vec3(1, 0, 0);
    second.rotation = test::rot_z(M_PI / 2);
    acc.add(1.0, Vec3::Zero(), local, second);
    MassProperties mp = acc.result();
    CHECK(mp.mass == mbx_test::relative(2.0, 1e-6));
    CHECK((mp.com - Vec3(1, 0, 0)).norm() < 1e-12);  // reference frame sits at x = -1
    CHECK((mp.inertia - Mat3(Vec3(3, 5, 8).asDiagonal())).norm() < 1e-12);
}

TEST_CASE("compound inertia expressed in a rotated reference frame") {
    // One rod-like part (Ixx small) along world x, reference frame turned 90 deg
    // about z: in reference axes the rod lies along -y, so its small moment is Iyy.
    Pose ref;
    ref.rotation = test::rot_z(M_PI / 2);
    MassAccumulator acc(ref);
    acc.add(3.0, Vec3(0.5, 0, 0), Vec3(0.1, 2.0, 2.0).asDiagonal(), Pose());
    MassProperties mp = acc.result();
    CHECK((mp.com - Vec3(0, -0.5, 0)).norm() < 1e-12);
    CHECK((mp.inertia - Mat3(Vec3(2.0, 0.1, 2.0).asDiagonal())).norm() < 1e-12);
}

TEST_CASE("offset centres of mass: unequal masses, hand-computed") {
    // 1 kg at (0,0,0) and 3 kg at (0,0,4) (both as point masses): com z = 3;
    // Ixx = Iyy = 1*9 + 3*1 = 12, Izz = 0.
    Pose ref;
    MassAccumulator acc(ref);
    acc.add(1.0, Vec3::Zero(), Mat3::Zero(), Pose());
    Pose p;
    p.position = Vec3(0, 0, 2);
    acc.add(3.0, Vec3(0, 0, 2), Mat3::Zero(), p);
    MassProperties mp = acc.result();
    CHECK(mp.com.z() == mbx_test::relative(3.0, 1e-6));
    CHECK(mp.inertia(0, 0) == mbx_test::relative(12.0, 1e-6));
    CHECK(mp.inertia(1, 1) == mbx_test::relative(12.0, 1e-6));
    CHECK(std::abs(mp.inertia(2, 2)) < 1e-12);
}

TEST_CASE("inertia checks name what is wrong") {
    Vec3 l;
    CHECK(check_inertia(Vec3(1, 2, 2.5).asDiagonal(), l) == InertiaIssue::none);
    CHECK(l[0] == mbx_test::relative(1.0, 1e-6));
    CHECK(check_inertia(Vec3(1, 1, 3).asDiagonal(), l) == InertiaIssue::triangle_inequality);
    CHECK(check_inertia(Vec3(-1, -2, -2.5).asDiagonal(), l) == InertiaIssue::not_positive_definite);
    CHECK(check_inertia(Mat3::Zero(), l) == InertiaIssue::semi_definite);
    // A thin rod (I1 ~ 0, I2 = I3) sits on the triangle boundary: legal.
    CHECK(check_inertia(Vec3(1e-7, 1, 1).asDiagonal(), l) == InertiaIssue::none);
    // Rounded to 6 significant digits, a disc (I1 + I2 = I3) stays legal.
    CHECK(check_inertia(Vec3(0.500001, 0.499999, 1.00000).asDiagonal(), l) == InertiaIssue::none);
    // A rotated valid tensor stays valid; its principal moments are unchanged.
    Mat3 r = test::rot_x(0.3) * test::rot_z(1.1);
    CHECK(check_inertia(r * Vec3(1, 2, 2.5).asDiagonal() * r.transpose(), l) == InertiaIssue::none);
    CHECK(l[2] == mbx_test::relative(2.5, 1e-6));
}
}  // namespace MBX_UNITY_ID
