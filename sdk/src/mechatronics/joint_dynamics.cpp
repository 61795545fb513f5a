#include <cmath>

#include "mechatronics/drive.h"
#include "mechatronics/joint_lookup.h"
#include "translator/mechanism.h"

namespace mbx {

std::vector<std::pair<const char*, double>> joint_dynamics_coefficients(const JointDynamicsSpec& s) {
    return {{"damping", s.damping},     {"coulomb", s.coulomb},     {"coulomb_velocity", s.coulomb_velocity},
            {"stiffness", s.stiffness}, {"armature", s.armature}};
}

std::vector<ResolvedJointDynamics> resolve_joint_dynamics(const MechatronicSpec& spec, const Mechanism& m,
                                                          std::vector<DriveError>& errors) {
    std::vector<ResolvedJointDynamics> out;
    if (spec.joint_dynamics.empty()) return out;
    out.reserve(spec.joint_dynamics.size());
    const JointIndex joints_of = index_joints_by_constraint(m);
    std::vector<int> given(m.joints.size(), -1);  // joint -> spec index that claimed it
    for (size_t index = 0; index < spec.joint_dynamics.size(); ++index) {
        const JointDynamicsSpec& s = spec.joint_dynamics[index];
        const std::string who = s.joint.constraint_id;
        auto error = [&](std::string message) { errors.push_back({s.file, s.line, who, std::move(message)}); };

        std::string why;
        const int j = find_joint(s.joint, joints_of, m, why);
        if (j < 0) {
            error(why);
            continue;
        }
        const Joint& joint = m.joints[size_t(j)];
        if (joint.type != MBX_PRIMITIVE_REVOLUTE && joint.type != MBX_PRIMITIVE_PRISMATIC) {
            error("joint '" + joint.name + "' is " + (joint.type == MBX_PRIMITIVE_SPHERICAL ? "spherical" : "a weld") +
                  ": joint dynamics act on one coordinate, so only prismatic and revolute joints take them");
            continue;
        }
        if (joint.cut) {
            // The simulator closes a cut joint as constraint rows without a
            // coordinate, and MJCF and URDF have no joint there at all.
            error("joint '" + joint.name +
                  "' closes a loop (cut joint) and has no coordinate: give the joint dynamics to a tree joint of the "
                  "loop instead");
            continue;
        }
        if (given[size_t(j)] >= 0) {
            const JointDynamicsSpec& first = spec.joint_dynamics[size_t(given[size_t(j)])];
            error("joint '" + joint.name + "' is given joint dynamics twice" +
                  (first.line > 0 ? " (the first at line " + std::to_string(first.line) + ")" : std::string()));
            continue;
        }
        const bool linear = joint.type == MBX_PRIMITIVE_PRISMATIC;
        const bool angle_unit = s.unit == "rad" || s.unit == "deg";
        const bool length_unit = s.unit == "m" || s.unit == "mm";
        if ((linear && angle_unit) || (!linear && length_unit)) {
            error("positions in '" + s.unit + "' for the " + (linear ? "prismatic" : "revolute") + " joint '" +
                  joint.name + "'");
            continue;
        }
        // Checked again here: the C API fills specs without the file reader.
        bool good = true;
        for (const auto& [name, value] : joint_dynamics_coefficients(s))
            if (!std::isfinite(value) || value < 0) {
                error(std::string(name) + " of joint '" + joint.name + "' must be finite and not negative");
                good = false;
            }
        if (!std::isfinite(s.rest)) {
            error("rest of joint '" + joint.name + "' must be finite");
            good = false;
        }
        if (s.limited && !(std::isfinite(s.lower) && std::isfinite(s.upper) && s.lower <= s.upper)) {
            error("limits of joint '" + joint.name + "' must be finite with lower <= upper");
            good = false;
        }
        if (!good) continue;

        ResolvedJointDynamics r;
        r.spec = s;
        r.joint = j;
        r.source = int(index);
        r.name = joint.name;
        r.linear = linear;
        r.damping = s.damping;
        r.coulomb = s.coulomb;
        r.coulomb_velocity = s.coulomb_velocity;
        r.stiffness = s.stiffness;
        r.rest = s.rest;
        r.armature = s.armature;
        r.limited = s.limited;
        r.lower = s.lower;
        r.upper = s.upper;
        given[size_t(j)] = int(index);
        out.push_back(std::move(r));
    }
    return out;
}

}  // namespace mbx
