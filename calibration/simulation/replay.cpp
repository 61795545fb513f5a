#include "calibration/simulation/replay.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "calibration/records/body_quantities.h"
#include "calibration/identification/closed_chain.h"
#include "calibration/records/filters.h"
#include "core/finding.h"
#include "core/heartbeat.h"
#include "core/text_format.h"
#include "sim/transmission.h"
#include "sim/dynamics.h"
#include "sim/integrator.h"
#include "sim/joint_forces.h"
#include "sim/simulation.h"

namespace mbx::calibration {

namespace {

[[noreturn]] void fail(const std::string& file, int line, const std::string& what) {
    throw Error(MBX_ERROR_INVALID_INPUT, Subject::model("experiment"), file + ":" + std::to_string(line) + ": " + what, file,
                line);
}

// Fixed RK4 steps that land on every sample and stay at or below 0.5 ms, the
// step the drive tests reproduce the EMPS rig with.
sim::IntegratorSettings settings_for(double dt) {
    sim::IntegratorSettings s;
    s.kind = sim::IntegratorKind::RK4;
    s.step = dt / std::ceil(dt / 0.5e-3 - 1e-9);
    return s;
}

double value_at(const Record& r, const std::vector<double>& v, double t) {
    if (t <= r.t.front()) return v.front();
    if (t >= r.t.back()) return v.back();
    const size_t k = size_t(std::upper_bound(r.t.begin(), r.t.end(), t) - r.t.begin());
    const double a = (t - r.t[k - 1]) / (r.t[k] - r.t[k - 1]);
    return (1 - a) * v[k - 1] + a * v[k];
}

[[noreturn]] void diverged(const Record& r, double t, const Error& e) {
    if (e.status() == MBX_ERROR_CANCELLED) throw e;
    std::ostringstream s;
    s << "replay of " << r.path << " diverged at t = " << t << " s: " << e.what();
    throw Error(MBX_ERROR_SIMULATION, e.subject(), s.str());
}

bool any_body_signal(const std::vector<ComparedSignal>& compared) {
    for (const ComparedSignal& c : compared)
        if (c.body >= 0) return true;
    return false;
}

// Filtered measured positions and rates of every measured coordinate.
struct MeasuredMotion {
    std::vector<std::vector<double>> q, qd, qdd;  // per velocity coordinate; empty if not measured
};

MeasuredMotion measured_motion(const sim::Model& m, const Record& r, bool accelerations) {
    MeasuredMotion mm;
    mm.q.resize(size_t(m.nv)), mm.qd.resize(size_t(m.nv)), mm.qdd.resize(size_t(m.nv));
    const double dt = r.sample_period();
    for (const Signal& s : r.signals) {
        if (s.quantity != Quantity::Position) continue;
        const size_t d = size_t(s.dof);
        // The identification's cut-off, so that an effort predicted along
        // the filtered motion sees the same signal.
        mm.q[d] = low_pass(s.values, dt, r.filter_cutoff());
        mm.qd[d] = derivative(mm.q[d], dt);
        if (accelerations) mm.qdd[d] = derivative(mm.qd[d], dt);
    }
    return mm;
}

// The measured position and rate at sample k: a quadratic fitted by least
// squares to the samples within 10 ms around it (one-sided at the record's
// ends), because the zero-phase filter's estimate of the rate bends at the
// ends, where a free run starts.
void local_fit(const Record& r, const std::vector<double>& q, size_t k, double& position, double& rate) {
    const size_t n = q.size();
    const size_t half = std::max<size_t>(3, size_t(std::llround(0.01 / r.sample_period())));
    size_t a = k > half ? k - half : 0, b = std::min(n, k + half + 1);
    if (b - a < 2 * half + 1) {
        if (a == 0) b = std::min(n, 2 * half + 1);
        else a = b > 2 * half + 1 ? b - 2 * half - 1 : 0;
    }
    Eigen::MatrixXd A(Eigen::Index(b - a), 3);
    Eigen::VectorXd y(Eigen::Index(b - a));
    for (size_t i = a; i < b; ++i) {
        const double dt = r.t[i] - r.t[k];
        A.row(Eigen::Index(i - a)) << 1, dt, dt * dt;
        y[Eigen::Index(i - a)] = q[i];
    }
    const Eigen::Vector3d c = A.colPivHouseholderQr().solve(y);
    position = c[0], rate = c[1];
}

// Sets the state to the measured one at sample k (loops closed for the rest).
void measured_state(const sim::Model& m, sim::Data& d, const Record& r, size_t k, const ReplayAdjustments& adjust) {
    std::vector<sim::FixedValue> fixed;
    for (const Signal& s : r.signals) {
        if (s.quantity != Quantity::Position) continue;
        double q = 0, qd = 0;
        local_fit(r, s.values, k, q, qd);
        // The reading includes the sensor's offset; the joint is where it is without it.
        fixed.push_back({s.joint, 0, false, q - adjust.sensor_offset[size_t(s.dof)]});
        fixed.push_back({s.joint, 0, true, qd});
    }
    sim::initial_state(m, d, fixed);
    // The encoders of joints with an elastic transmission read the motor.
    sim::start_from_motor_side(m, d);
    set_measured_free_bodies(m, d, r, k);
    d.time = r.t[k];
}

double simulated_value(const sim::Model& m, const sim::Data& d, const ComparedSignal& c, const ReplayAdjustments& a,
                       const BodyKinematics& bodies, const Record& r, size_t k) {
    if (c.body >= 0) return bodies.value(c.quantity, c.body, c.component, c.point, &r, k);
    switch (c.quantity) {
    case Quantity::Position: return sim::sensed_position(m, d, c.dof) + a.sensor_offset[size_t(c.dof)];
    case Quantity::Velocity: return sim::sensed_rate(m, d, c.dof);
    case Quantity::Effort:
        // The recorded effort is what the drive was told to give; the joint got gain times it.
        return d.drives.signals[size_t(c.drive)].effort / a.effort_gain[size_t(c.dof)];
    default: break;
    }
    (void)m;
    return NAN;
}

std::vector<std::vector<double>> closed_loop(const sim::Model& m, const Record& r, const std::vector<ComparedSignal>& compared,
                                             const ReplayAdjustments& adjust) {
    const size_t n = r.t.size();
    std::vector<const std::vector<double>*> reference(m.drives.size(), nullptr), added(m.drives.size(), nullptr);
    for (size_t k = 0; k < m.drives.size(); ++k) {
        const Signal* ref = r.find(Quantity::Reference, m.drive_dof[k]);
        const Signal* add = r.find(Quantity::ControllerInput, m.drive_dof[k]);
        if (ref) reference[k] = &ref->values;
        if (add) added[k] = &add->values;
    }
    sim::Data d(m);
    measured_state(m, d, r, 0, adjust);
    BodyKinematics bodies(m);
    const bool any_body = any_body_signal(compared);
    const sim::IntegratorSettings settings = settings_for(r.sample_period());
    std::vector<std::vector<double>> out(compared.size(), std::vector<double>(n, NAN));
    for (size_t k = 0; k < n; ++k) {
        for (size_t i = 0; i < m.drives.size(); ++i) {
            if (reference[i]) d.drives.target_override[i] = (*reference[i])[k];
            d.drives.output_add[i] = added[i] ? (*added[i])[k] : 0.0;
        }
        // Positions at the sample; efforts over the period that follows it,
        // which is when the output computed at the sample acts.
        if (any_body) bodies.update(d);
        for (size_t c = 0; c < compared.size(); ++c)
            if (compared[c].quantity != Quantity::Effort) out[c][k] = simulated_value(m, d, compared[c], adjust, bodies, r, k);
        const double t_next = k + 1 < n ? r.t[k + 1] : r.t[k] + r.sample_period();
        heartbeat(double(k) / double(n));
        try {
            sim::advance(m, d, settings, t_next);
        } catch (const Error& e) {
            diverged(r, d.time, e);
        }
        for (size_t c = 0; c < compared.size(); ++c)
            if (compared[c].quantity == Quantity::Effort) out[c][k] = simulated_value(m, d, compared[c], adjust, bodies, r, k);
    }
    return out;
}

// Forward simulation from measured states over windows of `horizon`
// seconds (free replays: one window over the whole record, no effort).
void forward_windows(const sim::Model& m, const Record& r, const std::vector<ComparedSignal>& compared,
                     const ReplayAdjustments& adjust, double horizon, bool effort_driven,
                     std::vector<std::vector<double>>& out) {
    const size_t n = r.t.size();
    std::vector<const Signal*> effort(size_t(m.nv), nullptr);
    if (effort_driven)
        for (int dof = 0; dof < m.nv; ++dof) effort[size_t(dof)] = r.find(Quantity::Effort, dof);
    const double dt = r.sample_period();
    const size_t window = horizon > 0 ? std::max<size_t>(2, size_t(std::llround(horizon / dt))) : n;
    const sim::IntegratorSettings settings = settings_for(dt);
    sim::Data d(m);
    BodyKinematics bodies(m);
    const bool any_body = any_body_signal(compared);
    for (size_t w0 = 0; w0 < n; w0 += window) {
        measured_state(m, d, r, w0, adjust);
        const size_t w1 = std::min(n, w0 + window);
        for (size_t k = w0; k < w1; ++k) {
            if (any_body) bodies.update(d);
            for (size_t c = 0; c < compared.size(); ++c)
                if (compared[c].quantity != Quantity::Effort) out[c][k] = simulated_value(m, d, compared[c], adjust, bodies, r, k);
            if (k + 1 == w1) break;
            for (int dof = 0; dof < m.nv; ++dof) {
                const Signal* s = effort[size_t(dof)];
                d.effort[dof] = s ? adjust.effort_gain[size_t(dof)] *
                                        value_at(r, s->values, r.t[k] - adjust.effort_delay[size_t(dof)])
                                  : 0.0;
            }
            heartbeat(double(k) / double(n));
            try {
                sim::advance(m, d, settings, r.t[k + 1]);
            } catch (const Error& e) {
                diverged(r, d.time, e);
            }
        }
    }
}

// Efforts the actuators must give along the measured motion (inverse
// dynamics minus the joint dynamics), as the recorded command: divided by
// the gain and shifted by the delay.
void inverse_effort(const sim::Model& m, const Record& r, const std::vector<ComparedSignal>& compared,
                    const ReplayAdjustments& adjust, std::vector<std::vector<double>>& out) {
    bool any = false;
    for (const ComparedSignal& c : compared) any = any || c.quantity == Quantity::Effort;
    if (!any) return;
    const MeasuredMotion mm = measured_motion(m, r, true);
    std::vector<char> measured(size_t(m.nv), 0);
    for (int dof = 0; dof < m.nv; ++dof) measured[size_t(dof)] = !mm.q[size_t(dof)].empty();
    for (int dof = 0; dof < m.nv; ++dof)
        if (!measured[size_t(dof)] && m.closures.empty())
            throw Error(MBX_ERROR_INVALID_INPUT, m.joints[size_t(m.dof_joint[size_t(dof)])].subject(),
                        r.path + ": joint '" + m.joints[size_t(m.dof_joint[size_t(dof)])].name +
                            "' has no measured position, which inverse dynamics along the measured motion needs");
    // A closed chain's other coordinates follow from its loops; its
    // actuators' efforts are the tree's projected onto the measured ones.
    ClosedChain chain = closed_chain(m, measured);
    const size_t n = r.t.size();
    sim::Data d(m);
    d.q = m.q_reference;
    Eigen::VectorXd qd(m.nv), qdd(m.nv), tau(m.nv);
    Eigen::MatrixXd G;
    std::vector<std::vector<double>> tau_joint(size_t(m.nv), std::vector<double>(n, NAN));
    for (size_t k = 0; k < n; ++k) {
        heartbeat(double(k) / double(n));
        qd.setZero(), qdd.setZero();
        for (int dof : chain.independent) {
            const int j = m.dof_joint[size_t(dof)];
            d.q[m.joints[size_t(j)].q_index] = mm.q[size_t(dof)][k] - adjust.sensor_offset[size_t(dof)];
            qd[dof] = mm.qd[size_t(dof)][k];
            qdd[dof] = mm.qdd[size_t(dof)][k];
        }
        if (chain.active()) {
            try {
                chain.close(m, d, qd, qdd, G);
            } catch (const Error& e) {
                throw Error(e.status(), e.subject(), r.path + " at t = " + readable(r.t[k]) + " s: " + e.what());
            }
        }
        d.v = qd;
        sim::update_kinematics(m, d);
        sim::inverse_dynamics(m, d, qdd, tau);
        // An elastic transmission in its rigid limit (the link at the
        // measured motor position): its motor inertia is one more armature.
        for (const sim::Transmission& t : m.transmissions) tau[t.dof] += t.motor_inertia * qdd[t.dof];
        sim::passive_forces(m, d, sim::FrictionLaw::Regularised);
        tau -= d.qfrc_passive;
        if (chain.active()) {
            const Eigen::VectorXd ti = G.transpose() * tau;
            for (size_t i = 0; i < chain.independent.size(); ++i) tau_joint[size_t(chain.independent[i])][k] = ti[Eigen::Index(i)];
        } else {
            for (int dof = 0; dof < m.nv; ++dof) tau_joint[size_t(dof)][k] = tau[dof];
        }
    }
    for (size_t c = 0; c < compared.size(); ++c) {
        if (compared[c].quantity != Quantity::Effort) continue;
        const size_t dof = size_t(compared[c].dof);
        for (size_t k = 0; k < n; ++k)
            out[c][k] = value_at(r, tau_joint[dof], r.t[k] + adjust.effort_delay[dof]) / adjust.effort_gain[dof];
    }
}

}  // namespace

void measured_start_state(const sim::Model& m, sim::Data& d, const Record& r, size_t sample,
                          const ReplayAdjustments& adjust) {
    measured_state(m, d, r, sample, adjust);
}

std::vector<ComparedSignal> compared_signals(const Experiment& e, const sim::Model& m) {
    std::vector<ComparedSignal> out;
    for (const CompareSpec& c : e.compare) {
        if (!c.body.empty()) {
            out.push_back(bind_body_compare(e, c, m));
            continue;
        }
        const int j = joint_of_key(m, c.joint, e.path, c.line);
        const sim::JointT<double>& joint = m.joints[size_t(j)];
        ComparedSignal s;
        s.joint = j, s.dof = joint.v_index, s.q_index = joint.q_index;
        s.quantity = c.quantity, s.weight = c.weight, s.start = c.start, s.stop = c.stop, s.line = c.line;
        for (size_t k = 0; k < m.drive_dof.size(); ++k)
            if (m.drive_dof[k] == s.dof) s.drive = int(k);
        if (c.quantity != Quantity::Position && c.quantity != Quantity::Velocity && c.quantity != Quantity::Effort)
            fail(e.path, c.line, std::string("a replay cannot compare the ") + quantity_name(c.quantity) +
                                     " (compare a position, velocity or effort)");
        if (c.quantity == Quantity::Effort && e.mode == DriveMode::ClosedLoop && s.drive < 0)
            fail(e.path, c.line, "joint '" + joint.name +
                                     "' has no drive, so a closed-loop replay gives it no effort to compare "
                                     "(describe its drive, or drive the experiment by effort)");
        if (c.quantity == Quantity::Effort && e.mode == DriveMode::Free)
            fail(e.path, c.line, "a free replay has no effort to compare on joint '" + joint.name + "'");
        out.push_back(s);
    }
    return out;
}

bool in_window(const ComparedSignal& s, const Record& r, size_t k) {
    return (s.start < 0 || r.t[k] >= s.start) && (s.stop < 0 || r.t[k] <= s.stop);
}

std::vector<std::vector<double>> replay(const sim::Model& m, const Experiment& e, const Record& r,
                                        const std::vector<ComparedSignal>& compared, const ReplayAdjustments& adjust) {
    for (const ComparedSignal& c : compared)
        if (!measured_values(r, c))
            throw Error(MBX_ERROR_INVALID_INPUT,
                        c.body >= 0 ? Subject::rigid_body(m.bodies[size_t(c.body)].id, m.bodies[size_t(c.body)].name)
                                    : m.joints[size_t(c.joint)].subject(),
                        r.path + ": no measured " + quantity_name(c.quantity) + " of " +
                            (c.body >= 0 ? "body '" + m.bodies[size_t(c.body)].name + "' (a <column> of the same axis or component and point)"
                                         : "joint '" + m.joints[size_t(c.joint)].name + "'") +
                            " to compare with (" + e.path + ":" + std::to_string(c.line) + ")");
    std::vector<std::vector<double>> out;
    switch (e.mode) {
    case DriveMode::ClosedLoop:
        for (size_t k = 0; k < m.drives.size(); ++k)
            if (!r.find(Quantity::Reference, m.drive_dof[k]))
                throw Error(MBX_ERROR_INVALID_INPUT, Subject::model(m.name),
                            r.path + ": no reference column for the drive of joint '" +
                                m.joints[size_t(m.dof_joint[size_t(m.drive_dof[k])])].name +
                                "', which a closed-loop replay follows (" + e.path + ")");
        out = closed_loop(m, r, compared, adjust);
        break;
    case DriveMode::Effort:
        out.assign(compared.size(), std::vector<double>(r.t.size(), NAN));
        forward_windows(m, r, compared, adjust, e.horizon, true, out);
        inverse_effort(m, r, compared, adjust, out);
        break;
    case DriveMode::Free:
        out.assign(compared.size(), std::vector<double>(r.t.size(), NAN));
        forward_windows(m, r, compared, adjust, 0, false, out);
        break;
    }
    for (size_t c = 0; c < compared.size(); ++c)
        for (size_t k = 0; k < r.t.size(); ++k)
            if (!in_window(compared[c], r, k)) out[c][k] = NAN;
    return out;
}

std::vector<double> error_reference(const Experiment& e, const Record& r, const ComparedSignal& c,
                                    const std::vector<double>& measured) {
    if (e.mode == DriveMode::ClosedLoop || c.quantity == Quantity::Effort) return measured;
    const double dt = r.sample_period();
    const size_t window = e.mode == DriveMode::Effort ? std::max<size_t>(2, size_t(std::llround(e.horizon / dt)))
                                                      : r.t.size();
    std::vector<double> ref(measured.size());
    for (size_t k = 0; k < measured.size(); ++k) ref[k] = measured[k] - measured[k - k % window];
    return ref;
}

}  // namespace mbx::calibration
