// The rigid-body algorithms over (model, data), in body coordinates
// (Featherstone, "Rigid Body Dynamics Algorithms", 2008): forward kinematics
// and velocities, recursive Newton-Euler (inverse dynamics), composite rigid
// body (mass matrix), articulated body (forward dynamics of the tree),
// Jacobians and energy. Loop closures are in sim/loop_closure.h; the
// constrained forward dynamics that uses both in sim/forward_dynamics.h.
// Written once on the scalar S: double, or a Ceres Jet for calibration.
#pragma once
#include <cmath>
#include <string>

#include "sim/data.h"

namespace mbx::sim {

// S v for a joint's n velocity coordinates, and S^T f into n efforts, on
// fixed-size columns (a dynamic-size product costs more than the arithmetic
// for the 1-column subspaces of most joints).
template <class S> Vec6T<S> subspace_motion(const SubspaceT<S>& s, const S* v, int n) {
    Vec6T<S> r = Vec6T<S>::Zero();
    for (int k = 0; k < n; ++k) r += s.col(k) * v[k];
    return r;
}
template <class S> void subspace_force(const SubspaceT<S>& s, const Vec6T<S>& f, S* out, int n) {
    for (int k = 0; k < n; ++k) out[k] = s.col(k).dot(f);
}

// X^T Ia X for X the motion transform from the parent to the child frame
// (pose X of the child in the parent): a (symmetric) articulated inertia
// moved to the parent frame by 3x3 blocks, rotated, then its origin shifted by p.
template <class S> Mat6T<S> articulated_to_parent(const Mat6T<S>& Ia, const Transform<S>& X) {
    // R M R^T as two fixed-size lazy products (the nested product expression
    // went through Eigen's generic kernel).
    const Mat3T<S> Rt = X.R.transpose();
    auto rotate = [&](const Mat3T<S>& M) -> Mat3T<S> {
        const Mat3T<S> RM = X.R.lazyProduct(M);
        return RM.lazyProduct(Rt);
    };
    const Mat3T<S> A = rotate(Ia.template topLeftCorner<3, 3>());
    const Mat3T<S> B = rotate(Ia.template topRightCorner<3, 3>());
    const Mat3T<S> C = rotate(Ia.template bottomRightCorner<3, 3>());
    const Mat3T<S> px = skew<S>(X.p);
    const Mat3T<S> top_right = B + px * C;
    Mat6T<S> r;
    r.template topLeftCorner<3, 3>() = A + px * B.transpose() - top_right * px;
    r.template topRightCorner<3, 3>() = top_right;
    r.template bottomLeftCorner<3, 3>() = top_right.transpose();
    r.template bottomRightCorner<3, 3>() = C;
    return r;
}

// Body poses and each joint's motion subspace from data.q.
template <class S> void update_positions(const ModelT<S>& m, DataT<S>& d);

// Spatial velocities (body coordinates) and the joints' velocity-product
// accelerations; needs update_positions.
template <class S> void update_velocities(const ModelT<S>& m, DataT<S>& d);

template <class S> void update_kinematics(const ModelT<S>& m, DataT<S>& d);

// Recursive Newton-Euler: the joint efforts that give acceleration qacc at
// (data.q, data.v) with gravity (when `with_gravity`), armature included.
// Needs update_kinematics.
template <class S>
void inverse_dynamics(const ModelT<S>& m, DataT<S>& d, const VecXT<S>& qacc, VecXT<S>& tau, bool with_gravity = true);

// Composite rigid body algorithm: data.M, armature on the diagonal. Needs update_positions.
template <class S> void mass_matrix(const ModelT<S>& m, DataT<S>& d);

// Thrown by articulated_body when a joint moves no inertia at all (a massless
// leaf, e.g. a joint node whose chain ends at a cut joint): its acceleration
// is not determined by the tree alone. forward_dynamics then falls back to
// the constrained solve, which may determine it.
struct UndeterminedJoint {
    int joint = -1;
};

// Articulated body algorithm: qacc of the tree (no loop closures) under the
// joint efforts tau, gravity and armature. Needs update_kinematics.
template <class S> void articulated_body(const ModelT<S>& m, DataT<S>& d, const VecXT<S>& tau, VecXT<S>& qacc);

// World Jacobian of the point `p_world` fixed on body b: rows [angular;
// linear velocity of the point], world axes, one column per velocity
// coordinate. Needs update_positions. J must be 6 x nv; it is overwritten.
template <class S, class Derived>
void point_jacobian(const ModelT<S>& m, const DataT<S>& d, int body, const Vec3T<S>& p_world,
                    Eigen::MatrixBase<Derived> const& J_out) {
    auto& J = const_cast<Eigen::MatrixBase<Derived>&>(J_out);
    J.setZero();
    for (int b = body; b > 0; b = m.bodies[size_t(b)].parent) {
        const JointT<S>& j = m.joints[size_t(b - 1)];
        for (int k = 0; k < j.nv(); ++k) {
            const Vec6T<S> w = d.x_world[size_t(b)].motion_to_parent(Vec6T<S>(d.subspace[size_t(b)].col(k)));
            J.col(j.v_index + k).template head<3>() = w.template head<3>();
            J.col(j.v_index + k).template tail<3>() =
                w.template tail<3>() + w.template head<3>().cross(p_world);
        }
    }
}

// World angular velocity and velocity of a point fixed on body b (needs update_kinematics).
template <class S> Vec6T<S> point_velocity(const DataT<S>& d, int body, const Vec3T<S>& p_world);

// World angular acceleration and classical acceleration of a point fixed
// on body b, from data.acc (after inverse_dynamics or articulated_body).
template <class S> Vec6T<S> point_acceleration(const DataT<S>& d, const Vec6T<S>& acc_body, int body,
                                               const Vec3T<S>& p_world);

// Kinetic energy (bodies and armature), potential energy of gravity (zero
// at the world origin) and of joint springs. Needs update_kinematics.
template <class S> void energy(const ModelT<S>& m, const DataT<S>& d, S& kinetic, S& gravity, S& spring);

// The instances of the algorithms above for a scalar S (a type name without
// commas). Compiled once per scalar (sim/instances_double.cpp and
// sim/forward_dynamics_double.cpp; calibration/simulation/fit_scalar.cpp and
// fit_scalar_forward.cpp for the fit's Jet) and declared extern everywhere
// else, so no other unit compiles the algorithms again.
#define MBX_SIM_DYNAMICS_INSTANCES(EXTERN, S)                                                                 \
    EXTERN template void update_positions<S>(const ModelT<S>&, DataT<S>&);                                    \
    EXTERN template void update_velocities<S>(const ModelT<S>&, DataT<S>&);                                   \
    EXTERN template void update_kinematics<S>(const ModelT<S>&, DataT<S>&);                                   \
    EXTERN template void inverse_dynamics<S>(const ModelT<S>&, DataT<S>&, const VecXT<S>&, VecXT<S>&, bool);   \
    EXTERN template void mass_matrix<S>(const ModelT<S>&, DataT<S>&);                                         \
    EXTERN template void articulated_body<S>(const ModelT<S>&, DataT<S>&, const VecXT<S>&, VecXT<S>&);        \
    EXTERN template Vec6T<S> point_velocity<S>(const DataT<S>&, int, const Vec3T<S>&);                        \
    EXTERN template Vec6T<S> point_acceleration<S>(const DataT<S>&, const Vec6T<S>&, int, const Vec3T<S>&);   \
    EXTERN template void energy<S>(const ModelT<S>&, const DataT<S>&, S&, S&, S&);
MBX_SIM_DYNAMICS_INSTANCES(extern, double)

}  // namespace mbx::sim
