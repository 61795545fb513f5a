// Joint dynamics from the description file into the simulator: resolved
// entries map onto BuildOptions by mechanism joint, add their armature to a
// drive's, replace the CAD limits, and a damped pendulum in mbx's own
// simulator decays and rings at the analytic rates.
#include <doctest/doctest.h>

#include <cmath>

#include "apps/stub_host/assemblies/builder.h"
#include "tests/export/drives_support.h"
#include "tests/export/export_fixture.h"
#include "tests/export/joint_dynamics_support.h"
#include "sim/build_model.h"
#include "sim/data.h"
#include "sim/integrator.h"
#include "sim/resolved_joint_dynamics.h"
#include "tests/common/near.h"

namespace MBX_UNITY_ID {

using namespace mbx;

namespace {

constexpr double kPi = 3.14159265358979323846;

using xtest::resolve_joints;

// A pendulum about x hanging along -z from ground: a bob of kMass at kLength.
constexpr double kLength = 0.4, kMass = 2.0, kBobInertia = 1e-3;
mbx_memory::Assembly pendulum() {
    namespace build = mbx_stub::build;
    mbx_memory::Assembly a;
    a.name = "pendulum";
    const mbx_units si{1, 1, 1};
    build::Builder b(a, "pend", si, si);
    const build::Mat3 I = build::Mat3::Identity();
    b.body("base", "Base", MBX_BODY_GROUND, 10, I, build::Vec3(0, 0, 0), build::Vec3(0, 0, 0), I);
    b.body("bob", "Bob", 0, kMass, I, build::Vec3(0, 0, -kLength), build::Vec3(0, 0, -kLength), kBobInertia * I);
    b.joint("pivot", "base", "bob", build::Vec3(0, 0, 0), I,
            {build::revolute(build::Vec3(1, 0, 0), MBX_AXIS_IN_WORLD, -2, 2)}, MBX_FRAME_IN_WORLD, MBX_FRAME_IN_WORLD);
    return a;
}

}  // namespace

TEST_CASE("joint dynamics: description entries reach the simulation model, armature on top of a drive's") {
    auto t = xtest::translate_file(std::string(MBX_SAMPLES_DIR) + "/five_axis_arm/five_axis_arm.xml");
    const Mechanism& m = *t->mechanism;
    sim::BuildOptions options;
    options.drives =
        xtest::resolve_drive_file(m, std::string(MBX_SAMPLES_DIR) + "/mechatronics/five_axis_arm_drives.xml");
    const std::vector<ResolvedJointDynamics> jd = resolve_joints(
        m, "<joint constraint=\"40:-:41\" damping=\"1.5\" coulomb=\"0.8\" coulomb_velocity=\"0.02\" stiffness=\"4\" "
           "rest=\"10\" armature=\"0.2\" lower=\"-30\" upper=\"60\" unit=\"deg\"/>\n");
    REQUIRE(jd.size() == 1);
    options.joint_dynamics = sim::joint_dynamics_by_joint(jd);
    REQUIRE(options.joint_dynamics.size() == 1);
    const sim::Model model = sim::build_model(m, options);

    const Drive* waist = nullptr;
    for (const Drive& d : options.drives)
        if (d.joint == jd[0].joint) waist = &d;
    REQUIRE(waist);
    const int sj = model.joint_of_source[size_t(jd[0].joint)];
    REQUIRE(sj >= 0);
    const sim::JointDynamics& got = model.joints[size_t(sj)].dynamics;
    CHECK(got.armature == mbx_test::relative(waist->armature + 0.2, 1e-14));
    CHECK(got.damping == 1.5);
    CHECK(got.coulomb == 0.8);
    CHECK(got.coulomb_velocity == mbx_test::relative(0.02 * kPi / 180, 1e-14));
    CHECK(got.stiffness == 4);
    CHECK(got.rest == mbx_test::relative(kPi / 18, 1e-14));
    CHECK(got.limited);
    CHECK(got.lower == mbx_test::relative(-kPi / 6, 1e-14));
    CHECK(got.upper == mbx_test::relative(kPi / 3, 1e-14));
    CHECK(got.limit_stiffness > 0);  // sized by build_model from the joint's inertia
    // Joints without an entry keep only their drive's armature.
    for (const Drive& d : options.drives) {
        if (&d == waist) continue;
        CHECK(model.joints[size_t(model.joint_of_source[size_t(d.joint)])].dynamics.armature == d.armature);
    }
}

TEST_CASE("joint dynamics: a damped pendulum in mbx's simulator decays at b / (2 I) and rings at the damped frequency") {
    auto t = xtest::translate(pendulum());
    const Mechanism& m = *t->mechanism;
    const double b = 0.15, k = 3, armature = 0.02;
    sim::BuildOptions options;
    options.joint_dynamics = sim::joint_dynamics_by_joint(resolve_joints(
        m, "<joint constraint=\"pend/pivot\" damping=\"" + std::to_string(b) + "\" stiffness=\"" + std::to_string(k) +
               "\" armature=\"" + std::to_string(armature) + "\"/>\n"));
    const sim::Model model = sim::build_model(m, options);
    REQUIRE(model.nv == 1);
    sim::Data data(model);
    data.q[0] = 0.01;
    data.v[0] = 0;

    const double I = kBobInertia + kMass * kLength * kLength + armature;
    const double rate = b / (2 * I);
    const double omega_d = std::sqrt((kMass * 9.81 * kLength + k) / I - rate * rate);
    sim::IntegratorSettings settings;
    settings.kind = sim::IntegratorKind::RK4;
    settings.step = 5e-4;
    std::vector<std::pair<double, double>> peaks;
    double prev2 = data.q[0], prev1 = prev2, t_prev1 = 0;
    while (data.time < 6.0) {
        sim::fixed_step(model, data, settings);
        const double q = data.q[0];
        if (prev1 > prev2 && prev1 >= q && data.time > 1e-3) {
            // Parabola through the last three samples: the peak between samples.
            const double h = settings.step, c2 = (q - 2 * prev1 + prev2) / (2 * h * h), c1 = (q - prev2) / (2 * h);
            const double dt = -c1 / (2 * c2);
            peaks.push_back({t_prev1 + dt, prev1 + c1 * dt + c2 * dt * dt});
        }
        prev2 = prev1, prev1 = q, t_prev1 = data.time;
    }
    REQUIRE(peaks.size() >= 4);
    const double measured_rate =
        std::log(peaks.front().second / peaks.back().second) / (peaks.back().first - peaks.front().first);
    const double period = (peaks.back().first - peaks.front().first) / double(peaks.size() - 1);
    MESSAGE("mbx: decay rate " << measured_rate << " 1/s (analytic " << rate << "), period " << period
                               << " s (analytic " << 2 * kPi / omega_d << ")");
    CHECK(measured_rate == mbx_test::relative(rate, 1e-4));
    CHECK(period == mbx_test::relative(2 * kPi / omega_d, 1e-4));
}
}  // namespace MBX_UNITY_ID
