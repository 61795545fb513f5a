// Definition of sim/forward_dynamics.h's solve (see sim/dynamics.hxx for
// who includes this file).
#pragma once
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <string>

#include "sim/forward_dynamics.h"
#include "sim/loop_closure.hxx"

namespace mbx::sim {

template <class S>
void forward_dynamics(const ModelT<S>& m, DataT<S>& d, const MatXT<S>* extra_rows,
                      const VecXT<S>* extra_bias, bool positions_ready) {
    if (positions_ready)
        update_velocities(m, d);
    else
        update_kinematics(m, d);
    const bool constrained = !m.closures.empty() || (extra_rows && extra_rows->rows() > 0);
    if (!constrained) {
        try {
            articulated_body(m, d, d.qfrc_total, d.qacc);
            return;
        } catch (const UndeterminedJoint& u) {
            throw_undetermined(m, d, u.joint);
        }
    }
    mass_matrix(m, d);
    d.tmp_v.setZero(m.nv);
    inverse_dynamics(m, d, d.tmp_v, d.bias);  // C v + g
    if (!positions_ready) update_closure_jacobian(m, d);
    update_closure_bias(m, d);
    const MatXT<S>* J = &d.J;
    const VecXT<S>* gamma = &d.gamma;
    MatXT<S> J_all;
    VecXT<S> gamma_all;
    if (extra_rows && extra_rows->rows() > 0) {
        J_all.resize(d.J.rows() + extra_rows->rows(), m.nv);
        J_all << d.J, *extra_rows;
        gamma_all.resize(J_all.rows());
        gamma_all << d.gamma, *extra_bias;
        J = &J_all;
        gamma = &gamma_all;
    }
    ClosureFactor<S>& f = d.closure_factor;
    f.factor(*J);
    // Off the manifold (RK4 stages) redundant closure rows gain tiny singular
    // values; counting them would blow the particular solution up.
    if (m.closure_rank >= 0) f.rank = std::min(f.rank, m.closure_rank + int(J->rows() - d.J.rows()));
    d.qacc_particular = f.particular(*gamma);
    const MatXT<S>& N = f.null_space();
    d.mass_null.noalias() = d.M * N;
    d.reduced_mass.noalias() = N.transpose() * d.mass_null;
    d.tmp_v2 = d.qfrc_total - d.bias;
    d.tmp_v2.noalias() -= d.M * d.qacc_particular;
    d.reduced_rhs.noalias() = N.transpose() * d.tmp_v2;
    Eigen::LDLT<MatXT<S>>& ldlt = d.reduced_ldlt;
    ldlt.compute(d.reduced_mass);
    using std::abs;
    S scale = S(0);
    for (int k = 0; k < m.nv; ++k) scale = std::max(scale, abs(d.M(k, k)));
    const S floor = S(1e-13) * (scale > S(0) ? scale : S(1));
    bool ok = ldlt.info() == Eigen::Success;
    if (ok && N.cols() > 0) ok = ldlt.vectorD().minCoeff() > floor;
    if (!ok) {
        // The direction of the motion nothing resists: the joint with the
        // largest share in the reduced mass matrix's weakest eigenvector.
        // (On plain values: the eigen-solver needs a real scalar type.)
        const Eigen::MatrixXd reduced = d.reduced_mass.unaryExpr([](const S& x) { return value_of(x); });
        const Eigen::MatrixXd basis = N.unaryExpr([](const S& x) { return value_of(x); });
        Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(reduced);
        const Eigen::VectorXd dir = basis * eig.eigenvectors().col(0);
        int dof = 0;
        for (int k = 1; k < m.nv; ++k)
            if (std::fabs(dir[k]) > std::fabs(dir[dof])) dof = k;
        throw_undetermined(m, d, m.dof_joint[size_t(dof)]);
    }
    ldlt.solveInPlace(d.reduced_rhs);
    d.qacc = d.qacc_particular;
    d.qacc.noalias() += N * d.reduced_rhs;
}

}  // namespace mbx::sim
