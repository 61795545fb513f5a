#include "calibration/identification/causes.h"

#include <algorithm>
#include <cmath>

#include <Eigen/Eigenvalues>

#include "calibration/cause_table.h"
#include "calibration/identification/tall_qr.h"
#include "core/heartbeat.h"
#include "core/mechatronics/body_mass.h"

namespace mbx::calibration {

double sign_speed(const RegressionRows& rows, int dof) {
    const double rms = std::sqrt(rows.qd.col(dof).squaredNorm() / double(std::max(1, rows.samples)));
    return std::max(1e-9, 0.01 * rms);
}

namespace {

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
// column-pivoted QR of their weighted columns, in pivot order (of their R,
// by blocks of rows: the same pivots, as Q keeps every column's norm).
std::vector<int> identifiable(const RegressionRows& rows, int body, const Eigen::MatrixXd& directions) {
    const Eigen::Index A = Eigen::Index(rows.actuated.size());
    const Eigen::MatrixXd& regressor = rows.inertial_regressor[size_t(body)];
    const Eigen::Index block = tall_block_rows(A);
    TallR tall(directions.cols());
    Eigen::MatrixXd cols;
    for (Eigen::Index from = 0; from < regressor.rows(); from += block) {
        heartbeat();
        cols = regressor.middleRows(from, std::min(block, regressor.rows() - from)) * directions;
        for (Eigen::Index r = 0; r < cols.rows(); ++r) cols.row(r) *= rows.weight[size_t((from + r) % A)];
        tall.add(cols);
    }
    Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(tall.R());
    qr.setThreshold(1e-6);
    std::vector<int> out;
    for (Eigen::Index k = 0; k < qr.rank(); ++k) out.push_back(int(qr.colsPermutation().indices()[k]));
    std::sort(out.begin(), out.end());
    return out;
}

}  // namespace

// One law per
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

const CauseKind& Candidate::kind() const { return cause_kind(cause); }

Eigen::MatrixXd Candidate::columns(const RegressionRows& rows) const {
    Eigen::MatrixXd c = Eigen::MatrixXd::Zero(rows.samples * Eigen::Index(rows.actuated.size()), Eigen::Index(parameters.size()));
    kind().columns(*this, rows, c);
    return c;
}

bool Candidate::physical(const Eigen::VectorXd& theta) const {
    const CauseKind& k = kind();
    return !k.physical || k.physical(*this, theta);
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

std::string subject_text(const sim::Model& m, const Candidate& c) {
    if (c.body >= 0 && size_t(c.body) < m.bodies.size()) return "body '" + m.bodies[size_t(c.body)].name + "'";
    if (c.joint >= 0 && size_t(c.joint) < m.joints.size()) return "joint '" + m.joints[size_t(c.joint)].name + "'";
    return "the mounting";
}

std::vector<Candidate> catalogue(const sim::Model& m, const RegressionRows& fit) {
    // Subject by subject, each in the table's order (which breaks ties).
    std::vector<Candidate> out;
    auto offer = [&](CauseSubject subject, const Candidate& proto) {
        for (const CauseKind& k : cause_table()) {
            if (k.subject != subject || !k.candidates) continue;
            Candidate c = proto;
            c.cause = k.name, c.parameters = k.parameters;
            k.candidates(fit, c, out);
        }
    };
    auto joint_proto = [&](int dof) {
        Candidate c;
        c.joint = m.dof_joint[size_t(dof)], c.dof = dof, c.q_index = m.joints[size_t(c.joint)].q_index;
        return c;
    };
    for (int dof : fit.actuated) offer(CauseSubject::ActuatedJoint, joint_proto(dof));
    for (int dof = 0; dof < m.nv; ++dof) offer(CauseSubject::AnyJoint, joint_proto(dof));
    for (int b = 1; b < m.body_count(); ++b) {
        Candidate c;
        c.body = b, c.body_inertia = m.bodies[size_t(b)].inertia;
        if (c.body_inertia.mass > 0) offer(CauseSubject::Body, c);
    }
    offer(CauseSubject::Mounting, Candidate());
    return out;
}

}  // namespace mbx::calibration
