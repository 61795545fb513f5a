// Identification's least squares (calibration/identification/tall_qr.h): the
// R factor by blocks of rows, then a column-pivoted QR of R, against its peer,
// Eigen's column-pivoted QR of the whole matrix (what identification did
// before, with no progress until it returned), at three heights and the
// regression's usual width. Prints each figure, the ratio, the agreement of
// the two solutions and the blocked run's longest stretch between beats.
//   bench_least_squares [columns]   (default 8)
#include <Eigen/Dense>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <random>

#include "calibration/identification/tall_qr.h"
#include "core/heartbeat.h"

namespace {

using Clock = std::chrono::steady_clock;
double since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

}  // namespace

int main(int argc, char** argv) {
    const Eigen::Index cols = argc > 1 ? std::max(1, std::atoi(argv[1])) : 8;
    std::mt19937 random(3);
    std::normal_distribution<double> normal;
    for (const Eigen::Index rows : {Eigen::Index(100000), Eigen::Index(1000000), Eigen::Index(4000000)}) {
        Eigen::MatrixXd X(rows, cols);
        for (Eigen::Index j = 0; j < cols; ++j)
            for (Eigen::Index i = 0; i < rows; ++i) X(i, j) = std::sin(double((j + 1) * i) * 1e-4) + 0.1 * normal(random);
        const Eigen::VectorXd y = X * Eigen::VectorXd::LinSpaced(cols, 1, 2) + 0.01 * Eigen::VectorXd::NullaryExpr(rows, [&] { return normal(random); });

        auto t0 = Clock::now();
        const Eigen::ColPivHouseholderQR<Eigen::MatrixXd> whole(X);
        const Eigen::VectorXd peer = whole.solve(y);
        const double peer_time = since(t0);

        mbx::Heartbeat heart([](const char*, double) { return true; }, "bench", std::chrono::nanoseconds(0));
        mbx::HeartbeatScope scope(&heart);
        t0 = Clock::now();
        const Eigen::MatrixXd R = mbx::calibration::tall_r({X, y});
        const Eigen::ColPivHouseholderQR<Eigen::MatrixXd> small(R.topLeftCorner(cols, cols));
        const Eigen::VectorXd blocked = small.solve(Eigen::VectorXd(R.col(cols).head(cols)));
        const double blocked_time = since(t0);

        std::printf("least squares %7ld x %ld: blocked R %.1f ms, Eigen's pivoted QR of the whole %.1f ms, ratio %.2f; "
                    "solutions agree to %.1e; longest between beats %.2f ms\n",
                    long(rows), long(cols), 1e3 * blocked_time, 1e3 * peer_time, blocked_time / peer_time,
                    (blocked - peer).norm() / peer.norm(), 1e3 * heart.longest_gap());
    }
}
