#include "core/kinematics/forward_kinematics.h"

namespace mbx {

Pose joint_motion(mbx_primitive_type type, const Vec3& axis, const JointPosition& q) {
    Pose p;
    switch (type) {
    case MBX_PRIMITIVE_REVOLUTE: p.rotation = Eigen::AngleAxisd(q.value, axis).toRotationMatrix(); break;
    case MBX_PRIMITIVE_PRISMATIC: p.position = axis * q.value; break;
    case MBX_PRIMITIVE_SPHERICAL: p.rotation = q.rotation.normalized().toRotationMatrix(); break;
    case MBX_PRIMITIVE_WELD: break;
    }
    return p;
}

std::vector<Pose> forward_kinematics(const Mechanism& m, const std::vector<JointPosition>& q,
                                     const std::vector<Pose>* root_poses) {
    const TreeIndex tree = index_tree(m);
    std::vector<Pose> world(m.bodies.size());
    const JointPosition zero;
    for (int b : tree.order) {
        const RigidBody& body = m.bodies[size_t(b)];
        if (body.parent_joint < 0) {
            world[size_t(b)] = root_poses && size_t(b) < root_poses->size() ? (*root_poses)[size_t(b)] : body.pose;
            continue;
        }
        const int j = body.parent_joint;
        const Joint& joint = m.joints[size_t(j)];
        const JointPlacement p = place_joint(m, j);
        const JointPosition& qj = size_t(j) < q.size() ? q[size_t(j)] : zero;
        world[size_t(b)] = world[size_t(joint.parent)] * p.parent_to_joint * joint_motion(joint.type, p.axis, qj) *
                           p.joint_to_child;
    }
    return world;
}

}  // namespace mbx
