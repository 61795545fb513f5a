// Builds the simulation model of a translated mechanism: the spanning tree's
// joints in reduced coordinates (zero at the CAD assembly pose, as every
// exporter places them), a free joint for each floating body, one loop
// closure per cut joint, and the joint dynamics the user described.
#pragma once
#include <map>
#include <vector>

#include "sim/model.h"
#include "core/translator/mechanism.h"

namespace mbx::sim {

struct BuildOptions {
    Vec3T<double> gravity = Vec3T<double>(0, 0, -kDefaultGravity);
    // Joint dynamics by Mechanism::joints index (revolute and prismatic tree
    // joints). Joint limits come from the CAD joint unless given here.
    std::map<int, JointDynamics> joint_dynamics;
    // Resolved drives (mechatronics/drive.h): each acts on its joint in the
    // loop and adds its armature (rotor and transmission inertia) there.
    std::vector<Drive> drives;
    // Elastic transmissions by Mechanism::joints index (revolute and
    // prismatic tree joints; sim/model.h TransmissionT, joint and dof filled
    // here). A drive on such a joint adds its armature to the motor's inertia.
    std::map<int, Transmission> transmissions;
    // Time constant and damping ratio of a position limit, as the joint's own
    // inertia at the assembly pose sees it (MuJoCo's solref defaults).
    double limit_time_constant = 0.02;
    double limit_damping_ratio = 1.0;
};

// Throws mbx::Error (MBX_ERROR_INVALID_INPUT) naming the joint for joint
// dynamics or a transmission that are not finite, negative where they
// cannot be, or on a joint that has no single coordinate.
Model build_model(const Mechanism& m, const BuildOptions& options = {});

}  // namespace mbx::sim
