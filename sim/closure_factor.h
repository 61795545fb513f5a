// The factorisation the loop-closure solves share: a column-pivoted QR of
// J^T, which reveals J's rank (redundant rows of planar loops and CAD
// over-constraints drop out), gives minimum-norm solutions of J x = b and a
// basis of J's null space (the motions the loops allow).
#pragma once
#include <Eigen/QR>

#include "sim/spatial.h"

namespace mbx::sim {

// A rank-revealing factorisation of J^T (column-pivoted QR), reused for the
// particular solution of J x = b, the null space of J and its rank.
template <class S> struct ClosureFactor {
    Eigen::ColPivHouseholderQR<MatXT<S>> qr;
    MatXT<S> Q;  // nv x nv
    int rank = 0;

    // Relative threshold under which a row counts as redundant.
    void factor(const MatXT<S>& J, double tolerance = 1e-10) {
        qr.setThreshold(S(tolerance));
        qr.compute(J.transpose());
        rank = int(qr.rank());
        Q = qr.householderQ();
    }
    // Minimum-norm x with J x = b (least squares in the kept rows).
    VecXT<S> particular(const VecXT<S>& b) const {
        const VecXT<S> pb = qr.colsPermutation().transpose() * b;
        VecXT<S> y = qr.matrixR().topLeftCorner(rank, rank).template triangularView<Eigen::Upper>().transpose().solve(
            pb.head(rank));
        return Q.leftCols(rank) * y;
    }
    // Columns spanning the motions the closures allow.
    auto null_space() const { return Q.rightCols(Q.cols() - rank); }
};

}  // namespace mbx::sim
