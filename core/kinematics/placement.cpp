#include "core/kinematics/placement.h"

#include <deque>

namespace mbx {

Vec3 tree_axis(const Joint& joint) { return joint.reversed ? Vec3(-joint.axis) : joint.axis; }

JointPlacement place_joint(const Mechanism& m, int j) {
    const Joint& joint = m.joints[size_t(j)];
    const Pose& parent = m.bodies[size_t(joint.parent)].pose;
    const Pose& child = m.bodies[size_t(joint.child)].pose;
    Pose joint_world{parent.rotation, joint.frame.position};
    JointPlacement p;
    p.parent_to_joint = parent.inverse() * joint_world;
    p.joint_to_child = joint_world.inverse() * child;
    Vec3 axis = parent.rotation.transpose() * tree_axis(joint);
    const double n = axis.norm();
    p.axis = n > 0 ? Vec3(axis / n) : Vec3::UnitZ();
    return p;
}

TreeIndex index_tree(const Mechanism& m) {
    TreeIndex t;
    const size_t nb = m.bodies.size();
    t.child_joints.assign(nb, {});
    for (size_t j = 0; j < m.joints.size(); ++j) {
        const Joint& joint = m.joints[j];
        if (!joint.cut && joint.parent >= 0) t.child_joints[size_t(joint.parent)].push_back(int(j));
    }
    t.order.reserve(nb);
    std::vector<char> seen(nb, 0);
    std::deque<int> queue;
    for (size_t root = 0; root < nb; ++root) {
        if (m.bodies[root].parent_joint >= 0 || seen[root]) continue;
        t.roots.push_back(int(root));
        seen[root] = 1;
        queue.push_back(int(root));
        while (!queue.empty()) {
            const int u = queue.front();
            queue.pop_front();
            t.order.push_back(u);
            for (int j : t.child_joints[size_t(u)]) {
                const int v = m.joints[size_t(j)].child;
                if (seen[size_t(v)]) continue;
                seen[size_t(v)] = 1;
                queue.push_back(v);
            }
        }
    }
    return t;
}

}  // namespace mbx
