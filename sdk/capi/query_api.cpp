// Flat, index-based queries of a translated mechanism. Returned strings point
// into the mechanism and live as long as it does.
#include <cstring>
#include <limits>

#include "sdk/capi/guard.h"

using namespace mbx;

namespace {

void put(const Vec3& v, double* out) {
    for (int i = 0; i < 3; ++i) out[i] = v[i];
}
void put(const Mat3& m, double* out) {
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) out[3 * i + j] = m(i, j);
}
void put(const Pose& p, mbx_pose& out) {
    put(p.position, out.position);
    put(p.rotation, out.rotation);
}

bool valid(const mbx_mechanism* m) { return m && m->model; }

}  // namespace

extern "C" {

MBX_API mbx_status mbx_mechanism_get_summary(const mbx_mechanism* mechanism, mbx_mechanism_summary* out) {
    if (!valid(mechanism)) return MBX_ERROR_INVALID_ARGUMENT;
    const Mechanism& m = *mechanism->model;
    mbx_mechanism_summary s{};
    s.struct_size = sizeof s;
    s.part_count = uint32_t(m.assembly.parts.size());
    s.cad_part_count = uint32_t(m.assembly.cad_part_count());
    for (const RigidBody& b : m.bodies) {
        s.rigid_body_count += b.kind == MBX_RIGID_BODY_DYNAMIC;
        s.joint_node_count += b.kind == MBX_RIGID_BODY_JOINT_NODE;
    }
    s.joint_count = uint32_t(m.joints.size());
    for (const Joint& j : m.joints) {
        s.revolute_count += j.type == MBX_PRIMITIVE_REVOLUTE;
        s.prismatic_count += j.type == MBX_PRIMITIVE_PRISMATIC;
        s.spherical_count += j.type == MBX_PRIMITIVE_SPHERICAL;
        s.cut_joint_count += j.cut;
    }
    s.weld_count = uint32_t(m.weld_count);
    s.loop_count = uint32_t(m.loops.size());
    for (const Loop& l : m.loops) s.planar_loop_count += l.planar;
    s.collapsed_weld_loop_count = uint32_t(m.collapsed_weld_loops);
    s.dof = m.dof;
    s.gruebler_dof = m.gruebler_dof;
    s.redundant_constraint_count = uint32_t(m.redundant);
    s.floating_body_count = uint32_t(m.floating_roots);
    s.warning_count = uint32_t(m.count(MBX_SEVERITY_WARNING));
    s.error_count = uint32_t(m.count(MBX_SEVERITY_ERROR));
    return copy_out(out, s);
}

MBX_API mbx_status mbx_mechanism_get_rigid_body(const mbx_mechanism* mechanism, uint32_t index,
                                                mbx_rigid_body_info* out) {
    if (!valid(mechanism) || index >= mechanism->model->bodies.size()) return MBX_ERROR_INVALID_ARGUMENT;
    const RigidBody& b = mechanism->model->bodies[index];
    mbx_rigid_body_info r{};
    r.struct_size = sizeof r;
    r.kind = b.kind;
    r.name = b.name.c_str();
    r.id = b.id.c_str();
    r.part_count = uint32_t(b.parts.size());
    r.mass = b.mass;
    put(b.com, r.com);
    put(b.inertia, r.inertia);
    put(b.pose, r.pose);
    r.parent_joint = b.parent_joint;
    return copy_out(out, r);
}

MBX_API mbx_status mbx_mechanism_find_part(const mbx_mechanism* mechanism, const char* part_id,
                                           uint32_t* out_rigid_body) {
    if (!valid(mechanism) || !part_id || !out_rigid_body) return MBX_ERROR_INVALID_ARGUMENT;
    const Mechanism& m = *mechanism->model;
    if (mechanism->part_index.empty())
        for (size_t i = 0; i < m.assembly.parts.size(); ++i) mechanism->part_index.emplace(m.assembly.parts[i].id, int(i));
    auto it = mechanism->part_index.find(part_id);
    if (it == mechanism->part_index.end() || m.part_body[size_t(it->second)] < 0) return MBX_ERROR_INVALID_ARGUMENT;
    *out_rigid_body = uint32_t(m.part_body[size_t(it->second)]);
    return MBX_OK;
}

MBX_API mbx_status mbx_mechanism_get_joint(const mbx_mechanism* mechanism, uint32_t index, mbx_joint_info* out) {
    if (!valid(mechanism) || index >= mechanism->model->joints.size()) return MBX_ERROR_INVALID_ARGUMENT;
    const Mechanism& m = *mechanism->model;
    const Joint& j = m.joints[index];
    mbx_joint_info r{};
    r.struct_size = sizeof r;
    r.type = j.type;
    r.name = j.name.c_str();
    r.constraint_id = m.assembly.constraints[size_t(j.constraint)].id.c_str();
    r.primitive_index = uint32_t(j.primitive_index);
    r.parent = uint32_t(j.parent);
    r.child = uint32_t(j.child);
    r.is_cut = j.cut;
    r.reversed = j.reversed;
    put(j.axis, r.axis);
    put(j.frame, r.frame);
    r.has_limits = j.has_limits;
    r.lower = j.lower;
    r.upper = j.upper;
    r.loop = j.loop;
    return copy_out(out, r);
}

MBX_API mbx_status mbx_mechanism_get_loop(const mbx_mechanism* mechanism, uint32_t index, mbx_loop_info* out) {
    if (!valid(mechanism) || index >= mechanism->model->loops.size()) return MBX_ERROR_INVALID_ARGUMENT;
    const Loop& l = mechanism->model->loops[index];
    mbx_loop_info r{};
    r.struct_size = sizeof r;
    r.cut_joint = uint32_t(l.cut_joint);
    r.joint_count = uint32_t(l.joints.size());
    r.dof = l.dof;
    r.gruebler_dof = l.gruebler_dof;
    r.redundant = uint32_t(l.redundant);
    r.planar = l.planar;
    put(l.planar_normal, r.planar_normal);
    return copy_out(out, r);
}

MBX_API mbx_status mbx_mechanism_get_loop_joints(const mbx_mechanism* mechanism, uint32_t index, uint32_t* joints,
                                                 uint32_t* inout_count) {
    if (!valid(mechanism) || !inout_count || index >= mechanism->model->loops.size())
        return MBX_ERROR_INVALID_ARGUMENT;
    const Loop& l = mechanism->model->loops[index];
    const uint32_t capacity = *inout_count;
    *inout_count = uint32_t(l.joints.size());
    if (capacity == 0) return MBX_OK;
    if (!joints || capacity < l.joints.size()) return MBX_ERROR_INVALID_ARGUMENT;
    for (size_t i = 0; i < l.joints.size(); ++i) joints[i] = uint32_t(l.joints[i]);
    return MBX_OK;
}

MBX_API const char* mbx_finding_code_name(mbx_finding_code code) { return finding_code_name(code); }

MBX_API uint32_t mbx_mechanism_finding_count(const mbx_mechanism* mechanism) {
    return valid(mechanism) ? uint32_t(mechanism->model->findings.size()) : 0;
}

MBX_API mbx_status mbx_mechanism_get_finding(const mbx_mechanism* mechanism, uint32_t index, mbx_finding* out) {
    if (!valid(mechanism) || index >= mechanism->model->findings.size()) return MBX_ERROR_INVALID_ARGUMENT;
    const Finding& f = mechanism->model->findings[index];
    mbx_finding r{};
    r.struct_size = sizeof r;
    r.severity = f.severity;
    r.code = f.code;
    r.subject_kind = f.subject.kind;
    r.subject_id = f.subject.id.c_str();
    r.subject_name = f.subject.name.c_str();
    r.message = f.message.c_str();
    r.code_name = f.code_name();
    r.file = f.file.c_str();
    r.line = f.line;
    return copy_out(out, r);
}

MBX_API mbx_status mbx_mechanism_get_shape_stats(mbx_context* context, mbx_mechanism* mechanism, uint32_t index,
                                                 mbx_shape_stats* out) {
    if (!context) return MBX_ERROR_INVALID_ARGUMENT;
    if (!valid(mechanism) || index >= mechanism->model->bodies.size() || !out)
        return context->fail(MBX_ERROR_INVALID_ARGUMENT, "no such mechanism or rigid body " + std::to_string(index));
    const bool cached = index < mechanism->shapes.size() && mechanism->shapes[index];
    if (!cached && !mechanism->has_host)
        return context->fail(MBX_ERROR_INVALID_ARGUMENT,
                             "the host was released; shapes of rigid body " + std::to_string(index) +
                                 " can no longer be asked for");
    return guarded(context, [&] {
        const std::vector<Mesh>& meshes = mechanism->body_shapes(*mechanism->model, int(index));
        mbx_shape_stats s{};
        s.struct_size = sizeof s;
        Vec3 lo = Vec3::Constant(std::numeric_limits<double>::infinity()), hi = -lo;
        for (const Mesh& mesh : meshes) {
            ++s.mesh_count;
            s.vertex_count += mesh.vertices.size();
            s.triangle_count += mesh.triangles.size() / 3;
            for (const Vec3& v : mesh.vertices) {
                lo = lo.cwiseMin(v);
                hi = hi.cwiseMax(v);
            }
        }
        if (s.vertex_count == 0) lo = hi = Vec3::Zero();
        put(lo, s.bounds_min);
        put(hi, s.bounds_max);
        if (copy_out(out, s) != MBX_OK) throw Error(MBX_ERROR_INVALID_ARGUMENT, {}, "out.struct_size is not set");
    });
}

}  // extern "C"
