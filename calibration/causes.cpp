#include "calibration/causes.h"

#include <algorithm>
#include <cmath>

#include "calibration/filters.h"

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

// A friction law f(q̇) per row. The measured effort was low-passed, so the
// law is evaluated at the record's full rate and filtered alike: a law that
// steps at a reversal reaches the filtered effort smoothed over the filter's
// response, and its unfiltered value at the rows would be too sharp there
// (biasing laws that live near zero speed, Stribeck's most).
template <class F> Eigen::VectorXd filtered_law(const RegressionRows& rows, int dof, F f) {
    Eigen::VectorXd out(rows.samples);
    const bool full = rows.row_record.size() == size_t(rows.samples) && !rows.record_velocity.empty();
    if (!full) {
        for (Eigen::Index s = 0; s < rows.samples; ++s) out[s] = f(rows.qd(s, dof));
        return out;
    }
    std::vector<std::vector<double>> law(rows.record_velocity.size());
    for (size_t r = 0; r < law.size(); ++r) {
        const Eigen::MatrixXd& v = rows.record_velocity[r];
        std::vector<double> x(size_t(v.rows()));
        for (Eigen::Index k = 0; k < v.rows(); ++k) x[size_t(k)] = f(v(k, dof));
        law[r] = low_pass(x, rows.record_period[r], rows.record_cutoff[r]);
    }
    for (Eigen::Index s = 0; s < rows.samples; ++s)
        out[s] = law[size_t(rows.row_record[size_t(s)])][size_t(rows.row_sample[size_t(s)])];
    return out;
}

// The effort d seconds before each row (linear interpolation between samples).
double effort_before(const RegressionRows& rows, Eigen::Index s, int a, double d) {
    const Eigen::MatrixXd& e = rows.record_effort[size_t(rows.row_record[size_t(s)])];
    const double back = double(rows.row_sample[size_t(s)]) - d / rows.record_period[size_t(rows.row_record[size_t(s)])];
    const double at = std::clamp(back, 0.0, double(e.rows() - 1));
    const Eigen::Index k0 = std::min(Eigen::Index(std::floor(at)), e.rows() - 1), k1 = std::min(k0 + 1, e.rows() - 1);
    const double w = at - double(k0);
    return (1 - w) * e(k0, a) + w * e(k1, a);
}

}  // namespace

Eigen::MatrixXd Candidate::columns(const RegressionRows& rows) const {
    const Eigen::Index A = Eigen::Index(rows.actuated.size()), S = rows.samples;
    Eigen::MatrixXd c = Eigen::MatrixXd::Zero(S * A, Eigen::Index(parameters.size()));
    const int a = dof >= 0 ? actuated_index(rows, dof) : -1;
    auto put = [&](Eigen::Index s, int col, Eigen::Index at, double v) { c(s * A + at, col) = rows.weight[size_t(at)] * v; };
    Eigen::VectorXd law;
    if (a >= 0) {
        const double vs = sign_speed(rows, dof);
        if (cause == "coulomb_friction")
            law = filtered_law(rows, dof, [vs](double v) { return std::tanh(v / vs); });
        else if (cause == "asymmetric_friction")
            law = filtered_law(rows, dof, [vs](double v) { return std::abs(std::tanh(v / vs)); });
        else if (cause == "stribeck_friction")
            law = filtered_law(rows, dof, [vs = smoothing > 0 ? smoothing : vs, st = scale](double v) {
                return std::tanh(v / vs) * std::exp(-(v / st) * (v / st));
            });
    }
    const bool exact_delay = cause == "delay" && scale > 0 && rows.row_record.size() == size_t(rows.samples) &&
                             !rows.record_effort.empty();
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
        if (cause == "viscous_friction") {
            put(s, 0, a, v);
        } else if (cause == "coulomb_friction" || cause == "stribeck_friction") {
            put(s, 0, a, law[s]);
        } else if (cause == "effort_offset") {
            put(s, 0, a, 1.0);
        } else if (cause == "armature") {
            put(s, 0, a, rows.qdd(s, dof));
        } else if (cause == "backlash" && parameters.size() == 2) {
            put(s, 1, a, rows.qdd(s, dof));  // its rigid limit too
        } else if (cause == "compliance" && parameters.size() == 3) {
            // The rigid limit: the motor inertia is an armature; stiffness
            // and damping have no column (the simulation fit finds them).
            put(s, 2, a, rows.qdd(s, dof));
        } else if (cause == "asymmetric_friction") {
            // c sgn + dc |sgn| is c + dc one way and c - dc the other; likewise for damping.
            put(s, 0, a, law[s]);
            if (parameters.size() > 1) put(s, 1, a, std::abs(v));
        } else if (cause == "position_dependent_effort") {
            put(s, 0, a, rows.q(s, q_index));
        } else if (cause == "actuator_gain") {
            // The actuator gives g times what was measured as commanded.
            put(s, 0, a, rows.effort(s, a));
        } else if (cause == "delay" && exact_delay) {
            // The joint feels the effort of d seconds ago: tau(t) - tau(t - d)
            // is left over; per second of the delay at the setting d =
            // `scale`, so the coefficient is the delay when the setting is.
            put(s, 0, a, (rows.effort(s, a) - effort_before(rows, s, int(a), scale)) / scale);
        } else if (cause == "delay") {
            // To first order, tau(t - d) ~ tau - d dtau/dt.
            put(s, 0, a, rows.effort_rate(s, a));
        }
    }
    return c;
}

bool Candidate::physical(const Eigen::VectorXd& theta) const {
    if (cause == "viscous_friction" || cause == "coulomb_friction" || cause == "armature" ||
        cause == "stribeck_friction" || cause == "delay")
        return theta[0] > 0;
    // A gain 1 - theta or a mass (1 + theta) m near zero is no correction
    // but another machine: with every body's mass and the actuator's effort
    // gone, any record fits exactly (gain 0, masses 0).
    if (cause == "actuator_gain") return theta[0] < 0.9;
    if (cause == "mass_error") return theta[0] > -0.9;
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
        // Asymmetric Coulomb friction alone, or with asymmetric damping: a
        // zero damping asymmetry would otherwise fail the significance test
        // and hide a clear Coulomb asymmetry.
        add("asymmetric_friction", {"coulomb_asymmetry"});
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
