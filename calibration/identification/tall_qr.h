// The R factor of a tall matrix (the regression's millions of rows by a few
// dozen columns) computed by blocks of rows: each block is stacked under the
// R so far and factorised again (R of [R; block]), so no step holds more
// than a block, the columns need not be copied side by side first, and the
// run's heartbeat beats between blocks (a single Householder QR of a
// 1.2-million-row regression held the progress callback back for 220 ms).
// Q is never formed: R^T R = X^T X, and with the right-hand side as the last
// column, its last column holds Q^T y and its corner the residual's norm.
#pragma once
#include <Eigen/Dense>
#include <initializer_list>

namespace mbx::calibration {

// R of rows added a block at a time (a few thousand rows each: what a
// block costs is what holds the heartbeat back).
class TallR {
public:
    explicit TallR(Eigen::Index cols) : R_(Eigen::MatrixXd::Zero(cols, cols)) {}
    void add(const Eigen::Ref<const Eigen::MatrixXd>& rows);
    const Eigen::MatrixXd& R() const { return R_; }

private:
    Eigen::MatrixXd R_, stack_;
    Eigen::HouseholderQR<Eigen::MatrixXd> qr_;
};

// The upper-triangular R (cols x cols, signs as Householder leaves them) of
// the matrix whose columns are `parts`' side by side; every part has the
// same rows. Beats the current heartbeat once per block.
Eigen::MatrixXd tall_r(std::initializer_list<Eigen::Ref<const Eigen::MatrixXd>> parts);

// The rows per block: a multiple of `joints` (the rows of one sample), so a
// block never splits a sample's rows.
Eigen::Index tall_block_rows(Eigen::Index joints);

}  // namespace mbx::calibration
