#include "core/mechatronics/joint_lookup.h"

#include "core/translator/mechanism.h"

namespace mbx {

JointIndex index_joints_by_constraint(const Mechanism& m) {
    JointIndex joints_of;
    joints_of.reserve(m.assembly.constraints.size());
    for (const Constraint& c : m.assembly.constraints) joints_of[c.id];
    for (size_t j = 0; j < m.joints.size(); ++j) {
        const Joint& joint = m.joints[j];
        if (joint.constraint < 0) continue;
        joints_of[m.assembly.constraints[size_t(joint.constraint)].id].push_back(int(j));
    }
    return joints_of;
}

std::string joint_ref_text(const JointRef& ref) {
    return "constraint '" + ref.constraint_id + "'" +
           (ref.primitive >= 0 ? " primitive " + std::to_string(ref.primitive) : std::string());
}

int find_joint(const JointRef& ref, const JointIndex& joints_of, const Mechanism& m, std::string& why) {
    const auto it = joints_of.find(ref.constraint_id);
    if (it == joints_of.end()) {
        why = "no constraint with id '" + ref.constraint_id + "' in the assembly";
        return -1;
    }
    std::vector<int> candidates;
    for (int j : it->second) {
        const Joint& joint = m.joints[size_t(j)];
        if (ref.primitive >= 0 ? joint.primitive_index == ref.primitive
                               : joint.type == MBX_PRIMITIVE_REVOLUTE || joint.type == MBX_PRIMITIVE_PRISMATIC)
            candidates.push_back(j);
    }
    if (candidates.empty()) {
        why = joint_ref_text(ref) + " has no " +
              (ref.primitive >= 0 ? "such primitive joint (welds are merged away)" : "prismatic or revolute primitive");
        return -1;
    }
    if (candidates.size() > 1) {
        why = joint_ref_text(ref) + " has " + std::to_string(candidates.size()) +
              " prismatic/revolute primitives: say which with a primitive index";
        return -1;
    }
    return candidates.front();
}

}  // namespace mbx
