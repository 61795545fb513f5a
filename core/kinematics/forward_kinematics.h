// mbx's own forward kinematics over the spanning tree; the reference the
// exporters' consumers (MuJoCo, urdfdom) are checked against.
#pragma once
#include <Eigen/Geometry>
#include <vector>

#include "core/kinematics/placement.h"

namespace mbx {

// Coordinate of one joint. Revolute: angle (rad); prismatic: displacement (m);
// spherical: rotation of the child relative to the parent, in the joint frame.
struct JointPosition {
    double value = 0;
    Eigen::Quaterniond rotation = Eigen::Quaterniond::Identity();
};

// Motion across a joint: pose of the joint's child-side frame in its parent-side frame.
Pose joint_motion(mbx_primitive_type type, const Vec3& axis, const JointPosition& q);

// World pose of every rigid body with tree joint j at q[j] (cut joints are
// ignored; q may be shorter than the joint list: missing joints sit at zero).
// Roots keep their assembly pose unless `root_poses` (indexed by body) gives one.
std::vector<Pose> forward_kinematics(const Mechanism& m, const std::vector<JointPosition>& q,
                                     const std::vector<Pose>* root_poses = nullptr);

}  // namespace mbx
