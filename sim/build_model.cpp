#include "sim/build_model.h"

#include <cmath>

#include "core/kinematics/placement.h"
#include "sim/data.h"
#include "sim/dynamics.h"
#include "sim/loop_closure.h"

namespace mbx::sim {
namespace {

Transform<double> to_transform(const Pose& p) { return {p.rotation, p.position}; }

JointKind kind_of(mbx_primitive_type t) {
    switch (t) {
    case MBX_PRIMITIVE_REVOLUTE: return JointKind::Revolute;
    case MBX_PRIMITIVE_PRISMATIC: return JointKind::Prismatic;
    case MBX_PRIMITIVE_SPHERICAL: return JointKind::Spherical;
    case MBX_PRIMITIVE_WELD: return JointKind::Fixed;
    }
    return JointKind::Fixed;
}

// Two unit vectors completing `a` to a right-handed orthonormal basis.
void complete_basis(const Vec3& a, Vec3& u, Vec3& w) {
    const Vec3 seed = std::fabs(a.x()) < 0.6 ? Vec3::UnitX() : std::fabs(a.y()) < 0.6 ? Vec3::UnitY() : Vec3::UnitZ();
    u = a.cross(seed).normalized();
    w = a.cross(u);
}

Vec6T<double> selector(const Vec3& angular, const Vec3& linear) {
    Vec6T<double> r;
    r << angular, linear;
    return r;
}

void check_dynamics(const JointT<double>& j, const JointDynamics& jd) {
    auto fail = [&](const std::string& what) {
        throw Error(MBX_ERROR_INVALID_INPUT, j.subject(), "joint '" + j.name + "': " + what);
    };
    if (j.nv() != 1) fail(std::string("joint dynamics need a revolute or prismatic joint, not ") + joint_kind_name(j.kind));
    const std::pair<const char*, double> values[] = {
        {"damping", jd.damping}, {"coulomb", jd.coulomb}, {"coulomb_velocity", jd.coulomb_velocity},
        {"stiffness", jd.stiffness}, {"armature", jd.armature}, {"limit_stiffness", jd.limit_stiffness},
        {"limit_damping", jd.limit_damping}, {"stribeck", jd.stribeck}, {"stribeck_velocity", jd.stribeck_velocity},
        {"damping_negative", jd.asymmetric ? jd.damping_negative : 0.0},
        {"coulomb_negative", jd.asymmetric ? jd.coulomb_negative : 0.0}};
    for (const auto& [name, value] : values)
        if (!std::isfinite(value) || value < 0) fail(std::string(name) + " must be finite and not negative");
    if (!std::isfinite(jd.offset)) fail("offset must be finite");
    if (jd.stribeck > 0 && !(jd.stribeck_velocity > 0)) fail("stribeck needs a positive stribeck_velocity");
    if (!std::isfinite(jd.rest)) fail("rest position must be finite");
    if (jd.limited && !(std::isfinite(jd.lower) && std::isfinite(jd.upper) && jd.lower <= jd.upper))
        fail("limits must be finite with lower <= upper");
}

void check_transmission(const JointT<double>& j, const Transmission& t) {
    auto fail = [&](const std::string& what) {
        throw Error(MBX_ERROR_INVALID_INPUT, j.subject(), "joint '" + j.name + "': transmission " + what);
    };
    if (j.nv() != 1) fail(std::string("needs a revolute or prismatic joint, not ") + joint_kind_name(j.kind));
    const std::pair<const char*, double> values[] = {{"motor_inertia", t.motor_inertia}, {"stiffness", t.stiffness},
                                                     {"damping", t.damping}, {"backlash", t.backlash}};
    for (const auto& [name, value] : values)
        if (!std::isfinite(value) || value < 0) fail(std::string(name) + " must be finite and not negative");
    if (!(t.motor_inertia > 0)) fail("motor_inertia must be positive (the motor side needs an inertia of its own)");
    if (!(t.backlash > 0) && !(t.stiffness > 0)) fail("needs a positive stiffness, or a backlash (a dead band between stops)");
}

}  // namespace

Model build_model(const Mechanism& m, const BuildOptions& options) {
    Model model;
    model.name = m.assembly.name;
    model.gravity = options.gravity;
    const TreeIndex tree = index_tree(m);
    const Pose ground_pose = m.bodies.empty() ? Pose{} : m.bodies[0].pose;

    model.body_of_source.assign(m.bodies.size(), -1);
    model.joint_of_source.assign(m.joints.size(), -1);
    model.bodies.push_back(BodyT<double>{-1, 0, m.bodies.empty() ? "" : m.bodies[0].id, "world", {}});
    if (!m.bodies.empty()) model.body_of_source[0] = 0;

    double total_mass = 0;
    for (int src : tree.order) {
        if (src == 0) continue;
        const RigidBody& rb = m.bodies[size_t(src)];
        BodyT<double> body;
        body.source = src;
        body.id = rb.id;
        body.name = rb.name;
        body.inertia = Inertia<double>::from_com(rb.mass, rb.com, rb.inertia);
        total_mass += rb.mass;
        JointT<double> j;
        if (rb.parent_joint < 0) {
            // Floating root: a free joint whose coordinates are the body's world pose.
            body.parent = 0;
            j.kind = JointKind::Free;
            j.name = rb.name;
            j.constraint_id = rb.id;
        } else {
            const Joint& mj = m.joints[size_t(rb.parent_joint)];
            const JointPlacement p = place_joint(m, rb.parent_joint);
            body.parent = model.body_of_source[size_t(mj.parent)];
            j.kind = kind_of(mj.type);
            j.source = rb.parent_joint;
            j.name = mj.name;
            j.constraint_id = mj.constraint >= 0 ? m.assembly.constraints[size_t(mj.constraint)].id : "";
            j.parent_to_joint = to_transform(mj.parent == 0 ? ground_pose * p.parent_to_joint : p.parent_to_joint);
            j.joint_to_child = to_transform(p.joint_to_child);
            j.axis = p.axis;
            if (mj.has_limits && j.nv() == 1) {
                j.dynamics.limited = true;
                j.dynamics.lower = mj.lower;
                j.dynamics.upper = mj.upper;
            }
            auto given = options.joint_dynamics.find(rb.parent_joint);
            if (given != options.joint_dynamics.end()) {
                check_dynamics(j, given->second);
                const bool cad_limits = j.dynamics.limited && !given->second.limited;
                const double lower = j.dynamics.lower, upper = j.dynamics.upper;
                j.dynamics = given->second;
                if (cad_limits) j.dynamics.limited = true, j.dynamics.lower = lower, j.dynamics.upper = upper;
            }
            model.joint_of_source[size_t(rb.parent_joint)] = int(model.joints.size());
        }
        j.body = int(model.bodies.size());
        j.q_index = model.nq;
        j.v_index = model.nv;
        model.nq += j.nq();
        model.nv += j.nv();
        // Motion subspace in child body coordinates: the joint-frame axis
        // carried through the constant joint_to_child offset.
        const Transform<double> child_in_joint = j.joint_to_child;
        switch (j.kind) {
        case JointKind::Revolute:
        case JointKind::Prismatic: {
            Vec6T<double> s = j.kind == JointKind::Revolute ? selector(j.axis, Vec3::Zero()) : selector(Vec3::Zero(), j.axis);
            j.subspace = child_in_joint.motion_to_child(s);
            break;
        }
        case JointKind::Spherical:
            j.subspace.resize(6, 3);
            for (int k = 0; k < 3; ++k) j.subspace.col(k) = child_in_joint.motion_to_child(selector(Vec3::Unit(k), Vec3::Zero()));
            break;
        case JointKind::Fixed: j.subspace.resize(6, 0); break;
        case JointKind::Free: j.subspace.setZero(6, 6); break;  // depends on the state
        }
        j.prepare_pose();
        model.body_of_source[size_t(src)] = int(model.bodies.size());
        model.bodies.push_back(std::move(body));
        model.joints.push_back(std::move(j));
    }
    for (const JointT<double>& j : model.joints)
        for (int k = 0; k < j.nv(); ++k) model.dof_joint.push_back(int(&j - model.joints.data()));

    model.q_reference = VecXT<double>::Zero(model.nq);
    for (const JointT<double>& j : model.joints) {
        neutral_joint<double>(j.kind, model.q_reference.data() + j.q_index);
        if (j.kind == JointKind::Free) {
            const Pose& pose = m.bodies[size_t(model.bodies[size_t(j.body)].source)].pose;
            const Eigen::Quaterniond r(pose.rotation);
            double* q = model.q_reference.data() + j.q_index;
            q[0] = pose.position.x(), q[1] = pose.position.y(), q[2] = pose.position.z();
            q[3] = r.w(), q[4] = r.x(), q[5] = r.y(), q[6] = r.z();
        }
    }

    for (const Joint& cut : m.joints) {
        if (!cut.cut) continue;
        const int c = int(&cut - m.joints.data());
        const JointPlacement p = place_joint(m, c);
        LoopClosureT<double> lc;
        lc.body_a = model.body_of_source[size_t(cut.parent)];
        lc.body_b = model.body_of_source[size_t(cut.child)];
        lc.frame_a = to_transform(cut.parent == 0 ? ground_pose * p.parent_to_joint : p.parent_to_joint);
        Pose b_in_child = p.joint_to_child.inverse();
        lc.frame_b = to_transform(cut.child == 0 ? ground_pose * b_in_child : b_in_child);
        lc.kind = kind_of(cut.type);
        lc.loop = cut.loop;
        lc.source = c;
        lc.name = cut.name;
        lc.constraint_id = cut.constraint >= 0 ? m.assembly.constraints[size_t(cut.constraint)].id : "";
        Vec3 u, w;
        complete_basis(p.axis, u, w);
        const Vec3 ex = Vec3::UnitX(), ey = Vec3::UnitY(), ez = Vec3::UnitZ(), zero = Vec3::Zero();
        std::vector<Vec6T<double>> rows;
        switch (lc.kind) {
        case JointKind::Revolute: rows = {selector(u, zero), selector(w, zero), selector(zero, ex), selector(zero, ey), selector(zero, ez)}; break;
        case JointKind::Prismatic: rows = {selector(ex, zero), selector(ey, zero), selector(ez, zero), selector(zero, u), selector(zero, w)}; break;
        case JointKind::Spherical: rows = {selector(zero, ex), selector(zero, ey), selector(zero, ez)}; break;
        case JointKind::Fixed:
        case JointKind::Free:
            rows = {selector(ex, zero), selector(ey, zero), selector(ez, zero), selector(zero, ex), selector(zero, ey), selector(zero, ez)};
            lc.kind = JointKind::Fixed;
            break;
        }
        lc.rows = int(rows.size());
        for (size_t k = 0; k < rows.size(); ++k) lc.row[k] = rows[k];
        model.closure_rows += lc.rows;
        model.closures.push_back(std::move(lc));
    }

    model.transmission_of_dof.assign(size_t(model.nv), -1);
    for (const auto& [source, given] : options.transmissions) {
        const int sj = source >= 0 && size_t(source) < model.joint_of_source.size() ? model.joint_of_source[size_t(source)] : -1;
        if (sj < 0) {
            const std::string name = source >= 0 && size_t(source) < m.joints.size() ? m.joints[size_t(source)].name : "?";
            throw Error(MBX_ERROR_INVALID_INPUT, Subject::model(model.name),
                        "joint '" + name + "': a transmission needs a revolute or prismatic joint of the spanning tree");
        }
        const JointT<double>& j = model.joints[size_t(sj)];
        check_transmission(j, given);
        Transmission t = given;
        t.joint = sj, t.dof = j.v_index;
        model.transmission_of_dof[size_t(t.dof)] = int(model.transmissions.size());
        model.transmissions.push_back(t);
    }
    for (const Drive& drive : options.drives) {
        const int sj = drive.joint >= 0 && size_t(drive.joint) < model.joint_of_source.size()
                           ? model.joint_of_source[size_t(drive.joint)]
                           : -1;
        if (sj < 0 || model.joints[size_t(sj)].nv() != 1)
            throw Error(MBX_ERROR_INVALID_INPUT, Subject::constraint(drive.spec.joint.constraint_id, drive.name),
                        "drive '" + drive.name + "' is not on a revolute or prismatic tree joint of this mechanism");
        JointT<double>& j = model.joints[size_t(sj)];
        // The rotor is on the motor side of an elastic transmission.
        const int t = model.transmission_of_dof[size_t(j.v_index)];
        if (t >= 0)
            model.transmissions[size_t(t)].motor_inertia += drive.armature;
        else
            j.dynamics.armature += drive.armature;
        model.drives.push_back(drive);
        model.drive_dof.push_back(j.v_index);
    }

    model.mass_scale = total_mass > 0 ? total_mass : 1.0;
    model.length_scale = m.assembly.size > 0 ? m.assembly.size : 1.0;

    // Limit springs sized by each joint's own inertia at the assembly pose,
    // so that a limit behaves alike on a finger and on a crane.
    Data data(model);
    update_positions(model, data);
    mass_matrix(model, data);
    if (!model.closures.empty()) {
        // The assembly pose closes every loop (validate refuses cut joints whose frames are apart).
        update_closure_jacobian(model, data);
        data.closure_factor.factor(data.J);
        model.closure_rank = data.closure_factor.rank;
    }
    for (JointT<double>& j : model.joints) {
        if (j.nv() == 1) j.reference_inertia = data.M(j.v_index, j.v_index);
        const int ti = j.nv() == 1 ? model.transmission_of_dof[size_t(j.v_index)] : -1;
        if (ti >= 0) {
            // A dead band's stops: a 1 ms time constant, critically damped,
            // on the motor and the link in series (the simulation fit's law).
            Transmission& t = model.transmissions[size_t(ti)];
            const double link = j.reference_inertia, motor = t.motor_inertia;
            const double reduced = link > 0 ? motor * link / (motor + link) : motor;
            constexpr double rate = 1000;  // 1/s
            t.stop_stiffness = reduced * rate * rate;
            t.stop_damping = 2 * reduced * rate;
        }
        JointDynamics& jd = j.dynamics;
        if (!jd.limited || (jd.limit_stiffness > 0 && jd.limit_damping > 0)) continue;
        double inertia = data.M(j.v_index, j.v_index);
        if (!(inertia > 0)) inertia = double(model.undetermined_inertia(j.kind)) * 1e6;
        const double tc = options.limit_time_constant, zeta = options.limit_damping_ratio;
        const double omega = 1.0 / (tc * zeta);
        if (jd.limit_stiffness == 0) jd.limit_stiffness = inertia * omega * omega;
        if (jd.limit_damping == 0) jd.limit_damping = 2 * zeta * omega * inertia;
    }
    return model;
}

}  // namespace mbx::sim
