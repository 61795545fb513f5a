// The four joint kinds of the simulator and what each means for coordinates:
// how many position and velocity coordinates it has, the motion across it,
// its motion subspace and how its position integrates a velocity. Position
// and velocity conventions are MuJoCo's, so a state copies across unchanged.
#pragma once
#include "sim/spatial.h"

namespace mbx::sim {

enum class JointKind {
    Revolute,   // q: angle (rad), v: rate; about `axis`
    Prismatic,  // q: displacement (m), v: rate; along `axis`
    Spherical,  // q: unit quaternion w x y z; v: angular velocity in the child-side joint frame
    Fixed,      // no coordinates (a weld primitive inside a CAD joint chain)
    Free        // q: position x y z (parent frame) then quaternion; v: linear velocity of the
                // child frame's origin (parent frame), angular velocity (child frame)
};

inline int position_size(JointKind k) {
    return k == JointKind::Free ? 7 : k == JointKind::Spherical ? 4 : k == JointKind::Fixed ? 0 : 1;
}
inline int velocity_size(JointKind k) {
    return k == JointKind::Free ? 6 : k == JointKind::Spherical ? 3 : k == JointKind::Fixed ? 0 : 1;
}
inline const char* joint_kind_name(JointKind k) {
    switch (k) {
    case JointKind::Revolute: return "revolute";
    case JointKind::Prismatic: return "prismatic";
    case JointKind::Spherical: return "spherical";
    case JointKind::Fixed: return "fixed";
    case JointKind::Free: return "free";
    }
    return "?";
}

template <class S> QuatT<S> quat_from(const S* q) { return QuatT<S>(q[0], q[1], q[2], q[3]); }

// Pose of the child-side joint frame in the parent-side joint frame.
template <class S> Transform<S> joint_transform(JointKind kind, const Vec3T<S>& axis, const S* q) {
    using std::cos;
    using std::sin;
    Transform<S> X;
    switch (kind) {
    case JointKind::Revolute: {
        // Rodrigues with a unit axis: R = c I + s [a]x + (1 - c) a a^T.
        const S c = cos(q[0]), s = sin(q[0]);
        X.R = c * Mat3T<S>::Identity() + s * skew<S>(axis) + (S(1) - c) * axis * axis.transpose();
        break;
    }
    case JointKind::Prismatic: X.p = axis * q[0]; break;
    case JointKind::Fixed: break;
    case JointKind::Spherical: X.R = quat_from(q).normalized().toRotationMatrix(); break;
    case JointKind::Free:
        X.p = Vec3T<S>(q[0], q[1], q[2]);
        X.R = quat_from(q + 3).normalized().toRotationMatrix();
        break;
    }
    return X;
}

// q <- q (+) v dt on the joint's manifold (quaternions stay unit).
template <class S> void integrate_joint(JointKind kind, S* q, const S* v, const S& dt) {
    switch (kind) {
    case JointKind::Revolute:
    case JointKind::Prismatic: q[0] += v[0] * dt; break;
    case JointKind::Fixed: break;
    case JointKind::Spherical: {
        const QuatT<S> r = quat_integrate_local<S>(quat_from(q), Vec3T<S>(v[0], v[1], v[2]), dt);
        q[0] = r.w(), q[1] = r.x(), q[2] = r.y(), q[3] = r.z();
        break;
    }
    case JointKind::Free: {
        for (int k = 0; k < 3; ++k) q[k] += v[k] * dt;
        const QuatT<S> r = quat_integrate_local<S>(quat_from(q + 3), Vec3T<S>(v[3], v[4], v[5]), dt);
        q[3] = r.w(), q[4] = r.x(), q[5] = r.y(), q[6] = r.z();
        break;
    }
    }
}

// The velocity that takes q0 to q1 in unit time (inverse of integrate_joint).
template <class S> void difference_joint(JointKind kind, const S* q0, const S* q1, S* v) {
    switch (kind) {
    case JointKind::Revolute:
    case JointKind::Prismatic: v[0] = q1[0] - q0[0]; break;
    case JointKind::Fixed: break;
    case JointKind::Spherical:
    case JointKind::Free: {
        const int o = kind == JointKind::Free ? 3 : 0;
        if (o) for (int k = 0; k < 3; ++k) v[k] = q1[k] - q0[k];
        const QuatT<S> d = quat_from(q0 + o).conjugate() * quat_from(q1 + o);
        const Vec3T<S> w = rotation_vector<S>(d.normalized().toRotationMatrix());
        for (int k = 0; k < 3; ++k) v[o + k] = w[k];
        break;
    }
    }
}

// Zero position of a joint (the CAD assembly pose for every tree joint).
template <class S> void neutral_joint(JointKind kind, S* q) {
    switch (kind) {
    case JointKind::Revolute:
    case JointKind::Prismatic: q[0] = S(0); break;
    case JointKind::Fixed: break;
    case JointKind::Spherical: q[0] = S(1), q[1] = q[2] = q[3] = S(0); break;
    case JointKind::Free:
        for (int k = 0; k < 7; ++k) q[k] = S(0);
        q[3] = S(1);
        break;
    }
}

}  // namespace mbx::sim
