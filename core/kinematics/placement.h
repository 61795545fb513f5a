// Where each tree joint sits between its two bodies. Every exporter and the
// forward kinematics use this one placement, so a joint coordinate means the
// same thing in Modelica, MJCF, URDF and mbx: zero at the CAD assembly pose,
// positive as the CAD follower moves relative to the CAD base.
#pragma once
#include <vector>

#include "core/math.h"
#include "core/translator/mechanism.h"

namespace mbx {

struct JointPlacement {
    Pose parent_to_joint;  // joint frame in the parent body frame; its axes are the parent body's
    Pose joint_to_child;   // child body frame in the joint frame at coordinate zero
    Vec3 axis = Vec3::UnitZ();  // unit, joint frame: +q moves the tree child relative to the tree parent
};

// Placement of joint `j` (a tree joint or a cut joint; for a cut joint the
// "child" is the body on its child side).
JointPlacement place_joint(const Mechanism& m, int j);

// The joint's axis in world, oriented for tree-parent -> tree-child motion:
// the CAD axis, negated when the tree runs from the CAD follower to the base.
Vec3 tree_axis(const Joint& joint);

struct TreeIndex {
    std::vector<int> order;                      // bodies, every parent before its children (ground first)
    std::vector<std::vector<int>> child_joints;  // per body: tree joints it is the parent of, in joint order
    std::vector<int> roots;                      // ground, then each floating root, in body order
};
TreeIndex index_tree(const Mechanism& m);

}  // namespace mbx
