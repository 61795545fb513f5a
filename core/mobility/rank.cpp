#include "core/mobility/rank.h"

#include <algorithm>
#include <cmath>

#include <Eigen/SVD>

namespace mbx::mobility {

int dense_rank(const Eigen::MatrixXd& m, double relative_tolerance) {
    if (m.size() == 0) return 0;
    Eigen::BDCSVD<Eigen::MatrixXd> svd(m);
    const Eigen::VectorXd& s = svd.singularValues();  // descending
    const double tau = relative_tolerance * std::max(1.0, s.size() ? s[0] : 0.0);
    int rank = 0;
    while (rank < s.size() && s[rank] > tau) ++rank;
    return rank;
}

Eigen::MatrixXd assemble(const std::vector<RowBlock>& blocks, int column_count) {
    Eigen::Index rows = 0;
    for (const RowBlock& b : blocks) rows += b.values.rows();
    Eigen::MatrixXd m = Eigen::MatrixXd::Zero(rows, column_count);
    Eigen::Index at = 0;
    for (const RowBlock& b : blocks) {
        for (size_t k = 0; k < b.columns.size(); ++k)
            m.block(at, b.columns[k], b.values.rows(), 1) = b.values.col(static_cast<Eigen::Index>(k));
        at += b.values.rows();
    }
    return m;
}

double largest_singular_value(const std::vector<RowBlock>& blocks, int column_count) {
    if (column_count == 0) return 0;
    // A fixed, irregular start vector: deterministic, and not orthogonal to
    // the dominant singular vector of any structured Jacobian we build.
    Eigen::VectorXd x(column_count);
    for (int i = 0; i < column_count; ++i) x[i] = 1.0 + 0.5 * std::sin(1.0 + 0.7 * i);
    x.normalize();
    Eigen::VectorXd y(column_count);
    double sigma2 = 0;
    for (int iteration = 0; iteration < 50; ++iteration) {
        y.setZero();
        for (const RowBlock& b : blocks) {
            Eigen::VectorXd local(b.columns.size());
            for (size_t k = 0; k < b.columns.size(); ++k) local[static_cast<Eigen::Index>(k)] = x[b.columns[k]];
            Eigen::VectorXd back = b.values.transpose() * (b.values * local);
            for (size_t k = 0; k < b.columns.size(); ++k) y[b.columns[k]] += back[static_cast<Eigen::Index>(k)];
        }
        const double next = y.norm();  // ||J^T J x|| with ||x|| = 1
        if (next == 0) return 0;
        x = y / next;
        const bool settled = std::abs(next - sigma2) <= 1e-3 * next;
        sigma2 = next;
        if (settled) break;
    }
    return std::sqrt(sigma2);
}

}  // namespace mbx::mobility
