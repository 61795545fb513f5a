// The blocked R factor of identification's least squares
// (calibration/identification/tall_qr.h) against Eigen's column-pivoted QR
// of the whole matrix: the same normal matrix, solution and residual, and a
// beat of the run's heartbeat per block of rows.
#include <doctest/doctest.h>

#include <Eigen/Dense>
#include <random>

#include "calibration/identification/tall_qr.h"
#include "core/heartbeat.h"
#include "tests/common/near.h"

namespace MBX_UNITY_ID {

using namespace mbx;
using namespace mbx::calibration;

TEST_CASE("calibration: tall_r by blocks of rows gives the least squares of the whole matrix, and beats per block") {
    std::mt19937 random(7);
    std::normal_distribution<double> normal;
    const Eigen::Index rows = 50000 + 123;  // not a whole number of blocks
    Eigen::MatrixXd X(rows, 5);
    for (Eigen::Index i = 0; i < rows; ++i) {
        const double t = double(i) / double(rows);
        // Columns of very different scales and one nearly another's (what causes' columns are like).
        X(i, 0) = 1, X(i, 1) = 1e3 * std::sin(40 * t), X(i, 2) = 1e-3 * std::cos(7 * t) + 1e-6 * normal(random);
        X(i, 3) = std::sin(40 * t) + 1e-4 * normal(random), X(i, 4) = t * t;
    }
    const Eigen::VectorXd truth = (Eigen::VectorXd(5) << 2, -0.5, 300, 7, -1).finished();
    Eigen::VectorXd y = X * truth;
    for (Eigen::Index i = 0; i < rows; ++i) y[i] += 0.01 * normal(random);

    long calls = 0;
    Heartbeat heart([&](const char*, double) { return ++calls, true; }, "test", std::chrono::nanoseconds(0));
    HeartbeatScope scope(&heart);
    // Two parts side by side and the right-hand side as the last column.
    const Eigen::MatrixXd R = tall_r({X.leftCols(2), X.rightCols(3), y});
    CHECK(calls >= rows / tall_block_rows(1));

    REQUIRE(R.rows() == 6);
    CHECK(R.isUpperTriangular());
    Eigen::MatrixXd Xy(rows, 6);
    Xy << X, y;
    const Eigen::MatrixXd gram = Xy.transpose() * Xy;
    CHECK((R.transpose() * R - gram).norm() == mbx_test::within(0, 1e-12 * gram.norm(), "X^T X, to rounding"));

    const Eigen::ColPivHouseholderQR<Eigen::MatrixXd> whole(X);
    const Eigen::VectorXd expected = whole.solve(y);
    const Eigen::VectorXd blocked = R.topLeftCorner(5, 5).triangularView<Eigen::Upper>().solve(R.col(5).head(5));
    for (Eigen::Index k = 0; k < 5; ++k) {
        CAPTURE(k);
        CHECK(blocked[k] == mbx_test::relative(expected[k], 1e-8));
    }
    // The corner holds the residual's norm.
    CHECK(std::abs(R(5, 5)) == mbx_test::relative((y - X * expected).norm(), 1e-8));
    // And the noise's 0.01 is what is left per row.
    CHECK(std::abs(R(5, 5)) / std::sqrt(double(rows)) == mbx_test::relative(0.01, 0.02));
}

TEST_CASE("calibration: tall_r of no rows or fewer rows than columns") {
    const Eigen::MatrixXd none(0, 3);
    CHECK(tall_r({none}).isZero());
    Eigen::MatrixXd two(2, 3);
    two << 1, 2, 3, 4, 5, 6;
    const Eigen::MatrixXd R = tall_r({two});
    CHECK((R.transpose() * R - two.transpose() * two).norm() < 1e-12);
    CHECK(R.row(2).isZero());
    CHECK(tall_block_rows(3) % 3 == 0);
}

}  // namespace MBX_UNITY_ID
