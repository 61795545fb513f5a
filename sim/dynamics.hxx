// Definitions of sim/dynamics.h's algorithms, for the translation units that
// instantiate them: sim/instances_double.cpp and forward_dynamics_double.cpp
// for double, calibration/simulation/fit_scalar*.cpp for its Jet, and a test
// with a scalar of its own. Everything else includes the
// header only and links the instances (docs/architecture.md, "Build").
#pragma once
#include "sim/dynamics.h"

namespace mbx::sim {

template <class S> void update_positions(const ModelT<S>& m, DataT<S>& d) {
    d.x_world[0] = Transform<S>();
    for (size_t b = 1; b < m.bodies.size(); ++b) {
        const JointT<S>& j = m.joints[b - 1];
        const int parent = m.bodies[b].parent;
        Transform<S>& x = d.x_parent[b];
        if (j.pose_prepared) {
            const S q = d.q[j.q_index];
            if (j.kind == JointKind::Revolute) {
                using std::cos;
                using std::sin;
                const S s = sin(q), c1 = S(1) - cos(q);
                x.R = j.pose_R0 + s * j.pose_R1 + c1 * j.pose_R2;
                x.p = j.pose_p0 + s * j.pose_p1 + c1 * j.pose_p2;
            } else {
                x.R = j.pose_R0;
                x.p = j.pose_p0 + q * j.pose_p1;
            }
            if (parent == 0)
                d.x_world[b] = x;
            else
                d.x_world[b] = d.x_world[size_t(parent)] * x;
            continue;
        }
        const Transform<S> motion = joint_transform<S>(j.kind, j.axis, d.q.data() + j.q_index);
        x = j.parent_to_joint * motion * j.joint_to_child;
        d.x_world[b] = d.x_world[size_t(parent)] * x;
        if (j.kind == JointKind::Free) {
            // Linear velocity in the parent frame, angular in the body frame.
            SubspaceT<S>& s = d.subspace[b];
            s.setZero(6, 6);
            s.template block<3, 3>(3, 0) = motion.R.transpose();
            s.template block<3, 3>(0, 3).setIdentity();
        }
    }
}

template <class S> void update_velocities(const ModelT<S>& m, DataT<S>& d) {
    d.vel[0].setZero();
    for (size_t b = 1; b < m.bodies.size(); ++b) {
        const JointT<S>& j = m.joints[b - 1];
        const Vec6T<S> vj = subspace_motion<S>(d.subspace[b], d.v.data() + j.v_index, j.nv());
        d.vel[b] = d.x_parent[b].motion_to_child(d.vel[size_t(m.bodies[b].parent)]) + vj;
        Vec6T<S> c = cross_motion<S>(d.vel[b], vj);
        if (j.kind == JointKind::Free) {
            // d/dt of the subspace's R^T: the body-frame linear velocity turns with the body.
            const Vec3T<S> w = d.v.template segment<3>(j.v_index + 3);
            c.template tail<3>() -= w.cross(vj.template tail<3>());
        }
        d.bias_acc[b] = c;
    }
}

template <class S> void update_kinematics(const ModelT<S>& m, DataT<S>& d) {
    update_positions(m, d);
    update_velocities(m, d);
}

template <class S>
void inverse_dynamics(const ModelT<S>& m, DataT<S>& d, const VecXT<S>& qacc, VecXT<S>& tau, bool with_gravity) {
    d.acc[0].setZero();
    if (with_gravity) d.acc[0].template tail<3>() = -m.gravity;
    const size_t nb = m.bodies.size();
    for (size_t b = 1; b < nb; ++b) {
        const JointT<S>& j = m.joints[b - 1];
        d.acc[b] = d.x_parent[b].motion_to_child(d.acc[size_t(m.bodies[b].parent)]) +
                   subspace_motion<S>(d.subspace[b], qacc.data() + j.v_index, j.nv()) + d.bias_acc[b];
        const Inertia<S>& I = m.bodies[b].inertia;
        d.force[b] = I * d.acc[b] + cross_force<S>(d.vel[b], I * d.vel[b]);
    }
    tau.resize(m.nv);
    for (size_t b = nb - 1; b >= 1; --b) {
        const JointT<S>& j = m.joints[b - 1];
        subspace_force<S>(d.subspace[b], d.force[b], tau.data() + j.v_index, j.nv());
        if (j.nv() == 1) tau[j.v_index] += j.dynamics.armature * qacc[j.v_index];
        const int p = m.bodies[b].parent;
        if (p > 0) d.force[size_t(p)] += d.x_parent[b].force_to_parent(d.force[b]);
    }
}

template <class S> void mass_matrix(const ModelT<S>& m, DataT<S>& d) {
    const size_t nb = m.bodies.size();
    for (size_t b = 1; b < nb; ++b) d.composite[b] = m.bodies[b].inertia;
    for (size_t b = nb - 1; b >= 1; --b) {
        const int p = m.bodies[b].parent;
        if (p > 0) d.composite[size_t(p)] += d.composite[b].to_parent(d.x_parent[b]);
    }
    d.M.setZero(m.nv, m.nv);
    for (size_t b = 1; b < nb; ++b) {
        const JointT<S>& j = m.joints[b - 1];
        const int n = j.nv();
        const SubspaceT<S>& s = d.subspace[b];
        if (n == 1) {
            // One column (most joints): carried up the chain as one force.
            Vec6T<S> f = d.composite[b] * Vec6T<S>(s.col(0));
            d.M(j.v_index, j.v_index) = s.col(0).dot(f) + j.dynamics.armature;
            for (size_t c = b; m.bodies[c].parent > 0;) {
                f = d.x_parent[c].force_to_parent(f);
                c = size_t(m.bodies[c].parent);
                const JointT<S>& jc = m.joints[c - 1];
                for (int i = 0; i < jc.nv(); ++i)
                    d.M(j.v_index, jc.v_index + i) = d.M(jc.v_index + i, j.v_index) = d.subspace[c].col(i).dot(f);
            }
            continue;
        }
        Mat6T<S> F;  // the columns of composite * S, carried up the chain as forces
        for (int k = 0; k < n; ++k) F.col(k) = d.composite[b] * Vec6T<S>(s.col(k));
        for (int k = 0; k < n; ++k)
            for (int i = 0; i < n; ++i) d.M(j.v_index + i, j.v_index + k) = s.col(i).dot(F.col(k));
        if (n == 1) d.M(j.v_index, j.v_index) += j.dynamics.armature;
        size_t c = b;
        while (m.bodies[c].parent > 0) {
            for (int k = 0; k < n; ++k) F.col(k) = d.x_parent[c].force_to_parent(Vec6T<S>(F.col(k)));
            c = size_t(m.bodies[c].parent);
            const JointT<S>& jc = m.joints[c - 1];
            const SubspaceT<S>& sc = d.subspace[c];
            for (int k = 0; k < n; ++k)
                for (int i = 0; i < jc.nv(); ++i)
                    d.M(j.v_index + k, jc.v_index + i) = d.M(jc.v_index + i, j.v_index + k) = sc.col(i).dot(F.col(k));
        }
    }
}

template <class S> void articulated_body(const ModelT<S>& m, DataT<S>& d, const VecXT<S>& tau, VecXT<S>& qacc) {
    using std::abs;
    const size_t nb = m.bodies.size();
    for (size_t b = 1; b < nb; ++b) {
        const Inertia<S>& I = m.bodies[b].inertia;
        d.articulated[b] = I.matrix();
        d.bias_force[b] = cross_force<S>(d.vel[b], I * d.vel[b]);
    }
    for (size_t b = nb - 1; b >= 1; --b) {
        const JointT<S>& j = m.joints[b - 1];
        const int n = j.nv();
        const SubspaceT<S>& s = d.subspace[b];
        const int p = m.bodies[b].parent;
        Mat6T<S> Ia;
        Vec6T<S> pa;
        if (n == 1) {
            // One coordinate (most joints): D and u are scalars, Ia a rank-1 update.
            const Vec6T<S> sc = s.col(0);
            const Vec6T<S> U = d.articulated[b] * sc;
            const S D = sc.dot(U) + j.dynamics.armature;
            if (!(abs(D) > m.undetermined_inertia(j.kind))) throw UndeterminedJoint{int(b - 1)};
            const S D_inv = S(1) / D;
            const S u = tau[j.v_index] - sc.dot(d.bias_force[b]);
            d.U[b].col(0) = U;
            d.D_inv[b](0, 0) = D_inv;
            d.u[b](0) = u;
            if (p == 0) continue;
            const Vec6T<S> UD = U * D_inv;
            Ia = d.articulated[b] - UD * U.transpose();
            pa = d.bias_force[b] + Ia * d.bias_acc[b] + UD * u;
        } else {
            d.U[b].noalias() = d.articulated[b] * s;
            Eigen::Matrix<S, Eigen::Dynamic, Eigen::Dynamic, 0, 6, 6> D = s.transpose() * d.U[b];
            d.u[b] = tau.segment(j.v_index, n) - s.transpose() * d.bias_force[b];
            if (n > 1) {
                Eigen::LLT<Eigen::Matrix<S, Eigen::Dynamic, Eigen::Dynamic, 0, 6, 6>> llt(D);
                using std::sqrt;
                if (llt.info() != Eigen::Success ||
                    !(abs(llt.matrixLLT().diagonal().minCoeff()) > sqrt(m.undetermined_inertia(JointKind::Revolute))))
                    throw UndeterminedJoint{int(b - 1)};
                d.D_inv[b] = llt.solve(Eigen::Matrix<S, Eigen::Dynamic, Eigen::Dynamic, 0, 6, 6>::Identity(n, n));
            }
            // n == 0: a weld, the body rides on its parent.
            if (p == 0) continue;
            const SubspaceT<S> UD = d.U[b] * d.D_inv[b];
            Ia = d.articulated[b] - UD * d.U[b].transpose();
            pa = d.bias_force[b] + Ia * d.bias_acc[b] + UD * d.u[b];
        }
        d.articulated[size_t(p)] += articulated_to_parent<S>(Ia, d.x_parent[b]);
        d.bias_force[size_t(p)] += d.x_parent[b].force_to_parent(pa);
    }
    qacc.resize(m.nv);
    d.acc[0].setZero();
    d.acc[0].template tail<3>() = -m.gravity;
    for (size_t b = 1; b < nb; ++b) {
        const JointT<S>& j = m.joints[b - 1];
        const Vec6T<S> a = d.x_parent[b].motion_to_child(d.acc[size_t(m.bodies[b].parent)]) + d.bias_acc[b];
        if (j.nv() == 1) {
            const S qa = d.D_inv[b](0, 0) * (d.u[b](0) - d.U[b].col(0).dot(a));
            qacc[j.v_index] = qa;
            d.acc[b] = a + d.subspace[b].col(0) * qa;
            continue;
        }
        auto qa = qacc.segment(j.v_index, j.nv());
        qa = d.D_inv[b] * (d.u[b] - d.U[b].transpose() * a);
        d.acc[b] = a + subspace_motion<S>(d.subspace[b], qa.data(), j.nv());
    }
}

template <class S> Vec6T<S> point_velocity(const DataT<S>& d, int body, const Vec3T<S>& p_world) {
    const Vec6T<S> w = d.x_world[size_t(body)].motion_to_parent(d.vel[size_t(body)]);
    Vec6T<S> r;
    r.template head<3>() = w.template head<3>();
    r.template tail<3>() = w.template tail<3>() + w.template head<3>().cross(p_world);
    return r;
}

template <class S> Vec6T<S> point_acceleration(const DataT<S>& d, const Vec6T<S>& acc_body, int body,
                                               const Vec3T<S>& p_world) {
    const Vec6T<S> a = d.x_world[size_t(body)].motion_to_parent(acc_body);
    const Vec6T<S> v = point_velocity(d, body, p_world);
    Vec6T<S> r;
    r.template head<3>() = a.template head<3>();
    r.template tail<3>() = a.template tail<3>() + a.template head<3>().cross(p_world) +
                           v.template head<3>().cross(v.template tail<3>());
    return r;
}

template <class S> void energy(const ModelT<S>& m, const DataT<S>& d, S& kinetic, S& gravity, S& spring) {
    kinetic = gravity = spring = S(0);
    for (size_t b = 1; b < m.bodies.size(); ++b) {
        const Inertia<S>& I = m.bodies[b].inertia;
        kinetic += S(0.5) * d.vel[b].dot(I * d.vel[b]);
        const Vec3T<S> h_world = d.x_world[b].R * I.h + I.mass * d.x_world[b].p;  // m * com, world
        gravity -= m.gravity.dot(h_world);
        const JointT<S>& j = m.joints[b - 1];
        if (j.nv() == 1) {
            const S qd = d.v[j.v_index];
            kinetic += S(0.5) * j.dynamics.armature * qd * qd;
            const S dq = d.q[j.q_index] - j.dynamics.rest;
            spring += S(0.5) * j.dynamics.stiffness * dq * dq;
        }
    }
}

}  // namespace mbx::sim
