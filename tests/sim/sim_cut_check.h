// An independent look at a simulated loop: each cut joint's frame on its
// parent side and on its child side, placed from the mechanism with
// kinematics/placement (not the simulator's closure rows), at the body poses
// the simulator computed. How far apart they are is how open the loop is.
#pragma once
#include <cmath>
#include <vector>

#include "core/kinematics/placement.h"
#include "sim/dynamics.h"
#include "core/translator/mechanism.h"

namespace simtest {

struct CutGap {
    double distance = 0;  // m, less the sliding component of a prismatic cut
    double angle = 0;     // rad the child side left what the joint allows
};

inline mbx::Pose body_pose(const mbx::Mechanism& m, const mbx::sim::Model& model, const mbx::sim::Data& d, int body) {
    if (body == 0) return m.bodies[0].pose;
    const auto& x = d.x_world[size_t(model.body_of_source[size_t(body)])];
    mbx::Pose p;
    p.rotation = x.R;
    p.position = x.p;
    return p;
}

// Needs update_positions on d.
inline CutGap cut_gap(const mbx::Mechanism& m, const mbx::sim::Model& model, const mbx::sim::Data& d, int c) {
    const mbx::Joint& joint = m.joints[size_t(c)];
    const mbx::JointPlacement p = mbx::place_joint(m, c);
    const mbx::Pose parent_side = body_pose(m, model, d, joint.parent) * p.parent_to_joint;
    const mbx::Pose child_side = body_pose(m, model, d, joint.child) * p.joint_to_child.inverse();
    const mbx::Vec3 axis = parent_side.rotation * p.axis;
    mbx::Vec3 gap = child_side.position - parent_side.position;
    CutGap e;
    auto rotation_angle = [](const mbx::Mat3& a, const mbx::Mat3& b) { return Eigen::AngleAxisd(a.transpose() * b).angle(); };
    switch (joint.type) {
    case MBX_PRIMITIVE_PRISMATIC:
        gap -= axis * axis.dot(gap);
        e.angle = rotation_angle(parent_side.rotation, child_side.rotation);
        break;
    case MBX_PRIMITIVE_REVOLUTE: {
        const mbx::Vec3 child_axis = child_side.rotation * p.axis;
        e.angle = std::atan2(axis.cross(child_axis).norm(), axis.dot(child_axis));
        break;
    }
    case MBX_PRIMITIVE_WELD: e.angle = rotation_angle(parent_side.rotation, child_side.rotation); break;
    case MBX_PRIMITIVE_SPHERICAL: break;
    }
    e.distance = gap.norm();
    return e;
}

// The largest gap over every cut joint.
inline CutGap worst_cut_gap(const mbx::Mechanism& m, const mbx::sim::Model& model, const mbx::sim::Data& d) {
    CutGap worst;
    for (size_t c = 0; c < m.joints.size(); ++c) {
        if (!m.joints[c].cut) continue;
        const CutGap e = cut_gap(m, model, d, int(c));
        worst.distance = std::max(worst.distance, e.distance);
        worst.angle = std::max(worst.angle, e.angle);
    }
    return worst;
}

}  // namespace simtest
