#include "calibration/simulation/model_extension.h"

#include "calibration/cause_table.h"
#include "calibration/identification/causes.h"

namespace mbx::calibration {

namespace {

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

}  // namespace

void ExtensionStep::unwritten(const std::string& reason) { ext.unwritten.push_back({cause, reason}); }

int ExtensionStep::drive_of(int dof) const {
    for (size_t k = 0; k < model.drive_dof.size(); ++k)
        if (model.drive_dof[k] == dof) return int(k);
    return -1;
}

JointUpdate* ExtensionStep::joint(const SelectedCause& c) {
    if (c.candidate.joint < 0 || model.joints[size_t(c.candidate.joint)].source < 0) {
        unwritten("no CAD joint to hold it");
        return nullptr;
    }
    JointUpdate& u = update_of(ext, mechanism, base, model, c.candidate.joint);
    u.causes.push_back(c.candidate.cause);
    return &u;
}

void ExtensionStep::refuse(JointUpdate& u, const std::string& reason) {
    u.causes.pop_back();
    unwritten(reason);
}

ModelExtension extend(const Mechanism& mech, const sim::BuildOptions& base, const sim::Model& model,
                      const Identification& id, size_t count, const RegressionRows& fit) {
    ModelExtension ext;
    ext.options = base;
    ext.body_corrections.assign(model.bodies.size(), BodyCorrection());
    ext.drive_gain.assign(model.drives.size(), 1.0);
    ext.adjust = ReplayAdjustments(model.nv);
    for (size_t i = 0; i < std::min(count, id.causes.size()); ++i) {
        ExtensionStep step{mech, base, model, fit, ext, int(i)};
        const CauseKind& kind = id.causes[i].candidate.kind();
        if (kind.extend) kind.extend(id.causes[i], step);
        else step.unwritten(std::string("mbx has no model extension for ") + kind.name + " yet");
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
