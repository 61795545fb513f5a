// Elastic transmissions (sim/transmission.h): the motor as one more inertia
// joined to the link by a spring and damper, or through a dead band. Every
// number from closed forms on the pendulum assembly without gravity (a rigid
// rotor of inertia I about its hinge): motor and link are a two-mass
// oscillator, whose deflection rings at sqrt(k (1/Jm + 1/I)) while the
// common angle (Jm theta_m + I q) / (Jm + I) moves with the effort alone.
#include <cmath>
#include <cstdio>

#include "tests/export/export_fixture.h"
#include "tests/export/joint_dynamics_support.h"
#include "tests/export/mujoco_assemblies.h"
#include "sim/build_model.h"
#include "sim/cvode_session.h"
#include "sim/resolved_joint_dynamics.h"
#include "sim/simulation.h"
#include "sim/transmission.h"
#include "tests/common/near.h"

namespace MBX_UNITY_ID {

using namespace mbx;

namespace {

struct Rig {
    xtest::mjcf_assemblies::Pendulum shape;
    sim::Model model;
    double link = 0;  // I about the hinge
};

Rig rig(double motor_ratio, double stiffness, double damping, double backlash = 0) {
    Rig r;
    auto t = xtest::translate(r.shape.assembly());
    sim::BuildOptions options;
    options.gravity = Eigen::Vector3d::Zero();
    const sim::Model bare = sim::build_model(*t->mechanism, options);
    REQUIRE(bare.nv == 1);
    r.link = r.shape.pivot_inertia();
    sim::Transmission tr;
    tr.motor_inertia = motor_ratio * r.link;
    tr.stiffness = stiffness, tr.damping = damping, tr.backlash = backlash;
    options.transmissions[bare.joints[0].source] = tr;
    r.model = sim::build_model(*t->mechanism, options);
    return r;
}

sim::IntegratorSettings rk4(double step) {
    sim::IntegratorSettings s;
    s.kind = sim::IntegratorKind::RK4;
    s.step = step;
    return s;
}

sim::IntegratorSettings accurate() {
    sim::IntegratorSettings s;
    s.kind = sim::IntegratorKind::Accurate;
    s.tolerance = 1e-10;
    s.step = 0;
    return s;
}

}  // namespace

TEST_CASE("sim transmission: a released deflection rings at the two-mass frequency and keeps the energy") {
    const double I0 = xtest::mjcf_assemblies::Pendulum{}.pivot_inertia();
    const double k = I0 * std::pow(2 * M_PI * 8, 2);  // link alone: 8 Hz
    const Rig r = rig(0.4, k, 0);
    const double Jm = r.model.transmissions[0].motor_inertia, I = r.link;
    CHECK(r.model.joints[0].reference_inertia == mbx_test::relative(I, 1e-9));
    const double w = std::sqrt(k * (1 / Jm + 1 / I));
    const double theta0 = 0.05;
    for (const sim::IntegratorSettings& is : {rk4(1e-4), accurate()}) {
        sim::Data d(r.model);
        sim::initial_state(r.model, d, {});
        CHECK(d.motor_q[0] == 0.0);  // no load: the motor sits with the link
        d.motor_q[0] = theta0;
        double worst_q = 0, worst_dq = 0, worst_e = 0;
        const double e0 = 0.5 * k * theta0 * theta0;
        for (int s = 1; s <= 400; ++s) {
            const double t = s * 2.5e-3;
            sim::advance(r.model, d, is, t);
            // Momentum is zero: Jm theta_m + I q = Jm theta0; theta_m - q = theta0 cos wt.
            const double dq = theta0 * std::cos(w * t);
            const double q = Jm * theta0 * (1 - std::cos(w * t)) / (Jm + I);
            worst_q = std::max(worst_q, std::fabs(d.q[0] - q));
            worst_dq = std::max(worst_dq, std::fabs(d.motor_q[0] - d.q[0] - dq));
            const double e = 0.5 * I * d.v[0] * d.v[0] + sim::transmission_energy(r.model, d);
            worst_e = std::max(worst_e, std::fabs(e - e0) / e0);
        }
        std::printf("[transmission] %s: two-mass oscillator %.3f Hz over 1 s: link off by %.2e rad, deflection by "
                    "%.2e rad (of %.2g), energy by %.2e\n",
                    sim::integrator_name(is.kind), w / (2 * M_PI), worst_q, worst_dq, theta0, worst_e);
        CHECK(worst_q < 1e-6 * theta0 * 100);
        CHECK(worst_dq < 1e-6 * theta0 * 100);
        CHECK(worst_e < 1e-5);
    }
}

TEST_CASE("sim transmission: the damper takes the deflection down at c / (2 mu)") {
    const double I0 = xtest::mjcf_assemblies::Pendulum{}.pivot_inertia();
    const double k = I0 * std::pow(2 * M_PI * 8, 2);
    const double Jm = 0.4 * I0, mu = Jm * I0 / (Jm + I0);
    const double c = 2 * 0.05 * std::sqrt(k * mu);  // damping ratio 0.05
    const Rig r = rig(0.4, k, c);
    sim::Data d(r.model);
    sim::initial_state(r.model, d, {});
    d.motor_q[0] = 0.05;
    // The relative coordinate x = theta_m - q: mu x'' + c x' + k x = 0.
    const double decay = c / (2 * mu), wd = std::sqrt(k / mu - decay * decay);
    double worst = 0;
    for (int s = 1; s <= 200; ++s) {
        const double t = s * 5e-3;
        sim::advance(r.model, d, accurate(), t);
        const double x = 0.05 * std::exp(-decay * t) * (std::cos(wd * t) + decay / wd * std::sin(wd * t));
        worst = std::max(worst, std::fabs(d.motor_q[0] - d.q[0] - x));
    }
    std::printf("[transmission] damped deflection (zeta 0.05) over 1 s: off by %.2e rad of 0.05\n", worst);
    CHECK(worst < 1e-6);
}

TEST_CASE("sim transmission: an effort turns the motor, and the link only through the spring") {
    const double I0 = xtest::mjcf_assemblies::Pendulum{}.pivot_inertia();
    const double k = I0 * std::pow(2 * M_PI * 8, 2);
    const Rig r = rig(0.3, k, 0);
    const double Jm = r.model.transmissions[0].motor_inertia, I = r.link, tau = 0.2;
    const double w = std::sqrt(k * (1 / Jm + 1 / I));
    for (const sim::IntegratorSettings& is : {rk4(1e-4), accurate()}) {
        sim::Data d(r.model);
        sim::initial_state(r.model, d, {});
        d.effort[0] = tau;
        double worst = 0;
        for (int s = 1; s <= 100; ++s) {
            const double t = s * 5e-3;
            sim::advance(r.model, d, is, t);
            // The common angle accelerates at tau / (Jm + I); the deflection
            // x obeys mu x'' + k x = mu tau / Jm from rest: x = tau/(Jm w^2) (1 - cos wt).
            const double common = 0.5 * tau / (Jm + I) * t * t;
            const double x = tau / (Jm * w * w) * (1 - std::cos(w * t));
            const double motor = common + I / (Jm + I) * x, link = common - Jm / (Jm + I) * x;
            worst = std::max({worst, std::fabs(d.motor_q[0] - motor), std::fabs(d.q[0] - link)});
        }
        std::printf("[transmission] %s: constant effort on the motor side over 0.5 s: off by %.2e rad\n",
                    sim::integrator_name(is.kind), worst);
        CHECK(worst < 1e-7);
    }
}

TEST_CASE("sim transmission: across the dead band the link feels nothing until the stop") {
    const Rig r = rig(0.5, 0, 0, 0.02);
    const double Jm = r.model.transmissions[0].motor_inertia, I = r.link;
    sim::Data d(r.model);
    sim::initial_state(r.model, d, {});
    d.motor_v[0] = 1.0;  // 1 rad/s: the band's half (0.01 rad) in 10 ms
    sim::advance(r.model, d, rk4(1e-5), 0.0099);
    CHECK(d.q[0] == 0.0);
    CHECK(d.v[0] == 0.0);
    CHECK(d.motor_v[0] == mbx_test::relative(1.0, 1e-12));
    // Through the stop the momentum Jm * 1 is shared and none is made; the
    // stop's damper takes energy and gives none.
    sim::advance(r.model, d, rk4(1e-5), 0.03);
    CHECK(d.v[0] > 0.1 * Jm / (Jm + I));
    CHECK(Jm * d.motor_v[0] + I * d.v[0] == mbx_test::relative(Jm, 1e-9));
    CHECK(0.5 * I * d.v[0] * d.v[0] + sim::transmission_energy(r.model, d) < 0.5 * Jm);
}

TEST_CASE("sim transmission: the motor's columns follow the joints' in a trajectory, and gravity's load is settled") {
    xtest::mjcf_assemblies::Pendulum shape;
    auto t = xtest::translate(shape.assembly());
    sim::BuildOptions options;
    const sim::Model bare = sim::build_model(*t->mechanism, options);
    sim::Transmission tr;
    tr.motor_inertia = 0.01, tr.stiffness = 2000, tr.damping = 0.5;
    options.transmissions[bare.joints[0].source] = tr;
    const sim::Model m = sim::build_model(*t->mechanism, options);
    const std::vector<std::string> cols = sim::trajectory_columns(m);
    REQUIRE(cols.size() == 5);
    CHECK(cols[3] == bare.joints[0].name + ".motor_q");
    CHECK(cols[4] == bare.joints[0].name + ".motor_qd");
    // Held out of its hanging pose, the link's gravity load is carried by the
    // spring: started there, the link does not move at first.
    sim::Data d(m);
    sim::initial_state(m, d, {{0, 0, false, 0.4}});
    sim::Data rigid(bare);
    sim::initial_state(bare, rigid, {{0, 0, false, 0.4}});
    sim::update_kinematics(bare, rigid);
    Eigen::VectorXd zero = Eigen::VectorXd::Zero(1), g(1);
    sim::inverse_dynamics(bare, rigid, zero, g);
    CHECK(tr.stiffness * (d.motor_q[0] - d.q[0]) == mbx_test::relative(g[0], 1e-9));
    sim::evaluate(m, d, sim::FrictionLaw::Regularised);
    CHECK(std::fabs(d.qacc[0]) < 1e-9);
    sim::RunSettings rs;
    rs.stop_time = 0.1;
    rs.output_step = 0.01;
    sim::Trajectory out;
    sim::run(m, d, rs, out);
    CHECK(out.rows() == 11);
}

TEST_CASE("sim transmission: bad values are refused naming the joint") {
    xtest::mjcf_assemblies::Pendulum shape;
    auto t = xtest::translate(shape.assembly());
    const sim::Model bare = sim::build_model(*t->mechanism);
    const std::string name = bare.joints[0].name;
    auto build = [&](double jm, double k, double c, double b) {
        sim::BuildOptions options;
        sim::Transmission tr;
        tr.motor_inertia = jm, tr.stiffness = k, tr.damping = c, tr.backlash = b;
        options.transmissions[bare.joints[0].source] = tr;
        return sim::build_model(*t->mechanism, options);
    };
    CHECK_THROWS_WITH(build(0, 100, 0, 0), doctest::Contains(("joint '" + name + "': transmission motor_inertia must be positive").c_str()));
    CHECK_THROWS_WITH(build(0.1, -1, 0, 0), doctest::Contains("stiffness must be finite and not negative"));
    CHECK_THROWS_WITH(build(0.1, 100, NAN, 0), doctest::Contains("damping must be finite"));
    CHECK_THROWS_WITH(build(0.1, 0, 0, 0), doctest::Contains("needs a positive stiffness, or a backlash"));
    CHECK_NOTHROW(build(0.1, 0, 0, 0.01));
}

TEST_CASE("sim transmission: a description's <transmission> reaches the model, a drive's rotor on the motor side") {
    xtest::mjcf_assemblies::Pendulum shape;
    auto t = xtest::translate(shape.assembly());
    const sim::Model bare = sim::build_model(*t->mechanism);
    const std::string id = bare.joints[0].constraint_id;
    const std::vector<ResolvedJointDynamics> jd = xtest::resolve_joints(
        *t->mechanism, "<joint constraint=\"" + id + "\" damping=\"0.1\" unit=\"deg\">\n"
                       "<transmission stiffness=\"1500\" damping=\"0.3\" motor_inertia=\"0.02\" backlash=\"1\"/></joint>\n");
    sim::BuildOptions options;
    options.joint_dynamics = sim::joint_dynamics_by_joint(jd);
    options.transmissions = sim::transmissions_by_joint(jd);
    Drive drive;
    drive.name = "d";
    drive.joint = bare.joints[0].source;
    drive.armature = 0.005;
    options.drives.push_back(drive);
    const sim::Model m = sim::build_model(*t->mechanism, options);
    REQUIRE(m.transmissions.size() == 1);
    const sim::Transmission& tr = m.transmissions[0];
    CHECK(tr.joint == 0);
    CHECK(tr.stiffness == 1500);
    CHECK(tr.damping == 0.3);
    CHECK(tr.backlash == mbx_test::relative(M_PI / 180, 1e-15));
    CHECK(tr.motor_inertia == mbx_test::relative(0.025, 1e-15));  // the drive's rotor added
    CHECK(m.joints[0].dynamics.armature == 0);                         // not on the link
    CHECK(m.joints[0].dynamics.damping == 0.1);                        // the joint's own stay on the link
    CHECK(m.transmission_of_dof[0] == 0);
}
}  // namespace MBX_UNITY_ID
