// Multifrontal rank of a block-sparse matrix (see rank.h). Orthogonal row
// operations inside a front never change the rank; the pivot rows accepted
// in every front are then checked for dependencies that the local pivots
// could not see.
#include <algorithm>
#include <cmath>
#include <functional>
#include <queue>
#include <utility>

#include <Eigen/Householder>
#include <Eigen/QR>

#include "core/mobility/rank.h"

namespace mbx::mobility {
namespace {

class Eliminator {
public:
    Eliminator(std::vector<RowBlock> blocks, int column_count, double tau)
        : blocks_(std::move(blocks)),
          alive_(blocks_.size(), true),
          column_blocks_(column_count),
          degree_(column_count, 0),
          done_(column_count, false),
          position_(column_count, -1),
          count_(column_count, 0),
          pivot_of_(column_count, -1),
          tau_(tau) {
        for (size_t b = 0; b < blocks_.size(); ++b)
            for (int c : blocks_[b].columns) {
                column_blocks_[c].push_back(static_cast<int>(b));
                ++degree_[c];
            }
        for (int c = 0; c < column_count; ++c) {
            if (degree_[c] == 0)
                done_[c] = true;  // an all-zero column adds nothing
            else
                queue_.push({degree_[c], c});
        }
    }

    int run() {
        while (!queue_.empty()) {
            auto [degree, column] = queue_.top();
            queue_.pop();
            if (done_[column] || degree != degree_[column]) continue;  // stale entry
            eliminate(column);
        }
        // Rows were recorded by column id: accepted columns go to R, the
        // dropped ones to S.
        PivotRows w;
        w.diagonal = std::move(diagonal_);
        std::vector<int> extra_of(pivot_of_.size(), -1);
        for (size_t row = 0; row < w.diagonal.size(); ++row) {
            for (size_t e = row_begin_[row]; e < row_begin_[row + 1]; ++e) {
                const int c = entry_column_[e];
                if (pivot_of_[c] >= 0) {
                    w.column.push_back(pivot_of_[c]);
                    w.value.push_back(entry_value_[e]);
                } else {
                    if (extra_of[c] < 0) extra_of[c] = w.extra_columns++;
                    w.extra_column.push_back(extra_of[c]);
                    w.extra_value.push_back(entry_value_[e]);
                }
            }
            w.row_begin.push_back(w.column.size());
            w.extra_begin.push_back(w.extra_column.size());
        }
        return w.size() - count_small_singular_values(w, tau_);
    }

private:
    void eliminate(int pivot) {
        // Gather the live blocks holding the pivot column, dropping dead ids
        // from its list on the way.
        std::vector<int> front;
        std::vector<int>& holders = column_blocks_[pivot];
        for (int b : holders)
            if (alive_[b]) front.push_back(b);
        holders = front;

        // Columns of the front; those that no block outside it touches are
        // fully summed and are factored now, the others stay for later.
        std::vector<int> columns;
        Eigen::Index rows = 0;
        for (int b : front) {
            rows += blocks_[b].values.rows();
            for (int c : blocks_[b].columns) {
                if (count_[c]++ == 0) columns.push_back(c);
            }
        }
        std::vector<int> summed, rest;
        for (int c : columns) (count_[c] == degree_[c] ? summed : rest).push_back(c);
        std::sort(summed.begin(), summed.end());
        std::sort(rest.begin(), rest.end());
        int at = 0;
        for (int c : summed) position_[c] = at++;
        for (int c : rest) position_[c] = at++;

        Eigen::MatrixXd f = Eigen::MatrixXd::Zero(rows, at);
        Eigen::Index row = 0;
        for (int b : front) {
            RowBlock& block = blocks_[b];
            for (size_t k = 0; k < block.columns.size(); ++k)
                f.block(row, position_[block.columns[k]], block.values.rows(), 1) =
                    block.values.col(static_cast<Eigen::Index>(k));
            row += block.values.rows();
            alive_[b] = false;
            block = RowBlock{};
        }

        const Eigen::Index ns = static_cast<Eigen::Index>(summed.size());
        const Eigen::Index nr = static_cast<Eigen::Index>(rest.size());
        Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(f.leftCols(ns));
        const Eigen::Index diagonal = std::min(rows, ns);
        Eigen::Index accepted = 0;
        while (accepted < diagonal && std::abs(qr.matrixQR()(accepted, accepted)) > tau_) ++accepted;

        Eigen::MatrixXd r;
        if (nr > 0) {
            r = f.rightCols(nr);
            r.applyOnTheLeft(qr.householderQ().adjoint());
        }
        record_pivot_rows(qr, accepted, summed, rest, r);

        // Rows below the accepted pivots no longer involve the summed columns
        // (their remainders are below tau: dependent, dropped).
        RowBlock next;
        if (nr > 0 && rows > accepted) {
            Eigen::MatrixXd remaining = r.bottomRows(rows - accepted);
            if (remaining.rows() > nr) {
                // More rows than columns: an orthogonal compression to the
                // triangular factor keeps later fronts small.
                Eigen::HouseholderQR<Eigen::MatrixXd> compress(remaining);
                remaining = compress.matrixQR().topRows(nr).triangularView<Eigen::Upper>();
            }
            next.columns = rest;
            next.values = std::move(remaining);
        }

        for (int c : summed) done_[c] = true;
        const int id = static_cast<int>(blocks_.size());
        const bool keep = !next.columns.empty();
        for (int c : rest) {
            degree_[c] += (keep ? 1 : 0) - count_[c];
            if (keep) column_blocks_[c].push_back(id);
            if (degree_[c] == 0)
                done_[c] = true;
            else
                queue_.push({degree_[c], c});
        }
        for (int c : columns) {
            count_[c] = 0;
            position_[c] = -1;
        }
        if (keep) {
            blocks_.push_back(std::move(next));
            alive_.push_back(true);
        }
    }

    // Pivot row k: diagonal, then entries in the front's later columns by
    // column id, sorted into R and S at the end (the fate of `rest` columns
    // is not known yet; summed columns past `accepted` are dropped ones).
    void record_pivot_rows(const Eigen::ColPivHouseholderQR<Eigen::MatrixXd>& qr, Eigen::Index accepted,
                           const std::vector<int>& summed, const std::vector<int>& rest, const Eigen::MatrixXd& r) {
        const auto& order = qr.colsPermutation().indices();
        const Eigen::Index ns = static_cast<Eigen::Index>(summed.size());
        const int first = static_cast<int>(diagonal_.size());
        for (Eigen::Index i = 0; i < accepted; ++i) pivot_of_[summed[order[i]]] = first + static_cast<int>(i);
        for (Eigen::Index i = 0; i < accepted; ++i) {
            diagonal_.push_back(qr.matrixQR()(i, i));
            for (Eigen::Index j = i + 1; j < ns; ++j) add_entry(summed[order[j]], qr.matrixQR()(i, j));
            for (size_t c = 0; c < rest.size(); ++c) add_entry(rest[c], r(i, static_cast<Eigen::Index>(c)));
            row_begin_.push_back(entry_column_.size());
        }
    }
    void add_entry(int column, double v) {
        if (v == 0) return;
        entry_column_.push_back(column);
        entry_value_.push_back(v);
    }

    std::vector<RowBlock> blocks_;
    std::vector<bool> alive_;
    std::vector<std::vector<int>> column_blocks_;  // may hold dead block ids
    std::vector<int> degree_;                      // live blocks per column
    std::vector<bool> done_;
    std::vector<int> position_;  // column -> front position, -1 outside a front
    std::vector<int> count_;     // column -> blocks of the current front holding it
    std::priority_queue<std::pair<int, int>, std::vector<std::pair<int, int>>, std::greater<>> queue_;
    std::vector<int> pivot_of_;  // column -> its row of R, -1 until accepted
    std::vector<double> diagonal_;
    std::vector<size_t> row_begin_{0};
    std::vector<int> entry_column_;
    std::vector<double> entry_value_;
    double tau_;
};

}  // namespace

int sparse_rank(std::vector<RowBlock> blocks, int column_count, double relative_tolerance) {
    const double tau = relative_tolerance * std::max(1.0, largest_singular_value(blocks, column_count));
    return Eliminator(std::move(blocks), column_count, tau).run();
}

}  // namespace mbx::mobility
