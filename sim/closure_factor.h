// The factorisation the loop-closure solves share: a column-pivoted QR of
// J^T, which reveals J's rank (redundant rows of planar loops and CAD
// over-constraints drop out), gives minimum-norm solutions of J x = b and a
// basis of J's null space (the motions the loops allow).
#pragma once
#include <Eigen/QR>  // kept: files that include this one use Eigen's QR
#include <cmath>
#include <type_traits>
#include <utility>
#include <vector>

#include "sim/spatial.h"

namespace mbx::sim {

// A rank-revealing factorisation of J^T (Householder QR with column
// pivoting, Businger-Golub), reused for the particular solution of J x = b,
// the null space of J and its rank. Written out on plain loops: the
// matrices are a few rows and columns, where a general library
// decomposition spends more on bookkeeping than on arithmetic.
template <class S> struct ClosureFactor {
    // The rank used by the solves; a caller may lower it (never raise it)
    // after factor().
    int rank = 0;

    // Relative threshold under which a row counts as redundant: a pivot
    // (diagonal of R) at most `tolerance` times the largest one.
    void factor(const MatXT<S>& J, double tolerance = 1e-10) {
        // A fixed step factors the same J twice (closing the velocities at
        // the end of a step, then the next step's first evaluation at the
        // same positions): the second time is skipped. Only for plain
        // values: a Jet compares equal by its value alone.
        if constexpr (std::is_arithmetic_v<S>) {
            if (factored_ && tolerance == tolerance_ && J.rows() == J_.rows() && J.cols() == J_.cols() && J == J_) {
                rank = full_rank_;
                return;
            }
            J_ = J;
        }
        using std::abs;
        using std::sqrt;
        const int n = int(J.cols()), m = int(J.rows());
        a_ = J.transpose();
        tau_.resize(std::min(n, m));
        perm_.resize(size_t(m));
        for (int j = 0; j < m; ++j) perm_[size_t(j)] = j;
        int r = 0;
        S largest = S(0);
        for (int k = 0; k < std::min(n, m); ++k) {
            // The remaining column of largest norm (recomputed: exact, and
            // cheap at these sizes).
            int best = k;
            S best_sq = S(-1);
            for (int j = k; j < m; ++j) {
                S sq = S(0);
                for (int i = k; i < n; ++i) sq += a_(i, j) * a_(i, j);
                if (sq > best_sq) best_sq = sq, best = j;
            }
            const S pivot = sqrt(best_sq);
            if (k == 0) largest = pivot;
            // Pivots only shrink from here on: the rest is round-off.
            if (!(pivot > S(tolerance) * largest)) break;
            if (best != k) {
                a_.col(k).swap(a_.col(best));
                std::swap(perm_[size_t(k)], perm_[size_t(best)]);
            }
            // Reflector H = I - tau v v^T (v_k = 1, v below k kept in the
            // column) with H a(k:, k) = beta e_k.
            const S alpha = a_(k, k);
            S sigma = S(0);
            for (int i = k + 1; i < n; ++i) sigma += a_(i, k) * a_(i, k);
            if (sigma == S(0)) {
                tau_[k] = S(0);
            } else {
                const S mu = sqrt(alpha * alpha + sigma);
                const S beta = alpha <= S(0) ? mu : -mu;
                tau_[k] = (beta - alpha) / beta;
                const S scale = S(1) / (alpha - beta);
                for (int i = k + 1; i < n; ++i) a_(i, k) *= scale;
                a_(k, k) = beta;
                for (int j = k + 1; j < m; ++j) {
                    S w = a_(k, j);
                    for (int i = k + 1; i < n; ++i) w += a_(i, k) * a_(i, j);
                    w *= tau_[k];
                    a_(k, j) -= w;
                    for (int i = k + 1; i < n; ++i) a_(i, j) -= w * a_(i, k);
                }
            }
            r = k + 1;
        }
        rank = full_rank_ = r;
        factored_ = true, tolerance_ = tolerance, q_formed_ = false;
    }
    bool factored() const { return factored_; }
    // Minimum-norm x with J x = b (least squares in the kept rows):
    // x = Q [R_r^-T (P^T b)_r; 0].
    const VecXT<S>& particular(const VecXT<S>& b) {
        const int n = int(a_.rows());
        x_.setZero(n);
        for (int i = 0; i < rank; ++i) {
            S y = b[perm_[size_t(i)]];
            for (int l = 0; l < i; ++l) y -= a_(l, i) * x_[l];
            x_[i] = y / a_(i, i);
        }
        for (int k = rank - 1; k >= 0; --k) reflect(k, x_.data());
        return x_;
    }
    // Columns spanning the motions the closures allow: Q's columns past the
    // rank, kept for the same factor and rank.
    const MatXT<S>& null_space() {
        const int n = int(a_.rows()), free = n - rank;
        if (!(q_formed_ && null_rank_ == rank)) {
            null_.setZero(n, free);
            for (int c = 0; c < free; ++c) {
                null_(rank + c, c) = S(1);
                for (int k = rank - 1; k >= 0; --k) reflect(k, null_.col(c).data());
            }
            q_formed_ = true, null_rank_ = rank;
        }
        return null_;
    }

private:
    // x <- H_k x.
    void reflect(int k, S* x) const {
        const int n = int(a_.rows());
        S w = x[k];
        for (int i = k + 1; i < n; ++i) w += a_(i, k) * x[i];
        w *= tau_[k];
        x[k] -= w;
        for (int i = k + 1; i < n; ++i) x[i] -= w * a_(i, k);
    }

    MatXT<S> J_;  // the last J factored (plain scalars only)
    MatXT<S> a_;  // R on and above the diagonal, the reflectors' vectors below
    VecXT<S> tau_;
    std::vector<int> perm_;  // column k of J^T P is column perm_[k] of J^T
    VecXT<S> x_;
    MatXT<S> null_;
    int full_rank_ = 0, null_rank_ = -1;
    double tolerance_ = 0;
    bool factored_ = false, q_formed_ = false;
};

}  // namespace mbx::sim
