#include "calibration/transmission_stage.h"

#include "core/finding.h"

namespace mbx::calibration {

namespace {

// Where the stage would look: the joints of a named armature or gain.
std::vector<std::string> candidate_joints(const sim::Model& m, const Identification& id) {
    std::vector<std::string> out;
    for (const SelectedCause& c : id.causes)
        if ((c.candidate.cause == "armature" || c.candidate.cause == "actuator_gain") && c.candidate.joint >= 0)
            out.push_back("'" + m.joints[size_t(c.candidate.joint)].name + "'");
    return out;
}

std::string joined(const std::vector<std::string>& v) {
    std::string s;
    for (size_t i = 0; i < v.size(); ++i) s += (i ? ", " : "") + v[i];
    return s;
}

}  // namespace

sim::Model rigid_limit(const sim::Model& m) {
    if (m.transmissions.empty()) return m;
    sim::Model r = m;
    for (const sim::Transmission& t : m.transmissions) {
        sim::JointT<double>& j = r.joints[size_t(t.joint)];
        j.dynamics.armature += t.motor_inertia;
        j.reference_inertia += t.motor_inertia;
    }
    r.transmissions.clear();
    r.transmission_of_dof.assign(size_t(r.nv), -1);
    return r;
}

Identification transmission_stage(const sim::Model& m, const std::vector<const Record*>& fit,
                                  const std::vector<const Record*>& validation, const Identification& linear,
                                  const TransmissionOptions& options) {
    const std::vector<std::string> joints = candidate_joints(m, linear);
    if (joints.empty()) return linear;
    Identification out = linear;
    auto skip = [&](const std::string& why) {
        out.warnings.push_back("compliance was not tried on joint " + joined(joints) + ": " + why);
        return out;
    };
    if (!m.closures.empty())
        return skip("the simulation stage does not carry an elastic transmission in a closed loop yet");
    for (const sim::JointT<double>& j : m.joints)
        if (j.nv() != 1) return skip("the simulation stage handles 1-dof joints only (joint '" + j.name + "')");
    if (!m.transmissions.empty())
        return skip("the model already has an elastic transmission (on joint '" +
                    m.joints[size_t(m.transmissions[0].joint)].name + "'), which the stage does not refit");
    for (const SelectedCause& c : linear.causes)
        if (!simulation_supports(c.candidate.cause))
            return skip("the simulation stage cannot carry " + c.candidate.cause + ", which was named");
    Identification staged;
    try {
        staged = add_transmissions(m, fit, validation, linear, options);
    } catch (const Error& e) {
        return skip(std::string("the simulation fit failed: ") + e.what());
    }
    // The compliance's inverse-dynamics figures: its rigid limit is the
    // armature (or gain) it replaced, so those of that step.
    for (SelectedCause& c : staged.causes) {
        if (c.candidate.cause != "compliance") continue;
        for (const SelectedCause& was : linear.causes)
            if (was.candidate.joint == c.candidate.joint &&
                (was.candidate.cause == "armature" || was.candidate.cause == "actuator_gain")) {
                c.fit_error = was.fit_error;
                c.validation_error = was.validation_error;
                c.validation_gain = was.validation_gain;
            }
    }
    return staged;
}

}  // namespace mbx::calibration
