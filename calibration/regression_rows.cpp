#include "calibration/regression_rows.h"

#include <algorithm>
#include <cmath>

#include "calibration/filters.h"
#include "core/finding.h"
#include "sim/dynamics.h"
#include "sim/joint_forces.h"

namespace mbx::calibration {

Eigen::VectorXd RegressionRows::y() const {
    const Eigen::Index n = Eigen::Index(actuated.size());
    Eigen::VectorXd r(samples * n);
    for (int s = 0; s < samples; ++s)
        for (Eigen::Index a = 0; a < n; ++a) r[s * n + a] = weight[size_t(a)] * (effort(s, a) - model_effort(s, a));
    return r;
}

Eigen::VectorXd RegressionRows::measured() const {
    const Eigen::Index n = Eigen::Index(actuated.size());
    Eigen::VectorXd r(samples * n);
    for (int s = 0; s < samples; ++s)
        for (Eigen::Index a = 0; a < n; ++a) r[s * n + a] = weight[size_t(a)] * effort(s, a);
    return r;
}

namespace {

// The model with every body's inertia but one taken away (and no armature,
// no joint dynamics): its inverse dynamics is that body's share of the effort.
sim::Model only_body(const sim::Model& m, int body) {
    sim::Model r = m;
    for (size_t b = 1; b < r.bodies.size(); ++b)
        if (int(b) != body) r.bodies[b].inertia = sim::Inertia<double>();
    for (sim::JointT<double>& j : r.joints) j.dynamics = sim::JointDynamics();
    return r;
}

// Effort the actuators must supply at (q, qd, qdd): inverse dynamics minus
// what the model's own joint dynamics already do.
void model_effort(const sim::Model& m, sim::Data& d, const Eigen::VectorXd& qdd, Eigen::VectorXd& tau) {
    sim::update_kinematics(m, d);
    sim::inverse_dynamics(m, d, qdd, tau);
    sim::passive_forces(m, d, sim::FrictionLaw::Regularised);
    tau -= d.qfrc_passive;
}

}  // namespace

RegressionRows regression_rows(const sim::Model& m, const std::vector<const Record*>& records,
                               const IdentifyOptions& options, const std::vector<double>* weights) {
    RegressionRows rows;
    if (!m.closures.empty())
        throw Error(MBX_ERROR_INVALID_INPUT, Subject::model(m.name),
                    "inverse-dynamics identification of models with loops is not supported yet");
    for (const sim::JointT<double>& j : m.joints)
        if (j.nv() != 1)
            throw Error(MBX_ERROR_INVALID_INPUT, j.subject(),
                        "joint '" + j.name + "' is not a revolute or prismatic joint: inverse-dynamics "
                        "identification needs every coordinate measured");
    // Actuated coordinates: those with an effort signal in every record.
    for (int dof = 0; dof < m.nv; ++dof) {
        bool all = !records.empty();
        for (const Record* r : records) all = all && r->find(Quantity::Effort, dof);
        if (all) rows.actuated.push_back(dof);
    }
    if (rows.actuated.empty())
        throw Error(MBX_ERROR_INVALID_INPUT, Subject::model(m.name), "no joint has a measured effort in every record");
    const size_t na = rows.actuated.size();

    std::vector<sim::Model> body_models;
    for (int b = 1; b < m.body_count(); ++b) body_models.push_back(only_body(m, b));

    struct Sample {
        Eigen::VectorXd q, qd, qdd, effort, rate;
    };
    std::vector<Sample> kept;
    for (const Record* r : records) {
        const double dt = r->sample_period();
        const double fs = 1 / dt;
        const double cutoff = options.cutoff > 0 ? options.cutoff : std::min(25.0, fs / 40);
        std::vector<std::vector<double>> q(size_t(m.nv)), qd(size_t(m.nv)), qdd(size_t(m.nv));
        for (int dof = 0; dof < m.nv; ++dof) {
            const Signal* p = r->find(Quantity::Position, dof);
            if (!p)
                throw Error(MBX_ERROR_INVALID_INPUT, m.joints[size_t(m.dof_joint[size_t(dof)])].subject(),
                            r->path + ": joint '" + m.joints[size_t(m.dof_joint[size_t(dof)])].name +
                                "' has no measured position: inverse-dynamics identification needs every coordinate");
            q[size_t(dof)] = low_pass(p->values, dt, cutoff);
            qd[size_t(dof)] = derivative(q[size_t(dof)], dt);
            qdd[size_t(dof)] = derivative(qd[size_t(dof)], dt);
        }
        std::vector<std::vector<double>> effort(na), rate(na);
        for (size_t a = 0; a < na; ++a) {
            effort[a] = low_pass(r->find(Quantity::Effort, rows.actuated[a])->values, dt, cutoff);
            rate[a] = derivative(effort[a], dt);
        }
        // Decimate to about four samples per cutoff period (neighbouring
        // rows of filtered data carry no new information and would make the
        // standard errors look smaller than they are); drop the ends, where
        // the filter and the differences are least certain.
        const size_t step = std::max<size_t>(1, size_t(std::floor(fs / (4 * cutoff))));
        const size_t edge = size_t(std::ceil(fs / cutoff));
        const size_t n = r->t.size();
        for (size_t k = edge; k + edge < n; k += step) {
            Sample s;
            s.q = m.q_reference, s.qd.resize(m.nv), s.qdd.resize(m.nv), s.effort.resize(long(na)), s.rate.resize(long(na));
            for (int dof = 0; dof < m.nv; ++dof) {
                const sim::JointT<double>& j = m.joints[size_t(m.dof_joint[size_t(dof)])];
                s.q[j.q_index] = q[size_t(dof)][k];
                s.qd[dof] = qd[size_t(dof)][k];
                s.qdd[dof] = qdd[size_t(dof)][k];
            }
            for (size_t a = 0; a < na; ++a) s.effort[long(a)] = effort[a][k], s.rate[long(a)] = rate[a][k];
            kept.push_back(std::move(s));
        }
    }
    rows.samples = int(kept.size());
    if (rows.samples < 10)
        throw Error(MBX_ERROR_INVALID_INPUT, Subject::model(m.name), "too few samples for identification");
    const Eigen::Index S = rows.samples, A = Eigen::Index(na);
    rows.q.resize(S, m.nq), rows.qd.resize(S, m.nv), rows.qdd.resize(S, m.nv);
    rows.effort.resize(S, A), rows.effort_rate.resize(S, A), rows.model_effort.resize(S, A);
    rows.effort_by_position.assign(size_t(m.nv), Eigen::MatrixXd(S, A));
    rows.effort_of_body.assign(size_t(m.body_count()), Eigen::MatrixXd::Zero(S, A));
    sim::Data d(m);
    std::vector<sim::Data> body_data;
    for (const sim::Model& bm : body_models) body_data.emplace_back(bm);
    Eigen::VectorXd tau, tau2;
    for (Eigen::Index s = 0; s < S; ++s) {
        const Sample& x = kept[size_t(s)];
        rows.q.row(s) = x.q.transpose(), rows.qd.row(s) = x.qd.transpose(), rows.qdd.row(s) = x.qdd.transpose();
        rows.effort.row(s) = x.effort.transpose(), rows.effort_rate.row(s) = x.rate.transpose();
        d.q = x.q, d.v = x.qd;
        model_effort(m, d, x.qdd, tau);
        for (Eigen::Index a = 0; a < A; ++a) rows.model_effort(s, a) = tau[rows.actuated[size_t(a)]];
        // Sensitivity to each position (a sensor offset shifts the whole motion by it).
        for (int dof = 0; dof < m.nv; ++dof) {
            const sim::JointT<double>& j = m.joints[size_t(m.dof_joint[size_t(dof)])];
            const double h = 1e-6 * std::max(1.0, std::abs(x.q[j.q_index]));
            d.q = x.q;
            d.q[j.q_index] += h;
            model_effort(m, d, x.qdd, tau2);
            for (Eigen::Index a = 0; a < A; ++a)
                rows.effort_by_position[size_t(dof)](s, a) = (tau2[rows.actuated[size_t(a)]] - tau[rows.actuated[size_t(a)]]) / h;
        }
        for (size_t b = 0; b < body_models.size(); ++b) {
            sim::Data& bd = body_data[b];
            bd.q = x.q, bd.v = x.qd;
            sim::update_kinematics(body_models[b], bd);
            sim::inverse_dynamics(body_models[b], bd, x.qdd, tau2);
            for (Eigen::Index a = 0; a < A; ++a) rows.effort_of_body[b + 1](s, a) = tau2[rows.actuated[size_t(a)]];
        }
    }
    if (weights) {
        rows.weight = *weights;
    } else {
        // Each actuated joint weighs by its own effort level, so a joint in
        // N and one in N m count alike.
        for (Eigen::Index a = 0; a < A; ++a) {
            const double rms = std::sqrt(rows.effort.col(a).squaredNorm() / double(S));
            rows.weight.push_back(rms > 0 ? 1 / rms : 1.0);
        }
    }
    return rows;
}

}  // namespace mbx::calibration
