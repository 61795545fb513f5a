// mbx's simulator (RK4 and semi-implicit Euler) against closed-form
// results: a compound pendulum's period, torque-free precession of a
// symmetric free body, viscous decay, a spring joint's frequency, the
// Coulomb stick threshold under a slowly rising effort and a position limit
// holding against a steady effort.
#include <cmath>

#include "sim/build_model.h"
#include "sim/simulation.h"
#include "tests/export/test_inputs.h"

namespace MBX_UNITY_ID {

using namespace mbx;

namespace {

constexpr double kPi = 3.14159265358979323846;
namespace a = xtest::mjcf_assemblies;

// Upward zero crossings of q[0] - offset, linearly interpolated between steps.
struct Crossings {
    std::vector<double> times;
    double previous = 0;
    bool started = false;
    void sample(double t, double h, double x) {
        if (started && previous < 0 && x >= 0) times.push_back(t - h * x / (x - previous));
        previous = x;
        started = true;
    }
    double period() const { return (times.back() - times.front()) / double(times.size() - 1); }
};

sim::IntegratorSettings rk4(double h) {
    sim::IntegratorSettings s;
    s.kind = sim::IntegratorKind::RK4;
    s.step = h;
    return s;
}

// A pendulum model with joint dynamics on its hinge (gravity as given).
sim::Model pendulum_model(const sim::JointDynamics& jd, const Eigen::Vector3d& gravity, xtest::Translated& t) {
    sim::BuildOptions o;
    o.gravity = gravity;
    o.joint_dynamics[0] = jd;
    return sim::build_model(*t.mechanism, o);
}

}  // namespace

TEST_CASE("sim: a compound pendulum swings with period 2 pi sqrt(I_pivot / (m g d)) (RK4)") {
    const a::Pendulum pendulum;
    auto t = xtest::translate(pendulum.assembly());
    const sim::Model m = sim::build_model(*t->mechanism);
    REQUIRE(m.nv == 1);
    sim::Data d(m);
    sim::update_positions(m, d);
    sim::mass_matrix(m, d);
    // The hinge's inertia is the parallel-axis moment about the pivot.
    CHECK(std::fabs(d.M(0, 0) - pendulum.pivot_inertia()) < 1e-12 * pendulum.pivot_inertia());

    const double theta0 = 0.02, g = sim::kDefaultGravity;
    sim::initial_state(m, d, {{0, 0, false, theta0}});
    const double t0 = 2 * kPi * std::sqrt(pendulum.pivot_inertia() / (pendulum.mass * g * pendulum.arm()));
    const double expected = t0 * (1 + theta0 * theta0 / 16 + 11 * std::pow(theta0, 4) / 3072);
    const double h = 1e-3;
    Crossings c;
    while (c.times.size() < 7 && d.time < 20 * t0) {
        sim::fixed_step(m, d, rk4(h));
        c.sample(d.time, h, d.q[0]);
    }
    REQUIRE(c.times.size() == 7);
    const double measured = c.period();
    MESSAGE("pendulum: period " << measured << " s, expected " << expected << " s, relative error "
                                << (measured - expected) / expected);
    // Measured 7.5e-12 relative (RK4's phase error at w h ~ 0.006 and the
    // crossing interpolation); the finite-amplitude correction is 2.5e-5.
    CHECK(std::fabs(measured - expected) < 1e-8 * expected);
    CHECK(std::fabs(measured - t0) > 1e-5 * t0);
}

TEST_CASE("sim: a torque-free symmetric body keeps its angular momentum and precesses as Euler's equations say") {
    // The tumbler made axisymmetric about body axis n: principal moments
    // (I1, I1, I3) along a frame that does not line up with the body axes.
    a::Tumbler tumbler;
    const Eigen::Matrix3d axes = mbx_stub::build::axis_angle(Eigen::Vector3d(1, 2, -1), 0.6);
    const double I1 = 0.004, I3 = 0.009;
    tumbler.inertia_body = axes * Eigen::Vector3d(I1, I1, I3).asDiagonal() * axes.transpose();
    const Eigen::Vector3d n = axes.col(2);
    auto t = xtest::translate(tumbler.assembly());
    const sim::Model m = sim::build_model(*t->mechanism, [] {
        sim::BuildOptions o;
        o.gravity.setZero();
        return o;
    }());
    REQUIRE(m.nv == 6);
    REQUIRE(m.joints[0].kind == sim::JointKind::Free);
    sim::Data d(m);
    sim::initial_state(m, d, {});
    // Body rates (free joint: angular velocity in the body frame) and an
    // origin velocity that leaves the centre of mass at rest.
    const Eigen::Vector3d w0(1.1, -2.3, 3.7);
    const Eigen::Quaterniond r0(d.q[3], d.q[4], d.q[5], d.q[6]);
    const Eigen::Vector3d c_world = r0 * tumbler.com_body;
    // v_origin = v_com + w x (origin - com), the free joint's linear rate in world axes.
    const Eigen::Vector3d v_origin = -(r0 * w0).cross(c_world);
    for (int k = 0; k < 3; ++k) d.v[k] = v_origin[k], d.v[3 + k] = w0[k];

    auto com_world = [&] {
        const Eigen::Quaterniond r(d.q[3], d.q[4], d.q[5], d.q[6]);
        return Eigen::Vector3d(Eigen::Vector3d(d.q[0], d.q[1], d.q[2]) + r.normalized() * tumbler.com_body);
    };
    auto momentum = [&] {  // about the centre of mass, world axes
        const Eigen::Quaterniond r(d.q[3], d.q[4], d.q[5], d.q[6]);
        const Eigen::Vector3d w(d.v[3], d.v[4], d.v[5]);
        return Eigen::Vector3d(r.normalized() * (tumbler.inertia_body * w));
    };
    const Eigen::Vector3d L0 = momentum(), p0 = com_world();
    // Euler: the body rate's component along n stays, the rest turns about n
    // at lambda = (I3 - I1) / I1 * (w . n) relative to the body.
    const double lambda = (I3 - I1) / I1 * w0.dot(n);
    const double h = 1e-3;
    double worst_L = 0, worst_w = 0, worst_p = 0;
    for (int s = 1; s <= int(3 / h); ++s) {
        sim::fixed_step(m, d, rk4(h));
        if (s % int(0.01 / h)) continue;
        const Eigen::Vector3d w(d.v[3], d.v[4], d.v[5]);
        const Eigen::Vector3d expected = Eigen::AngleAxisd(lambda * d.time, n) * w0;
        worst_w = std::max(worst_w, (w - expected).norm());
        worst_L = std::max(worst_L, (momentum() - L0).norm());
        worst_p = std::max(worst_p, (com_world() - p0).norm());
    }
    MESSAGE("free body over 3 s: |L - L0| " << worst_L << " (|L0| " << L0.norm() << "), body rate off Euler's by "
                                          << worst_w << " rad/s (lambda " << lambda << " rad/s), centre of mass moved "
                                          << worst_p << " m");
    // Measured: body rates within 1.4e-10 rad/s of Euler's (fourth order in
    // the step: 2.3e-9 at 2 ms, 1.0e-11 at 0.5 ms); |L - L0| 5.3e-7 of |L0|
    // and the centre of mass 5.4e-7 m, both second order in the step (2.1e-6
    // and 2.2e-6 at 2 ms, 1.3e-7 and 1.4e-7 at 0.5 ms): RK4 moves the
    // orientation by one rotation with the stages' averaged rate, as MuJoCo
    // does, which is second order on the rotation group. A wrong gyroscopic
    // term, inertia transform or rate convention is off by 1e-2 or more.
    CHECK(worst_w < 1e-8);
    CHECK(worst_L < 2e-6 * L0.norm());
    CHECK(worst_p < 2e-6);
    CHECK(std::fabs(lambda) * 3 > 2 * kPi);  // the transverse rate turned more than once
}

TEST_CASE("sim: viscous joint damping: a pendulum's oscillation decays as exp(-b t / (2 I))") {
    const a::Pendulum pendulum;
    auto t = xtest::translate(pendulum.assembly());
    sim::JointDynamics jd;
    const double I = pendulum.pivot_inertia();
    jd.damping = 0.02 * I;  // b / (2 I) = 0.01 1/s, decay rate
    const sim::Model m = pendulum_model(jd, Eigen::Vector3d(0, 0, -sim::kDefaultGravity), *t);
    sim::Data d(m);
    const double theta0 = 0.01;
    sim::initial_state(m, d, {{0, 0, false, theta0}});
    // Successive maxima: ln(A_k / A_k+1) = (b / 2I) T_d.
    const double h = 1e-3;
    std::vector<double> peaks, peak_times;
    double q1 = d.q[0], q2 = d.q[0];
    while (peaks.size() < 8) {
        sim::fixed_step(m, d, rk4(h));
        const double q = d.q[0];
        if (q1 > q2 && q1 >= q) {
            // Parabola through the three samples around the maximum.
            const double denom = q2 - 2 * q1 + q;
            const double offset = 0.5 * (q2 - q) / denom;
            peaks.push_back(q1 - 0.25 * (q2 - q) * offset);
            peak_times.push_back(d.time - h + offset * h);
        }
        q2 = q1, q1 = q;
    }
    const double decay = std::log(peaks.front() / peaks.back()) / (peak_times.back() - peak_times.front());
    const double expected = jd.damping / (2 * I);
    MESSAGE("damped pendulum: decay rate " << decay << " 1/s, expected " << expected << ", relative error "
                                           << (decay - expected) / expected);
    // Measured 4.8e-6 relative (the peak fit); twice or half the
    // damping is 100 % off.
    CHECK(std::fabs(decay - expected) < 1e-3 * expected);
}

TEST_CASE("sim: a spring joint oscillates at sqrt(k / I) and with damping follows the closed-form solution") {
    const a::Pendulum pendulum;
    auto t = xtest::translate(pendulum.assembly());
    const double I = pendulum.pivot_inertia();
    sim::JointDynamics jd;
    jd.stiffness = 4.0 * I;  // w0 = 2 rad/s
    jd.rest = 0.3;
    jd.damping = 0.2 * I;    // zeta w0 = 0.1
    const sim::Model m = pendulum_model(jd, Eigen::Vector3d::Zero(), *t);
    sim::Data d(m);
    sim::initial_state(m, d, {{0, 0, false, 0.0}, {0, 0, true, 0.5}});
    // I x'' + b x' + k x = 0 with x = q - rest: exact for a hinge without gravity.
    const double w0 = std::sqrt(jd.stiffness / I), sigma = jd.damping / (2 * I), wd = std::sqrt(w0 * w0 - sigma * sigma);
    const double x0 = -jd.rest, v0 = 0.5;
    auto exact = [&](double time) {
        return jd.rest + std::exp(-sigma * time) * (x0 * std::cos(wd * time) + (v0 + sigma * x0) / wd * std::sin(wd * time));
    };
    for (const sim::IntegratorKind kind : {sim::IntegratorKind::RK4, sim::IntegratorKind::Euler}) {
        sim::initial_state(m, d, {{0, 0, false, 0.0}, {0, 0, true, 0.5}});
        sim::IntegratorSettings is;
        is.kind = kind;
        is.step = 1e-3;
        double worst = 0;
        while (d.time < 5) {
            sim::fixed_step(m, d, is);
            worst = std::max(worst, std::fabs(d.q[0] - exact(d.time)));
        }
        MESSAGE(std::string(sim::integrator_name(kind)) << ": spring-damper joint off the closed form by " << worst << " rad over 5 s");
        // Measured 3.1e-13 (RK4) and 2.6e-4 (semi-implicit Euler, first order:
        // w0 h = 2e-3). A frequency 1 % off gives ~0.03 rad.
        CHECK(worst < (kind == sim::IntegratorKind::RK4 ? 1e-10 : 1e-3));
    }
}

TEST_CASE("sim: Coulomb friction holds a joint until a slowly rising effort passes its level") {
    // Hinge without gravity, Coulomb level Fc; the effort rises at r.
    const a::Pendulum pendulum;
    auto t = xtest::translate(pendulum.assembly());
    const double I = pendulum.pivot_inertia();
    sim::JointDynamics jd;
    jd.coulomb = 0.5;
    const sim::Model m = pendulum_model(jd, Eigen::Vector3d::Zero(), *t);
    sim::Data d(m);
    sim::initial_state(m, d, {});
    const double rate = 0.25, vc = m.coulomb_velocity;  // N m/s; regularisation speed
    const double t_stick = jd.coulomb / rate;           // 2 s
    // The regularised law is stiff: d(friction)/d(qd) / I = Fc / (vc I) =
    // 5000 1/s here, past RK4's stability bound 2.8 / h at 1 ms; 0.1 ms is inside it.
    const double h = 1e-4;
    double q_at_90 = 0, qd_at_90 = 0;
    while (d.time < t_stick + 0.5 - 1e-12) {
        d.effort[0] = rate * (d.time + h / 2);  // held over the step at its mid value
        sim::fixed_step(m, d, rk4(h));
        if (std::fabs(d.time - 0.9 * t_stick) < h / 2) q_at_90 = d.q[0], qd_at_90 = d.v[0];
    }
    // Below the level the regularised law creeps at vc atanh(F / Fc)
    // (quasi-static: the creep's time constant I vc / Fc is 0.2 ms): 1.47 vc
    // at 90 %, having moved vc t_stick (x atanh x + ln(1 - x^2) / 2) by then.
    const double creep = vc * std::atanh(0.9);
    const double crept = vc * t_stick * (0.9 * std::atanh(0.9) + 0.5 * std::log(1 - 0.81));
    MESSAGE("Coulomb: at 90 % of the level q " << q_at_90 << " rad (creep law " << crept << "), qd " << qd_at_90
                                              << " rad/s (creep law " << creep << "); 0.5 s past it qd " << d.v[0]
                                              << " rad/s");
    CHECK(std::fabs(qd_at_90 - creep) < 0.02 * creep);
    CHECK(std::fabs(q_at_90 - crept) < 0.02 * crept);
    // Past the level it slides: I qdd = r (t - t_stick), so qd = r dt^2 / (2 I)
    // plus what the creep had (within a few vc).
    const double slide = rate * 0.25 / (2 * I);
    CHECK(d.v[0] > 0.9 * slide);
    CHECK(d.v[0] < slide + 10 * vc);
}

TEST_CASE("sim: a position limit holds its joint against a steady effort") {
    const a::Pendulum pendulum;
    auto t = xtest::translate(pendulum.assembly());
    sim::JointDynamics jd;
    jd.limited = true;
    jd.lower = -0.2;
    jd.upper = 0.1;
    const sim::Model m = pendulum_model(jd, Eigen::Vector3d::Zero(), *t);
    sim::Data d(m);
    sim::initial_state(m, d, {});
    const double effort = 0.3;  // N m
    d.effort[0] = effort;
    double overshoot = 0;
    while (d.time < 1.5) {
        sim::fixed_step(m, d, rk4(1e-3));
        overshoot = std::max(overshoot, d.q[0] - jd.upper);
    }
    // The limit is a spring k = I w^2, w = 1 / (time constant * zeta) = 50 1/s
    // (BuildOptions' defaults), critically damped: at rest it gives way by F / k.
    const double k = m.joints[0].dynamics.limit_stiffness;
    CHECK(std::fabs(k - pendulum.pivot_inertia() * 2500) < 1e-9 * k);
    MESSAGE("limit: rests at " << d.q[0] << " rad (limit " << jd.upper << ", F/k " << effort / k << "), overshoot "
                               << overshoot << " rad");
    CHECK(std::fabs(d.q[0] - (jd.upper + effort / k)) < 1e-6);
    CHECK(std::fabs(d.v[0]) < 1e-6);
    CHECK(overshoot < 0.05);
}
}  // namespace MBX_UNITY_ID
