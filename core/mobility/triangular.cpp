// Smallest singular values of the pivot rows of an elimination (see rank.h).
#include <algorithm>
#include <cmath>

#include <Eigen/QR>
#include <Eigen/SVD>

#include "core/mobility/rank.h"

namespace mbx::mobility {
namespace {

// Solutions of an ill-conditioned triangular system can outgrow a double by
// hundreds of orders of magnitude; only their direction matters here, so
// the whole vector is scaled down whenever an entry passes this bound.
constexpr double kRescale = 1e150;

void rescale_if_huge(Eigen::Ref<Eigen::VectorXd> x, double entry) {
    if (std::abs(entry) > kRescale) x /= std::abs(entry);
}

// x <- R^{-T} x (up to a positive factor): forward, column by column.
void solve_transposed(const PivotRows& r, Eigen::Ref<Eigen::VectorXd> x) {
    for (int i = 0; i < r.size(); ++i) {
        rescale_if_huge(x, x[i] / r.diagonal[i]);
        const double zi = x[i] / r.diagonal[i];
        x[i] = zi;
        for (size_t e = r.row_begin[i]; e < r.row_begin[i + 1]; ++e) x[r.column[e]] -= r.value[e] * zi;
    }
}

// x <- R^{-1} x (up to a positive factor): backward, row by row.
void solve(const PivotRows& r, Eigen::Ref<Eigen::VectorXd> x) {
    for (int i = r.size() - 1; i >= 0; --i) {
        double s = x[i];
        for (size_t e = r.row_begin[i]; e < r.row_begin[i + 1]; ++e) s -= r.value[e] * x[r.column[e]];
        x[i] = s / r.diagonal[i];
        rescale_if_huge(x, x[i]);
    }
}

// W^T z for each column z of `z`: R^T z on top, S^T z below.
Eigen::MatrixXd multiply_transposed(const PivotRows& w, const Eigen::MatrixXd& z) {
    const int n = w.size();
    Eigen::MatrixXd out = Eigen::MatrixXd::Zero(n + w.extra_columns, z.cols());
    for (int i = 0; i < n; ++i) {
        out.row(i) += w.diagonal[i] * z.row(i);
        for (size_t e = w.row_begin[i]; e < w.row_begin[i + 1]; ++e) out.row(w.column[e]) += w.value[e] * z.row(i);
        for (size_t e = w.extra_begin[i]; e < w.extra_begin[i + 1]; ++e)
            out.row(n + w.extra_column[e]) += w.extra_value[e] * z.row(i);
    }
    return out;
}

Eigen::MatrixXd orthonormal_basis(const Eigen::MatrixXd& x) {
    Eigen::HouseholderQR<Eigen::MatrixXd> qr(x);
    return qr.householderQ() * Eigen::MatrixXd::Identity(x.rows(), x.cols());
}

int count_at_most(const Eigen::VectorXd& values, double tau) {
    int n = 0;
    for (Eigen::Index i = 0; i < values.size(); ++i) n += values[i] <= tau;
    return n;
}

constexpr int kOversampling = 4;  // extra vectors: faster, surer convergence
constexpr int kIterations = 8;
constexpr int kMaxBlock = 512;    // beyond this the count is a lower bound

}  // namespace

int count_small_singular_values(const PivotRows& w, double tau) {
    const int n = w.size();
    if (n == 0) return 0;
    for (int wanted = 1;; wanted *= 2) {
        const int k = std::min(n, wanted + kOversampling);
        // A fixed irregular start: deterministic, generic enough.
        Eigen::MatrixXd z(n, k);
        for (int i = 0; i < n; ++i)
            for (int j = 0; j < k; ++j) z(i, j) = std::sin(0.5 + 1.3 * i + 2.9 * j + 0.37 * i * j);
        z = orthonormal_basis(z);
        for (int iteration = 0; iteration < kIterations; ++iteration) {
            for (int j = 0; j < k; ++j) {
                solve(w, z.col(j));
                solve_transposed(w, z.col(j));
                if (!z.col(j).allFinite()) z.col(j).setZero();  // lost: the basis below replaces it
            }
            z = orthonormal_basis(z);
        }
        // Ritz values on span(z): of R alone to know the block holds all of
        // R's small values, of W for the answer.
        const Eigen::MatrixXd wz = multiply_transposed(w, z);
        const int small_r = count_at_most(Eigen::JacobiSVD<Eigen::MatrixXd>(wz.topRows(n)).singularValues(), tau);
        if (small_r < wanted || k == n || wanted >= kMaxBlock)
            return count_at_most(Eigen::JacobiSVD<Eigen::MatrixXd>(wz).singularValues(), tau);
    }
}

}  // namespace mbx::mobility
