#include "calibration/simulation/model_extension.h"

#include <cmath>
#include <sstream>

#include "calibration/identification/causes.h"

namespace mbx::calibration {

namespace {

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

JointUpdate& update_of(ModelExtension& ext, const Mechanism& mech, const sim::BuildOptions& base,
                       const sim::Model& model, int sim_joint) {
    const sim::JointT<double>& j = model.joints[size_t(sim_joint)];
    for (JointUpdate& u : ext.joints)
        if (u.sim_joint == sim_joint) return u;
    JointUpdate u;
    u.sim_joint = sim_joint;
    u.mechanism_joint = j.source;
    u.name = j.name;
    u.constraint_id = j.constraint_id;
    u.linear = j.kind == sim::JointKind::Prismatic;
    if (j.source >= 0) u.primitive = mech.joints[size_t(j.source)].primitive_index;
    const auto it = base.joint_dynamics.find(j.source);
    if (it != base.joint_dynamics.end()) u.before = it->second;
    u.after = u.before;
    const auto t = base.transmissions.find(j.source);
    if (t != base.transmissions.end()) u.transmission_before = t->second;
    u.transmission_after = u.transmission_before;
    ext.joints.push_back(u);
    return ext.joints.back();
}

// Makes a symmetric law direction-dependent (the negative side starts equal).
void split_directions(sim::JointDynamics& d) {
    if (d.asymmetric) return;
    d.asymmetric = true;
    d.coulomb_negative = d.coulomb;
    d.damping_negative = d.damping;
}

}  // namespace

ModelExtension extend(const Mechanism& mech, const sim::BuildOptions& base, const sim::Model& model,
                      const Identification& id, size_t count, const RegressionRows& fit) {
    ModelExtension ext;
    ext.options = base;
    ext.body_corrections.assign(model.bodies.size(), BodyCorrection());
    ext.drive_gain.assign(model.drives.size(), 1.0);
    ext.adjust = ReplayAdjustments(model.nv);
    auto drive_of = [&](int dof) {
        for (size_t k = 0; k < model.drive_dof.size(); ++k)
            if (model.drive_dof[k] == dof) return int(k);
        return -1;
    };
    for (size_t i = 0; i < std::min(count, id.causes.size()); ++i) {
        const SelectedCause& c = id.causes[i];
        const std::string& cause = c.candidate.cause;
        const int dof = c.candidate.dof;
        auto unwritten = [&](const std::string& reason) { ext.unwritten.push_back({int(i), reason}); };
        if (cause == "mass_error") {
            const int b = c.candidate.body;
            Eigen::VectorXd theta(Eigen::Index(c.parameters.size()));
            for (size_t k = 0; k < c.parameters.size(); ++k) theta[Eigen::Index(k)] = c.parameters[k].value;
            const BodyCorrection correction = c.candidate.body_correction(theta);
            ext.body_corrections[size_t(b)] = correction.after(ext.body_corrections[size_t(b)]);
            const sim::BodyT<double>& body = model.bodies[size_t(b)];
            if (body.source < 0) {
                unwritten("the body has no CAD part to hold a mass correction");
                continue;
            }
            BodyUpdate* u = nullptr;
            for (BodyUpdate& x : ext.bodies)
                if (x.sim_body == b) u = &x;
            if (!u) {
                ext.bodies.push_back({b, body.source, mech.bodies[size_t(body.source)].id, body.name, {}});
                u = &ext.bodies.back();
            }
            u->correction = correction.after(u->correction);
            continue;
        }
        if (cause == "sensor_offset") {
            ext.adjust.sensor_offset[size_t(dof)] += parameter(c, "offset");
            unwritten("a property of the measurement, not of the machine: subtract it from the recorded position");
            continue;
        }
        if (cause == "actuator_gain") {
            const double g = 1 - parameter(c, "gain_deficit");
            ext.adjust.effort_gain[size_t(dof)] *= g;
            const int k = drive_of(dof);
            if (k >= 0) ext.drive_gain[size_t(k)] *= g;
            unwritten("the description file has no actuator gain yet: scale the drive's amplifier gain or motor "
                      "constant by " + number(g));
            continue;
        }
        if (cause == "delay") {
            const double delay = parameter(c, "delay");
            ext.adjust.effort_delay[size_t(dof)] += delay;
            const int k = drive_of(dof);
            if (k < 0) {
                unwritten("the joint has no drive whose controller could hold the delay");
                continue;
            }
            // The drive in the description that this model drive came from.
            Drive& drive = ext.options.drives[size_t(k)];
            ControllerSpec& ctl = drive.spec.controller;
            const double before = ctl.delay;
            double added = delay;
            if (ctl.sample_period > 0) {
                // A discrete controller delays by whole samples.
                added = std::round(delay / ctl.sample_period) * ctl.sample_period;
                if (added == 0) {
                    unwritten("shorter than half the controller's sample period (" + number(ctl.sample_period) +
                              " s), which is the smallest delay the drive can hold");
                    continue;
                }
            }
            ctl.delay += added;
            DriveUpdate* u = nullptr;
            for (DriveUpdate& d : ext.drives)
                if (d.drive == k) u = &d;
            if (!u) {
                ext.drives.push_back({k, model.joints[size_t(model.dof_joint[size_t(dof)])].constraint_id, drive.name, before, before});
                u = &ext.drives.back();
            }
            u->delay_after = ctl.delay;
            continue;
        }
        if (c.candidate.joint < 0 || model.joints[size_t(c.candidate.joint)].source < 0) {
            unwritten("no CAD joint to hold it");
            continue;
        }
        JointUpdate& u = update_of(ext, mech, base, model, c.candidate.joint);
        sim::JointDynamics& d = u.after;
        u.causes.push_back(cause);
        if (cause == "viscous_friction") {
            const double v = parameter(c, "damping");
            d.damping += v;
            if (d.asymmetric) d.damping_negative += v;
        } else if (cause == "coulomb_friction") {
            const double v = parameter(c, "coulomb");
            if (d.coulomb == 0 && !(d.asymmetric && d.coulomb_negative > 0)) d.coulomb_velocity = sign_speed(fit, dof);
            d.coulomb += v;
            if (d.asymmetric) d.coulomb_negative += v;
        } else if (cause == "effort_offset") {
            d.offset += parameter(c, "offset");
        } else if (cause == "armature") {
            d.armature += parameter(c, "armature");
        } else if (cause == "asymmetric_friction") {
            // c sgn + dc |sgn| is c + dc for qd > 0 and c - dc for qd < 0 (damping alike).
            split_directions(d);
            const double dc = parameter(c, "coulomb_asymmetry"), dd = parameter(c, "damping_asymmetry");
            if (d.coulomb == 0 && d.coulomb_negative == 0) d.coulomb_velocity = sign_speed(fit, dof);
            d.coulomb += dc, d.coulomb_negative -= dc;
            d.damping += dd, d.damping_negative -= dd;
            for (double* v : {&d.coulomb, &d.coulomb_negative, &d.damping, &d.damping_negative})
                if (*v < 0) {
                    ext.warnings.push_back("asymmetric friction on joint '" + u.name +
                                           "' would need a negative friction one way; clipped at 0");
                    *v = 0;
                }
        } else if (cause == "stribeck_friction") {
            d.stribeck += parameter(c, "stribeck");
            d.stribeck_velocity = parameter(c, "stribeck_velocity", c.candidate.scale);
            // The law's smoothing of sign(q̇) was refined with the Stribeck speed; it is the joint's law now.
            if (c.candidate.smoothing > 0) d.coulomb_velocity = c.candidate.smoothing;
            else if (d.coulomb == 0 && !(d.asymmetric && d.coulomb_negative > 0)) d.coulomb_velocity = sign_speed(fit, dof);
        } else if (cause == "position_dependent_effort") {
            // The actuator holds k q besides the model: a spring k (q - rest) with the same effect.
            const double k = parameter(c, "stiffness");
            const double total = d.stiffness + k;
            if (total > 0) {
                d.rest = d.stiffness * d.rest / total;
                d.stiffness = total;
            } else {
                u.causes.pop_back();
                unwritten("a negative stiffness (an effort that pushes away from the rest position) is no spring: "
                          "the description file cannot hold it");
            }
        } else if (cause == "compliance" || cause == "backlash") {
            // The motor side the rigid model saw as armature, now an inertia
            // of its own behind a spring and damper, or a dead band.
            sim::Transmission t;
            t.stiffness = parameter(c, "stiffness");
            t.damping = parameter(c, "damping");
            t.backlash = parameter(c, "width");
            t.motor_inertia = parameter(c, "motor_inertia");
            if (!((t.stiffness > 0 || t.backlash > 0) && t.motor_inertia > 0 && t.damping >= 0)) {
                u.causes.pop_back();
                unwritten("the fitted transmission is not physical (stiffness or width, and motor inertia, must be positive)");
                continue;
            }
            const int k = drive_of(dof);
            if (k >= 0 && model.drives[size_t(k)].armature > 0)
                ext.warnings.push_back("the rotor inertia of drive '" + model.drives[size_t(k)].name + "' (" +
                                       number(model.drives[size_t(k)].armature) + ") moves to the motor side of the "
                                       "transmission on joint '" + u.name + "', on top of the fitted motor inertia");
            u.transmission_after = t;
        } else {
            u.causes.pop_back();
            unwritten("mbx has no model extension for " + cause + " yet");
        }
    }
    // Joints whose dynamics the causes changed take them into the build.
    for (const JointUpdate& u : ext.joints) {
        ext.options.joint_dynamics[u.mechanism_joint] = u.after;
        if (u.transmission_after) ext.options.transmissions[u.mechanism_joint] = *u.transmission_after;
    }
    return ext;
}

sim::Model extended_model(const Mechanism& mech, const ModelExtension& ext, DriveMode mode) {
    sim::BuildOptions options = ext.options;
    for (size_t k = 0; k < options.drives.size() && k < ext.drive_gain.size(); ++k)
        options.drives[k].efficiency *= ext.drive_gain[k];
    sim::Model m = sim::build_model(mech, options);
    for (size_t b = 1; b < m.bodies.size() && b < ext.body_corrections.size(); ++b) {
        const BodyCorrection& c = ext.body_corrections[b];
        if (c.identity()) continue;
        m.bodies[b].inertia = corrected_inertia(m.bodies[b].inertia, c.mass_scale, c.com_shift.data(), c.inertia_change.data());
    }
    if (mode != DriveMode::ClosedLoop) {
        // The recorded effort replaces the controllers; the rotors' inertia,
        // which build_model put on the joints, stays.
        m.drives.clear();
        m.drive_dof.clear();
    }
    return m;
}

}  // namespace mbx::calibration
