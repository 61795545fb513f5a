// The joint-dynamics terms calibration identifies (docs/mechatronics.md,
// "Joint dynamics"): a constant effort offset, direction-dependent Coulomb
// friction and damping, and a Stribeck peak. Each number is from the law's
// closed form: a free slider under the offset alone accelerates at
// -offset / m; the efforts at chosen speeds are the documented formulas; a
// joint under a slowly rising load in the accurate mode breaks away exactly
// when the load reaches the pushed direction's Coulomb level plus the peak.
#include <doctest/doctest.h>

#include <cmath>
#include <cstdio>

#include "apps/stub_host/assemblies/builder.h"
#include "tests/export/drives_support.h"
#include "tests/export/export_fixture.h"
#include "sim/build_model.h"
#include "sim/cvode_session.h"
#include "sim/data.h"
#include "sim/integrator.h"
#include "sim/joint_forces.h"
#include "sim/resolved_joint_dynamics.h"
#include "tests/common/near.h"

namespace MBX_UNITY_ID {

using namespace mbx;

namespace {

constexpr double kMass = 2.0, kInertia = 0.05;

// Ground and one body on a single joint at the origin: a slider along x or a
// rotor about z, its centre of mass on the axis (so gravity, switched off
// anyway, does no work on it).
mbx_memory::Assembly one_axis(bool linear) {
    namespace build = mbx_stub::build;
    mbx_memory::Assembly a;
    a.name = linear ? "slider" : "rotor";
    const mbx_units si{1, 1, 1};
    build::Builder b(a, "one", si, si);
    const build::Mat3 I = build::Mat3::Identity();
    b.body("base", "Base", MBX_BODY_GROUND, 10, I, build::Vec3(0, 0, 0), build::Vec3(0, 0, 0), I);
    b.body("load", "Load", 0, kMass, I, build::Vec3(0, 0, 0), build::Vec3(0, 0, 0), kInertia * I);
    build::Prim p = build::revolute(build::Vec3(0, 0, 1));
    if (linear) {
        p.type = MBX_PRIMITIVE_PRISMATIC;
        p.axis = build::Vec3(1, 0, 0);
    }
    b.joint("axis", "base", "load", build::Vec3(0, 0, 0), I, {p}, MBX_FRAME_IN_WORLD, MBX_FRAME_IN_WORLD);
    return a;
}

struct Axis {
    std::unique_ptr<xtest::Translated> t;
    sim::Model model;
};

// The one-axis mechanism with `attributes` on its <joint> entry, read
// through the description file as a user (or calibration) writes it.
Axis axis_with(bool linear, const std::string& attributes) {
    Axis a;
    a.t = xtest::translate(one_axis(linear));
    const Mechanism& m = *a.t->mechanism;
    MechatronicSpec spec;
    std::vector<DriveError> errors;
    load_drive_text("<mechatronics version=\"1\">\n<joint constraint=\"one/axis\" " + attributes + "/>\n</mechatronics>\n",
                    "joints.xml", "", spec, errors);
    for (const DriveError& e : errors) FAIL_CHECK(e.text());
    const std::vector<ResolvedJointDynamics> resolved = resolve_joint_dynamics(spec, m, errors);
    for (const DriveError& e : errors) FAIL_CHECK(e.text());
    REQUIRE(resolved.size() == 1);
    sim::BuildOptions options;
    options.gravity = Eigen::Vector3d::Zero();
    options.joint_dynamics = sim::joint_dynamics_by_joint(resolved);
    a.model = sim::build_model(m, options);
    REQUIRE(a.model.nv == 1);
    return a;
}

// qfrc_passive at speed `qd` under `law`.
double passive_at(const sim::Model& m, double qd, sim::FrictionLaw law) {
    sim::Data d(m);
    d.v[0] = qd;
    sim::passive_forces(m, d, law);
    return d.qfrc_passive[0];
}

}  // namespace

TEST_CASE("joint dynamics extra: an effort offset alone accelerates a free slider at -offset / m") {
    const double offset = -3.16;  // the EMPS rig's identified offset, N
    Axis a = axis_with(true, "offset=\"-3.16\"");
    sim::Data d(a.model);
    const double q0 = d.q[0];
    sim::IntegratorSettings rk4;
    rk4.kind = sim::IntegratorKind::RK4;
    rk4.step = 1e-3;
    for (int k = 0; k < 1000; ++k) sim::fixed_step(a.model, d, rk4);
    const double accel = -offset / kMass, t = d.time;
    CHECK(t == mbx_test::relative(1.0, 1e-12));
    CHECK(d.qacc[0] == mbx_test::relative(accel, 1e-12));
    CHECK(d.v[0] == mbx_test::relative(accel * t, 1e-12));
    CHECK(d.q[0] - q0 == mbx_test::relative(0.5 * accel * t * t, 1e-12));
    // The offset is an effort, not friction: it acts at rest and in motion alike.
    CHECK(passive_at(a.model, 0.0, sim::FrictionLaw::Regularised) == mbx_test::relative(-offset, 1e-15));
    CHECK(passive_at(a.model, -5.0, sim::FrictionLaw::Slipping) == mbx_test::relative(-offset, 1e-15));
    std::printf("[joint dynamics extra] offset %.3g N on a %.3g kg slider: acceleration %.6g m/s^2 (exact %.6g), "
                "x(1 s) %.9g m (exact %.9g)\n",
                offset, kMass, d.qacc[0], accel, d.q[0] - q0, 0.5 * accel * t * t);
}

TEST_CASE("joint dynamics extra: asymmetric Coulomb friction and damping take each direction's value") {
    const double cp = 2.0, cn = 0.5, dp = 3.0, dn = 1.2, vc = 1e-3, v = 0.5;  // v = 500 v_c: tanh is 1 in double
    Axis a = axis_with(true, "coulomb=\"2\" coulomb_negative=\"0.5\" damping=\"3\" damping_negative=\"1.2\" "
                             "coulomb_velocity=\"0.001\"");
    const sim::JointT<double>& j = a.model.joints[0];
    for (sim::FrictionLaw law : {sim::FrictionLaw::Regularised, sim::FrictionLaw::Slipping}) {
        CHECK(sim::coulomb_effort(a.model, j, v, law) == mbx_test::relative(-cp, 1e-14));
        CHECK(sim::coulomb_effort(a.model, j, -v, law) == mbx_test::relative(cn, 1e-14));
        CHECK(passive_at(a.model, v, law) == mbx_test::relative(-cp - dp * v, 1e-14));
        CHECK(passive_at(a.model, -v, law) == mbx_test::relative(cn + dn * v, 1e-14));
    }
    CHECK(sim::damping_effort(j.dynamics, v) == -dp * v);
    CHECK(sim::damping_effort(j.dynamics, -v) == dn * v);
    // Near rest the regularised law blends the two levels:
    // -(c+ (1 + t)/2 + c- (1 - t)/2) t with t = tanh(qd / v_c), 0 at rest.
    CHECK(sim::coulomb_effort(a.model, j, 0.0, sim::FrictionLaw::Regularised) == 0.0);
    for (double x : {-2.0, -0.5, 0.3, 1.0}) {
        const double t = std::tanh(x);
        const double expected = -(cp * (1 + t) / 2 + cn * (1 - t) / 2) * t;
        CHECK(sim::coulomb_effort(a.model, j, x * vc, sim::FrictionLaw::Regularised) ==
              mbx_test::relative(expected, 1e-14));
    }
}

TEST_CASE("joint dynamics extra: the Stribeck peak adds stribeck exp(-(qd/vs)^2) to each direction's Coulomb level") {
    const double cp = 1.0, cn = 0.3, s = 0.6, vs = 0.02;
    Axis a = axis_with(false, "coulomb=\"1\" coulomb_negative=\"0.3\" stribeck=\"0.6\" stribeck_velocity=\"0.02\" "
                              "coulomb_velocity=\"0.0001\"");
    const sim::JointT<double>& j = a.model.joints[0];
    for (sim::FrictionLaw law : {sim::FrictionLaw::Regularised, sim::FrictionLaw::Slipping}) {
        // 0.5 vs = 100 v_c and beyond: tanh is 1, the level is the formula's.
        for (double x : {0.5, 1.0, 2.0, 4.0}) {
            const double peak = s * std::exp(-x * x);
            CHECK(sim::coulomb_effort(a.model, j, x * vs, law) == mbx_test::relative(-(cp + peak), 1e-14));
            CHECK(sim::coulomb_effort(a.model, j, -x * vs, law) == mbx_test::relative(cn + peak, 1e-14));
        }
    }
    CHECK(sim::static_friction(j.dynamics, 1) == mbx_test::relative(cp + s, 1e-15));
    CHECK(sim::static_friction(j.dynamics, -1) == mbx_test::relative(cn + s, 1e-15));
}

TEST_CASE("joint dynamics extra: accurate mode breaks away at the pushed direction's Coulomb level plus the Stribeck peak") {
    const double cp = 0.8, cn = 0.3, s = 0.4, rate = 0.4;
    Axis a = axis_with(false, "coulomb=\"0.8\" coulomb_negative=\"0.3\" stribeck=\"0.4\" stribeck_velocity=\"0.05\"");
    for (int direction : {1, -1}) {
        const double t_slip = ((direction > 0 ? cp : cn) + s) / rate;  // 3 s pushing up, 1.75 s pushing down
        sim::Data d(a.model);
        const double q0 = d.q[0];
        sim::IntegratorSettings is;
        is.kind = sim::IntegratorKind::Accurate;
        is.tolerance = 1e-10;
        is.step = 0;
        sim::AccurateRequest r;
        r.stop_time = t_slip + 0.2;
        for (double t : {0.5, t_slip - 0.3, t_slip - 1e-3, t_slip + 1e-3, t_slip + 0.1, t_slip + 0.2}) r.sample_times.push_back(t);
        struct Sample {
            double t, q, qd;
            int mode;
        };
        std::vector<Sample> got;
        r.sample = [&](sim::Data& at) { got.push_back({at.time, at.q[0], at.v[0], sim::friction_mode(at, 0)}); };
        r.inputs = [&](double t, sim::Data& at) { at.effort[0] = direction * rate * t; };
        sim::accurate_advance(a.model, d, is, r);
        REQUIRE(got.size() == 6);
        INFO("direction " << direction);
        for (size_t k = 0; k < 3; ++k) {
            CHECK(got[k].mode == 0);
            CHECK(got[k].qd == 0.0);
            CHECK(std::fabs(got[k].q - q0) < 1e-12);
        }
        for (size_t k = 3; k < 6; ++k) {
            CHECK(got[k].mode == direction);
            CHECK(got[k].qd * direction > 0);
        }
        CHECK(d.stats.mode_switches == 1);
        std::printf("[joint dynamics extra] accurate mode, load %s: held to %.3f s, slipping at %.3f s (%.3g rad/s); "
                    "threshold %.3g N m at %.3g s\n",
                    direction > 0 ? "rising" : "falling", got[2].t, got[3].t, got[3].qd,
                    (direction > 0 ? cp : cn) + s, t_slip);
    }
}
}  // namespace MBX_UNITY_ID
