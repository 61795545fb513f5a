// Definitions of sim/loop_closure.h's functions (see sim/dynamics.hxx for
// who includes this file).
#pragma once
#include "sim/dynamics.hxx"
#include "sim/loop_closure.h"

namespace mbx::sim {

template <class S> void update_closure_residual(const ModelT<S>& m, DataT<S>& d) {
    int row = 0;
    for (const LoopClosureT<S>& c : m.closures) {
        const Transform<S> A = d.x_world[size_t(c.body_a)] * c.frame_a;
        const Transform<S> B = d.x_world[size_t(c.body_b)] * c.frame_b;
        const Mat3T<S> R_rel = A.R.transpose() * B.R;
        const Vec3T<S> p_rel = A.R.transpose() * (B.p - A.p);
        Vec3T<S> rot;
        if (c.kind == JointKind::Revolute) {
            // Tilt of B's axis out of A's, as components whose rates are the
            // relative angular velocity along u and w: exact at any turn angle.
            const Vec3T<S> u = c.row[0].template head<3>(), w = c.row[1].template head<3>();
            const Vec3T<S> a_b = R_rel * u.cross(w);
            rot = -w.dot(a_b) * u + u.dot(a_b) * w;
        } else {
            rot = rotation_vector<S>(R_rel);
        }
        for (int r = 0; r < c.rows; ++r) {
            const Vec6T<S>& sel = c.row[size_t(r)];
            d.residual[row++] = (sel.template head<3>().dot(rot) + sel.template tail<3>().dot(p_rel)) *
                                closure_row_scale(m, c, r);
        }
    }
}

template <class S> void update_closure_jacobian(const ModelT<S>& m, DataT<S>& d) {
    d.J.setZero(m.closure_rows, m.nv);
    // Each velocity coordinate's motion in world coordinates (about the world
    // origin), once for all closures rather than once per chain walk.
    d.world_motion.resize(size_t(m.nv));
    for (size_t b = 1; b < m.bodies.size(); ++b) {
        const JointT<S>& j = m.joints[b - 1];
        for (int k = 0; k < j.nv(); ++k)
            d.world_motion[size_t(j.v_index + k)] = d.x_world[b].motion_to_parent(Vec6T<S>(d.subspace[b].col(k)));
    }
    int row = 0;
    for (const LoopClosureT<S>& c : m.closures) {
        const Transform<S> A = d.x_world[size_t(c.body_a)] * c.frame_a;
        const Transform<S> B = d.x_world[size_t(c.body_b)] * c.frame_b;
        // Row r picks sa . w + sl . (v + w x p) out of a world motion (w, v)
        // about the origin seen at point p, i.e. (sa + p x sl) . w + sl . v:
        // one 6-vector per row and end.
        Eigen::Matrix<S, 6, 6> ga, gb;
        for (int r = 0; r < c.rows; ++r) {
            const S scale = closure_row_scale(m, c, r);
            const Vec3T<S> sa = A.R * c.row[size_t(r)].template head<3>() * scale;
            const Vec3T<S> sl = A.R * c.row[size_t(r)].template tail<3>() * scale;
            ga.col(r).template head<3>() = sa + A.p.cross(sl);
            gb.col(r).template head<3>() = sa + B.p.cross(sl);
            ga.col(r).template tail<3>() = sl;
            gb.col(r).template tail<3>() = sl;
        }
        // + columns of body b's chain at B, - columns of body a's chain at A;
        // the common ancestors' columns cancel.
        auto add_chain = [&](int body, const Eigen::Matrix<S, 6, 6>& g, bool minus) {
            for (int b = body; b > 0; b = m.bodies[size_t(b)].parent) {
                const JointT<S>& j = m.joints[size_t(b - 1)];
                for (int k = 0; k < j.nv(); ++k) {
                    const Vec6T<S>& w = d.world_motion[size_t(j.v_index + k)];
                    for (int r = 0; r < c.rows; ++r) {
                        const S x = g.col(r).dot(w);
                        if (minus)
                            d.J(row + r, j.v_index + k) -= x;
                        else
                            d.J(row + r, j.v_index + k) += x;
                    }
                }
            }
        };
        add_chain(c.body_b, gb, false);
        add_chain(c.body_a, ga, true);
        row += c.rows;
    }
}

template <class S> void update_closure_bias(const ModelT<S>& m, DataT<S>& d) {
    int row = 0;
    for (const LoopClosureT<S>& c : m.closures) {
        const Transform<S> A = d.x_world[size_t(c.body_a)] * c.frame_a;
        const Transform<S> B = d.x_world[size_t(c.body_b)] * c.frame_b;
        // World velocity and acceleration of the bodies (about the world
        // origin), then at the closure's points.
        const Vec6T<S> Va = d.x_world[size_t(c.body_a)].motion_to_parent(d.vel[size_t(c.body_a)]);
        const Vec6T<S> Vb = d.x_world[size_t(c.body_b)].motion_to_parent(d.vel[size_t(c.body_b)]);
        const Vec6T<S> Aa = d.x_world[size_t(c.body_a)].motion_to_parent(d.acc[size_t(c.body_a)]);
        const Vec6T<S> Ab = d.x_world[size_t(c.body_b)].motion_to_parent(d.acc[size_t(c.body_b)]);
        const Vec3T<S> wa = Va.template head<3>(), wb = Vb.template head<3>();
        const Vec3T<S> va = Va.template tail<3>() + wa.cross(A.p), vb = Vb.template tail<3>() + wb.cross(B.p);
        const Vec3T<S> aa = Aa.template tail<3>() + Aa.template head<3>().cross(A.p) + wa.cross(va);
        const Vec3T<S> ab = Ab.template tail<3>() + Ab.template head<3>().cross(B.p) + wb.cross(vb);
        // Rows are fixed in A, which turns with body a at w_a.
        const Vec3T<S> w_rel = wb - wa;
        const Vec3T<S> v_rel = vb - va;
        const Vec3T<S> dw = Ab.template head<3>() - Aa.template head<3>() - wa.cross(w_rel);
        const Vec3T<S> dv = ab - aa - wa.cross(v_rel);
        const Vec3T<S> dw_a = A.R.transpose() * dw, dv_a = A.R.transpose() * dv;
        for (int r = 0; r < c.rows; ++r)
            d.gamma[row++] = -(c.row[size_t(r)].template head<3>().dot(dw_a) + c.row[size_t(r)].template tail<3>().dot(dv_a)) *
                             closure_row_scale(m, c, r);
    }
}

template <class S> int worst_closure(const ModelT<S>& m, const VecXT<S>& v) {
    int row = 0, worst = -1;
    S best = S(-1);
    for (size_t k = 0; k < m.closures.size(); ++k) {
        for (int r = 0; r < m.closures[k].rows; ++r, ++row) {
            using std::abs;
            if (abs(v[row]) > best) best = abs(v[row]), worst = int(k);
        }
    }
    return worst;
}

template <class S>
bool project_positions(const ModelT<S>& m, DataT<S>& d, ClosureFactor<S>& f, double tolerance, int max_iterations,
                       const std::vector<char>* fixed, bool warm, VecXT<S>* moved) {
    if (m.closures.empty()) return true;
    warm = warm && f.factored();
    VecXT<S>& step = d.closure_step;
    VecXT<S>& rhs = d.closure_rhs;
    double previous = 0;
    for (int it = 0; it <= max_iterations; ++it) {
        update_positions(m, d);
        update_closure_residual(m, d);
        const double norm = value_of(S(d.residual.template lpNorm<Eigen::Infinity>()));
        if (!(norm > tolerance)) return true;
        if (it == max_iterations) break;
        // A fixed step leaves a small residual that a step with the first
        // iterate's factor (a chord step) cuts as well as a fresh one; a new
        // factor only when the last step did not cut the residual tenfold.
        if ((it == 0 && !warm) || (it > 0 && !(norm < 0.1 * previous))) {
            update_closure_jacobian(m, d);
            if (fixed)
                for (int k = 0; k < m.nv; ++k)
                    if ((*fixed)[size_t(k)]) d.J.col(k).setZero();
            f.factor(d.J);
        }
        previous = norm;
        rhs = -d.residual;
        step = f.particular(rhs);
        if (!step.allFinite()) return false;
        // Zeroed columns leave round-off in the minimum-norm step: fixed means exactly kept.
        if (fixed)
            for (int k = 0; k < m.nv; ++k)
                if ((*fixed)[size_t(k)]) step[k] = S(0);
        for (const JointT<S>& j : m.joints)
            integrate_joint<S>(j.kind, d.q.data() + j.q_index, step.data() + j.v_index, S(1));
        if (moved) *moved += step;
    }
    return false;
}

template <class S>
S project_velocities(const ModelT<S>& m, DataT<S>& d, ClosureFactor<S>& f, const std::vector<char>* fixed,
                     bool check) {
    if (m.closures.empty()) return S(0);
    update_closure_jacobian(m, d);
    d.closure_rhs.noalias() = d.J * d.v;
    if (fixed)
        for (int k = 0; k < m.nv; ++k)
            if ((*fixed)[size_t(k)]) d.J.col(k).setZero();
    f.factor(d.J);
    VecXT<S>& change = d.closure_step;
    change = f.particular(d.closure_rhs);
    if (fixed)
        for (int k = 0; k < m.nv; ++k)
            if ((*fixed)[size_t(k)]) change[k] = S(0);
    d.v -= change;
    if (!check && !fixed) return S(0);
    // Zeroed columns must come back for the check; otherwise J is still whole.
    if (fixed) update_closure_jacobian(m, d);
    d.closure_rhs.noalias() = d.J * d.v;
    return d.closure_rhs.template lpNorm<Eigen::Infinity>();
}

}  // namespace mbx::sim
