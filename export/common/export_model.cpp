#include "export/common/export_model.h"

#include "export/common/names.h"

namespace mbx {

const char* mesh_extension(mbx_mesh_format format) {
    switch (format) {
    case MBX_MESH_OBJ: return "obj";
    case MBX_MESH_GLTF: return "glb";  // assimp 5.2 embeds the buffer only in binary glTF
    case MBX_MESH_STL: break;
    }
    return "stl";
}

ExportModel::ExportModel(const Mechanism& m, BodyShapes shapes, ExportSettings settings)
    : m_(m), fetch_(std::move(shapes)), settings_(std::move(settings)), tree_(index_tree(m)) {
    placements_.reserve(m.joints.size());
    for (size_t j = 0; j < m.joints.size(); ++j) placements_.push_back(place_joint(m, int(j)));
    loaded_.assign(m.bodies.size(), 0);
    cache_.resize(m.bodies.size());
    drive_index_.assign(m.joints.size(), -1);
    for (size_t d = 0; d < settings_.drives.size(); ++d) {
        const int j = settings_.drives[d].joint;
        if (j >= 0 && size_t(j) < m.joints.size()) drive_index_[size_t(j)] = int(d);
    }
    dynamics_index_.assign(m.joints.size(), -1);
    for (size_t d = 0; d < settings_.joint_dynamics.size(); ++d) {
        const int j = settings_.joint_dynamics[d].joint;
        if (j >= 0 && size_t(j) < m.joints.size()) dynamics_index_[size_t(j)] = int(d);
    }
}

bool ExportModel::limits(int joint, double& lower, double& upper) const {
    if (const ResolvedJointDynamics* jd = joint_dynamics_of(joint); jd && jd->limited) {
        lower = jd->lower, upper = jd->upper;
        return true;
    }
    const Joint& j = m_.joints[size_t(joint)];
    if (!j.has_limits) return false;
    lower = j.lower, upper = j.upper;
    return true;
}

Subject ExportModel::joint_subject(int joint) const {
    const Joint& j = m_.joints[size_t(joint)];
    if (j.constraint >= 0 && size_t(j.constraint) < m_.assembly.constraints.size()) {
        const Constraint& c = m_.assembly.constraints[size_t(j.constraint)];
        return Subject::constraint(c.id, c.name);
    }
    return Subject::constraint({}, j.name);
}

const std::vector<Mesh>& ExportModel::shapes(int body) {
    const size_t b = size_t(body);
    if (loaded_[b] || !fetch_ || m_.bodies[b].parts.empty()) return cache_[b];
    loaded_[b] = 1;
    try {
        cache_[b] = fetch_(body);
    } catch (const Error& e) {
        const RigidBody& rb = m_.bodies[b];
        note(MBX_SEVERITY_WARNING, MBX_FINDING_EXPORT_MESH_MISSING, Subject::rigid_body(rb.id, rb.name),
             "rigid body '" + rb.name + "' is exported without geometry: " + e.what());
    }
    return cache_[b];
}

void ExportModel::assign_stems() {
    stems_assigned_ = true;
    stems_.assign(m_.bodies.size(), {});
    NameTable names;
    for (size_t b = 0; b < m_.bodies.size(); ++b) {
        bool any = false;
        for (const Mesh& mesh : shapes(int(b))) any = any || !mesh.triangles.empty();
        if (any) stems_[b] = names.claim(sanitize_identifier(m_.bodies[b].name, "body"));
    }
}

const std::string& ExportModel::mesh_stem(int body) {
    if (!stems_assigned_) assign_stems();
    return stems_[size_t(body)];
}

std::string ExportModel::mesh_path(int body, mbx_mesh_format format) {
    return "meshes/" + mesh_stem(body) + "." + mesh_extension(format);
}

void ExportModel::note(mbx_severity severity, mbx_finding_code code, Subject subject, std::string message) {
    for (const Finding& f : notes_)
        if (f.code == code && f.subject.id == subject.id && f.subject.kind == subject.kind && f.message == message)
            return;
    Finding f;
    f.severity = severity;
    f.code = code;
    f.subject = std::move(subject);
    f.message = std::move(message);
    notes_.push_back(std::move(f));
}

}  // namespace mbx
