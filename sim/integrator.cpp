#include "sim/integrator.h"

#include <algorithm>
#include <cmath>

#include "core/heartbeat.h"
#include "core/text_format.h"
#include "sim/cvode_session.h"

namespace mbx::sim {

const char* integrator_name(IntegratorKind k) {
    switch (k) {
    case IntegratorKind::Euler: return "euler";
    case IntegratorKind::RK4: return "rk4";
    case IntegratorKind::Accurate: return "accurate";
    }
    return "?";
}

bool parse_integrator(const std::string& word, IntegratorKind& out) {
    for (IntegratorKind k : {IntegratorKind::Euler, IntegratorKind::RK4, IntegratorKind::Accurate})
        if (word == integrator_name(k)) {
            out = k;
            return true;
        }
    return false;
}

void add_applied_forces(const Model& m, Data& d) {
    update_kinematics(m, d);
    d.qfrc_applied.setZero(m.nv);
    d.applied_forces->apply(m, d);
    d.qfrc_total += d.qfrc_applied;
}

void evaluate(const Model& m, Data& d, FrictionLaw law, const std::vector<char>* stuck, double step,
              bool positions_ready) {
    passive_forces(m, d, law, stuck, step);
    drive_forces(m, d);
    d.qfrc_total = d.effort + d.qfrc_passive + d.qfrc_drive;
    apply_transmissions(m, d);
    if (d.applied_forces) add_applied_forces(m, d);
    forward_dynamics<double>(m, d, nullptr, nullptr, positions_ready);
    ++d.stats.evaluations;
}

void check_finite_state(const Model& m, const Data& d, const char* when, mbx_status status) {
    for (size_t i = 0; i < m.transmissions.size(); ++i)
        if (!std::isfinite(d.motor_q[Eigen::Index(i)]) || !std::isfinite(d.motor_v[Eigen::Index(i)])) {
            const JointT<double>& j = m.joints[size_t(m.transmissions[i].joint)];
            throw Error(status, j.subject(), std::string("the motor of joint '") + j.name + "' has a non-finite position or velocity " + when);
        }
    for (const JointT<double>& j : m.joints) {
        const bool finite = d.q.segment(j.q_index, j.nq()).allFinite() && d.v.segment(j.v_index, j.nv()).allFinite();
        if (!finite)
            throw Error(status, j.subject(),
                        std::string("joint '") + j.name + "' has a non-finite position or velocity " + when);
    }
}

double close_loops(const Model& m, Data& d, double tolerance, bool warm, Eigen::VectorXd* moved) {
    if (m.closures.empty()) return 0;
    const double scaled = tolerance / m.length_scale;
    if (!project_positions(m, d, d.closure_factor, scaled, 50, nullptr, warm, moved)) {
        const int worst = worst_closure(m, d.residual);
        const LoopClosureT<double>& c = m.closures[size_t(worst < 0 ? 0 : worst)];
        throw Error(MBX_ERROR_INVALID_INPUT, c.subject(),
                    "the loop closed by cut joint '" + c.name + "' cannot be closed (residual " +
                        readable(d.residual.lpNorm<Eigen::Infinity>() * m.length_scale) + ")");
    }
    project_velocities(m, d, d.closure_factor, nullptr, false);
    if (warm) d.q_closed = d.q;
    return d.residual.lpNorm<Eigen::Infinity>() * m.length_scale;
}

namespace {

void fixed_step_unguarded(const Model& m, Data& d, const IntegratorSettings& settings) {
    RunStats& stats = d.stats;
    const double h = settings.step;
    update_controllers(m, d, d.time);
    const FrictionLaw law = FrictionLaw::Regularised;
    const bool positions_ready = d.q_closed.size() == d.q.size() && d.q_closed == d.q;
    d.q_closed.resize(0);
    auto advance_from_start = [&](const Eigen::VectorXd& v, double dt) {
        d.q = d.q_start;
        for (const JointT<double>& j : m.joints) integrate_joint<double>(j.kind, d.q.data() + j.q_index, v.data() + j.v_index, dt);
    };
    if (settings.kind == IntegratorKind::Euler) {
        // Semi-implicit: the new velocity moves the positions (MuJoCo's Euler).
        evaluate(m, d, law, nullptr, h, positions_ready);
        d.v += h * d.qacc;
        d.motor_v += h * d.motor_acc;
        d.motor_q += h * d.motor_v;
        if (!m.closures.empty()) {
            // The step leaves the closures off by h^2/2 Jdot v = -h^2/2 gamma
            // to second order; moving back by the minimum-norm J x = gamma
            // (the dynamics' particular acceleration, at hand) leaves the
            // chord steps of close_loops a third-order rest.
            d.tmp_v2 = d.v;
            d.tmp_v2.noalias() -= (0.5 * h) * d.qacc_particular;
            // The third-order rest varies smoothly along the motion: the
            // last three steps' corrections, extrapolated (quadratically: a
            // linear extrapolation misses by their second difference, which
            // alone is ~10 times the tolerance on the six-bar) and added
            // here, leave the chord steps little (when the last steps ended
            // where the next ones began). So does the residual the last step
            // left within the tolerance, removed now rather than carried.
            if (!positions_ready) d.carry_count = 0;
            if (d.carry_count == 0)
                d.closure_moved.setZero(m.nv);
            else if (d.carry_count == 1)
                d.closure_moved = d.closure_carry;
            else if (d.carry_count == 2)
                d.closure_moved = 2 * d.closure_carry - d.closure_carry_before;
            else
                d.closure_moved = 3 * (d.closure_carry - d.closure_carry_before) + d.closure_carry_oldest;
            d.tmp_v2.noalias() += (1 / h) * d.closure_moved;
            if (d.carry_count > 0) d.tmp_v2.noalias() += (1 / h) * d.closure_leftover;
        } else {
            d.tmp_v2 = d.v;
        }
        for (const JointT<double>& j : m.joints)
            integrate_joint<double>(j.kind, d.q.data() + j.q_index, d.tmp_v2.data() + j.v_index, h);
    } else {
        // Classical RK4 on (q, v), positions moved on their manifold from the
        // step's start by each stage's velocity (as MuJoCo's RK4 does).
        static constexpr double c[4] = {0, 0.5, 0.5, 1}, w[4] = {1, 2, 2, 1};
        d.v_sum.setZero();
        d.a_sum.setZero();
        d.v_stage = d.v_start;
        // The motors (elastic transmissions) are stepped alongside.
        const bool motors = !m.transmissions.empty();
        if (motors) d.motor_v_sum.setZero(), d.motor_a_sum.setZero(), d.motor_v_stage = d.motor_v_start;
        for (int s = 0; s < 4; ++s) {
            if (s > 0) {
                advance_from_start(d.v_stage, c[s] * h);
                d.v_stage = d.v_start + (c[s] * h) * d.qacc;
                d.v = d.v_stage;
                if (motors) {
                    d.motor_q = d.motor_q_start + (c[s] * h) * d.motor_v_stage;
                    d.motor_v_stage = d.motor_v_start + (c[s] * h) * d.motor_acc;
                    d.motor_v = d.motor_v_stage;
                }
            }
            evaluate(m, d, law, nullptr, h, s == 0 && positions_ready);
            d.v_sum += w[s] * d.v_stage;
            d.a_sum += w[s] * d.qacc;
            if (motors) d.motor_v_sum += w[s] * d.motor_v_stage, d.motor_a_sum += w[s] * d.motor_acc;
        }
        advance_from_start(d.v_sum, h / 6);
        d.v = d.v_start + (h / 6) * d.a_sum;
        if (motors) {
            d.motor_q = d.motor_q_start + (h / 6) * d.motor_v_sum;
            d.motor_v = d.motor_v_start + (h / 6) * d.motor_a_sum;
        }
    }
    d.time += h;
    ++stats.steps;
    if (!(d.q.allFinite() && d.v.allFinite() && d.motor_q.allFinite() && d.motor_v.allFinite()))
        check_finite_state(m, d, ("at t = " + readable(d.time) + " s: the run diverged").c_str(), MBX_ERROR_SIMULATION);
    const bool carry = settings.kind == IntegratorKind::Euler && !m.closures.empty();
    stats.max_closure_residual = std::max(stats.max_closure_residual,
                                          close_loops(m, d, settings.closure_tolerance, true, carry ? &d.closure_moved : nullptr));
    if (carry) {
        // Only the correction across the closures carries over (its part
        // along the motion would push every later step the same way): its
        // minimum-norm part for the rows at the closed positions, counting
        // the residual left within the tolerance as corrected (so that the
        // history is the smooth correction the step needed, not one cut
        // short by wherever the chord steps stopped).
        d.closure_rhs = -d.residual;
        d.closure_leftover = d.closure_factor.particular(d.closure_rhs);
        d.closure_rhs.noalias() += d.J * d.closure_moved;
        d.closure_moved = d.closure_factor.particular(d.closure_rhs);
        std::swap(d.closure_carry_oldest, d.closure_carry_before);
        std::swap(d.closure_carry_before, d.closure_carry);
        std::swap(d.closure_carry, d.closure_moved);
        d.carry_count = std::min(d.carry_count + 1, 3);
    }
    if (d.applied_forces) {
        // At the step's end state, which the next step starts from.
        update_kinematics(m, d);
        d.applied_forces->step_taken(m, d);
    }
}

}  // namespace

void fixed_step(const Model& m, Data& d, const IntegratorSettings& settings) {
    // A failed step leaves the last good state (the caller may report it or retry).
    d.q_start = d.q;
    d.v_start = d.v;
    d.motor_q_start = d.motor_q;
    d.motor_v_start = d.motor_v;
    const double t0 = d.time;
    try {
        fixed_step_unguarded(m, d, settings);
    } catch (...) {
        d.q = d.q_start, d.v = d.v_start, d.time = t0;
        d.motor_q = d.motor_q_start, d.motor_v = d.motor_v_start;
        throw;
    }
}

void advance(const Model& m, Data& d, const IntegratorSettings& settings, double t_end) {
    if (!std::isfinite(t_end))
        throw Error(MBX_ERROR_INVALID_ARGUMENT, Subject::model(m.name), "the end time is not finite");
    if (settings.kind == IntegratorKind::Accurate) {
        AccurateRequest request;
        request.stop_time = t_end;
        accurate_advance(m, d, settings, request);
        return;
    }
    if (!(settings.step > 0)) throw Error(MBX_ERROR_INVALID_ARGUMENT, Subject::model(m.name), "the step must be positive");
    // Times from a step count, so that no round-off accumulates over long runs.
    const double t0 = d.time;
    const double span = t_end - t0;
    if (span <= 0) return;
    // Whole steps up to t_end (within a billionth of a step, so that an end
    // time carrying round-off does not add a sliver of a step), then the rest.
    const double tolerance = 1e-9 * settings.step;
    if (!(span / settings.step < 9e15))
        throw Error(MBX_ERROR_INVALID_ARGUMENT, Subject::model(m.name),
                    "advancing by " + readable(span) + " s in steps of " + readable(settings.step) +
                        " s would take more steps than can be counted");
    const long long whole = (long long)std::floor((span + tolerance) / settings.step);
    for (long long k = 1; k <= whole; ++k) {
        fixed_step(m, d, settings);
        d.time = t0 + double(k) * settings.step;
        heartbeat();
    }
    const double rest = t_end - d.time;
    if (rest > tolerance) {
        IntegratorSettings last = settings;
        last.step = rest;
        fixed_step(m, d, last);
    }
    d.time = t_end;
}

}  // namespace mbx::sim
