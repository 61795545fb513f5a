// The factorisation the loop-closure solves share: a column-pivoted QR of
// J^T, which reveals J's rank (redundant rows of planar loops and CAD
// over-constraints drop out), gives minimum-norm solutions of J x = b and a
// basis of J's null space (the motions the loops allow).
#pragma once
#include <Eigen/QR>
#include <type_traits>

#include "sim/spatial.h"

namespace mbx::sim {

// A rank-revealing factorisation of J^T (column-pivoted QR), reused for the
// particular solution of J x = b, the null space of J and its rank.
template <class S> struct ClosureFactor {
    Eigen::ColPivHouseholderQR<MatXT<S>> qr;
    int rank = 0;

    // Relative threshold under which a row counts as redundant.
    void factor(const MatXT<S>& J, double tolerance = 1e-10) {
        // A fixed step factors the same J twice (closing the velocities at
        // the end of a step, then the next step's first evaluation at the
        // same positions): the second time is skipped. Only for plain
        // values: a Jet compares equal by its value alone.
        if constexpr (std::is_arithmetic_v<S>) {
            if (factored_ && tolerance == tolerance_ && J.rows() == J_.rows() && J.cols() == J_.cols() && J == J_) {
                rank = int(qr.rank());
                return;
            }
            J_ = J;
        }
        qr.setThreshold(S(tolerance));
        qr.compute(J.transpose());
        rank = int(qr.rank());
        factored_ = true, tolerance_ = tolerance, q_formed_ = false, p_formed_ = false, solves_ = 0;
    }
    bool factored() const { return factored_; }
    // Minimum-norm x with J x = b (least squares in the kept rows). A fixed
    // step solves several right-hand sides with one factor (the velocities,
    // the dynamics, the chord steps), so from the second solve on the
    // solution's matrix is formed once per factor and rank and each solve
    // is one small product; a lone solve (RK4 stages) goes by the reflectors.
    const VecXT<S>& particular(const VecXT<S>& b) {
        if (p_formed_ && p_rank_ == rank) {
            x_.noalias() = pinv_ * b;
            return x_;
        }
        if (solves_++ > 0) {
            form_pseudo_inverse();
            x_.noalias() = pinv_ * b;
            return x_;
        }
        pb_.noalias() = qr.colsPermutation().transpose() * b;
        x_.setZero(qr.rows());
        x_.head(rank) = pb_.head(rank);
        qr.matrixR().topLeftCorner(rank, rank).template triangularView<Eigen::Upper>().transpose().solveInPlace(
            x_.head(rank));
        // Q [y; 0] by the Householder reflectors, without forming Q.
        x_.applyOnTheLeft(qr.householderQ());
        return x_;
    }
    // Columns spanning the motions the closures allow: the last columns of
    // Q, formed alone (a loop leaves few motions) and kept for the same J and rank.
    const MatXT<S>& null_space() {
        const Eigen::Index n = qr.rows(), free = n - rank;
        if (!(q_formed_ && null_rank_ == rank)) {
            null_.setZero(n, free);
            null_.bottomRows(free).setIdentity();
            null_.applyOnTheLeft(qr.householderQ());
            q_formed_ = true, null_rank_ = rank;
        }
        return null_;
    }

private:
    // pinv_ = Q_r R_r^-T P_r^T: the first `rank` columns of Q, the leading
    // triangle of R, and the rows the pivoting kept (the others get zero columns).
    void form_pseudo_inverse() {
        const Eigen::Index n = qr.rows(), rows = qr.cols();
        null_.setZero(n, rank);  // scratch for Q_r (null_ is re-formed on demand)
        null_.topRows(rank).setIdentity();
        null_.applyOnTheLeft(qr.householderQ());
        q_formed_ = false;
        MatXT<S> At = null_.transpose();  // (R_r^-1 Q_r^T) = (Q_r R_r^-T)^T
        qr.matrixR().topLeftCorner(rank, rank).template triangularView<Eigen::Upper>().solveInPlace(At);
        pinv_.setZero(n, rows);
        const auto& perm = qr.colsPermutation().indices();
        for (int i = 0; i < rank; ++i) pinv_.col(perm[i]) = At.row(i).transpose();
        p_formed_ = true, p_rank_ = rank;
    }

    MatXT<S> J_;  // the last J factored (plain scalars only)
    MatXT<S> pinv_;
    int p_rank_ = -1, solves_ = 0;
    bool p_formed_ = false;
    VecXT<S> pb_, x_;
    MatXT<S> null_;
    int null_rank_ = -1;
    double tolerance_ = 0;
    bool factored_ = false, q_formed_ = false;
};

}  // namespace mbx::sim
