#include "fingerprint.h"

#include <cstdio>

#include "plugin_fixture.h"

namespace itest {
namespace {

void put(std::string& out, const char* key, double v) {
    char buf[64];
    std::snprintf(buf, sizeof buf, " %s=%.17g", key, v);
    out += buf;
}
void put(std::string& out, const char* key, long long v) {
    out += " ";
    out += key;
    out += "=" + std::to_string(v);
}
void put(std::string& out, const char* key, const char* s) {
    out += " ";
    out += key;
    out += "='";
    out += s ? s : "(null)";
    out += "'";
}
void put(std::string& out, const char* key, const double* v, int n) {
    out += " ";
    out += key;
    out += "=[";
    for (int i = 0; i < n; ++i) {
        char buf[40];
        std::snprintf(buf, sizeof buf, i ? ",%.17g" : "%.17g", v[i]);
        out += buf;
    }
    out += "]";
}

}  // namespace

std::string fingerprint(const mbx_mechanism* m) {
    std::string out;
    const mbx_mechanism_summary s = summary(m);
    out += "summary";
    put(out, "parts", (long long)s.part_count);
    put(out, "rigid", (long long)s.rigid_body_count);
    put(out, "nodes", (long long)s.joint_node_count);
    put(out, "joints", (long long)s.joint_count);
    put(out, "R", (long long)s.revolute_count);
    put(out, "P", (long long)s.prismatic_count);
    put(out, "S", (long long)s.spherical_count);
    put(out, "welds", (long long)s.weld_count);
    put(out, "cuts", (long long)s.cut_joint_count);
    put(out, "loops", (long long)s.loop_count);
    put(out, "planar", (long long)s.planar_loop_count);
    put(out, "collapsed", (long long)s.collapsed_weld_loop_count);
    put(out, "dof", (long long)s.dof);
    put(out, "gruebler", (long long)s.gruebler_dof);
    put(out, "redundant", (long long)s.redundant_constraint_count);
    put(out, "floating", (long long)s.floating_body_count);
    put(out, "warnings", (long long)s.warning_count);
    put(out, "errors", (long long)s.error_count);
    out += "\n";
    const uint32_t bodies = 1 + s.rigid_body_count + s.joint_node_count;
    for (uint32_t i = 0; i < bodies; ++i) {
        const mbx_rigid_body_info b = rigid_body(m, i);
        out += "body";
        put(out, "kind", (long long)b.kind);
        put(out, "id", b.id);
        put(out, "name", b.name);
        put(out, "parts", (long long)b.part_count);
        put(out, "mass", b.mass);
        put(out, "com", b.com, 3);
        put(out, "inertia", b.inertia, 9);
        put(out, "p", b.pose.position, 3);
        put(out, "R", b.pose.rotation, 9);
        put(out, "parent", (long long)b.parent_joint);
        out += "\n";
    }
    for (uint32_t i = 0; i < s.joint_count; ++i) {
        const mbx_joint_info j = joint(m, i);
        out += "joint";
        put(out, "type", (long long)j.type);
        put(out, "name", j.name);
        put(out, "constraint", j.constraint_id);
        put(out, "primitive", (long long)j.primitive_index);
        put(out, "parent", (long long)j.parent);
        put(out, "child", (long long)j.child);
        put(out, "cut", (long long)j.is_cut);
        put(out, "reversed", (long long)j.reversed);
        put(out, "axis", j.axis, 3);
        put(out, "p", j.frame.position, 3);
        put(out, "R", j.frame.rotation, 9);
        put(out, "limits", (long long)j.has_limits);
        put(out, "lower", j.lower);
        put(out, "upper", j.upper);
        put(out, "loop", (long long)j.loop);
        out += "\n";
    }
    for (uint32_t i = 0; i < s.loop_count; ++i) {
        const mbx_loop_info l = loop(m, i);
        out += "loop";
        put(out, "cut", (long long)l.cut_joint);
        put(out, "joints", (long long)l.joint_count);
        put(out, "dof", (long long)l.dof);
        put(out, "gruebler", (long long)l.gruebler_dof);
        put(out, "redundant", (long long)l.redundant);
        put(out, "planar", (long long)l.planar);
        put(out, "normal", l.planar_normal, 3);
        out += " members=";
        for (uint32_t j : loop_joints(m, i)) out += std::to_string(j) + ",";
        out += "\n";
    }
    const uint32_t findings = api().mechanism_finding_count(m);
    for (uint32_t i = 0; i < findings; ++i) {
        mbx_finding f{};
        f.struct_size = sizeof f;
        if (api().mechanism_get_finding(m, i, &f) != MBX_OK) {
            out += "finding unreadable\n";
            continue;
        }
        out += "finding";
        put(out, "severity", (long long)f.severity);
        put(out, "code", (long long)f.code);
        put(out, "subject", (long long)f.subject_kind);
        put(out, "id", f.subject_id);
        put(out, "message", f.message);
        out += "\n";
    }
    return out;
}

}  // namespace itest
