#include "export/mjcf/mjcf_layout.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>

#include "export/common/names.h"
#include "export/common/number_text.h"

namespace mbx {
namespace {

// Stand-ins stay three orders of magnitude below the lightest real body:
// small enough not to change the dynamics, large enough that the mass matrix
// keeps a condition MuJoCo's solver handles.
constexpr double kLightFraction = 1e-3;
// A revolute cut's two connects sit this fraction of the model's size apart.
constexpr double kAxisSpacingFraction = 0.1;

bool degenerate(const Eigen::Vector3d& moments) {
    return !(moments.maxCoeff() > 0) || !(moments.minCoeff() > 1e-9 * moments.maxCoeff());
}

Eigen::Vector3d principal_moments(const Mat3& inertia) {
    Eigen::SelfAdjointEigenSolver<Mat3> eig(Mat3(0.5 * (inertia + inertia.transpose())), Eigen::EigenvaluesOnly);
    return eig.eigenvalues();  // ascending
}

class LayoutBuilder {
public:
    explicit LayoutBuilder(ExportModel& model) : model_(model), m_(model.mechanism()) {}

    MjcfLayout build() {
        body_names_.reserve("world");
        choose_light_values();
        choose_axis_spacing();
        out_.of_body.assign(m_.bodies.size(), -1);
        for (int b : model_.tree().order)
            if (b != 0) add_body(b);
        for (size_t j = 0; j < m_.joints.size(); ++j)
            if (m_.joints[j].cut) close_loop(int(j));
        for (const MjcfBody& body : out_.bodies)
            for (const MjcfJoint& joint : body.joints) {
                out_.constraint_rows += joint.limited ? 1 : 0;
                // MuJoCo's dry friction is a constraint row of its own.
                const ResolvedJointDynamics* jd = model_.joint_dynamics_of(joint.joint);
                out_.constraint_rows += jd && jd->symmetric_coulomb() > 0 ? 1 : 0;
            }
        for (const MjcfEquality& e : out_.equalities) out_.constraint_rows += e.kind == MjcfEquality::WELD ? 6 : 3;
        return std::move(out_);
    }

private:
    void choose_light_values() {
        double min_mass = 0, min_moment = 0;
        for (const RigidBody& b : m_.bodies) {
            if (b.kind != MBX_RIGID_BODY_DYNAMIC || !(b.mass > 0)) continue;
            min_mass = min_mass > 0 ? std::min(min_mass, b.mass) : b.mass;
            const Eigen::Vector3d moments = principal_moments(b.inertia);
            if (!degenerate(moments))
                min_moment = min_moment > 0 ? std::min(min_moment, moments.minCoeff()) : moments.minCoeff();
        }
        out_.light_mass = kLightFraction * (min_mass > 0 ? min_mass : 1.0);
        // Without any usable tensor: the light mass at a 1 cm radius of gyration.
        out_.light_inertia = min_moment > 0 ? kLightFraction * min_moment : out_.light_mass * 1e-4;
    }

    void choose_axis_spacing() {
        Vec3 lo = Vec3::Constant(INFINITY), hi = Vec3::Constant(-INFINITY);
        auto grow = [&](const Vec3& p) {
            lo = lo.cwiseMin(p);
            hi = hi.cwiseMax(p);
        };
        for (const RigidBody& b : m_.bodies) grow(b.pose.position);
        for (const Joint& j : m_.joints) grow(j.frame.position);
        const double size = (hi - lo).norm();
        out_.axis_spacing = kAxisSpacingFraction * (std::isfinite(size) && size > 1e-6 ? size : 1.0);
    }

    // MuJoCo frame of a rigid body: the world for ground, else its own body.
    int side(int body) const { return body == 0 ? -1 : out_.of_body[size_t(body)]; }
    Pose world_of(int mjcf_body) const {
        return mjcf_body < 0 ? Pose{} : out_.bodies[size_t(mjcf_body)].world;
    }

    int push_body(MjcfBody body) {
        const int index = int(out_.bodies.size());
        if (body.parent < 0)
            out_.top.push_back(index);
        else
            out_.bodies[size_t(body.parent)].children.push_back(index);
        out_.bodies.push_back(std::move(body));
        return index;
    }

    void add_body(int b) {
        const RigidBody& rb = m_.bodies[size_t(b)];
        const bool node = rb.kind == MBX_RIGID_BODY_JOINT_NODE;
        // A node with a joint below is merged into the body that chain ends in.
        if (node && !model_.tree().child_joints[size_t(b)].empty()) return;

        MjcfBody body;
        body.body = b;
        body.name = body_names_.claim(sanitize_identifier(rb.name, "body"));
        body.world = rb.pose;

        // The tree joints from the nearest non-node ancestor down to b.
        std::vector<int> chain;
        int top = -1;
        for (int cur = b; m_.bodies[size_t(cur)].parent_joint >= 0;) {
            const int j = m_.bodies[size_t(cur)].parent_joint;
            chain.push_back(j);
            cur = m_.joints[size_t(j)].parent;
            top = cur;
            if (m_.bodies[size_t(cur)].kind != MBX_RIGID_BODY_JOINT_NODE) break;
        }
        std::reverse(chain.begin(), chain.end());
        if (top < 0) {
            body.free = true;
            body.free_name = joint_names_.claim(body.name + "_free");
        } else {
            body.parent = side(top);
        }
        body.local = world_of(body.parent).inverse() * body.world;

        const Pose to_body = body.world.inverse();
        for (int j : chain) {
            const Joint& joint = m_.joints[size_t(j)];
            if (joint.type == MBX_PRIMITIVE_WELD) continue;  // no freedom, no MJCF joint
            const JointPlacement& p = model_.placement(j);
            MjcfJoint mj;
            mj.joint = j;
            mj.name = joint_names_.claim(sanitize_identifier(joint.name, "joint"));
            mj.type = joint.type;
            mj.frame = to_body * m_.bodies[size_t(joint.parent)].pose * p.parent_to_joint;
            mj.axis = mj.frame.rotation * p.axis;
            mj.limited = joint.type != MBX_PRIMITIVE_SPHERICAL && model_.limits(j, mj.lower, mj.upper);
            body.joints.push_back(std::move(mj));
        }

        if (node) {
            body.mass = out_.light_mass;
            body.inertia = out_.light_inertia * Mat3::Identity();
            model_.note(MBX_SEVERITY_WARNING, MBX_FINDING_EXPORT_APPROXIMATION, Subject::rigid_body(rb.id, rb.name),
                        "joint node '" + rb.name +
                            "' ends a chain at a cut joint and has no body below it; MuJoCo needs mass on a moving "
                            "body, so it carries " + number_text(body.mass) + " kg and " +
                            number_text(out_.light_inertia) + " kg*m^2 (1e-3 of the lightest body)");
        } else {
            inertial_of(rb, body);
        }
        out_.of_body[size_t(b)] = push_body(std::move(body));
    }

    void inertial_of(const RigidBody& rb, MjcfBody& body) {
        body.mass = rb.mass;
        body.com = rb.com;
        body.inertia = 0.5 * (rb.inertia + rb.inertia.transpose());
        const Subject subject = Subject::rigid_body(rb.id, rb.name);
        if (!(rb.mass > 0)) {
            body.mass = out_.light_mass;
            body.inertia = out_.light_inertia * Mat3::Identity();
            model_.note(MBX_SEVERITY_WARNING, MBX_FINDING_EXPORT_APPROXIMATION, subject,
                        "rigid body '" + rb.name + "' has no mass; MuJoCo refuses massless moving bodies, so it carries " +
                            number_text(body.mass) + " kg and " + number_text(out_.light_inertia) + " kg*m^2");
            return;
        }
        Eigen::SelfAdjointEigenSolver<Mat3> eig(body.inertia);
        Eigen::Vector3d moments = eig.eigenvalues();
        if (degenerate(moments)) {
            // MuJoCo needs positive principal moments; raise each to the
            // stand-in value, keeping the principal axes.
            moments = moments.cwiseMax(out_.light_inertia);
            body.inertia = eig.eigenvectors() * moments.asDiagonal() * eig.eigenvectors().transpose();
            model_.note(MBX_SEVERITY_WARNING, MBX_FINDING_EXPORT_APPROXIMATION, subject,
                        "rigid body '" + rb.name + "' has an inertia tensor that is not positive definite; its "
                        "principal moments were raised to at least " + number_text(out_.light_inertia) + " kg*m^2");
            std::sort(moments.data(), moments.data() + 3);
        }
        if (moments[0] + moments[1] < moments[2] * (1 - 1e-9)) {
            model_.note(MBX_SEVERITY_WARNING, MBX_FINDING_EXPORT_APPROXIMATION, subject,
                        "rigid body '" + rb.name +
                            "' has principal moments that break the triangle inequality; MuJoCo's balanceinertia "
                            "replaces them by their mean");
        }
    }

    void close_loop(int c) {
        const Joint& joint = m_.joints[size_t(c)];
        const JointPlacement& p = model_.placement(c);
        const std::string base = sanitize_identifier(joint.name, "cut");
        const Subject subject = Subject::constraint(constraint_id(joint), joint.name);
        int a = side(joint.parent), b = side(joint.child);
        const Pose frame = m_.bodies[size_t(joint.parent)].pose * p.parent_to_joint;  // world, qpos0
        const Vec3 axis = frame.rotation * p.axis;
        if (joint.has_limits && joint.type != MBX_PRIMITIVE_PRISMATIC)
            model_.note(MBX_SEVERITY_WARNING, MBX_FINDING_EXPORT_APPROXIMATION, subject,
                        "the limits of cut joint '" + joint.name + "' are not exported: MuJoCo's equality "
                        "constraints that close the loop carry no limits");

        auto connect = [&](const std::string& name, const Vec3& point) {
            int b1 = a, b2 = b;
            if (b1 < 0) std::swap(b1, b2);  // anchor on a moving body; MuJoCo finds the other from qpos0
            MjcfEquality e;
            e.kind = MjcfEquality::CONNECT;
            e.name = name;
            e.cut_joint = c;
            e.body1 = b1;
            e.body2 = b2;
            e.anchor = world_of(b1).inverse().apply(point);
            out_.equalities.push_back(std::move(e));
        };
        auto weld = [&](int b1, int b2) {
            if (b1 < 0) std::swap(b1, b2);
            MjcfEquality e;
            e.kind = MjcfEquality::WELD;
            e.name = eq_names_.claim(base);
            e.cut_joint = c;
            e.body1 = b1;
            e.body2 = b2;
            out_.equalities.push_back(std::move(e));
        };

        switch (joint.type) {
        case MBX_PRIMITIVE_SPHERICAL:
            connect(eq_names_.claim(base), frame.position);
            break;
        case MBX_PRIMITIVE_REVOLUTE: {
            // Two points on the axis fix the point and the axis direction.
            const Vec3 half = 0.5 * out_.axis_spacing * axis;
            const std::string n1 = eq_names_.claim(base + "_a");
            const std::string n2 = eq_names_.claim(base + "_b");
            connect(n1, frame.position - half);
            connect(n2, frame.position + half);
            break;
        }
        case MBX_PRIMITIVE_WELD:
            weld(a, b);
            break;
        case MBX_PRIMITIVE_PRISMATIC: {
            // No prismatic equality in MuJoCo: a light slider on the parent side,
            // welded to the child side.
            MjcfBody slider;
            slider.name = body_names_.claim(base + "_slider");
            slider.parent = a;
            slider.world = frame;
            slider.local = world_of(a).inverse() * frame;
            slider.mass = out_.light_mass;
            slider.inertia = out_.light_inertia * Mat3::Identity();
            MjcfJoint slide;
            slide.name = joint_names_.claim(base);
            slide.type = MBX_PRIMITIVE_PRISMATIC;
            slide.axis = p.axis;  // the joint frame has the parent's axes, so does the slider
            slide.limited = joint.has_limits;
            slide.lower = joint.lower;
            slide.upper = joint.upper;
            slider.joints.push_back(std::move(slide));
            const int s = push_body(std::move(slider));
            weld(s, b);
            model_.note(MBX_SEVERITY_WARNING, MBX_FINDING_EXPORT_APPROXIMATION, subject,
                        "MuJoCo has no prismatic equality constraint: cut joint '" + joint.name +
                            "' is a slide joint on a helper body of " + number_text(out_.light_mass) +
                            " kg welded to the child side");
            break;
        }
        }
    }

    std::string constraint_id(const Joint& joint) const {
        return joint.constraint >= 0 ? m_.assembly.constraints[size_t(joint.constraint)].id : joint.name;
    }

    ExportModel& model_;
    const Mechanism& m_;
    MjcfLayout out_;
    NameTable body_names_, joint_names_, eq_names_;
};

}  // namespace

MjcfLayout build_mjcf_layout(ExportModel& model) { return LayoutBuilder(model).build(); }

}  // namespace mbx
