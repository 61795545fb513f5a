#include "calibration/identification/tall_qr.h"

#include <algorithm>

#include "core/heartbeat.h"

namespace mbx::calibration {

Eigen::Index tall_block_rows(Eigen::Index joints) {
    // A few thousand rows: the block's factorisation stays in cache and a
    // block takes well under a millisecond at the regression's widths.
    constexpr Eigen::Index kRows = 4096;
    const Eigen::Index a = std::max<Eigen::Index>(1, joints);
    return std::max<Eigen::Index>(1, kRows / a) * a;
}

void TallR::add(const Eigen::Ref<const Eigen::MatrixXd>& rows) {
    const Eigen::Index cols = R_.cols();
    if (cols == 0 || rows.rows() == 0) return;
    stack_.resize(cols + rows.rows(), cols);
    stack_.topRows(cols) = R_;
    stack_.bottomRows(rows.rows()) = rows;
    qr_.compute(stack_);
    R_ = qr_.matrixQR().topRows(cols).triangularView<Eigen::Upper>();
}

Eigen::MatrixXd tall_r(std::initializer_list<Eigen::Ref<const Eigen::MatrixXd>> parts) {
    Eigen::Index cols = 0, rows = 0;
    for (const auto& p : parts) cols += p.cols(), rows = std::max(rows, p.rows());
    TallR r(cols);
    if (cols == 0) return r.R();
    const Eigen::Index block = tall_block_rows(1);
    Eigen::MatrixXd rows_here;
    for (Eigen::Index from = 0; from < rows; from += block) {
        heartbeat();
        const Eigen::Index n = std::min(block, rows - from);
        rows_here.resize(n, cols);
        Eigen::Index at = 0;
        for (const auto& p : parts) rows_here.middleCols(at, p.cols()) = p.middleRows(from, n), at += p.cols();
        r.add(rows_here);
    }
    return r.R();
}

}  // namespace mbx::calibration
