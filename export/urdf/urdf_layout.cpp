#include "export/urdf/urdf_layout.h"

#include <array>
#include <cmath>

#include "export/common/names.h"

namespace mbx {

Vec3 rpy_from_rotation(const Mat3& r) {
    // Yaw first, from the first column; then Rz(-yaw) * r = Ry(pitch) * Rx(roll)
    // is read from entries of order one. At pitch = +-90 degrees only
    // roll - yaw is defined: yaw = 0 and roll takes it all.
    const double c = std::hypot(r(0, 0), r(1, 0));
    const double yaw = c > 1e-300 ? std::atan2(r(1, 0), r(0, 0)) : 0.0;
    const Mat3 rest = Eigen::AngleAxisd(-yaw, Vec3::UnitZ()).toRotationMatrix() * r;
    const double pitch = std::atan2(-rest(2, 0), rest(0, 0));
    const double roll = std::atan2(-rest(1, 2), rest(1, 1));
    return {roll, pitch, yaw};
}

namespace {

// One URDF joint from a mechanism joint's placement; `rotate` is the child
// link's orientation in the joint frame. Limits are the model's (the joint
// dynamics' when given, else the CAD joint's).
UrdfJoint single_joint(const ExportModel& model, const Joint& joint, int source, const Pose& origin_rotated,
                       const Mat3& rotate, const Vec3& axis) {
    UrdfJoint u;
    u.source = source;
    u.origin = origin_rotated;
    u.axis = (rotate.transpose() * axis).normalized();
    double lower = 0, upper = 0;
    const bool limited = joint.type != MBX_PRIMITIVE_SPHERICAL && model.limits(source, lower, upper);
    switch (joint.type) {
    case MBX_PRIMITIVE_REVOLUTE:
        u.type = limited ? "revolute" : "continuous";
        u.has_limit = limited;
        u.lower = lower;
        u.upper = upper;
        break;
    case MBX_PRIMITIVE_PRISMATIC:
        u.type = "prismatic";
        u.has_limit = true;  // URDF requires one
        u.default_range = !limited;
        u.lower = limited ? lower : -kUrdfPrismaticRange;
        u.upper = limited ? upper : kUrdfPrismaticRange;
        break;
    case MBX_PRIMITIVE_WELD:
    case MBX_PRIMITIVE_SPHERICAL:  // split by the caller
        u.type = "fixed";
        break;
    }
    return u;
}

}  // namespace

UrdfLayout plan_urdf(const ExportModel& model) {
    const Mechanism& m = model.mechanism();
    const TreeIndex& tree = model.tree();
    UrdfLayout L;
    L.robot = sanitize_identifier(model.settings().model_name, "model");

    // Names first, in body and joint order, so they do not depend on the
    // shape of the tree. Links and joints are separate name spaces in URDF.
    NameTable link_names, joint_names;
    link_names.reserve("world");
    std::vector<std::string> body_name(m.bodies.size());
    for (size_t b = 0; b < m.bodies.size(); ++b)
        body_name[b] = link_names.claim(sanitize_identifier(m.bodies[b].name, "link"));
    L.joint_name.resize(m.joints.size());
    for (size_t j = 0; j < m.joints.size(); ++j)
        L.joint_name[j] = joint_names.claim(sanitize_identifier(m.joints[j].name, "joint"));
    static const char* const xyz[3] = {"x", "y", "z"};
    std::vector<std::array<std::string, 3>> split_joint(m.joints.size());
    std::vector<std::array<std::string, 2>> split_link(m.joints.size());
    for (size_t j = 0; j < m.joints.size(); ++j) {
        if (m.joints[j].cut || m.joints[j].type != MBX_PRIMITIVE_SPHERICAL) continue;
        for (int k = 0; k < 3; ++k) split_joint[j][size_t(k)] = joint_names.claim(L.joint_name[j] + "_" + xyz[k]);
        for (int k = 0; k < 2; ++k)
            split_link[j][size_t(k)] = link_names.claim(L.joint_name[j] + "_" + xyz[k] + "_link");
    }

    L.links.push_back({"world", -1});
    L.body_link.assign(m.bodies.size(), -1);
    L.link_in_body.assign(m.bodies.size(), Pose{});
    auto add_link = [&](std::string name, int body) {
        L.links.push_back({std::move(name), body});
        return int(L.links.size()) - 1;
    };

    for (int b : tree.order) {
        const RigidBody& body = m.bodies[size_t(b)];
        if (body.parent_joint < 0) {
            // Ground and floating roots: link frame = body frame, below "world".
            const int link = add_link(body_name[size_t(b)], b);
            L.body_link[size_t(b)] = link;
            UrdfJoint u;
            u.name = joint_names.claim("world_to_" + body_name[size_t(b)]);
            u.type = b == 0 ? "fixed" : "floating";
            u.parent_link = 0;
            u.child_link = link;
            u.origin = body.pose;
            L.joints.push_back(std::move(u));
            continue;
        }
        const int j = body.parent_joint;
        const Joint& joint = m.joints[size_t(j)];
        const JointPlacement& p = model.placement(j);
        const int parent_link = L.body_link[size_t(joint.parent)];
        // The joint frame in the parent link, and the child body's axes in it.
        const Pose joint_in_parent = L.link_in_body[size_t(joint.parent)].inverse() * p.parent_to_joint;
        const Mat3 rotate = p.joint_to_child.rotation;
        const Pose turn{rotate, Vec3::Zero()};
        L.link_in_body[size_t(b)] = Pose{Mat3::Identity(), p.joint_to_child.inverse().position};

        if (joint.type != MBX_PRIMITIVE_SPHERICAL) {
            UrdfJoint u = single_joint(model, joint, j, joint_in_parent * turn, rotate, p.axis);
            u.name = L.joint_name[size_t(j)];
            u.parent_link = parent_link;
            u.child_link = add_link(body_name[size_t(b)], b);
            L.body_link[size_t(b)] = u.child_link;
            L.joints.push_back(std::move(u));
            continue;
        }
        // Spherical: revolutes about x, y, z of the joint frame (intrinsic
        // order), through two massless links with the joint frame's axes.
        int previous = parent_link;
        for (int k = 0; k < 3; ++k) {
            UrdfJoint u;
            u.name = split_joint[size_t(j)][size_t(k)];
            u.type = "continuous";
            u.source = j;
            u.spherical_axis = k;
            u.parent_link = previous;
            const Vec3 e = Vec3::Unit(k);
            if (k == 0) {
                u.origin = joint_in_parent;
                u.axis = e;
            } else if (k == 1) {
                u.axis = e;
            } else {
                u.origin = turn;
                u.axis = (rotate.transpose() * e).normalized();
            }
            u.child_link = k < 2 ? add_link(split_link[size_t(j)][size_t(k)], -1) : add_link(body_name[size_t(b)], b);
            previous = u.child_link;
            L.joints.push_back(std::move(u));
        }
        L.body_link[size_t(b)] = previous;
    }
    return L;
}

}  // namespace mbx
