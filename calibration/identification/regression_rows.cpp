#include "calibration/identification/regression_rows.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "calibration/identification/closed_chain.h"
#include "calibration/records/filters.h"
#include "calibration/records/noise.h"
#include "core/finding.h"
#include "core/heartbeat.h"
#include "sim/dynamics.h"
#include "sim/joint_forces.h"
#include "sim/loop_closure.h"

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

double noise_floor(const sim::Model& m, const RegressionRows& rows, const std::vector<const Record*>& records) {
    const std::vector<SignalNoise> noise = effort_noise(records, rows.actuated);
    if (noise.empty() || rows.samples == 0) return NAN;
    const Eigen::Index na = Eigen::Index(rows.actuated.size());
    // Per record, each actuated effort's filtered noise variance.
    Eigen::MatrixXd effort_variance = Eigen::MatrixXd::Zero(Eigen::Index(records.size()), na);
    for (const SignalNoise& n : noise) {
        const Eigen::Index a = Eigen::Index(std::find(rows.actuated.begin(), rows.actuated.end(), n.dof) - rows.actuated.begin());
        if (a < na) effort_variance(n.record, a) = n.filtered * n.filtered;
    }
    // Per record, each coordinate's acceleration noise (rad/s^2 or m/s^2)
    // from its measured position's noise.
    Eigen::MatrixXd acceleration_sigma = Eigen::MatrixXd::Zero(Eigen::Index(records.size()), m.nv);
    const bool hinges = m.nq == m.nv;
    for (size_t r = 0; hinges && r < records.size(); ++r) {
        const Record& rec = *records[r];
        const double dt = rec.sample_period();
        if (!(dt > 0)) continue;
        const double share = low_pass_acceleration_share(dt, rec.filter_cutoff());
        for (const Signal& s : rec.signals)
            if (s.quantity == Quantity::Position && s.dof >= 0 && s.dof < m.nv)
                acceleration_sigma(Eigen::Index(r), s.dof) =
                    white_noise_sigma(s.values, dt, 2 * rec.filter_cutoff(), NoiseShape::Uniform) * std::sqrt(share) / (dt * dt);
    }
    const bool positions = hinges && acceleration_sigma.cwiseAbs().maxCoeff() > 0;
    // In a closed chain only the independent (measured) coordinates' noise
    // reaches the rows: the others are solved from them, so an independent
    // acceleration's error a moves them all by G a, and the rows' effort,
    // G^T tau, by G^T M G a. The tree's M alone would count the loop's
    // cancelling motions (on the four-bar the coupler turning against the
    // crank) and put the floor ten times too high.
    std::vector<char> in_every_record(size_t(m.nv), 0);
    for (int dof = 0; dof < m.nv; ++dof) {
        bool all = !records.empty();
        for (const Record* r : records) all = all && r->find(Quantity::Position, dof);
        in_every_record[size_t(dof)] = all;
    }
    ClosedChain chain;
    if (positions && !m.closures.empty()) chain = closed_chain(m, in_every_record);
    std::vector<int> coordinates;  // the columns of the inertia below
    if (chain.active()) {
        coordinates = chain.independent;
    } else {
        for (int dof = 0; dof < m.nv; ++dof) coordinates.push_back(dof);
    }
    std::vector<Eigen::Index> actuated_at(size_t(na), -1);
    for (Eigen::Index a = 0; a < na; ++a)
        actuated_at[size_t(a)] = Eigen::Index(std::find(coordinates.begin(), coordinates.end(), rows.actuated[size_t(a)]) -
                                              coordinates.begin());
    sim::Data d(m);
    Eigen::MatrixXd G, inertia;
    Eigen::VectorXd qd, qdd, sigma(Eigen::Index(coordinates.size()));
    double expected = 0;
    for (int s = 0; s < rows.samples && size_t(s) < rows.row_record.size(); ++s) {
        const int r = rows.row_record[size_t(s)];
        if (r < 0 || size_t(r) >= records.size()) continue;
        Eigen::VectorXd spread = effort_variance.row(r).transpose();
        if (positions) {
            d.q = rows.q.row(s).transpose();
            if (chain.active()) {
                qd = rows.qd.row(s).transpose(), qdd = rows.qdd.row(s).transpose();
                chain.close(m, d, qd, qdd, G);
            }
            sim::update_positions(m, d);
            sim::mass_matrix(m, d);
            inertia = chain.active() ? Eigen::MatrixXd(G.transpose() * d.M * G) : Eigen::MatrixXd(d.M);
            for (size_t c = 0; c < coordinates.size(); ++c) sigma[Eigen::Index(c)] = acceleration_sigma(r, coordinates[c]);
            for (Eigen::Index a = 0; a < na; ++a)
                if (actuated_at[size_t(a)] < inertia.rows())
                    spread[a] += inertia.row(actuated_at[size_t(a)]).transpose().cwiseProduct(sigma).squaredNorm();
        }
        for (Eigen::Index a = 0; a < na; ++a) expected += rows.weight[size_t(a)] * rows.weight[size_t(a)] * spread[a];
    }
    const double measured = rows.measured().squaredNorm();
    return measured > 0 ? 100 * std::sqrt(expected / measured) : NAN;
}

Eigen::Matrix<double, kInertialParameters, 1> inertial_parameters(const sim::Inertia<double>& inertia) {
    Eigen::Matrix<double, kInertialParameters, 1> p;
    const Eigen::Matrix3d& I = inertia.I;
    p << inertia.mass, inertia.h, I(0, 0), I(1, 1), I(2, 2), I(0, 1), I(0, 2), I(1, 2);
    return p;
}

sim::Inertia<double> inertia_of_parameters(const Eigen::Matrix<double, kInertialParameters, 1>& p) {
    sim::Inertia<double> r;
    r.mass = p[0];
    r.h = p.segment<3>(1);
    r.I << p[4], p[7], p[8], p[7], p[5], p[9], p[8], p[9], p[6];
    return r;
}

namespace {

// The model without inertia (and no armature, no joint dynamics): one body
// given a unit inertial parameter at a time, its inverse dynamics is a
// column of that body's inertial regressor.
sim::Model without_inertia(const sim::Model& m) {
    sim::Model r = m;
    for (sim::BodyT<double>& b : r.bodies) b.inertia = sim::Inertia<double>();
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


namespace {

std::string brief_number(double x) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.4g", x);
    return buf;
}

}  // namespace

RegressionRows regression_rows(const sim::Model& m, const std::vector<const Record*>& records,
                               const IdentifyOptions& options, const std::vector<double>* weights) {
    RegressionRows rows;
    for (const sim::JointT<double>& j : m.joints)
        if (j.nv() != 1)
            throw Error(MBX_ERROR_INVALID_INPUT, j.subject(),
                        "joint '" + j.name + "' is not a revolute or prismatic joint: inverse-dynamics "
                        "identification needs one coordinate per joint");
    // Actuated coordinates: those with an effort signal in every record;
    // measured ones: those with a position in every record.
    std::vector<char> measured(size_t(m.nv), 0);
    for (int dof = 0; dof < m.nv; ++dof) {
        bool effort = !records.empty(), position = !records.empty();
        for (const Record* r : records) {
            effort = effort && r->find(Quantity::Effort, dof);
            position = position && r->find(Quantity::Position, dof);
        }
        if (effort) rows.actuated.push_back(dof);
        measured[size_t(dof)] = position;
    }
    if (rows.actuated.empty())
        throw Error(MBX_ERROR_INVALID_INPUT, Subject::model(m.name), "no joint has a measured effort in every record");
    for (int dof : rows.actuated)
        if (!measured[size_t(dof)] && !m.closures.empty())
            throw Error(MBX_ERROR_INVALID_INPUT, m.joints[size_t(m.dof_joint[size_t(dof)])].subject(),
                        "joint '" + m.joints[size_t(m.dof_joint[size_t(dof)])].name +
                            "' has a measured effort but no measured position in every record");
    ClosedChain chain = closed_chain(m, measured);
    const size_t na = rows.actuated.size();
    // Decimate to about four samples per cutoff period (neighbouring rows of
    // filtered data carry no new information and would make the standard
    // errors look smaller than they are); drop the ends, where the filter
    // and the differences are least certain.
    struct Decimation {
        size_t step, edge, rows;
    };
    auto decimation = [&](const Record& r) {
        const double fs = 1 / r.sample_period();
        const double cutoff = options.cutoff > 0 ? options.cutoff : r.filter_cutoff();
        Decimation d{std::max<size_t>(1, size_t(std::floor(fs / (4 * cutoff)))), size_t(std::ceil(fs / cutoff)), 0};
        const size_t n = r.t.size();
        d.rows = n > 2 * d.edge ? (n - 2 * d.edge - 1) / d.step + 1 : 0;
        return d;
    };
    size_t all_rows = 0;
    for (const Record* r : records) all_rows += decimation(*r).rows;
    // (Allocated once: grown row by row, a million-sample record's rows were
    // moved about in pauses of up to 75 ms.)
    RowSamples kept(m.nq, m.nv, Eigen::Index(na), Eigen::Index(all_rows));
    size_t at = 0;
    constexpr size_t kMinimumRows = 10;
    // Errors are sums of squares: an effort beyond 1e150 squares to
    // infinity and every percentage after it is NaN or infinite (a record of
    // 1e308 N m fitted "0.00 %"; masses of 1e300 "explained the data within
    // its noise"). Such a record or model is refused, naming which.
    constexpr double kLargestEffort = 1e150;
    std::string rows_of_records;  // what each record gave, for the message when it is too little
    for (const Record* r : records) {
        const double dt = r->sample_period();
        const double fs = 1 / dt;
        const double cutoff = options.cutoff > 0 ? options.cutoff : r->filter_cutoff();
        std::vector<std::vector<double>> q(size_t(m.nv)), qd(size_t(m.nv)), qdd(size_t(m.nv));
        for (int dof : chain.independent) {
            const Signal* p = r->find(Quantity::Position, dof);
            if (!p)
                throw Error(MBX_ERROR_INVALID_INPUT, m.joints[size_t(m.dof_joint[size_t(dof)])].subject(),
                            r->path + ": joint '" + m.joints[size_t(m.dof_joint[size_t(dof)])].name +
                                "' has no measured position: inverse-dynamics identification needs every coordinate "
                                "of a tree");
            q[size_t(dof)] = low_pass(p->values, dt, cutoff);
            qd[size_t(dof)] = derivative(q[size_t(dof)], dt);
            qdd[size_t(dof)] = derivative(qd[size_t(dof)], dt);
        }
        std::vector<std::vector<double>> effort(na), rate(na);
        const size_t n = r->t.size();
        const int record = int(rows.record_period.size());
        rows.record_period.push_back(dt), rows.record_cutoff.push_back(cutoff);
        rows.record_effort.emplace_back(Eigen::Index(n), Eigen::Index(na));
        rows.record_velocity.emplace_back(Eigen::Index(n), m.nv);  // (set below, with beats)
        for (size_t a = 0; a < na; ++a) {
            const std::vector<double>& raw = r->find(Quantity::Effort, rows.actuated[a])->values;
            for (size_t k = 0; k < raw.size(); ++k)
                if (!(std::abs(raw[k]) < kLargestEffort)) {
                    const sim::JointT<double>& j = m.joints[size_t(m.dof_joint[size_t(rows.actuated[a])])];
                    throw Error(MBX_ERROR_INVALID_INPUT, j.subject(),
                                r->path + ": joint '" + j.name + "''s measured effort reaches " + brief_number(raw[k]) +
                                    " at t = " + brief_number(r->t[k]) + " s, beyond what can be compared (its square overflows)");
                }
            effort[a] = low_pass(raw, dt, cutoff);
            rate[a] = derivative(effort[a], dt);
            for (size_t k = 0; k < n; ++k) {
                if ((k & 4095) == 0) heartbeat();
                rows.record_effort.back()(Eigen::Index(k), Eigen::Index(a)) = effort[a][k];
            }
        }
        for (int dof = 0; dof < m.nv; ++dof) {
            const std::vector<double>& speed = qd[size_t(dof)];  // empty: not an independent coordinate
            for (size_t k = 0; k < n; ++k) {
                if ((k & 4095) == 0) heartbeat();
                rows.record_velocity.back()(Eigen::Index(k), dof) = speed.empty() ? 0.0 : speed[k];
            }
        }
        const auto [step, edge, record_rows] = decimation(*r);
        for (size_t k = edge; k + edge < n; k += step, ++at) {
            heartbeat();
            const Eigen::Index s = Eigen::Index(at);
            kept.start_row(s, m.q_reference, k == edge);
            rows.row_record.push_back(record), rows.row_sample.push_back(int(k));
            for (int dof : chain.independent) {
                const sim::JointT<double>& j = m.joints[size_t(m.dof_joint[size_t(dof)])];
                kept.q(j.q_index, s) = q[size_t(dof)][k];
                kept.qd(dof, s) = qd[size_t(dof)][k];
                kept.qdd(dof, s) = qdd[size_t(dof)][k];
            }
            for (size_t a = 0; a < na; ++a) kept.effort(long(a), s) = effort[a][k], kept.rate(long(a), s) = rate[a][k];
        }
        rows_of_records += (rows_of_records.empty() ? "" : "; ") + r->path + ": " + std::to_string(n) + " samples, " +
                           std::to_string(record_rows) + " rows (" + std::to_string(edge) +
                           " dropped at each end, every " + std::to_string(step) + (step == 1 ? "" : "th") + " kept, for a " +
                           brief_number(cutoff) + " Hz filter at " + brief_number(fs) + " Hz)";
    }
    if (all_rows < kMinimumRows)
        throw Error(MBX_ERROR_INVALID_INPUT, Subject::model(m.name),
                    "too few samples for identification: " + std::to_string(all_rows) + " rows where at least " +
                        std::to_string(kMinimumRows) + " are needed (" + rows_of_records +
                        "); longer records, or a higher filter cutoff, give more");
    fill_rows(m, chain, kept, rows);
    // (the measured efforts were checked as read; what the filter made of them is too)
    constexpr double kLargest = kLargestEffort;
    for (Eigen::Index s = 0; s < Eigen::Index(rows.samples); ++s)
        for (Eigen::Index a = 0; a < Eigen::Index(na); ++a) {
            const sim::JointT<double>& j = m.joints[size_t(m.dof_joint[size_t(rows.actuated[size_t(a)])])];
            const Record& r = *records[size_t(rows.row_record[size_t(s)])];
            const double t = r.t[size_t(rows.row_sample[size_t(s)])];
            if (!(std::abs(rows.effort(s, a)) < kLargest))
                throw Error(MBX_ERROR_INVALID_INPUT, j.subject(),
                            r.path + ": joint '" + j.name + "''s measured effort reaches " + brief_number(rows.effort(s, a)) +
                                " at t = " + brief_number(t) + " s, beyond what can be compared (its square overflows)");
            if (!(std::abs(rows.model_effort(s, a)) < kLargest))
                throw Error(MBX_ERROR_INVALID_INPUT, j.subject(),
                            "joint '" + j.name + "': the model's effort along " + r.path + " reaches " +
                                brief_number(rows.model_effort(s, a)) + " at t = " + brief_number(t) +
                                " s, beyond what can be compared: check the masses and inertias the model carries");
        }
    if (weights) {
        rows.weight = *weights;
    } else {
        // Each actuated joint weighs by its own effort level, so a joint in
        // N and one in N m count alike.
        rows.weight = effort_weights(rows);
    }
    return rows;
}

std::vector<double> effort_weights(const RegressionRows& rows) {
    std::vector<double> weight;
    for (Eigen::Index a = 0; a < rows.effort.cols(); ++a) {
        const double rms = std::sqrt(rows.effort.col(a).squaredNorm() / double(rows.samples));
        weight.push_back(rms > 0 ? 1 / rms : 1.0);
    }
    return weight;
}

void fill_rows(const sim::Model& m, ClosedChain& chain, const RowSamples& kept, RegressionRows& rows,
               unsigned parts) {
    const size_t na = rows.actuated.size();
    std::vector<Eigen::Index> actuated_at(na);  // position of each actuated coordinate among the independent ones
    for (size_t a = 0; a < na; ++a)
        actuated_at[a] = Eigen::Index(std::find(chain.independent.begin(), chain.independent.end(), rows.actuated[a]) -
                                      chain.independent.begin());
    sim::Model unit = without_inertia(m);
    rows.samples = int(kept.size());
    const Eigen::Index S = rows.samples, A = Eigen::Index(na);
    rows.q.resize(S, m.nq), rows.qd.resize(S, m.nv), rows.qdd.resize(S, m.nv);
    rows.effort.resize(S, A), rows.effort_rate.resize(S, A), rows.model_effort.resize(S, A);
    const bool positions = parts & kPositionSensitivity, gravity = parts & kGravityShares, inertial = parts & kInertialRegressor;
    // (Left unset here and zeroed a sample at a time below: on a long record
    // they are hundreds of MB, ten columns per body and row, and setting
    // them in one go held the progress callback back for a second.)
    auto unset = [](std::vector<Eigen::MatrixXd>& v, size_t count, Eigen::Index r, Eigen::Index c) {
        v.resize(count);
        for (Eigen::MatrixXd& x : v) x.resize(r, c);
    };
    unset(rows.effort_by_position, positions ? size_t(m.nv) : 0, S, A);
    unset(rows.effort_by_position2, positions ? size_t(m.nv) : 0, S, A);
    unset(rows.inertial_regressor, inertial ? size_t(m.body_count()) : 0, S * A, kInertialParameters);
    rows.gravity = m.gravity;
    unset(rows.effort_by_gravity, gravity ? 3 : 0, S, A);
    sim::Model held = m;  // its gravity set to each world axis in turn
    sim::Data d(m), probe(m), unit_data(unit), held_data(held);
    // The actuated efforts the model needs at a sample (positions in dd.q,
    // the loops closed from there): the tree's inverse dynamics, projected
    // onto the independent coordinates when there are loops.
    Eigen::MatrixXd G;
    Eigen::VectorXd tau, qd, qdd;
    auto needed = [&](sim::Data& dd, Eigen::Index row, Eigen::VectorXd& out) {
        qd = kept.qd.col(row), qdd = kept.qdd.col(row);
        if (chain.active()) chain.close(m, dd, qd, qdd, G);
        dd.v = qd;
        model_effort(m, dd, qdd, tau);
        out.resize(A);
        if (chain.active()) {
            const Eigen::VectorXd projected = G.transpose() * tau;
            for (Eigen::Index a = 0; a < A; ++a) out[a] = projected[actuated_at[size_t(a)]];
        } else {
            for (Eigen::Index a = 0; a < A; ++a) out[a] = tau[rows.actuated[size_t(a)]];
        }
    };
    Eigen::VectorXd base, moved, moved_back;
    std::vector<sim::Inertia<double>> unit_inertia;
    for (int k = 0; k < kInertialParameters; ++k)
        unit_inertia.push_back(inertia_of_parameters(Eigen::Matrix<double, kInertialParameters, 1>::Unit(k)));
    std::vector<int> actuated_of_dof(size_t(m.nv), -1);
    for (size_t a = 0; a < na; ++a) actuated_of_dof[size_t(rows.actuated[a])] = int(a);
    Eigen::Matrix<double, 6, kInertialParameters> forces;
    const std::vector<int> none, &probed = positions ? chain.independent : none;
    Eigen::MatrixXd joint_share;
    for (Eigen::Index s = 0; s < S; ++s) {
        heartbeat(double(s) / double(S));
        const auto x_q = kept.q.col(s);
        // Dependent positions start from the last sample's (or the assembly pose at a record's start).
        const Eigen::VectorXd start = kept.first[size_t(s)] || s == 0 ? m.q_reference : Eigen::VectorXd(d.q);
        d.q = start;
        for (int dof : chain.independent) {
            const int qi = m.joints[size_t(m.dof_joint[size_t(dof)])].q_index;
            d.q[qi] = x_q[qi];
        }
        needed(d, s, base);
        const Eigen::VectorXd q_full = d.q, qd_full = qd, qdd_full = qdd;
        const Eigen::MatrixXd G_here = G;
        rows.q.row(s) = q_full.transpose(), rows.qd.row(s) = qd_full.transpose(), rows.qdd.row(s) = qdd_full.transpose();
        rows.effort.row(s) = kept.effort.col(s).transpose(), rows.effort_rate.row(s) = kept.rate.col(s).transpose();
        rows.model_effort.row(s) = base.transpose();
        for (size_t dof = 0; dof < rows.effort_by_position.size(); ++dof)
            rows.effort_by_position[dof].row(s).setZero(), rows.effort_by_position2[dof].row(s).setZero();
        // Sensitivity to each measured position (a sensor offset shifts the
        // whole measured motion by it; in a loop the others follow).
        // Central differences: the second derivative makes a sensor offset's
        // column exact to second order (its quadratic part would otherwise
        // be left for another cause).
        for (int dof : probed) {
            const int qi = m.joints[size_t(m.dof_joint[size_t(dof)])].q_index;
            const double h = 1e-4 * std::max(1.0, std::abs(x_q[qi]));
            for (int side : {1, -1}) {
                probe.q = q_full;
                probe.q[qi] += side * h;
                needed(probe, s, side > 0 ? moved : moved_back);
            }
            rows.effort_by_position[size_t(dof)].row(s) = ((moved - moved_back) / (2 * h)).transpose();
            rows.effort_by_position2[size_t(dof)].row(s) = ((moved - 2 * base + moved_back) / (h * h)).transpose();
        }
        // The efforts that hold the bodies against a unit gravity along each axis.
        if (gravity) {
            held_data.q = q_full, held_data.v.setZero();
            sim::update_kinematics(held, held_data);
        }
        const Eigen::VectorXd still = Eigen::VectorXd::Zero(m.nv);
        for (int k = 0; k < (gravity ? 3 : 0); ++k) {
            held.gravity = Eigen::Vector3d::Unit(k);
            sim::inverse_dynamics(held, held_data, still, tau);
            const Eigen::VectorXd share = chain.active() ? Eigen::VectorXd(G_here.transpose() * tau) : tau;
            for (Eigen::Index a = 0; a < A; ++a)
                rows.effort_by_gravity[size_t(k)](s, a) = share[chain.active() ? actuated_at[size_t(a)] : rows.actuated[size_t(a)]];
        }
        // Inverse dynamics is linear in each body's inertial parameters: a
        // body's force is Y(acc, vel) times its ten parameters, and reaches
        // every joint between it and the ground through the force
        // transforms alone. One pass of the unit (inertia-free) model gives
        // every body's acceleration; a body's ten columns then cost its
        // depth, not another inverse dynamics per parameter.
        if (!inertial) continue;
        for (Eigen::MatrixXd& R : rows.inertial_regressor) R.middleRows(s * A, A).setZero();
        unit_data.q = q_full, unit_data.v = qd_full;
        sim::update_kinematics(unit, unit_data);
        sim::inverse_dynamics(unit, unit_data, qdd_full, tau);
        for (int b = 1; b < m.body_count(); ++b) {
            if (!(m.bodies[size_t(b)].inertia.mass > 0)) continue;  // massless CAD joint nodes
            const sim::Vec6T<double>& acc = unit_data.acc[size_t(b)];
            const sim::Vec6T<double>& vel = unit_data.vel[size_t(b)];
            for (int k = 0; k < kInertialParameters; ++k) forces.col(k) = unit_inertia[size_t(k)] * acc + sim::cross_force<double>(vel, unit_inertia[size_t(k)] * vel);
            Eigen::MatrixXd& R = rows.inertial_regressor[size_t(b)];
            if (chain.active()) joint_share.setZero(m.nv, kInertialParameters);
            for (size_t c = size_t(b); c > 0; c = size_t(m.bodies[c].parent)) {
                const sim::JointT<double>& jc = m.joints[c - 1];
                for (int i = 0; i < jc.nv(); ++i) {
                    const int dof = jc.v_index + i;
                    if (chain.active()) {
                        joint_share.row(dof) = unit_data.subspace[c].col(i).transpose() * forces;
                    } else if (actuated_of_dof[size_t(dof)] >= 0) {
                        R.row(s * A + actuated_of_dof[size_t(dof)]) = unit_data.subspace[c].col(i).transpose() * forces;
                    }
                }
                if (m.bodies[c].parent > 0)
                    for (int k = 0; k < kInertialParameters; ++k)
                        forces.col(k) = unit_data.x_parent[c].force_to_parent(sim::Vec6T<double>(forces.col(k)));
            }
            if (chain.active()) {
                const Eigen::MatrixXd share = G_here.transpose() * joint_share;
                for (Eigen::Index a = 0; a < A; ++a) R.row(s * A + a) = share.row(actuated_at[size_t(a)]);
            }
        }
    }
}

}  // namespace mbx::calibration
