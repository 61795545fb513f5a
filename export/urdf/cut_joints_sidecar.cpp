#include "export/urdf/cut_joints_sidecar.h"

#include <cmath>

#include "core/report/json_writer.h"

namespace mbx {
namespace {

// Same rule as number_text: rounding noise reads as an exact zero.
double clean(double v) { return std::fabs(v) < 1e-14 ? 0.0 : v; }

void write_vec(JsonWriter& w, const char* key, const Vec3& v) {
    const double a[3] = {clean(v.x()), clean(v.y()), clean(v.z())};
    w.key(key).number_array(a, 3);
}

const char* type_name(mbx_primitive_type t) {
    switch (t) {
    case MBX_PRIMITIVE_REVOLUTE: return "revolute";
    case MBX_PRIMITIVE_PRISMATIC: return "prismatic";
    case MBX_PRIMITIVE_SPHERICAL: return "spherical";
    case MBX_PRIMITIVE_WELD: break;
    }
    return "fixed";
}

// One side of a cut joint: the joint frame (axes of the tree-parent body at
// the assembly pose) in the link of body `body`, given the frame in the body.
void write_side(JsonWriter& w, const char* key, const UrdfLayout& L, int body, const Pose& frame_in_body,
                const Vec3& axis, bool has_axis) {
    const Pose in_link = L.link_in_body[size_t(body)].inverse() * frame_in_body;
    w.key(key).begin_object();
    w.member("link", L.links[size_t(L.body_link[size_t(body)])].name);
    write_vec(w, "xyz", in_link.position);
    write_vec(w, "rpy", rpy_from_rotation(in_link.rotation));
    if (has_axis)
        write_vec(w, "axis", (in_link.rotation * axis).normalized());
    else
        w.key("axis").null();
    w.end_object();
}

}  // namespace

std::string cut_joints_json(const ExportModel& model, const UrdfLayout& L) {
    const Mechanism& m = model.mechanism();
    bool any = false;
    for (const Joint& j : m.joints) any = any || j.cut;
    if (!any) return {};

    JsonWriter w;
    w.begin_object();
    w.member("format", "mbx-urdf-cut-joints");
    w.member("version", 1);
    w.member("robot", L.robot);
    w.member("urdf", L.robot + ".urdf");
    w.key("cut_joints").begin_array();
    for (size_t j = 0; j < m.joints.size(); ++j) {
        const Joint& joint = m.joints[j];
        if (!joint.cut) continue;
        const JointPlacement& p = model.placement(int(j));
        const bool has_axis = joint.type == MBX_PRIMITIVE_REVOLUTE || joint.type == MBX_PRIMITIVE_PRISMATIC;
        w.begin_object();
        w.member("name", L.joint_name[j]);
        w.member("cad_name", joint.name);
        w.member("type", type_name(joint.type));
        w.member("loop", joint.loop);
        const bool planar = joint.loop >= 0 && size_t(joint.loop) < m.loops.size() && m.loops[size_t(joint.loop)].planar;
        w.member("planar_loop", planar);
        write_side(w, "parent", L, joint.parent, p.parent_to_joint, p.axis, has_axis);
        write_side(w, "child", L, joint.child, p.joint_to_child.inverse(), p.axis, has_axis);
        if (has_axis && joint.has_limits) {
            w.key("limits").begin_object(JsonWriter::Layout::Inline);
            w.member("lower", clean(joint.lower)).member("upper", clean(joint.upper));
            w.end_object();
        } else {
            w.key("limits").null();
        }
        w.end_object();
    }
    w.end_array();
    w.end_object();
    std::string text = w.take();
    text += '\n';
    return text;
}

}  // namespace mbx
