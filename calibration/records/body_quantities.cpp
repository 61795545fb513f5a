#include "calibration/records/body_quantities.h"

#include <algorithm>
#include <cmath>

#include "core/finding.h"
#include "core/text_format.h"
#include "sim/dynamics.h"

namespace mbx::calibration {

namespace {

[[noreturn]] void fail(const std::string& file, int line, const std::string& what) {
    throw Error(MBX_ERROR_INVALID_INPUT, Subject::model("experiment"), file + ":" + std::to_string(line) + ": " + what, file,
                line);
}

bool all_components(const Record& r, Quantity q, int body, int count, const Eigen::Vector3d& point) {
    for (int c = 0; c < count; ++c)
        if (!r.find_body(q, body, c, point)) return false;
    return true;
}

// The samples within 10 ms around sample k (at least three each side;
// one-sided at the record's ends): [a, b).
void fit_window(const Record& r, size_t k, size_t& a, size_t& b) {
    const size_t n = r.t.size();
    const double dt = r.sample_period();
    const size_t half = std::max<size_t>(3, dt > 0 ? size_t(std::llround(0.01 / dt)) : 3);
    a = k > half ? k - half : 0, b = std::min(n, k + half + 1);
    if (b - a < 2 * half + 1) {
        if (a == 0) b = std::min(n, 2 * half + 1);
        else a = b > 2 * half + 1 ? b - 2 * half - 1 : 0;
    }
}

// Value and slope at sample k of a quadratic fitted by least squares to
// value(i) over the window [a, b): a tracker's positions are too noisy to
// difference sample by sample.
template <class Value>
void local_fit(const Record& r, size_t a, size_t b, size_t k, const Value& value, double& at, double& rate) {
    Eigen::MatrixXd A(Eigen::Index(b - a), 3);
    Eigen::VectorXd y(Eigen::Index(b - a));
    for (size_t i = a; i < b; ++i) {
        const double t = r.t[i] - r.t[k];
        A.row(Eigen::Index(i - a)) << 1, t, t * t;
        y[Eigen::Index(i - a)] = value(i);
    }
    const Eigen::Vector3d c = A.colPivHouseholderQr().solve(y);
    at = c[0], rate = c[1];
}

}  // namespace

int body_of_key(const sim::Model& m, const std::string& key, const std::string& file, int line) {
    int found = -1;
    for (size_t b = 0; b < m.bodies.size(); ++b) {
        if (m.bodies[b].id != key && m.bodies[b].name != key) continue;
        if (found >= 0 && found != int(b)) fail(file, line, "body '" + key + "' names several bodies; give its rigid body id");
        found = int(b);
    }
    if (found == 0) fail(file, line, "body '" + key + "' is the world, which does not move");
    if (found < 0) fail(file, line, "no body '" + key + "' in the model (rigid body id or report name)");
    return found;
}

ComparedSignal bind_body_compare(const Experiment& e, const CompareSpec& c, const sim::Model& m) {
    ComparedSignal s;
    s.body = body_of_key(m, c.body, e.path, c.line);
    s.component = c.component;
    s.point = Eigen::Vector3d(c.point[0], c.point[1], c.point[2]);
    s.quantity = c.quantity, s.weight = c.weight, s.start = c.start, s.stop = c.stop, s.line = c.line;
    return s;
}

const std::vector<double>* measured_values(const Record& r, const ComparedSignal& c) {
    if (c.body >= 0) {
        const BodySignal* s = r.find_body(c.quantity, c.body, c.component, c.point);
        return s ? &s->values : nullptr;
    }
    const Signal* s = r.find(c.quantity, c.dof);
    return s ? &s->values : nullptr;
}

void BodyKinematics::update(const sim::Data& d) {
    kin_.q = d.q;
    kin_.v = d.v;
    sim::update_kinematics(m_, kin_);
}

Eigen::Vector3d BodyKinematics::position(int body, const Eigen::Vector3d& point) const {
    return kin_.x_world[size_t(body)].apply(point);
}

Eigen::Quaterniond BodyKinematics::orientation(int body) const {
    Eigen::Quaterniond q(kin_.x_world[size_t(body)].R);
    q.normalize();
    return q;
}

double BodyKinematics::value(Quantity q, int body, int component, const Eigen::Vector3d& point, const Record* r,
                             size_t k) const {
    switch (q) {
    case Quantity::Position: return position(body, point)[component];
    case Quantity::Velocity: return sim::point_velocity(kin_, body, position(body, point))[3 + component];
    case Quantity::AngularVelocity: return kin_.vel[size_t(body)][component];
    case Quantity::Orientation: {
        const Eigen::Quaterniond o = orientation(body);
        const double c[4] = {o.w(), o.x(), o.y(), o.z()};
        double agree = 0;
        bool measured = false;
        if (r)
            for (const BodySignal& s : r->body_signals)
                if (s.quantity == Quantity::Orientation && s.body == body) {
                    agree += s.values[k] * c[s.component];
                    measured = true;
                }
        if (!measured) agree = o.w();
        return agree < 0 ? -c[component] : c[component];
    }
    default: break;
    }
    return NAN;
}

std::vector<int> measured_free_bodies(const sim::Model& m, const Record& r) {
    std::vector<int> out;
    for (size_t b = 1; b < m.bodies.size(); ++b) {
        if (m.joints[b - 1].kind != sim::JointKind::Free) continue;
        if (all_components(r, Quantity::Position, int(b), 3, Eigen::Vector3d::Zero()) &&
            all_components(r, Quantity::Orientation, int(b), 4, Eigen::Vector3d::Zero()))
            out.push_back(int(b));
    }
    return out;
}

PoseSample measured_pose(const Record& r, int body, size_t k) {
    const Eigen::Vector3d origin = Eigen::Vector3d::Zero();
    size_t a = 0, b = 0;
    fit_window(r, k, a, b);
    PoseSample s;
    s.t = r.t[k];
    for (int c = 0; c < 3; ++c) {
        const std::vector<double>& p = r.find_body(Quantity::Position, body, c, origin)->values;
        double value = 0;
        local_fit(r, a, b, k, [&](size_t i) { return p[i]; }, value, s.v[c]);
        s.p[c] = p[k];
    }
    if (all_components(r, Quantity::Velocity, body, 3, origin))
        for (int c = 0; c < 3; ++c) s.v[c] = r.find_body(Quantity::Velocity, body, c, origin)->values[k];
    const std::vector<double>* q[4];
    for (int c = 0; c < 4; ++c) q[c] = &r.find_body(Quantity::Orientation, body, c, origin)->values;
    auto at = [&](size_t i) { return Eigen::Vector4d((*q[0])[i], (*q[1])[i], (*q[2])[i], (*q[3])[i]); };
    const Eigen::Vector4d here = at(k);
    s.q = Eigen::Quaterniond(here[0], here[1], here[2], here[3]);
    if (!(s.q.norm() > 1e-6))
        throw Error(MBX_ERROR_INVALID_INPUT, Subject::model("experiment"),
                    r.path + ": the measured orientation of body " + std::to_string(body) + " at t = " +
                        readable(r.t[k]) + " s is a zero quaternion");
    s.q.normalize();
    if (all_components(r, Quantity::AngularVelocity, body, 3, origin)) {
        for (int c = 0; c < 3; ++c) s.w[c] = r.find_body(Quantity::AngularVelocity, body, c, origin)->values[k];
        return s;
    }
    // The measured quaternions made continuous in sign around the sample
    // before fitting, since a tracker may give q or -q.
    auto aligned = [&](size_t i) {
        const Eigen::Vector4d v = at(i);
        return v.dot(here) < 0 ? Eigen::Vector4d(-v) : v;
    };
    Eigen::Vector4d qd;
    for (int c = 0; c < 4; ++c) {
        double value = 0;
        local_fit(r, a, b, k, [&](size_t i) { return aligned(i)[c]; }, value, qd[c]);
    }
    // w_body = 2 conj(q) q', with q' scaled like q's normalisation.
    const double scale = 1 / here.norm();
    const Eigen::Quaterniond dq(qd[0] * scale, qd[1] * scale, qd[2] * scale, qd[3] * scale);
    s.w = 2 * (s.q.conjugate() * dq).vec();
    return s;
}

void set_measured_free_bodies(const sim::Model& m, sim::Data& d, const Record& r, size_t k) {
    for (int b : measured_free_bodies(m, r)) {
        const sim::JointT<double>& j = m.joints[size_t(b) - 1];
        const PoseSample s = measured_pose(r, b, k);
        d.q.segment<3>(j.q_index) = s.p;
        d.q[j.q_index + 3] = s.q.w(), d.q[j.q_index + 4] = s.q.x(), d.q[j.q_index + 5] = s.q.y(), d.q[j.q_index + 6] = s.q.z();
        d.v.segment<3>(j.v_index) = s.v;
        d.v.segment<3>(j.v_index + 3) = s.w;
    }
}

PoseRecord pose_record(const Record& r, int body, int trial) {
    PoseRecord out;
    out.trial = trial;
    for (size_t k = 0; k < r.t.size(); ++k) out.samples.push_back(measured_pose(r, body, k));
    return out;
}

}  // namespace mbx::calibration
