// The simulation model: constant once built, shared by any number of data
// objects (sim/data.h), like Pinocchio's Model or MuJoCo's mjModel. Bodies
// are numbered parent-first (body 0 is the world), each non-world body has
// exactly one joint to its parent (a free joint for a floating root), and
// every cut joint of the translated mechanism is a loop-closure constraint.
// Templated on the scalar so that identified parameters (masses, friction)
// can be Ceres Jets; build_model (sim/build_model.h) makes the double one.
#pragma once
#include <array>
#include <string>
#include <vector>

#include "core/finding.h"
#include "core/mechatronics/drive.h"
#include "core/mechatronics/joint_dynamics_fields.h"
#include "sim/joint_motion.h"

namespace mbx::sim {

// What acts on one joint besides the bodies (per velocity coordinate of a
// revolute or prismatic joint; efforts in N m or N). All zero: a free joint.
template <class S> struct JointDynamicsT {
    S damping = S(0);          // viscous: -damping * qd (qd > 0 only when asymmetric)
    S coulomb = S(0);          // Coulomb friction magnitude (qd > 0 only when asymmetric)
    S coulomb_velocity = S(0); // regularisation speed of the fixed-step law (0: model default)
    // asymmetric: damping_negative and coulomb_negative hold for qd < 0.
    bool asymmetric = false;
    S damping_negative = S(0), coulomb_negative = S(0);
    S stribeck = S(0);           // static friction above the Coulomb level: + stribeck * exp(-(qd/stribeck_velocity)^2)
    S stribeck_velocity = S(0);
    S offset = S(0);             // constant effort the actuator supplies besides the rest: acts as -offset
    S stiffness = S(0);        // spring: -stiffness * (q - rest)
    S rest = S(0);
    S armature = S(0);         // added to the joint's diagonal of the mass matrix (reflected rotor inertia)
    bool limited = false;
    S lower = S(0), upper = S(0);
    S limit_stiffness = S(0), limit_damping = S(0);  // set by build_model from the joint's inertia

    template <class T> JointDynamicsT<T> cast() const {
        JointDynamicsT<T> r;
#define MBX_CAST_FIELD(field) r.field = T(field);
        MBX_JOINT_DYNAMICS_SCALARS(MBX_CAST_FIELD)
#undef MBX_CAST_FIELD
        r.asymmetric = asymmetric, r.damping_negative = T(damping_negative), r.coulomb_negative = T(coulomb_negative);
        r.limited = limited;
        r.limit_stiffness = T(limit_stiffness), r.limit_damping = T(limit_damping);
        return r;
    }
    // The Coulomb level and the viscous coefficient for motion along
    // `direction` (+1 or -1).
    const S& coulomb_along(int direction) const { return asymmetric && direction < 0 ? coulomb_negative : coulomb; }
    const S& damping_along(int direction) const { return asymmetric && direction < 0 ? damping_negative : damping; }
    // Any dry friction (the accurate mode's stick/slip joints).
    bool dry_friction() const {
        return coulomb != S(0) || (asymmetric && coulomb_negative != S(0)) || stribeck != S(0);
    }
    bool passive() const {
        return damping != S(0) || (asymmetric && damping_negative != S(0)) || dry_friction() || offset != S(0) ||
               stiffness != S(0) || limited;
    }
};

// An elastic transmission on a 1-dof joint: a motor-side inertia with a
// coordinate of its own (in the joint's units: the motor angle as the joint
// sees it through the gear), joined to the link by a spring and damper,
// through a dead band of `backlash` when that is not 0. The drive, a
// recorded effort and the encoder are on the motor side; the joint's own
// dynamics (friction, armature, limits) stay on the link.
template <class S> struct TransmissionT {
    int joint = -1, dof = -1;  // sim joint and its velocity coordinate
    S motor_inertia = S(0);    // kg m^2 (kg for a slide)
    S stiffness = S(0);        // N m/rad (N/m)
    S damping = S(0);          // N m s/rad (N s/m)
    S backlash = S(0);         // rad (m): the dead band's whole width
    // The stops of a dead band: stiff against the motion (a 1 ms time
    // constant, critically damped, on the two inertias in series; set by
    // build_model), pushing and never pulling.
    S stop_stiffness = S(0), stop_damping = S(0);

    template <class T> TransmissionT<T> cast() const {
        TransmissionT<T> r;
        r.joint = joint, r.dof = dof;
        r.motor_inertia = T(motor_inertia), r.stiffness = T(stiffness), r.damping = T(damping), r.backlash = T(backlash);
        r.stop_stiffness = T(stop_stiffness), r.stop_damping = T(stop_damping);
        return r;
    }
};

template <class S> struct BodyT {
    int parent = -1;     // sim body index (-1 for the world)
    int source = -1;     // Mechanism::bodies index (-1: none)
    std::string id, name;
    Inertia<S> inertia;  // body frame
    template <class T> BodyT<T> cast() const { return {parent, source, id, name, inertia.template cast<T>()}; }
};

// The joint between body `body` and its parent.
template <class S> struct JointT {
    JointKind kind = JointKind::Revolute;
    int body = -1;
    int source = -1;          // Mechanism::joints index (-1: a floating root's free joint)
    std::string name;         // the report's joint name (or the floating body's name)
    std::string constraint_id;  // CAD constraint id ("" for a free joint)
    int q_index = 0, v_index = 0;
    Transform<S> parent_to_joint;  // parent-side joint frame in the parent body frame
    Transform<S> joint_to_child;   // child body frame in the child-side joint frame
    Vec3T<S> axis = Vec3T<S>::UnitZ();  // joint frame
    SubspaceT<S> subspace;     // motion subspace in child body coordinates (free: filled per state)
    JointDynamicsT<S> dynamics;
    // The joint's diagonal of the mass matrix at the CAD pose, armature
    // included (1-dof joints): the inertia limits and friction are sized by.
    S reference_inertia = S(0);
    // x_parent (body in parent) of a revolute or prismatic joint as a
    // function of q, folded from the frames and axis above by
    // prepare_pose() (build_model and cast() call it; call it again after
    // changing them): with K = [axis]x, R(q) = I + sin q K + (1 - cos q) K^2,
    // so parent_to_joint * (R(q), 0) * joint_to_child has rotation
    // R0 + sin q R1 + (1 - cos q) R2 and position p0 + sin q p1 +
    // (1 - cos q) p2; a slider's is (R0, p0 + q p1). Fewer operations than
    // composing three transforms in the chord steps that close the loops.
    Mat3T<S> pose_R0, pose_R1, pose_R2;
    Vec3T<S> pose_p0, pose_p1, pose_p2;
    bool pose_prepared = false;

    void prepare_pose() {
        pose_prepared = kind == JointKind::Revolute || kind == JointKind::Prismatic;
        if (!pose_prepared) return;
        const Mat3T<S>& P = parent_to_joint.R;
        pose_R0 = P * joint_to_child.R;
        pose_p0 = P * joint_to_child.p + parent_to_joint.p;
        if (kind == JointKind::Prismatic) {
            pose_R1.setZero(), pose_R2.setZero();
            pose_p1 = P * axis, pose_p2.setZero();
            return;
        }
        const Mat3T<S> K = skew<S>(axis);
        const Mat3T<S> PK = P * K, PKK = PK * K;
        pose_R1 = PK * joint_to_child.R, pose_R2 = PKK * joint_to_child.R;
        pose_p1 = PK * joint_to_child.p, pose_p2 = PKK * joint_to_child.p;
    }

    template <class T> JointT<T> cast() const {
        JointT<T> r;
        r.kind = kind, r.body = body, r.source = source, r.name = name, r.constraint_id = constraint_id;
        r.q_index = q_index, r.v_index = v_index;
        r.parent_to_joint = parent_to_joint.template cast<T>();
        r.joint_to_child = joint_to_child.template cast<T>();
        r.axis = axis.template cast<T>();
        r.subspace = subspace.template cast<T>();
        r.dynamics = dynamics.template cast<T>();
        r.reference_inertia = T(reference_inertia);
        if (pose_prepared) r.prepare_pose();
        return r;
    }
    int nq() const { return position_size(kind); }
    int nv() const { return velocity_size(kind); }
    Subject subject() const {
        return source >= 0 ? Subject::constraint(constraint_id, name) : Subject::rigid_body(constraint_id, name);
    }
};

// A cut joint: frame A on body_a and frame B on body_b must coincide up to
// the joint's own motion. Rows select components of B's motion relative to
// A in A's coordinates, [rotation; translation]: 5 for revolute and
// prismatic, 3 for spherical, 6 for a weld.
template <class S> struct LoopClosureT {
    int body_a = 0, body_b = 0;
    Transform<S> frame_a;  // A in body_a
    Transform<S> frame_b;  // B in body_b
    JointKind kind = JointKind::Revolute;
    int rows = 0;
    std::array<Vec6T<S>, 6> row;  // unit selectors in A coordinates
    int loop = -1;                // Mechanism::loops index
    int source = -1;              // Mechanism::joints index of the cut joint
    std::string name, constraint_id;

    template <class T> LoopClosureT<T> cast() const {
        LoopClosureT<T> r;
        r.body_a = body_a, r.body_b = body_b, r.kind = kind, r.rows = rows, r.loop = loop, r.source = source;
        r.frame_a = frame_a.template cast<T>(), r.frame_b = frame_b.template cast<T>();
        for (int k = 0; k < 6; ++k) r.row[size_t(k)] = row[size_t(k)].template cast<T>();
        r.name = name, r.constraint_id = constraint_id;
        return r;
    }
    Subject subject() const { return Subject::loop(name); }
};

// Default gravity: 9.81 m/s^2 along -z, as every exporter writes it (CAD
// assemblies are mostly z-up). Settable per model.
constexpr double kDefaultGravity = 9.81;

template <class S> struct ModelT {
    std::string name;
    int nq = 0, nv = 0;
    std::vector<BodyT<S>> bodies;    // [0] the world
    std::vector<JointT<S>> joints;   // joints[b - 1] is body b's joint, in body order
    std::vector<LoopClosureT<S>> closures;
    std::vector<int> dof_joint;      // velocity coordinate -> joint index
    std::vector<int> body_of_source; // Mechanism::bodies index -> sim body (-1: none)
    std::vector<int> joint_of_source;// Mechanism::joints index -> sim joint (-1: cut or none)
    Vec3T<S> gravity = Vec3T<S>(S(0), S(0), S(-kDefaultGravity));
    VecXT<S> q_reference;            // the CAD assembly pose (every tree coordinate neutral, floating roots at their pose)
    int closure_rows = 0;            // sum of closures' rows
    // Rank of the closure rows at the assembly pose (-1: not known). Rows
    // redundant on the constraint manifold (spatial loops whose axes meet)
    // are independent off it, with singular values as small as the distance
    // to it, so rank decisions at off-manifold states (RK4 stages) are capped by this.
    int closure_rank = -1;
    // Drives in the loop (resolved against the mechanism) and the velocity
    // coordinate each acts on; their armature is already in the joints'.
    std::vector<Drive> drives;
    std::vector<int> drive_dof;
    // Elastic transmissions (at most one per joint) and, per velocity
    // coordinate, the one on it (-1: none).
    std::vector<TransmissionT<S>> transmissions;
    std::vector<int> transmission_of_dof;
    // Fixed-step Coulomb friction is regularised as coulomb * tanh(qd / v);
    // v is the joint's coulomb_velocity or this.
    S coulomb_velocity = S(1e-3);
    // Below this a joint's effective inertia counts as none (1e-12 of the
    // model's mass times its size squared, or its mass for a prismatic joint).
    S mass_scale = S(1), length_scale = S(1);
    S undetermined_inertia(JointKind k) const {
        return k == JointKind::Prismatic ? S(1e-12) * mass_scale : S(1e-12) * mass_scale * length_scale * length_scale;
    }

    int body_count() const { return int(bodies.size()); }
    const JointT<S>& joint_of_body(int b) const { return joints[size_t(b - 1)]; }

    template <class T> ModelT<T> cast() const {
        ModelT<T> r;
        r.name = name, r.nq = nq, r.nv = nv;
        for (const auto& b : bodies) r.bodies.push_back(b.template cast<T>());
        for (const auto& j : joints) r.joints.push_back(j.template cast<T>());
        for (const auto& c : closures) r.closures.push_back(c.template cast<T>());
        r.dof_joint = dof_joint, r.body_of_source = body_of_source, r.joint_of_source = joint_of_source;
        r.gravity = gravity.template cast<T>();
        r.q_reference = q_reference.template cast<T>();
        r.closure_rows = closure_rows;
        r.closure_rank = closure_rank;
        r.drives = drives, r.drive_dof = drive_dof;
        for (const auto& t : transmissions) r.transmissions.push_back(t.template cast<T>());
        r.transmission_of_dof = transmission_of_dof;
        r.coulomb_velocity = T(coulomb_velocity);
        r.mass_scale = T(mass_scale), r.length_scale = T(length_scale);
        return r;
    }
};

using Model = ModelT<double>;
using JointDynamics = JointDynamicsT<double>;
using Transmission = TransmissionT<double>;

}  // namespace mbx::sim
