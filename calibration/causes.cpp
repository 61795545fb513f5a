#include "calibration/causes.h"

#include <cmath>

namespace mbx::calibration {

double sign_speed(const RegressionRows& rows, int dof) {
    const double rms = std::sqrt(rows.qd.col(dof).squaredNorm() / double(std::max(1, rows.samples)));
    return std::max(1e-9, 0.01 * rms);
}

namespace {

int actuated_index(const RegressionRows& rows, int dof) {
    for (size_t a = 0; a < rows.actuated.size(); ++a)
        if (rows.actuated[a] == dof) return int(a);
    return -1;
}

}  // namespace

Eigen::MatrixXd Candidate::columns(const RegressionRows& rows) const {
    const Eigen::Index A = Eigen::Index(rows.actuated.size()), S = rows.samples;
    Eigen::MatrixXd c = Eigen::MatrixXd::Zero(S * A, Eigen::Index(parameters.size()));
    const int a = dof >= 0 ? actuated_index(rows, dof) : -1;
    auto put = [&](Eigen::Index s, int col, Eigen::Index at, double v) { c(s * A + at, col) = rows.weight[size_t(at)] * v; };
    for (Eigen::Index s = 0; s < S; ++s) {
        if (cause == "mass_error") {
            for (Eigen::Index k = 0; k < A; ++k) put(s, 0, k, rows.effort_of_body[size_t(body)](s, k));
            continue;
        }
        if (cause == "sensor_offset") {
            // A reading off by o puts the model at q - o: its effort changes by -o dtau/dq.
            for (Eigen::Index k = 0; k < A; ++k) put(s, 0, k, -rows.effort_by_position[size_t(dof)](s, k));
            continue;
        }
        if (a < 0) continue;
        const double v = rows.qd(s, dof);
        const double sgn = std::tanh(v / sign_speed(rows, dof));
        if (cause == "viscous_friction") {
            put(s, 0, a, v);
        } else if (cause == "coulomb_friction") {
            put(s, 0, a, sgn);
        } else if (cause == "effort_offset") {
            put(s, 0, a, 1.0);
        } else if (cause == "armature") {
            put(s, 0, a, rows.qdd(s, dof));
        } else if (cause == "asymmetric_friction") {
            // c sgn + dc |sgn| is c + dc one way and c - dc the other; likewise for damping.
            put(s, 0, a, std::abs(sgn));
            put(s, 1, a, std::abs(v));
        } else if (cause == "stribeck_friction") {
            put(s, 0, a, sgn * std::exp(-(v / scale) * (v / scale)));
        } else if (cause == "position_dependent_effort") {
            put(s, 0, a, rows.q(s, q_index));
        } else if (cause == "actuator_gain") {
            // The actuator gives g times what was measured as commanded.
            put(s, 0, a, rows.effort(s, a));
        } else if (cause == "delay") {
            // The joint feels the effort of d seconds ago: tau(t - d) ~ tau - d dtau/dt.
            put(s, 0, a, rows.effort_rate(s, a));
        }
    }
    return c;
}

bool Candidate::physical(const Eigen::VectorXd& theta) const {
    if (cause == "viscous_friction" || cause == "coulomb_friction" || cause == "armature" ||
        cause == "stribeck_friction" || cause == "delay")
        return theta[0] > 0;
    if (cause == "actuator_gain") return theta[0] < 1;  // gain 1 - theta > 0
    if (cause == "mass_error") return theta[0] > -1;    // mass (1 + theta) m > 0
    return true;
}

std::vector<Candidate> catalogue(const sim::Model& m, const RegressionRows& fit) {
    std::vector<Candidate> out;
    for (int dof : fit.actuated) {
        const int j = m.dof_joint[size_t(dof)];
        const int qi = m.joints[size_t(j)].q_index;
        auto add = [&](const char* cause, std::vector<std::string> params, double scale = 0) {
            Candidate c;
            c.cause = cause, c.joint = j, c.dof = dof, c.q_index = qi, c.parameters = std::move(params), c.scale = scale;
            out.push_back(std::move(c));
        };
        add("viscous_friction", {"damping"});
        add("coulomb_friction", {"coulomb"});
        add("effort_offset", {"offset"});
        add("armature", {"armature"});
        add("asymmetric_friction", {"coulomb_asymmetry", "damping_asymmetry"});
        // Stribeck speeds from a grid around the joint's typical speed.
        const double typical = 100 * sign_speed(fit, dof);
        for (double f : {0.02, 0.05, 0.1, 0.2, 0.5}) add("stribeck_friction", {"stribeck"}, f * typical);
        add("position_dependent_effort", {"stiffness"});
        add("actuator_gain", {"gain_deficit"});
        add("delay", {"delay"});
    }
    // A sensor offset on any measured coordinate, a mass error on any body that moves.
    for (int dof = 0; dof < m.nv; ++dof) {
        Candidate c;
        c.cause = "sensor_offset", c.joint = m.dof_joint[size_t(dof)], c.dof = dof;
        c.q_index = m.joints[size_t(c.joint)].q_index;
        c.parameters = {"offset"};
        out.push_back(c);
    }
    for (int b = 1; b < m.body_count(); ++b) {
        if (!(m.bodies[size_t(b)].inertia.mass > 0)) continue;
        Candidate c;
        c.cause = "mass_error", c.body = b, c.parameters = {"mass_change"};
        out.push_back(c);
    }
    return out;
}

}  // namespace mbx::calibration
