#include "calibration/identification/causes.h"

#include <algorithm>
#include <cmath>

#include <Eigen/Eigenvalues>

#include "calibration/records/filters.h"
#include "core/mechatronics/body_mass.h"

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

// The directions, in the body's inertial parameters, of one unit of a
// centre-of-mass shift along each body axis (the inertia about the centre
// of mass kept; first order) and of each inertia entry's change.
Eigen::Matrix<double, kInertialParameters, 3> com_directions(const sim::Inertia<double>& inertia,
                                                             const Eigen::Vector3d& anchor) {
    Eigen::Matrix<double, kInertialParameters, 3> d = Eigen::Matrix<double, kInertialParameters, 3>::Zero();
    const double m = inertia.mass;
    const Eigen::Vector3d c = inertia.h / m;
    const Eigen::Matrix3d one = Eigen::Matrix3d::Identity();
    for (int k = 0; k < 3; ++k) {
        const Eigen::Vector3d e = Eigen::Vector3d::Unit(k);
        // I_origin = I_com + m (|c|^2 1 - c c^T). A shift s adds
        // m (2 (c.s) 1 - c s^T - s c^T) + m (|s|^2 1 - s s^T); the second
        // part is B(a) s = m ((a.s) 1 - (a s^T + s a^T) / 2) at a = s.
        const Eigen::Matrix3d dI = m * (2 * c.dot(e) * one - c * e.transpose() - e * c.transpose()) +
                                   m * (anchor.dot(e) * one - 0.5 * (anchor * e.transpose() + e * anchor.transpose()));
        d.col(k) << 0, m * e, dI(0, 0), dI(1, 1), dI(2, 2), dI(0, 1), dI(0, 2), dI(1, 2);
    }
    return d;
}

Eigen::Matrix<double, kInertialParameters, 6> inertia_directions() {
    Eigen::Matrix<double, kInertialParameters, 6> d = Eigen::Matrix<double, kInertialParameters, 6>::Zero();
    for (int k = 0; k < 6; ++k) d(4 + k, k) = 1;
    return d;
}

// Of a family of directions, those whose effort the records can tell apart
// (a shift along a joint axis of a planar arm changes no effort): a
// column-pivoted QR of their weighted columns, in pivot order.
std::vector<int> identifiable(const RegressionRows& rows, int body, const Eigen::MatrixXd& directions) {
    const Eigen::Index A = Eigen::Index(rows.actuated.size());
    Eigen::MatrixXd cols = rows.inertial_regressor[size_t(body)] * directions;
    for (Eigen::Index r = 0; r < cols.rows(); ++r) cols.row(r) *= rows.weight[size_t(r % A)];
    Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(cols);
    qr.setThreshold(1e-6);
    std::vector<int> out;
    for (Eigen::Index k = 0; k < qr.rank(); ++k) out.push_back(int(qr.colsPermutation().indices()[k]));
    std::sort(out.begin(), out.end());
    return out;
}

// mass_error variants of one body: its mass (and inertia alike), a centre
// of mass shifted along each axis the records see or along all of them,
// and each inertia entry they see changed, or all of them. One law per
// body is named (identify), so the variants compete; single-axis ones keep
// a shift along one axis from failing the significance test on the others.
std::vector<Candidate> body_candidates(const RegressionRows& fit, int body, const sim::Inertia<double>& inertia) {
    std::vector<Candidate> out;
    auto add = [&](std::vector<std::string> names, Eigen::MatrixXd directions) {
        Candidate c;
        c.cause = "mass_error", c.body = body, c.body_inertia = inertia;
        c.parameters = std::move(names), c.inertial_directions = std::move(directions);
        out.push_back(std::move(c));
    };
    add({"mass_change"}, inertial_parameters(inertia));
    auto family = [&](const Eigen::MatrixXd& directions, const char* const* names) {
        const std::vector<int> seen = identifiable(fit, body, directions);
        for (int k : seen) add({names[k]}, directions.col(k));
        if (seen.size() < 2) return;
        Eigen::MatrixXd all(kInertialParameters, Eigen::Index(seen.size()));
        std::vector<std::string> all_names;
        for (size_t i = 0; i < seen.size(); ++i) all.col(Eigen::Index(i)) = directions.col(seen[i]), all_names.push_back(names[seen[i]]);
        add(all_names, all);
    };
    family(com_directions(inertia, Eigen::Vector3d::Zero()), Candidate::kComShiftNames);
    family(inertia_directions(), Candidate::kInertiaChangeNames);
    return out;
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
            const Eigen::MatrixXd& R = rows.inertial_regressor[size_t(body)];
            for (Eigen::Index k = 0; k < A; ++k)
                for (Eigen::Index p = 0; p < inertial_directions.cols(); ++p)
                    put(s, int(p), k, R.row(s * A + k).dot(inertial_directions.col(p)));
            continue;
        }
        if (cause == "sensor_offset") {
            // A reading off by o puts the model at q - o: its effort changes by -o dtau/dq.
            // To second order, -o dtau/dq + o^2/2 d2tau/dq2: the secant through the anchor.
            for (Eigen::Index k = 0; k < A; ++k)
                put(s, 0, k, -rows.effort_by_position[size_t(dof)](s, k) +
                                 0.5 * offset_anchor * rows.effort_by_position2[size_t(dof)](s, k));
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
    if (cause == "mass_error") {
        const BodyCorrection b = body_correction(theta);
        if (!(b.mass_scale > 0.1)) return false;
        // A centre of mass moved beyond the body's own extent (its radius
        // of gyration about the centre of mass, or half the centre's
        // distance from the body origin for a compact body) is no CAD error
        // but another cause's signature taken up.
        if (!(b.com_shift.norm() <= largest_com_shift(body_inertia))) return false;
        // An inertia about the centre of mass no rigid body has (not
        // positive definite, or a principal moment above the sum of the
        // other two) is a fit to noise or to another cause.
        // (The check the description file's reader makes, so what is named can be written.)
        if (!b.inertia_change.isZero(0)) {
            const double one = 1;
            const sim::Inertia<double> c =
                corrected_inertia(body_inertia, one, b.com_shift.data(), b.inertia_change.data());
            if (!implausible_inertia(about_com(c)).empty()) return false;
        }
        return true;
    }
    return true;
}

BodyCorrection BodyCorrection::after(const BodyCorrection& first) const {
    BodyCorrection r;
    r.mass_scale = first.mass_scale * mass_scale;
    r.com_shift = first.com_shift + com_shift;
    r.inertia_change = mass_scale * first.inertia_change + inertia_change;
    return r;
}

double largest_com_shift(const sim::Inertia<double>& inertia) {
    const double m = inertia.mass;
    if (!(m > 0)) return 0;
    const double gyration = std::sqrt(std::max(0.0, about_com(inertia).trace()) / m);
    return std::max(gyration, 0.5 * (inertia.h / m).norm());
}

bool Candidate::shifts_com() const {
    for (const std::string& p : parameters)
        for (const char* n : kComShiftNames)
            if (p == n) return true;
    return false;
}

void Candidate::anchor_com_shift(const Eigen::VectorXd& theta) {
    com_anchor = body_correction(theta).com_shift;
    const Eigen::Matrix<double, kInertialParameters, 3> d = com_directions(body_inertia, com_anchor);
    for (size_t i = 0; i < parameters.size(); ++i)
        for (int k = 0; k < 3; ++k)
            if (parameters[i] == kComShiftNames[k]) inertial_directions.col(Eigen::Index(i)) = d.col(k);
}

BodyCorrection Candidate::body_correction(const Eigen::VectorXd& theta) const {
    BodyCorrection b;
    body_correction(theta.data(), b.mass_scale, b.com_shift.data(), b.inertia_change.data());
    // Entries the records cannot see (a planar arm sees only the moment
    // about its joints' axis) are no evidence of anything, but a change of
    // the others alone may leave a body no material has (one moment above
    // the sum of the other two). The unseen moments then grow alike, by the
    // least that makes the body whole again: what these records identify
    // stays as found, and the description file holds a real body.
    bool seen[6] = {false, false, false, false, false, false};
    for (const std::string& p : parameters)
        for (int k = 0; k < 6; ++k) seen[k] = seen[k] || p == kInertiaChangeNames[k];
    std::vector<int> unseen;
    for (int k = 0; k < 3; ++k)
        if (!seen[k]) unseen.push_back(k);
    if (b.inertia_change.isZero(0) || unseen.empty() || !(body_inertia.mass > 0)) return b;
    const Eigen::Matrix3d about = about_com(body_inertia);
    auto excess = [&](double t) {
        InertiaEntries e;
        for (int k = 0; k < 6; ++k) e[size_t(k)] = b.inertia_change[k];
        for (int k : unseen) e[size_t(k)] += t;
        const Eigen::Matrix3d I = b.mass_scale * about + inertia_from_entries(e);
        const Eigen::Vector3d p = Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(I).eigenvalues();
        return std::max(p[2] - p[0] - p[1], -p[0]);
    };
    if (!(excess(0) > 0)) return b;
    // The excess falls as the unseen moments grow (each adds to both sides
    // of at most one inequality's right-hand side): bisect for the least.
    double lo = 0, hi = std::max(1e-300, b.inertia_change.cwiseAbs().maxCoeff());
    for (int it = 0; it < 60 && excess(hi) > 0; ++it) hi *= 2;
    if (excess(hi) > 0) return b;  // none will do: physical() refuses it
    for (int it = 0; it < 60; ++it) {
        const double mid = 0.5 * (lo + hi);
        (excess(mid) > 0 ? lo : hi) = mid;
    }
    for (int k : unseen) b.inertia_change[k] += hi;
    return b;
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
        const sim::Inertia<double>& inertia = m.bodies[size_t(b)].inertia;
        if (!(inertia.mass > 0)) continue;
        for (Candidate& c : body_candidates(fit, b, inertia)) out.push_back(std::move(c));
    }
    return out;
}

}  // namespace mbx::calibration
