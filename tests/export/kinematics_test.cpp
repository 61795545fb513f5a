// mbx's forward kinematics and joint placement, checked against hand-derived poses.
#include <cmath>

#include "export_fixture.h"

namespace MBX_UNITY_ID {

using namespace mbx;

TEST_CASE("forward kinematics: zero coordinates reproduce the assembly pose") {
    for (const std::string& name : mbx_stub::builtin_names()) {
        auto t = xtest::translate_builtin(name);
        const Mechanism& m = *t->mechanism;
        const std::vector<Pose> world = forward_kinematics(m, {});
        for (size_t b = 0; b < m.bodies.size(); ++b) {
            CHECK((world[b].position - m.bodies[b].pose.position).norm() < 1e-12);
            CHECK((world[b].rotation - m.bodies[b].pose.rotation).norm() < 1e-12);
        }
    }
}

TEST_CASE("forward kinematics: a revolute turns its child about the CAD axis through the joint point") {
    auto t = xtest::translate_builtin("fourbar");
    const Mechanism& m = *t->mechanism;
    for (size_t j = 0; j < m.joints.size(); ++j) {
        const Joint& joint = m.joints[j];
        if (joint.cut || joint.type != MBX_PRIMITIVE_REVOLUTE) continue;
        std::vector<JointPosition> q(m.joints.size());
        q[j].value = 0.3;
        const std::vector<Pose> world = forward_kinematics(m, q);
        const Pose& before = m.bodies[size_t(joint.child)].pose;
        const Pose& after = world[size_t(joint.child)];
        // Child relative to parent turns by +0.3 about the tree axis through the joint point.
        const Mat3 r = Eigen::AngleAxisd(0.3, tree_axis(joint)).toRotationMatrix();
        const Vec3 p = joint.frame.position;
        CHECK((after.rotation - r * before.rotation).norm() < 1e-12);
        CHECK((after.position - (r * (before.position - p) + p)).norm() < 1e-12);
    }
}
}  // namespace MBX_UNITY_ID
