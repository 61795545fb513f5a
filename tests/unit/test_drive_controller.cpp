// The drive controller against closed forms (PD on a double integrator,
// velocity loop = PD, integral action, saturation with anti-windup, exact
// delays), then against the real EMPS rig (shared/data/measured/emps): fed
// the logged positions it must give the logged controller output sample by
// sample, and closed around the published plant it must reproduce the
// measured motion and force as well as the authors' own simulation does.
#include <doctest/doctest.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "core/mechatronics/drive_controller.h"
#include "tests/common/near.h"
#include "tests/common/skip.h"
#include "tests/common/shared_data.h"

namespace MBX_UNITY_ID {

using namespace mbx;

namespace {

ControllerSpec pd(double kp, double kd) {
    ControllerSpec c;
    c.kp = kp;
    c.kd = kd;
    return c;
}

// Unit mass double integrator q'' = u + disturbance, the controller called
// once per step and its output held over the step (semi-implicit Euler).
struct DoubleIntegrator {
    double q = 0, v = 0;
    void step(double u, double h) {
        v += u * h;
        q += v * h;
    }
};

// ---- EMPS data --------------------------------------------------------------

constexpr double kKp = 160.18, kKv = 243.45, kTs = 1e-3, kUsat = 10;  // emps_constants.csv
constexpr double kGtau = 35.15065188248547;                            // N/V
// IDIM-LS parameters (NOTES.md): M q'' = F - Fv q' - Fc sign(q') - offset.
constexpr double kM = 95.11, kFv = 203.5, kFc = 20.39, kOffset = -3.16;
constexpr double kEncoderStep = 5e-8;  // m: the train record's positions are multiples of it

struct Emps {
    std::vector<double> t, ref, q, u, force, pulse;
    std::size_t size() const { return t.size(); }
};

// Columns t_s,q_ref_m,q_meas_m,u_drive_V,force_N[,pulse_cmd] (pulse 0 when
// absent); the test is skipped when the shared folder is not beside the
// repository.
Emps load_emps(const std::string& name) {
    Emps d;
    const std::string path = mbx_test::shared_data("measured/emps/" + name);
    std::ifstream in(path, std::ios::binary);
    REQUIRE_MESSAGE(in, "cannot read " << path);
    std::ostringstream buf;
    buf << in.rdbuf();
    const std::string text = buf.str();
    const char* p = text.data();
    const char* end = p + text.size();
    const char* header_end = std::find(p, end, '\n');
    const bool pulses = std::string(p, header_end).find("pulse_cmd") != std::string::npos;
    p = header_end;
    std::vector<double>* cols[] = {&d.t, &d.ref, &d.q, &d.u, &d.force, &d.pulse};
    const int ncols = pulses ? 6 : 5;
    bool ok = true;
    while (ok && p < end) {
        while (p < end && (*p == '\n' || *p == '\r')) ++p;
        if (p == end) break;
        for (int c = 0; ok && c < ncols; ++c) {
            double v = 0;
            const auto r = std::from_chars(p, end, v);
            ok = r.ec == std::errc() && (c + 1 == ncols || (r.ptr < end && *r.ptr == ','));
            cols[c]->push_back(v);
            p = r.ptr + (c + 1 < ncols ? 1 : 0);
        }
    }
    REQUIRE_MESSAGE(ok, name << ": unreadable row " << d.t.size());
    if (!pulses) d.pulse.assign(d.t.size(), 0.0);
    REQUIRE(d.size() == 24841);
    return d;
}

ControllerSpec emps_controller(double delay, VelocityEstimate estimate = VelocityEstimate::FilteredDifference,
                               double limit = kUsat) {
    ControllerSpec c;
    c.kp = kKp;
    c.kv = kKv;
    c.sample_period = kTs;
    c.delay = delay;
    c.output_limit = limit;
    c.velocity_estimate = estimate;
    return c;
}

// The controller's output on the logged samples.
std::vector<double> replay(const Emps& d, const ControllerSpec& spec) {
    DriveController ctrl(spec);
    std::vector<double> u(d.size());
    for (std::size_t k = 0; k < d.size(); ++k) u[k] = ctrl.update(d.t[k], d.ref[k], d.q[k], 0.0);
    return u;
}

struct Stats {
    double max = 0, median = 0;
};

Stats abs_stats(std::vector<double> e) {
    for (double& x : e) x = std::fabs(x);
    Stats s;
    s.max = *std::max_element(e.begin(), e.end());
    std::nth_element(e.begin(), e.begin() + static_cast<long>(e.size() / 2), e.end());
    s.median = e[e.size() / 2];
    return s;
}

// The logged controller ran before the record starts, so the first samples
// of the estimate (which needs two past positions) cannot match.
constexpr std::size_t kWarmup = 3;

// Logged output minus the controller's, from kWarmup on, over the samples
// `keep` accepts.
std::vector<double> residual(const Emps& d, const std::vector<double>& u, const std::function<bool(std::size_t)>& keep,
                             double pulse_offset = 0) {
    std::vector<double> r;
    for (std::size_t k = kWarmup; k < d.size(); ++k)
        if (keep(k)) r.push_back(d.u[k] - d.pulse[k] - u[k] - (d.pulse[k] != 0 ? pulse_offset : 0.0));
    return r;
}

double relative_error_percent(const std::vector<double>& y, const std::vector<double>& yhat) {
    double num = 0, den = 0;
    for (std::size_t k = 0; k < y.size(); ++k) {
        num += (y[k] - yhat[k]) * (y[k] - yhat[k]);
        den += y[k] * y[k];
    }
    return 100 * std::sqrt(num / den);
}

struct ClosedLoop {
    std::vector<double> q, force_applied, force_command;
};

// The axis with the IDIM-LS model inside the documented loop: the encoder
// quantizes q, the controller (one-sample delay, +-10 V) samples it at 1 kHz,
// the pulse is added after the saturation and before gtau. RK4 at Ts/10 with
// a smooth Coulomb sign (tanh(v / 1e-4 m/s)).
ClosedLoop simulate_emps(const Emps& d) {
    DriveController ctrl(emps_controller(kTs));
    ClosedLoop out;
    out.q.resize(d.size());
    out.force_applied.resize(d.size());
    out.force_command.resize(d.size());
    // Start on the record's first state.
    double x = d.q[0], v = (d.q[1] - d.q[0]) / kTs;
    constexpr int kSub = 10;
    const double h = kTs / kSub;
    // A second controller without the delay gives the command the rig logs
    // (vir is logged before the delay).
    DriveController logged(emps_controller(0));
    for (std::size_t k = 0; k < d.size(); ++k) {
        const double qm = std::round(x / kEncoderStep) * kEncoderStep;
        const double u = ctrl.update(d.t[k], d.ref[k], qm, 0.0) + d.pulse[k];
        out.q[k] = x;
        out.force_applied[k] = kGtau * u;
        out.force_command[k] = kGtau * (logged.update(d.t[k], d.ref[k], qm, 0.0) + d.pulse[k]);
        const double f = kGtau * u - kOffset;
        const auto acc = [f](double vel) { return (f - kFv * vel - kFc * std::tanh(vel / 1e-4)) / kM; };
        for (int s = 0; s < kSub; ++s) {
            const double a1 = acc(v), v1 = v;
            const double v2 = v + 0.5 * h * a1, a2 = acc(v2);
            const double v3 = v + 0.5 * h * a2, a3 = acc(v3);
            const double v4 = v + h * a3, a4 = acc(v4);
            x += h / 6 * (v1 + 2 * v2 + 2 * v3 + v4);
            v += h / 6 * (a1 + 2 * a2 + 2 * a3 + a4);
        }
    }
    return out;
}

}  // namespace

// ---- construction -----------------------------------------------------------

TEST_CASE("drive controller: specs that cannot work are refused") {
    const double nan = std::numeric_limits<double>::quiet_NaN();
    const double inf = std::numeric_limits<double>::infinity();
    auto refused = [](ControllerSpec c, const char* word) {
        try {
            DriveController ctrl(c);
            FAIL("accepted a spec that should be refused (" << word << ")");
        } catch (const std::invalid_argument& e) {
            CHECK_MESSAGE(std::string(e.what()).find(word) != std::string::npos, e.what());
        }
    };
    ControllerSpec c = pd(1, 1);
    c.kp = -1;
    refused(c, "kp");
    c = pd(1, 1);
    c.kd = nan;
    refused(c, "kd");
    c = pd(1, 1);
    c.output_limit = inf;
    refused(c, "output_limit");
    c = pd(1, 1);
    c.delay = -1e-3;
    refused(c, "delay");
    c = pd(1, 1);
    c.kvi = 1;  // without kv
    refused(c, "kvi");
    c = pd(1, 1);
    c.velocity_estimate = VelocityEstimate::Difference;  // continuous
    refused(c, "sample_period");
    c = pd(1, 1);
    c.sample_period = 1e-3;
    c.delay = 1.5e-3;
    refused(c, "whole number");

    c.delay = 3e-3;  // 2.9999999999999996 samples in floating point
    CHECK_NOTHROW(DriveController{c});
    c.delay = 3e-3 * (1 + 1e-12);
    CHECK_NOTHROW(DriveController{c});
    CHECK_NOTHROW(DriveController{pd(0, 0)});
}

// ---- closed forms -------------------------------------------------------------

TEST_CASE("drive controller: continuous PD on a unit mass gives the critically damped step response") {
    // q'' = kp (1 - q) - kd q' with kp = w^2, kd = 2 w: q = 1 - (1 + w t) e^{-w t}.
    const double w = 3;
    DriveController ctrl(pd(w * w, 2 * w));
    DoubleIntegrator plant;
    const double h = 1e-4;
    double worst = 0;
    for (int i = 0; i <= 60000; ++i) {
        const double t = i * h;
        worst = std::max(worst, std::fabs(plant.q - (1 - (1 + w * t) * std::exp(-w * t))));
        plant.step(ctrl.update(t, 1.0, plant.q, plant.v), h);
    }
    CHECK(worst < 1e-3);
}

TEST_CASE("drive controller: a P position loop around a velocity loop is the PD with kp*kv and kv") {
    ControllerSpec cascade;
    cascade.kp = 4;
    cascade.kv = 3;
    DriveController a(cascade), b(pd(12, 3));
    for (int i = 0; i < 1000; ++i) {
        const double t = 1e-3 * i;
        const double r = std::sin(3 * t), q = 0.7 * std::cos(5 * t), qd = std::sin(11 * t);
        REQUIRE(a.update(t, r, q, qd) == mbx_test::relative(b.update(t, r, q, qd), 1e-12));
    }
}

TEST_CASE("drive controller: integrals advance with the time between calls") {
    // Constant e = 1 at rest, irregular steps: integral(e) = t exactly, so
    // u_p = kp + ki t; the velocity loop's integral takes u_p at the end of
    // each step (backward Euler).
    ControllerSpec c;
    c.kp = 2;
    c.ki = 0.5;
    c.kv = 3;
    c.kvi = 7;
    DriveController ctrl(c);
    double t = 0, iv = 0;
    for (double dt : {0.0, 0.1, 0.02, 0.5, 0.0, 0.33, 1.0}) {
        t += dt;
        const double up = c.kp + c.ki * t;
        iv += up * dt;
        CHECK(ctrl.update(t, 1.0, 0.0, 0.0) == mbx_test::relative(c.kv * up + c.kvi * iv, 1e-12));
    }
    CHECK_THROWS_AS(ctrl.update(t - 0.1, 1, 0, 0), std::invalid_argument);  // time went back
}

TEST_CASE("drive controller: integral action removes a constant disturbance's steady-state error") {
    // q'' = u + d: PD settles at q = r + d / kp; PID (stable as kd kp > ki) at r.
    const double d = -0.5, kp = 4, kd = 4, ki = 2, h = 1e-3;
    auto settle = [&](const ControllerSpec& c) {
        DriveController ctrl(c);
        DoubleIntegrator plant;
        for (int i = 0; i <= 60000; ++i) plant.step(ctrl.update(i * h, 1.0, plant.q, plant.v) + d, h);
        return plant.q - 1.0;
    };
    ControllerSpec pid = pd(kp, kd);
    pid.ki = ki;
    CHECK(settle(pd(kp, kd)) == mbx_test::relative(d / kp, 1e-3));
    CHECK(std::fabs(settle(pid)) < 1e-5);
}

TEST_CASE("drive controller: the output stays within the limit and the integral does not wind up") {
    ControllerSpec c = pd(50, 10);
    c.ki = 20;
    c.output_limit = 2;
    DriveController ctrl(c);
    DoubleIntegrator plant;
    int saturated = 0;
    for (int i = 0; i <= 20000; ++i) {
        const double u = ctrl.update(i * 1e-3, 5.0, plant.q, plant.v);
        REQUIRE(std::fabs(u) <= 2.0);
        saturated += std::fabs(u) == 2.0;
        plant.step(u, 1e-3);
    }
    CHECK(saturated > 100);
    CHECK(plant.q == mbx_test::relative(5.0, 2e-4));

    // Held far from the target for 10 s, the proportional term alone
    // saturates, so the integral must stay at 0: back on target, u = 0
    // (with windup it would be ki * 10 s * 1, clamped to the limit).
    for (double kvi : {0.0, 5.0}) {
        ControllerSpec s;
        s.kp = 10;
        s.ki = kvi == 0 ? 1.0 : 0.0;
        s.kv = kvi == 0 ? 0.0 : 1.0;
        s.kvi = kvi;
        s.output_limit = 1;
        DriveController held(s);
        for (int i = 0; i <= 1000; ++i) CHECK(held.update(i * 0.01, 1.0, 0.0, 0.0) == 1.0);
        CHECK(held.update(10.01, 0.0, 0.0, 0.0) == mbx_test::within(0.0, 1e-9, "a held controller's output is zero, within rounding"));
        // An error back out of the saturation integrates as usual.
        // ki: -0.1 + 1 * (-0.01) * 0.5; kvi: kv u_p + kvi u_p 0.5 with u_p = -0.1.
        CHECK(held.update(10.51, -0.01, 0.0, 0.0) == mbx_test::relative(kvi == 0 ? -0.105 : -0.35, 1e-6));
    }
}

TEST_CASE("drive controller: a continuous delay shifts the output by exactly the delay") {
    ControllerSpec c = pd(3, 0.5);
    c.ki = 2;
    ControllerSpec late = c;
    late.delay = 0.01;
    DriveController now(c), delayed(late);
    const double h = 1e-3;
    std::vector<double> u;
    for (int i = 0; i < 2000; ++i) {
        const double t = i * h, r = std::sin(2 * t) + (t > 0.5), q = 0.3 * std::sin(7 * t), qd = std::cos(3 * t);
        u.push_back(now.update(t, r, q, qd));
        const double ud = delayed.update(t, r, q, qd);
        if (i < 10) REQUIRE(ud == 0.0);
        else REQUIRE(ud == mbx_test::relative(u[static_cast<std::size_t>(i - 10)], 1e-12));
    }
    // Between the calls it interpolates linearly: steps of h/2 now.
    DriveController half(late);
    DriveController ref(c);
    std::vector<double> uref;
    for (int i = 0; i < 100; ++i) uref.push_back(ref.update(i * h, 1.0 + i, 0, 0));
    for (int i = 0; i < 100; ++i) half.update(i * h, 1.0 + i, 0, 0);
    CHECK(half.update(99.5 * h, 100.0, 0, 0) == mbx_test::relative(0.5 * (uref[89] + uref[90]), 1e-6));
    half.reset();
    CHECK(half.update(1.0, 1.0, 0, 0) == 0.0);  // time restarts at the first call after reset
}

TEST_CASE("drive controller: a discrete controller samples, holds and delays by whole samples") {
    ControllerSpec c = pd(2, 0);
    c.ki = 1;
    c.sample_period = 1e-3;
    ControllerSpec late = c;
    late.delay = 3e-3;
    DriveController now(c), delayed(late);
    std::vector<double> per_sample;
    // Called four times per sample with a target that moves continuously.
    for (int i = 0; i < 400; ++i) {
        const double t = i * 0.25e-3, r = 0.5 + std::sin(40 * t);
        const double u = now.update(t, r, 0.0, 0.0), ud = delayed.update(t, r, 0.0, 0.0);
        const auto k = static_cast<std::size_t>(i / 4);
        if (i % 4 == 0) per_sample.push_back(u);
        REQUIRE(u == per_sample[k]);  // held between the instants
        if (k < 3) REQUIRE(ud == 0.0);
        else REQUIRE(ud == per_sample[k - 3]);
    }
    // kp e_k + ki Ts (e_1 + ... + e_k): the first sample has nothing to integrate.
    CHECK(per_sample[10] == mbx_test::relative(2 * (0.5 + std::sin(40 * 0.01)) + 1e-3 * [] {
        double s = 0;
        for (int k = 1; k <= 10; ++k) s += 0.5 + std::sin(40 * k * 1e-3);
        return s;
    }(), 1e-12));
    CHECK_THROWS_AS(now.update(0.1 + 2.5e-3, 0, 0, 0), std::invalid_argument);  // steps over a sample
}

TEST_CASE("drive controller: velocity estimates from the sampled positions") {
    // q = 2 m/s * t, kd = 1: u = -v_est.
    for (auto [estimate, expected] :
         {std::pair{VelocityEstimate::Difference, std::vector<double>{0, -2, -2, -2}},
          std::pair{VelocityEstimate::FilteredDifference, std::vector<double>{0, -1, -2, -2}},
          std::pair{VelocityEstimate::Measured, std::vector<double>{-5, -5, -5, -5}}}) {
        ControllerSpec c = pd(0, 1);
        c.sample_period = 0.01;
        c.velocity_estimate = estimate;
        DriveController ctrl(c);
        for (int k = 0; k < 4; ++k) CHECK(ctrl.update(0.01 * k, 0, 2 * 0.01 * k, 5.0) == mbx_test::relative_to(expected[k], 5.0, 1e-9));
        ctrl.reset();
        CHECK(ctrl.update(1.0, 0, 7.0, 5.0) == mbx_test::relative_to(expected[0], 5.0, 1e-9));  // no past samples after reset
    }
}

// ---- EMPS: the real rig's controller ----------------------------------------------

TEST_CASE("drive controller: reproduces the EMPS rig's logged controller output (train record)") {
    const Emps d = load_emps("emps_train.csv");
    if (d.size() == 0) return;
    const auto all = [](std::size_t) { return true; };
    // Measured: max 0.0123 V, median 1.22e-4 V, against one encoder count
    // (5e-8 m) worth 2e-3 V through kp kv and 6e-3 V through the estimate.
    const Stats right = abs_stats(residual(d, replay(d, emps_controller(0)), all));
    MESSAGE("EMPS train, u error: max " << right.max << " V, median " << right.median << " V");
    CHECK(right.max < 0.03);
    CHECK(right.median < 1e-3);
    // The wrong structures do not: plain difference (max 0.18 V), a one-sample
    // delay before the logged point (max 0.37 V).
    const Stats difference = abs_stats(residual(d, replay(d, emps_controller(0, VelocityEstimate::Difference)), all));
    const Stats delayed = abs_stats(residual(d, replay(d, emps_controller(kTs)), all));
    CHECK(difference.max > 0.1);
    CHECK(difference.median > 1e-3);
    CHECK(delayed.max > 0.3);
    CHECK(delayed.median > 1e-3);
}

TEST_CASE("drive controller: reproduces the EMPS rig's logged controller output (pulse record)") {
    const Emps d = load_emps("emps_test_pulses.csv");
    if (d.size() == 0) return;
    // The logged vir is the controller output plus the pulse. Two findings
    // in this record: (1) it is not clamped at 10 V (14 samples reach
    // -10.91 V before the pulse is added), so the rig's saturation, if any,
    // acts after the logging point: the ±10 V is the authors' Simulink
    // model's; compare without it. (2) During the pulse vir exceeds the
    // controller output by 5.0695 V, not by pulse_cmd = 5: a constant
    // 0.069 V (1.4 %, 2.4 N) that no controller structure explains.
    const auto off = [&](std::size_t k) { return d.pulse[k] == 0; };
    const auto on = [&](std::size_t k) { return d.pulse[k] != 0; };
    const std::vector<double> u = replay(d, emps_controller(0, VelocityEstimate::FilteredDifference, 0));
    const Stats off_pulse = abs_stats(residual(d, u, off));
    std::vector<double> on_raw = residual(d, u, on);
    double mean_on = 0;
    for (double r : on_raw) mean_on += r / static_cast<double>(on_raw.size());
    const Stats on_pulse = abs_stats(residual(d, u, on, mean_on));
    // Measured: off the pulse max 0.0324 V, median 0.0027 V (the positions of
    // this record are not on the encoder grid, so they are not exactly
    // what the controller read); on the pulse offset 0.0695 V, then max
    // 0.040 V, median 0.0027 V.
    MESSAGE("EMPS pulses, u error off the pulse: max " << off_pulse.max << " V, median " << off_pulse.median
                                                         << " V; on the pulse: offset " << mean_on << " V, max "
                                                         << on_pulse.max << " V, median " << on_pulse.median << " V");
    CHECK(off_pulse.max < 0.05);
    CHECK(off_pulse.median < 5e-3);
    CHECK(mean_on == mbx_test::relative(0.0695, 0.02));
    CHECK(on_pulse.max < 0.05);
    CHECK(on_pulse.median < 5e-3);

    const Stats difference =
        abs_stats(residual(d, replay(d, emps_controller(0, VelocityEstimate::Difference, 0)), off));
    const Stats delayed =
        abs_stats(residual(d, replay(d, emps_controller(kTs, VelocityEstimate::FilteredDifference, 0)), off));
    const Stats saturated = abs_stats(residual(d, replay(d, emps_controller(0)), on, mean_on));
    CHECK(difference.max > 0.2);
    CHECK(delayed.max > 0.5);
    CHECK(delayed.median > 5e-3);
    CHECK(saturated.max > 0.5);
}

TEST_CASE("drive controller: closed around the published EMPS plant it reproduces the measured motion and force") {
    // Relative error 100 ||y - yhat|| / ||y||. Published for the authors'
    // closed-loop simulation with the same parameters: train 0.0138 %
    // (position) and 5.85 % (force), test 0.0080 % and 8.94 %.
    // Measured here: train 0.00157 % and 5.88 %, test 0.00255 % and 8.71 %,
    // with the force the model applies (gtau (delayed u + pulse)), which is
    // what reproduces the published force figures. Against the command as
    // logged (before the delay, like vir) the force errors are 6.94 % and 10.05 %.
    struct Case {
        const char* file;
        double position, force, command;
    };
    for (const Case& c : {Case{"emps_train.csv", 0.005, 6.5, 7.5}, Case{"emps_test_pulses.csv", 0.005, 9.5, 10.5}}) {
        const Emps d = load_emps(c.file);
        if (d.size() == 0) return;
        const ClosedLoop sim = simulate_emps(d);
        const double position = relative_error_percent(d.q, sim.q);
        const double force = relative_error_percent(d.force, sim.force_applied);
        const double command = relative_error_percent(d.force, sim.force_command);
        MESSAGE(std::string(c.file) << ": position " << position << " %, force " << force << " % (command " << command << " %)");
        CHECK(position < c.position);
        CHECK(force < c.force);
        CHECK(command < c.command);
    }
}
}  // namespace MBX_UNITY_ID
