// The URDF tests' consumer side: urdfdom parses the exported file, and the
// link poses are composed here from what urdfdom read (joint origins and
// axes), independently of the exporter's own frame arithmetic.
#pragma once
#include <functional>
#include <map>
#include <random>
#include <string>

#include <urdf_parser/urdf_parser.h>

#include "export_fixture.h"
#include "export/urdf/urdf_export.h"
#include "export/urdf/urdf_layout.h"

namespace urdf_test {

using namespace mbx;  // test helpers only: the SDK's vocabulary unqualified

inline Pose to_pose(const urdf::Pose& p) {
    const Eigen::Quaterniond q(p.rotation.w, p.rotation.x, p.rotation.y, p.rotation.z);
    return {q.normalized().toRotationMatrix(), Vec3(p.position.x, p.position.y, p.position.z)};
}

inline Vec3 to_vec(const urdf::Vector3& v) { return {v.x, v.y, v.z}; }

// Rotation from a URDF rpy triple, through urdfdom's own conversion.
inline Mat3 rpy_rotation(double roll, double pitch, double yaw) {
    urdf::Rotation r;
    r.setFromRPY(roll, pitch, yaw);
    return Eigen::Quaterniond(r.w, r.x, r.y, r.z).normalized().toRotationMatrix();
}

// World pose of every link, joints at `q` (by joint name; missing ones at 0;
// floating joints at their origin).
inline std::map<std::string, Pose> link_poses(const urdf::ModelInterface& model,
                                              const std::map<std::string, double>& q) {
    std::map<std::string, Pose> out;
    std::function<void(const urdf::Link&, const Pose&)> walk = [&](const urdf::Link& link, const Pose& pose) {
        out[link.name] = pose;
        for (const urdf::JointSharedPtr& joint : link.child_joints) {
            const auto it = q.find(joint->name);
            const double v = it == q.end() ? 0.0 : it->second;
            Pose motion;
            const Vec3 axis = to_vec(joint->axis).normalized();
            switch (joint->type) {
            case urdf::Joint::REVOLUTE:
            case urdf::Joint::CONTINUOUS: motion.rotation = Eigen::AngleAxisd(v, axis).toRotationMatrix(); break;
            case urdf::Joint::PRISMATIC: motion.position = axis * v; break;
            default: break;
            }
            const urdf::LinkConstSharedPtr child = model.getLink(joint->child_link_name);
            REQUIRE(child);
            walk(*child, pose * to_pose(joint->parent_to_joint_origin_transform) * motion);
        }
    };
    walk(*model.getRoot(), Pose{});
    return out;
}

inline double pose_error(const Pose& a, const Pose& b) {
    return std::max((a.position - b.position).norm(), (a.rotation - b.rotation).norm());
}

// Random coordinates for the tree joints (within CAD limits when there are
// some) and the matching URDF joint values.
struct Configuration {
    std::vector<mbx::JointPosition> mbx;
    std::map<std::string, double> urdf;
};

inline Configuration random_configuration(const mbx::Mechanism& m, const UrdfLayout& layout, std::mt19937& rng) {
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    Configuration c;
    c.mbx.resize(m.joints.size());
    std::vector<Vec3> angles(m.joints.size(), Vec3::Zero());
    for (size_t j = 0; j < m.joints.size(); ++j) {
        const mbx::Joint& joint = m.joints[j];
        if (joint.cut) continue;
        double lo = joint.type == MBX_PRIMITIVE_PRISMATIC ? -0.05 : -2.5, hi = -lo;
        if (joint.has_limits && joint.upper > joint.lower) lo = joint.lower, hi = joint.upper;
        c.mbx[j].value = lo + (hi - lo) * unit(rng);
        if (joint.type == MBX_PRIMITIVE_SPHERICAL) {
            for (int k = 0; k < 3; ++k) angles[j][k] = -1.4 + 2.8 * unit(rng);
            c.mbx[j].rotation = Eigen::AngleAxisd(angles[j].x(), Vec3::UnitX()) *
                                Eigen::AngleAxisd(angles[j].y(), Vec3::UnitY()) *
                                Eigen::AngleAxisd(angles[j].z(), Vec3::UnitZ());
        }
    }
    for (const mbx::UrdfJoint& u : layout.joints) {
        if (u.source < 0) continue;
        c.urdf[u.name] = u.spherical_axis >= 0 ? angles[size_t(u.source)][u.spherical_axis] : c.mbx[size_t(u.source)].value;
    }
    return c;
}

// The file urdf/<robot>.urdf among `files`.
inline const mbx::OutputFile& urdf_file(const OutputFiles& files, const std::string& robot) {
    const mbx::OutputFile* f = xtest::find_file(files, "urdf/" + robot + ".urdf");
    REQUIRE(f != nullptr);
    return *f;
}

inline int count_notes(const Findings& notes, mbx_finding_code code) {
    int n = 0;
    for (const mbx::Finding& f : notes) n += f.code == code;
    return n;
}

struct Result {
    UrdfLayout layout;
    OutputFiles files;
    Findings notes;
    urdf::ModelInterfaceSharedPtr urdf;
};

// Link frame convention (docs/exporters.md, URDF): the body's axes, at the
// body origin for roots and at the parent joint's point otherwise.
inline Pose expected_link_in_body(const ExportModel& model, int b) {
    const RigidBody& body = model.mechanism().bodies[size_t(b)];
    if (body.parent_joint < 0) return Pose{};
    return Pose{Mat3::Identity(), model.placement(body.parent_joint).joint_to_child.inverse().position};
}

inline void check_types_and_limits(const Mechanism& m, const UrdfLayout& layout, const urdf::ModelInterface& u) {
    for (size_t j = 0; j < m.joints.size(); ++j) {
        const Joint& joint = m.joints[j];
        const urdf::JointConstSharedPtr uj = u.getJoint(layout.joint_name[j]);
        if (joint.cut || joint.type == MBX_PRIMITIVE_SPHERICAL) {
            CHECK(!uj);  // cut joints live in the sidecar, sphericals are split
            if (joint.type == MBX_PRIMITIVE_SPHERICAL && !joint.cut)
                for (const char* s : {"_x", "_y", "_z"}) {
                    const urdf::JointConstSharedPtr part = u.getJoint(layout.joint_name[j] + s);
                    REQUIRE(part);
                    CHECK(part->type == urdf::Joint::CONTINUOUS);
                }
            continue;
        }
        CAPTURE(joint.name);
        REQUIRE(uj);
        if (joint.type == MBX_PRIMITIVE_REVOLUTE) {
            CHECK(uj->type == (joint.has_limits ? urdf::Joint::REVOLUTE : urdf::Joint::CONTINUOUS));
            if (joint.has_limits) {
                REQUIRE(uj->limits);
                CHECK(uj->limits->lower == joint.lower);
                CHECK(uj->limits->upper == joint.upper);
            }
        } else if (joint.type == MBX_PRIMITIVE_PRISMATIC) {
            CHECK(uj->type == urdf::Joint::PRISMATIC);
            REQUIRE(uj->limits);
            CHECK(uj->limits->lower == (joint.has_limits ? joint.lower : -kUrdfPrismaticRange));
            CHECK(uj->limits->upper == (joint.has_limits ? joint.upper : kUrdfPrismaticRange));
        }
        if (uj->limits) {
            CHECK(uj->limits->effort > 0);
            CHECK(uj->limits->velocity > 0);
        }
    }
}

// Everything that the parsed model says about link `b`, in world at one configuration.
inline void check_body(ExportModel& model, const Result& r, int b, const Pose& fk, const std::map<std::string, Pose>& links) {
    const Mechanism& m = model.mechanism();
    const RigidBody& body = m.bodies[size_t(b)];
    const std::string& name = r.layout.links[size_t(r.layout.body_link[size_t(b)])].name;
    CAPTURE(body.name);
    CAPTURE(name);
    const auto it = links.find(name);
    REQUIRE(it != links.end());
    const Pose& link = it->second;
    CHECK(pose_error(link, fk * expected_link_in_body(model, b)) < 1e-9);

    const urdf::LinkConstSharedPtr u = r.urdf->getLink(name);
    REQUIRE(u);
    if (body.kind == MBX_RIGID_BODY_JOINT_NODE || body.mass <= 0) {
        CHECK(!u->inertial);
    } else {
        REQUIRE(u->inertial);
        CHECK(u->inertial->mass == body.mass);
        const Pose frame = link * to_pose(u->inertial->origin);
        CHECK((frame.position - fk.apply(body.com)).norm() < 1e-9);
        const urdf::Inertial& in = *u->inertial;
        Mat3 local;
        local << in.ixx, in.ixy, in.ixz, in.ixy, in.iyy, in.iyz, in.ixz, in.iyz, in.izz;
        const Mat3 world = frame.rotation * local * frame.rotation.transpose();
        const Mat3 expected = fk.rotation * body.inertia * fk.rotation.transpose();
        CHECK((world - expected).norm() <= 1e-9 * (expected.norm() + 1e-300));
    }
    if (model.has_mesh(b)) {
        REQUIRE(u->visual);
        CHECK(u->visual_array.size() == 1);
        REQUIRE(u->visual->geometry);
        REQUIRE(u->visual->geometry->type == urdf::Geometry::MESH);
        const auto& mesh = static_cast<const urdf::Mesh&>(*u->visual->geometry);
        const mbx_mesh_format format = urdf_mesh_format(model.settings().mesh_format);
        CHECK(mesh.filename == "../meshes/" + model.mesh_stem(b) + "." + mesh_extension(format));
        // The mesh is in the body frame: the visual frame is the body frame.
        CHECK(pose_error(link * to_pose(u->visual->origin), fk) < 1e-9);
    } else {
        CHECK(!u->visual);
    }
}

// Exports, parses and compares with forward kinematics at zero and at `trials` random configurations.
inline Result check_urdf(xtest::Translated& t, unsigned seed, int trials = 3, ExportSettings settings = {}) {
    ExportModel model = xtest::export_model(t, settings);
    Result r;
    export_urdf(model, r.files);
    r.layout = plan_urdf(model);
    r.notes = model.notes();
    const OutputFile& file = urdf_file(r.files, r.layout.robot);
    r.urdf = urdf::parseURDF(file.contents);
    REQUIRE_MESSAGE(r.urdf, "urdfdom rejected " << file.path);
    const Mechanism& m = *t.mechanism;

    CHECK(r.urdf->getName() == r.layout.robot);
    CHECK(r.urdf->getRoot()->name == "world");
    size_t spherical = 0;
    for (const Joint& j : m.joints) spherical += !j.cut && j.type == MBX_PRIMITIVE_SPHERICAL;
    CHECK(r.urdf->links_.size() == m.bodies.size() + 1 + 2 * spherical);
    CHECK(r.urdf->joints_.size() + 1 == r.urdf->links_.size());
    check_types_and_limits(m, r.layout, *r.urdf);

    std::mt19937 rng(seed);
    for (int trial = 0; trial <= trials; ++trial) {
        CAPTURE(trial);
        Configuration c;
        if (trial == 0) {
            c.mbx.resize(m.joints.size());
        } else {
            c = random_configuration(m, r.layout, rng);
        }
        const std::vector<Pose> fk = forward_kinematics(m, c.mbx);
        const std::map<std::string, Pose> links = link_poses(*r.urdf, c.urdf);
        CHECK(links.size() == r.urdf->links_.size());
        for (size_t b = 0; b < m.bodies.size(); ++b) check_body(model, r, int(b), fk[b], links);
    }
    const int loops_as_tree = count_notes(r.notes, MBX_FINDING_EXPORT_LOOPS_AS_TREE);
    CHECK(loops_as_tree == (m.loops.empty() ? 0 : 1));
    CHECK((xtest::find_file(r.files, "urdf/" + r.layout.robot + ".cut_joints.json") != nullptr) == !m.loops.empty());
    return r;
}

}  // namespace urdf_test
