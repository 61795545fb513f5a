#include "urdf_assembly.h"

#include <algorithm>
#include <map>

#include "core/text_format.h"
#include "host_adapters/common/file_error.h"

namespace mbx_files {
namespace {

std::string quoted(const std::string& s) { return "'" + s + "'"; }

mbx_memory::Primitive primitive(mbx_primitive_type type, const Eigen::Vector3d& world_axis) {
    mbx_memory::Primitive p{};
    p.type = type;
    p.axis_reference = MBX_AXIS_IN_WORLD;
    for (int k = 0; k < 3; ++k) p.axis[k] = world_axis[k];
    return p;
}

// A unit vector normal to `n`.
Eigen::Vector3d normal_to(const Eigen::Vector3d& n) {
    Eigen::Vector3d::Index least;
    n.cwiseAbs().minCoeff(&least);
    Eigen::Vector3d e = Eigen::Vector3d::Zero();
    e[least] = 1;
    return (e - e.dot(n) * n).normalized();
}

void add_frame_pair(mbx_memory::Assembly& a, const std::string& joint, const std::string& base, const std::string& follower,
                    const Eigen::Isometry3d& world) {
    mbx_memory::Frame b;
    b.id = joint + "/parent";
    b.name = joint + " (parent side)";
    b.body_id = base;
    b.pose = urdf_pose(world);
    mbx_memory::Frame f = b;
    f.id = joint + "/child";
    f.name = joint + " (child side)";
    f.body_id = follower;
    a.frames.push_back(b);
    a.frames.push_back(f);
}

}  // namespace

mbx_pose urdf_pose(const Eigen::Isometry3d& x) {
    mbx_pose p{};
    for (int i = 0; i < 3; ++i) {
        p.position[i] = x.translation()[i];
        for (int j = 0; j < 3; ++j) p.rotation[3 * i + j] = x.linear()(i, j);
    }
    return p;
}

UrdfAssembly to_assembly(const UrdfModel& model, const UrdfAssemblyOptions& options) {
    UrdfAssembly out;
    mbx_memory::Assembly& a = out.assembly;
    a.name = model.name;
    a.source = model.file;
    a.diagnostics = model.diagnostics;
    auto fail = [&](int line, const std::string& message) { throw FileError(model.file, line, message); };

    std::map<std::string, int> link_index;
    for (size_t k = 0; k < model.links.size(); ++k) link_index[model.links[k].name] = int(k);
    std::map<std::string, int> joint_index;
    for (size_t k = 0; k < model.joints.size(); ++k) joint_index[model.joints[k].name] = int(k);

    // The tree: each link's parent joint, each link's child joints in file order.
    std::vector<int> parent_joint(model.links.size(), -1);
    std::vector<std::vector<int>> child_joints(model.links.size());
    for (size_t k = 0; k < model.joints.size(); ++k) {
        const UrdfJoint& j = model.joints[k];
        const auto parent = link_index.find(j.parent), child = link_index.find(j.child);
        if (parent == link_index.end()) fail(j.line, "joint " + quoted(j.name) + ": its parent link " + quoted(j.parent) + " is not in the file");
        if (child == link_index.end()) fail(j.line, "joint " + quoted(j.name) + ": its child link " + quoted(j.child) + " is not in the file");
        if (parent->second == child->second) fail(j.line, "joint " + quoted(j.name) + " joins link " + quoted(j.parent) + " to itself");
        int& p = parent_joint[size_t(child->second)];
        if (p >= 0) {
            const UrdfJoint& other = model.joints[size_t(p)];
            fail(j.line, "link " + quoted(j.child) + " is the child of joint " + quoted(other.name) + " (line " +
                             std::to_string(other.line) + ") and of joint " + quoted(j.name) +
                             ": a URDF is a tree (a loop's closing joint goes in the cut-joint file beside it)");
        }
        p = int(k);
        child_joints[size_t(parent->second)].push_back(int(k));
    }
    std::vector<int> roots;
    for (size_t k = 0; k < model.links.size(); ++k)
        if (parent_joint[k] < 0) roots.push_back(int(k));
    if (roots.empty()) fail(model.robot_line, "every link has a parent joint: the joints make a cycle, not a tree");
    if (roots.size() > 1) {
        std::string names;
        for (size_t k = 0; k < roots.size() && k < 5; ++k) names += (k ? ", " : "") + quoted(model.links[size_t(roots[k])].name);
        fail(model.links[size_t(roots[1])].line, std::to_string(roots.size()) + " links have no parent joint (" + names +
                                                     (roots.size() > 5 ? ", ..." : "") + "): a URDF robot is one tree");
    }
    out.root = roots[0];

    // Poses at zero joint positions, from the root down (an explicit stack:
    // a long chain must not exhaust the call stack).
    out.link_world.assign(model.links.size(), Eigen::Isometry3d::Identity());
    std::vector<int> stack{out.root};
    while (!stack.empty()) {
        const int link = stack.back();
        stack.pop_back();
        out.link_order.push_back(link);
        const std::vector<int>& children = child_joints[size_t(link)];
        for (auto it = children.rbegin(); it != children.rend(); ++it) {
            const UrdfJoint& j = model.joints[size_t(*it)];
            const int child = link_index[j.child];
            out.link_world[size_t(child)] = out.link_world[size_t(link)] * j.origin.pose();
            stack.push_back(child);
        }
    }
    if (out.link_order.size() != model.links.size()) {
        for (size_t k = 0; k < model.links.size(); ++k)
            if (std::find(out.link_order.begin(), out.link_order.end(), int(k)) == out.link_order.end())
                fail(model.links[k].line, "link " + quoted(model.links[k].name) +
                                              " is not below the root link: its joints make a cycle");
    }

    // A root named "world" without mass is the world itself, as in ROS.
    const UrdfLink& root = model.links[size_t(out.root)];
    const bool root_is_world = root.name == kUrdfWorldId && !(root.inertial.given && root.inertial.mass > 0);
    const bool add_world = options.floating_base && !root_is_world;
    if (add_world) {
        mbx_memory::Body world;
        world.id = world.name = kUrdfWorldId;
        world.flags = MBX_BODY_GROUND;
        world.pose = urdf_pose(Eigen::Isometry3d::Identity());
        a.bodies.push_back(world);
    }
    for (int k : out.link_order) {
        const UrdfLink& link = model.links[size_t(k)];
        mbx_memory::Body b;
        b.id = b.name = link.name;
        b.pose = urdf_pose(out.link_world[size_t(k)]);
        if (k == out.root && !add_world) b.flags = MBX_BODY_GROUND;
        if (link.inertial.given) {
            const UrdfInertial& in = link.inertial;
            Eigen::Matrix3d I;
            I << in.ixx, in.ixy, in.ixz, in.ixy, in.iyy, in.iyz, in.ixz, in.iyz, in.izz;
            const Eigen::Matrix3d R = in.origin.pose().linear();
            const Eigen::Matrix3d in_link = R * I * R.transpose();
            b.mass = in.mass;
            for (int r = 0; r < 3; ++r) {
                b.com[r] = in.origin.xyz[r];
                for (int c = 0; c < 3; ++c) b.inertia[3 * r + c] = in_link(r, c);
            }
        }
        a.bodies.push_back(b);
    }
    if (add_world) {
        // Slides along the world's axes, then a ball joint at the root's origin.
        const Eigen::Isometry3d at = out.link_world[size_t(out.root)];
        add_frame_pair(a, kUrdfFloatingBaseId, kUrdfWorldId, root.name, at);
        mbx_memory::Constraint c;
        c.id = c.name = kUrdfFloatingBaseId;
        c.base_frame_id = std::string(kUrdfFloatingBaseId) + "/parent";
        c.follower_frame_id = std::string(kUrdfFloatingBaseId) + "/child";
        for (int k = 0; k < 3; ++k) c.chain.push_back(primitive(MBX_PRIMITIVE_PRISMATIC, Eigen::Vector3d::Unit(k)));
        c.chain.push_back(primitive(MBX_PRIMITIVE_SPHERICAL, Eigen::Vector3d::UnitZ()));
        a.constraints.push_back(c);
    }

    // Joints in the bodies' order (each link's parent joint).
    for (int k : out.link_order) {
        if (parent_joint[size_t(k)] < 0) continue;
        const UrdfJoint& j = model.joints[size_t(parent_joint[size_t(k)])];
        const Eigen::Isometry3d at = out.link_world[size_t(k)];
        add_frame_pair(a, j.name, j.parent, j.child, at);
        mbx_memory::Constraint c;
        c.id = c.name = j.name;
        c.base_frame_id = j.name + "/parent";
        c.follower_frame_id = j.name + "/child";
        const Eigen::Vector3d axis = at.linear() * j.axis;
        // Rated speed and effort for every kind that has them; the range
        // not for a continuous joint, whose lower and upper URDF ignores.
        auto rated = [&](mbx_memory::Primitive p) {
            if (j.has_limit) p.velocity_limit = j.velocity, p.effort_limit = j.effort;
            return p;
        };
        auto limited = [&](mbx_memory::Primitive p) {
            if (j.has_limit) {
                p.has_limits = true;
                p.lower = j.lower;
                p.upper = j.upper;
            }
            return rated(p);
        };
        if (j.type == "revolute") {
            c.chain.push_back(limited(primitive(MBX_PRIMITIVE_REVOLUTE, axis)));
        } else if (j.type == "continuous") {
            c.chain.push_back(rated(primitive(MBX_PRIMITIVE_REVOLUTE, axis)));
        } else if (j.type == "prismatic") {
            c.chain.push_back(limited(primitive(MBX_PRIMITIVE_PRISMATIC, axis)));
        } else if (j.type == "fixed") {
            c.chain.push_back(primitive(MBX_PRIMITIVE_WELD, axis));
        } else if (j.type == "floating") {
            for (int e = 0; e < 3; ++e) c.chain.push_back(primitive(MBX_PRIMITIVE_PRISMATIC, at.linear().col(e)));
            c.chain.push_back(primitive(MBX_PRIMITIVE_SPHERICAL, axis));
        } else {  // planar: the plane normal to the axis
            const Eigen::Vector3d u = normal_to(axis), v = axis.cross(u);
            c.chain.push_back(primitive(MBX_PRIMITIVE_PRISMATIC, u));
            c.chain.push_back(primitive(MBX_PRIMITIVE_PRISMATIC, v));
            c.chain.push_back(primitive(MBX_PRIMITIVE_REVOLUTE, axis));
        }
        a.constraints.push_back(c);
        if (j.has_mimic) {
            mbx_memory::Diagnostic d;
            d.severity = MBX_SEVERITY_WARNING;
            d.code = "urdf_mimic_not_simulated";
            d.subject_kind = MBX_SUBJECT_CONSTRAINT;
            d.subject_id = d.subject_name = j.name;
            d.file = model.file;
            d.line = j.mimic_line;
            d.message = "joint " + quoted(j.name) + " mimics " + quoted(j.mimic_joint) +
                        " (its position = " + mbx::readable(j.mimic_multiplier) + " x that one's + " +
                        std::to_string(j.mimic_offset) +
                        "); mbx keeps it a joint of its own, free to move: couple it with a drive in the description "
                        "file if the coupling matters";
            if (!joint_index.count(j.mimic_joint)) d.message += " (no joint of that name is in the file)";
            a.diagnostics.push_back(std::move(d));
        }
    }
    // The loops' closing joints, from the cut-joint file: each side's frame in
    // its link, the axis in the parent link's.
    for (const UrdfCutJoint& c : model.cut_joints) {
        const auto cut_fail = [&](const std::string& message) { throw FileError(model.cut_joint_file, c.line, message); };
        const auto parent = link_index.find(c.parent), child = link_index.find(c.child);
        if (parent == link_index.end()) cut_fail("cut joint " + quoted(c.name) + ": link " + quoted(c.parent) + " is not in the URDF");
        if (child == link_index.end()) cut_fail("cut joint " + quoted(c.name) + ": link " + quoted(c.child) + " is not in the URDF");
        if (joint_index.count(c.name)) cut_fail("cut joint " + quoted(c.name) + " has the name of a joint of the URDF");
        const Eigen::Isometry3d parent_world = out.link_world[size_t(parent->second)];
        mbx_memory::Frame b, f;
        b.id = c.name + "/parent";
        b.name = c.name + " (parent side)";
        b.body_id = c.parent;
        b.pose = urdf_pose(parent_world * c.parent_origin.pose());
        f.id = c.name + "/child";
        f.name = c.name + " (child side)";
        f.body_id = c.child;
        f.pose = urdf_pose(out.link_world[size_t(child->second)] * c.child_origin.pose());
        a.frames.push_back(b);
        a.frames.push_back(f);
        mbx_memory::Constraint k;
        k.id = k.name = c.name;
        k.base_frame_id = b.id;
        k.follower_frame_id = f.id;
        const Eigen::Vector3d axis = parent_world.linear() * c.axis;
        mbx_memory::Primitive p = primitive(c.type == "revolute"    ? MBX_PRIMITIVE_REVOLUTE
                                            : c.type == "prismatic" ? MBX_PRIMITIVE_PRISMATIC
                                            : c.type == "spherical" ? MBX_PRIMITIVE_SPHERICAL
                                                                    : MBX_PRIMITIVE_WELD,
                                            axis);
        if (c.has_limit) {
            p.has_limits = true;
            p.lower = c.lower;
            p.upper = c.upper;
        }
        k.chain.push_back(p);
        a.constraints.push_back(k);
    }
    return out;
}

}  // namespace mbx_files
