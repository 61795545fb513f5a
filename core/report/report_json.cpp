// report.json schema (key order as written; indices are 0-based; SI units;
// 3x3 matrices as 9 numbers row-major; absent references are null):
//   mbx_version, model {name, source},
//   summary {parts, rigid_bodies, joint_nodes, joints {revolute, prismatic,
//     spherical, total}, welds_merged, cut_joints, loops, planar_loops,
//     collapsed_weld_loops, floating_bodies, dof, gruebler_dof,
//     redundant_constraints, warnings, errors, length_tolerance_m},
//   parts [{id, name, flags [..], mass, rigid_body, cad_volume_m3 and
//     cad_density_kg_m3 (null when the host gave no volume), shape_check}],
//   bodies [{index, kind, id, name, parts [part ids], mass, com, inertia,
//     position, rotation, parent_joint, depth}],
//   joints [{index, name, type, constraint_id, primitive_index, parent, child,
//     cut, reversed, axis, position, limits {lower, upper}, loop}],
//   tree [for body i: the child bodies of its tree joints, in joint order],
//   loops [{index, cut_joint, joints, signs, dof, gruebler_dof, redundant,
//     planar, planar_normal}],
//   drives [{name, joint, constraint_id, primitive_index, motor, transmission,
//     linear, ratio, efficiency, armature, effort_limit, velocity_limit,
//     output_limit, motor_constants {torque_constant, stall_torque,
//     no_load_speed, rotor_inertia, resistance, inductance},
//     servo {stiffness, damping, emf_damping, approximation},
//     controller {amplifier, amplifier_gain, kp, ki, kd, kv, kvi,
//     sample_period, delay}, motion {interpolation, points [[t, q]..]}}]
//     (only when the mechanism has drives),
//   joint_dynamics [{name, joint, constraint_id, primitive_index, linear,
//     damping, coulomb, coulomb_velocity, damping_negative, coulomb_negative
//     (equal to damping and coulomb when symmetric), stribeck,
//     stribeck_velocity, offset, stiffness, rest, armature,
//     limits {lower, upper} or null}] (only when there are any),
//   findings [{severity, code, subject {kind, id, name}, message}]
#include "core/report/json_writer.h"
#include "core/report/report.h"
#include "core/report/report_detail.h"

namespace mbx {
namespace {

using namespace report_detail;
using Layout = JsonWriter::Layout;

void write_vec(JsonWriter& w, const char* name, const Vec3& v) {
    const double a[3] = {v.x(), v.y(), v.z()};
    w.key(name).number_array(a, 3);
}

void write_mat(JsonWriter& w, const char* name, const Mat3& m) {
    double a[9];
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) a[3 * i + j] = m(i, j);
    w.key(name).number_array(a, 9);
}

void write_index_or_null(JsonWriter& w, const char* name, int index) {
    w.key(name);
    if (index >= 0)
        w.value(index);
    else
        w.null();
}

void write_int_array(JsonWriter& w, const char* name, const std::vector<int>& v) {
    w.key(name).begin_array(Layout::Inline);
    for (int i : v) w.value(i);
    w.end_array();
}

void write_summary(JsonWriter& w, const Mechanism& m, const Counts& c) {
    w.key("summary").begin_object();
    w.member("parts", m.assembly.parts.size());
    w.member("cad_parts", m.assembly.cad_part_count());
    w.member("rigid_bodies", c.dynamic_bodies);
    w.member("joint_nodes", c.joint_nodes);
    w.key("joints").begin_object();
    w.member("revolute", c.revolute).member("prismatic", c.prismatic).member("spherical", c.spherical);
    w.member("total", m.joints.size());
    w.end_object();
    w.member("welds_merged", m.weld_count);
    w.member("cut_joints", c.cut_joints);
    w.member("loops", m.loops.size());
    w.member("planar_loops", c.planar_loops);
    w.member("collapsed_weld_loops", m.collapsed_weld_loops);
    w.member("floating_bodies", m.floating_roots);
    w.member("dof", m.dof);
    w.member("gruebler_dof", m.gruebler_dof);
    w.member("redundant_constraints", m.redundant);
    w.member("warnings", c.warnings);
    w.member("errors", c.errors);
    w.member("length_tolerance_m", m.length_tolerance);
    w.end_object();
}

void write_parts(JsonWriter& w, const Mechanism& m) {
    w.key("parts").begin_array();
    for (std::size_t i = 0; i < m.assembly.parts.size(); ++i) {
        const Part& p = m.assembly.parts[i];
        w.begin_object();
        w.member("id", p.id).member("name", p.name);
        w.key("flags").begin_array(Layout::Inline);
        if (p.is_ground()) w.value("ground");
        if (p.is_helper()) w.value("helper");
        w.end_array();
        w.member("mass", p.mass);
        const int body = i < m.part_body.size() ? m.part_body[i] : -1;
        write_index_or_null(w, "rigid_body", valid_index(m.bodies, body) ? body : -1);
        if (p.volume > 0) {
            w.member("cad_volume_m3", p.volume);
            w.member("cad_density_kg_m3", p.mass / p.volume);
        } else {
            w.key("cad_volume_m3").null();
            w.key("cad_density_kg_m3").null();
        }
        if (i < m.shape_checks.size() && m.shape_checks[i].checked) {
            const ShapeCheck& c = m.shape_checks[i];
            w.key("shape_check").begin_object(Layout::Inline);
            w.member("mesh_volume_m3", c.volume);
            w.member("centroid_mismatch_mm", c.centroid_mismatch * 1e3);
            w.member("tolerance_mm", c.tolerance * 1e3);
            w.member("density_kg_m3", c.density);
            w.end_object();
        } else {
            w.key("shape_check").null();
        }
        w.end_object();
    }
    w.end_array();
}

void write_bodies(JsonWriter& w, const Mechanism& m) {
    w.key("bodies").begin_array();
    for (std::size_t i = 0; i < m.bodies.size(); ++i) {
        const RigidBody& b = m.bodies[i];
        w.begin_object();
        w.member("index", i).member("kind", body_kind_name(b.kind));
        w.member("id", b.id).member("name", b.name);
        w.key("parts").begin_array(Layout::Inline);
        for (int p : b.parts) {
            if (valid_index(m.assembly.parts, p))
                w.value(m.assembly.parts[static_cast<std::size_t>(p)].id);
            else
                w.null();
        }
        w.end_array();
        w.member("mass", b.mass);
        write_vec(w, "com", b.com);
        write_mat(w, "inertia", b.inertia);
        write_vec(w, "position", b.pose.position);
        write_mat(w, "rotation", b.pose.rotation);
        write_index_or_null(w, "parent_joint", b.parent_joint);
        w.member("depth", b.depth);
        w.end_object();
    }
    w.end_array();
}

void write_joints(JsonWriter& w, const Mechanism& m) {
    w.key("joints").begin_array();
    for (std::size_t i = 0; i < m.joints.size(); ++i) {
        const Joint& j = m.joints[i];
        w.begin_object();
        w.member("index", i).member("name", j.name).member("type", joint_type_name(j.type));
        w.key("constraint_id");
        if (valid_index(m.assembly.constraints, j.constraint))
            w.value(m.assembly.constraints[static_cast<std::size_t>(j.constraint)].id);
        else
            w.null();
        w.member("primitive_index", j.primitive_index);
        write_index_or_null(w, "parent", j.parent);
        write_index_or_null(w, "child", j.child);
        w.member("cut", j.cut).member("reversed", j.reversed);
        write_vec(w, "axis", j.axis);
        write_vec(w, "position", j.frame.position);
        w.key("limits");
        if (j.has_limits)
            w.begin_object(Layout::Inline).member("lower", j.lower).member("upper", j.upper).end_object();
        else
            w.null();
        write_index_or_null(w, "loop", j.loop);
        w.end_object();
    }
    w.end_array();
}

void write_tree(JsonWriter& w, const Mechanism& m) {
    const JointsByParent tree = joints_by_parent(m, false);
    w.key("tree").begin_array();
    for (std::size_t b = 0; b < m.bodies.size(); ++b) {
        w.begin_array(Layout::Inline);
        for (const int* j = tree.begin(b); j != tree.end(b); ++j) w.value(m.joints[static_cast<std::size_t>(*j)].child);
        w.end_array();
    }
    w.end_array();
}

void write_loops(JsonWriter& w, const Mechanism& m) {
    w.key("loops").begin_array();
    for (std::size_t i = 0; i < m.loops.size(); ++i) {
        const Loop& l = m.loops[i];
        w.begin_object();
        w.member("index", i);
        write_index_or_null(w, "cut_joint", l.cut_joint);
        write_int_array(w, "joints", l.joints);
        write_int_array(w, "signs", l.signs);
        w.member("dof", l.dof).member("gruebler_dof", l.gruebler_dof).member("redundant", l.redundant);
        w.member("planar", l.planar);
        if (l.planar)
            write_vec(w, "planar_normal", l.planar_normal);
        else
            w.key("planar_normal").null();
        w.end_object();
    }
    w.end_array();
}

void write_drives(JsonWriter& w, const Mechanism& m, const std::vector<Drive>& drives) {
    w.key("drives").begin_array();
    for (const Drive& d : drives) {
        const Joint& j = m.joints[static_cast<std::size_t>(d.joint)];
        w.begin_object();
        w.member("name", d.name).member("joint", d.joint);
        w.member("constraint_id", m.assembly.constraints[static_cast<std::size_t>(j.constraint)].id);
        w.member("primitive_index", j.primitive_index);
        w.member("motor", d.motor_name).member("transmission", d.transmission_name).member("linear", d.linear);
        w.member("ratio", d.ratio).member("efficiency", d.efficiency).member("armature", d.armature);
        w.member("effort_limit", d.effort_limit).member("velocity_limit", d.velocity_limit);
        w.member("output_limit", d.output_limit);
        w.key("motor_constants").begin_object(Layout::Inline);
        w.member("torque_constant", d.motor.torque_constant).member("stall_torque", d.motor.stall_torque);
        w.member("no_load_speed", d.motor.no_load_speed).member("rotor_inertia", d.motor.rotor_inertia);
        w.member("resistance", d.armature_resistance).member("inductance", d.armature_inductance);
        w.end_object();
        w.key("servo").begin_object(Layout::Inline);
        w.member("stiffness", d.servo.stiffness).member("damping", d.servo.damping);
        w.member("emf_damping", d.servo.emf_damping).member("approximation", d.servo.approximation);
        w.end_object();
        const ControllerSpec& c = d.spec.controller;
        w.key("controller").begin_object(Layout::Inline);
        w.member("amplifier", d.spec.amplifier.mode == AmplifierMode::Current ? "current" : "voltage");
        w.member("amplifier_gain", d.spec.amplifier.gain);
        w.member("kp", c.kp).member("ki", c.ki).member("kd", c.kd).member("kv", c.kv).member("kvi", c.kvi);
        w.member("sample_period", c.sample_period).member("delay", c.delay);
        w.end_object();
        w.key("motion").begin_object();
        w.member("interpolation", interpolation_name(d.spec.motion.interpolation()));
        w.key("points").begin_array();
        for (const MotionPoint& p : d.spec.motion.points()) {
            const double tq[2] = {p.time, p.value};
            w.number_array(tq, 2);
        }
        w.end_array();
        w.end_object();
        w.end_object();
    }
    w.end_array();
}

void write_findings(JsonWriter& w, const Mechanism& m) {
    w.key("findings").begin_array();
    for (const Finding& f : m.findings) {
        w.begin_object();
        w.member("severity", severity_name(f.severity)).member("code", f.code_name());
        w.key("subject").begin_object(Layout::Inline);
        w.member("kind", subject_kind_name(f.subject.kind));
        w.member("id", f.subject.id).member("name", f.subject.name);
        w.end_object();
        w.member("message", f.message);
        if (!f.file.empty()) {
            w.member("file", f.file);
            w.member("line", f.line);
        }
        w.end_object();
    }
    w.end_array();
}

// Rough bytes per element, so the buffer grows once instead of ~20 times.
std::size_t json_size_estimate(const Mechanism& m) {
    std::size_t n = 1024;
    n += m.assembly.parts.size() * 160;
    n += m.bodies.size() * 760;
    n += m.joints.size() * 420;
    for (const Loop& l : m.loops) n += 260 + 8 * l.joints.size();
    for (const Finding& f : m.findings) n += 200 + f.message.size() + f.subject.id.size() + f.subject.name.size();
    return n;
}

void write_joint_dynamics(JsonWriter& w, const Mechanism& m, const std::vector<ResolvedJointDynamics>& all) {
    w.key("joint_dynamics").begin_array();
    for (const ResolvedJointDynamics& d : all) {
        const Joint& j = m.joints[static_cast<std::size_t>(d.joint)];
        w.begin_object(Layout::Inline);
        w.member("name", d.name).member("joint", d.joint);
        w.member("constraint_id", m.assembly.constraints[static_cast<std::size_t>(j.constraint)].id);
        w.member("primitive_index", j.primitive_index).member("linear", d.linear);
        w.member("damping", d.damping).member("coulomb", d.coulomb).member("coulomb_velocity", d.coulomb_velocity);
        w.member("damping_negative", d.damping_negative).member("coulomb_negative", d.coulomb_negative);
        w.member("stribeck", d.stribeck).member("stribeck_velocity", d.stribeck_velocity).member("offset", d.offset);
        w.member("stiffness", d.stiffness).member("rest", d.rest).member("armature", d.armature);
        w.key("limits");
        if (d.limited)
            w.begin_object(Layout::Inline).member("lower", d.lower).member("upper", d.upper).end_object();
        else
            w.null();
        w.end_object();
    }
    w.end_array();
}

}  // namespace

std::string report_json(const Mechanism& m, const std::vector<Drive>* drives,
                        const std::vector<ResolvedJointDynamics>* joint_dynamics) {
    JsonWriter w(json_size_estimate(m));
    w.begin_object();
    w.member("mbx_version", MBX_VERSION_STRING);
    w.key("model").begin_object().member("name", m.assembly.name).member("source", m.assembly.source).end_object();
    write_summary(w, m, count(m));
    write_parts(w, m);
    write_bodies(w, m);
    write_joints(w, m);
    write_tree(w, m);
    write_loops(w, m);
    if (drives && !drives->empty()) write_drives(w, m, *drives);
    if (joint_dynamics && !joint_dynamics->empty()) write_joint_dynamics(w, m, *joint_dynamics);
    write_findings(w, m);
    w.end_object();
    std::string text = w.take();
    text.push_back('\n');
    return text;
}

}  // namespace mbx
