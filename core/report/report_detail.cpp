#include "core/report/report_detail.h"

namespace mbx::report_detail {

const char* joint_type_name(mbx_primitive_type type) {
    switch (type) {
        case MBX_PRIMITIVE_WELD: return "weld";
        case MBX_PRIMITIVE_PRISMATIC: return "prismatic";
        case MBX_PRIMITIVE_REVOLUTE: return "revolute";
        case MBX_PRIMITIVE_SPHERICAL: return "spherical";
    }
    return "unknown";
}

const char* body_kind_name(mbx_rigid_body_kind kind) {
    switch (kind) {
        case MBX_RIGID_BODY_GROUND: return "ground";
        case MBX_RIGID_BODY_DYNAMIC: return "dynamic";
        case MBX_RIGID_BODY_JOINT_NODE: return "joint_node";
    }
    return "unknown";
}

JointsByParent joints_by_parent(const Mechanism& m, bool include_cut_joints) {
    const std::size_t n = m.bodies.size();
    JointsByParent g;
    g.offset.assign(n + 1, 0);
    auto wanted = [&](const Joint& j) {
        return (include_cut_joints || !j.cut) && valid_index(m.bodies, j.parent) && valid_index(m.bodies, j.child);
    };
    for (const Joint& j : m.joints)
        if (wanted(j)) ++g.offset[static_cast<std::size_t>(j.parent) + 1];
    for (std::size_t b = 0; b < n; ++b) g.offset[b + 1] += g.offset[b];
    g.joints.resize(g.offset[n]);
    std::vector<std::size_t> fill(g.offset.begin(), g.offset.end() - 1);
    for (std::size_t i = 0; i < m.joints.size(); ++i)
        if (wanted(m.joints[i])) g.joints[fill[static_cast<std::size_t>(m.joints[i].parent)]++] = static_cast<int>(i);
    return g;
}

Counts count(const Mechanism& m) {
    Counts c;
    for (const RigidBody& b : m.bodies) {
        c.dynamic_bodies += b.kind == MBX_RIGID_BODY_DYNAMIC;
        c.joint_nodes += b.kind == MBX_RIGID_BODY_JOINT_NODE;
    }
    for (const Joint& j : m.joints) {
        c.revolute += j.type == MBX_PRIMITIVE_REVOLUTE;
        c.prismatic += j.type == MBX_PRIMITIVE_PRISMATIC;
        c.spherical += j.type == MBX_PRIMITIVE_SPHERICAL;
        c.cut_joints += j.cut;
    }
    for (const Loop& l : m.loops) c.planar_loops += l.planar;
    for (const Finding& f : m.findings) {
        c.info += f.severity == MBX_SEVERITY_INFO;
        c.warnings += f.severity == MBX_SEVERITY_WARNING;
        c.errors += f.severity == MBX_SEVERITY_ERROR;
    }
    return c;
}

}  // namespace mbx::report_detail
