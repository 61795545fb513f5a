#include "export/urdf/urdf_export.h"

#include <sstream>

#include <pugixml.hpp>

#include "export/common/number_text.h"
#include "export/mesh/collision_meshes.h"
#include "export/mesh/mesh_export.h"
#include "export/urdf/cut_joints_sidecar.h"
#include "export/urdf/urdf_layout.h"

namespace mbx {
namespace {

void set_origin(pugi::xml_node parent, const Pose& pose) {
    pugi::xml_node o = parent.append_child("origin");
    o.append_attribute("xyz") = spaced_text(pose.position).c_str();
    o.append_attribute("rpy") = spaced_text(rpy_from_rotation(pose.rotation)).c_str();
}

void set_number(pugi::xml_node node, const char* name, double v) {
    node.append_attribute(name) = number_text(v).c_str();
}

// Inertial, with the body's CoM and inertia moved into the link frame.
void write_inertial(pugi::xml_node link, const RigidBody& body, const Pose& link_in_body) {
    const Pose body_in_link = link_in_body.inverse();
    pugi::xml_node in = link.append_child("inertial");
    set_origin(in, Pose{body_in_link.rotation, body_in_link.apply(body.com)});
    set_number(in.append_child("mass"), "value", body.mass);
    const Mat3 I = 0.5 * (body.inertia + body.inertia.transpose());
    pugi::xml_node t = in.append_child("inertia");
    set_number(t, "ixx", I(0, 0));
    set_number(t, "ixy", I(0, 1));
    set_number(t, "ixz", I(0, 2));
    set_number(t, "iyy", I(1, 1));
    set_number(t, "iyz", I(1, 2));
    set_number(t, "izz", I(2, 2));
}

// One SimpleTransmission per drive (the ROS convention consumers such as
// ros2_control and Gazebo read), with the reduction, and the rotor inertia in
// Drake's extension: Drake adds rotor_inertia * gear_ratio^2 to the joint,
// which is the drive's armature when rotor_inertia is armature / ratio^2.
// A hull's mesh file (the hull in its body's frame), by shape index.
struct UrdfHull {
    int shape = -1;
    std::string path;  // relative to the output directory
};

// The collision shapes on `body`, each placed by its pose in the body
// frame taken into the link frame. URDF has no capsule: it becomes the
// cylinder and the two spheres whose union it is (exact). Planes have no
// URDF geometry (noted in export_urdf).
void write_collisions(pugi::xml_node link, const ExportModel& model, int body, const Pose& link_in_body,
                      const std::vector<UrdfHull>& hulls) {
    const ResolvedContact& rc = model.settings().contact;
    const Pose body_in_link = link_in_body.inverse();
    auto element = [&](const std::string& name, const Pose& pose_in_body) {
        pugi::xml_node c = link.append_child("collision");
        c.append_attribute("name") = name.c_str();
        set_origin(c, body_in_link * pose_in_body);
        return c.append_child("geometry");
    };
    for (size_t i = 0; i < rc.shapes.size(); ++i) {
        const ResolvedCollision& r = rc.shapes[i];
        if (r.body != body) continue;
        const CollisionSpec& s = r.spec;
        switch (s.kind) {
        case CollisionKind::Sphere: set_number(element(r.name, r.pose).append_child("sphere"), "radius", s.radius); break;
        case CollisionKind::Box:
            element(r.name, r.pose).append_child("box").append_attribute("size") = spaced_text(s.size).c_str();
            break;
        case CollisionKind::Cylinder:
        case CollisionKind::Capsule: {
            pugi::xml_node cyl = element(r.name, r.pose).append_child("cylinder");
            set_number(cyl, "radius", s.radius), set_number(cyl, "length", s.length);
            if (s.kind == CollisionKind::Capsule)
                for (const double end : {-0.5, 0.5}) {
                    const Pose cap = r.pose * Pose{Mat3::Identity(), Vec3(0, 0, end * s.length)};
                    set_number(element(r.name + (end < 0 ? "_cap0" : "_cap1"), cap).append_child("sphere"), "radius", s.radius);
                }
            break;
        }
        case CollisionKind::Hull:
            for (const UrdfHull& h : hulls)
                if (h.shape == int(i))
                    element(r.name, r.pose).append_child("mesh").append_attribute("filename") = ("../" + h.path).c_str();
            break;
        case CollisionKind::Plane: break;
        }
    }
}

void write_transmissions(pugi::xml_node robot, const ExportModel& model, const UrdfLayout& L) {
    const Mechanism& m = model.mechanism();
    for (size_t j = 0; j < m.joints.size(); ++j) {
        const Drive* d = model.drive_of(int(j));
        if (!d) continue;
        const std::string& joint = L.joint_name[j];
        pugi::xml_node t = robot.append_child("transmission");
        t.append_attribute("name") = ("drive_" + joint).c_str();
        t.append_child("type").text() = "transmission_interface/SimpleTransmission";
        pugi::xml_node tj = t.append_child("joint");
        tj.append_attribute("name") = joint.c_str();
        tj.append_child("hardwareInterface").text() = "hardware_interface/EffortJointInterface";
        pugi::xml_node a = t.append_child("actuator");
        a.append_attribute("name") = ("motor_" + joint).c_str();
        a.append_child("mechanicalReduction").text() = number_text(d->ratio).c_str();
        set_number(a.append_child("drake:rotor_inertia"), "value", d->armature / (d->ratio * d->ratio));
        set_number(a.append_child("drake:gear_ratio"), "value", d->ratio);
    }
}

std::string urdf_text(ExportModel& model, const UrdfLayout& L, const std::vector<UrdfHull>& hulls) {
    const Mechanism& m = model.mechanism();
    const mbx_mesh_format mesh_format = urdf_mesh_format(model.settings().mesh_format);
    pugi::xml_document doc;
    pugi::xml_node decl = doc.append_child(pugi::node_declaration);
    decl.append_attribute("version") = "1.0";
    decl.append_attribute("encoding") = "UTF-8";
    doc.append_child(pugi::node_comment)
        .set_value(" Generated by mbx. Link frames: the rigid body's axes at its parent joint's point; "
                   "see docs/exporters.md, URDF. ");
    pugi::xml_node robot = doc.append_child("robot");
    robot.append_attribute("name") = L.robot.c_str();
    if (!model.settings().drives.empty()) robot.append_attribute("xmlns:drake") = "http://drake.mit.edu";

    // Each link, then the joint that holds it, in parent-first order.
    std::vector<int> joint_of_link(L.links.size(), -1);
    for (size_t k = 0; k < L.joints.size(); ++k) joint_of_link[size_t(L.joints[k].child_link)] = int(k);

    for (size_t l = 0; l < L.links.size(); ++l) {
        const UrdfLink& link = L.links[l];
        pugi::xml_node xl = robot.append_child("link");
        xl.append_attribute("name") = link.name.c_str();
        if (link.body >= 0) {
            const RigidBody& body = m.bodies[size_t(link.body)];
            const Pose& link_in_body = L.link_in_body[size_t(link.body)];
            if (body.kind != MBX_RIGID_BODY_JOINT_NODE && body.mass > 0) write_inertial(xl, body, link_in_body);
            if (model.has_mesh(link.body)) {
                pugi::xml_node v = xl.append_child("visual");
                set_origin(v, link_in_body.inverse());  // meshes are in the body frame
                const std::string file = "../" + model.mesh_path(link.body, mesh_format);
                v.append_child("geometry").append_child("mesh").append_attribute("filename") = file.c_str();
            }
            write_collisions(xl, model, link.body, link_in_body, hulls);
        }
        if (joint_of_link[l] < 0) continue;
        const UrdfJoint& u = L.joints[size_t(joint_of_link[l])];
        pugi::xml_node xj = robot.append_child("joint");
        xj.append_attribute("name") = u.name.c_str();
        xj.append_attribute("type") = u.type.c_str();
        set_origin(xj, u.origin);
        xj.append_child("parent").append_attribute("link") = L.links[size_t(u.parent_link)].name.c_str();
        xj.append_child("child").append_attribute("link") = L.links[size_t(u.child_link)].name.c_str();
        if (u.type != "fixed" && u.type != "floating")
            xj.append_child("axis").append_attribute("xyz") = spaced_text(u.axis).c_str();
        const Drive* drive = u.spherical_axis < 0 ? model.drive_of(u.source) : nullptr;
        // The joint's own rated speed and effort, as the host gave them.
        const Primitive* rated = nullptr;
        if (u.source >= 0 && u.spherical_axis < 0) {
            const Joint& joint = model.mechanism().joints[size_t(u.source)];
            rated = &model.mechanism().assembly.constraints[size_t(joint.constraint)].chain[size_t(joint.primitive_index)];
        }
        const double rated_effort = rated ? rated->effort_limit : 0, rated_velocity = rated ? rated->velocity_limit : 0;
        if (u.has_limit || drive || rated_effort > 0 || rated_velocity > 0) {
            // A driven joint's effort and velocity limits are its drive's,
            // else the joint's own, else stand-ins URDF requires; a
            // continuous joint carries them without lower/upper.
            pugi::xml_node lim = xj.append_child("limit");
            if (u.has_limit) {
                set_number(lim, "lower", u.lower);
                set_number(lim, "upper", u.upper);
            }
            set_number(lim, "effort", drive ? drive->effort_limit : rated_effort > 0 ? rated_effort : kUrdfEffortLimit);
            set_number(lim, "velocity", drive ? drive->velocity_limit : rated_velocity > 0 ? rated_velocity : kUrdfVelocityLimit);
        }
        // URDF's dynamics: viscous damping (the motor's back-EMF braking
        // and the joint's own) and dry friction.
        const ResolvedJointDynamics* jd = u.spherical_axis < 0 ? model.joint_dynamics_of(u.source) : nullptr;
        // Both are symmetric in URDF: the law's symmetric part (add_notes names the rest).
        const double damping = (drive ? drive->servo.emf_damping : 0) + (jd ? jd->symmetric_damping() : 0);
        const double friction = jd ? jd->symmetric_coulomb() : 0;
        if (damping > 0 || friction > 0) {
            pugi::xml_node dyn = xj.append_child("dynamics");
            if (damping > 0) set_number(dyn, "damping", damping);
            if (friction > 0) set_number(dyn, "friction", friction);
        }
    }
    write_transmissions(robot, model, L);
    std::ostringstream os;
    doc.save(os, "  ", pugi::format_indent, pugi::encoding_utf8);
    return os.str();
}

void add_notes(ExportModel& model, const UrdfLayout& L) {
    const Mechanism& m = model.mechanism();
    for (const UrdfJoint& u : L.joints) {
        if (u.source < 0) continue;
        const Joint& joint = m.joints[size_t(u.source)];
        const std::string& name = L.joint_name[size_t(u.source)];
        if (u.spherical_axis == 0)
            model.note(MBX_SEVERITY_WARNING, MBX_FINDING_EXPORT_APPROXIMATION, model.joint_subject(u.source),
                       "URDF has no spherical joint: '" + joint.name + "' is exported as three continuous revolutes " +
                           name + "_x, " + name + "_y, " + name +
                           "_z about the x, y, z axes of its joint frame (two massless links between them); "
                           "singular where the middle angle is +-90 degrees");
        if (const ResolvedJointDynamics* jd = u.spherical_axis < 0 ? model.joint_dynamics_of(u.source) : nullptr) {
            std::string lost;
            if (jd->stiffness > 0) lost = "its spring (stiffness " + number_text(jd->stiffness) + ", rest " + number_text(jd->rest) + ")";
            if (jd->armature > 0)
                lost += (lost.empty() ? "its armature " : " and its armature ") + number_text(jd->armature);
            if (!lost.empty())
                model.note(MBX_SEVERITY_WARNING, MBX_FINDING_EXPORT_APPROXIMATION, model.joint_subject(u.source),
                           "URDF has no joint spring or armature: joint '" + joint.name + "' is written without " +
                               lost + " (its damping, friction and limits are written)");
            if (const std::string beyond = joint_dynamics_beyond_symmetric(*jd); !beyond.empty())
                model.note(MBX_SEVERITY_WARNING, MBX_FINDING_EXPORT_APPROXIMATION, model.joint_subject(u.source),
                           "URDF joint friction and damping are symmetric and it has no constant joint effort: joint '" +
                               joint.name + "' is written without " + beyond);
        }
        if (u.default_range)
            model.note(MBX_SEVERITY_WARNING, MBX_FINDING_EXPORT_APPROXIMATION, model.joint_subject(u.source),
                       "prismatic joint '" + joint.name + "' has no CAD limits; URDF requires some, so it is given +-" +
                           number_text(kUrdfPrismaticRange) + " m");
    }
    std::string cut_names;
    int cuts = 0;
    for (size_t j = 0; j < m.joints.size(); ++j) {
        if (!m.joints[j].cut) continue;
        if (++cuts <= 8) cut_names += (cuts > 1 ? ", '" : "'") + m.joints[j].name + "'";
    }
    if (cuts == 0) return;
    if (cuts > 8) cut_names += ", ...";
    model.note(MBX_SEVERITY_WARNING, MBX_FINDING_EXPORT_LOOPS_AS_TREE, Subject::model(L.robot),
               "URDF cannot close loops: urdf/" + L.robot + ".urdf holds the spanning tree and the " +
                   std::to_string(cuts) + " cut joint" + (cuts > 1 ? "s" : "") + " that close the " +
                   std::to_string(m.loops.size()) + " loop" + (m.loops.size() > 1 ? "s" : "") + " (" + cut_names +
                   ") are listed in urdf/" + L.robot + ".cut_joints.json");
}

}  // namespace

void export_urdf(ExportModel& model, OutputFiles& out) {
    const UrdfLayout layout = plan_urdf(model);
    // Hulls as binary STL files beside the body meshes, computed as the
    // simulator computes them (collision_meshes notes the planes it leaves
    // out and hulls without a mesh).
    std::vector<UrdfHull> hulls;
    for (const CollisionMesh& c : collision_meshes(model, "URDF", true)) {
        const std::string path = "meshes/collision/" + c.node + ".stl";
        out.push_back({path, encode_mesh({c.mesh}, c.node, MBX_MESH_STL), false});
        hulls.push_back({c.shape, path});
    }
    for (const ResolvedCollision& r : model.settings().contact.shapes) {
        if (r.spec.kind == CollisionKind::Plane)
            model.note(MBX_SEVERITY_INFO, MBX_FINDING_EXPORT_APPROXIMATION, Subject::model(r.name),
                       "URDF: plane '" + r.name + "' has no URDF geometry and is left out");
        if (r.spec.kind == CollisionKind::Capsule)
            model.note(MBX_SEVERITY_INFO, MBX_FINDING_EXPORT_APPROXIMATION, Subject::model(r.name),
                       "URDF: capsule '" + r.name + "' is written as its cylinder and two end spheres (URDF has no capsule)");
    }
    out.push_back({"urdf/" + layout.robot + ".urdf", urdf_text(model, layout, hulls), false});
    std::string sidecar = cut_joints_json(model, layout);
    if (!sidecar.empty()) out.push_back({"urdf/" + layout.robot + ".cut_joints.json", std::move(sidecar), false});
    add_notes(model, layout);
}

}  // namespace mbx
