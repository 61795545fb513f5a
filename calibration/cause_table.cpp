#include "calibration/cause_table.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "calibration/identification/causes.h"
#include "calibration/identification/identify.h"
#include "calibration/records/filters.h"
#include "calibration/simulation/model_extension.h"
#include "core/finding.h"
#include "core/heartbeat.h"
#include "core/mechatronics/body_mass.h"
#include "core/mechatronics/mounting.h"

namespace mbx::calibration {

namespace {

// ---- What many causes share ------------------------------------------------

int actuated_index(const RegressionRows& rows, int dof) {
    for (size_t a = 0; a < rows.actuated.size(); ++a)
        if (rows.actuated[a] == dof) return int(a);
    return -1;
}

// Writes weighted column entries: row (sample s, actuated coordinate at).
struct ColumnWriter {
    const RegressionRows& rows;
    Eigen::MatrixXd& c;
    Eigen::Index A = Eigen::Index(rows.actuated.size());
    void put(Eigen::Index s, int col, Eigen::Index at, double v) { c(s * A + at, col) = rows.weight[size_t(at)] * v; }
};

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
        for (Eigen::Index k = 0; k < v.rows(); ++k) {
            if ((k & 4095) == 0) heartbeat();
            x[size_t(k)] = f(v(k, dof));
        }
        law[r] = low_pass(x, rows.record_period[r], rows.record_cutoff[r]);
    }
    for (Eigen::Index s = 0; s < rows.samples; ++s)
        out[s] = law[size_t(rows.row_record[size_t(s)])][size_t(rows.row_sample[size_t(s)])];
    return out;
}

// One column on the joint's own effort, value(s) per row.
template <class F> void joint_column(const Candidate& c, const RegressionRows& rows, Eigen::MatrixXd& out, int col, F value) {
    const int a = actuated_index(rows, c.dof);
    if (a < 0) return;
    ColumnWriter w{rows, out};
    for (Eigen::Index s = 0; s < rows.samples; ++s) w.put(s, col, a, value(s));
}

void one_candidate(const RegressionRows&, const Candidate& proto, std::vector<Candidate>& out) { out.push_back(proto); }

bool positive(const Candidate&, const Eigen::VectorXd& theta) { return theta[0] > 0; }

void first_at_least_zero(const Candidate&, size_t i, double, double& lower, double&) {
    if (i == 0) lower = 0;
}

double parameter(const SelectedCause& c, const char* name, double fallback = 0) {
    for (const Estimate& e : c.parameters)
        if (e.name == name) return e.value;
    return fallback;
}

std::string number(double v) {
    std::ostringstream s;
    s.precision(4);
    s << v;
    return s.str();
}

// Whether the joint's Coulomb law has no friction yet (its smoothing speed is then the records').
bool frictionless(const sim::JointDynamics& d) { return d.coulomb == 0 && !(d.asymmetric && d.coulomb_negative > 0); }

// ---- viscous_friction: damping b q̇ ------------------------------------------

void viscous_columns(const Candidate& c, const RegressionRows& rows, Eigen::MatrixXd& out) {
    joint_column(c, rows, out, 0, [&](Eigen::Index s) { return rows.qd(s, c.dof); });
}

void viscous_extend(const SelectedCause& c, ExtensionStep& step) {
    JointUpdate* u = step.joint(c);
    if (!u) return;
    const double v = parameter(c, "damping");
    u->after.damping += v;
    if (u->after.asymmetric) u->after.damping_negative += v;
}

// ---- coulomb_friction: c sgn(q̇), smoothed at 1 % of the joint's RMS speed --

void coulomb_columns(const Candidate& c, const RegressionRows& rows, Eigen::MatrixXd& out) {
    if (actuated_index(rows, c.dof) < 0) return;
    const double vs = sign_speed(rows, c.dof);
    const Eigen::VectorXd law = filtered_law(rows, c.dof, [vs](double v) { return std::tanh(v / vs); });
    joint_column(c, rows, out, 0, [&](Eigen::Index s) { return law[s]; });
}

void coulomb_extend(const SelectedCause& c, ExtensionStep& step) {
    JointUpdate* u = step.joint(c);
    if (!u) return;
    sim::JointDynamics& d = u->after;
    const double v = parameter(c, "coulomb");
    if (frictionless(d)) d.coulomb_velocity = sign_speed(step.fit, c.candidate.dof);
    d.coulomb += v;
    if (d.asymmetric) d.coulomb_negative += v;
}

// ---- effort_offset: a constant effort the model lacks -----------------------

void offset_columns(const Candidate& c, const RegressionRows& rows, Eigen::MatrixXd& out) {
    joint_column(c, rows, out, 0, [](Eigen::Index) { return 1.0; });
}

void offset_extend(const SelectedCause& c, ExtensionStep& step) {
    if (JointUpdate* u = step.joint(c)) u->after.offset += parameter(c, "offset");
}

// ---- armature: a rotor inertia on the joint coordinate ----------------------

void armature_columns(const Candidate& c, const RegressionRows& rows, Eigen::MatrixXd& out) {
    joint_column(c, rows, out, 0, [&](Eigen::Index s) { return rows.qdd(s, c.dof); });
}

void armature_extend(const SelectedCause& c, ExtensionStep& step) {
    if (JointUpdate* u = step.joint(c)) u->after.armature += parameter(c, "armature");
}

// ---- asymmetric_friction: Coulomb (and damping) different each way ----------

// Asymmetric Coulomb friction alone, or with asymmetric damping: a zero
// damping asymmetry would otherwise fail the significance test and hide a
// clear Coulomb asymmetry.
void asymmetric_candidates(const RegressionRows&, const Candidate& proto, std::vector<Candidate>& out) {
    Candidate c = proto;
    c.parameters = {"coulomb_asymmetry"};
    out.push_back(c);
    c.parameters = {"coulomb_asymmetry", "damping_asymmetry"};
    out.push_back(c);
}

void asymmetric_columns(const Candidate& c, const RegressionRows& rows, Eigen::MatrixXd& out) {
    if (actuated_index(rows, c.dof) < 0) return;
    // c sgn + dc |sgn| is c + dc one way and c - dc the other; likewise for damping.
    const double vs = sign_speed(rows, c.dof);
    const Eigen::VectorXd law = filtered_law(rows, c.dof, [vs](double v) { return std::abs(std::tanh(v / vs)); });
    joint_column(c, rows, out, 0, [&](Eigen::Index s) { return law[s]; });
    if (c.parameters.size() > 1) joint_column(c, rows, out, 1, [&](Eigen::Index s) { return std::abs(rows.qd(s, c.dof)); });
}

// Makes a symmetric law direction-dependent (the negative side starts equal).
void split_directions(sim::JointDynamics& d) {
    if (d.asymmetric) return;
    d.asymmetric = true;
    d.coulomb_negative = d.coulomb;
    d.damping_negative = d.damping;
}

void asymmetric_extend(const SelectedCause& c, ExtensionStep& step) {
    JointUpdate* u = step.joint(c);
    if (!u) return;
    sim::JointDynamics& d = u->after;
    // c sgn + dc |sgn| is c + dc for qd > 0 and c - dc for qd < 0 (damping alike).
    split_directions(d);
    const double dc = parameter(c, "coulomb_asymmetry"), dd = parameter(c, "damping_asymmetry");
    if (d.coulomb == 0 && d.coulomb_negative == 0) d.coulomb_velocity = sign_speed(step.fit, c.candidate.dof);
    d.coulomb += dc, d.coulomb_negative -= dc;
    d.damping += dd, d.damping_negative -= dd;
    for (double* v : {&d.coulomb, &d.coulomb_negative, &d.damping, &d.damping_negative})
        if (*v < 0) {
            step.ext.warnings.push_back("asymmetric friction on joint '" + u->name +
                                        "' would need a negative friction one way; clipped at 0");
            *v = 0;
        }
}

// ---- stribeck_friction: a friction peak at rest, falling off with speed -----

// Stribeck speeds from a grid around the joint's typical speed.
void stribeck_candidates(const RegressionRows& fit, const Candidate& proto, std::vector<Candidate>& out) {
    const double typical = 100 * sign_speed(fit, proto.dof);
    for (double f : {0.02, 0.05, 0.1, 0.2, 0.5}) {
        Candidate c = proto;
        c.parameters = {"stribeck"};
        c.scale = f * typical;
        out.push_back(c);
    }
}

void stribeck_columns(const Candidate& c, const RegressionRows& rows, Eigen::MatrixXd& out) {
    if (actuated_index(rows, c.dof) < 0) return;
    const double vs = c.smoothing > 0 ? c.smoothing : sign_speed(rows, c.dof), st = c.scale;
    const Eigen::VectorXd law = filtered_law(rows, c.dof, [vs, st](double v) {
        return std::tanh(v / vs) * std::exp(-(v / st) * (v / st));
    });
    joint_column(c, rows, out, 0, [&](Eigen::Index s) { return law[s]; });
}

void stribeck_extend(const SelectedCause& c, ExtensionStep& step) {
    JointUpdate* u = step.joint(c);
    if (!u) return;
    sim::JointDynamics& d = u->after;
    d.stribeck += parameter(c, "stribeck");
    d.stribeck_velocity = parameter(c, "stribeck_velocity", c.candidate.scale);
    // The law's smoothing of sign(q̇) was refined with the Stribeck speed; it is the joint's law now.
    if (c.candidate.smoothing > 0) d.coulomb_velocity = c.candidate.smoothing;
    else if (frictionless(d)) d.coulomb_velocity = sign_speed(step.fit, c.candidate.dof);
}

// ---- position_dependent_effort: an effort k q the model lacks ---------------

void position_columns(const Candidate& c, const RegressionRows& rows, Eigen::MatrixXd& out) {
    joint_column(c, rows, out, 0, [&](Eigen::Index s) { return rows.q(s, c.q_index); });
}

void position_extend(const SelectedCause& c, ExtensionStep& step) {
    JointUpdate* u = step.joint(c);
    if (!u) return;
    sim::JointDynamics& d = u->after;
    // The actuator holds k q besides the model: a spring k (q - rest) with the same effect.
    const double k = parameter(c, "stiffness");
    const double total = d.stiffness + k;
    if (total > 0) {
        d.rest = d.stiffness * d.rest / total;
        d.stiffness = total;
    } else {
        step.refuse(*u, "a negative stiffness (an effort that pushes away from the rest position) is no spring: "
                        "the description file cannot hold it");
    }
}

// ---- actuator_gain: the actuator gives g times the commanded effort ---------

void gain_columns(const Candidate& c, const RegressionRows& rows, Eigen::MatrixXd& out) {
    const int a = actuated_index(rows, c.dof);
    joint_column(c, rows, out, 0, [&](Eigen::Index s) { return rows.effort(s, a); });
}

// A gain 1 - theta near zero is no correction but another machine: with
// every body's mass and the actuator's effort gone, any record fits exactly.
bool gain_physical(const Candidate&, const Eigen::VectorXd& theta) { return theta[0] < 0.9; }

void gain_bounds(const Candidate&, size_t i, double, double&, double& upper) {
    if (i == 0) upper = 0.9;
}

void gain_extend(const SelectedCause& c, ExtensionStep& step) {
    const int dof = c.candidate.dof;
    const double g = 1 - parameter(c, "gain_deficit");
    step.ext.adjust.effort_gain[size_t(dof)] *= g;
    const int k = step.drive_of(dof);
    if (k >= 0) step.ext.drive_gain[size_t(k)] *= g;
    step.unwritten("the description file has no actuator gain yet: scale the drive's amplifier gain or motor "
                   "constant by " + number(g));
}

// ---- delay: the joint feels the effort of d seconds ago ---------------------

// The effort d seconds before each row (linear interpolation between samples).
double effort_before(const RegressionRows& rows, Eigen::Index s, int a, double d) {
    const Eigen::MatrixXd& e = rows.record_effort[size_t(rows.row_record[size_t(s)])];
    const double back = double(rows.row_sample[size_t(s)]) - d / rows.record_period[size_t(rows.row_record[size_t(s)])];
    const double at = std::clamp(back, 0.0, double(e.rows() - 1));
    const Eigen::Index k0 = std::min(Eigen::Index(std::floor(at)), e.rows() - 1), k1 = std::min(k0 + 1, e.rows() - 1);
    const double w = at - double(k0);
    return (1 - w) * e(k0, a) + w * e(k1, a);
}

void delay_columns(const Candidate& c, const RegressionRows& rows, Eigen::MatrixXd& out) {
    const int a = actuated_index(rows, c.dof);
    const bool exact = c.scale > 0 && rows.row_record.size() == size_t(rows.samples) && !rows.record_effort.empty();
    if (exact) {
        // tau(t) - tau(t - d) is left over; per second of the delay at the
        // setting d = `scale`, so the coefficient is the delay when the setting is.
        joint_column(c, rows, out, 0, [&](Eigen::Index s) {
            return (rows.effort(s, a) - effort_before(rows, s, a, c.scale)) / c.scale;
        });
    } else {
        // To first order, tau(t - d) ~ tau - d dtau/dt.
        joint_column(c, rows, out, 0, [&](Eigen::Index s) { return rows.effort_rate(s, a); });
    }
}

void delay_extend(const SelectedCause& c, ExtensionStep& step) {
    const int dof = c.candidate.dof;
    const double delay = parameter(c, "delay");
    step.ext.adjust.effort_delay[size_t(dof)] += delay;
    const int k = step.drive_of(dof);
    if (k < 0) {
        step.unwritten("the joint has no drive whose controller could hold the delay");
        return;
    }
    // The drive in the description that this model drive came from.
    Drive& drive = step.ext.options.drives[size_t(k)];
    ControllerSpec& ctl = drive.spec.controller;
    const double before = ctl.delay;
    double added = delay;
    if (ctl.sample_period > 0) {
        // A discrete controller delays by whole samples.
        added = std::round(delay / ctl.sample_period) * ctl.sample_period;
        if (added == 0) {
            step.unwritten("shorter than half the controller's sample period (" + number(ctl.sample_period) +
                           " s), which is the smallest delay the drive can hold");
            return;
        }
    }
    ctl.delay += added;
    DriveUpdate* u = nullptr;
    for (DriveUpdate& d : step.ext.drives)
        if (d.drive == k) u = &d;
    if (!u) {
        const std::string& constraint = step.model.joints[size_t(step.model.dof_joint[size_t(dof)])].constraint_id;
        step.ext.drives.push_back({k, constraint, drive.name, before, before});
        u = &step.ext.drives.back();
    }
    u->delay_after = ctl.delay;
}

// ---- sensor_offset: a position reading off by a constant --------------------

void sensor_columns(const Candidate& c, const RegressionRows& rows, Eigen::MatrixXd& out) {
    // A reading off by o puts the model at q - o: its effort changes by -o dtau/dq.
    // To second order, -o dtau/dq + o^2/2 d2tau/dq2: the secant through the anchor.
    ColumnWriter w{rows, out};
    const Eigen::MatrixXd& d1 = rows.effort_by_position[size_t(c.dof)];
    const Eigen::MatrixXd& d2 = rows.effort_by_position2[size_t(c.dof)];
    for (Eigen::Index s = 0; s < rows.samples; ++s)
        for (Eigen::Index k = 0; k < w.A; ++k) w.put(s, 0, k, -d1(s, k) + 0.5 * c.offset_anchor * d2(s, k));
}

void sensor_extend(const SelectedCause& c, ExtensionStep& step) {
    step.ext.adjust.sensor_offset[size_t(c.candidate.dof)] += parameter(c, "offset");
    step.unwritten("a property of the measurement, not of the machine: subtract it from the recorded position");
}

// ---- mass_error: a body's mass, centre of mass or inertia off ---------------

void mass_candidates(const RegressionRows& fit, const Candidate& proto, std::vector<Candidate>& out) {
    for (Candidate& c : body_candidates(fit, proto.body, proto.body_inertia)) out.push_back(std::move(c));
}

void mass_columns(const Candidate& c, const RegressionRows& rows, Eigen::MatrixXd& out) {
    ColumnWriter w{rows, out};
    const Eigen::MatrixXd& R = rows.inertial_regressor[size_t(c.body)];
    for (Eigen::Index s = 0; s < rows.samples; ++s)
        for (Eigen::Index k = 0; k < w.A; ++k)
            for (Eigen::Index p = 0; p < c.inertial_directions.cols(); ++p)
                w.put(s, int(p), k, R.row(s * w.A + k).dot(c.inertial_directions.col(p)));
}

bool mass_physical(const Candidate& c, const Eigen::VectorXd& theta) {
    // A mass (1 + theta) m near zero is no correction but another machine.
    const BodyCorrection b = c.body_correction(theta);
    if (!(b.mass_scale > 0.1)) return false;
    // A centre of mass moved beyond the body's own extent (its radius of
    // gyration about the centre of mass, or half the centre's distance from
    // the body origin for a compact body) is no CAD error but another
    // cause's signature taken up.
    if (!(b.com_shift.norm() <= largest_com_shift(c.body_inertia))) return false;
    // An inertia about the centre of mass no rigid body has (not positive
    // definite, or a principal moment above the sum of the other two) is a
    // fit to noise or to another cause. (The check the description file's
    // reader makes, so what is named can be written.)
    if (!b.inertia_change.isZero(0)) {
        const double one = 1;
        const sim::Inertia<double> corrected =
            corrected_inertia(c.body_inertia, one, b.com_shift.data(), b.inertia_change.data());
        if (!implausible_inertia(about_com(corrected)).empty()) return false;
    }
    return true;
}

void mass_bounds(const Candidate& c, size_t i, double, double& lower, double&) {
    if (c.parameters[i] == "mass_change") lower = -0.9;
}

void mass_extend(const SelectedCause& c, ExtensionStep& step) {
    const int b = c.candidate.body;
    Eigen::VectorXd theta(Eigen::Index(c.parameters.size()));
    for (size_t k = 0; k < c.parameters.size(); ++k) theta[Eigen::Index(k)] = c.parameters[k].value;
    const BodyCorrection correction = c.candidate.body_correction(theta);
    step.ext.body_corrections[size_t(b)] = correction.after(step.ext.body_corrections[size_t(b)]);
    const sim::BodyT<double>& body = step.model.bodies[size_t(b)];
    if (body.source < 0) {
        step.unwritten("the body has no CAD part to hold a mass correction");
        return;
    }
    BodyUpdate* u = nullptr;
    for (BodyUpdate& x : step.ext.bodies)
        if (x.sim_body == b) u = &x;
    if (!u) {
        step.ext.bodies.push_back({b, body.source, step.mechanism.bodies[size_t(body.source)].id, body.name, {}});
        u = &step.ext.bodies.back();
    }
    u->correction = correction.after(u->correction);
}

// ---- compliance and backlash: a motor inertia behind a spring or a dead band -

// The rigid limit: the motor inertia is an armature; stiffness, damping and
// width have no column (the simulation fit finds them).
void transmission_columns(const Candidate& c, const RegressionRows& rows, Eigen::MatrixXd& out) {
    for (size_t i = 0; i < c.parameters.size(); ++i)
        if (c.parameters[i] == "motor_inertia")
            joint_column(c, rows, out, int(i), [&](Eigen::Index s) { return rows.qdd(s, c.dof); });
}

// Stiffness and motor inertia stay within a thousandth of their start; damping non-negative.
void compliance_bounds(const Candidate&, size_t i, double start, double& lower, double&) {
    lower = i == 1 ? 0.0 : 1e-3 * start;
}

void backlash_bounds(const Candidate&, size_t i, double start, double& lower, double&) {
    lower = i == 0 ? 0.0 : 1e-3 * start;
}

void transmission_extend(const SelectedCause& c, ExtensionStep& step) {
    JointUpdate* u = step.joint(c);
    if (!u) return;
    // The motor side the rigid model saw as armature, now an inertia of its
    // own behind a spring and damper, or a dead band.
    sim::Transmission t;
    t.stiffness = parameter(c, "stiffness");
    t.damping = parameter(c, "damping");
    t.backlash = parameter(c, "width");
    t.motor_inertia = parameter(c, "motor_inertia");
    if (!((t.stiffness > 0 || t.backlash > 0) && t.motor_inertia > 0 && t.damping >= 0)) {
        step.refuse(*u, "the fitted transmission is not physical (stiffness or width, and motor inertia, must be positive)");
        return;
    }
    const int k = step.drive_of(c.candidate.dof);
    if (k >= 0 && step.model.drives[size_t(k)].armature > 0)
        step.ext.warnings.push_back("the rotor inertia of drive '" + step.model.drives[size_t(k)].name + "' (" +
                                    number(step.model.drives[size_t(k)].armature) + ") moves to the motor side of the "
                                    "transmission on joint '" + u->name + "', on top of the fitted motor inertia");
    u->transmission_after = t;
}

// ---- mounting_tilt: gravity turned in the base frame by a floor out of level -

// The world axes a tilt turns gravity about (x, y): parameter i's.
constexpr const char* kTiltNames[2] = {"tilt_x", "tilt_y"};

Eigen::Vector3d tilt_axis(const std::string& parameter) {
    return parameter == kTiltNames[0] ? Eigen::Vector3d::UnitX() : Eigen::Vector3d::UnitY();
}

// Both angles, or the one the records see when gravity's turn about the
// other moves no actuated joint (a planar arm swinging about y feels no turn
// about x): its column is zero and the joint fit of both is singular.
void tilt_candidates(const RegressionRows& fit, const Candidate& proto, std::vector<Candidate>& out) {
    if (!(fit.gravity.norm() > 0) || fit.effort_by_gravity.size() != 3) return;
    std::vector<std::string> seen;
    for (const char* name : kTiltNames) {
        const Eigen::Vector3d turn = tilt_axis(name).cross(fit.gravity);
        double size = 0;
        for (int k = 0; k < 3; ++k) size += std::abs(turn[k]) * fit.effort_by_gravity[size_t(k)].cwiseAbs().sum();
        if (size > 1e-9 * fit.gravity.norm() * double(fit.samples)) seen.push_back(name);
    }
    if (seen.empty()) return;
    Candidate c = proto;
    c.parameters = seen;
    out.push_back(c);
    if (seen.size() == 2)
        for (const std::string& name : seen) {
            c.parameters = {name};
            out.push_back(c);
        }
}

// A small angle θ about axis a adds θ (a × g) to gravity, and inverse
// dynamics is linear in gravity (second order: 0.14 % of the gravity effort at 3°).
void tilt_columns(const Candidate& c, const RegressionRows& rows, Eigen::MatrixXd& out) {
    ColumnWriter w{rows, out};
    for (size_t p = 0; p < c.parameters.size(); ++p) {
        const Eigen::Vector3d turn = tilt_axis(c.parameters[p]).cross(rows.gravity);
        for (Eigen::Index s = 0; s < rows.samples; ++s)
            for (Eigen::Index a = 0; a < w.A; ++a) {
                double v = 0;
                for (int k = 0; k < 3; ++k) v += turn[k] * rows.effort_by_gravity[size_t(k)](s, a);
                w.put(s, int(p), a, v);
            }
    }
}

// A floor or table out of level by a few degrees; beyond a tenth of a
// radian the first-order column is no longer the law, and it is another
// cause's signature taken up.
bool tilt_physical(const Candidate&, const Eigen::VectorXd& theta) { return theta.cwiseAbs().maxCoeff() <= 0.1; }

void tilt_extend(const SelectedCause& c, ExtensionStep& step) {
    MountingSpec found;
    found.given = true;
    found.tilt_x = parameter(c, kTiltNames[0]), found.tilt_y = parameter(c, kTiltNames[1]);
    step.ext.options.gravity = tilted_gravity(step.ext.options.gravity, found);
    step.ext.tilt += Eigen::Vector2d(found.tilt_x, found.tilt_y);
    step.ext.tilted = true;
}

// A one-parameter cause on a joint.
CauseKind joint_cause(CauseId id, const char* name, const char* meaning, std::vector<std::string> parameters,
                      void (*columns)(const Candidate&, const RegressionRows&, Eigen::MatrixXd&),
                      void (*extend)(const SelectedCause&, ExtensionStep&)) {
    CauseKind k{};
    k.id = id, k.name = name, k.subject = CauseSubject::ActuatedJoint, k.meaning = meaning;
    k.parameters = std::move(parameters);
    k.candidates = one_candidate, k.columns = columns, k.refinement = Refinement::None, k.extend = extend;
    k.simulated = true, k.needs_effort = true;
    return k;
}

std::vector<CauseKind> make_table() {
    std::vector<CauseKind> t;
    CauseKind k = joint_cause(CauseId::ViscousFriction, "viscous_friction", "damping b q̇ on the joint", {"damping"},
                              viscous_columns, viscous_extend);
    k.physical = positive, k.simulation_bounds = first_at_least_zero, k.needs_effort = false;
    t.push_back(k);
    k = joint_cause(CauseId::CoulombFriction, "coulomb_friction", "Coulomb friction c sgn(q̇) on the joint", {"coulomb"},
                    coulomb_columns, coulomb_extend);
    k.physical = positive, k.simulation_bounds = first_at_least_zero, k.needs_effort = false;
    t.push_back(k);
    t.push_back(joint_cause(CauseId::EffortOffset, "effort_offset", "a constant effort on the joint", {"offset"}, offset_columns,
                            offset_extend));
    k = joint_cause(CauseId::Armature, "armature", "a rotor inertia on the joint coordinate", {"armature"}, armature_columns,
                    armature_extend);
    k.physical = positive, k.simulation_bounds = first_at_least_zero, k.rigid_motor = true;
    t.push_back(k);
    k = joint_cause(CauseId::AsymmetricFriction, "asymmetric_friction",
                    "Coulomb friction (and damping) different in each direction", {"coulomb_asymmetry"}, asymmetric_columns,
                    asymmetric_extend);
    k.candidates = asymmetric_candidates, k.simulated = false;
    t.push_back(k);
    k = joint_cause(CauseId::StribeckFriction, "stribeck_friction",
                    "friction above Coulomb's at rest, falling off with speed", {"stribeck"}, stribeck_columns, stribeck_extend);
    k.candidates = stribeck_candidates, k.physical = positive, k.simulated = false;
    k.refinement = Refinement::GridAndSpeeds, k.settings = 2;  // the Stribeck and smoothing speeds
    t.push_back(k);
    t.push_back(joint_cause(CauseId::PositionDependentEffort, "position_dependent_effort",
                            "an effort k q along the joint's position (a spring)", {"stiffness"}, position_columns, position_extend));
    k = joint_cause(CauseId::ActuatorGain, "actuator_gain", "the actuator gives less effort than recorded", {"gain_deficit"},
                    gain_columns, gain_extend);
    k.physical = gain_physical, k.simulation_bounds = gain_bounds, k.rigid_motor = true;
    t.push_back(k);
    k = joint_cause(CauseId::Delay, "delay", "the joint feels the recorded effort late", {"delay"}, delay_columns, delay_extend);
    k.physical = positive, k.simulation_bounds = first_at_least_zero, k.refinement = Refinement::ExactLag;
    t.push_back(k);
    k = joint_cause(CauseId::SensorOffset, "sensor_offset", "a position reading off by a constant", {"offset"}, sensor_columns,
                    sensor_extend);
    k.subject = CauseSubject::AnyJoint, k.refinement = Refinement::OffsetAnchor, k.simulated = false;
    k.row_parts = kPositionSensitivity;
    k.needs_effort = false;
    t.push_back(k);
    k = CauseKind{};
    k.id = CauseId::MassError, k.name = "mass_error", k.subject = CauseSubject::Body;
    k.meaning = "a body's mass, centre of mass or inertia differs from the CAD's";
    k.parameters = {"mass_change"};  // and the variants' centre-of-mass shifts and inertia changes
    k.candidates = mass_candidates, k.columns = mass_columns, k.physical = mass_physical;
    k.refinement = Refinement::ComAnchor, k.extend = mass_extend, k.simulated = true;
    k.simulation_bounds = mass_bounds, k.row_parts = kInertialRegressor;
    t.push_back(k);
    k = joint_cause(CauseId::Compliance, "compliance", "a motor inertia behind a spring and damper",
                    {"stiffness", "damping", "motor_inertia"},
                    transmission_columns, transmission_extend);
    k.subject = CauseSubject::Transmission, k.candidates = nullptr, k.elastic = true;
    k.simulation_bounds = compliance_bounds;
    t.push_back(k);
    k = joint_cause(CauseId::Backlash, "backlash", "a motor inertia behind a dead band between stops", {"width", "motor_inertia"},
                    transmission_columns, transmission_extend);
    k.subject = CauseSubject::Transmission, k.candidates = nullptr, k.elastic = true;
    k.simulation_bounds = backlash_bounds;
    t.push_back(k);
    k = CauseKind{};
    k.id = CauseId::MountingTilt, k.name = "mounting_tilt", k.subject = CauseSubject::Mounting;
    k.meaning = "gravity turned in the base frame (a floor or table out of level)";
    k.parameters = {kTiltNames[0], kTiltNames[1]};  // (rad) or the one the records see
    k.candidates = tilt_candidates, k.columns = tilt_columns, k.physical = tilt_physical;
    k.refinement = Refinement::None, k.extend = tilt_extend, k.simulated = false;
    k.row_parts = kGravityShares;
    t.push_back(k);
    return t;
}

}  // namespace

const std::vector<CauseKind>& cause_table() {
    static const std::vector<CauseKind> table = make_table();
    return table;
}

const CauseKind& cause_kind(const std::string& name) {
    for (const CauseKind& k : cause_table())
        if (name == k.name) return k;
    throw Error(MBX_ERROR_INVALID_INPUT, Subject::model("calibration"), "no calibration cause is named '" + name + "'");
}

const char* cause_name(CauseId id) { return cause_table()[size_t(id)].name; }

}  // namespace mbx::calibration
