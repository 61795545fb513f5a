// Coulomb friction in the accurate mode (sim/cvode_session.h): a joint is
// held exactly while the effort that holds it is within its Coulomb limit,
// slips once the load passes it, and sticks again where it comes to rest.
// Every number from the rigid rotor's closed-form motion: the pendulum
// assembly with no gravity turns about its hinge with inertia I.
#include <cmath>
#include <cstdio>

#include "tests/export/export_fixture.h"
#include "tests/export/mujoco_assemblies.h"
#include "sim/build_model.h"
#include "sim/cvode_session.h"
#include "tests/common/near.h"

namespace MBX_UNITY_ID {

using namespace mbx;

namespace {

struct Rotor {
    xtest::mjcf_assemblies::Pendulum shape;
    sim::Model model;
    double inertia = 0;
};

Rotor rotor(double coulomb) {
    Rotor r;
    auto t = xtest::translate(r.shape.assembly());
    sim::BuildOptions options;
    options.gravity = Eigen::Vector3d::Zero();
    const sim::Model bare = sim::build_model(*t->mechanism, options);
    REQUIRE(bare.nv == 1);
    sim::JointDynamics jd;
    jd.coulomb = coulomb;
    options.joint_dynamics[bare.joints[0].source] = jd;
    r.model = sim::build_model(*t->mechanism, options);
    r.inertia = r.shape.pivot_inertia();
    return r;
}

struct Sample {
    double t, q, qd;
    int mode;
};

std::vector<Sample> run_accurate(const sim::Model& m, sim::Data& d, double stop, double every, const sim::InputFunction& inputs) {
    sim::IntegratorSettings is;
    is.kind = sim::IntegratorKind::Accurate;
    is.tolerance = 1e-10;
    is.step = 0;
    sim::AccurateRequest r;
    r.stop_time = stop;
    for (int k = 1; k * every <= stop * (1 + 1e-12); ++k) r.sample_times.push_back(k * every);
    std::vector<Sample> out;
    r.sample = [&](sim::Data& at) { out.push_back({at.time, at.q[0], at.v[0], sim::friction_mode(at, 0)}); };
    r.inputs = inputs;
    sim::accurate_advance(m, d, is, r);
    return out;
}

}  // namespace

TEST_CASE("sim accurate: a joint under a slowly rising effort stays exactly still until the effort passes Coulomb's limit") {
    const double Fc = 0.8, rate = 0.4, t_slip = Fc / rate;  // the effort reaches Fc at 2 s
    Rotor r = rotor(Fc);
    sim::Data d(r.model);
    const double q0 = d.q[0];
    auto ramp = [&](double t, sim::Data& at) { at.effort[0] = rate * t; };
    const std::vector<Sample> s = run_accurate(r.model, d, 3.0, 0.01, ramp);
    REQUIRE(s.size() == 300);
    double moved_before = 0, worst_after = 0, end_relative = 0;
    for (const Sample& x : s) {
        if (x.t < t_slip - 1e-9) {
            moved_before = std::max(moved_before, std::fabs(x.q - q0));
            CHECK(x.qd == 0.0);
            CHECK(x.mode == 0);
        } else if (x.t > t_slip + 0.05) {
            // Past the limit the net effort is rate (t - t*): q = rate (t - t*)^3 / (6 I).
            const double tau = x.t - t_slip;
            const double q_exact = rate * tau * tau * tau / (6 * r.inertia);
            worst_after = std::max(worst_after, std::fabs(x.q - q0 - q_exact));
            end_relative = std::fabs(x.q - q0 - q_exact) / q_exact;
            CHECK(x.mode == 1);
        }
    }
    CHECK(moved_before < 1e-12);
    CHECK(worst_after < 1e-8);    // rad, through the slip phase
    CHECK(end_relative < 1e-6);   // at 3 s, where q = rate / (6 I)
    CHECK(d.stats.mode_switches == 1);

    // The regularised fixed-step law (-Fc tanh(qd / v_c)) cannot hold: it
    // creeps at v_c atanh(e / Fc) under a load e below the limit. Its
    // quasi-static creep to t: (Fc / rate) v_c [x atanh x + ln(1 - x^2) / 2], x = rate t / Fc.
    sim::Data f(r.model);
    sim::IntegratorSettings rk4;
    rk4.kind = sim::IntegratorKind::RK4;
    rk4.step = 1e-4;  // Fc / (v_c I) ~ 8000 / s: RK4 needs h well under 3e-4 s to be stable
    const double t_check = 1.9;
    while (f.time < t_check - 1e-9) {
        f.effort[0] = rate * (f.time + 0.5 * rk4.step);
        sim::fixed_step(r.model, f, rk4);
    }
    const double x = rate * t_check / Fc, vc = r.model.coulomb_velocity;
    const double creep_expected = (Fc / rate) * vc * (x * std::atanh(x) + 0.5 * std::log(1 - x * x));
    const double creep = f.q[0] - q0;
    CHECK(creep == mbx_test::relative(creep_expected, 0.02));
    std::printf("[accurate friction] rising effort: accurate mode moved %.3g rad before the limit (exact: 0), "
                "slip phase within %.3g rad of rate (t - t*)^3 / (6 I) (%.3g relative at 3 s); regularised RK4 "
                "(0.1 ms) crept %.4g rad by t = %.1f s (quasi-static estimate %.4g rad); %lld evaluations, %lld steps\n",
                moved_before, worst_after, end_relative, creep, t_check, creep_expected, d.stats.evaluations,
                d.stats.steps);
}

TEST_CASE("sim accurate: a joint sliding to rest under a load within the limit sticks there") {
    const double Fc = 0.8, E = 0.4, w0 = 2.0;
    Rotor r = rotor(Fc);
    sim::Data d(r.model);
    const double q0 = d.q[0];
    d.v[0] = w0;
    d.effort[0] = E;  // pushes along the motion; half the limit, so once at rest it is held
    const double decel = (Fc - E) / r.inertia;
    const double t_rest = w0 / decel, q_rest = q0 + w0 * w0 / (2 * decel);
    const std::vector<Sample> s = run_accurate(r.model, d, 2.0, 0.01, {});
    REQUIRE(t_rest < 1.5);
    double worst_slide = 0;
    for (const Sample& x : s) {
        if (x.t < t_rest - 1e-6) {
            const double q_exact = q0 + w0 * x.t - 0.5 * decel * x.t * x.t;
            worst_slide = std::max(worst_slide, std::fabs(x.q - q_exact));
            CHECK(x.mode == 1);
        } else if (x.t > t_rest + 1e-6) {
            CHECK(x.qd == 0.0);
            CHECK(x.mode == 0);
            CHECK(x.q == s.back().q);  // held exactly, not creeping
        }
    }
    CHECK(worst_slide < 1e-9);
    CHECK(std::fabs(d.q[0] - q_rest) < 1e-9);
    CHECK(d.v[0] == 0.0);
    CHECK(d.stats.mode_switches == 1);

    // The regularised law keeps moving at v_c atanh(E / Fc) once it has slowed down.
    sim::Data f(r.model);
    f.v[0] = w0;
    f.effort[0] = E;
    sim::IntegratorSettings rk4;
    rk4.kind = sim::IntegratorKind::RK4;
    rk4.step = 1e-4;
    for (int k = 0; k < 20000; ++k) sim::fixed_step(r.model, f, rk4);
    const double creep_speed = r.model.coulomb_velocity * std::atanh(E / Fc);
    CHECK(f.v[0] == mbx_test::relative(creep_speed, 0.01));
    std::printf("[accurate friction] slide to rest: accurate q(2 s) - q_rest = %.3g rad, qd = %g exactly, slide within "
                "%.3g rad of the parabola; regularised RK4 at 2 s: %.4g rad past the rest point, still creeping at "
                "%.4g rad/s (v_c atanh(E/Fc) = %.4g)\n",
                d.q[0] - q_rest, d.v[0], worst_slide, f.q[0] - q_rest, f.v[0], creep_speed);
}

TEST_CASE("sim accurate: a run whose efforts become non-finite stops with an error naming the time") {
    Rotor r = rotor(0);
    sim::Data d(r.model);
    d.v[0] = 1;
    auto broken = [](double t, sim::Data& at) { at.effort[0] = t < 0.5 ? 0.1 : NAN; };
    try {
        run_accurate(r.model, d, 1.0, 0.1, broken);
        FAIL("the run should have stopped");
    } catch (const Error& e) {
        CHECK(e.status() == MBX_ERROR_SIMULATION);
        const std::string what = e.what();
        CAPTURE(what);
        // The run cannot pass t = 0.5 s: the message names where it stopped.
        const size_t at = what.find("t = ");
        REQUIRE(at != std::string::npos);
        CHECK(std::stod(what.substr(at + 4)) == mbx_test::relative(0.5, 1e-9));
        CHECK(what.find("step size underflowed") != std::string::npos);
        // The state is the last accepted one, before the failure.
        CHECK(d.time <= 0.5);
        CHECK(std::isfinite(d.q[0]));
    }
}
}  // namespace MBX_UNITY_ID
