// Numeric rank of loop-closure Jacobians, dense and sparse.
//
// Both paths count what exceeds the same absolute threshold
//     tau = relative_tolerance * max(1, sigma_max):
// the dense path counts singular values. The sparse path first eliminates
// with local column-pivoted QRs, dropping columns whose pivot |R_kk| <= tau,
// which leaves J orthogonally reduced to the pivot rows W = [R S] (R
// triangular over the accepted columns, S their entries in dropped columns)
// plus residuals below tau. It then counts the singular values of W that
// are <= tau. That second step is what makes the count match the SVD: local
// pivots miss a dependency whose null vector is graded, e.g. a mobility that
// attenuates along a long chain of loops (in a 10 000-loop planar ladder
// every pivot stays above tau, although the ladder moves), and S keeps a
// direction from being counted twice when a column was dropped for it. On
// geometry within a small factor of the tolerance the two paths may still
// differ by one.
//
// Why not Eigen::SparseQR (COLAMD): its left-looking factorization clears
// two dense work vectors of length max(rows, cols) for every column, so it
// is at least quadratic in the size of a coupled group (measured on a
// spatial ladder of four-bars: 300 loops 0.15 s, 350 loops not done after
// 4 minutes; this code: 2 ms and 0.2 s for 10 000 loops), and its threshold
// pivots have the same blind spot for graded dependencies. The multifrontal
// elimination here does work proportional to the sizes of its fronts, which
// stay small for loops that only touch their neighbours.
#pragma once
#include <vector>

#include <Eigen/Core>

namespace mbx::mobility {

// A dense block of rows that are nonzero only in `columns` (distinct ids).
struct RowBlock {
    std::vector<int> columns;
    Eigen::MatrixXd values;  // rows x columns.size()
};

// Rank of a dense matrix by singular values.
int dense_rank(const Eigen::MatrixXd& m, double relative_tolerance);

// The matrix stacked from `blocks` (row blocks in order), for the dense path.
Eigen::MatrixXd assemble(const std::vector<RowBlock>& blocks, int column_count);

// Largest singular value of the stacked blocks by power iteration on J^T J
// (converges from below; within a few percent is all tau needs).
double largest_singular_value(const std::vector<RowBlock>& blocks, int column_count);

// The pivot rows W = [R S] of an elimination, both parts by rows (CSR): R
// upper triangular with a nonzero diagonal over the accepted columns (in
// pivot order), S over the dropped ones.
struct PivotRows {
    std::vector<double> diagonal;
    std::vector<size_t> row_begin{0};  // size() + 1 offsets into column/value
    std::vector<int> column;           // pivot index, > its row
    std::vector<double> value;
    std::vector<size_t> extra_begin{0};  // the same for S
    std::vector<int> extra_column;       // dropped column, 0..extra_columns-1
    std::vector<double> extra_value;
    int extra_columns = 0;

    int size() const { return static_cast<int>(diagonal.size()); }
};

// How many singular values of W are <= tau. Inverse subspace iteration with
// R finds R's smallest left singular vectors, growing the block until it
// holds a value above tau; W's small singular vectors lie in that subspace
// (W W^T >= R R^T), and Ritz values of W on it bound W's smallest singular
// values from above, so what is counted is there. Convergence is fast in
// practice because the values counted lie far below the rest. Triangular
// solves rescale to survive graded solutions.
int count_small_singular_values(const PivotRows& w, double tau);

// Rank of the stacked blocks by multifrontal QR: columns are eliminated in
// minimum-degree order (fewest blocks first, ties by id, so the result is
// deterministic); each elimination merges the blocks holding the column into
// a dense front, factors all columns that no other block touches with a
// column-pivoted QR, and keeps the remaining rows, compressed to at most as
// many rows as columns, as a new block. The rank is the number of accepted
// pivots less count_small_singular_values of the pivot rows.
int sparse_rank(std::vector<RowBlock> blocks, int column_count, double relative_tolerance);

}  // namespace mbx::mobility
