// The joint dynamics of a description file (mechatronics/joint_dynamics.h),
// resolved against the mechanism, as the simulator's BuildOptions take them.
// mbx_core cannot see sim/, so the mapping lives on this side.
#pragma once
#include <map>
#include <vector>

#include "core/mechatronics/joint_dynamics.h"
#include "sim/model.h"

namespace mbx::sim {

// Keyed by Mechanism::joints index, for BuildOptions::joint_dynamics. Limit
// stiffness and damping stay 0 so build_model sizes them from the joint's
// inertia; a drive's armature is added by build_model on top of these.
inline std::map<int, JointDynamics> joint_dynamics_by_joint(const std::vector<ResolvedJointDynamics>& resolved) {
    std::map<int, JointDynamics> out;
    for (const ResolvedJointDynamics& r : resolved) {
        JointDynamics& jd = out[r.joint];
#define MBX_COPY_FROM_RESOLVED(field) jd.field = r.field;
        MBX_JOINT_DYNAMICS_SCALARS(MBX_COPY_FROM_RESOLVED)
#undef MBX_COPY_FROM_RESOLVED
        jd.asymmetric = r.asymmetric();
        jd.damping_negative = r.damping_negative;
        jd.coulomb_negative = r.coulomb_negative;
        jd.limited = r.limited;
    }
    return out;
}

// The elastic transmissions the description gives, keyed the same way, for
// BuildOptions::transmissions.
inline std::map<int, Transmission> transmissions_by_joint(const std::vector<ResolvedJointDynamics>& resolved) {
    std::map<int, Transmission> out;
    for (const ResolvedJointDynamics& r : resolved) {
        if (!r.transmission) continue;
        Transmission& t = out[r.joint];
        t.stiffness = r.transmission->stiffness;
        t.damping = r.transmission->damping;
        t.motor_inertia = r.transmission->motor_inertia;
        t.backlash = r.transmission->backlash;
    }
    return out;
}

}  // namespace mbx::sim
