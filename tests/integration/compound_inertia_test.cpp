// Link 2 of six_axis_arm is three welded parts with three different body
// frames; one part's inertia is a full tensor. The compound is recomputed
// here by hand: each part's tensor rotated to world (R I R^T), shifted to the
// common CoM with the parallel-axis theorem, summed -- then compared with
// what the SDK reports in its own body frame.
#include <doctest/doctest.h>

#include "support/plugin_fixture.h"
#include "support/stub_geometry.h"
#include "tests/common/near.h"

namespace MBX_UNITY_ID {

using namespace itest;

TEST_CASE("six_axis_arm: link 2 is one rigid body with the compound mass of its three parts") {
    const mbx_stub::Assembly a = builtin("six_axis_arm");
    const Run r = translate(a);
    REQUIRE_MESSAGE(r.status == MBX_OK, r.error);
    const mbx_mechanism* m = r.get();

    const char* ids[] = {"six_axis_arm/link2_housing", "six_axis_arm/link2_tube", "six_axis_arm/link2_elbow"};
    const uint32_t link2 = find_part(m, ids[0]);
    CHECK(link2 != 0);
    CHECK(find_part(m, ids[1]) == link2);
    CHECK(find_part(m, ids[2]) == link2);
    const mbx_rigid_body_info info = rigid_body(m, link2);
    CHECK(info.part_count == 3);

    // Hand computation, in SI world terms (this builtin is in SI units).
    double mass = 0;
    Vec3 first_moment = Vec3::Zero();
    Vec3 com_w[3];
    Mat3 inertia_w[3];
    double masses[3];
    for (int k = 0; k < 3; ++k) {
        const mbx_stub::Body& b = body_by_id(a, ids[k]);
        REQUIRE(b.units.length_to_m == 1.0);
        REQUIRE(b.units.inertia_to_kg_m2 == 1.0);
        const Mat3 R = rotation(b.pose.rotation);
        const Vec3 p = vec(b.pose.position);
        masses[k] = b.mass;
        com_w[k] = R * vec(b.com) + p;                       // CoM given in the body frame
        inertia_w[k] = R * rotation(b.inertia) * R.transpose();  // tensor given in body axes
        mass += b.mass;
        first_moment += b.mass * com_w[k];
    }
    const Vec3 com = first_moment / mass;
    Mat3 inertia = Mat3::Zero();
    for (int k = 0; k < 3; ++k) {
        const Vec3 d = com_w[k] - com;
        inertia += inertia_w[k] + masses[k] * (d.dot(d) * Mat3::Identity() - d * d.transpose());
    }
    CHECK(mass == mbx_test::relative(6.0 + 9.0 + 4.0, 1e-6));

    // The SDK reports CoM and inertia in the body frame `info.pose`.
    const Mat3 R = rotation(info.pose.rotation);
    const Vec3 p = vec(info.pose.position);
    CHECK(info.mass == mbx_test::relative(mass, 1e-12));
    const Vec3 sdk_com = R * vec(info.com) + p;
    CHECK((sdk_com - com).norm() < 1e-12);
    const Mat3 sdk_inertia = R * rotation(info.inertia) * R.transpose();
    INFO("hand inertia (world):\n" << inertia << "\nSDK inertia (world):\n" << sdk_inertia);
    CHECK((sdk_inertia - inertia).cwiseAbs().maxCoeff() < 1e-12 * inertia.cwiseAbs().maxCoeff() * 10);
    // The body-frame tensor itself is symmetric positive definite.
    const Mat3 body_inertia = rotation(info.inertia);
    CHECK((body_inertia - body_inertia.transpose()).cwiseAbs().maxCoeff() < 1e-12);
    CHECK(Eigen::SelfAdjointEigenSolver<Mat3>(body_inertia).eigenvalues().minCoeff() > 0);

    // The check discriminates: skipping the tensor rotation gives a visibly
    // different answer, so an SDK that forgot it could not pass.
    Mat3 unrotated = Mat3::Zero();
    for (int k = 0; k < 3; ++k) {
        const Vec3 d = com_w[k] - com;
        unrotated += rotation(body_by_id(a, ids[k]).inertia) +
                     masses[k] * (d.dot(d) * Mat3::Identity() - d * d.transpose());
    }
    CHECK((unrotated - inertia).cwiseAbs().maxCoeff() > 1e-3 * inertia.cwiseAbs().maxCoeff());
}

TEST_CASE("fourbar: millimetres and grams arrive as metres and kilograms") {
    const mbx_stub::Assembly a = builtin("fourbar");
    const Run r = translate(a);
    REQUIRE_MESSAGE(r.status == MBX_OK, r.error);
    const mbx_rigid_body_info crank = rigid_body(r.get(), find_part(r.get(), "fourbar/crank"));
    // 20 g crank, 40 mm long, pivot A at (0, 0, 10) mm, CoM half-way to B (24, 32, 10) mm.
    CHECK(crank.mass == mbx_test::relative(0.020, 1e-12));
    const Vec3 com = rotation(crank.pose.rotation) * vec(crank.com) + vec(crank.pose.position);
    CHECK((com - Vec3(0.012, 0.016, 0.010)).norm() < 1e-12);
    CHECK((vec(crank.pose.position) - Vec3(0, 0, 0.010)).norm() < 1e-12);
    // Box 50 x 8 x 5 mm of 20 g about its own axes: m/12 (b^2 + c^2) etc., in kg m^2.
    CHECK(crank.inertia[0] == mbx_test::relative(0.020 / 12 * (0.008 * 0.008 + 0.005 * 0.005), 1e-9));
    CHECK(crank.inertia[4] == mbx_test::relative(0.020 / 12 * (0.050 * 0.050 + 0.005 * 0.005), 1e-9));
    CHECK(crank.inertia[8] == mbx_test::relative(0.020 / 12 * (0.050 * 0.050 + 0.008 * 0.008), 1e-9));
    // Ground link, RootPart (massless helper) and ground merge into the ground body.
    CHECK(find_part(r.get(), "fourbar/RootPart") == 0);
}
}  // namespace MBX_UNITY_ID
