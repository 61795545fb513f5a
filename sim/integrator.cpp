#include "sim/integrator.h"

#include <cmath>

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

void evaluate(const Model& m, Data& d, FrictionLaw law, const std::vector<char>* stuck) {
    passive_forces(m, d, law, stuck);
    drive_forces(m, d);
    d.qfrc_total = d.effort + d.qfrc_passive + d.qfrc_drive;
    forward_dynamics(m, d);
    ++d.stats.evaluations;
}

void check_finite_state(const Model& m, const Data& d, const char* when) {
    for (const JointT<double>& j : m.joints) {
        const bool finite = d.q.segment(j.q_index, j.nq()).allFinite() && d.v.segment(j.v_index, j.nv()).allFinite();
        if (!finite)
            throw Error(MBX_ERROR_INVALID_INPUT, j.subject(),
                        std::string("joint '") + j.name + "' has a non-finite position or velocity " + when);
    }
}

double close_loops(const Model& m, Data& d, double tolerance) {
    if (m.closures.empty()) return 0;
    const double scaled = tolerance / m.length_scale;
    if (!project_positions(m, d, d.closure_factor, scaled)) {
        const int worst = worst_closure(m, d.residual);
        const LoopClosureT<double>& c = m.closures[size_t(worst < 0 ? 0 : worst)];
        throw Error(MBX_ERROR_INVALID_INPUT, c.subject(),
                    "the loop closed by cut joint '" + c.name + "' cannot be closed (residual " +
                        std::to_string(d.residual.lpNorm<Eigen::Infinity>() * m.length_scale) + ")");
    }
    project_velocities(m, d, d.closure_factor);
    return d.residual.lpNorm<Eigen::Infinity>() * m.length_scale;
}

void fixed_step(const Model& m, Data& d, const IntegratorSettings& settings) {
    RunStats& stats = d.stats;
    const double h = settings.step;
    update_controllers(m, d, d.time);
    const FrictionLaw law = FrictionLaw::Regularised;
    auto advance = [&](Eigen::VectorXd& q, const Eigen::VectorXd& v, double dt) {
        for (const JointT<double>& j : m.joints) integrate_joint<double>(j.kind, q.data() + j.q_index, v.data() + j.v_index, dt);
    };
    if (settings.kind == IntegratorKind::Euler) {
        // Semi-implicit: the new velocity moves the positions (MuJoCo's Euler).
        evaluate(m, d, law);
        d.v += h * d.qacc;
        advance(d.q, d.v, h);
    } else {
        const Eigen::VectorXd q0 = d.q, v0 = d.v;
        Eigen::VectorXd v_sum = Eigen::VectorXd::Zero(m.nv), a_sum = Eigen::VectorXd::Zero(m.nv);
        const double c[4] = {0, 0.5, 0.5, 1}, w[4] = {1, 2, 2, 1};
        Eigen::VectorXd v_stage = v0, a_stage = Eigen::VectorXd::Zero(m.nv);
        for (int s = 0; s < 4; ++s) {
            if (s > 0) {
                d.q = q0;
                advance(d.q, v_stage, c[s] * h);
                v_stage = v0 + c[s] * h * a_stage;
                d.v = v_stage;
            }
            evaluate(m, d, law);
            a_stage = d.qacc;
            v_sum += w[s] * v_stage;
            a_sum += w[s] * a_stage;
        }
        d.q = q0;
        advance(d.q, v_sum, h / 6);
        d.v = v0 + (h / 6) * a_sum;
    }
    d.time += h;
    ++stats.steps;
    check_finite_state(m, d, "after a step: the run diverged");
    stats.max_closure_residual = std::max(stats.max_closure_residual, close_loops(m, d, settings.closure_tolerance));
}

}  // namespace mbx::sim
